# sss-stat --error: per-vertex error of a file against the exact evaluator
# (docs/accuracy.md). Fewer directions must mean more error; compressing must add
# error; the JSON has the documented keys; bad arguments fail cleanly.
. "$(dirname "$0")/lib.sh"
expect_ok "$SSS_GENMESH" blob 2 "$TMP/blob.ply"
for n in 25 200; do
  expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/b$n.sss" --material skin1 --mm-per-unit 20 --dirs $n --quant float -q
done
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/sh2.sss" --material skin1 --mm-per-unit 20 --dirs 200 --sh-order 2 --refs 0 -q
num() { sed -n "s/.*\"$2\":\([-0-9.eE+]*\).*/\1/p" "$1"; }
for f in b25 b200 sh2; do
  expect_ok "$SSS_STAT" "$TMP/$f.sss" --error --views 20 --seed 3 --json
  cp "$TMP/out" "$TMP/$f.json"
  for key in '"vertex_error":{' '"rms":\[' '"rel_rms":\[' '"max_abs":\[' '"rms_exact":\[' '"views":20' '"seed":3'; do
    contains "$TMP/$f.json" "$key"
  done
done
e25=$(num "$TMP/b25.json" rel_rms_all); e200=$(num "$TMP/b200.json" rel_rms_all); esh=$(num "$TMP/sh2.json" rel_rms_all)
awk -v a="$e25" -v b="$e200" -v c="$esh" 'BEGIN { exit !(a > 1.5 * b && b > 0 && c > b) }' ||
  fail "relative RMS: 25 dirs $e25, 200 dirs $e200, SH order 2 $esh (want 25 > 1.5 x 200 > 0 and SH > 200)"
# the same seed gives the same numbers; text output has a row per channel
expect_ok "$SSS_STAT" "$TMP/b200.sss" --error --views 20 --seed 3 --json
cmp -s "$TMP/out" "$TMP/b200.json" || fail "--error is not deterministic"
expect_ok "$SSS_STAT" "$TMP/b200.sss" --error --views 5
contains "$TMP/out" 'rel. RMS'
contains "$TMP/out" '  all '
expect_fail 'views' "$SSS_STAT" "$TMP/b200.sss" --error --views 0
expect_fail 'views' "$SSS_STAT" "$TMP/b200.sss" --error --views x
expect_fail 'exclude' "$SSS_STAT" "$TMP/b200.sss" --error --query 1 --light 0,0,1
echo "cli_vertex_error: ok"
