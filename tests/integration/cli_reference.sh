# sss-ref (docs/reference.md) and sss-stat --model-error: the command-line
# contract scripts depend on (the JSON keys of a query, the image and its
# standard-error image), the same result whatever --threads or the number of
# MPI ranks, a time budget, and one-line refusals of what does not go
# together. Small budgets: a 642-vertex blob of skin1.
. "$(dirname "$0")/lib.sh"
: "${SSS_REF:?}"
# expect_rc RC PATTERN CMD...: exactly exit status RC, a one-line message matching PATTERN
expect_rc() {
  local want=$1 pat=$2; shift 2
  "$@" >"$TMP/out" 2>"$TMP/err"; local rc=$?
  [ $rc -eq "$want" ] || { cat "$TMP/err" >&2; fail "expected exit status $want, got $rc: $*"; }
  [ "$(wc -l <"$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "expected a one-line message: $*"; }
  grep -q -- "$pat" "$TMP/err" || { cat "$TMP/err" >&2; fail "message should match '$pat': $*"; }
}
json_field() { sed -n "s/.*\"$1\":\(\[[^]]*\]\|[^,}]*\).*/\1/p" "$TMP/out"; }

expect_ok "$SSS_GENMESH" blob 3 "$TMP/b.ply" 1
M=(--material skin1 --mm-per-unit 20 --light 0,0.3,1)

expect_ok "$SSS_REF" --help
contains "$TMP/out" "usage: sss-ref MESH"

# a query: radiance and stderr, three channels each, positive
expect_ok "$SSS_REF" "$TMP/b.ply" "${M[@]}" --query 5 --view 0,0,1 --paths 200 --seed 3 --json --threads 1
for key in radiance stderr vertex view material sigma_a sigma_s g eta mm_per_unit light seed paths seconds mpi_ranks walks; do
  contains "$TMP/out" "\"$key\":"
done
contains "$TMP/out" '"paths":200,'
r1=$(json_field radiance); s1=$(json_field stderr)
awk -v r="$r1" -v s="$s1" 'BEGIN { gsub(/[][]/, "", r); gsub(/[][]/, "", s); n = split(r, a, ","); m = split(s, b, ",");
  ok = n == 3 && m == 3; for (i = 1; i <= 3; i++) ok = ok && a[i] > 0 && b[i] > 0 && b[i] < a[i]; exit !ok }' ||
  fail "query: radiance $r1 stderr $s1"

# the same numbers with two threads and from two MPI ranks; another seed differs
expect_ok "$SSS_REF" "$TMP/b.ply" "${M[@]}" --query 5 --view 0,0,1 --paths 200 --seed 3 --json --threads 2
[ "$(json_field radiance)" = "$r1" ] || fail "2 threads: $(json_field radiance), 1 thread: $r1"
expect_ok "$SSS_REF" "$TMP/b.ply" "${M[@]}" --query 5 --view 0,0,1 --paths 200 --seed 4 --json
[ "$(json_field radiance)" != "$r1" ] || fail "seed 4 gives seed 3's radiance"
command -v mpirun >/dev/null || fail "mpirun not found (scripts/setup.sh installs openmpi-bin)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
mpi_env=(env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0") # as cli_gather_mpi.sh
expect_ok "${mpi_env[@]}" mpirun -x ASAN_OPTIONS -np 2 "$SSS_REF" "$TMP/b.ply" "${M[@]}" --query 5 --view 0,0,1 \
  --paths 200 --seed 3 --json --threads 1
[ "$(json_field radiance)" = "$r1" ] || fail "2 MPI ranks: $(json_field radiance), 1 process: $r1"
contains "$TMP/out" '"mpi_ranks":2'

# an image and its standard error, byte for byte the same from two ranks
expect_ok "$SSS_REF" "$TMP/b.ply" "${M[@]}" --out "$TMP/a.exr" --size 24x16 --view 0.2,0,1 --paths 8 --json -q
for key in image stderr_image width height covered_pixels mean_radiance mean_relative_stderr; do
  contains "$TMP/out" "\"$key\":"
done
[ -s "$TMP/a.exr" ] && [ -s "$TMP/a.stderr.exr" ] || fail "image or standard-error image missing"
[ "$(json_field covered_pixels)" -gt 20 ] || fail "the image sees too little: $(cat "$TMP/out")"
expect_ok "${mpi_env[@]}" mpirun -x ASAN_OPTIONS -np 2 "$SSS_REF" "$TMP/b.ply" "${M[@]}" --out "$TMP/b.exr" \
  --size 24x16 --view 0.2,0,1 --paths 8 -q --threads 1
cmp "$TMP/a.exr" "$TMP/b.exr" || fail "2-rank image differs from the 1-process image"

# a time budget: some whole rounds, and the count it reached
expect_ok "$SSS_REF" "$TMP/b.ply" "${M[@]}" --query 5 --view 0,0,1 --seconds 0.3 --json
[ "$(json_field paths)" -ge 16 ] || fail "--seconds 0.3 traced $(json_field paths) paths"

# a point light: far away along the directional light, with intensity D²
# (unit irradiance), it gives the directional light's radiance within a few
# standard errors; its position and intensity are reported
expect_ok "$SSS_REF" "$TMP/b.ply" --material skin1 --mm-per-unit 20 --query 5 --view 0,0,1 --paths 200 --seed 3 \
  --json --threads 1 --point-light 0,2873.4788,9578.2629,1e8
contains "$TMP/out" '"point_light":\[0,2873.4788,9578.2629,100000000\]'
python3 - "$r1" "$s1" "$(json_field radiance)" "$(json_field stderr)" <<'PY' || fail "far point light differs from the directional light"
import json, sys
r1, s1, r2, s2 = (json.loads(a) for a in sys.argv[1:])
for a, sa, b, sb in zip(r1, s1, r2, s2):
    assert abs(a - b) <= 4 * (sa * sa + sb * sb) ** 0.5 + 1e-12, (a, b, sa, sb)
PY
expect_rc 2 "must be X,Y,Z or X,Y,Z,I" "$SSS_REF" "$TMP/b.ply" --point-light 0,1 --query 5 --view 0,0,1
expect_rc 2 "must be X,Y,Z or X,Y,Z,I" "$SSS_REF" "$TMP/b.ply" --point-light 0,1,2,3,4 --query 5 --view 0,0,1
expect_rc 2 "intensity must lie" "$SSS_REF" "$TMP/b.ply" --point-light 0,0,9,0 --query 5 --view 0,0,1
expect_rc 2 "exclude each other" "$SSS_REF" "$TMP/b.ply" --point-light 0,0,9 --light 0,0,1 --query 5 --view 0,0,1
expect_rc 1 "inside the mesh" "$SSS_REF" "$TMP/b.ply" --point-light 0,0,0 --query 5 --view 0,0,1

# refusals: one line each, exit status 2 (arguments) or 1 (input)
expect_rc 2 "missing --light" "$SSS_REF" "$TMP/b.ply" --query 5 --view 0,0,1
expect_rc 2 "give --query" "$SSS_REF" "$TMP/b.ply" --light 0,0,1
expect_rc 2 "needs --view" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --query 5
expect_rc 2 "exclude each other" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --query 5 --view 0,0,1 --out "$TMP/x.exr"
expect_rc 2 "exclude each other" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --query 5 --view 0,0,1 --paths 4 --seconds 1
expect_rc 2 "either --material" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --query 5 --view 0,0,1 --material skin1 --sigma-a 1,1,1
expect_rc 2 "must name an .exr" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --out "$TMP/x.png"
expect_rc 2 "'1.5' must be a number" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --query 5 --view 0,0,1 --g 1.5
expect_rc 2 "not a direction" "$SSS_REF" "$TMP/b.ply" --light 0,0,0 --query 5 --view 0,0,1
expect_rc 2 "vertex index out of range" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --query 642 --view 0,0,1
expect_rc 2 "no-such" "$SSS_REF" "$TMP/b.ply" --light 0,0,1 --query 5 --view 0,0,1 --material no-such
expect_rc 1 "missing.ply" "$SSS_REF" "$TMP/missing.ply" --light 0,0,1 --query 5 --view 0,0,1

# sss-stat --model-error: the viewer's radiance, the exact evaluator's and the reference's
expect_ok "$SSS_BAKE" "$TMP/b.ply" -o "$TMP/b.sss" --material skin1 --mm-per-unit 20 --dirs 20 -q
expect_ok "$SSS_STAT" "$TMP/b.sss" --model-error --light 0,0.3,1 --view 0,0,1 --vertices 4 --paths 64 --json
for key in mean_radiance realtime exact reference reference_stderr approximation_error model_error ratio_of_means \
           rel_rms reference_noise_rel_rms per_vertex sampled_vertices; do
  contains "$TMP/out" "\"$key\":"
done
contains "$TMP/out" '"sampled_vertices":4,'
cp "$TMP/out" "$TMP/jensen.json"
# the normalised exit divides the real-time and exact radiance by c(1.3) = 0.93887, not the reference
expect_ok "$SSS_STAT" "$TMP/b.sss" --model-error --light 0,0.3,1 --view 0,0,1 --vertices 4 --paths 64 --json --exit normalised
contains "$TMP/out" '"exit":"normalised"'
python3 - "$TMP/jensen.json" "$TMP/out" <<'PY' || fail "--exit normalised is not the Jensen exit divided by c(eta)"
import json, sys
a, b = (json.load(open(p))["mean_radiance"] for p in sys.argv[1:])
for k in ("realtime", "exact"):
    for x, y in zip(a[k], b[k]):
        assert abs(y * 0.93887 - x) <= 1e-4 * x, (k, x, y)
assert a["reference"] == b["reference"]
PY
expect_rc 2 "must be jensen or normalised" "$SSS_STAT" "$TMP/b.sss" --model-error --light 0,0.3,1 --view 0,0,1 --exit nope
expect_ok "$SSS_STAT" "$TMP/b.sss" --model-error --light 0,0.3,1 --view 0,0,1 --query 5 --paths 64
contains "$TMP/out" "model ratio"
expect_rc 2 "needs --light" "$SSS_STAT" "$TMP/b.sss" --model-error --view 0,0,1
expect_rc 2 "go with --model-error" "$SSS_STAT" "$TMP/b.sss" --query 5 --light 0,0,1 --paths 64
expect_rc 2 "exclude each other" "$SSS_STAT" "$TMP/b.sss" --model-error --error --light 0,0,1 --view 0,0,1
echo "cli_reference: ok"
