#!/usr/bin/env bash
# Single scattering per pixel (docs/layers.md §8): frame time of sss-view at
# 800x600 against N = 10, 50, 100 for the per-segment closed form and seed
# 002's Algorithm 1, next to the frame without the term (median of FRAMES
# frames, sss-view --bench: wall clock after glFinish, the light moving
# every frame so that the light-space map is redrawn each time).
#   tests/bench/single_gpu.sh [OUTDIR] [FRAMES]
# Needs build/ and data/stanford/bunny.ply (data/fetch.sh). Prints a
# markdown table.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-out/single_gpu}
FRAMES=${2:-3}
mkdir -p "$OUT"
F=$OUT/bunny_ketchup.sss
[ -f "$F" ] || build/precompute/sss-bake data/stanford/bunny.ply -o "$F" --material ketchup --mm-per-unit 10.1 \
  --dirs 40 --quant float -q 2>/dev/null
bench() { build/runtime/sss-view "$F" --offscreen --bench "$FRAMES" --size 800x600 "$@" |
  python3 -c 'import json,sys; r=json.load(sys.stdin); print("%.1f | %.2f" % (r["frame_ms_median"], r["fps"]))'; }
echo "| single scattering | N | frame ms (median) | fps |"
echo "|---|---|---|---|"
echo "| off | — | $(bench --single off) |"
for n in 10 50 100; do
  echo "| per-segment closed form | $n | $(bench --single on --single-samples $n) |"
  echo "| Algorithm 1 | $n | $(bench --single on --single-samples $n --single-march seed) |"
done
