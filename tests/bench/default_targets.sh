#!/usr/bin/env bash
# The accuracy targets at default settings (docs/accuracy.md, "The defaults"): each
# model baked as a new user bakes it, `sss-bake MESH -o OUT --material M
# --mm-per-unit S` and nothing else, at its real size (the Stanford dragon
# 20 cm: 1000 mm per unit; the bunny 10 cm: 10 mm per unit), then the
# paper's §3.3 image error over VIEWS random views and VIEWS back-lit views
# (the light within 30 degrees of opposite the camera), the bytes per
# vertex (every byte of the file but the mesh, section GEOM: sss-stat's
# bytes_apart_geometry_per_vertex; the header, material and parameters
# count too), the bake time and the frame time of both viewer paths
# (llvmpipe here: the light moves every frame).
#
#   data/fetch.sh                        # the Stanford meshes (once)
#   tests/bench/default_targets.sh       # BUILD=build OUT=out/default_targets
#
# Knobs: VIEWS (100), SIZE (256), CASES (all rows below: "mesh:material:mm"
# with "grey" for a one-channel material, marble's green channel). Writes
# OUT/rows.tsv and prints it.
set -eu
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=${OUT:-out/default_targets}
VIEWS=${VIEWS:-100}
SIZE=${SIZE:-256}
CASES=${CASES:-"bunny:skin1:10 dragon_22998:marble:1000 dragon_22998:skin1:1000 dragon_22998:grey:1000 dragon_100250:marble:1000 dragon_100250:skin1:1000"}
BAKE=$BUILD/precompute/sss-bake STAT=$BUILD/precompute/sss-stat VIEW=$BUILD/runtime/sss-view
S=data/stanford
mkdir -p "$OUT"
num() { sed -n "s/.*\"$2\":\([-0-9.eE+]*\).*/\1/p" "$1" | head -1; }
img() { tr -d '\n' < "$1" | sed -n "s/.*\"image_error\":{[^}]*\"$2\":\([-0-9.eE+]*\).*/\1/p"; }
printf 'mesh\tmaterial\tmm_per_unit\tB_per_vertex\timage_rms_max\timage_rms_mean\tbacklit_rms_max\tbacklit_rms_mean\tvertex_rel_rms\tnear_mm\tnear_per_vertex\tbake_s\tgpu_ms\tcpu_ms\n' > "$OUT/rows.tsv"
for c in $CASES; do
  IFS=: read -r mesh mat mm <<<"$c"
  case $mat in
    grey) M=(--sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62) ;; # marble's green (Jensen et al. 2001)
    *) M=(--material "$mat") ;;
  esac
  f=$OUT/${mesh}_${mat}
  t0=$(date +%s.%N)
  "$BAKE" "$S/$mesh.ply" -o "$f.sss" "${M[@]}" --mm-per-unit "$mm" -q --json > "$f.bake.json"
  t1=$(date +%s.%N)
  "$STAT" "$f.sss" --json > "$f.stat.json"
  E=(--error --views "$VIEWS" --image-views "$VIEWS" --image-size "$SIZE" --seed 1 --json)
  "$STAT" "$f.sss" "${E[@]}" > "$f.err.json"
  "$STAT" "$f.sss" "${E[@]}" --backlit > "$f.back.json"
  "$VIEW" "$f.sss" --offscreen --bench 5 --size "${SIZE}x$SIZE" > "$f.gpu.json"
  "$VIEW" "$f.sss" --offscreen --bench 5 --size "${SIZE}x$SIZE" --cpu > "$f.cpu.json"
  printf '%s\t%s\t%s\t%.2f\t%s\t%s\t%s\t%s\t%s\t%.2f\t%.1f\t%.1f\t%s\t%s\n' "$mesh" "$mat" "$mm" \
    "$(num "$f.stat.json" bytes_apart_geometry_per_vertex)" \
    "$(img "$f.err.json" rms_max)" "$(img "$f.err.json" rms_mean)" "$(img "$f.back.json" rms_max)" \
    "$(img "$f.back.json" rms_mean)" "$(num "$f.err.json" rel_rms_all)" "$(num "$f.bake.json" near_radius_mm)" \
    "$(num "$f.bake.json" near_entries_per_vertex)" "$(echo "$t1 - $t0" | bc)" \
    "$(num "$f.gpu.json" scatter_ms_median)" "$(num "$f.cpu.json" scatter_ms_median)" | tee -a "$OUT/rows.tsv"
done
column -t -s"$(printf '\t')" "$OUT/rows.tsv"
