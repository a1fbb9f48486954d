#!/usr/bin/env bash
# accuracy_study.sh: what accuracy costs (docs/accuracy.md). Bakes the
# Stanford meshes and a generated sphere over the bake's knobs and records
# for each configuration: bake time and peak memory (sss-bake --json),
# bytes per vertex (sss-stat --json, everything counted), per-frame
# evaluation time on the CPU and GPU paths (sss-view --offscreen --bench; the
# GPU is Mesa llvmpipe on a machine without one), the per-vertex error and
# the image error of the paper's protocol (Hao–Varshney 2004 §3.3;
# sss-stat --error) over random views and, in the real-size series, over
# back-lit views (the light within 30° of opposite the camera).
#
# Two series (docs/accuracy.md "Setup"):
#   SERIES=real (default): each model at its real size — the Stanford
#     dragon 20 cm long (1000 mm per unit), the bunny 10 cm tall (10), the
#     teapot 26 cm wide (8), the sphere 10 cm across (radius 50 mm) — and
#     every knob varied one at a time around the defaults of sss-bake.
#     Writes docs/data/accuracy/ and docs/accuracy.md.
#   SERIES=4000: the dragon at 4000 mm per unit (80 cm), the bunny at 15,
#     the teapot at 5 and the sphere at 100, with the paper's method as the
#     base (every term baked, float rows, point weights) and the earlier
#     sweeps: directions 25 → 800, ε, quantisation, SH order, reference
#     fraction (Fig. 9), the presets, and the near terms by rings. The
#     flags the defaults of that time implied are spelt out, so the rows
#     can be measured again with today's sss-bake. Writes
#     docs/data/accuracy_4000/ and docs/accuracy_4000.md.
#
#   data/fetch.sh && tests/bench/accuracy_study.sh     # about 70 min on an idle 2-core machine
#   FULL=1 tests/bench/accuracy_study.sh               # + the 100K dragon (13 GB for its exact
#                                                      #   evaluator; the 4000 series: + the 437K)
#   REPORT_ONLY=1 [SERIES=4000] tests/bench/accuracy_study.sh   # plots + page from the committed results
#
# Environment: BUILD (default build), OUT (scratch, default out/accuracy or
# out/accuracy_4000; finished bakes and measurements there are reused:
# delete it to measure a new build afresh), SERIES, FULL, REPORT_ONLY,
# VIEWS (image views, default 100), FRAME_REPS (rounds of frame times,
# default 3). Needs jq and gnuplot (scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
SERIES=${SERIES:-real}
FULL=${FULL:-0}
VIEWS=${VIEWS:-100}
FRAME_REPS=${FRAME_REPS:-3}
REPORT_ONLY=${REPORT_ONLY:-0}
case $SERIES in
  real) OUT=${OUT:-out/accuracy} DATA=docs/data/accuracy DOC=docs/accuracy.md ;;
  4000) OUT=${OUT:-out/accuracy_4000} DATA=docs/data/accuracy_4000 DOC=docs/accuracy_4000.md ;;
  *) echo "accuracy_study: SERIES must be real or 4000, not '$SERIES'" >&2; exit 1 ;;
esac
BAKE=$BUILD/precompute/sss-bake STAT=$BUILD/precompute/sss-stat VIEW=$BUILD/runtime/sss-view
for t in jq gnuplot; do command -v $t >/dev/null || { echo "accuracy_study: '$t' not found (scripts/setup.sh installs it)" >&2; exit 1; }; done
mkdir -p "$OUT/sss" "$OUT/json" "$DATA"
T0=$(date +%s) MEASURED=0
log() { printf '[%s] accuracy_study: %s\n' "$(date -u +%H:%M:%S)" "$*" >&2; }

# Meshes and their physical scale (mm per mesh unit).
declare -A MESH=( [bunny]=data/stanford/bunny.ply [teapot]=data/stanford/teapot.ply
                  [d23]=data/stanford/dragon_22998.ply [d100]=data/stanford/dragon_100250.ply
                  [d437]=data/stanford/dragon_437645.ply [sphere]=$OUT/sphere.ply )
# d23g, d100g: the dragons in grey marble (marble's green coefficients, one
# channel), the one-channel budget
MESH[d23g]=${MESH[d23]} MESH[d100g]=${MESH[d100]}
if [ "$SERIES" = real ]; then
  declare -A SCALE=( [bunny]=10 [teapot]=8 [d23]=1000 [d100]=1000 [d437]=1000 [sphere]=50 [d23g]=1000 [d100g]=1000 )
else
  declare -A SCALE=( [bunny]=15 [teapot]=5 [d23]=4000 [d100]=4000 [d437]=4000 [sphere]=100 [d23g]=4000 [d100g]=4000 )
fi
# A convex control without self-shadowing (generated, 10,242 vertices, unit
# radius): q is then smooth in the light direction, and the direction error
# is interpolation alone.
[ "$REPORT_ONLY" = 1 ] || [ -s "$OUT/sphere.ply" ] || "$BUILD/data/sss-genmesh" sphere 5 "$OUT/sphere.ply" 2>/dev/null
# The Stanford meshes come from data/fetch.sh; a missing one is fetched once,
# and if that fails its configurations are left out (the sphere remains).
have_mesh() {
  [ -f "${MESH[$1]}" ] && return 0
  [ -n "${FETCHED:-}" ] || { FETCHED=1; data/fetch.sh >&2 || true; }
  [ -f "${MESH[$1]}" ] || { log "${MESH[$1]} missing (data/fetch.sh failed): its configurations are left out"; return 1; }
}
mat_of() { case $1 in *g) echo "--sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62 --eta 1.3" ;; *) echo "--material marble" ;; esac; }

# One configuration: run ID MESH STUDY INTERPS -- BAKE-ARGS...
# The manifest line says what was varied; the files under $OUT/json hold
# the measurements (an existing file is not measured again).
run() {
  local id=$1 m=$2 study=$3 interps=$4; shift 5
  local f="$OUT/sss/$id.sss" j="$OUT/json/$id"
  printf '%s\t%s\t%s\t%s\t%s\n' "$id" "$m" "$study" "$interps" "$*" >> "$OUT/manifest.tsv.new"
  have_mesh "$m" || return 0
  if [ ! -s "$j.bake.json" ] || [ ! -f "$f" ]; then
    MEASURED=$((MEASURED + 1))
    log "$id: bake $*"
    "$BAKE" "${MESH[$m]}" -o "$f" $(mat_of "$m") --mm-per-unit "${SCALE[$m]}" "$@" --json -q > "$j.bake.json"
  fi
  [ -s "$j.stat.json" ] || "$STAT" "$f" --json > "$j.stat.json"
  [ -s "$OUT/json/$m.exposure" ] || exposure "$m" "$f"
  local exp; exp=$(cat "$OUT/json/$m.exposure")
  for ip in $interps; do
    # "map": files with near terms, imaged with the viewer's shadow map
    # instead of its default GPU rays (docs/viewer.md)
    local ia=(--interp "$ip"); [ "$ip" = map ] && ia=(--interp triangle --image-visibility map)
    local E=(--error --views 100 --image-views "$VIEWS" --seed 1 --exposure "$exp" "${ia[@]}" --json)
    if [ ! -s "$j.$ip.err.json" ]; then
      log "$id: error ($ip)"
      "$STAT" "$f" "${E[@]}" > "$j.$ip.err.json"
    fi
    if [ "$SERIES" = real ] && [ ! -s "$j.$ip.back.json" ]; then
      log "$id: error ($ip, back-lit)"
      "$STAT" "$f" "${E[@]}" --backlit > "$j.$ip.back.json"
    fi
  done
}
# Frame times (sss-view --offscreen --bench 10 at 512², the CPU and the GPU
# path): FRAME_REPS rounds over every file of the manifest, one file after
# the other, so that a slow spell of the machine touches every
# configuration alike; the page takes the median of the rounds' medians.
frame_times() {
  local r id rest f j
  for r in $(seq 1 "$FRAME_REPS"); do
    while IFS=$'\t' read -r id rest; do
      f="$OUT/sss/$id.sss" j="$OUT/json/$id"
      [ -f "$f" ] && [ ! -s "$j.gpu.$r.json" ] || continue
      "$VIEW" "$f" --offscreen --bench 10 --size 512x512 --cpu > "$j.cpu.$r.json"
      "$VIEW" "$f" --offscreen --bench 10 --size 512x512 > "$j.gpu.$r.json"
    done < "$OUT/manifest.tsv"
  done
}
# the median over the rounds of one key of the frame-time files given
frame_median() { local k=$1; shift; jq -s --arg k "$k" 'map(.[$k]) | sort | .[(length - 1) / 2 | floor] // null' "$@"; }
# The image exposure of a mesh: the automatic one of its first bake (the
# real series: the defaults; the 4000 series: the 200-direction float
# bake), then fixed for every configuration of that mesh (image RMS
# figures of one mesh compare only at one exposure). The exposure follows
# the exact evaluator only, not the storage.
exposure() {
  "$STAT" "$2" --error --views 1 --image-views 1 --image-size 16 --json | jq -r '.image_error.exposure' > "$OUT/json/$1.exposure"
  log "$1: exposure $(cat "$OUT/json/$1.exposure")"
}

# The worst view's exact, approximate and error images of a 23K dragon
# configuration, for the page
worst_images() {
  [ ! -s "$DATA/worst_error.png" ] && [ -f "$OUT/sss/$1.sss" ] || return 0
  "$STAT" "$OUT/sss/$1.sss" --error --views 1 --image-views "$VIEWS" --seed 1 \
    --exposure "$(cat "$OUT/json/d23.exposure")" --error-images "$OUT/worst" --json > "$OUT/json/worst.json"
  for n in exact approx error; do cp "$OUT/worst/$n.png" "$DATA/worst_$n.png"; done
}

# ---- the real sizes: every knob one at a time around the defaults
configs_real() {
  local m
  for m in d23 bunny teapot sphere d23g; do
    local ip=triangle; [ "$m" = d23 ] && ip="triangle nearest4"
    run "${m}_defaults" "$m" defaults "$ip" --
    [ "$m" = d23g ] || run "${m}_paper" "$m" paper triangle -- --preset paper
  done
  # light directions (200 by default)
  for m in d23 bunny sphere teapot; do for n in 50 100 400; do
    run "${m}_dirs$n" "$m" dirs triangle -- --dirs $n
  done; done
  # the near terms: the fraction of R_d,total their radius holds (0.95 by
  # default), rings instead of the radius (the expert option), every term
  # baked, and the point weights instead of the hat functions
  for m in d23 bunny teapot; do
    for f in 0.9 0.97 0.99; do run "${m}_frac$f" "$m" fraction triangle -- --near-fraction $f; done
    for k in 1 2; do run "${m}_rings$k" "$m" rings triangle -- --rings $k; done
  done
  for m in d23 bunny sphere teapot; do
    run "${m}_baked" "$m" near triangle -- --own-term baked
    run "${m}_point" "$m" weights triangle -- --weights point
  done
  # storage: reference fraction (1 % by default), SH order (3), no
  # compression (float, lloyd8)
  for r in 0.005 0.02 0.03; do run "d23_refs$r" d23 refs triangle -- --refs $r; done
  for o in 2 4; do run "d23_sh$o" d23 sh triangle -- --sh-order $o; done
  for m in d23 bunny teapot; do run "${m}_float" "$m" quant triangle -- --quant float; done
  run d23_lloyd8 d23 quant triangle -- --quant lloyd8
  # the two that trade against each other: a wider near radius (no bytes,
  # frame time) with a coarser compression (fewer bytes, error)
  for m in d23 bunny; do
    run "${m}_frac0.99_sh2" "$m" combined triangle -- --near-fraction 0.99 --sh-order 2
    run "${m}_frac0.99_sh2_refs0.005" "$m" combined triangle -- --near-fraction 0.99 --sh-order 2 --refs 0.005
  done
  if [ "$FULL" = 1 ]; then
    run d100_defaults d100 defaults triangle --
    run d100_paper d100 paper triangle -- --preset paper
  fi
  worst_images d23_defaults
}

# ---- 4000 mm per unit: the paper's method as the base. old ID MESH STUDY
# INTERPS -- ARGS adds what the bake's defaults meant then: point weights,
# float rows without --quant or --compress, every term baked without
# --own-term.
old() {
  local a=(--weights point) x
  [[ " $* " == *" --quant "* || " $* " == *" --compress "* ]] || a+=(--quant float)
  [[ " $* " == *" --own-term "* ]] || a+=(--own-term baked)
  local id=$1 m=$2 study=$3 interps=$4; shift 5
  run "$id" "$m" "$study" "$interps" -- "$@" "${a[@]}"
}
configs_4000() {
  local m n o r e k p SMALL="bunny teapot d23" SMALL_ARGS="--refs 0.005 --sh-order 2" NEAR=(--own-term runtime)
  for m in $SMALL sphere d100 d100g; do
    local qt=float; [ "$m" = d100 ] || [ "$m" = d100g ] && qt=lloyd8
    [ "$m" = d100g ] || old "${m}_dirs200_$qt" "$m" dirs triangle -- --dirs 200 --quant $qt
  done
  # Figure 5: error against the number of directions, both interpolations.
  for m in $SMALL sphere; do
    for n in 25 50 100 200 400 800; do old "${m}_dirs${n}_float" "$m" dirs "triangle nearest4" -- --dirs $n; done
  done
  local D100_DIRS="50 200"; [ "$FULL" = 1 ] && D100_DIRS="25 50 100 200 400 800"
  for n in $D100_DIRS; do old "d100_dirs${n}_lloyd8" d100 dirs "triangle" -- --dirs $n --quant lloyd8; done
  for m in $SMALL; do old "${m}_dirs200_lloyd8" "$m" quant "triangle" -- --dirs 200 --quant lloyd8; done
  for e in 1e-2 1e-4; do old "d23_eps${e}_float" d23 eps "triangle" -- --dirs 200 --eps $e; done
  # Figure 9: reference fraction at 9 and 36 SH coefficients (order 3 and 6),
  # the paper's linear 8-bit codes and 16-bit barycentric weights; refs 0 is SH alone
  for o in 3 6; do
    for r in 0 0.005 0.01 0.02 0.03 0.05 0.1 0.2; do
      old "d23_sh${o}_refs${r}" d23 refs "triangle" -- --dirs 200 --sh-order $o --refs $r --sh-quant linear8
    done
  done
  for o in 1 2 4 8; do old "d23_sh${o}_refs0" d23 sh "triangle" -- --dirs 200 --sh-order $o --refs 0 --sh-quant linear8; done
  local PRESET_MESHES="$SMALL d100"; [ "$FULL" = 1 ] && PRESET_MESHES="$SMALL d100 d437"
  for m in $PRESET_MESHES; do
    for p in paper compact; do old "${m}_${p}" "$m" preset "triangle" -- --dirs 200 --compress $p; done
    [ "$m" = d100 ] && old "d100_dirs200_float" d100 preset "triangle" -- --dirs 200
    [ "$m" = d437 ] && old "d437_dirs200_lloyd8" d437 preset "triangle" -- --dirs 200 --quant lloyd8
  done
  # Near terms at run time by rings: own term, 1 and 2 rings
  for m in $SMALL sphere; do
    for k in 0 2; do old "${m}_dirs200_ring${k}" "$m" near "triangle map" -- --dirs 200 "${NEAR[@]}" --rings $k; done
  done
  for m in d23 sphere; do
    for n in 25 50 100 200 400; do old "${m}_dirs${n}_ring1" "$m" dirs_ring1 "triangle map" -- --dirs $n "${NEAR[@]}" --rings 1; done
  done
  for m in bunny teapot; do old "${m}_dirs200_ring1" "$m" dirs_ring1 "triangle map" -- --dirs 200 "${NEAR[@]}" --rings 1; done
  old "d100_dirs200_lloyd8_ring1" d100 dirs_ring1 "triangle map" -- --dirs 200 --quant lloyd8 "${NEAR[@]}" --rings 1
  for m in $SMALL d100; do
    old "${m}_compact_ring1" "$m" preset_ring1 "triangle map" -- --dirs 200 --compress compact "${NEAR[@]}" --rings 1
  done
  for m in d23 d100; do
    old "${m}_small_ring1" "$m" preset_ring1 "triangle map" -- --dirs 200 --compress compact $SMALL_ARGS "${NEAR[@]}" --rings 1
    old "${m}_small_ring2" "$m" preset_ring2 "triangle" -- --dirs 200 --compress compact $SMALL_ARGS "${NEAR[@]}" --rings 2
  done
  old "d100_dirs200_lloyd8_ring2" d100 near "triangle" -- --dirs 200 --quant lloyd8 "${NEAR[@]}" --rings 2
  old "d100_small_ring3" d100 preset_ring3 "triangle" -- --dirs 200 --compress compact $SMALL_ARGS "${NEAR[@]}" --rings 3
  old "d100g_compact" d100g preset "triangle" -- --dirs 200 --compress compact
  old "d100g_compact_ring1" d100g preset_ring1 "triangle map" -- --dirs 200 --compress compact "${NEAR[@]}" --rings 1
  old "d100g_compact_ring2" d100g preset_ring2 "triangle" -- --dirs 200 --compress compact "${NEAR[@]}" --rings 2
  # Where the error comes from (tests/bench/error_sources): the float
  # bakes' error split into lobe, terminator and cast shadows, and what
  # splitting off the own term and its rings leaves
  local id
  for id in sphere_dirs200_float d23_dirs200_float bunny_dirs200_float teapot_dirs200_float d100_dirs200_float; do
    [ -f "$OUT/sss/$id.sss" ] || continue
    [ -s "$OUT/json/$id.sources.json" ] || { log "$id: error sources"; "$BUILD/tests/bench/error_sources" "$OUT/sss/$id.sss" 100 1 > "$OUT/json/$id.sources.json"; }
  done
  cat "$OUT"/json/*.sources.json 2>/dev/null > "$DATA/error_sources.jsonl" || true
  worst_images d23_dirs200_float
}

# ---- collect: one JSON line and one CSV row per (configuration, interpolation)
collect() {
  : > "$DATA/results.jsonl"
  local id m study interps args ip j
  while IFS=$'\t' read -r id m study interps args; do
    j="$OUT/json/$id"
    for ip in $interps; do
      [ -s "$j.$ip.err.json" ] || continue
      local back=null; [ -s "$j.$ip.back.json" ] && back=$(jq -c '.image_error' "$j.$ip.back.json")
      local cf=("$j".cpu.[0-9]*.json) gf=("$j".gpu.[0-9]*.json)
      local c g
      c=$(jq -n --argjson s "$(frame_median scatter_ms_median "${cf[@]}")" --argjson f "$(frame_median frame_ms_median "${cf[@]}")" '{scatter_ms_median: $s, frame_ms_median: $f, fps: (if $f then 1000 / $f else null end)}')
      g=$(jq -n --argjson s "$(frame_median scatter_ms_median "${gf[@]}")" --argjson f "$(frame_median frame_ms_median "${gf[@]}")" \
            --arg r "$(jq -r '.renderer' "${gf[0]}")" '{scatter_ms_median: $s, frame_ms_median: $f, fps: (if $f then 1000 / $f else null end), renderer: $r}')
      jq -c -n --arg id "$id" --arg mesh "$m" --arg study "$study" --arg interp "$ip" --arg args "$args" \
        --argjson scale "${SCALE[$m]}" --argjson back "$back" --argjson c "$c" --argjson g "$g" \
        --slurpfile b "$j.bake.json" --slurpfile s "$j.stat.json" --slurpfile e "$j.$ip.err.json" '
        ($b[0]) as $b | ($s[0]) as $s | ($e[0]) as $e |
        { id: $id, mesh: $mesh, study: $study, interp: $interp, bake_args: $args, mm_per_unit: $scale,
          vertices: $s.vertices, triangles: $s.triangles, directions: $s.directions, quant: $s.quant,
          eps: ($s.params.eps // null), weights: ($s.params.weights // null),
          near_radius_mm: ($b.near_radius_mm // null), near_entries_per_vertex: ($b.near_entries_per_vertex // null),
          sh_order: ($s.compression.sh_order // null), refs: ($s.compression.refs // 0),
          refs_fraction: ($s.compression.refs_fraction // 0),
          bake_s: $b.seconds, peak_rss_mib: $b.peak_rss_mib,
          bytes_per_vertex: ($s.bytes_apart_geometry_per_vertex // $s.scattering_bytes_per_vertex),
          file_bytes_per_vertex: $s.bytes_per_vertex, ratio_vs_8bit: $s.ratio_vs_8bit,
          vertex_rel_rms: $e.vertex_error.rel_rms_all, vertex_rms: $e.vertex_error.rms_all,
          image: $e.image_error, backlit: $back,
          cpu_scatter_ms: $c.scatter_ms_median, cpu_frame_ms: $c.frame_ms_median, cpu_fps: $c.fps,
          gpu_scatter_ms: $g.scatter_ms_median, gpu_frame_ms: $g.frame_ms_median, gpu_fps: $g.fps,
          gl_renderer: $g.renderer }' >> "$DATA/results.jsonl"
    done
  done < "$OUT/manifest.tsv"
  jq -r -s '(["id","mesh","study","interp","mm_per_unit","vertices","directions","quant","eps","sh_order","refs","refs_fraction",
     "near_radius_mm","near_entries_per_vertex",
     "bake_total_s","bake_neighbourhoods_s","bake_visibility_s","bake_integrals_s","bake_quantise_s","bake_compress_s",
     "peak_rss_mib","bytes_per_vertex","ratio_vs_8bit","vertex_rel_rms","vertex_rms","image_rms_max","image_rms_mean",
     "image_rms_median","image_exposure","backlit_rms_max","backlit_rms_mean",
     "cpu_scatter_ms","cpu_frame_ms","gpu_scatter_ms","gpu_frame_ms"] | @csv),
    (.[] | [.id,.mesh,.study,.interp,.mm_per_unit,.vertices,.directions,.quant,.eps,.sh_order,.refs,.refs_fraction,
     .near_radius_mm,.near_entries_per_vertex,
     .bake_s.total,.bake_s.neighbourhoods,.bake_s.visibility,.bake_s.integrals,.bake_s.quantise,.bake_s.compress,
     .peak_rss_mib,.bytes_per_vertex,.ratio_vs_8bit,.vertex_rel_rms,.vertex_rms,.image.rms_max,.image.rms_mean,
     .image.rms_median,.image.exposure,.backlit.rms_max,.backlit.rms_mean,
     .cpu_scatter_ms,.cpu_frame_ms,.gpu_scatter_ms,.gpu_frame_ms] | @csv)' \
    "$DATA/results.jsonl" > "$DATA/results.csv"
}

if [ "$REPORT_ONLY" = 1 ]; then
  [ -s "$DATA/results.jsonl" ] || { echo "accuracy_study: REPORT_ONLY=1 needs $DATA/results.jsonl (none there)" >&2; exit 1; }
else
  : > "$OUT/manifest.tsv.new"
  configs_$SERIES
  mv "$OUT/manifest.tsv.new" "$OUT/manifest.tsv"
  log "frame times"
  frame_times
  log "collecting"
  collect
  # the run, as measured (not when the page is drawn again, nor when every
  # bake was already there; REV names the build when it is not this tree's)
  [ "$MEASURED" = 0 ] || { echo "date $(date -u +%Y-%m-%d)"
    echo "commit ${REV:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet HEAD 2>/dev/null || echo ' plus uncommitted changes')}"
    echo "cpu $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(nproc) cores"
    echo "wall $(( ($(date +%s) - T0 + 30) / 60 )) min, FULL=$FULL, VIEWS=$VIEWS"; } > "$DATA/last_run.txt"
fi
. "$(dirname "$0")/accuracy_report_$SERIES.sh"
log "wrote $DATA/results.csv, $DATA/*.png|svg, $DOC"
