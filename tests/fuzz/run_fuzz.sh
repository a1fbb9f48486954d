#!/bin/bash
# run_fuzz.sh FUZZER SEED_CORPUS SECONDS [LIBFUZZER_FLAGS...]: a bounded libFuzzer
# run (docs/robustness.md).
# The seed corpus is copied to a scratch directory (the committed one stays
# as it is); new inputs found during the run are thrown away with it. Crash
# inputs are kept in the current directory as crash-* and fail the run.
set -euo pipefail
fuzzer=$1 seeds=$2 secs=$3
shift 3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r "$seeds"/. "$work"/
# Seed inputs first: each must pass on its own (a regression test).
"$fuzzer" -runs=0 "$@" "$work" 2>&1 | tail -3
# -rss_limit_mb: the readers must not allocate beyond their input's size;
# -max_len 1 MiB keeps each input's work bounded; 2 workers on 2 cores.
exec "$fuzzer" -max_total_time="$secs" -rss_limit_mb=2048 -max_len=1048576 -timeout=30 \
  -print_final_stats=1 "$@" "$work"
