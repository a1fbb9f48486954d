#!/usr/bin/env bash
# accuracy_study.sh: what accuracy costs (docs/accuracy.md). Bakes the Stanford
# meshes over the knobs — directions (25 → 800), neighbourhood cutoff ε,
# quantisation (float / lloyd8), SH order, reference fraction, the
# compression presets, and the direction interpolation (our spherical
# triangle vs the paper's 4 nearest, Hao–Varshney 2004 §3.2) — and records
# for each: bake time per phase and peak memory (sss-bake --json), bytes per
# vertex (sss-stat --json, everything counted), per-frame evaluation time on
# the CPU and GPU paths (sss-view --offscreen --bench; the GPU is Mesa
# llvmpipe on a machine without one), the per-vertex error and the image
# error of the paper's protocol (§3.3; sss-stat --error). A generated sphere
# is the control without self-shadowing. Writes
# docs/data/accuracy/{results.csv,results.jsonl} and the plots, and
# regenerates docs/accuracy.md (plots and tables: accuracy_report.sh; the
# text: accuracy_doc.sh; both sourced from here).
#
#   data/fetch.sh && tests/bench/accuracy_study.sh          # default: sized for ~25 min on an
#                                                           #   idle 2-core machine (47 min measured
#                                                           #   on a shared one)
#   FULL=1 tests/bench/accuracy_study.sh                    # + the 100K dragon over all
#                                                           #   directions, the 437K dragon
#   REPORT_ONLY=1 tests/bench/accuracy_study.sh             # plots + doc from the saved results
#
# Environment: BUILD (default build), OUT (scratch, default out/accuracy;
# finished bakes and measurements there are reused: delete it to measure a
# new build afresh), FULL, REPORT_ONLY,
# VIEWS (image views, default 100). Needs jq and gnuplot (scripts/setup.sh).
# Python-free.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=${OUT:-out/accuracy}
FULL=${FULL:-0}
VIEWS=${VIEWS:-100}
DATA=docs/data/accuracy
DOC=docs/accuracy.md
BAKE=$BUILD/precompute/sss-bake STAT=$BUILD/precompute/sss-stat VIEW=$BUILD/runtime/sss-view
for t in jq gnuplot; do command -v $t >/dev/null || { echo "accuracy_study: '$t' not found (scripts/setup.sh installs it)" >&2; exit 1; }; done
mkdir -p "$OUT/sss" "$OUT/json" "$DATA"
# REPORT_ONLY draws from the measurements of a run under $OUT/json; without
# them it would write empty results over the committed ones
if [ "${REPORT_ONLY:-0}" = 1 ] && ! ls "$OUT"/json/*.err.json >/dev/null 2>&1; then
  echo "accuracy_study: REPORT_ONLY=1 needs the measurements of a run in $OUT/json (none there)" >&2
  exit 1
fi
T0=$(date +%s)
log() { printf '[%s] accuracy_study: %s\n' "$(date -u +%H:%M:%S)" "$*" >&2; }

# Meshes and their physical scale (mm per mesh unit; docs/accuracy.md "Setup").
declare -A MESH=( [bunny]=data/stanford/bunny.ply [teapot]=data/stanford/teapot.ply
                  [d23]=data/stanford/dragon_22998.ply [d100]=data/stanford/dragon_100250.ply
                  [d437]=data/stanford/dragon_437645.ply )
declare -A SCALE=( [bunny]=15 [teapot]=5 [d23]=4000 [d100]=4000 [d437]=4000 [sphere]=100 [d100g]=4000 )
# d100g: the 100K dragon in grey marble (marble's green coefficients, one
# channel): the one-channel budget of docs/compression.md
MESH[d100g]=data/stanford/dragon_100250.ply
# A convex control without self-shadowing (generated): q is then smooth in
# the light direction, and the direction error is interpolation alone.
MESH[sphere]=$OUT/sphere.ply
[ -s "$OUT/sphere.ply" ] || "$BUILD/data/sss-genmesh" sphere 5 "$OUT/sphere.ply" 2>/dev/null
# The Stanford meshes come from data/fetch.sh; a missing one is fetched once,
# and if that fails its configurations are left out (the sphere remains).
have_mesh() {
  [ -f "${MESH[$1]}" ] && return 0
  [ -n "${FETCHED:-}" ] || { FETCHED=1; data/fetch.sh >&2 || true; }
  [ -f "${MESH[$1]}" ] || { log "${MESH[$1]} missing (data/fetch.sh failed): its configurations are left out"; return 1; }
}
MAT=(--material marble)
mat_of() { if [ "$1" = d100g ]; then echo "--sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62 --eta 1.3"; else echo "--material marble"; fi; }
# compression for <= 16 bytes/vertex RGB with the near terms split off
# (docs/accuracy.md "Choosing settings")
SMALL_ARGS=${SMALL_ARGS:---refs 0.005 --sh-order 2}

# One configuration: run ID MESH STUDY INTERPS -- BAKE-ARGS...
# The manifest line says what was varied; the files under $OUT/json hold
# the measurements (an existing file is not measured again).
: > "$OUT/manifest.tsv.new"
run() {
  local id=$1 m=$2 study=$3 interps=$4; shift 5
  local f="$OUT/sss/$id.sss" j="$OUT/json/$id"
  printf '%s\t%s\t%s\t%s\t%s\n' "$id" "$m" "$study" "$interps" "$*" >> "$OUT/manifest.tsv.new"
  [ "${REPORT_ONLY:-0}" = 1 ] && return 0
  have_mesh "$m" || return 0
  if [ ! -s "$j.bake.json" ] || [ ! -f "$f" ]; then
    log "$id: bake $*"
    "$BAKE" "${MESH[$m]}" -o "$f" $(mat_of "$m") --mm-per-unit "${SCALE[$m]}" "$@" --json -q > "$j.bake.json"
  fi
  [ -s "$j.stat.json" ] || "$STAT" "$f" --json > "$j.stat.json"
  local exp; exp=$(cat "$OUT/json/$m.exposure")
  for ip in $interps; do
    if [ ! -s "$j.$ip.err.json" ]; then
      log "$id: error ($ip)"
      # "map": files with near terms, imaged with the viewer's shadow map
      # instead of its default GPU rays (docs/viewer.md)
      local ia=(--interp "$ip"); [ "$ip" = map ] && ia=(--interp triangle --image-visibility map)
      "$STAT" "$f" --error --views 100 --image-views "$VIEWS" --seed 1 --exposure "$exp" "${ia[@]}" --json > "$j.$ip.err.json"
    fi
  done
  if [ ! -s "$j.gpu.json" ]; then
    "$VIEW" "$f" --offscreen --bench 10 --size 512x512 --cpu > "$j.cpu.json"
    "$VIEW" "$f" --offscreen --bench 10 --size 512x512 > "$j.gpu.json"
  fi
}
# The image exposure of a mesh: the automatic one of its 200-direction float
# bake, then fixed for every configuration of that mesh (image RMS figures
# of one mesh compare only at one exposure).
# (The exposure depends on the exact evaluator only, not on the storage:
# the 437K dragon uses its lloyd8 bake, a quarter of the float's 1 GB.)
exposure() {
  local m=$1 qt=float
  [ "$m" = d437 ] && qt=lloyd8
  local id="$1_dirs200_$qt"
  [ "${REPORT_ONLY:-0}" = 1 ] && return 0
  [ -s "$OUT/json/$m.exposure" ] && return 0
  have_mesh "$m" || return 0
  [ -f "$OUT/sss/$id.sss" ] || "$BAKE" "${MESH[$m]}" -o "$OUT/sss/$id.sss" $(mat_of "$m") --mm-per-unit "${SCALE[$m]}" --dirs 200 --quant $qt --json -q > "$OUT/json/$id.bake.json"
  "$STAT" "$OUT/sss/$id.sss" --error --views 1 --image-views 1 --image-size 16 --json | jq -r '.image_error.exposure' > "$OUT/json/$m.exposure"
  log "$m: exposure $(cat "$OUT/json/$m.exposure")"
}

SMALL="bunny teapot d23"
for m in $SMALL d100 sphere d100g; do exposure "$m"; done
[ "$FULL" = 1 ] && exposure d437
# Figure 5: error against the number of directions, both interpolations.
for m in $SMALL sphere; do
  for n in 25 50 100 200 400 800; do run "${m}_dirs${n}_float" "$m" dirs "triangle nearest4" -- --dirs $n; done
done
D100_DIRS="50 200"; [ "$FULL" = 1 ] && D100_DIRS="25 50 100 200 400 800"
for n in $D100_DIRS; do run "d100_dirs${n}_lloyd8" d100 dirs "triangle" -- --dirs $n --quant lloyd8; done
# quantisation
for m in $SMALL; do run "${m}_dirs200_lloyd8" "$m" quant "triangle" -- --dirs 200 --quant lloyd8; done
# neighbourhood cutoff ε (1e-3 is the default, in the directions sweep)
for e in 1e-2 1e-4; do run "d23_eps${e}_float" d23 eps "triangle" -- --dirs 200 --eps $e; done
# Figure 9: reference fraction at 9 and 36 SH coefficients (order 3 and 6),
# the paper's linear 8-bit codes and 16-bit barycentric weights; refs 0 is SH alone
for o in 3 6; do
  for r in 0 0.005 0.01 0.02 0.03 0.05 0.1 0.2; do
    run "d23_sh${o}_refs${r}" d23 refs "triangle" -- --dirs 200 --sh-order $o --refs $r --sh-quant linear8
  done
done
# SH order alone
for o in 1 2 4 8; do run "d23_sh${o}_refs0" d23 sh "triangle" -- --dirs 200 --sh-order $o --refs 0 --sh-quant linear8; done
# the presets (Table I) on every mesh
PRESET_MESHES="$SMALL d100"; [ "$FULL" = 1 ] && PRESET_MESHES="$SMALL d100 d437"
for m in $PRESET_MESHES; do
  for p in paper compact; do run "${m}_${p}" "$m" preset "triangle" -- --dirs 200 --compress $p; done
  [ "$m" = d100 ] && run "d100_dirs200_float" d100 preset "triangle" -- --dirs 200
  [ "$m" = d437 ] && run "d437_dirs200_lloyd8" d437 preset "triangle" -- --dirs 200 --quant lloyd8
done
# Near terms at run time (sss/nearterms.h, format 1.3): the vertex's own term
# and its mesh rings split off in the bake and added back by the reader with
# a shadow test per vertex. Rings 0 / 1 / 2 at 200 directions, and the
# directions sweep again with the default ring (1).
NEAR=(--own-term runtime)
for m in $SMALL sphere; do
  for k in 0 2; do run "${m}_dirs200_ring${k}" "$m" near "triangle map" -- --dirs 200 "${NEAR[@]}" --rings $k; done
done
for m in d23 sphere; do
  for n in 25 50 100 200 400; do run "${m}_dirs${n}_ring1" "$m" dirs_ring1 "triangle map" -- --dirs $n "${NEAR[@]}" --rings 1; done
done
for m in bunny teapot; do run "${m}_dirs200_ring1" "$m" dirs_ring1 "triangle map" -- --dirs 200 "${NEAR[@]}" --rings 1; done
run "d100_dirs200_lloyd8_ring1" d100 dirs_ring1 "triangle map" -- --dirs 200 --quant lloyd8 "${NEAR[@]}" --rings 1
for m in $SMALL d100; do
  run "${m}_compact_ring1" "$m" preset_ring1 "triangle map" -- --dirs 200 --compress compact "${NEAR[@]}" --rings 1
done
# the settings recommended for the issue's budget (<= 16 bytes/vertex RGB): fewer
# references and lower SH order suffice once the near terms are off the rows
for m in d23 d100; do
  run "${m}_small_ring1" "$m" preset_ring1 "triangle map" -- --dirs 200 --compress compact $SMALL_ARGS "${NEAR[@]}" --rings 1
done
# finer meshes hold more of q beyond the 1-ring: two rings
for m in d23 d100; do
  run "${m}_small_ring2" "$m" preset_ring2 "triangle" -- --dirs 200 --compress compact $SMALL_ARGS "${NEAR[@]}" --rings 2
done
run "d100_dirs200_lloyd8_ring2" d100 near "triangle" -- --dirs 200 --quant lloyd8 "${NEAR[@]}" --rings 2
run "d100_small_ring3" d100 preset_ring3 "triangle" -- --dirs 200 --compress compact $SMALL_ARGS "${NEAR[@]}" --rings 3
# one channel: the compact preset is <= 16 bytes/vertex as it is
run "d100g_compact" d100g preset "triangle" -- --dirs 200 --compress compact
run "d100g_compact_ring1" d100g preset_ring1 "triangle map" -- --dirs 200 --compress compact "${NEAR[@]}" --rings 1
run "d100g_compact_ring2" d100g preset_ring2 "triangle" -- --dirs 200 --compress compact "${NEAR[@]}" --rings 2
mv "$OUT/manifest.tsv.new" "$OUT/manifest.tsv"
# Where the error comes from (tests/bench/error_sources): the float bakes'
# error split into lobe, terminator and cast shadows, and what splitting off
# the own term and its rings leaves
if [ "${REPORT_ONLY:-0}" != 1 ]; then
  for id in sphere_dirs200_float d23_dirs200_float bunny_dirs200_float teapot_dirs200_float d100_dirs200_float; do
    [ -f "$OUT/sss/$id.sss" ] || continue
    [ -s "$OUT/json/$id.sources.json" ] || { log "$id: error sources"; "$BUILD/tests/bench/error_sources" "$OUT/sss/$id.sss" 100 1 > "$OUT/json/$id.sources.json"; }
  done
fi
mkdir -p "$DATA"
cat "$OUT"/json/*.sources.json 2>/dev/null > "$DATA/error_sources.jsonl" || true
# the worst view's images of the 200-direction float dragon, for the page
if [ "${REPORT_ONLY:-0}" != 1 ] && [ ! -s "$DATA/worst_error.png" ] && [ -f "$OUT/sss/d23_dirs200_float.sss" ]; then
  "$STAT" "$OUT/sss/d23_dirs200_float.sss" --error --views 1 --image-views "$VIEWS" --seed 1 \
    --exposure "$(cat "$OUT/json/d23.exposure")" --error-images "$OUT/worst" --json > "$OUT/json/worst.json"
  for n in exact approx error; do cp "$OUT/worst/$n.png" "$DATA/worst_$n.png"; done
fi

# ---- collect: one JSON line and one CSV row per (configuration, interpolation)
log "collecting"
: > "$DATA/results.jsonl"
while IFS=$'\t' read -r id m study interps args; do
  j="$OUT/json/$id"
  for ip in $interps; do
    [ -s "$j.$ip.err.json" ] || continue
    jq -c -n --arg id "$id" --arg mesh "$m" --arg study "$study" --arg interp "$ip" --arg args "$args" \
      --argjson scale "${SCALE[$m]}" \
      --slurpfile b "$j.bake.json" --slurpfile s "$j.stat.json" --slurpfile e "$j.$ip.err.json" \
      --slurpfile c "$j.cpu.json" --slurpfile g "$j.gpu.json" '
      ($b[0]) as $b | ($s[0]) as $s | ($e[0]) as $e | ($c[0]) as $c | ($g[0]) as $g |
      { id: $id, mesh: $mesh, study: $study, interp: $interp, bake_args: $args, mm_per_unit: $scale,
        vertices: $s.vertices, triangles: $s.triangles, directions: $s.directions, quant: $s.quant,
        eps: ($s.params.eps // null),
        sh_order: ($s.compression.sh_order // null), refs: ($s.compression.refs // 0),
        refs_fraction: ($s.compression.refs_fraction // 0),
        bake_s: $b.seconds, peak_rss_mib: $b.peak_rss_mib,
        bytes_per_vertex: $s.scattering_bytes_per_vertex, file_bytes_per_vertex: $s.bytes_per_vertex,
        ratio_vs_8bit: $s.ratio_vs_8bit,
        vertex_rel_rms: $e.vertex_error.rel_rms_all, vertex_rms: $e.vertex_error.rms_all,
        image: $e.image_error,
        cpu_scatter_ms: $c.scatter_ms_median, cpu_frame_ms: $c.frame_ms_median, cpu_fps: $c.fps,
        gpu_scatter_ms: $g.scatter_ms_median, gpu_frame_ms: $g.frame_ms_median, gpu_fps: $g.fps,
        gl_renderer: $g.renderer }' >> "$DATA/results.jsonl"
  done
done < "$OUT/manifest.tsv"
jq -r -s '(["id","mesh","study","interp","vertices","directions","quant","eps","sh_order","refs","refs_fraction",
   "bake_total_s","bake_neighbourhoods_s","bake_visibility_s","bake_integrals_s","bake_quantise_s","bake_compress_s",
   "peak_rss_mib","bytes_per_vertex","ratio_vs_8bit","vertex_rel_rms","vertex_rms","image_rms_max","image_rms_mean",
   "image_rms_median","image_exposure","cpu_scatter_ms","cpu_frame_ms","gpu_scatter_ms","gpu_frame_ms"] | @csv),
  (.[] | [.id,.mesh,.study,.interp,.vertices,.directions,.quant,.eps,.sh_order,.refs,.refs_fraction,
   .bake_s.total,.bake_s.neighbourhoods,.bake_s.visibility,.bake_s.integrals,.bake_s.quantise,.bake_s.compress,
   .peak_rss_mib,.bytes_per_vertex,.ratio_vs_8bit,.vertex_rel_rms,.vertex_rms,.image.rms_max,.image.rms_mean,
   .image.rms_median,.image.exposure,.cpu_scatter_ms,.cpu_frame_ms,.gpu_scatter_ms,.gpu_frame_ms] | @csv)' \
  "$DATA/results.jsonl" > "$DATA/results.csv"

# wall time of a measuring run (not of a REPORT_ONLY one), for the page
[ "${REPORT_ONLY:-0}" = 1 ] || echo "$(( ($(date +%s) - T0 + 30) / 60 )) min, FULL=$FULL, VIEWS=$VIEWS, $(date -u +%Y-%m-%d)" > "$DATA/last_run.txt"
. "$(dirname "$0")/accuracy_report.sh"
log "wrote $DATA/results.csv, $DATA/*.png|svg, $DOC"
