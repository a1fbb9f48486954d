# Bad input: a clear one-line message naming the file and element, a
# non-zero exit, no crash, and nothing written.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" sphere 2 "$TMP/s.ply"
expect_fail "nope.ply" "$SSS_BAKE" "$TMP/nope.ply" -o "$TMP/x.sss"
expect_fail "jelly" "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" --material jelly
expect_fail "dirs" "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" --dirs 0
expect_fail "mm-per-unit" "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" --mm-per-unit -1
expect_fail "quant" "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" --quant bf16
expect_fail "sigma" "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" --sigma-a 0,0,0 --sigma-s 0,1,1
expect_fail "unknown option" "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/x.sss" --frobnicate
expect_fail "missing -o" "$SSS_BAKE" "$TMP/s.ply"
[ ! -e "$TMP/x.sss" ] || fail "a failed bake left $TMP/x.sss"
# a face index out of range
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9001\n' > "$TMP/badidx.ply"
expect_fail "badidx.ply: face 0" "$SSS_BAKE" "$TMP/badidx.ply" -o "$TMP/x.sss"
# a header that declares 2^31 vertices in a tiny file
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 2147483648\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0000' > "$TMP/huge.ply"
expect_fail "huge.ply" "$SSS_BAKE" "$TMP/huge.ply" -o "$TMP/x.sss"
# corrupt and truncated .sss files
expect_ok "$SSS_BAKE" "$TMP/s.ply" -o "$TMP/good.sss" --dirs 12 -q
head -c 100 "$TMP/good.sss" > "$TMP/trunc.sss"
expect_fail "trunc.sss" "$SSS_STAT" "$TMP/trunc.sss"
cp "$TMP/good.sss" "$TMP/flip.sss"
printf '\x55' | dd of="$TMP/flip.sss" bs=1 seek=300 conv=notrunc status=none
expect_fail "flip.sss" "$SSS_STAT" "$TMP/flip.sss"
expect_fail "missing.sss" "$SSS_STAT" "$TMP/missing.sss"
: > "$TMP/empty.sss"
expect_fail "empty.sss" "$SSS_STAT" "$TMP/empty.sss"
# a failed bake leaves an existing output untouched
cp "$TMP/good.sss" "$TMP/keep.sss"
expect_fail "badidx.ply" "$SSS_BAKE" "$TMP/badidx.ply" -o "$TMP/keep.sss"
cmp "$TMP/good.sss" "$TMP/keep.sss" || fail "failed bake changed an existing output"
echo "cli_bad_input: ok"
