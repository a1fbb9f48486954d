# Bake a generated mesh with both storages, then read it back with sss-stat.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 3 "$TMP/blob.ply"
for q in float lloyd8; do
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_$q.sss" --material skin1 --mm-per-unit 20 --dirs 50 --quant $q --json -q
  cp "$TMP/out" "$TMP/bake_$q.json"
  contains "$TMP/bake_$q.json" '"vertices":642'
  contains "$TMP/bake_$q.json" '"directions":50'
  contains "$TMP/bake_$q.json" "\"quant\":\"$q\""
  expect_ok "$SSS_STAT" "$TMP/blob_$q.sss" --json
  contains "$TMP/out" '"vertices":642'
  contains "$TMP/out" '"channels":3'
  contains "$TMP/out" '"tag":"GEOM"'
  expect_ok "$SSS_STAT" "$TMP/blob_$q.sss"
  contains "$TMP/out" 'bytes/vertex'
done
contains "$TMP/bake_lloyd8.json" '"lloyd_snr_db"'
# no flags: the best answer at the fewest bytes (docs/accuracy.md, "The defaults"): hat
# weights, the near terms at run time within the material's radius, the
# compact compression (1 % references for RGB); --quant keeps the rows whole
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_default.sss" --material skin1 --mm-per-unit 20 --json -q
contains "$TMP/out" '"quant":"refs"'
contains "$TMP/out" '"near_capped":false'
expect_ok "$SSS_STAT" "$TMP/blob_default.sss" --json
for key in '"format_version":"1.6"' '"weights":"hat"' '"near_fraction":0.95' '"sh_quant":"lloyd4"' '"weight_bits":8' \
  '"refs_fraction":0.01' '"directions":200'; do
  contains "$TMP/out" "$key"
done
# skin1's radius holding 95 % of R_d total in every channel (red: 1/sigma_tr
# is the longest), the same whatever the mesh
sed -n 's/.*"near_radius_mm":\([0-9.eE+-]*\).*/\1/p' "$TMP/out" | awk '{ exit !($1 > 8 && $1 < 25) }' ||
  fail "default near radius out of range: $(cat "$TMP/out")"
# a one-channel material holds 97 % by default (sss/nearterms.h), and
# --near-fraction still rules
G=(--sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62 --mm-per-unit 20 --dirs 50 -q)
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_grey.sss" "${G[@]}"
expect_ok "$SSS_STAT" "$TMP/blob_grey.sss" --json
contains "$TMP/out" '"channels":1,'
contains "$TMP/out" '"near_fraction":0.97'
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_grey.sss" "${G[@]}" --near-fraction 0.95
expect_ok "$SSS_STAT" "$TMP/blob_grey.sss" --json
contains "$TMP/out" '"near_fraction":0.95'
# lloyd8 integrals take 1 byte instead of 4: the file must be much smaller
f=$(stat -c %s "$TMP/blob_float.sss"); l=$(stat -c %s "$TMP/blob_lloyd8.sss")
[ $((l * 3)) -lt "$f" ] || fail "lloyd8 file ($l B) should be < 1/3 of float ($f B)"
# compressed forms (format 1.1): SH only, and references + SH deltas
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_sh.sss" --material skin1 --mm-per-unit 20 --dirs 50 --sh-order 3 --refs 0 --json -q
contains "$TMP/out" '"quant":"sh"'
contains "$TMP/out" '"sh_order":3'
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_refs.sss" --material skin1 --mm-per-unit 20 --dirs 50 \
  --sh-order 2 --refs 0.05 --sh-quant lloyd4 --weight-bits 8 --ls-weights --own-term baked --weights point --json -q
contains "$TMP/out" '"quant":"refs"'
expect_ok "$SSS_STAT" "$TMP/blob_refs.sss" --json
# the compact compression stores its directions in float32 (DIRC, format 1.6)
contains "$TMP/out" '"format_version":"1.6"'
contains "$TMP/out" '"tag":"DIRC","bytes":1184,'
# every byte but the mesh: file_bytes 48695 less GEOM's 30776
contains "$TMP/out" '"file_bytes":48695,'
contains "$TMP/out" '"bytes_apart_geometry":17919,'
for part in ref_vertex_indices ref_triangles vertex_triangle_indices weights ref_values sh_tables sh_codes directions; do
  contains "$TMP/out" "\"$part\":{\"bytes\":"
done
contains "$TMP/out" '"sh_quant":"lloyd4"'
contains "$TMP/out" '"weight_bits":8'
contains "$TMP/out" '"ratio_vs_float":'
contains "$TMP/out" '"ls_weights":true'
expect_ok "$SSS_STAT" "$TMP/blob_sh.sss"
contains "$TMP/out" 'sh_codes'
contains "$TMP/out" 'smaller than 8-bit'
# SH order 3 at one byte per coefficient: 27 bytes per vertex of codes, far
# below the 150 of lloyd8
s=$(stat -c %s "$TMP/blob_sh.sss"); l=$(stat -c %s "$TMP/blob_lloyd8.sss")
[ "$s" -lt "$l" ] || fail "SH file ($s B) should be smaller than lloyd8 ($l B)"
# the compact preset: 4-bit Lloyd SH codes, 8-bit least-squares weights,
# illumination-aware references, 1 % of the vertices for RGB; an explicit
# option overrides the preset
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_compact.sss" --material skin1 --mm-per-unit 20 --dirs 50 --compress compact -q
expect_ok "$SSS_STAT" "$TMP/blob_compact.sss" --json
contains "$TMP/out" '"sh_quant":"lloyd4"'
contains "$TMP/out" '"weight_bits":8'
contains "$TMP/out" '"refs":6,'
contains "$TMP/out" '"ls_weights":true'
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_compact2.sss" --material skin1 --mm-per-unit 20 --dirs 50 --compress compact --sh-order 2 -q
expect_ok "$SSS_STAT" "$TMP/blob_compact2.sss" --json
contains "$TMP/out" '"sh_order":2'
contains "$TMP/out" '"sh_quant":"lloyd4"'
expect_fail 'paper, compact or paper-sh' "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --compress tiny
# contradictory or empty compression settings are refused before baking
expect_fail 'exclude each other' "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --quant lloyd8 --sh-order 3
expect_fail 'needs --refs' "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --sh-order 0
expect_fail 'sh-order' "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --sh-order 9
expect_fail 'refs' "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --refs 1.5
expect_fail 'weight-bits' "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --weight-bits 12
[ ! -e "$TMP/x.sss" ] || fail "a refused bake left a file"
# --own-term runtime alone sizes the near terms by the material: the radius
# that holds --near-fraction (default 0.95) of R_d,total in every channel,
# 8.71 mm for skin1 whatever the mesh's scale (docs/accuracy.md)
for s in 20 10; do
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/n$s.sss" --material skin1 --mm-per-unit $s --dirs 20 --own-term runtime -q \
    --json
  cp "$TMP/out" "$TMP/n$s.json"
  contains "$TMP/n$s.json" '"near_capped":false'
  expect_ok "$SSS_STAT" "$TMP/n$s.sss" --json
  contains "$TMP/out" '"near_radius_mm":8.71073'
  contains "$TMP/out" '"near_fraction":0.95'
done
# the entries a reader builds: more per vertex on the smaller object (the
# radius is the same number of mm, so it spans more of the mesh)
e20=$(sed -n 's/.*"near_entries_per_vertex":\([0-9.eE+]*\).*/\1/p' "$TMP/n20.json")
e10=$(sed -n 's/.*"near_entries_per_vertex":\([0-9.eE+]*\).*/\1/p' "$TMP/n10.json")
awk -v a="$e20" -v b="$e10" 'BEGIN { exit !(a >= 1 && b > 2.5 * a) }' || fail "near entries per vertex: $e20 at 20 mm/unit, $e10 at 10"
# smaller still (5 mm/unit, a 10 mm blob), the radius would take most of the
# mesh: it shrinks until the rows hold at most 512 entries per vertex
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/n5.sss" --material skin1 --mm-per-unit 5 --dirs 20 -q --json
contains "$TMP/out" '"near_capped":true'
e5=$(sed -n 's/.*"near_entries_per_vertex":\([0-9.eE+]*\).*/\1/p' "$TMP/out")
r5=$(sed -n 's/.*"near_radius_mm":\([0-9.eE+]*\).*/\1/p' "$TMP/out")
h5=$(sed -n 's/.*"near_fraction_held":\([0-9.eE+]*\).*/\1/p' "$TMP/out")
awk -v e="$e5" -v r="$r5" -v h="$h5" 'BEGIN { exit !(e <= 512 && e > 256 && r < 8.71 && h < 0.95 && h > 0.5) }' ||
  fail "capped near terms: $e5 entries per vertex within $r5 mm holding $h5 of R_d total"
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/n99.sss" --material skin1 --mm-per-unit 20 --dirs 20 --own-term runtime \
  --near-fraction 0.99 -q
expect_ok "$SSS_STAT" "$TMP/n99.sss"
contains "$TMP/out" 'every vertex within 13.6'
# --preset paper: Hao-Varshney 2004 exactly (200 directions, point weights,
# every term baked, 3 % references, SH order 3, linear 8-bit codes, 16-bit
# barycentric weights), the same bytes as those options spelt out
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/hv.sss" --material skin1 --mm-per-unit 20 --preset paper -q
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/hv2.sss" --material skin1 --mm-per-unit 20 --dirs 200 --weights point \
  --own-term baked --compress paper -q
cmp -s "$TMP/hv.sss" "$TMP/hv2.sss" || fail "--preset paper differs from its options spelt out"
expect_ok "$SSS_STAT" "$TMP/hv.sss"
for k in 'directions 200, storage refs' 'weights: point samples' '16-bit weights in \[0, 1\], SH order 3 (linear8)' \
         'references ([23]\.[0-9]*%)'; do
  contains "$TMP/out" "$k"
done
grep -q 'near terms added at run time' "$TMP/out" && fail "--preset paper split near terms off"
# and keeps its directions in float64 (DIRS), as 1.1 readers read them
expect_ok "$SSS_STAT" "$TMP/hv.sss" --json
contains "$TMP/out" '"tag":"DIRS","bytes":9560,'
# --preset paper-sh: the paper's SH-only storage (§4.1): SH order 7, each
# coefficient a normalised short, no references: 49 x 2 = 98 code bytes per
# vertex and channel, 294 in RGB; the same bytes as its options spelt out
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/hs.sss" --material skin1 --mm-per-unit 20 --preset paper-sh -q
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/hs2.sss" --material skin1 --mm-per-unit 20 --dirs 200 --weights point \
  --own-term baked --compress paper --sh-order 7 --refs 0 --sh-quant linear16 -q
cmp -s "$TMP/hs.sss" "$TMP/hs2.sss" || fail "--preset paper-sh differs from its options spelt out"
expect_ok "$SSS_STAT" "$TMP/hs.sss"
for k in 'format 1.7,' 'directions 200, storage sh' 'SH order 7 (linear16) at every vertex' \
         'sh_codes  *188748  *294.000' 'sh_tables  *588 '; do
  contains "$TMP/out" "$k"
done
grep -q 'near terms added at run time' "$TMP/out" && fail "--preset paper-sh split near terms off"
# the bundled sample bakes too
expect_ok "$SSS_BAKE" "$SSS_SOURCE/data/meshes/blob.ply" -o "$TMP/sample.sss" --material marble --mm-per-unit 100 --dirs 25 -q
echo "cli_bake_stat: ok"
