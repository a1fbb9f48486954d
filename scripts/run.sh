#!/usr/bin/env bash
# The main job on the bundled sample: set up (packages + build), bake
# data/meshes/blob.ply with marble into out/blob.sss, describe the file, then
# open the viewer (or, with no display, render out/blob.png offscreen).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
mkdir -p out
build/precompute/sss-bake data/meshes/blob.ply -o out/blob.sss --material marble --mm-per-unit 40 --quant lloyd8
build/precompute/sss-stat out/blob.sss
if [ -n "${DISPLAY:-}" ] && [ -z "${CI:-}" ]; then
  build/runtime/sss-view out/blob.sss
else
  build/runtime/sss-view out/blob.sss --offscreen --out out/blob.png --size 800x600 --light -1,0.5,-0.4 --view 0.3,0.2,1 --exposure 2.5
  echo "no display: rendered out/blob.png (marble, lit from the side and behind)"
fi
