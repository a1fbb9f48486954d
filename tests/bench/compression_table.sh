#!/bin/bash
# compression_table.sh: the table of docs/compression.md.
#   tests/bench/compression_table.sh OUT.md FILE.sss [FILE.sss ...]
# Each FILE is a float bake (sss-bake --quant float, RGB). For each it
# measures, mono (channel 1, green, as a one-channel bake) and RGB:
#   - SH alone at orders 1-7 (the paper's linear 8-bit codes),
#   - references {1, 3, 5} % x SH order {2, 3, 4} (paper's scheme),
#   - the variants in $EXTRA (lines "ORDER FRACTION [compress_bench options]").
# Bytes count every byte of the scattering data (sss_file_storage, the
# direction set included); error = area-weighted relative RMS of q against
# the uncompressed interpolation at $DIRS (1000) random light directions.
# One compress_bench process per file and mode reads the bake once and
# decimates once per (fraction, --illum).
set -euo pipefail
out=$1; shift
bench=${BENCH:-build/tests/bench/compress_bench}
dirs=${DIRS:-1000}
cfg=$(mktemp)
trap 'rm -f "$cfg"' EXIT
{
  for o in 1 2 3 4 5 6 7; do echo "$o 0"; done
  for fr in 0.01 0.03 0.05; do
    for o in 2 3 4; do echo "$o $fr"; done
    # variants at this fraction without --illum share its references
    [ -n "${EXTRA:-}" ] && grep -E "^[0-9]+ $fr( |$)" <<< "$EXTRA" | grep -v -- '--illum' || true
  done
  [ -n "${EXTRA:-}" ] && grep -v -E "^[0-9]+ (0.01|0.03|0.05)( |$)" <<< "$EXTRA" | grep -v '^$' || true
  [ -n "${EXTRA:-}" ] && grep -E "^[0-9]+ (0.01|0.03|0.05)( |$)" <<< "$EXTRA" | grep -- '--illum' || true
} > "$cfg"
{
  echo "| mesh | channels | references | SH order | SH codes | weights | B/vertex | rel. RMS | RMS | max abs |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
} > "$out"
for f in "$@"; do
  name=$(basename "$f" .sss)
  for mode in "--mono 1" ""; do
    # shellcheck disable=SC2086
    "$bench" "$f" --configs "$cfg" $mode --dirs "$dirs" --row | sed "s/^/| $name /" >> "$out"
  done
done
