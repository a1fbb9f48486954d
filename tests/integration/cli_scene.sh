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
# a scene bake without a moving directional light has no direction set:
# --error measures its static light and point shells alone; --query refuses
cat > "$TMP/nd.json" <<'J'
{"objects": [{"name": "blob", "mesh": "blob.ply", "material": "skin1", "mm_per_unit": 10}],
 "lights": [{"type": "directional", "direction": [1, 0, 1]}, {"type": "point", "position": [0, 3, 0], "moving": true}],
 "bake": {"dirs": 40, "shells": 2}}
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
expect_fail "must be an existing directory" "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/nodir"
expect_fail "needs --scene" "$SSS_BAKE" --plan
echo "cli_scene: ok"
