#!/usr/bin/env bash
# Bake-cost benchmark (docs/benchmarks.md): phases, peak memory, bytes/vertex and the
# Lloyd quantiser's SNR for one mesh at given scales, float and lloyd8,
# REPEAT runs each; prints a markdown table of medians and writes the raw
# JSON lines to OUT.jsonl.
#   tests/bench/bake_phases.sh MESH MATERIAL "SCALES" REPEAT OUT.jsonl
# Needs build/ (scripts/setup.sh) and python3.
set -euo pipefail
cd "$(dirname "$0")/../.."
MESH=${1:-data/stanford/dragon_100250.ply}
MAT=${2:-marble}
SCALES=${3:-"2000 4000"}
REPEAT=${4:-3}
OUT=${5:-out/bench_bake.jsonl}
mkdir -p "$(dirname "$OUT")" out
: > "$OUT"
for s in $SCALES; do
  for q in float lloyd8; do
    for r in $(seq "$REPEAT"); do
      build/precompute/sss-bake "$MESH" -o out/bench.sss --material "$MAT" --mm-per-unit "$s" \
        --dirs 200 --quant "$q" --threads 2 --json -q >> "$OUT"
      echo "bench: $s mm/unit $q run $r done" >&2
    done
  done
done
python3 - "$OUT" <<'PY'
import json, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
groups = {}
for r in rows:
    groups.setdefault((r["mm_per_unit"], r["quant"]), []).append(r)
def med(rs, f): return statistics.median(f(r) for r in rs)
print("| mm/unit | storage | runs | mean neighbours | import s | neighbourhoods s | visibility s | integrals s | quantise s | write s | total s | peak RSS MiB | file B/vertex | integrals B/vertex | Lloyd SNR dB |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for (s, q), rs in sorted(groups.items()):
    t = lambda k: med(rs, lambda r: r["seconds"][k])
    snr = "%.2f" % med(rs, lambda r: r["lloyd_snr_db"]) if q == "lloyd8" else "—"
    print(f"| {s:g} | {q} | {len(rs)} | {rs[0]['neighbours_mean']:.0f} | {t('import'):.2f} | {t('neighbourhoods'):.2f} | "
          f"{t('visibility'):.2f} | {t('integrals'):.2f} | {t('quantise'):.2f} | {t('write'):.2f} | {t('total'):.2f} | "
          f"{med(rs, lambda r: r['peak_rss_mib']):.0f} | {rs[0]['bytes_per_vertex']:.1f} | {rs[0]['integral_bytes_per_vertex']:.1f} | {snr} |")
PY
