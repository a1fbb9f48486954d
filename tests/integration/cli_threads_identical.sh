# Same input and options give the same bytes with 1 and 2 threads.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 4 "$TMP/blob.ply"
for q in float lloyd8; do
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/t1.sss" --material marble --mm-per-unit 8 --dirs 100 --quant $q --threads 1 -q
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/t2.sss" --material marble --mm-per-unit 8 --dirs 100 --quant $q --threads 2 -q
  cmp "$TMP/t1.sss" "$TMP/t2.sss" || fail "$q: output differs between 1 and 2 threads"
done
echo "cli_threads_identical: ok"
