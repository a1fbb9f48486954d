# Several lights and point lights without a scene file (docs/viewer.md,
# "Several lights and point lights"): sss-bake MESH --point-light bakes the
# distance shells (Hao & Varshney 2004 sec. 3.3) next to the direction set;
# sss-view --point-light draws from them, --light may be repeated, and every
# light is summed as a scene's lights are. The pictures are compared in
# linear float (EXR) with the specular term off, so that a sum is a sum.
. "$(dirname "$0")/lib.sh"
VIEW() { if [ -n "${SSS_VIEW_PRELOAD:-}" ]; then LD_PRELOAD="$SSS_VIEW_PRELOAD" "$SSS_VIEW" "$@"; else "$SSS_VIEW" "$@"; fi; }
# single scattering off: it is drawn for one directional light only, not
# for a sum of lights (docs/layers.md §7), and sums are compared here
IMG="--offscreen --size 96x72 --no-specular --single off"
expect_ok "$SSS_GENMESH" blob 2 "$TMP/blob.ply"
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/plain.sss" --material skin1 --mm-per-unit 10 --dirs 40 -q
# a file without shells: one line naming the file and the bake that adds them, exit 2, no image
expect_fail "^sss-view: $TMP/plain.sss: not baked for near point lights (no distance shells, section PSHL): bake it with 'sss-bake blob.ply --material skin1 --mm-per-unit 10 --point-light 0,0,2 -o $TMP/plain.sss'\$" \
  VIEW "$TMP/plain.sss" --point-light 0,0,2 $IMG --out "$TMP/x.exr"
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "more than one line: $(cat "$TMP/err")"
[ ! -e "$TMP/x.exr" ] || fail "an image was written for a file without shells"
# the bake with point lights: the planner's point-shells pass and the direction set in one file
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/pt.sss" --material skin1 --mm-per-unit 10 --dirs 40 \
  --point-light 0,0,2 --point-light 1,1,1,3 --json -q
# (skin1 also takes single scattering by the planner's rule, docs/layers.md §4)
contains "$TMP/out" '"direction-set","point-shells","single-scattering"]'
expect_ok VIEW "$TMP/pt.sss" --point-light 0,0,2 $IMG --out "$TMP/point.exr"
contains "$TMP/err" 'lights of the command line: point-shells$'
expect_ok VIEW "$TMP/pt.sss" --light 0,0,1 $IMG --out "$TMP/dir.exr"
read -r D MP MD < <("$SSS_EXRSTATS" "$TMP/point.exr" "$TMP/dir.exr")
awk -v d="$D" -v a="$MP" 'BEGIN { exit !(d > 0.05 && a > 0) }' || fail "the point light draws the directional picture (difference $D, mean $MP)"
# the CPU sum draws the GPU's picture
expect_ok VIEW "$TMP/pt.sss" --point-light 0,0,2 $IMG --out "$TMP/point_cpu.exr" --cpu
read -r D _ _ < <("$SSS_EXRSTATS" "$TMP/point.exr" "$TMP/point_cpu.exr")
awk -v d="$D" 'BEGIN { exit !(d < 1e-4) }' || fail "--point-light on the CPU differs from the GPU by $D"
# linear in I: I = 2 at the same place is the sum of two I = 1
expect_ok VIEW "$TMP/pt.sss" --point-light 0,0,2,1 $IMG --out "$TMP/i1.exr" --exposure 1
expect_ok VIEW "$TMP/pt.sss" --point-light 0,0,2,2 $IMG --out "$TMP/i2.exr" --exposure 1
D=$("$SSS_EXRSTATS" "$TMP/i1.exr" "$TMP/i1.exr" "$TMP/i2.exr")
awk -v d="$D" 'BEGIN { exit !(d < 1e-4) }' || fail "I = 2 is not twice I = 1 (difference $D)"
# two --light: the sum of the two one-light pictures (float rounding), on both paths
expect_ok VIEW "$TMP/pt.sss" --light 1,0,1 $IMG --out "$TMP/side.exr"
for c in "" --cpu; do
  # shellcheck disable=SC2086
  expect_ok VIEW "$TMP/pt.sss" --light 1,0,1 --light 0,0,1 $IMG --out "$TMP/two.exr" $c
  D=$("$SSS_EXRSTATS" "$TMP/side.exr" "$TMP/dir.exr" "$TMP/two.exr")
  awk -v d="$D" 'BEGIN { exit !(d < 1e-4) }' || fail "two --light${c:+ ($c)} differ from the sum of one each by $D"
done
# a point light and a --light: the sum too
expect_ok VIEW "$TMP/pt.sss" --light 0,0,1 --point-light 0,0,2 $IMG --out "$TMP/mixed.exr"
D=$("$SSS_EXRSTATS" "$TMP/dir.exr" "$TMP/point.exr" "$TMP/mixed.exr")
awk -v d="$D" 'BEGIN { exit !(d < 1e-4) }' || fail "--light + --point-light differ from the sum by $D"
expect_ok VIEW "$TMP/pt.sss" --point-light 0,0,2 --point-light 2,0,0 --offscreen --bench 2 --size 64x48
contains "$TMP/out" '"paths":"point-shells"'
# bad values: one line each, exit 2
L17=""; for i in $(seq 17); do L17="$L17 --light 0,0,1"; done
# shellcheck disable=SC2086
expect_fail "^sss-view: --light: '0,0,1': at most 16 may be given\$" VIEW "$TMP/pt.sss" $L17 --offscreen --out "$TMP/x.exr"
expect_fail "^sss-view: --point-light: 'nan,0,2' must be X,Y,Z or X,Y,Z,I with I > 0\$" \
  VIEW "$TMP/pt.sss" --point-light nan,0,2 --offscreen --out "$TMP/x.exr"
expect_fail "^sss-view: --point-light: '0,0,2,0' must be X,Y,Z or X,Y,Z,I with I > 0\$" \
  VIEW "$TMP/pt.sss" --point-light 0,0,2,0 --offscreen --out "$TMP/x.exr"
expect_fail "^sss-view: --light: '1,nan,0' must be three numbers X,Y,Z\$" \
  VIEW "$TMP/pt.sss" --light 0,0,1 --light 1,nan,0 --offscreen --out "$TMP/x.exr"
expect_fail "^sss-view: --scene names its own lights: not with --point-light\$" \
  VIEW "$TMP/pt.sss" --point-light 0,0,2 --scene "$TMP/none.json" --offscreen --out "$TMP/x.exr"
[ ! -e "$TMP/x.exr" ] || fail "a refused command wrote an image"
P17=""; for i in $(seq 17); do P17="$P17 --point-light 0,0,$i"; done
# shellcheck disable=SC2086
expect_fail "^sss-bake: --point-light: '0,0,17': at most 16 may be given\$" "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" $P17
expect_fail "^sss-bake: --point-light: '0,0,2,-1' must be X,Y,Z or X,Y,Z,I with I > 0\$" \
  "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --point-light 0,0,2,-1
expect_fail "^sss-bake: --quant: not with --point-light" "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/x.sss" --point-light 0,0,2 --quant float
expect_fail "^sss-bake: --point-light and --scene exclude each other" "$SSS_BAKE" --scene "$TMP/none.json" -o "$TMP" --point-light 0,0,2
expect_fail "^sss-bake: .*missing.ply" "$SSS_BAKE" "$TMP/missing.ply" -o "$TMP/x.sss" --point-light 0,0,2
[ ! -e "$TMP/x.sss" ] || fail "a refused bake wrote a file"
echo PASS
