# Hierarchical gather under a memory limit (docs/benchmarks.md, "Bake at scale"): when the transfer rows
# and tree moments of every light direction do not fit next to q, the bake
# takes the directions in chunks, and the file must be byte for byte the
# unlimited bake's (1 and 2 threads, and 2 MPI ranks); when not even one
# direction at a time fits, it refuses before starting with one line and
# writes nothing. The limit (SSS_MEMORY_LIMIT_MB) is found from the
# unlimited bake's own estimate, so the test follows the estimate if it
# changes, and fails if no limit gives two or more chunks.
. "$(dirname "$0")/lib.sh"
# the blob of 2562 vertices: the chunks show from 1 MiB below the estimate,
# and each bake takes a quarter of the 10242-vertex blob's
expect_ok "$SSS_GENMESH" blob 4 "$TMP/blob.ply" 30
# grey marble (one channel): q is 4 bytes per vertex and direction, the
# transfer rows and moments ~8, so chunks have room to help before the
# phases after the gather (q and the file image) bind; RGB chunks are
# checked in-process by test_gather (tree_chunks_give_the_same_bytes)
bake=("$SSS_BAKE" "$TMP/blob.ply" --sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62 --dirs 200 --gather tree)
expect_ok "${bake[@]}" -o "$TMP/whole.sss" --threads 2 --json -q
num() { grep -o "\"$1\":[0-9.e+-]*" "$2" | head -1 | cut -d: -f2; }
[ "$(num direction_chunks "$TMP/out")" = 1 ] || fail "the unlimited bake came in $(num direction_chunks "$TMP/out") chunks"
peak=$(num predicted_peak_mib "$TMP/out")
[ -n "$peak" ] || fail "no predicted_peak_mib in --json"
# every limit below the estimate, down to the first refusal: each bake that
# runs gives the whole bake's bytes; at least one must use 2 or more chunks
# (3 here when measured; narrower chunks, down to one direction, are
# test_gather's tree_chunks_give_the_same_bytes)
lim=$(awk -v p="$peak" 'BEGIN { printf "%d", p + 1 }') # the first bake at the whole MiB below the estimate
most=1 most_lim=0 first_lim=0
while [ "$lim" -gt 1 ]; do
  lim=$((lim - 1))
  rm -f "$TMP/part.sss"
  SSS_MEMORY_LIMIT_MB=$lim "${bake[@]}" -o "$TMP/part.sss" --threads 2 --json >"$TMP/out" 2>"$TMP/err" || break
  chunks=$(num direction_chunks "$TMP/out")
  cmp "$TMP/whole.sss" "$TMP/part.sss" || fail "bake in $chunks direction chunks (${lim} MiB) differs from the whole bake"
  awk -v a="$(num predicted_peak_mib "$TMP/out")" -v l="$lim" 'BEGIN { exit !(a <= l) }' ||
    fail "estimate $(num predicted_peak_mib "$TMP/out") MiB above the limit ${lim} MiB that it was planned for"
  if [ "$chunks" -ge 2 ]; then
    grep -q "light directions in $chunks chunks" "$TMP/err" || { cat "$TMP/err" >&2; fail "no stderr line about the chunks"; }
    [ "$first_lim" -gt 0 ] || first_lim=$lim
  fi
  [ "$chunks" -gt "$most" ] && most=$chunks most_lim=$lim
done
grep -q 'even one light direction at a time' "$TMP/err" || { cat "$TMP/err" >&2; fail "the bake at ${lim} MiB failed otherwise than by the memory refusal"; }
[ "$most" -ge 2 ] || fail "no memory limit below ${peak} MiB gave two or more direction chunks"
echo "cli_gather_chunks: up to $most chunks (${most_lim} MiB), refused at ${lim} MiB"
# one thread, the narrowest chunks: the same bytes
expect_ok env SSS_MEMORY_LIMIT_MB=$most_lim "${bake[@]}" -o "$TMP/one.sss" --threads 1 --json -q
[ "$(num direction_chunks "$TMP/out")" -ge 2 ] || fail "1 thread at ${most_lim} MiB: no chunks"
cmp "$TMP/whole.sss" "$TMP/one.sss" || fail "bake in $(num direction_chunks "$TMP/out") chunks with 1 thread differs"
# not even one direction at a time: refused with one line, no file
rm -f "$TMP/none.sss"
SSS_MEMORY_LIMIT_MB=4 expect_fail 'needs at least .* GiB .* even one light direction at a time .* is available' \
  "${bake[@]}" -o "$TMP/none.sss" -q
[ "$(wc -l <"$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "the refusal is not one line"; }
[ ! -e "$TMP/none.sss" ] || fail "a refused bake wrote a file"
if ls "$TMP"/none.sss.tmp.* >/dev/null 2>&1; then fail "a refused bake left a temporary file"; fi
# two MPI ranks under the same limit (each rank plans its own memory; the
# narrowest chunk wins): the same bytes again
command -v mpirun >/dev/null || fail "mpirun not found (scripts/setup.sh installs openmpi-bin)"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# leak checking off for the two-rank run only (OpenMPI's plugins, see cli_gather_mpi.sh)
expect_ok env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0" SSS_MEMORY_LIMIT_MB=$first_lim \
  mpirun -x ASAN_OPTIONS -x SSS_MEMORY_LIMIT_MB -np 2 "${bake[@]}" -o "$TMP/mpi.sss" --threads 1 --json -q
[ "$(num direction_chunks "$TMP/out")" -ge 2 ] || fail "the 2-rank bake under ${first_lim} MiB did not use chunks"
cmp "$TMP/whole.sss" "$TMP/mpi.sss" || fail "2-rank MPI bake in direction chunks differs from the whole bake"
echo "cli_gather_chunks: ok"
