#!/usr/bin/env bash
# The vector integral Q against q (docs/accuracy.md, "Vector integral Q";
# Hao–Varshney 2004 §3.1–3.2, Fig. 4): each model baked as the defaults
# bake it but uncompressed, `sss-bake MESH -o OUT --material M
# --mm-per-unit S --quant float`, once without and once with --vector,
# side by side in one run; then for the file with Q the paper's §3.3
# image error over VIEWS random views, where sss-stat draws every view
# from Q (what readers show), from the same file's q rows, and the exact
# q (image RMS of each against exact, and of q against Q); the bytes of
# QFLT and QVEC per vertex, the bake times, and the viewer's frame time
# from Q and from q (--no-vector) on both paths (llvmpipe here: the light
# moves every frame).
#
#   data/fetch.sh                        # the Stanford meshes (once)
#   tests/bench/vector_q.sh              # BUILD=build OUT=out/vector_q S=data/stanford
#
# Knobs: VIEWS (100), SIZE (256), CASES ("mesh:material:mm"). Writes
# OUT/rows.tsv and prints it.
set -eu
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=${OUT:-out/vector_q}
VIEWS=${VIEWS:-100}
SIZE=${SIZE:-256}
S=${S:-data/stanford}
CASES=${CASES:-"bunny:skin1:10 dragon_22998:marble:1000"}
BAKE=$BUILD/precompute/sss-bake STAT=$BUILD/precompute/sss-stat VIEW=$BUILD/runtime/sss-view
mkdir -p "$OUT"
printf 'mesh\tmaterial\tvertices\tQ_image_rms_max\tQ_image_rms_mean\tq_image_rms_max\tq_image_rms_mean\tq_vs_Q_rms_max\tq_vs_Q_rms_mean\tQ_vertex_rel_rms\tq_vertex_rel_rms\tQFLT_B_per_v\tQVEC_B_per_v\tbake_q_s\tbake_qQ_s\tgpu_q_ms\tgpu_Q_ms\tcpu_q_ms\tcpu_Q_ms\n' > "$OUT/rows.tsv"
for c in $CASES; do
  IFS=: read -r mesh mat mm <<<"$c"
  f=$OUT/${mesh}_${mat}
  B=("$S/$mesh.ply" --material "$mat" --mm-per-unit "$mm" --quant float -q --json)
  t0=$(date +%s.%N)
  "$BAKE" "${B[@]}" -o "$f.q.sss" > "$f.q.bake.json"
  t1=$(date +%s.%N)
  "$BAKE" "${B[@]}" -o "$f.Q.sss" --vector > "$f.Q.bake.json"
  t2=$(date +%s.%N)
  "$STAT" "$f.Q.sss" --json > "$f.stat.json"
  E=(--error --views "$VIEWS" --image-views "$VIEWS" --image-size "$SIZE" --seed 1 --json)
  "$STAT" "$f.Q.sss" "${E[@]}" > "$f.err.json"
  "$STAT" "$f.Q.sss" --error --views "$VIEWS" --seed 1 --json --no-vector --no-image > "$f.err_q.json"
  V=(--offscreen --bench 5 --size "${SIZE}x$SIZE")
  "$VIEW" "$f.Q.sss" "${V[@]}" --no-vector > "$f.gpu_q.json"
  "$VIEW" "$f.Q.sss" "${V[@]}" > "$f.gpu_Q.json"
  "$VIEW" "$f.Q.sss" "${V[@]}" --no-vector --cpu > "$f.cpu_q.json"
  "$VIEW" "$f.Q.sss" "${V[@]}" --cpu > "$f.cpu_Q.json"
  python3 - "$f" "$mesh" "$mat" "$(echo "$t1 - $t0" | bc)" "$(echo "$t2 - $t1" | bc)" <<'PY' | tee -a "$OUT/rows.tsv"
import json, sys
f, mesh, mat, tq, tQ = sys.argv[1:]
J = lambda s: json.load(open(f + s))
st, er, eq = J(".stat.json"), J(".err.json"), J(".err_q.json")
nv = st["vertices"]
sec = {s["tag"].strip(): s["bytes"] / nv for s in st["sections"]}
im, sq = er["image_error"], er["image_error"]["scalar_q"]
ms = lambda s: J(s)["scatter_ms_median"]
row = [mesh, mat, nv, im["rms_max"], im["rms_mean"], sq["rms_max"], sq["rms_mean"], sq["q_vs_Q_rms_max"],
       sq["q_vs_Q_rms_mean"], er["vertex_error"]["rel_rms_all"], eq["vertex_error"]["rel_rms_all"], sec["QFLT"],
       sec["QVEC"], float(tq), float(tQ), ms(".gpu_q.json"), ms(".gpu_Q.json"), ms(".cpu_q.json"), ms(".cpu_Q.json")]
print("\t".join("%.3g" % x if isinstance(x, float) else str(x) for x in row))
PY
done
column -t -s"$(printf '\t')" "$OUT/rows.tsv"
