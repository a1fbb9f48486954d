# Layers of variable depth (docs/layers.md §3): depth maps written by
# sss-genmesh and procedural depths reach the file (section LDEP) through
# the scene bake; identical layers give one layer's single scattering and
# the same q whatever their depths; a map of one value is its number; the
# example scene (data/scenes/veins_skin.json) bakes on a generated mesh;
# bad maps are refused in one line naming the scene, the object and the
# layer, and nothing is written.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" plane 8 "$TMP/p.ply" 40
expect_ok "$SSS_GENMESH" depthmap veins 64 "$TMP/veins.png" 16
expect_ok "$SSS_GENMESH" depthmap constant 4 "$TMP/one.png" 8
expect_ok "$SSS_GENMESH" cube 4 "$TMP/c.ply" 40
D='"sigma_s": [2, 1, 1], "sigma_a": [0.6, 0.6, 0.6], "g": 0.25'
cat > "$TMP/s.json" <<JSON
{"objects": [
  {"name": "one", "mesh": "p.ply", "moving": true, "material": {"preset": "skin1", "layers": [{$D, "depth_mm": 2}]}},
  {"name": "split", "mesh": "p.ply", "moving": true, "material": {"preset": "skin1", "layers": [
    {$D, "depth_mm": {"map": "veins.png", "scale_mm": 1.5}},
    {$D, "depth_mm": {"procedural": "bumps", "seed": 4, "scale_mm": 8, "depth_mm": [0.5, 1.8]}},
    {$D, "depth_mm": 2}]}},
  {"name": "number", "mesh": "p.ply", "moving": true, "material": {"preset": "skin1", "layers": [
    {$D, "depth_mm": 0.3}, {"sigma_s": [6, 3, 2], "sigma_a": [0.6, 0.6, 0.6], "g": 0.4, "depth_mm": 0.75}]}},
  {"name": "map", "mesh": "p.ply", "moving": true, "material": {"preset": "skin1", "layers": [
    {$D, "depth_mm": 0.3},
    {"sigma_s": [6, 3, 2], "sigma_a": [0.6, 0.6, 0.6], "g": 0.4, "depth_mm": {"map": "one.png", "scale_mm": 0.75}}]}}],
 "lights": [{"type": "directional", "direction": [0.4, 0.1, 0.9], "moving": true}],
 "bake": {"dirs": 20}}
JSON
mkdir -p "$TMP/scene"
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/scene" -q
# numbers only: no LDEP, format 1.8; a map or a procedural depth: LDEP, 1.9
expect_ok "$SSS_STAT" "$TMP/scene/one.sss"
contains "$TMP/out" "LAYR"
grep -q "LDEP" "$TMP/out" && fail "one.sss: flat layers wrote LDEP"
contains "$TMP/out" "format 1.8"
expect_ok "$SSS_STAT" "$TMP/scene/split.sss"
contains "$TMP/out" "LDEP"
contains "$TMP/out" "format 1.9"
contains "$TMP/out" "LDEP              972        12.00             81"
python3 - "$TMP/out" <<'PY' || fail "split.sss: depth ranges"
import re, sys
t = open(sys.argv[1]).read()
r = [tuple(map(float, m)) for m in re.findall(r"layer \d ([0-9.e-]+) to ([0-9.e-]+) mm", t)]
assert len(r) == 3, t
assert 0 <= r[0][0] < 0.2 and 0.5 < r[0][1] <= 1.5, r      # the map: 0 to 1.5 mm
assert 0.5 <= r[1][0] < 0.8 and 1.4 < r[1][1] <= 1.8, r    # bumps in [0.5, 1.8]
assert r[2] == (2.0, 2.0), r                               # the number
PY
# interior vertices of the 9 x 9 plane (its rim aside, docs/layers.md §5)
for v in 20 30 40 50 60; do
  for o in one split number map; do
    expect_ok "$SSS_STAT" "$TMP/scene/$o.sss" --query $v --light 0.4,0.1,0.9 --view -0.3,0.2,0.93 --json
    cp "$TMP/out" "$TMP/$o.$v.json"
  done
  python3 - "$TMP/one.$v.json" "$TMP/split.$v.json" "$TMP/number.$v.json" "$TMP/map.$v.json" <<'PY' || fail "vertex $v"
import json, sys
one, split, number, mp = (json.load(open(p)) for p in sys.argv[1:5])
a, b = one["terms"], split["terms"]
for c in range(3):
    # the same dipole and q; one layer's single scattering to float rays
    assert a["multiple_scattering"][c] == b["multiple_scattering"][c]
    assert abs(a["single_scattering"][c] - b["single_scattering"][c]) <= 1e-6 * a["single_scattering"][c], \
        (c, a["single_scattering"][c], b["single_scattering"][c])
    # a map of one value everywhere is the number (0.75 is exact in float)
    n, m = number["terms"]["single_scattering"][c], mp["terms"]["single_scattering"][c]
    assert abs(n - m) <= 1e-7 * n, (c, n, m)
for k in ("exact", "reconstructed"):
    assert one[k] == split[k], k
PY
done
# the example: veins under skin, baked on a generated sphere (20 mm, with
# texture coordinates although its depths are procedural)
expect_ok "$SSS_GENMESH" sphere 4 "$TMP/sphere.ply" 2
sed 's|"../meshes/blob.ply"|"sphere.ply"|' "$SSS_SOURCE/data/scenes/veins_skin.json" > "$TMP/veins_skin.json"
mkdir -p "$TMP/ex"
expect_ok "$SSS_BAKE" --scene "$TMP/veins_skin.json" -o "$TMP/ex" -q
expect_ok "$SSS_STAT" "$TMP/ex/arm.sss"
contains "$TMP/out" "3 layers over the material"
python3 - "$TMP/out" <<'PY' || fail "veins_skin: blood depths"
import re, sys
t = open(sys.argv[1]).read()
m = re.search(r"layer 1 ([0-9.e-]+) to ([0-9.e-]+) mm", t)
lo, hi = float(m.group(1)), float(m.group(2))
assert 0.35 <= lo < 0.5 and 0.9 < hi <= 1.2, (lo, hi)   # veins reach down, the rest stays thin
PY
# bad maps: one line naming the scene, the object, the layer and the map;
# no file written for any object
bad() { # NAME MESH DEPTH PATTERN
  cat > "$TMP/b.json" <<JSON
{"objects": [{"name": "ok", "mesh": "p.ply", "moving": true, "material": "skin1"},
  {"name": "$1", "mesh": "$2", "moving": true, "material": {"preset": "skin1", "layers": [{$D, "depth_mm": $3}]}}],
 "lights": [{"type": "directional", "direction": [0.4, 0.1, 0.9], "moving": true}], "bake": {"dirs": 20}}
JSON
  rm -rf "$TMP/bad" && mkdir -p "$TMP/bad"
  expect_fail "$4" "$SSS_BAKE" --scene "$TMP/b.json" -o "$TMP/bad" -q
  [ "$(wc -l < "$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "$1: more than one line"; }
  contains "$TMP/err" "b.json: /objects/1"
  [ -z "$(ls "$TMP/bad")" ] || fail "$1: wrote $(ls "$TMP/bad")"
}
bad missing p.ply '{"map": "nothere.png", "scale_mm": 1}' "material/layers/0/depth_mm/map: .*nothere.png: cannot open the depth map"
cp "$TMP/s.json" "$TMP/text.png"
bad text p.ply '{"map": "text.png", "scale_mm": 1}' "text.png: not a PNG file"
bad nouv c.ply '{"map": "one.png", "scale_mm": 1}' "material/layers/0/depth_mm: the depth map .*one.png needs texture coordinates, and the mesh .*c.ply has none"
bad range p.ply '{"procedural": "veins", "scale_mm": 1, "depth_mm": [2, 1]}' "b.json: /objects/1/material/layers/0/depth_mm/depth_mm: max 1 is below min 2"
echo "cli_layers: ok"
