#!/bin/bash
# campaign.sh BUILD_FUZZ OUTDIR [RUNS] [HARNESS...]: the long fuzz campaign of
# docs/robustness.md ("The long campaign"). Each harness runs to RUNS
# executions (default 10^7) from its seed corpus, one after another on one
# core, with the flags of its bounded ctest run (tests/fuzz/CMakeLists.txt).
# OUTDIR/HARNESS/ keeps the grown corpus, the log and any crash-* input;
# OUTDIR/campaign.md gets one table row per harness as it finishes.
set -uo pipefail
build=$(cd "$1" && pwd) out=$2 runs=${3:-10000000}
shift 3 2>/dev/null || shift $#
here=$(cd "$(dirname "$0")" && pwd)
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(scene cli sss mesh probe plan view)
swrast=$(sed -n 's/^SSS_FUZZ_SWRAST:FILEPATH=//p' "$build/CMakeCache.txt")
mkdir -p "$out"
[ -f "$out/campaign.md" ] || {
  echo "| harness | executions | wall time | executions/s | corpus (seeds → end) | findings |"
  echo "|---|---|---|---|---|---|"
} > "$out/campaign.md"
for t in "${harnesses[@]}"; do
  d=$out/$t
  mkdir -p "$d/corpus"
  cp -rn "$here/corpus/$t/." "$d/corpus/"
  seeds=$(ls "$here/corpus/$t" | wc -l)
  flags=(-runs="$runs" -rss_limit_mb=2048 -max_len=1048576 -timeout=30 -print_final_stats=1
         -artifact_prefix="$d/")
  pre=()
  case $t in
    cli) flags+=(-close_fd_mask=3) ;;
    view) flags+=(-timeout=120); pre=(env "LD_PRELOAD=$swrast") ;;
  esac
  t0=$(date +%s)
  "${pre[@]}" "$build/tests/fuzz/fuzz_$t" "${flags[@]}" "$d/corpus" > "$d/log" 2>&1
  rc=$?
  t1=$(date +%s)
  n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$d/log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$d/log" | tail -1)
  found="none"
  [ $rc -eq 0 ] || found="exit $rc: $(ls "$d" | grep -E '^(crash|leak|timeout|oom|slow-unit)-' | head -3 | tr '\n' ' ')"
  echo "| fuzz_$t | ${n:-?} | $((t1 - t0)) s | ${rate:-?} | $seeds → $(ls "$d/corpus" | wc -l) | $found |" >> "$out/campaign.md"
done
cat "$out/campaign.md"
