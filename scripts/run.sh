#!/usr/bin/env bash
# The main job on the bundled sample: set up (packages + build), bake
# data/meshes/blob.ply (8 cm across) in marble into out/blob.sss at the
# defaults (docs/accuracy.md, "The defaults"), describe the file, then open
# the viewer (or, with no display, render it front-lit and lit from behind into
# out/blob_front.png and out/blob_back.png, exposed from the file).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
mkdir -p out
build/precompute/sss-bake data/meshes/blob.ply -o out/blob.sss --material marble --mm-per-unit 40
build/precompute/sss-stat out/blob.sss
if [ -n "${DISPLAY:-}" ] && [ -z "${CI:-}" ]; then
  build/runtime/sss-view out/blob.sss
else
  build/runtime/sss-view out/blob.sss --offscreen --out out/blob_front.png --size 640x480 --light 0.4,0.5,1 --view 0.3,0.2,1
  build/runtime/sss-view out/blob.sss --offscreen --out out/blob_back.png --size 640x480 --light -1,0.5,-0.4 --view 0.3,0.2,1
  echo "no display: rendered out/blob_front.png and out/blob_back.png (marble, lit from the front, and from the side and behind)"
fi
