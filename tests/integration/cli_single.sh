# sss-stat --query V --light --view: every term of the radiance towards the
# viewer (docs/layers.md §5). On a flat plane every vertex sees a half-space,
# so the single-scattering term must be the closed form of a half-space with
# refraction, Fresnel in and out, the beam's spread and 1/eta^2 (computed
# below from Snell's law and the textbook Fresnel equations, independently of
# libsss), and the surface reflectance 1 - F_t at the light's angle.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" plane 8 "$TMP/p.ply" 100
# seed 002's dermis (Table 1): sigma_s 2,1,1, sigma_t 2.6,1.6,1.6, g 0.25
expect_ok "$SSS_BAKE" "$TMP/p.ply" -o "$TMP/p.sss" --sigma-a 0.6,0.6,0.6 --sigma-s 2,1,1 --g 0.25 --dirs 20 \
  --quant float -q
for v in 0 40; do
  expect_ok "$SSS_STAT" "$TMP/p.sss" --query $v --light 0.4,0.1,0.9 --view -0.3,0.2,0.93 --json
  python3 - "$TMP/out" <<'PY' || fail "vertex $v: terms"
import json, math, sys
o = json.load(open(sys.argv[1]))
t = o["terms"]
eta, g = 1.3, 0.25
def unit(v):
    l = math.sqrt(sum(x * x for x in v)); return [x / l for x in v]
wi, wo = unit([0.4, 0.1, 0.9]), unit([-0.3, 0.2, 0.93])
def ft(c):  # unpolarised Fresnel transmittance from outside, textbook form
    st = math.sqrt(1 - c * c) / eta; ct = math.sqrt(1 - st * st)
    rs = (c - eta * ct) / (c + eta * ct); rp = (eta * c - ct) / (eta * c + ct)
    return 1 - 0.5 * (rs * rs + rp * rp)
def refr(w):  # the direction a ray from outside along -w continues in
    c = w[2]; ct = math.sqrt(1 - (1 - c * c) / eta ** 2)
    return [-w[0] / eta, -w[1] / eta, -ct], ct
ti, mi = refr(wi); to, mo = refr(wo)
cosp = -sum(a * b for a, b in zip(ti, to))
p = (1 - g * g) / (4 * math.pi * (1 + g * g - 2 * g * cosp) ** 1.5)
for c, (ss, st) in enumerate([(2, 2.6), (1, 1.6), (1, 1.6)]):
    want = ft(wi[2]) * wi[2] / mi * ft(wo[2]) / eta ** 2 * ss * p * mi / (st * (mi + mo))
    got = t["single_scattering"][c]
    assert abs(got - want) <= 1e-5 * want, (c, got, want)
    assert abs(t["total"][c] - t["multiple_scattering"][c] - got) <= 1e-12 + 1e-9 * got
    assert t["multiple_scattering"][c] > 0
assert abs(t["surface_reflectance"] - (1 - ft(wi[2]))) < 1e-9
assert t["g"] == 0.25 and t["single_scattering_in_effects"] is False
for k in ("exact", "reconstructed", "difference", "nearest_direction"):  # the keys --query had stay
    assert k in o, k
PY
done
# the human text has the same terms
expect_ok "$SSS_STAT" "$TMP/p.sss" --query 3 --light 0.4,0.1,0.9 --view -0.3,0.2,0.93
contains "$TMP/out" "surface reflectance"
contains "$TMP/out" "single"
# a viewer below the surface sees no single scattering
expect_ok "$SSS_STAT" "$TMP/p.sss" --query 3 --light 0,0,1 --view 0,1,-1 --json
python3 -c 'import json,sys; t=json.load(open(sys.argv[1]))["terms"]; assert t["single_scattering"] == [0, 0, 0], t' \
  "$TMP/out" || fail "below the surface"
# seed 002's Table 1 layers in a scene material reach the file (LAYR) and the
# terms: the top of a 100 mm cube, with and without the layers over skin1
expect_ok "$SSS_GENMESH" cube 8 "$TMP/c.ply" 100
cat > "$TMP/s.json" <<'JSON'
{"objects": [{"name": "plain", "mesh": "c.ply", "material": "skin1", "moving": true},
             {"name": "layered", "mesh": "c.ply", "moving": true, "material": {"preset": "skin1", "layers": [
    {"name": "dermis", "sigma_s": [2, 1, 1], "sigma_a": [0.6, 0.6, 0.6], "g": 0.25, "depth_mm": 0.3},
    {"name": "blood", "sigma_s": [6, 3, 2], "sigma_a": [0.6, 0.6, 0.6], "g": 0.4, "depth_mm": 0.8}]}}],
 "lights": [{"type": "directional", "direction": [0.4, 0.1, 0.9], "moving": true}],
 "bake": {"dirs": 20}}
JSON
mkdir -p "$TMP/scene"
expect_ok "$SSS_BAKE" --scene "$TMP/s.json" -o "$TMP/scene" -q
for o in plain layered; do
  # vertex 361 is the centre of the cube's top face (sss-genmesh's numbering)
  expect_ok "$SSS_STAT" "$TMP/scene/$o.sss" --query 361 --light 0.4,0.1,0.9 --view -0.3,0.2,0.93 --json
  cp "$TMP/out" "$TMP/$o.json"
done
python3 - "$TMP/plain.json" "$TMP/layered.json" <<'PY' || fail "layers: terms"
import json, sys
a, b = (json.load(open(p))["terms"] for p in sys.argv[1:3])
assert a["single_scattering_in_effects"] and b["single_scattering_in_effects"]
for c in range(3):  # the same dipole, a different single scattering
    assert a["multiple_scattering"][c] == b["multiple_scattering"][c]
    assert abs(a["single_scattering"][c] - b["single_scattering"][c]) > 0.05 * a["single_scattering"][c], c
PY
expect_ok "$SSS_STAT" "$TMP/scene/layered.sss"
contains "$TMP/out" "LAYR"
contains "$TMP/out" "2 layers over the material (single scattering), lower boundaries at 0.3 0.8 mm"
echo "cli_single: ok"
