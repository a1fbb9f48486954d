#!/usr/bin/env bash
# Benchmark of scene-driven effects (docs/scenes.md "Benchmark"):
# one mesh under scenes calling for different effect sets; per scene the
# bake time, rays, bytes per vertex of the scattering data and the frame
# time of sss-view --scene --bench (offscreen), with the lights summed on the
# GPU (fx_gpu.c, the default) and on the CPU (--cpu). Prints a Markdown table.
# usage: tests/bench/scene_effects.sh BUILD_DIR [MESH] [MM_PER_UNIT]
# (defaults: data/stanford/dragon_22998.ply, 4000 mm per unit; the light
# positions and camera are set for that mesh; THREADS: the bakes' threads, default 2)
set -eu
B=${1:?build dir}
MESH=$(readlink -f "${2:-data/stanford/dragon_22998.ply}")
MM=${3:-4000}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$B/tests/bench/make_probe" "$T/sky.exr" 128 64
obj() { echo "{\"name\": \"obj\", \"mesh\": \"$MESH\", \"material\": $1, \"mm_per_unit\": $MM}"; }
SUN='{"type": "directional", "direction": [0.3, 0.4, 0.85]}'
MOVING='{"type": "directional", "direction": [0.3, 0.4, 0.85], "moving": true}'
POINT='{"type": "point", "position": [0.12, 0.22, 0.12], "intensity": 0.04}'
ENV='{"type": "environment", "probe": "'$T'/sky.exr", "intensity": 0.3}'
CAM='"camera": {"position": [0, 0.13, 0.45], "target": [0, 0.125, 0], "fov_deg": 35}'
BAKE='"bake": {"dirs": 200, "shells": 4, "sh_order": 4}'
scene() { # name material lights...
  local n=$1 m=$2; shift 2
  local ls; ls=$(IFS=,; echo "$*")
  echo "{\"objects\": [$(obj "$m")], \"lights\": [$ls], $CAM, $BAKE}" > "$T/$n.json"
}
scene sun_grey '{"sigma_a": [0.004, 0.004, 0.004], "sigmap_s": [2.6, 2.6, 2.6]}' "$SUN"
scene sun '"marble"' "$SUN"
scene moving_sun '"marble"' "$MOVING"
scene env '"marble"' "$ENV"
scene point '"marble"' "$POINT"
scene sun_env '"marble"' "$SUN" "$ENV"
scene all '"marble"' "$MOVING" "$POINT" "$ENV"
echo "| scene | effects | bake (s) | rays | scattering bytes/vertex | file bytes/vertex | evaluation, GPU sum (ms) | evaluation, CPU sum (ms) | GPU programs | draw (ms) |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---|---:|"
for s in sun_grey sun moving_sun env point sun_env all; do
  mkdir -p "$T/$s"
  j=$("$B/precompute/sss-bake" --scene "$T/$s.json" -o "$T/$s" --threads "${THREADS:-2}" -q --json)
  fx=$(echo "$j" | sed 's/.*"effects":\[\([^]]*\)\].*/\1/; s/"//g; s/,/ /g')
  tb=$(echo "$j" | sed 's/.*"bake_seconds":\([0-9.e+-]*\).*/\1/')
  rays=$(echo "$j" | sed 's/.*"rays":\([0-9.e+-]*\).*/\1/')
  fbpv=$(echo "$j" | sed 's/.*"bytes_per_vertex":\([0-9.e+-]*\).*/\1/')
  v=$("$B/runtime/sss-view" "$T/$s/obj.sss" --scene "$T/$s.json" --offscreen --bench 30 --size 640x480)
  sbpv=$(echo "$v" | sed 's/.*"bytes_per_vertex":\([0-9.e+-]*\).*/\1/')
  sc=$(echo "$v" | sed 's/.*"scatter_ms_median":\([0-9.e+-]*\).*/\1/')
  dr=$(echo "$v" | sed 's/.*"draw_ms_median":\([0-9.e+-]*\).*/\1/')
  pg=$(echo "$v" | sed 's/.*"gpu_programs":"\([^"]*\)".*/\1/')
  vc=$("$B/runtime/sss-view" "$T/$s/obj.sss" --scene "$T/$s.json" --offscreen --bench 30 --size 640x480 --cpu)
  scc=$(echo "$vc" | sed 's/.*"scatter_ms_median":\([0-9.e+-]*\).*/\1/')
  printf "| %s | %s | %.2f | %s | %.1f | %.1f | %.3f | %.3f | %s | %.2f |\n" "$s" "$fx" "$tb" "$rays" "$sbpv" "$fbpv" "$sc" "$scc" "$pg" "$dr"
done
