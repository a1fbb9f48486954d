# Hierarchical gather (docs/benchmarks.md, "Bake at scale"): the same bytes with 1 and 2 threads, and
# from `mpirun -np 2` (receivers split across two ranks, rank 0 writes) as
# from one process. Skip-proof: scripts/setup.sh installs openmpi-bin, and a
# missing mpirun fails this test instead of skipping it.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 4 "$TMP/blob.ply" 30
for q in float lloyd8; do
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/t1.sss" --material marble --dirs 48 --quant $q --gather tree --threads 1 -q
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/t2.sss" --material marble --dirs 48 --quant $q --gather tree --threads 2 -q
  cmp "$TMP/t1.sss" "$TMP/t2.sss" || fail "$q: tree gather output differs between 1 and 2 threads"
done
command -v mpirun >/dev/null || fail "mpirun not found (scripts/setup.sh installs openmpi-bin)"
# root in containers needs these; --oversubscribe: two ranks on any machine
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Sanitizer builds: OpenMPI's MPI_Init keeps blocks until exit, many
# allocated by MCA plugins it dlclose()s, which LeakSanitizer then reports
# from "<unknown module>" where no suppression can match; leak checking is
# off for the two-rank runs only (address and UB checks stay on; the
# one-process runs above and below keep leak checking).
mpi_env=(env ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0")
for g in tree direct; do
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/one.sss" --material marble --dirs 48 --gather $g --threads 1 -q
  expect_ok "${mpi_env[@]}" mpirun -x ASAN_OPTIONS -np 2 "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/two.sss" --material marble --dirs 48 --gather $g --threads 1 -q
  cmp "$TMP/one.sss" "$TMP/two.sss" || fail "$g: 2-rank MPI bake differs from the 1-process bake"
done
echo "cli_gather_mpi: ok"
