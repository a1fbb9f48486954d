#!/usr/bin/env bash
# What a reference run costs (docs/benchmarks.md, "The path-traced
# reference"): paths per second per core of sss-ref on the 10 cm bunny in
# marble (and skin1, and the 20 cm 23K dragon in marble), with and without
# the next-event roulette of docs/reference.md §3, and how the standard
# error of one query falls with the time spent.
#
#   tests/bench/ref_bench.sh          # BUILD=build; SECONDS_MAX=32
#
# Per-core figures are one thread's paths over the process's CPU seconds
# (user + sys, GNU time), so that a machine shared with other jobs does not
# inflate them; the time series uses every core and wall-clock seconds.
set -eu
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
REF=$BUILD/precompute/sss-ref
SECONDS_MAX=${SECONDS_MAX:-32}
BUNNY=(data/stanford/bunny.ply --mm-per-unit 10.094 --light 0,0.3,1 --query 669 --view 0,0.15,1)
DRAGON=(data/stanford/dragon_22998.ply --mm-per-unit 982.05 --light 0,0.3,1 --query 16429 --view 0,0.15,1)
TMP=$(mktemp -d /tmp/ref-bench.XXXXXX)
trap 'rm -rf "$TMP"' EXIT

echo "| mesh, material | next-event roulette | paths | CPU s | paths / CPU s | rays / path | scatterings / path | s.e. × √paths (R) |"
echo "|---|---|---|---|---|---|---|---|"
per_core() { # LABEL ROULETTE PATHS ARGS...
  local label=$1 rl=$2 n=$3; shift 3
  local extra=()
  [ "$rl" = off ] && extra=(--no-nee-roulette)
  /usr/bin/time -f "%U %S" -o "$TMP/t" "$REF" "$@" --paths "$n" --threads 1 --json -q "${extra[@]}" >"$TMP/j"
  local cpu
  cpu=$(awk '{ print $1 + $2 }' "$TMP/t")
  jq -r --arg l "$label" --arg r "$rl" --arg c "$cpu" '"| \($l) | \($r) | \(.paths) | \($c) | " +
    "\(.paths / ($c | tonumber) | round) | \(.walks.rays / .paths * 10 | round / 10) | " +
    "\(.walks.scatterings / .paths * 10 | round / 10) | \(.stderr[0] * (.paths | sqrt) * 1000 | round / 1000) |"' "$TMP/j"
}
per_core "bunny 10 cm, marble" on 8000 "${BUNNY[@]}" --material marble
per_core "bunny 10 cm, marble" off 8000 "${BUNNY[@]}" --material marble
per_core "bunny 10 cm, skin1" on 8000 "${BUNNY[@]}" --material skin1
per_core "dragon 20 cm, marble" on 4000 "${DRAGON[@]}" --material marble

echo
echo "| --seconds | paths | relative s.e. R / G / B | s.e. × √seconds (R) |"
echo "|---|---|---|---|"
t=1
while [ "$t" -le "$SECONDS_MAX" ]; do
  "$REF" "${BUNNY[@]}" --material marble --seconds "$t" --json -q >"$TMP/j"
  jq -r --arg t "$t" '"| \($t) | \(.paths) | " +
    ([range(0;3) as $c | (.stderr[$c] / .radiance[$c] * 10000 | round / 100 | tostring) + " %"] | join(" / ")) +
    " | \(.stderr[0] * (.seconds | sqrt) * 10000 | round / 10000) |"' "$TMP/j"
  t=$((t * 2))
done
