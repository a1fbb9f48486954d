#!/usr/bin/env bash
# Viewer benchmark (docs/viewer.md): scatter-evaluation throughput of the CPU and
# GPU paths and whole-frame time, with the memory-bandwidth bound, for the
# dragon at 100,250 and 437,645 vertices, mono and RGB.
#   tests/bench/view_bench.sh [OUTDIR]
# Needs build/ (scripts/setup.sh), data/fetch.sh, python3. Prints a markdown
# table; raw JSON lines go to OUTDIR/view_bench.jsonl.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-out/vb}
mkdir -p "$OUT"
: > "$OUT/view_bench.jsonl"
bake() { # name mesh scale quant material-args...
  local name=$1 mesh=$2 s=$3 q=$4; shift 4
  [ -f "$OUT/$name.sss" ] || build/precompute/sss-bake "$mesh" -o "$OUT/$name.sss" --mm-per-unit "$s" --quant "$q" "$@" -q
}
RGB=(--material marble)
MONO=(--sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62)   # marble's green channel, grey
bake d100_rgb_l8  data/stanford/dragon_100250.ply 8000 lloyd8 "${RGB[@]}"
bake d100_mono_l8 data/stanford/dragon_100250.ply 8000 lloyd8 "${MONO[@]}"
bake d437_rgb_l8  data/stanford/dragon_437645.ply 16000 lloyd8 "${RGB[@]}"
bake d437_mono_l8 data/stanford/dragon_437645.ply 16000 lloyd8 "${MONO[@]}"
bake d437_rgb_f32 data/stanford/dragon_437645.ply 16000 float "${RGB[@]}"
for name in d100_mono_l8 d100_rgb_l8 d437_mono_l8 d437_rgb_l8 d437_rgb_f32; do
  f="$OUT/$name.sss"
  echo "{\"name\":\"$name\",\"decode\":$(build/tests/bench/decode_bench "$f" 50),\"cpu\":$(build/runtime/sss-view "$f" --offscreen --bench 10 --size 800x600 --cpu),\"gpu\":$(build/runtime/sss-view "$f" --offscreen --bench 10 --size 800x600)}" >> "$OUT/view_bench.jsonl"
  echo "view_bench: $name done" >&2
done
python3 - "$OUT/view_bench.jsonl" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
print("| mesh | ch | storage | B/vertex read+written | CPU decode, 1 core: ms (Mvert/s) | bandwidth bound, 1 core: ms | ratio | CPU decode, 2 cores: ms | GPU path (llvmpipe) scatter: ms (Mvert/s) | frame, CPU path: ms (fps) | frame, GPU path: ms (fps) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    d, c, g = r["decode"], r["cpu"], r["gpu"]
    print(f"| dragon {d['vertices']:,} | {d['channels']} | {d['quant']} | {d['bytes_read_per_vertex']:.0f}+{d['bytes_written_per_vertex']:.0f} | "
          f"{d['decode_ms_1t']:.3f} ({d['vertices_per_s_1t']/1e6:.0f}) | {d['bound_ms_1t']:.3f} | {d['ratio_to_bound_1t']:.2f} | {d['decode_ms_all']:.3f} | "
          f"{g['scatter_ms_median']:.2f} ({g['scatter_vertices_per_s']/1e6:.0f}) | {c['frame_ms_median']:.1f} ({c['fps']:.1f}) | {g['frame_ms_median']:.1f} ({g['fps']:.1f}) |")
bw = rows[0]["decode"]
print()
print(f"Measured bandwidth (three float read streams + one write stream, like the decode): {bw['sum3_GBps_1t']:.1f} GB/s on one core, {bw['sum3_GBps_all']:.1f} GB/s on {bw['threads_max']} cores; plain copy {bw['copy_GBps_1t']:.1f} / {bw['copy_GBps_all']:.1f} GB/s.")
PY
