# The adversarial pass's findings at the command line (docs/robustness.md,
# "The adversarial pass"), one block per item; each check fails on the tree
# before its fix. Paths (items 2, 6) are cli_hostile.sh's; the viewer's
# pictures (item 10) are view_scene.sh's and test_view_paths'.
. "$(dirname "$0")/lib.sh"
S=$TMP
"$SSS_GENMESH" sphere 2 "$S/s.ply" >/dev/null 2>&1 || fail "genmesh"
one_line() { [ "$(wc -l < "$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "not one line: $*"; }; }

# ---- 1: a half-float RGBA probe (what HDR tools write) bakes -------------------
"$SSS_MKEXR" "$S/rgba.exr" 64 32 half RGBA 0.5 zip || fail "mkexr"
cat > "$S/env.json" <<EOF
{"objects": [{"name": "ball", "mesh": "s.ply", "material": "marble", "mm_per_unit": 20}],
 "lights": [{"type": "environment", "probe": "rgba.exr"}], "bake": {"sh_order": 2}}
EOF
mkdir -p "$S/env"
expect_ok "$SSS_BAKE" --scene "$S/env.json" -o "$S/env" -q
expect_ok "$SSS_STAT" "$S/env/ball.sss"
contains "$TMP/out" "ENVT"
# an environment-only file is measured by sss-stat --error (its SH transfer
# against the exact evaluator, cli_scene.sh), not refused; --query refuses it
expect_ok "$SSS_STAT" "$S/env/ball.sss" --error --no-image --views 2
contains "$TMP/out" "environment (ENVT), SH order 2: 64 of 162 vertices"
expect_fail "has none of them" "$SSS_STAT" "$S/env/ball.sss" --query 0 --light 0,0,1
one_line

# ---- 3: coordinates beyond the range: one line, no abort -----------------------
printf 'OFF\n4 4 0\n2e18 0 0\n-1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > "$S/huge.off"
expect_fail "vertex 0: coordinate 0 is 2e+18, beyond 1e+15" "$SSS_BAKE" "$S/huge.off" -o "$S/x.sss" -q
one_line; [ ! -e "$S/x.sss" ] || fail "huge.off: a file was written"

# ---- 4: a byte-order mark is not a statement; unknown statements are warned ------
body='v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 9 9 9\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n'
printf "$body" > "$S/plain.obj"; printf "\xef\xbb\xbf$body" > "$S/bom.obj"
for m in plain bom; do
  expect_ok "$SSS_BAKE" "$S/$m.obj" -o "$S/$m.sss" --dirs 8 -q
  expect_ok "$SSS_STAT" "$S/$m.sss" --query 0 --light 0.2,0.3,1 --json
  sed 's/"file":"[^"]*",//' "$TMP/out" > "$S/$m.q"
done
cmp -s "$S/plain.q" "$S/bom.q" || fail "an OBJ with a byte-order mark bakes another mesh"
printf "vv 0 0 0\n$body" > "$S/typo.obj"
expect_ok "$SSS_BAKE" "$S/typo.obj" -o "$S/typo.sss" --dirs 8 -q
contains "$TMP/err" "warning: 1 line with a statement OBJ does not have was ignored (the first: 'vv' on line 1)"

# ---- 5: a material the dipole cannot hold is refused up front ----------------------
expect_fail "sigma'_t = sigma_a + sigma'_s = 1e-160 /mm, below 1e-12" "$SSS_BAKE" "$S/s.ply" -o "$S/x.sss" \
  --sigma-a 0,0,0 --sigma-s 1e-160,1e-160,1e-160
one_line
"$SSS_BAKE" "$S/s.ply" -o "$S/x.sss" --sigma-a 0,0,0 --sigma-s 1e-160,1e-160,1e-160 >/dev/null 2>&1
[ $? -eq 2 ] || fail "a bad material should exit 2"

# ---- 7: sss-stat plans its neighbourhoods as the bake does ----------------------
"$SSS_GENMESH" sphere 4 "$S/s4.ply" >/dev/null 2>&1
expect_ok "$SSS_BAKE" "$S/s4.ply" -o "$S/all.sss" --sigma-a 0,0,0 --sigma-s 1,1,1 --mm-per-unit 10 --dirs 12 -q
for a in "--query 0 --light 0,0,1" "--error --views 2 --no-image"; do
  # shellcheck disable=SC2086
  SSS_MEMORY_LIMIT_MB=20 expect_fail "exact evaluator: neighbourhoods need .* GiB .* but only .* GiB may be used" \
    "$SSS_STAT" "$S/all.sss" $a
  one_line
done
expect_ok "$SSS_STAT" "$S/all.sss" --query 0 --light 0,0,1 # without the limit it fits
# a small file declaring a large probe: refused before its pixels are allocated
"$SSS_MKEXR" "$S/big.exr" 8192 4096 half Y 1 zip || fail "mkexr big"
sed 's/rgba.exr/big.exr/' "$S/env.json" > "$S/big.json"
SSS_MEMORY_LIMIT_MB=64 expect_fail "/lights/0/probe: .*big.exr: the probe needs at least 0.38 GiB for 8192 x 4096 pixels" \
  "$SSS_BAKE" --scene "$S/big.json" --plan
one_line

# ---- 8: refused in the planner, before any bake -----------------------------------------
# 1025 directions spread over the sphere (a spiral), all distinct
awk 'BEGIN { printf "{\"objects\": [{\"mesh\": \"s.ply\", \"material\": \"marble\"}], \"lights\": [";
  for (i = 0; i < 1025; i++) { z = 1 - (2 * i + 1) / 1025; r = sqrt(1 - z * z); a = 2.39996323 * i;
    printf "%s{\"type\": \"directional\", \"direction\": [%.9f, %.9f, %.9f]}", i ? "," : "", r * cos(a), r * sin(a), z }
  print "]}" }' > "$S/many.json"
expect_fail "many.json: /lights/1024: more than 1024 static lights of distinct directions" "$SSS_BAKE" --scene "$S/many.json" --plan
one_line
# lights of one direction share one QDIR row
{ printf '{"objects": [{"name": "ball", "mesh": "s.ply", "material": "marble"}], "lights": ['
  for i in 0 1 2; do printf '%s{"type": "directional", "direction": [0, 0, %d]}' "$([ "$i" -gt 0 ] && echo ,)" "$((i + 1))"; done
  printf '], "bake": {"dirs": 8}}\n'; } > "$S/same.json"
mkdir -p "$S/same"
expect_ok "$SSS_BAKE" --scene "$S/same.json" -o "$S/same" -q
expect_ok "$SSS_STAT" "$S/same/ball.sss" --json
[ "$(jq '.sections[] | select(.tag == "QDIR") | .count' "$TMP/out")" = 1 ] || fail "three identical lights made more than one QDIR row"
# a probe of finite pixels beyond what ENVT stores
"$SSS_MKEXR" "$S/hot.exr" 16 8 float RGB 2e38 || fail "mkexr hot"
sed 's/rgba.exr/hot.exr/' "$S/env.json" > "$S/hot.json"
expect_fail "hot.json: /lights/0: the probe's radiance times the intensity and colour reaches .* beyond 1e+30" \
  "$SSS_BAKE" --scene "$S/hot.json" --plan
one_line

# ---- 9: what the tools report is what they measured ----------------------------------
mkdir -p "$S/static"
sed 's/"lights": \[.*\]/"lights": [{"type": "directional", "direction": [0, 0, 1]}]/' "$S/env.json" > "$S/static.json"
expect_ok "$SSS_BAKE" --scene "$S/static.json" -o "$S/static" -q
expect_fail "this scene bake has none" "$SSS_STAT" "$S/static/ball.sss" --query 0 --light 0,0,1
one_line
# --error measures what the file has: its static light's exact values (QDIR)
expect_ok "$SSS_STAT" "$S/static/ball.sss" --error --views 2 --no-image
contains "$TMP/out" 'static light 0 (0, 0, 1), exact values (QDIR)'
# the tree gather has no per-vertex maximum: not "max 0"
expect_ok "$SSS_BAKE" "$S/s.ply" -o "$S/t.sss" --dirs 8
grep -q "(max 0)" "$TMP/err" && fail "the tree gather reports 'max 0 neighbours'"
contains "$TMP/err" "neighbours in the dense blocks"
# a file larger than its raw values says so
expect_ok "$SSS_STAT" "$S/t.sss"
grep -q " 0\.[0-9]x smaller" "$TMP/out" && fail "'0.Nx smaller' printed"
contains "$TMP/out" "x larger than 8-bit"
# a file of 8-bit codes is the size of the 8-bit values, not "1.0x larger"
expect_ok "$SSS_GENMESH" sphere 4 "$S/s4.ply"
expect_ok "$SSS_BAKE" "$S/s4.ply" -o "$S/t8.sss" --dirs 200 --quant lloyd8
expect_ok "$SSS_STAT" "$S/t8.sss"
grep -q " 1\.0x " "$TMP/out" && fail "'1.0x smaller/larger' printed"
contains "$TMP/out" "(the size of 8-bit"
# --json is valid UTF-8 whatever the bytes of a file name
bad=$S/$(printf 'bad\xff')
cp "$S/s.ply" "$bad.ply"
expect_ok "$SSS_BAKE" "$bad.ply" -o "$bad.sss" --dirs 8 -q --json
iconv -f UTF-8 -t UTF-8 "$TMP/out" >/dev/null 2>&1 || fail "sss-bake --json is not UTF-8"
jq -e '.mesh | endswith("bad\\xFF.ply")' "$TMP/out" >/dev/null || fail "the mesh name is not escaped as \\xFF"
for a in "" "--query 0 --light 0,0,1"; do
  # shellcheck disable=SC2086
  expect_ok "$SSS_STAT" "$bad.sss" --json $a
  iconv -f UTF-8 -t UTF-8 "$TMP/out" >/dev/null 2>&1 || fail "sss-stat --json $a is not UTF-8"
  jq -e . "$TMP/out" >/dev/null || fail "sss-stat --json $a does not parse"
done
echo "cli_robustness: ok"
