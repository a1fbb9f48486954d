# Hard meshes and the rest of the cases of docs/robustness.md at the command line
# (docs/robustness.md): each is repaired and reported, warned with a count,
# or refused naming the parameter, and whatever is baked reads back finite.
. "$(dirname "$0")/lib.sh"
finite_error() {  # the file reads back and its error against the exact evaluator is a finite number
  expect_ok "$SSS_STAT" "$1" --error --views 3 --json
  grep -q '"rel_rms_all":[0-9]' "$TMP/out" || { cat "$TMP/out" >&2; fail "$1: error is not a finite number"; }
  ! grep -qi 'nan\|inf' "$TMP/out" || fail "$1: NaN or Inf in the error report"
}
json_num() {  # json_num KEY FILE: the first numeric value of "KEY"
  grep -o "\"$1\":[-0-9.e+]*" "$2" | head -1 | cut -d: -f2
}

# B5: an inside-out cube is turned outward, and says so
printf 'OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n4 1 2 3 0\n4 7 6 5 4\n4 4 5 1 0\n4 6 7 3 2\n4 3 7 4 0\n4 5 6 2 1\n' > "$TMP/inv.off"
expect_ok "$SSS_BAKE" "$TMP/inv.off" -o "$TMP/inv.sss" --mm-per-unit 10 --dirs 12 --json
contains "$TMP/err" 'inv.off: repaired: 12 triangles of closed surfaces flipped to face outward consistently'
contains "$TMP/err" 'inv.off: repaired: 1 closed surface was inside out as a whole'
[ "$(json_num faces_flipped "$TMP/out")" = 12 ] || fail "inside-out cube: faces_flipped in --json"
[ "$(json_num occluded_fraction "$TMP/out")" = 0 ] || fail "inside-out cube: rays still blocked after the repair (convex)"
finite_error "$TMP/inv.sss"
# a non-orientable strip: warned even with -q, and still baked
awk 'BEGIN { K = 12; pi = atan2(0, -1); print "OFF"; print 2 * K, K, 0
  for (i = 0; i < K; i++) { a = 2 * pi * i / K; h = a / 2
    for (s = -1; s <= 1; s += 2) { r = 2 + 0.5 * s * cos(h); printf "%.9g %.9g %.9g\n", r * cos(a), r * sin(a), 0.5 * s * sin(h) } }
  for (i = 0; i < K; i++) { j = (i + 1) % K; b0 = 2 * j + (j == 0); b1 = 2 * j + (j != 0); print 4, 2 * i, b0, b1, 2 * i + 1 } }' > "$TMP/moebius.off"
expect_ok "$SSS_BAKE" "$TMP/moebius.off" -o "$TMP/moebius.sss" --mm-per-unit 10 --dirs 12 -q
contains "$TMP/err" 'moebius.off: warning: 1 edge between triangles of opposite orientation could not be made consistent'
finite_error "$TMP/moebius.sss"

# B7: a non-convex polygon is ear-clipped, not fanned over itself
printf 'OFF\n6 1 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n6 2 3 4 5 0 1\n' > "$TMP/l.off"
expect_ok "$SSS_BAKE" "$TMP/l.off" -o "$TMP/l.sss" --dirs 4
contains "$TMP/err" 'l.off: repaired: 1 non-convex polygon ear-clipped in its plane instead'

# B6: a unit sphere 10^6 from the origin, coordinates to 17 digits: recentred
# before float32, nothing collapses, nothing shadows a convex object
awk 'BEGIN { o = 1e6; N = 64; M = 32; pi = atan2(0, -1); S = 1 + (M - 1) * N
  print "OFF"; print 2 + (M - 1) * N, N + (M - 2) * N + N, 0
  printf "%.17g %.17g %.17g\n", o, o, o + 1
  for (j = 1; j < M; j++) for (i = 0; i < N; i++)
    printf "%.17g %.17g %.17g\n", o + sin(pi * j / M) * cos(2 * pi * i / N), o + sin(pi * j / M) * sin(2 * pi * i / N), o + cos(pi * j / M)
  printf "%.17g %.17g %.17g\n", o, o, o - 1
  for (i = 0; i < N; i++) print 3, 0, 1 + i, 1 + (i + 1) % N
  for (j = 1; j < M - 1; j++) for (i = 0; i < N; i++)
    print 4, 1 + (j - 1) * N + i, 1 + j * N + i, 1 + j * N + (i + 1) % N, 1 + (j - 1) * N + (i + 1) % N
  for (i = 0; i < N; i++) print 3, S, 1 + (M - 2) * N + (i + 1) % N, 1 + (M - 2) * N + i }' > "$TMP/far.off"
expect_ok "$SSS_BAKE" "$TMP/far.off" -o "$TMP/far.sss" --material skin1 --mm-per-unit 20 --dirs 20 --json
contains "$TMP/err" 'far.off: repaired: mesh recentred: (1000000, 1000000, 1000000) subtracted'
[ "$(json_num faces_zero_area "$TMP/out")" = 0 ] || fail "far sphere: triangles collapsed"
[ "$(json_num occluded_fraction "$TMP/out")" = 0 ] || fail "far sphere: a convex object shadows itself"
[ "$(json_num triangles "$TMP/out")" = $((64 * 2 + 64 * 30 * 2)) ] || fail "far sphere: triangles lost"
finite_error "$TMP/far.sss"

# B8: a 4 mm slab with sigma_a = 0 is thinner than the range: warned with a
# count (also with -q); a thick sphere is not
expect_ok "$SSS_GENMESH" slab 10 "$TMP/slab.ply"
expect_ok "$SSS_BAKE" "$TMP/slab.ply" -o "$TMP/slab.sss" --sigma-a 0,0,0 --sigma-s 1,1,1 --mm-per-unit 200 --dirs 12 -q --json
contains "$TMP/err" 'slab.ply: warning: [0-9]* vertices lie on parts thinner than the scattering length'
n=$(json_num thin_vertices "$TMP/out")
[ "$n" -gt 400 ] || fail "slab: thin_vertices $n, expected most of its 602 vertices"
finite_error "$TMP/slab.sss"
expect_ok "$SSS_GENMESH" sphere 3 "$TMP/s.ply"    # 642 vertices
expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/s.sss" --material skin1 --mm-per-unit 20 --dirs 12 --json
! grep -q 'thinner than' "$TMP/err" || fail "a 40 mm skin sphere was called thin"
[ "$(json_num thin_vertices "$TMP/out")" = 0 ] || fail "sphere: thin_vertices not 0"

# --refs 0 with --sh-order 0 would store nothing: refused, nothing written
expect_fail '--refs 0 (SH only) needs --sh-order >= 1' "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/none.sss" --refs 0 --sh-order 0
[ ! -e "$TMP/none.sss" ] || fail "a refused bake wrote a file"

# the neighbourhood rows are counted before they are allocated and refused
# with their size when they would not fit (the direct gather builds them)
if "$SSS_BAKE" --help | grep -q -- '--gather direct'; then
  SSS_MEMORY_LIMIT_MB=2 expect_fail 'neighbourhoods need .* GiB (.* neighbours per vertex within .* mm) but only' \
    "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/none.sss" --material marble --mm-per-unit 20 --dirs 1 --gather direct -q
  [ ! -e "$TMP/none.sss" ] || fail "a refused bake wrote a file"
fi

# the compressed forms are byte-identical with 1 and 2 threads too
for c in "--compress paper" "--compress compact" "--sh-order 3 --refs 0 --sh-quant lloyd8"; do
  # shellcheck disable=SC2086
  expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/c1.sss" --material skin1 --mm-per-unit 20 --dirs 50 --threads 1 -q $c
  # shellcheck disable=SC2086
  expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/c2.sss" --material skin1 --mm-per-unit 20 --dirs 50 --threads 2 -q $c
  cmp "$TMP/c1.sss" "$TMP/c2.sss" || fail "$c: output differs between 1 and 2 threads"
done
echo "cli_hard_meshes: ok"
