#!/usr/bin/env bash
# Bake at scale (docs/benchmarks.md, "Bake at scale"): the Stanford dragon at 5,205 / 22,998 / 100,250 /
# 437,645 vertices, each scaled so that its longest bounding-box side is
# 200 mm, marble (RGB) and a grey marble (mono: sigma_a 0.0041, sigma'_s
# 2.62 /mm, one channel), 200 directions: bake time per phase and peak
# memory for the hierarchical gather (sss-bake --gather tree) and the direct
# sum (--gather direct), the fitted scaling exponent, and sgemm's own peak.
#
#   tests/bench/bake_scale.sh [BUILD] [REPEAT] [OUT.jsonl] [SIZES] [DIRECT_MAX]
#
# The direct bake is run whole up to DIRECT_MAX vertices (default 25000);
# above that it would take hours and more memory than the machine has, and
# its time is estimated by gather_compare from every STRIDE-th vertex
# (neighbourhood search + weights + integrals for the subset, × nv/subset),
# which also gives the tree's error on that subset. Medians of REPEAT runs.
# Needs data/fetch.sh and python3.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${1:-build}
REPEAT=${2:-3}
OUT=${3:-out/bench_scale.jsonl}
SIZES=${4:-"5205 22998 100250 437645"}
DIRECT_MAX=${5:-25000}
mkdir -p "$(dirname "$OUT")" out
: > "$OUT"
BAKE=$BUILD/precompute/sss-bake
CMP=$BUILD/tests/bench/gather_compare
# mm per unit that makes the longest side of a PLY 200 mm
mm_per_unit() {
  python3 - "$1" <<'PY'
import sys
f = open(sys.argv[1], 'rb')
nv = 0
fmt = ''
while True:
    l = f.readline().decode().strip()
    if l.startswith('format'): fmt = l.split()[1]
    if l.startswith('element vertex'): nv = int(l.split()[2])
    if l == 'end_header': break
assert fmt == 'ascii', 'bake_scale.sh reads ascii PLY headers only'
lo = [1e30] * 3; hi = [-1e30] * 3
for _ in range(nv):
    p = list(map(float, f.readline().split()[:3]))
    for a in range(3): lo[a] = min(lo[a], p[a]); hi[a] = max(hi[a], p[a])
print('%.6f' % (200.0 / max(hi[a] - lo[a] for a in range(3))))
PY
}
OMP_NUM_THREADS=2 "$BUILD/tests/bench/sgemm_peak" 1000 1000 1000 10 | sed 's/^{/{"sgemm_peak":1,/' >> "$OUT"
OMP_NUM_THREADS=1 "$BUILD/tests/bench/sgemm_peak" 1000 1000 1000 10 | sed 's/^{/{"sgemm_peak":1,/' >> "$OUT"
for n in $SIZES; do
  mesh=data/stanford/dragon_$n.ply
  [ -f "$mesh" ] || { echo "bench: $mesh missing (data/fetch.sh)" >&2; continue; }
  s=$(mm_per_unit "$mesh")
  for ch in rgb mono; do
    if [ $ch = rgb ]; then mat=(--material marble); else mat=(--sigma-a 0.0041,0.0041,0.0041 --sigma-s 2.62,2.62,2.62); fi
    gathers="tree"
    [ "$n" -le "$DIRECT_MAX" ] && gathers="tree direct"
    for g in $gathers; do
      for r in $(seq "$REPEAT"); do
        /usr/bin/time -f '%e' -o out/bench_scale.wall "$BAKE" "$mesh" -o out/bench_scale.sss "${mat[@]}" --mm-per-unit "$s" \
          --dirs 200 --gather $g --threads 2 --json -q |
          python3 -c "import json,sys; d=json.load(sys.stdin); d['wall_s']=float(open('out/bench_scale.wall').read().split()[-1]); d['size']=$n; d['ch']='$ch'; print(json.dumps(d))" >> "$OUT"
        echo "bench: $n $ch $g run $r done" >&2
      done
    done
    if [ "$n" -gt "$DIRECT_MAX" ]; then
      stride=$(( n / 1000 ))
      grey=""; [ $ch = mono ] && grey=grey
      # gather_compare takes a preset; its grey is marble's green channel, as above
      "$CMP" "$mesh" marble "$s" 200 "0.4" "$stride" $grey |
        python3 -c "import json,sys; d=json.loads(sys.stdin.readline()); d['size']=$n; d['ch']='$ch'; d['direct_estimate']=1; print(json.dumps(d))" >> "$OUT"
      echo "bench: $n $ch direct estimate done" >&2
    fi
  done
done
python3 - "$OUT" <<'PY'
import json, math, statistics, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
peak = [r for r in rows if r.get('sgemm_peak')]
for p in peak:
    print(f"sgemm peak ({p['M']}x{p['N']}x{p['K']}), {p['threads']} thread(s): {p['gflops_total']:.1f} GFLOP/s"
          + (f", {p['gflops_per_thread_cpu']:.1f} per thread by CPU time" if 'gflops_per_thread_cpu' in p else ""))
bakes = [r for r in rows if 'gather' in r and 'seconds' in r]
est = {(r['size'], r['ch']): r for r in rows if r.get('direct_estimate')}
groups = {}
for r in bakes:
    groups.setdefault((r['size'], r['ch'], r['gather']), []).append(r)
med = lambda rs, f: statistics.median(f(r) for r in rs)
print()
print("| vertices | ch | gather | runs | import s | neighbourhoods s | visibility s | tree s | integrals s | write s | total s | wall s | peak RSS MiB | predicted MiB | sgemm GFLOP/s | dense blocks GFLOP/s | rows/block | far nodes/vertex |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for (n, ch, g), rs in sorted(groups.items()):
    t = lambda k: med(rs, lambda r: r['seconds'].get(k, 0.0))
    tree = g == 'tree'
    print(f"| {rs[0]['vertices']:,} | {ch} | {g} | {len(rs)} | {t('import'):.2f} | {t('neighbourhoods'):.2f} | {t('visibility'):.2f} | "
          f"{t('tree'):.2f} | {t('integrals'):.2f} | {t('write'):.2f} | {t('total'):.2f} | {med(rs, lambda r: r['wall_s']):.2f} | "
          f"{med(rs, lambda r: r['peak_rss_mib']):.0f} | {med(rs, lambda r: r['predicted_peak_mib']):.0f} | "
          f"{med(rs, lambda r: r['gather_gflops']):.1f} | {med(rs, lambda r: r.get('near_gflops', 0.0)):.1f} | "
          f"{rs[0].get('rows_per_block', 0):.0f} | {rs[0].get('far_nodes_per_vertex', 0):.1f} |")
print()
print("Direct sum estimated from a subset of receivers (gather_compare):")
print("| vertices | ch | subset | mean neighbours | direct s (subset) | direct s (estimated, all) | tree gather s | error RMS per vertex | max |")
print("|---|---|---|---|---|---|---|---|---|")
for (n, ch), e in sorted(est.items()):
    print(f"| {e['vertices']:,} | {ch} | {e['subset']} | {e['neighbours_mean']:.0f} | {e['t_direct_subset']:.1f} | {e['t_direct_est']:.0f} | "
          f"{e['t_tree'] + e['t_gather']:.1f} | {e['rel_rms_per_vertex']:.2e} | {e['rel_max']:.2e} |")
# scaling exponents: time(nv) ~ nv^p, least squares on logs
def fit(pts):
    if len(pts) < 2: return float('nan')
    xs = [math.log(a) for a, _ in pts]; ys = [math.log(b) for _, b in pts]
    mx = sum(xs) / len(xs); my = sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
print()
for ch in ('rgb', 'mono'):
    tp = [(rs[0]['vertices'], med(rs, lambda r: r['seconds'].get('tree', 0) + r['seconds']['integrals']))
          for (n, c, g), rs in sorted(groups.items()) if c == ch and g == 'tree']
    dp = [(rs[0]['vertices'], med(rs, lambda r: r['seconds']['neighbourhoods'] + r['seconds']['integrals']))
          for (n, c, g), rs in sorted(groups.items()) if c == ch and g == 'direct']
    dp += [(e['vertices'], e['t_direct_est']) for (n, c), e in sorted(est.items()) if c == ch]
    print(f"{ch}: tree (tree + integrals) time ~ N^{fit(tp):.2f}; direct (neighbourhoods + integrals) ~ N^{fit(dp):.2f}")
PY
