#!/usr/bin/env bash
# The viewer on a real GPU (docs/benchmarks.md, "On an NVIDIA GPU"): one
# prepared, unattended run on a machine that has an NVIDIA GPU and none of
# our Debian packages, no network and a few minutes of use.
#
#   tests/bench/gpu_bench.sh pack [BUILD] [PREBAKED.sss...]   # here
#   tests/bench/gpu_bench.sh run OUTDIR [BUDGET_S]            # there
#   tests/bench/gpu_bench.sh report OUTDIR                    # here
#   tests/bench/gpu_bench.sh shell OUTDIR CMD...              # there: CMD in run's set-up
#   tests/bench/gpu_bench.sh schemes OUTDIR [ROUNDS [BUDGET_S]] # there: the compressed forms' SH tables
#   tests/bench/gpu_bench.sh report-schemes OUTDIR            # here: their rows
#   tests/bench/gpu_bench.sh ab OUTDIR ROUNDS VIEWER_A VIEWER_B [MESH]  # there: two viewers side by side
#
# pack (on the machine that built BUILD, default build/): writes
#   .gpubench/bundle.tar.xz (git-ignored, under 64 MiB): BUILD's programs and
#   ctest files, stripped; every shared library they load except the C
#   library's own (libstdc++ and libgcc_s apart, used only where the other
#   machine has none); the GL loaders (libglvnd), used only where it has none;
#   data/stanford's meshes; and PREBAKED files (the 437,645-vertex dragon at
#   the defaults takes minutes of baking: bring it baked).
# run (there, from a copy of this repository holding .gpubench/): unpacks
#   the bundle, points the GL loader at the NVIDIA driver, then, while
#   BUDGET_S (default 420) lasts, each step under its own timeout and
#   skipped when too little time is left:
#     1. the GPU and driver (nvidia-smi) and the GL renderer sss-view gets;
#     2. the render tests (ctest -L render) on the NVIDIA driver through EGL,
#        with the files the whole run times baked meanwhile on the CPUs;
#     3. the GPU's memory bandwidth (a device-to-device copy through python3's
#        torch, when it has it: the bound of every scatter row);
#     4. scatter evaluation and whole frame at 1920x1080 (sss-view --offscreen
#        --bench: wall clock after glFinish, and GL timer queries), GPU and
#        CPU paths, for the dragon at 100,250 and 437,645 vertices (20 cm),
#        mono and RGB, lloyd8 and float, and the PREBAKED files (default
#        near terms by rays and by shadow map);
#     5. the compressed forms against lloyd8 (the 100K dragon, as
#        compressed_forms.sh makes them);
#     6. Table I (table1.sh: its models and stand-ins, both paths, with and
#        without scattering, bakes on every core);
#     7. the scene effects (scene_effects.sh), single scattering per pixel
#        (single_gpu.sh).
#   OUTDIR gets results.jsonl (one JSON object a measurement), log.txt,
#   ctest.txt, bakes.txt, the tables of steps 6-7 and a 1920x1080 image of
#   each PREBAKED file lit from behind.
#   GPU_BENCH_ANY_GL=1 goes on without an NVIDIA renderer (to try the script
#   here, on llvmpipe).
# report: the Markdown tables of OUTDIR/results.jsonl.
set -uo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
MODE=${1:?usage: gpu_bench.sh pack [BUILD] [PREBAKED...] | run OUTDIR [BUDGET_S] | report OUTDIR | shell OUTDIR CMD...}
shift

pack() {
  set -e
  local B=${1:-build}; shift || true
  local S=.gpubench/stage
  rm -rf .gpubench && mkdir -p $S/build $S/lib $S/libcxx $S/glvnd $S/data $S/pre
  # programs, shared objects and ctest files of BUILD, not its objects
  (cd "$B" && find . -path '*/CMakeFiles' -prune -o -type f \
     \( -name CTestTestfile.cmake -o -name '*.so*' -o -perm -u+x \) -print) |
    while read -r f; do mkdir -p "$S/build/$(dirname "$f")"; cp -p "$B/$f" "$S/build/$f"; done
  find $S/build -type f -perm -u+x -exec sh -c 'file -b "$1" | grep -q ELF && strip --strip-unneeded "$1"' _ {} \;
  # every library they load, but the C library's own
  find $S/build -type f -exec sh -c 'file -b "$1" | grep -q ELF && ldd "$1"' _ {} \; 2>/dev/null |
    awk '$2 == "=>" && $3 ~ /^\// {print $3}' | sort -u | while read -r l; do
      case $(basename "$l") in
        libc.so*|libm.so*|libdl.so*|libpthread.so*|librt.so*|ld-linux*|libresolv.so*) ;;
        libstdc++.so*|libgcc_s.so*) cp -L "$l" $S/libcxx/ ;;
        libEGL.so*|libGL.so*|libGLX.so*|libOpenGL.so*|libGLdispatch.so*|libGLESv2.so*) ;;
        *) cp -L "$l" $S/lib/ ;;
      esac
    done
  for l in libEGL.so.1 libGLdispatch.so.0 libOpenGL.so.0 libGLX.so.0 libGL.so.1 libGLESv2.so.2; do
    cp -L "$(ldconfig -p | awk -v l="$l" '$1 == l && /x86-64/ {print $NF; exit}')" $S/glvnd/
  done
  cp -p data/stanford/*.ply $S/data/
  for f in "$@"; do cp -p "$f" $S/pre/; done
  (cd $S && tar -cf - .) | xz -9 -T0 > .gpubench/bundle.tar.xz
  rm -rf $S
  ls -l .gpubench/bundle.tar.xz
}

# --- run ---------------------------------------------------------------
T0=$(date +%s)
left() { echo $((BUDGET - ($(date +%s) - T0))); }
log() { echo "[$(($(date +%s) - T0)) s] $*" | tee -a "$OUT/log.txt" >&2; }
# json KIND NAME JSON: one line of results.jsonl
json() { printf '{"kind":"%s","name":"%s","data":%s}\n' "$1" "$2" "${3:-null}" >> "$OUT/results.jsonl"; }
# step NEED_S TIMEOUT_S cmd...: cmd under a timeout, when NEED_S seconds are left
step() {
  local need=$1 lim=$2; shift 2
  if [ "$(left)" -lt "$need" ]; then log "skipped (time): $*"; return 99; fi
  local l; l=$(left); [ "$lim" -le "$l" ] || lim=$l
  timeout -k 5 "$lim" "$@"
}
view() { # NAME FILE ARGS...: one sss-view --bench row
  local n=$1 f=$2; shift 2
  local r; r=$(step 20 "${VT:-90}" build/runtime/sss-view "$f" --offscreen "$@" 2>>"$OUT/log.txt")
  if [ -n "$r" ]; then json view "$n" "$r"; log "view $n $*: $(echo "$r" | python3 -c 'import json,sys; d=json.load(sys.stdin); print("scatter %.3f ms, frame %.3f ms" % (d["scatter_ms_median"], d["frame_ms_median"]))' 2>/dev/null)"
  else log "view $n $*: no result"; fi
}

# the bundle unpacked and the environment pointed at it and at the driver
setup() {
  X=$ROOT/.gpubench/x
  log "unpacking"
  rm -rf "$X" && mkdir -p "$X"
  python3 -c 'import sys, tarfile; tarfile.open(sys.argv[1]).extractall(sys.argv[2])' .gpubench/bundle.tar.xz "$X" || { log "unpack failed"; return 1; }
  # the build's absolute paths are /work/main/...: point them here
  [ "$ROOT" = /work/main ] || { mkdir -p /work && ln -sfn "$ROOT" /work/main; }
  [ -e build ] || ln -s "$X/build" build
  mkdir -p data/stanford && cp --update=none "$X"/data/*.ply data/stanford/ 2>/dev/null || cp -n "$X"/data/*.ply data/stanford/
  local LP=$X/lib
  ldconfig -p | grep -q 'libstdc++.so.6 ' || LP=$LP:$X/libcxx
  ldconfig -p | grep -q 'libEGL.so.1 ' || LP=$LP:$X/glvnd
  for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do [ -d $d ] && LP=$LP:$d; done
  export LD_LIBRARY_PATH=$LP${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  local vj=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
  [ -f /usr/share/glvnd/egl_vendor.d/10_nvidia.json ] || [ ! -f $vj ] || export __EGL_VENDOR_LIBRARY_FILENAMES=$vj
  NT=$(nproc)
  export OMP_NUM_THREADS=$NT
  log "threads $NT, LD_LIBRARY_PATH=$LD_LIBRARY_PATH"
}

run() {
  OUT=${1:?run OUTDIR}; BUDGET=${2:-420}
  mkdir -p "$OUT"; : > "$OUT/results.jsonl"; : > "$OUT/log.txt"
  setup || return 1

  # 1. the machine
  local smi; smi=$(nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,clocks.max.mem --format=csv,noheader 2>&1 | head -1)
  json machine gpu "$(python3 -c 'import json,sys; print(json.dumps(sys.argv[1]))' "$smi")"
  json machine cpu "$(python3 -c 'import json,sys; print(json.dumps(sys.argv[1]))' "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //') x $NT")"
  log "gpu: $smi"
  local W=$X/work; mkdir -p "$W"
  local BK=(build/precompute/sss-bake) GEN=build/data/sss-genmesh
  local G=(--sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62)   # marble's green channel, grey (table1.sh)
  step 30 30 $GEN sphere 2 "$W/s.ply" >/dev/null 2>&1 && step 30 60 "${BK[@]}" "$W/s.ply" -o "$W/s.sss" --mm-per-unit 10 --dirs 50 -q 2>>"$OUT/log.txt"
  view smoke "$W/s.sss" --bench 3 --size 256x256
  if [ -z "${GPU_BENCH_ANY_GL:-}" ] && ! grep -q '"name":"smoke".*NVIDIA' "$OUT/results.jsonl"; then
    # no NVIDIA GL: say what the loader saw and stop, leaving the time for a second try
    { echo "== no NVIDIA renderer"; ldd build/runtime/sss-view | grep -v "$X/lib"; ls -l /usr/local/nvidia/lib64 2>&1 | grep -iE 'egl|glx|gl_' | head
      ls /usr/share/glvnd/egl_vendor.d /usr/local/nvidia/share/glvnd/egl_vendor.d 2>&1; env | grep -E 'EGL|NVIDIA|LD_' ; } >> "$OUT/log.txt" 2>&1
    return 3
  fi

  # 2. render tests, with the bakes of steps 4-5 on the CPUs meanwhile
  local L20=(--mm-per-unit 976.13 --own-term baked --weights point -q)   # the dragons at 20 cm, every term baked
  (
    for m in 100250:d100 437645:d437; do
      IFS=: read -r nv n <<<"$m"
      for c in mono rgb; do
        a=(--material marble); [ $c = mono ] && a=("${G[@]}")
        timeout 200 "${BK[@]}" data/stanford/dragon_$nv.ply -o "$W/${n}_${c}_l8.sss" --quant lloyd8 "${a[@]}" "${L20[@]}"
      done
    done
    timeout 200 "${BK[@]}" data/stanford/dragon_100250.ply -o "$W/d100_rgb_f32.sss" --quant float --material marble "${L20[@]}"
    B=build/tests/bench/compress_bench
    timeout 100 $B "$W/d100_rgb_f32.sss" 3 0 --kind linear8 --dirs 2 --out "$W/sh3_linear8.sss"
    timeout 100 $B "$W/d100_rgb_f32.sss" 3 0 --kind lloyd4 --dirs 2 --out "$W/sh3_lloyd4.sss"
    timeout 100 $B "$W/d100_rgb_f32.sss" 7 0 --kind linear16 --dirs 2 --out "$W/sh7_linear16.sss"
    timeout 150 $B "$W/d100_rgb_f32.sss" 3 0.03 --kind linear8 --dirs 2 --out "$W/refs_paper.sss"
    timeout 150 $B "$W/d100_rgb_f32.sss" 3 0.01 --kind lloyd4 --wbits 8 --ls --illum 0.001 --dirs 2 --out "$W/refs_compact.sss"
    timeout 200 "${BK[@]}" data/stanford/dragon_437645.ply -o "$W/d437_rgb_f32.sss" --quant float --material marble "${L20[@]}"
  ) > "$OUT/bakes.txt" 2>&1 &
  local bakes=$!
  log "render tests"
  step 60 150 ctest --test-dir build -L render -j 6 --timeout 120 --output-on-failure > "$OUT/ctest.txt" 2>&1
  json tests render "$(python3 - "$OUT/ctest.txt" <<'PY'
import json, re, sys
t = open(sys.argv[1], errors='replace').read()
r = {'passed': re.findall(r'Test +#\d+: (\S+) \.+ +Passed', t), 'failed': re.findall(r'Test +#\d+: (\S+) \.+\**\s*(?:Failed|\*\*\*|Exception|Timeout|Not Run)', t)}
m = re.search(r'(\d+)% tests passed, (\d+) tests failed out of (\d+)', t)
r['summary'] = m.group(0) if m else 'none'
print(json.dumps(r))
PY
)"
  log "render tests: $(grep -E 'tests passed' "$OUT/ctest.txt")"
  log "waiting for the bakes"
  while kill -0 $bakes 2>/dev/null && [ "$(left)" -gt 200 ]; do sleep 2; done
  # a bake still running past the budget: its timeout (which ends the bake
  # with it) and then the list
  pkill -P $bakes 2>/dev/null; kill $bakes 2>/dev/null; wait $bakes 2>/dev/null
  ls -l "$W"/*.sss >> "$OUT/log.txt"

  # 3. bandwidth
  local bw; bw=$(step 60 60 python3 - <<'PY' 2>>"$OUT/log.txt"
import json, torch
n = 1 << 30                       # 4 GiB of floats: far beyond the 60 MB L2
a = torch.empty(n, device='cuda'); b = torch.empty_like(a); a.fill_(1.0)
def t(f, k=10):
    f(); torch.cuda.synchronize()
    s, e = torch.cuda.Event(enable_timing=True), torch.cuda.Event(enable_timing=True)
    v = []
    for _ in range(k):
        s.record(); f(); e.record(); torch.cuda.synchronize(); v.append(s.elapsed_time(e) / 1e3)
    return sorted(v)[k // 2]
copy = 2 * 4 * n / t(lambda: b.copy_(a)) / 1e9
read = 4 * n / t(lambda: a.sum()) / 1e9
print(json.dumps({"copy_GBps": copy, "read_GBps": read, "device": torch.cuda.get_device_name()}))
PY
)
  [ -n "$bw" ] && json bandwidth torch "$bw"; log "bandwidth: $bw"

  # 4. scatter and frame at 1920x1080
  local HD=(--size 1920x1080)
  # the PREBAKED files first (the defaults: the frame the targets name); the
  # image is the last bench frame's, the light beside the view, seen from behind
  for f in "$X"/pre/*.sss; do
    [ -f "$f" ] || continue
    n=$(basename "$f" .sss)
    VT=150 view "$n/gpu" "$f" --bench 30 "${HD[@]}" --view -0.5,0.15,-1 --exposure 2 --out "$OUT/$n.png"
    VT=150 view "$n/gpu_map" "$f" --bench 30 "${HD[@]}" --near-visibility map
    VT=150 view "$n/cpu" "$f" --bench 3 "${HD[@]}" --cpu
  done
  for n in d100_mono_l8 d100_rgb_l8 d437_mono_l8 d437_rgb_l8 d100_rgb_f32 d437_rgb_f32; do
    [ -f "$W/$n.sss" ] || { log "$n: not baked"; continue; }
    view "$n/gpu" "$W/$n.sss" --bench 30 "${HD[@]}"
    view "$n/cpu" "$W/$n.sss" --bench 10 "${HD[@]}" --cpu
  done
  # 5. compressed forms (GPU path, and the CPU path on every core)
  for n in d100_rgb_l8 sh3_linear8 sh3_lloyd4 sh7_linear16 refs_paper refs_compact; do
    [ -f "$W/$n.sss" ] || { log "$n: not made"; continue; }
    view "forms/$n/gpu" "$W/$n.sss" --bench 30 "${HD[@]}"
    view "forms/$n/cpu" "$W/$n.sss" --bench 15 --size 64x64 --cpu
  done

  # 6. Table I on the GPU path (table1.sh's models; lloyd8 and the paper preset)
  if [ "$(left)" -gt 120 ]; then
    log "table I"
    step 120 $(( $(left) - 60 )) env THREADS=$NT bash tests/bench/table1.sh build "$W/t1" 10 "horse teapot dragon buddha" > "$OUT/table1.md" 2>>"$OUT/log.txt"
    [ -f "$W/t1/table1.jsonl" ] && while read -r l; do json table1 row "$l"; done < "$W/t1/table1.jsonl"
  fi
  # 7. scene effects, single scattering
  step 60 90 env THREADS=$NT bash tests/bench/scene_effects.sh build > "$OUT/scene_effects.md" 2>>"$OUT/log.txt"
  step 30 60 bash tests/bench/single_gpu.sh "$W/single" 10 > "$OUT/single_gpu.md" 2>>"$OUT/log.txt"
  log "done, $(left) s of the budget left"
}

# The compressed forms' SH tables on the GPU (docs/viewer.md, "SH tables
# on the GPU"): the render tests on the driver (both ways against the C
# decoder, to the bit), then ROUNDS rounds of every form of step 5 with
# its tables as a uniform block and as a storage buffer, GPU path at
# 1920x1080 (FRAMES frames, default 30), with the CPU path (every core)
# and decode_bench's one-thread decode beside them (NOCPU=1: not); BIG=1
# adds the 437,645-vertex dragon's lloyd8 and reference forms.
schemes() {
  OUT=${1:?schemes OUTDIR [ROUNDS]}; local R=${2:-3}; BUDGET=${3:-400}
  mkdir -p "$OUT"; : > "$OUT/results.jsonl"; : > "$OUT/log.txt"
  setup || return 1
  local smi; smi=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>&1 | head -1)
  json machine gpu "$(python3 -c 'import json,sys; print(json.dumps(sys.argv[1]))' "$smi")"
  log "gpu: $smi"
  local W=${SCHEMES_WORK:-$X/work}; mkdir -p "$W"   # SCHEMES_WORK: files made before (a try here)
  local L20=(--material marble --mm-per-unit 976.13 --own-term baked --weights point -q)
  [ -f "$W/refs_compact.sss" ] || (
    timeout 200 build/precompute/sss-bake data/stanford/dragon_100250.ply -o "$W/d100_rgb_f32.sss" --quant float "${L20[@]}"
    timeout 200 build/precompute/sss-bake data/stanford/dragon_100250.ply -o "$W/d100_rgb_l8.sss" --quant lloyd8 "${L20[@]}" &
    B=build/tests/bench/compress_bench
    timeout 100 $B "$W/d100_rgb_f32.sss" 3 0 --kind linear8 --dirs 2 --out "$W/sh3_linear8.sss" &
    timeout 100 $B "$W/d100_rgb_f32.sss" 3 0 --kind lloyd4 --dirs 2 --out "$W/sh3_lloyd4.sss" &
    timeout 100 $B "$W/d100_rgb_f32.sss" 7 0 --kind linear16 --dirs 2 --out "$W/sh7_linear16.sss" &
    timeout 150 $B "$W/d100_rgb_f32.sss" 3 0.03 --kind linear8 --dirs 2 --out "$W/refs_paper.sss" &
    timeout 150 $B "$W/d100_rgb_f32.sss" 3 0.01 --kind lloyd4 --wbits 8 --ls --illum 0.001 --dirs 2 --out "$W/refs_compact.sss" &
    wait
    # BIG=1: the 437,645-vertex dragon's lloyd8 and reference forms too
    [ -n "${BIG:-}" ] || exit 0
    timeout 200 build/precompute/sss-bake data/stanford/dragon_437645.ply -o "$W/d437_rgb_f32.sss" --quant float "${L20[@]}"
    timeout 200 build/precompute/sss-bake data/stanford/dragon_437645.ply -o "$W/d437_rgb_l8.sss" --quant lloyd8 "${L20[@]}" &
    timeout 200 $B "$W/d437_rgb_f32.sss" 3 0.03 --kind linear8 --dirs 2 --out "$W/d437_refs_paper.sss" &
    timeout 200 $B "$W/d437_rgb_f32.sss" 3 0.01 --kind lloyd4 --wbits 8 --ls --illum 0.001 --dirs 2 --out "$W/d437_refs_compact.sss" &
    wait
  ) > "$OUT/bakes.txt" 2>&1 &
  local bakes=$!
  log "render tests"
  [ -n "${BIG:-}" ] || step 60 150 ctest --test-dir build -L render -j 6 --timeout 120 --output-on-failure > "$OUT/ctest.txt" 2>&1
  log "render tests: $(grep -E 'tests passed' "$OUT/ctest.txt")"
  step 30 60 build/tests/render/test_render_single > "$OUT/render_single.txt" 2>&1; echo "exit $?" >> "$OUT/render_single.txt"
  step 30 90 build/tests/render/test_render > "$OUT/render.txt" 2>&1; echo "exit $?" >> "$OUT/render.txt"
  log "test_render_single: $(tail -1 "$OUT/render_single.txt"), test_render: $(tail -1 "$OUT/render.txt")"
  while kill -0 $bakes 2>/dev/null && [ "$(left)" -gt 200 ]; do sleep 1; done
  wait $bakes 2>/dev/null
  ls -l "$W"/*.sss >> "$OUT/log.txt"
  local HD=(--size 1920x1080) NB=${FRAMES:-30}
  for ((r = 0; r < R; r++)); do
    for n in d100_rgb_l8 sh3_linear8 sh3_lloyd4 sh7_linear16 refs_paper refs_compact d437_rgb_l8 d437_refs_paper d437_refs_compact; do
      [ -f "$W/$n.sss" ] || { log "$n: not made"; continue; }
      local sc=("")
      case $n in
        sh3_*|sh7_*|refs_*|d437_refs_*) sc=("" "--sh-tables uniform" "--sh-tables storage") ;;   # "": the default
      esac
      for a in "${sc[@]}"; do
        # shellcheck disable=SC2086
        view "schemes/$n/${a// /_}/r$r" "$W/$n.sss" --bench "$NB" "${HD[@]}" $a
      done
      [ -z "${NOCPU:-}" ] || continue   # NOCPU=1: the GPU path alone
      view "schemes/$n/cpu/r$r" "$W/$n.sss" --bench 15 --size 64x64 --cpu
      local ms; ms=$(OMP_NUM_THREADS=1 step 20 30 build/tests/bench/decode_bench --decode-only 30 --evict 64 "$W/$n.sss" | awk '{print $3}')
      json decode "schemes/$n/decode1t_evict/r$r" "${ms:-null}"
    done
  done
  log "done, $(left) s of the budget left"
}

report() {
  python3 - "${1:?report OUTDIR}/results.jsonl" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
get = lambda k, n: next((r['data'] for r in rows if r['kind'] == k and r['name'] == n), None)
print('GPU:', get('machine', 'gpu'), '; CPU:', get('machine', 'cpu'))
bw = get('bandwidth', 'torch')
print('bandwidth:', bw)
t = get('tests', 'render')
print('render tests:', t and t['summary'], 'failed:', t and t['failed'])
print()
# bytes a frame moves per vertex on the GPU path: the three directions'
# rows of an uncompressed file (one byte or float per channel each), every
# stored byte of a compressed one, and q written (a float per channel)
def moved(d):
    C = d['channels']
    read = {'lloyd8': 3 * C, 'float': 12 * C}.get(d['quant'], d['bytes_per_vertex'])
    return read + 4 * C
print('| file | vertices | ch | storage | path | B/vertex moved | scatter ms (GL timer) | near terms ms (GL timer) | bound ms | ratio | frame ms (fps) |')
print('|---|---|---|---|---|---|---|---|---|---|---|')
for r in rows:
    if r['kind'] != 'view' or r['name'] == 'smoke': continue
    d = r['data']
    gpu = d['path'] == 'gpu'
    bound = d['vertices'] * moved(d) / (bw['copy_GBps'] * 1e9) * 1e3 if bw and gpu else None
    print(f"| {r['name']} | {d['vertices']:,} | {d['channels']} | {d['storage']} | {d['path']} | {moved(d):.1f} | "
          f"{d['scatter_ms_median']:.3f} ({'%.3f' % d['gpu_timer_scatter_ms_last'] if gpu else '—'}) | "
          f"{'%.3f' % d['gpu_timer_own_ms_last'] if gpu and d['own_term'] != 'none' else '—'} | {'%.4f' % bound if bound else '—'} | "
          f"{'%.1f' % (d['scatter_ms_median'] / bound) if bound else '—'} | {d['frame_ms_median']:.2f} ({d['fps']:.0f}) |")
PY
}

# Two builds of the viewer side by side on one file baked there at the
# defaults (MESH: default the 100,250-vertex dragon at 20 cm, marble):
# ROUNDS rounds of each at 1920x1080, --bench 30, interleaved; rows named
# ab/VIEWER/rROUND. The near terms' GL timer is gpu_timer_own_ms_last.
ab() {
  OUT=${1:?ab OUTDIR ROUNDS VIEWER_A VIEWER_B [MESH]}; local R=$2 A=$3 B=$4 M=${5:-data/stanford/dragon_100250.ply}
  BUDGET=${BUDGET:-400}
  mkdir -p "$OUT"; : > "$OUT/results.jsonl"; : > "$OUT/log.txt"
  setup || return 1
  local W=$X/work; mkdir -p "$W"
  step 60 300 build/precompute/sss-bake "$M" -o "$W/ab.sss" --material marble --mm-per-unit 976.13 -q 2>>"$OUT/log.txt"
  log "baked: $(ls -l "$W/ab.sss" 2>&1)"
  for ((r = 0; r < R; r++)); do
    for v in "$A" "$B"; do
      local res; res=$(step 30 150 "$v" "$W/ab.sss" --offscreen --bench 30 --size 1920x1080 2>>"$OUT/log.txt")
      [ -n "$res" ] && json view "ab/$(basename "$v")/r$r" "$res"
      log "$(basename "$v") r$r: $(echo "$res" | python3 -c 'import json,sys; d=json.load(sys.stdin); print("scatter %.3f ms, near (GL) %.3f ms, frame %.3f ms" % (d["scatter_ms_median"], d["gpu_timer_own_ms_last"], d["frame_ms_median"]))' 2>/dev/null)"
    done
  done
  log "done, $(left) s of the budget left"
}

# the schemes' rows: medians over the rounds, ms
report_schemes() {
  python3 - "${1:?report-schemes OUTDIR}/results.jsonl" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
print('GPU:', next((r['data'] for r in rows if r['kind'] == 'machine'), None))
cell = {}
for r in rows:
    if not r['name'].startswith('schemes/') or r['data'] is None: continue
    _, form, scheme, _ = r['name'].split('/')
    cell.setdefault((form, scheme), []).append(r['data'])
med = lambda v: statistics.median(v) if v else float('nan')
print('| form | scheme | rounds | scatter ms, wall | submit ms | GL timer ms | frame ms |')
print('|---|---|---|---|---|---|---|')
for (form, scheme), v in cell.items():
    if scheme.startswith('decode'):
        print(f'| {form} | decode_bench, 1 thread, --evict 64 | {len(v)} | {med(v):.4f} | | | |'); continue
    name = 'CPU path, every core' if scheme == 'cpu' else ('default: ' if scheme == '' else '') + v[0]['scheme']
    print(f"| {form} | {name} | {len(v)} | "
          f"{med([d['scatter_ms_median'] for d in v]):.4f} | {med([d['scatter_submit_ms_median'] for d in v]):.4f} | "
          f"{med([d.get('gpu_timer_scatter_ms_median', d['gpu_timer_scatter_ms_last']) for d in v]):.4f} | "
          f"{med([d['frame_ms_median'] for d in v]):.3f} |")
PY
}

case $MODE in
  pack) pack "$@" ;;
  run) run "$@" ;;
  schemes) schemes "$@" ;;
  ab) ab "$@" ;;
  shell) OUT=${1:?shell OUTDIR CMD...}; shift; BUDGET=600; mkdir -p "$OUT"; : > "$OUT/log.txt"; setup && "$@" ;;
  report) report "$@" ;;
  report-schemes) report_schemes "$@" ;;
  *) echo "gpu_bench.sh: unknown mode '$MODE' (pack, run, report or shell)" >&2; exit 2 ;;
esac
