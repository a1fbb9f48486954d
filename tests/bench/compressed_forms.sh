#!/usr/bin/env bash
# Per-frame cost of the compressed forms against lloyd8 (docs/benchmarks.md,
# "Compressed forms' per-frame cost"): the 100K dragon at 20 cm, marble,
# every term baked, stored as lloyd8, SH-only (order 3 linear8 and lloyd4,
# order 7 linear16: the paper's §4.1 storage) and references + SH deltas
# (the paper's 3 % with linear8 codes, the compact preset's settings), all
# compressed from one float bake so that only the storage differs.
#   tests/bench/compressed_forms.sh OUTDIR [ROUNDS] [BUILD...]
# A BUILD that cannot read a file (an older one, before 16-bit codes)
# shows "—" there. Each round runs every file on every BUILD (default: build) in turn, so
# that builds and forms share the machine's load; printed: the median over
# the rounds of sss-view's scatter median (--offscreen --bench 15 --size
# 64x64, GPU path and --cpu path) and of decode_bench's one-thread decode,
# with the data in cache and with 64 MiB written between frames (--evict
# 64: the caches emptied, as the viewer's draw empties them).
# OMP_NUM_THREADS=1 (THREADS=N for N): on a loaded machine OpenMP's spinning threads, not the
# decode, set the CPU path's time (docs/benchmarks.md).
# Needs data/fetch.sh, python3.
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:?usage: compressed_forms.sh OUTDIR [ROUNDS] [BUILD...]}
ROUNDS=${2:-3}
shift $(($# < 2 ? $# : 2))
BUILDS=("$@")
[ ${#BUILDS[@]} -gt 0 ] || BUILDS=(build)
mkdir -p "$OUT"
B=${BUILDS[0]}
MESH=data/stanford/dragon_100250.ply
ARGS=(--material marble --mm-per-unit 976.13 --own-term baked --weights point -q)   # 20 cm long
for q in float lloyd8; do
  [ -f "$OUT/d100_$q.sss" ] || "$B/precompute/sss-bake" "$MESH" -o "$OUT/d100_$q.sss" --quant "$q" "${ARGS[@]}"
done
form() { # name order fraction options...
  local name=$1; shift
  [ -f "$OUT/$name.sss" ] || "$B/tests/bench/compress_bench" "$OUT/d100_float.sss" "$@" --dirs 2 --out "$OUT/$name.sss" >/dev/null
}
form sh3_linear8 3 0 --kind linear8
form sh3_lloyd4 3 0 --kind lloyd4
form sh7_linear16 7 0 --kind linear16
form refs_paper 3 0.03 --kind linear8
form refs_compact 3 0.01 --kind lloyd4 --wbits 8 --ls --illum 0.001
FILES=(d100_lloyd8 sh3_linear8 sh3_lloyd4 sh7_linear16 refs_paper refs_compact)
export OMP_NUM_THREADS=${THREADS:-1}
: > "$OUT/forms.tsv"
for ((r = 0; r < ROUNDS; r++)); do
  for b in "${BUILDS[@]}"; do
    for f in "${FILES[@]}"; do
      for path in gpu cpu; do
        a=(); [ $path = cpu ] && a=(--cpu)
        ms=$("$b/runtime/sss-view" "$OUT/$f.sss" --offscreen --bench 15 --size 64x64 "${a[@]}" |
             python3 -c 'import json,sys; print(json.load(sys.stdin)["scatter_ms_median"])') || ms=nan
        printf '%s\t%s\t%s\t%s\n' "$b" "$f" "$path" "$ms" >> "$OUT/forms.tsv"
      done
      for ev in 0 64; do
        ms=$("$b/tests/bench/decode_bench" --decode-only 30 --evict $ev "$OUT/$f.sss" | awk '{print $3}') || ms=nan
        [ -n "$ms" ] || ms=nan
        col=decode1t; [ $ev = 0 ] || col=decode1t_evict
        printf '%s\t%s\t%s\t%s\n' "$b" "$f" $col "$ms" >> "$OUT/forms.tsv"
      done
    done
  done
  echo "compressed_forms: round $((r + 1)) of $ROUNDS" >&2
done
python3 - "$OUT/forms.tsv" "${BUILDS[@]}" <<'PY'
import statistics, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
builds = sys.argv[2:]
files = list(dict.fromkeys(r[1] for r in rows))
med = {}
for b, f, p, ms in rows:
    med.setdefault((b, f, p), []).append(float(ms))
m = {k: statistics.median(v) for k, v in med.items()}
cols = [(b, p) for p in ("gpu", "cpu", "decode1t", "decode1t_evict") for b in builds]
name = {"gpu": "GPU path (llvmpipe) scatter", "cpu": "CPU path scatter", "decode1t": "sss_decode_all, 1 thread",
        "decode1t_evict": "the same, caches evicted"}
print("| form | " + " | ".join(f"{name[p]}, ms ({b})" for b, p in cols) + " |")
print("|---|" + "---|" * len(cols))
for f in files:
    cells = []
    for b, p in cols:
        x, ref = m[(b, f, p)], m[(b, "d100_lloyd8", p)]
        cells.append("—" if x != x else f"{x:.2f} ({x / ref:.1f}×)")
    print(f"| {f} | " + " | ".join(cells) + " |")
PY
