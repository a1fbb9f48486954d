# Material fields on the command line (docs/heterogeneous.md): sss-genmesh
# writes a procedural field as .vdb, --plan says what each field becomes,
# the bake stores the field (section FELD, counted by sss-stat), the bytes
# do not depend on the thread count, and a bad .vdb or a field that does not
# cover the mesh fails in one line naming the file, leaving no file behind.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" sphere 2 "$TMP/ball.ply"
expect_ok "$SSS_GENMESH" field sphere 24 "$TMP/stone.vdb" 30
contains "$TMP/err" "stone.vdb: grid 'density', 24 x 24 x 24 nodes"
expect_fail "field kind 'clouds' is not" "$SSS_GENMESH" field clouds 24 "$TMP/x.vdb"
scene() { # scene NAME FIELD
  cat > "$TMP/$1.json" <<J
{"objects": [{"name": "ball", "mesh": "ball.ply", "mm_per_unit": 10,
  "material": {"sigma_a": [0.01, 0.01, 0.01], "sigmap_s": [1, 1, 1], "inside": "ketchup", "field": $2}}],
 "lights": [{"type": "directional", "direction": [0, 0, 1]}]}
J
}
scene vdb '{"vdb": "stone.vdb", "grid": "density"}'
expect_ok "$SSS_BAKE" --scene "$TMP/vdb.json" --plan
contains "$TMP/out" "field         baked              static object with a grid field"
contains "$TMP/out" "channels      3 channels"
mkdir -p "$TMP/o1" "$TMP/o2"
expect_ok "$SSS_BAKE" --scene "$TMP/vdb.json" -o "$TMP/o1" --threads 1
expect_ok "$SSS_BAKE" --scene "$TMP/vdb.json" -o "$TMP/o2" --threads 2
cmp "$TMP/o1/ball.sss" "$TMP/o2/ball.sss" || fail "the field bake's bytes depend on the thread count"
expect_ok "$SSS_STAT" "$TMP/o1/ball.sss" --json
contains "$TMP/out" '"field":"grid"'
contains "$TMP/out" '"tag":"FELD"'
expect_ok "$SSS_STAT" "$TMP/o1/ball.sss"
contains "$TMP/out" "field: grid, inside sigma_a"
# a constant is folded: no section FELD
scene const '{"constant": 0.25}'
expect_ok "$SSS_BAKE" --scene "$TMP/const.json" --plan
contains "$TMP/out" "field         folded             a constant field c = 0.25"
mkdir -p "$TMP/o3"
expect_ok "$SSS_BAKE" --scene "$TMP/const.json" -o "$TMP/o3"
expect_ok "$SSS_STAT" "$TMP/o3/ball.sss" --json
contains "$TMP/out" '"field":null'
grep -q FELD "$TMP/out" && fail "a folded constant should write no section FELD"
# a .vdb that is not one, a grid that is missing, a field that misses the mesh
printf 'not a volume' > "$TMP/junk.vdb"
scene junk '{"vdb": "junk.vdb", "grid": "density"}'
mkdir -p "$TMP/o4"
expect_fail "junk.vdb: not a readable OpenVDB file" "$SSS_BAKE" --scene "$TMP/junk.json" -o "$TMP/o4"
[ "$(wc -l < "$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "the error should be one line"; }
[ -z "$(ls -A "$TMP/o4")" ] || fail "a failed bake should leave no file"
scene nogrid '{"vdb": "stone.vdb", "grid": "temperature"}'
expect_fail "stone.vdb: grid 'temperature' not found (the file holds: density)" "$SSS_BAKE" --scene "$TMP/nogrid.json" -o "$TMP/o4"
expect_ok "$SSS_GENMESH" field sphere 8 "$TMP/small.vdb" 4
scene small '{"vdb": "small.vdb", "grid": "density"}'
expect_fail "small.vdb: field: the grid spans" "$SSS_BAKE" --scene "$TMP/small.json" -o "$TMP/o4"
scene far '{"procedural": "sphere", "centre_mm": [100, 0, 0], "radius_mm": 5}'
expect_fail "far.json: /objects/0/material/field: field: the sphere" "$SSS_BAKE" --scene "$TMP/far.json" -o "$TMP/o4"
[ -z "$(ls -A "$TMP/o4")" ] || fail "a failed bake should leave no file"
# a surface texture (docs/heterogeneous.md §4.4): the planner's reason, the
# flag in FELD (sss-stat), the reference refusing it, a bad value refused
scene tex '{"procedural": "sphere", "centre_mm": [0, 0, 8], "radius_mm": 4, "edge_mm": 1, "surface": true}'
expect_ok "$SSS_BAKE" --scene "$TMP/tex.json" --plan
contains "$TMP/out" "field         baked              surface texture (seed 001 sec. 5): endpoints' profiles, no volume march"
mkdir -p "$TMP/o5"
# with a moving light (a direction set), which sss-stat --model-error measures
sed 's/"direction": \[0, 0, 1\]}/"direction": [0, 0, 1], "moving": true}/' "$TMP/tex.json" > "$TMP/texm.json"
expect_ok "$SSS_BAKE" --scene "$TMP/texm.json" -o "$TMP/o5"
expect_ok "$SSS_STAT" "$TMP/o5/ball.sss"
contains "$TMP/out" "field: sphere surface texture (endpoints only, sec. 4.4), inside sigma_a"
expect_fail "ball.sss: reference: a surface texture (section FELD) has no volume for the paths to track" \
  "$SSS_STAT" "$TMP/o5/ball.sss" --model-error --light 0,0,1 --view 0,0,1 --paths 16
[ "$(wc -l < "$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "the error should be one line"; }
scene texbad '{"procedural": "sphere", "centre_mm": [0, 0, 8], "radius_mm": 4, "surface": "on"}'
expect_fail "texbad.json: /objects/0/material/field/surface: expected true or false" \
  "$SSS_BAKE" --scene "$TMP/texbad.json" -o "$TMP/o4"
[ -z "$(ls -A "$TMP/o4")" ] || fail "a refused scene should leave no file"
# scene errors name the JSON path
scene bad '{"procedural": "sphere", "centre_mm": [0, 0, 0]}'
expect_fail "bad.json: /objects/0/material/field/radius_mm: missing" "$SSS_BAKE" --scene "$TMP/bad.json" --plan
echo "cli_field: ok"
