# Extreme bake parameters and materials (docs/robustness.md): each
# either bakes a file whose every value decodes finite and non-negative (the
# reader refuses NaN/Inf; sss-stat --error recomputes and compares), or is
# refused before baking with a message naming the parameter.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" sphere 2 "$TMP/s.ply"      # 162 vertices
m=(--material skin1 --mm-per-unit 20 -q)
finite_error() {  # the file reads back and its error against the exact evaluator is a finite number
  expect_ok "$SSS_STAT" "$1" --error --views 5 --json
  grep -q '"rel_rms_all":[0-9]' "$TMP/out" || { cat "$TMP/out" >&2; fail "$1: error is not a finite number"; }
  ! grep -qi 'nan\|inf' "$TMP/out" || fail "$1: NaN or Inf in the error report"
}
# direction counts: 1 (no triangulation: nearest sample), 4 (tetrahedron), 5000
for n in 1 4 5000; do
  expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/d$n.sss" "${m[@]}" --dirs $n
  finite_error "$TMP/d$n.sss"
done
# materials: sigma_a -> 0 (albedo -> 1, long tail, radius clamped to the
# object), very large sigma_a, sigma'_s -> 0, eta at 1, below 1, 2.5
for mat in "--sigma-a 1e-9,1e-9,1e-9 --sigma-s 1,1,1" "--sigma-a 1e4,1e4,1e4 --sigma-s 1,1,1" \
           "--sigma-a 0.1,0.1,0.1 --sigma-s 1e-9,1e-9,1e-9" "--sigma-a 0.01,0.02,0.03 --sigma-s 1,1,1 --eta 1" \
           "--sigma-a 0.01,0.02,0.03 --sigma-s 1,1,1 --eta 0.7" "--sigma-a 0.01,0.02,0.03 --sigma-s 1,1,1 --eta 2.5"; do
  # shellcheck disable=SC2086
  expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/mat.sss" --mm-per-unit 20 --dirs 20 -q $mat
  finite_error "$TMP/mat.sss"
done
# one channel without any extinction: no dipole, refused naming the channel
expect_fail "channel R has sigma'_t = 0" "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" --sigma-a 0,0.1,0.1 --sigma-s 0,1,1
expect_fail 'outside \[0.3, 3.5\]' "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" "${m[@]}" --eta 0.2
# compression extremes: every vertex a reference (SH order 0), 100 % and SH
# order 8 on 200 directions; order 8 on 50 directions has more coefficients
# than samples and is refused
expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/r100.sss" "${m[@]}" --dirs 50 --refs 1 --sh-order 0
finite_error "$TMP/r100.sss"
expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/sh8.sss" "${m[@]}" --dirs 200 --sh-order 8 --refs 0 --sh-quant lloyd8
finite_error "$TMP/sh8.sss"
expect_fail '64 coefficients, more than the 50' "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" "${m[@]}" --dirs 50 --sh-order 8 --refs 0
[ ! -e "$TMP/x.sss" ] || fail "a refused bake wrote a file"
# resolution: a flat strip of 0.5 x 10 mm triangles (skin1, 1/sigma_tr = 3.67 mm
# in red) is warned about with a count; a fine mesh is not
awk 'BEGIN { nx = 120; ny = 6; print "OFF"; print (nx + 1) * (ny + 1), 2 * nx * ny, 0
  for (j = 0; j <= ny; j++) for (i = 0; i <= nx; i++) print -30 + 60 * i / nx, -30 + 60 * j / ny, 0
  for (j = 0; j < ny; j++) for (i = 0; i < nx; i++) { a = j * (nx + 1) + i
    print 3, a, a + 1, a + nx + 2; print 3, a, a + nx + 2, a + nx + 1 } }' > "$TMP/strip.off"
expect_ok "$SSS_BAKE" "$TMP/strip.off" -o "$TMP/strip.sss" --material skin1 --dirs 12 --weights point -q --json
contains "$TMP/err" 'warning: .* vertices have an edge longer than 7.35 mm'
grep -q '"coarse_vertices":[1-9]' "$TMP/out" || fail "coarse_vertices should count the strip's vertices"
# the default hat weights integrate R_d over those triangles: a flat strip
# bends nowhere, so nothing is left to warn about (docs/physics.md §9)
expect_ok "$SSS_BAKE" "$TMP/strip.off" -o "$TMP/strip.sss" --material skin1 --dirs 12 -q --json
contains "$TMP/out" '"coarse_vertices":0'
! grep -q 'edge longer' "$TMP/err" || fail "a flat strip with hat weights was warned about"
expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/fine.sss" "${m[@]}" --dirs 12 --json
contains "$TMP/out" '"coarse_vertices":0'
! grep -q 'warning' "$TMP/err" || fail "a fine mesh was warned about"
echo "cli_params_extreme: ok"
