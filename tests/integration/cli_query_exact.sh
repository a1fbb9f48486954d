# sss-stat --query: the exact evaluator (Hao–Varshney 2004 §3.1 recomputed
# from the file alone) next to the stored reconstruction at one vertex. At a
# direction sample of a float bake the two agree; between samples they do
# not (the interpolation error of §3.2); bad vertices and lights are refused
# with a one-line message naming the file and the value, exit status 2.
. "$(dirname "$0")/lib.sh"
# expect_rc RC PATTERN CMD...: exactly exit status RC, a one-line message matching PATTERN
expect_rc() {
  local want=$1 pat=$2; shift 2
  "$@" >"$TMP/out" 2>"$TMP/err"; local rc=$?
  [ $rc -eq "$want" ] || { cat "$TMP/err" >&2; fail "expected exit status $want, got $rc: $*"; }
  [ "$(wc -l <"$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "expected a one-line message: $*"; }
  grep -q -- "$pat" "$TMP/err" || { cat "$TMP/err" >&2; fail "message should match '$pat': $*"; }
}
# json_field KEY: the raw value of "KEY": in $TMP/out (a number or a [..] array)
json_field() { sed -n "s/.*\"$1\":\(\[[^]]*\]\|[^,}]*\).*/\1/p" "$TMP/out"; }

expect_ok "$SSS_GENMESH" blob 2 "$TMP/b.ply"
N=20
for q in float lloyd8; do
  expect_ok "$SSS_BAKE" "$TMP/b.ply" -o "$TMP/b_$q.sss" --material skin1 --mm-per-unit 20 --dirs $N --quant $q -q
done

# direction sample j of the spherical Fibonacci set (common/src/dirset.c)
J=5
W=$(awk -v j=$J -v n=$N 'BEGIN { pi = atan2(0, -1); g = (1 + sqrt(5)) / 2; z = 1 - 2 * (j + 0.5) / n;
  p = 2 * pi * j / g; r = sqrt(1 - z * z); printf "%.17g,%.17g,%.17g", r * cos(p), r * sin(p), z }')

# at the sample: exact = stored (float file) to float precision, at every lit vertex tried
lit=0
for v in 0 17 50 99 161; do
  expect_ok "$SSS_STAT" "$TMP/b_float.sss" --query $v --light "$W" --json
  for key in file vertex vertices light direction quant directions nearest_direction channels eps \
             search_radius_mm exact reconstructed difference relative_difference max_abs_difference; do
    contains "$TMP/out" "\"$key\":"
  done
  contains "$TMP/out" "\"vertex\":$v,"
  contains "$TMP/out" "\"nearest_direction\":{\"index\":$J,"
  contains "$TMP/out" '"quant":"float"'
  ex=$(json_field exact); d=$(json_field max_abs_difference)
  [ -n "$ex" ] && [ -n "$d" ] || fail "vertex $v: no exact / max_abs_difference in $(cat "$TMP/out")"
  awk -v ex="$ex" -v d="$d" 'BEGIN { gsub(/[][]/, "", ex); n = split(ex, a, ","); m = 0;
      for (i = 1; i <= n; i++) if (a[i] + 0 > m) m = a[i] + 0;
      exit !(n == 3 && d + 0 <= 1e-5 * m + 1e-12) }' ||
    fail "vertex $v at direction sample $J: exact $ex vs stored differ by $d"
  awk -v ex="$ex" 'BEGIN { gsub(/[][]/, "", ex); split(ex, a, ","); exit !(a[1] + 0 > 0) }' && lit=$((lit + 1))
done
[ $lit -ge 2 ] || fail "only $lit of the queried vertices are lit at direction sample $J: the check is vacuous"

# between samples: the stored interpolation differs from the exact value
expect_ok "$SSS_STAT" "$TMP/b_float.sss" --query 50 --light 0.3,-0.2,0.9 --json
ex_float=$(json_field exact); d=$(json_field max_abs_difference)
awk -v ex="$ex_float" -v d="$d" 'BEGIN { gsub(/[][]/, "", ex); split(ex, a, ","); exit !(a[1] + 0 > 0 && d + 0 > 1e-6 * a[1]) }' ||
  fail "off the samples the interpolation error should be non-zero: exact $ex_float, difference $d"

# lloyd8: the evaluator ignores the stored values, so the exact part is the same
expect_ok "$SSS_STAT" "$TMP/b_lloyd8.sss" --query 50 --light 0.3,-0.2,0.9 --json
contains "$TMP/out" '"quant":"lloyd8"'
[ "$(json_field exact)" = "$ex_float" ] || fail "lloyd8 file: exact $(json_field exact), float file: $ex_float"

# text output, a light of any length
expect_ok "$SSS_STAT" "$TMP/b_float.sss" --query 50 --light 3,-2,9
contains "$TMP/out" 'b_float.sss: vertex 50 of 162'
contains "$TMP/out" 'reconstructed'
contains "$TMP/out" 'max |difference|'
expect_ok "$SSS_STAT" --help
contains "$TMP/out" '--query VERTEX --light X,Y,Z'

# bad vertices and lights: exit 2, the file and the value named
F="$TMP/b_float.sss"
expect_rc 2 "b_float.sss: --query 162: vertex index out of range" "$SSS_STAT" "$F" --query 162 --light 0,0,1
expect_rc 2 "b_float.sss: --query '-1': a vertex index cannot be negative" "$SSS_STAT" "$F" --query -1 --light 0,0,1
expect_rc 2 "b_float.sss: --query 'seven' is not a vertex index" "$SSS_STAT" "$F" --query seven --light 0,0,1
expect_rc 2 "b_float.sss: --query '2.5' is not a vertex index" "$SSS_STAT" "$F" --query 2.5 --light 0,0,1
expect_rc 2 "b_float.sss: --query '' is not a vertex index" "$SSS_STAT" "$F" --query '' --light 0,0,1
expect_rc 2 "b_float.sss: --query 99999999999999999999999: vertex index out of range" "$SSS_STAT" "$F" --query 99999999999999999999999 --light 0,0,1
expect_rc 2 "b_float.sss: --light '0,0,0' is the zero vector" "$SSS_STAT" "$F" --query 3 --light 0,0,0
expect_rc 2 "b_float.sss: --light 'nan,0,1': every component must be a finite number" "$SSS_STAT" "$F" --query 3 --light nan,0,1
expect_rc 2 "b_float.sss: --light '1e999,0,0': every component must be a finite number" "$SSS_STAT" "$F" --query 3 --light 1e999,0,0
expect_rc 2 "b_float.sss: --light '1,2' must be three numbers" "$SSS_STAT" "$F" --query 3 --light 1,2
expect_rc 2 "b_float.sss: --light '1,2,3,4' must be three numbers" "$SSS_STAT" "$F" --query 3 --light 1,2,3,4
expect_rc 2 "b_float.sss: --light 'x,y,z' must be three numbers" "$SSS_STAT" "$F" --query 3 --light x,y,z
expect_rc 2 "--query needs --light" "$SSS_STAT" "$F" --query 3
expect_rc 2 "--light needs --query" "$SSS_STAT" "$F" --light 0,0,1
expect_rc 2 "--light needs a value" "$SSS_STAT" "$F" --query 3 --light
expect_rc 1 "missing.sss" "$SSS_STAT" "$TMP/missing.sss" --query 0 --light 0,0,1
echo "cli_query_exact: ok"
