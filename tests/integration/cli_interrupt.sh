# A bake interrupted at any point (SIGINT, SIGTERM, SIGKILL) leaves either
# the previous file or no file under the output name, never a partial one;
# a bake that would not fit in memory says so before starting, with its
# estimate (docs/robustness.md; docs/format.md §7 for the atomic write).
. "$(dirname "$0")/lib.sh"
mesh="$SSS_SOURCE/data/meshes/blob.ply"   # 10,242 vertices: a few seconds per bake
slow=(--material marble --mm-per-unit 60 --gather direct -q)  # the direct sum: slow enough to be caught mid-bake
# the "old" file: a quick bake of the same mesh
expect_ok "$SSS_BAKE" "$mesh" -o "$TMP/out.sss" --dirs 12 --material marble --mm-per-unit 60 -q
cp "$TMP/out.sss" "$TMP/old.sss"
# Background jobs of a non-interactive shell start with SIGINT ignored; the
# bake installs its own handler early in main, so wait for that (SigCgt in
# /proc) before the delay starts: otherwise a slow start (sanitizer builds)
# would see the signal while it is still ignored.
wait_handler() {
  local m i
  for i in $(seq 1 500); do
    m=$(awk '/^SigCgt:/ {print $2}' "/proc/$1/status" 2>/dev/null) || true
    if [ -n "$m" ] && (( (16#$m >> 1) & 1 )); then return 0; fi
    sleep 0.02
  done
  return 1
}
check_old() {
  cmp -s "$TMP/out.sss" "$TMP/old.sss" || fail "$1: the output was replaced or damaged"
  expect_ok "$SSS_STAT" "$TMP/out.sss"
}
for sig in INT TERM KILL; do
  for delay in 0.1 0.7 1.5; do
    "$SSS_BAKE" "$mesh" -o "$TMP/out.sss" "${slow[@]}" 2>"$TMP/err" &
    pid=$!
    wait_handler "$pid" || fail "the bake never installed its SIGINT handler"
    sleep "$delay"
    kill -"$sig" "$pid" 2>/dev/null
    wait "$pid"; rc=$?
    [ "$rc" -ne 0 ] || fail "SIG$sig after ${delay}s: the bake finished before the signal (make it slower)"
    case $sig in
      INT|TERM) [ "$rc" -eq 130 ] || { cat "$TMP/err" >&2; fail "SIG$sig: exit $rc, expected 130"; }
                grep -q 'interrupted' "$TMP/err" || fail "SIG$sig: no 'interrupted' message";;
      KILL) [ "$rc" -eq 137 ] || fail "SIGKILL: exit $rc, expected 137";;
    esac
    check_old "SIG$sig after ${delay}s"
    # a clean interruption leaves no temporary file either
    if [ "$sig" != KILL ] && ls "$TMP"/out.sss.tmp.* >/dev/null 2>&1; then fail "SIG$sig left a temporary file"; fi
  done
done
# with no previous file, an interrupted bake leaves none
rm -f "$TMP/out.sss" "$TMP"/out.sss.tmp.*
"$SSS_BAKE" "$mesh" -o "$TMP/out.sss" "${slow[@]}" 2>/dev/null &
pid=$!; wait_handler "$pid"; sleep 0.5; kill -INT "$pid"; wait "$pid"
[ ! -e "$TMP/out.sss" ] || fail "an interrupted first bake left an output file"
# SIGINT during the neighbourhood phase, which polls the flag per vertex
# (before, it ran to its end: 355 s for 10^6 vertices). The direct gather
# with ~900 neighbours per vertex and one direction spends nearly all its
# time there; the signal comes 40 % into the phase, timed by a first run.
if "$SSS_BAKE" --help | grep -q -- '--gather direct'; then
  nb=(--sigma-a 0.002,0.002,0.002 --sigma-s 2,2,2 --mm-per-unit 60 --dirs 1 --gather direct --weights point --own-term baked --quant float -q)
  expect_ok "$SSS_BAKE" "$mesh" -o "$TMP/nb.sss" "${nb[@]}" --json
  t_imp=$(grep -o '"import":[0-9.e+-]*' "$TMP/out" | cut -d: -f2)
  t_nb=$(grep -o '"neighbourhoods":[0-9.e+-]*' "$TMP/out" | cut -d: -f2)
  delay=$(awk -v a="$t_imp" -v b="$t_nb" 'BEGIN { printf "%.3f", a + 0.4 * b + 0.05 }')
  rm -f "$TMP/nb.sss"
  "$SSS_BAKE" "$mesh" -o "$TMP/nb.sss" "${nb[@]}" 2>"$TMP/err" &
  pid=$!
  wait_handler "$pid" || fail "the bake never installed its SIGINT handler"
  sleep "$delay"
  t0=$(date +%s.%N)
  kill -INT "$pid"
  wait "$pid"; rc=$?
  t1=$(date +%s.%N)
  [ "$rc" -eq 130 ] || { cat "$TMP/err" >&2; fail "SIGINT in the neighbourhoods: exit $rc, expected 130"; }
  grep -q 'interrupted during neighbourhoods' "$TMP/err" || { cat "$TMP/err" >&2; fail "SIGINT in the neighbourhoods: not stopped there"; }
  awk -v a="$t0" -v b="$t1" -v n="$t_nb" 'BEGIN { exit !(b - a < 0.4 * n) }' ||
    fail "SIGINT in the neighbourhoods: took $(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }') s to stop (phase ${t_nb} s)"
  [ ! -e "$TMP/nb.sss" ] || fail "a bake interrupted in the neighbourhoods left an output file"
  if ls "$TMP"/nb.sss.tmp.* >/dev/null 2>&1; then fail "a bake interrupted in the neighbourhoods left a temporary file"; fi
fi
# memory: refused before any work, with the estimate, nothing written
SSS_MEMORY_LIMIT_MB=8 expect_fail 'needs \(at least\|about\) .* GiB .* is available' "$SSS_BAKE" "$mesh" -o "$TMP/out.sss" --dirs 800 -q
[ ! -e "$TMP/out.sss" ] || fail "a refused bake wrote a file"
echo "cli_interrupt: ok"
