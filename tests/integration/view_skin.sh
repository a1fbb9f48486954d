# The scene's "skin" deformer (docs/deformable.md §2) through the tools, on
# the example scene data/scenes/skin_tube.json and a generated tube: the
# planner sends it to the per-frame path and nothing is baked; sss-stat
# measures its pose against the exact evaluator within the tree's bound;
# sss-view draws it, t = 0 being the rest pose and t = 1 another picture;
# bad bone chains are refused in one line naming the file and the JSON
# element, with a non-zero exit and nothing written.
. "$(dirname "$0")/lib.sh"
VIEW() { if [ -n "${SSS_VIEW_PRELOAD:-}" ]; then LD_PRELOAD="$SSS_VIEW_PRELOAD" "$SSS_VIEW" "$@"; else "$SSS_VIEW" "$@"; fi; }
expect_ok "$SSS_GENMESH" tube 8 "$TMP/tube.ply" 0.25
# the example lit from the front (it is lit from behind: only a rim glows)
python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); s["lights"][0]["direction"]=[0.6, -0.3, 0.8]
json.dump(s, open(sys.argv[2], "w"))' "$SSS_SOURCE/data/scenes/skin_tube.json" "$TMP/s.json"
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" --plan
contains "$TMP/out" 'deform        per-frame .*the object deforms (skin of 2 bones'
mkdir -p "$TMP/o"
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/o"
contains "$TMP/err" "object 'tube' deforms: evaluated per frame, nothing baked"
[ -z "$(ls -A "$TMP/o")" ] || fail "files written for a skinned object: $(ls "$TMP/o")"
# the pose's q (tree gather) against the exact evaluator on the pose,
# within the tree's bound of docs/deformable.md §3 (2e-3 of max q)
expect_ok "$SSS_STAT" --scene "$TMP/s.json" --time 1 --error --views 3 --json
contains "$TMP/out" '"object":"tube","deform":"skin","animated":false,"time":1,"theta_deg":60'
python3 - "$TMP/out" <<'P' || fail "sss-stat --scene: error beyond the tree's bound: $(cat "$TMP/out")"
import json, sys
o = json.load(open(sys.argv[1]))["objects"][0]
sys.exit(0 if o["rms_exact"] > 0 and o["max_abs"] <= 2e-3 * 5 * o["rms_exact"] and o["rel_rms"] < 2e-3 else 1)
P
expect_ok "$SSS_STAT" --scene "$TMP/s.json" --time 1 --error --views 2
contains "$TMP/out" "object 'tube' at t = 1 s (skin, theta 60 deg), 530 vertices, 2 views"
# pictures: t = 0 is the rest pose (the same pixels as a bend of angle 0),
# t = 1 (20 and 60 degrees) moves the tube
python3 -c 'import json,sys; s=json.load(open(sys.argv[1])); s["objects"][0]["deform"]={"type": "bend", "angle_deg": 0}
json.dump(s, open(sys.argv[2], "w"))' "$TMP/s.json" "$TMP/rest.json"
expect_ok VIEW --scene "$TMP/rest.json" --time 1 --offscreen --out "$TMP/rest.png" --size 160x120
for t in 0 1; do expect_ok VIEW --scene "$TMP/s.json" --time $t --offscreen --out "$TMP/t$t.png" --size 160x120; done
contains "$TMP/err" "'tube' at t = 1 s (skin, theta 60 deg), 530 vertices, q per frame on the CPU"
F=$("$SSS_PNGSTATS" "$TMP/rest.png" "$TMP/t0.png")
awk -v f="$F" 'BEGIN { exit !(f == 0) }' || fail "t = 0 differs from the rest pose in $F of the pixels"
read -r W H MEAN SD NONBG < <("$SSS_PNGSTATS" "$TMP/t1.png")
awk -v m="$MEAN" -v n="$NONBG" 'BEGIN { exit !(m > 1 && n > 0.02) }' || fail "t1.png is empty (mean $MEAN, lit $NONBG)"
F=$("$SSS_PNGSTATS" "$TMP/t0.png" "$TMP/t1.png")
awk -v f="$F" 'BEGIN { exit !(f > 0.02) }' || fail "the skin at t = 1 changed only $F of the pixels"
# bad chains: one line naming the file and the element, nothing written
bad() { # NAME PYTHON-EDIT WANT
  python3 -c "import json,sys; s=json.load(open(sys.argv[1])); b=s['objects'][0]['deform']['bones']; $2; json.dump(s, open(sys.argv[2], 'w'))" \
    "$TMP/s.json" "$TMP/$1.json"
  expect_fail "$1.json: $3" "$SSS_BAKE" --scene "$TMP/$1.json" -o "$TMP/o"
  [ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "$1: message should be one line"
  expect_fail "$1.json: $3" VIEW --scene "$TMP/$1.json" --time 1 --offscreen --out "$TMP/x.png"
  expect_fail "$1.json: $3" "$SSS_STAT" --scene "$TMP/$1.json" --time 1 --error
  [ -z "$(ls -A "$TMP/o")" ] && [ ! -e "$TMP/x.png" ] || fail "$1: a refused command wrote a file"
}
bad nobones 'b.clear()' '/objects/0/deform/bones: expected an array of 1 to 16 bones'
bad many 'b.extend([dict(b[0]) for i in range(15)])' '/objects/0/deform/bones: expected an array of 1 to 16 bones'
bad parent 'b[1]["parent"] = 5' '/objects/0/deform/bones/1/parent: 5 is not a bone index in \[0, 2)'
bad cycle 'b[0]["parent"] = 1' '/objects/0/deform/bones/0/parent: 1: the parents of bone 0 never reach a root (a cycle)'
bad zero 'b[1]["tail"] = b[1]["head"]' '/objects/0/deform/bones/1/tail: equals the head (a bone needs a length)'
bad nohead 'del b[0]["head"]' '/objects/0/deform/bones/0/head: missing'
bad noangle 'del b[1]["angle_deg"]' '/objects/0/deform/bones/1/angle_deg: missing'
bad axis 'b[1]["axis"] = [0, 0, 0]' '/objects/0/deform/bones/1/axis: must be a non-zero vector'
bad key 'b[0]["lenght"] = 1' '/objects/0/deform/bones/0/lenght: unknown key'
sed 's/"angle_deg": 60/"angle_deg": 1e999/' "$TMP/s.json" > "$TMP/inf.json"
expect_fail "inf.json: /objects/0/deform/bones/1/angle_deg: expected a number" "$SSS_BAKE" --scene "$TMP/inf.json" --plan
echo ok
