# sss-bake --scene (docs/scenes.md): --plan as text and JSON with a reason
# per decision; invalid scenes fail with the file and JSON path; one
# DIR/NAME.sss per object; a failing bake leaves no file; the bytes do not
# depend on the thread count.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 2 "$TMP/blob.ply"
expect_ok "$SSS_GENMESH" sphere 2 "$TMP/sphere.ply"
cat > "$TMP/s.json" <<'J'
{"objects": [
  {"name": "blob", "mesh": "blob.ply", "material": "marble", "mm_per_unit": 10},
  {"name": "ball", "mesh": "sphere.ply", "material": {"sigma_a": [0.02, 0.02, 0.02], "sigmap_s": [1, 1, 1]},
   "transform": {"translate": [3, 0, 0]}}],
 "lights": [{"type": "directional", "direction": [1, 0, 1]},
            {"type": "point", "position": [0, 3, 0], "moving": true}],
 "bake": {"dirs": 50, "shells": 3}}
J
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" --plan
for pat in "object 0 'blob'" "object 1 'ball'" 'channels      1 channel' 'self-shadow   off' 'the mesh is closed and convex' \
           "scene-shadow  on .*'blob' casts" 'light 0       directional-exact' 'light 1       point-shells'; do
  grep -q -- "$pat" "$TMP/out" || { cat "$TMP/out" >&2; fail "--plan should print '$pat'"; }
done
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" --plan --json
for pat in '"effects":' '"decisions":' '"reason":' '"passes":' '"pass":	"point-shells"' '"convex":	true'; do
  contains "$TMP/out" "$pat"
done
# invalid scenes: file and JSON path in a one-line message, exit 2
sed 's/"direction": \[1, 0, 1\]/"direction": [1, 0]/' "$TMP/s.json" > "$TMP/bad1.json"
expect_fail "bad1.json: /lights/0/direction: expected 3 numbers" "$SSS_BAKE" --scene "$TMP/bad1.json" --plan
sed 's/"moving": true/"moving": 1/' "$TMP/s.json" > "$TMP/bad2.json"
expect_fail "bad2.json: /lights/1/moving: expected true or false" "$SSS_BAKE" --scene "$TMP/bad2.json" --plan
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "message should be one line"
expect_fail "missing.json: cannot open" "$SSS_BAKE" --scene "$TMP/missing.json" --plan
# bake: one file per object, named after it
mkdir -p "$TMP/o1" "$TMP/o2" "$TMP/o3"
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/o1" --threads 1 -q
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/o2" --threads 2 -q --json
contains "$TMP/out" '"rays":'
contains "$TMP/out" '"gather":"tree","peak_rss_mib":'
for n in blob ball; do
  [ -s "$TMP/o1/$n.sss" ] || fail "no $n.sss"
  cmp -s "$TMP/o1/$n.sss" "$TMP/o2/$n.sss" || fail "$n.sss differs between 1 and 2 threads"
done
expect_ok "$SSS_STAT" "$TMP/o1/ball.sss"
contains "$TMP/out" 'format 1.5'
contains "$TMP/out" 'EFCT'
# a scene whose second object cannot be baked (probe missing) writes nothing half-done
sed 's/"lights": \[/"lights": [{"type": "environment", "probe": "nope.exr"}, /' "$TMP/s.json" > "$TMP/bad3.json"
expect_fail "nope.exr" "$SSS_BAKE" --scene "$TMP/bad3.json" -o "$TMP/o3" -q
[ -z "$(ls -A "$TMP/o3" | grep -v '^blob.sss$\|^ball.sss$' )" ] || fail "temporary files left: $(ls "$TMP/o3")"
[ ! -e "$TMP/o3/blob.sss" ] || fail "blob.sss written although its bake failed"
# sss-stat --error on a scene bake measures its static lights too (QDIR):
# each stored row against the exact evaluator at its direction, which the
# bake computed with the same weights (float-exact), next to the moving
# light's direction set; and its point shells, interpolated against the
# exact point light
cat > "$TMP/m.json" <<'J'
{"objects": [{"name": "blob", "mesh": "blob.ply", "material": "skin1", "mm_per_unit": 10}],
 "lights": [{"type": "directional", "direction": [1, 0, 1]}, {"type": "directional", "direction": [0, 1, 0.2]},
            {"type": "directional", "direction": [0, 1, 0], "moving": true},
            {"type": "point", "position": [0, 3, 0], "moving": true}],
 "bake": {"dirs": 40, "shells": 2}}
J
mkdir -p "$TMP/o4"
expect_ok "$SSS_BAKE" --scene "$TMP/m.json" -o "$TMP/o4" -q
expect_ok "$SSS_STAT" "$TMP/o4/blob.sss" --error --views 4 --no-image --json
contains "$TMP/out" '"static_lights":\[{"direction":\[0.70710678'
contains "$TMP/out" '"not_measured":""'
contains "$TMP/out" '"point_shells":{"lights":4,"rel_rms_max":'
p2=$(sed -n 's/.*"point_shells":{[^}]*"rel_rms_max":\([-0-9.eE+]*\).*/\1/p' "$TMP/out")
n=$(grep -o '"rel_rms":[-0-9.eE+]*' "$TMP/out" | sed -n '2,3p' | awk -F: '$2 <= 1e-6' | wc -l)
[ "$n" -eq 2 ] || fail "static lights' rows differ from the exact evaluator: $(cat "$TMP/out")"
expect_ok "$SSS_STAT" "$TMP/o4/blob.sss" --error --views 4 --no-image
contains "$TMP/out" 'static light 1 (0, 0.9806, 0.1961), exact values (QDIR): RMS'
contains "$TMP/out" 'point shells (PSHL), 4 point lights'
# the point shells' interpolation (Hao-Varshney 2004 sec. 3.3) against the
# exact point light: finer in distance and direction, smaller
sed 's/"shells": 2/"shells": 6/; s/"dirs": 40/"dirs": 200/' "$TMP/m.json" > "$TMP/m6.json"
mkdir -p "$TMP/o5"
expect_ok "$SSS_BAKE" --scene "$TMP/m6.json" -o "$TMP/o5" -q
expect_ok "$SSS_STAT" "$TMP/o5/blob.sss" --error --views 4 --no-image --json
p6=$(sed -n 's/.*"point_shells":{[^}]*"rel_rms_max":\([-0-9.eE+]*\).*/\1/p' "$TMP/out")
awk -v a="$p2" -v b="$p6" 'BEGIN { exit !(b > 0 && b < 0.5 * a && b < 0.1) }' ||
  fail "point shells' rel. RMS: $p2 with 2 shells x 40 directions, $p6 with 6 x 200 (want the second < half the first, < 0.1)"
# which gather sums the rows: the tree by default, --gather direct where
# the scene's "bake" says nothing (docs/heterogeneous.md sec. 4.5)
expect_ok "$SSS_BAKE" --scene "$TMP/m.json" --plan
contains "$TMP/out" 'gather        tree               hierarchical gather'
expect_ok "$SSS_BAKE" --scene "$TMP/m.json" --plan --gather direct
contains "$TMP/out" 'gather        direct             bake.gather (or --gather)'
# a --gather the scene's "bake" contradicts: one line, no plan
sed 's/"bake": {/"bake": {"gather": "direct", /' "$TMP/m.json" > "$TMP/mg.json"
grep -q '"gather": "direct"' "$TMP/mg.json" || fail "mg.json: no gather key written"
expect_fail 'mg.json: /bake/gather is "direct": --gather tree contradicts it' "$SSS_BAKE" --scene "$TMP/mg.json" --plan --gather tree
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "message should be one line"
expect_ok "$SSS_BAKE" --scene "$TMP/mg.json" --plan --gather direct
# the tree's memory planned before it is loaded: one line naming the
# object, no file
mkdir -p "$TMP/o9"
SSS_MEMORY_LIMIT_MB=2 expect_fail "m.json: /objects/0: the bake needs more than .* (the gather tree with 80 source columns)" \
  "$SSS_BAKE" --scene "$TMP/m.json" -o "$TMP/o9" -q
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "message should be one line"
[ ! -e "$TMP/o9/blob.sss" ] || fail "a refused bake should write no file"
# a scene bake without a moving directional light has no direction set:
# --error measures its static light and point shells alone; --query refuses.
# The direct rows: the static light's row is then the exact evaluator's
# bit for bit (the tree's far field and float sums are not)
cat > "$TMP/nd.json" <<'J'
{"objects": [{"name": "blob", "mesh": "blob.ply", "material": "skin1", "mm_per_unit": 10}],
 "lights": [{"type": "directional", "direction": [1, 0, 1]}, {"type": "point", "position": [0, 3, 0], "moving": true}],
 "bake": {"dirs": 40, "shells": 2, "gather": "direct"}}
J
mkdir -p "$TMP/o6"
expect_ok "$SSS_BAKE" --scene "$TMP/nd.json" -o "$TMP/o6" -q
expect_ok "$SSS_STAT" "$TMP/o6/blob.sss" --error --views 4 --json
for k in '"vertex_error":null' '"image_error_status":"skipped (no direction set)"' '"static_lights":\[{' \
         '"rel_rms":0,' '"point_shells":{"lights":4'; do
  contains "$TMP/out" "$k"
done
expect_ok "$SSS_STAT" "$TMP/o6/blob.sss" --error --views 4
contains "$TMP/out" 'no direction set (scene bake)'
expect_fail "has none of them" "$SSS_STAT" "$TMP/o6/blob.sss" --query 3 --light 0,0,1
# the environment's SH transfer (ENVT, docs/scenes.md "Accuracy"): T_i at 64
# random vertices against the exact q projected over 4 x the bake's 2048
# Fibonacci directions, rotated, and the radiance sum T_i L_i under the
# file's probe and random band-limited environments. An environment-only
# file is measured, not refused. The bake's own quadrature error on this
# blob reads 3.1-3.8e-4 (seeds 1-3; 3.2-3.6e-4 against 16 x the bake's
# directions): below 1e-3. The same file with every T_i
# scaled by 1.01 (its checksums redone) reads 0.01: the check can fail.
"$SSS_MKEXR" "$TMP/sky.exr" 32 16 half RGB 0.5 || fail "sss-mkexr"
cat > "$TMP/env.json" <<'J'
{"objects": [{"name": "blob", "mesh": "blob.ply", "material": "skin1", "mm_per_unit": 10}],
 "lights": [{"type": "environment", "probe": "sky.exr"}], "bake": {"sh_order": 3}}
J
mkdir -p "$TMP/o7"
expect_ok "$SSS_BAKE" --scene "$TMP/env.json" -o "$TMP/o7" -q
OMP_NUM_THREADS=2 expect_ok "$SSS_STAT" "$TMP/o7/blob.sss" --error --views 4 --json
cp "$TMP/out" "$TMP/env2.json"
for k in '"vertex_error":null' '"not_measured":""' \
         '"environment":{"order":3,"bake_directions":2048,"reference_directions":8192,' '"vertices":64,' \
         '"shadows":true' '"transfer":{"rms":' '"probe":{"rms":' '"random":{"environments":4,"rel_rms_max":'; do
  contains "$TMP/out" "$k"
done
t1=$(jq .environment.transfer.rel_rms "$TMP/out"); p1=$(jq .environment.probe.rel_rms "$TMP/out")
r1=$(jq .environment.random.rel_rms_max "$TMP/out")
awk -v t="$t1" -v p="$p1" -v r="$r1" 'BEGIN { exit !(t > 0 && t < 1e-3 && p > 0 && p < 1e-3 && r > 0 && r < 1e-3) }' ||
  fail "environment vs the exact evaluator: transfer $t1, probe $p1, random $r1 (want each in (0, 1e-3))"
# the same figures whatever the thread count
OMP_NUM_THREADS=1 expect_ok "$SSS_STAT" "$TMP/o7/blob.sss" --error --views 4 --json
cmp -s "$TMP/out" "$TMP/env2.json" || fail "sss-stat --error on ENVT differs between 1 and 2 threads"
expect_ok "$SSS_STAT" "$TMP/o7/blob.sss" --error --views 4
contains "$TMP/out" "environment (ENVT), SH order 3: 64 of 162 vertices against the exact q projected over 8192 directions"
contains "$TMP/out" "transfer T_i: RMS"
contains "$TMP/out" "radiance under 4 random band-limited environments: rel. RMS max"
python3 - "$TMP/o7/blob.sss" "$TMP/o7/scaled.sss" <<'P' || fail "cannot scale ENVT"
import struct, sys, zlib
b = bytearray(open(sys.argv[1], 'rb').read())
n = struct.unpack_from('<I', b, 12)[0]
for i in range(n):
    e = 24 + 40 * i
    if bytes(b[e:e + 4]) == b'ENVT':
        off, size = struct.unpack_from('<QQ', b, e + 8)
        order = struct.unpack_from('<I', b, off + 4)[0]
        t0 = off + 8 + 12 * order * order
        m = (off + size - t0) // 4
        v = struct.unpack_from('<%df' % m, b, t0)
        struct.pack_into('<%df' % m, b, t0, *[x * 1.01 for x in v])
        struct.pack_into('<I', b, e + 32, zlib.crc32(bytes(b[off:off + size])))
struct.pack_into('<I', b, 24 + 40 * n, zlib.crc32(bytes(b[:24 + 40 * n])))
open(sys.argv[2], 'wb').write(b)
P
expect_ok "$SSS_STAT" "$TMP/o7/scaled.sss" --error --views 4 --json
t2=$(jq .environment.transfer.rel_rms "$TMP/out"); p2=$(jq .environment.probe.rel_rms "$TMP/out")
awk -v t="$t2" -v p="$p2" 'BEGIN { exit !(t > 0.008 && t < 0.012 && p > 0.008 && p < 0.012) }' ||
  fail "ENVT scaled by 1.01: transfer $t2, probe $p2 (want each about 0.01)"
expect_fail "must be an existing directory" "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/nodir"
expect_fail "needs --scene" "$SSS_BAKE" --plan
echo "cli_scene: ok"
