# "editable": true (docs/heterogeneous.md §9): the planner takes the
# run-time path and says why, sss-bake --scene bakes nothing for the
# object, sss-view --scene --offscreen draws it with no .sss file (q per
# pixel by seed 000's pass), the embedded box darkens the picture against
# the same block without a field, directional and point lights are drawn
# (environment lights and a point light inside the object are not),
# --save-scene writes a scene that draws the same picture (§9.6), and bad
# uses are refused in one line.
. "$(dirname "$0")/lib.sh"
VIEW() { if [ -n "${SSS_VIEW_PRELOAD:-}" ]; then LD_PRELOAD="$SSS_VIEW_PRELOAD" "$SSS_VIEW" "$@"; else "$SSS_VIEW" "$@"; fi; }
expect_ok "$SSS_GENMESH" cube 8 "$TMP/block.ply" 2
cat > "$TMP/edit.json" <<'J'
{"objects": [{"name": "block", "mesh": "block.ply", "mm_per_unit": 10, "editable": true,
  "material": {"preset": "marble", "inside": "ketchup",
               "field": {"procedural": "box", "centre_mm": [0, 0, 0], "half_mm": [4, 4, 4], "edge_mm": 1}}}],
 "lights": [{"type": "directional", "direction": [0, 0, -1], "intensity": 1}],
 "camera": {"position": [0.6, 0.5, 4.5], "target": [0, 0, 0], "up": [0, 1, 0]}}
J
expect_ok "$SSS_BAKE" --scene "$TMP/edit.json" --plan
contains "$TMP/out" "field         run-time           editable object (box field)"
contains "$TMP/out" "light 0       run-time"
mkdir -p "$TMP/baked"
expect_ok "$SSS_BAKE" --scene "$TMP/edit.json" -o "$TMP/baked"
contains "$TMP/err" "object 'block' is editable: evaluated per frame, nothing baked"
[ ! -e "$TMP/baked/block.sss" ] || fail "an editable object was baked"
cp "$TMP/edit.json" "$TMP/input.json"
expect_ok VIEW --scene "$TMP/edit.json" --offscreen --out "$TMP/box.exr" --size 96x72 --exposure 100 --save-scene "$TMP/saved.json"
contains "$TMP/err" "'block' editable, 386 vertices, q per pixel by the run-time path (13 samples, 4 steps)"
contains "$TMP/err" "sss-view: edited scene written to $TMP/saved.json"
# the light's intensity enters once, in its map: twice the light, twice the picture
sed 's/"intensity": 1}/"intensity": 2}/' "$TMP/edit.json" > "$TMP/bright.json"
expect_ok VIEW --scene "$TMP/bright.json" --offscreen --out "$TMP/bright.exr" --size 96x72 --exposure 100
read -r D MA MB < <("$SSS_EXRSTATS" "$TMP/bright.exr" "$TMP/box.exr")
awk -v a="$MA" -v b="$MB" 'BEGIN { exit !(a > 1.98 * b && a < 2.02 * b) }' || fail "intensity 2: mean $MA against $MB at 1"
# the same block with no field: brighter everywhere the box was behind
sed 's/"field": {[^}]*}/"field": {"constant": 0}/' "$TMP/edit.json" > "$TMP/plain.json"
expect_ok VIEW --scene "$TMP/plain.json" --offscreen --out "$TMP/plain.exr" --size 96x72 --exposure 100
read -r D MA MB < <("$SSS_EXRSTATS" "$TMP/box.exr" "$TMP/plain.exr")
awk -v a="$MA" -v b="$MB" 'BEGIN { exit !(a > 0 && a < 0.9 * b) }' || fail "the box's mean $MA against $MB without it"
# a second directional light and a point light each add their own pass
# (brighter); a point light behind the block, with no directional light,
# draws it too (its perspective map), while an environment light and a
# point light within the object's bounding sphere are said not to be drawn
sed 's|"lights": \[|"lights": [{"type": "directional", "direction": [1, 0.3, 0.2], "intensity": 0.5}, {"type": "point", "position": [0, 0, 3], "intensity": 1},|' \
  "$TMP/edit.json" > "$TMP/two.json"
expect_ok "$SSS_BAKE" --scene "$TMP/two.json" --plan
contains "$TMP/out" "light 0       run-time           directional light: its light-space map is rendered each frame, the lights' q and surface terms summed"
contains "$TMP/out" "light 1       run-time           point light: its perspective light-space map (1/r^2 fall-off"
contains "$TMP/out" "light 2       run-time"
expect_ok VIEW --scene "$TMP/two.json" --offscreen --out "$TMP/two.exr" --size 96x72 --exposure 100
! grep -q "not drawn" "$TMP/err" || fail "a light said not to be drawn: $(cat "$TMP/err")"
read -r D MA MB < <("$SSS_EXRSTATS" "$TMP/two.exr" "$TMP/box.exr")
awk -v a="$MA" -v b="$MB" 'BEGIN { exit !(a > 1.1 * b) }' || fail "three lights' mean $MA against $MB for one"
cp "$TMP/box.exr" "$TMP/sky.exr"   # any probe: the planner reads it
sed 's|"lights": \[.*\],|"lights": [{"type": "environment", "probe": "sky.exr"}, {"type": "point", "position": [0, 0.5, 0.5], "intensity": 1}, {"type": "point", "position": [0, 0, -4], "intensity": 16}],|' \
  "$TMP/edit.json" > "$TMP/point.json"
expect_ok "$SSS_BAKE" --scene "$TMP/point.json" --plan
contains "$TMP/out" "light 0       none               the run-time path takes directional and point lights only (this environment light"
# the point light inside: the planner's reason and sss-view's line are one sentence, naming it and the object
INSIDE="the point light at (0, 0.5, 0.5) lies within object 'block''s bounding sphere (radius 1.76669): the run-time path does not draw it"
contains "$TMP/out" "light 1       none               $INSIDE"
contains "$TMP/out" "light 2       run-time           point light"
expect_ok VIEW --scene "$TMP/point.json" --offscreen --out "$TMP/point.exr" --size 96x72 --exposure 100
contains "$TMP/err" "point.json: /lights/1: $INSIDE"
contains "$TMP/err" "/lights: 2 light(s) not drawn: the run-time path sums up to 8 directional and point lights, no environment light and no point light within the object's bounding sphere"
read -r D MA MB < <("$SSS_EXRSTATS" "$TMP/point.exr" "$TMP/box.exr")
awk -v a="$MA" -v b="$MB" 'BEGIN { exit !(a > 0.5 * b && a < 2 * b) }' || fail "the point light's mean $MA against $MB for the directional light"
# --save-scene (docs/heterogeneous.md §9.6) offscreen (box.exr's, above):
# the scene as drawn, which draws the same picture; never over the input; a
# field's strength other than 1 is the run-time path's, refused by a bake
expect_ok VIEW --scene "$TMP/saved.json" --offscreen --out "$TMP/saved.exr" --size 96x72 --exposure 100
read -r D MA MB < <("$SSS_EXRSTATS" "$TMP/saved.exr" "$TMP/box.exr")
awk -v d="$D" 'BEGIN { exit !(d == 0) }' || fail "the saved scene draws differently ($D)"
expect_fail "edit.json: is the same file as the input" VIEW --scene "$TMP/edit.json" --offscreen --out "$TMP/y.png" --save-scene "$TMP/edit.json"
[ ! -e "$TMP/y.png" ] || fail "y.png written by a refused command"
cmp -s "$TMP/edit.json" "$TMP/input.json" || fail "the input scene changed"
# a target in a missing folder is refused at start-up, offscreen and in the window alike, creating nothing
for mode in "--offscreen --out $TMP/y.png" ""; do
  # shellcheck disable=SC2086
  expect_fail "sss-view: $TMP/nodir/e.json: its folder does not exist" VIEW --scene "$TMP/edit.json" $mode --save-scene "$TMP/nodir/e.json"
  [ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "more than one line: $(cat "$TMP/err")"
  [ ! -e "$TMP/y.png" ] && [ ! -e "$TMP/nodir" ] || fail "a refused --save-scene left a file"
done
sed 's/, "editable": true//' "$TMP/edit.json" > "$TMP/static.json"
expect_fail "--save-scene: only for a scene whose object is editable" VIEW --scene "$TMP/static.json" --offscreen --out "$TMP/y.png" --save-scene "$TMP/z.json"
[ ! -e "$TMP/z.json" ] || fail "z.json written by a refused command"
sed -e 's/"edge_mm": 1}/"edge_mm": 1, "strength": 2}/' -e 's/, "editable": true//' "$TMP/edit.json" > "$TMP/strong.json"
expect_fail "strong.json: /objects/0/material/field/strength: a strength other than 1 is drawn by the run-time path only" \
  "$SSS_BAKE" --scene "$TMP/strong.json" --plan
# refused in one line
sed 's/"editable": true/"editable": "yes"/' "$TMP/edit.json" > "$TMP/bad.json"
expect_fail "bad.json: /objects/0/editable: expected true or false" "$SSS_BAKE" --scene "$TMP/bad.json" --plan
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "message should be one line"
sed 's/"editable": true/"editable": true, "deform": {"type": "bend", "angle_deg": 30}/' "$TMP/edit.json" > "$TMP/bend.json"
expect_fail "bend.json: /objects/0/editable: an editable object that deforms is not supported yet" \
  "$SSS_BAKE" --scene "$TMP/bend.json" --plan
expect_fail "/objects/0/editable: an editable object that deforms is not supported yet" \
  VIEW --scene "$TMP/bend.json" --offscreen --out "$TMP/x.png"
[ ! -e "$TMP/x.png" ] || fail "x.png written by a refused command"
# the example scene, on the mesh its comment says to generate
mkdir -p "$TMP/ex"
expect_ok "$SSS_GENMESH" cube 16 "$TMP/ex/block.ply" 2
cp "$SSS_SOURCE/data/scenes/editable_box.json" "$TMP/ex/"
expect_ok VIEW --scene "$TMP/ex/editable_box.json" --offscreen --out "$TMP/ex.png" --size 96x72 --exposure 150
contains "$TMP/err" "'block' editable, 1538 vertices"
read -r W H MEAN SD NONBG < <("$SSS_PNGSTATS" "$TMP/ex.png")
awk -v n="$NONBG" 'BEGIN { exit !(n > 0.2) }' || fail "ex.png is nearly empty ($NONBG of the pixels drawn)"
echo ok
