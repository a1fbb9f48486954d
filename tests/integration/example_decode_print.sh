# examples/decode_print (the runtime API, sss/api.h) prints for a vertex
# the very q that sss-stat --query reconstructs there (the stored rows plus
# the run-time near terms, precompute's reconstruction): the same float,
# compared as the 9 significant digits that give a float back exactly, on
# the default bake (references + SH, near terms at run time) and on a float
# bake without near terms; the file's contents print; bad arguments give a
# one-line message and exit status 1.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 2 "$TMP/b.ply"
expect_ok "$SSS_BAKE" "$TMP/b.ply" -o "$TMP/default.sss" --material skin1 --mm-per-unit 20 --dirs 50 -q
expect_ok "$SSS_BAKE" "$TMP/b.ply" -o "$TMP/float.sss" --material skin1 --mm-per-unit 20 --dirs 50 \
  --quant float --own-term baked -q
# json_array KEY: the numbers of "KEY":[...] in $TMP/out, one per line, as %.9g
json_array() { sed -n "s/.*\"$1\":\[\([^]]*\)\].*/\1/p" "$TMP/out" | tr ',' '\n' | awk '{ printf "%.9g\n", $1 }'; }

checked=0
for f in default float; do
  for L in 0.3,-0.2,0.9 -1,0.4,0.2 0,0,-2; do
    for v in 17 90; do
      expect_ok "$SSS_STAT" "$TMP/$f.sss" --query $v --light "$L" --json
      want=$(json_array reconstructed)
      [ "$(echo "$want" | wc -l)" -eq 3 ] || fail "$f.sss: no reconstructed values in $(cat "$TMP/out")"
      expect_ok "$SSS_DECODE_PRINT" "$TMP/$f.sss" "$L" $v
      got=$(sed -n "s/^q\[$v\] = //p" "$TMP/out" | tr ' ' '\n')
      [ "$got" = "$want" ] || fail "$f.sss, light $L, vertex $v: decode_print $(echo $got) vs sss-stat $(echo $want)"
      awk -v x="$(echo "$want" | head -1)" 'BEGIN { exit !(x + 0 > 0) }' && checked=$((checked + 1))
    done
  done
done
[ $checked -ge 4 ] || fail "only $checked of the compared vertices are lit: the check is vacuous"

expect_ok "$SSS_DECODE_PRINT" "$TMP/default.sss" 0,0,1
contains "$TMP/out" "mesh: 162 vertices, 320 triangles, 20 mm per unit"
contains "$TMP/out" "material skin1"
contains "$TMP/out" "storage: refs (SH order"
contains "$TMP/out" "near terms: at run time, every vertex within"
[ "$(grep -c '^channel [012]: min' "$TMP/out")" -eq 3 ] || fail "three channels' statistics expected"
expect_ok "$SSS_DECODE_PRINT" "$TMP/float.sss" 0,0,1
contains "$TMP/out" "storage: float, 50 directions, 3 channels"
grep -q "near terms" "$TMP/out" && fail "a file with its near terms baked in has none at run time"

expect_fail "usage" "$SSS_DECODE_PRINT" "$TMP/float.sss"
expect_fail "three numbers" "$SSS_DECODE_PRINT" "$TMP/float.sss" 1,2
expect_fail "missing.sss" "$SSS_DECODE_PRINT" "$TMP/missing.sss" 0,0,1
expect_fail "zero or not finite" "$SSS_DECODE_PRINT" "$TMP/float.sss" 0,0,0
expect_fail "VERTEX" "$SSS_DECODE_PRINT" "$TMP/float.sss" 0,0,1 162
head -c 100 "$TMP/float.sss" >"$TMP/cut.sss"
expect_fail "cut.sss" "$SSS_DECODE_PRINT" "$TMP/cut.sss" 0,0,1
echo "PASS: decode_print = sss-stat --query at $checked lit vertex-lights"
