#!/usr/bin/env bash
# The main job on the bundled sample: set up (packages + build), bake
# data/meshes/blob.ply with marble into out/blob.sss, and describe the file.
# (The interactive viewer and its offscreen render arrive with sss-view.)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
mkdir -p out
build/precompute/sss-bake data/meshes/blob.ply -o out/blob.sss --material marble --mm-per-unit 100 --quant lloyd8
build/precompute/sss-stat out/blob.sss
