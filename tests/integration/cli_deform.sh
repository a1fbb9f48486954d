# sss-bake --scene with a deforming object (docs/deformable.md §4): the
# planner sends it to the per-frame path with its reason and bakes nothing
# for it, while a static object of the same scene keeps its bake; scene
# errors in "deform" name the file and the JSON path.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 2 "$TMP/blob.ply"
expect_ok "$SSS_GENMESH" sphere 2 "$TMP/sphere.ply"
cat > "$TMP/s.json" <<'J'
{"objects": [
  {"name": "bar", "mesh": "blob.ply", "material": "marble", "mm_per_unit": 10,
   "deform": {"type": "bend", "axis": [0, 0, 1], "angle_deg": 40, "period_s": 4}},
  {"name": "ball", "mesh": "sphere.ply", "material": "skin1", "transform": {"translate": [3, 0, 0]}}],
 "lights": [{"type": "directional", "direction": [1, 0, 1]},
            {"type": "point", "position": [0, 3, 0]}],
 "bake": {"dirs": 20}}
J
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" --plan
for pat in "object 0 'bar' .*effects: none (per-frame: nothing baked)" 'deform        per-frame .*the object deforms (bend' \
           'light 0       per-frame' 'light 1       none .*directional lights only' \
           "object 1 'ball'" 'scene-shadow  off .*every other object moves (or deforms)' 'light 0       directional-exact'; do
  grep -q -- "$pat" "$TMP/out" || { cat "$TMP/out" >&2; fail "--plan should print '$pat'"; }
done
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" --plan --json
contains "$TMP/out" '"per_frame":	true'
contains "$TMP/out" '"per_frame":	false'
# the bake writes the static object's file only, and says why not the other
mkdir -p "$TMP/o"
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/o"
contains "$TMP/err" "object 'bar' deforms: evaluated per frame, nothing baked"
[ -s "$TMP/o/ball.sss" ] || fail "no ball.sss"
[ ! -e "$TMP/o/bar.sss" ] || fail "bar.sss written for a deforming object"
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/o" -q --json
contains "$TMP/out" '"object":"bar","per_frame":true'
# sss-stat --scene --time --error: what sss-view draws for the pose (tree
# gather) against the exact evaluator on that pose, within the tree's
# stated bound (docs/deformable.md §3: 2e-3 of max q)
expect_ok "$SSS_STAT" --scene "$TMP/s.json" --time 1 --error --views 3 --json
contains "$TMP/out" '"object":"bar","deform":"bend","animated":false,"time":1,"theta_deg":40'
python3 - "$TMP/out" <<'P' || fail "sss-stat --scene: error beyond the tree's bound: $(cat "$TMP/out")"
import json, sys
o = json.load(open(sys.argv[1]))["objects"][0]
ok = o["rms_exact"] > 0 and o["max_abs"] <= 2e-3 * 5 * o["rms_exact"] and o["rel_rms"] < 2e-3
# the image error (section 3.3) of the same pose: pictures in [0, 1], so
# within the tree's bound too, and not 0 (the two q differ by rounding at least)
im = o["image_error"]
ok = ok and o["image_error_status"] == "ok" and im["views"] == 3 and 0 < im["rms_max"] < 2e-3
ok = ok and im["rms_mean"] <= im["rms_max"] and 0 < im["coverage_mean"] < 1
sys.exit(0 if ok else 1)
P
expect_ok "$SSS_STAT" --scene "$TMP/s.json" --time 1 --error --views 2
contains "$TMP/out" "object 'bar' at t = 1 s (bend, theta 40 deg), 162 vertices, 2 views: per-frame q (tree gather, point weights)"
contains "$TMP/out" "image RMS (section 3.3) over 2 views, 256x256"
expect_fail "takes --error" "$SSS_STAT" --scene "$TMP/s.json" --time 1
expect_fail "without FILE.sss" "$SSS_STAT" "$TMP/o/ball.sss" --scene "$TMP/s.json" --error
# a field on a deforming object: read at the rest pose, the endpoints'
# product (docs/deformable.md sec. 10); sss-stat has no tree to measure there
sed 's/"material": "marble", "mm_per_unit": 10,/"mm_per_unit": 10, "material": {"preset": "marble", "inside": "ketchup", "field": {"procedural": "veins", "scale_mm": 5}},/' \
  "$TMP/s.json" > "$TMP/field.json"
expect_ok "$SSS_BAKE" --scene "$TMP/field.json" --plan
grep -q -- "field         per-frame .*rest-pose position.*Eq. 8" "$TMP/out" || { cat "$TMP/out" >&2; fail "--plan should say the field's model"; }
expect_fail "field.json: /objects/0/material/field: a deforming object with a field is evaluated by the exact sum" \
  "$SSS_STAT" --scene "$TMP/field.json" --time 1 --error --views 2
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "message should be one line"
# a deforming object needs a directional light; bad deformers name their path
sed 's/{"type": "directional", "direction": \[1, 0, 1\]},//' "$TMP/s.json" > "$TMP/bad1.json"
expect_fail "bad1.json: /objects/0/deform: no directional light" "$SSS_BAKE" --scene "$TMP/bad1.json" --plan
sed 's/"angle_deg": 40/"angle_deg": "40"/' "$TMP/s.json" > "$TMP/bad2.json"
expect_fail "bad2.json: /objects/0/deform/angle_deg: expected a number" "$SSS_BAKE" --scene "$TMP/bad2.json" --plan
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "message should be one line"
sed 's/"type": "bend"/"type": "skin"/' "$TMP/s.json" > "$TMP/bad3.json"
expect_fail "bad3.json: /objects/0/deform/axis: unknown key" "$SSS_BAKE" --scene "$TMP/bad3.json" --plan
# a glTF whose skin its clip moves (sss-genmesh's two-bone tube) deforms
# without a "deform" key: per frame, no file; sss-stat measures its pose
expect_ok "$SSS_GENMESH" tube 4 "$TMP/arm.gltf" 0.25 skin
cat > "$TMP/arm.json" <<'J'
{"objects": [{"name": "arm", "mesh": "arm.gltf", "material": "skin1", "mm_per_unit": 100}],
 "lights": [{"type": "directional", "direction": [0.6, -0.3, 0.8]}]}
J
expect_ok "$SSS_BAKE" --scene "$TMP/arm.json" --plan
contains "$TMP/out" 'deform        per-frame          the mesh is skinned and its clip moves it'
mkdir -p "$TMP/oa"
expect_ok "$SSS_BAKE" --scene "$TMP/arm.json" -o "$TMP/oa" -q
[ ! -e "$TMP/oa/arm.sss" ] || fail "arm.sss written for an animated rig"
expect_ok "$SSS_STAT" --scene "$TMP/arm.json" --time 1 --error --views 2
contains "$TMP/out" "object 'arm' at t = 1 s (the glTF's clip), 138 vertices"
echo ok
