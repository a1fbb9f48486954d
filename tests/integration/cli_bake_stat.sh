# Bake a generated mesh with both storages, then read it back with sss-stat.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 3 "$TMP/blob.ply"
for q in float lloyd8; do
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/blob_$q.sss" --material skin1 --mm-per-unit 20 --dirs 50 --quant $q --json -q
  cp "$TMP/out" "$TMP/bake_$q.json"
  contains "$TMP/bake_$q.json" '"vertices":642'
  contains "$TMP/bake_$q.json" '"directions":50'
  contains "$TMP/bake_$q.json" "\"quant\":\"$q\""
  expect_ok "$SSS_STAT" "$TMP/blob_$q.sss" --json
  contains "$TMP/out" '"vertices":642'
  contains "$TMP/out" '"channels":3'
  contains "$TMP/out" '"tag":"GEOM"'
  expect_ok "$SSS_STAT" "$TMP/blob_$q.sss"
  contains "$TMP/out" 'bytes/vertex'
done
contains "$TMP/bake_lloyd8.json" '"lloyd_snr_db"'
# lloyd8 integrals take 1 byte instead of 4: the file must be much smaller
f=$(stat -c %s "$TMP/blob_float.sss"); l=$(stat -c %s "$TMP/blob_lloyd8.sss")
[ $((l * 3)) -lt "$f" ] || fail "lloyd8 file ($l B) should be < 1/3 of float ($f B)"
# the bundled sample bakes too
expect_ok "$SSS_BAKE" "$SSS_SOURCE/data/meshes/blob.ply" -o "$TMP/sample.sss" --material marble --mm-per-unit 100 --dirs 25 -q
echo "cli_bake_stat: ok"
