#!/bin/bash
# compression_table.sh: the table of docs/compression.md (issue 3).
#   tests/bench/compression_table.sh OUT.md FILE.sss [FILE.sss ...]
# Each FILE is a float bake (sss-bake --quant float, RGB). For each it
# measures, mono (channel 1, green, as a one-channel bake) and RGB:
#   - SH alone at orders 1-7 (the paper's linear 8-bit codes),
#   - references {1, 3, 5} % x SH order {2, 3, 4} (paper's scheme),
#   - the variants in $EXTRA (lines of compress_bench options), if set.
# ONLY=sh or ONLY=refs restricts to one of the first two groups.
# Bytes count every byte of the scattering data (sss_file_storage, the
# direction set included); error = area-weighted relative RMS of q against
# the uncompressed interpolation at 1000 random light directions.
set -euo pipefail
out=$1; shift
bench=${BENCH:-build/tests/bench/compress_bench}
dirs=${DIRS:-1000}
{
  echo "| mesh | channels | references | SH order | SH codes | weights | B/vertex | rel. RMS | RMS | max abs |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
} > "$out"
for f in "$@"; do
  name=$(basename "$f" .sss)
  for mode in "--mono 1" ""; do
    run() { echo -n "| $name "; $bench "$f" "$@" $mode --dirs "$dirs" --row; }
    if [ "${ONLY:-}" != refs ]; then for o in 1 2 3 4 5 6 7; do run $o 0 >> "$out"; done; fi
    if [ "${ONLY:-}" != sh ]; then for fr in 0.01 0.03 0.05; do for o in 2 3 4; do run $o $fr >> "$out"; done; done; fi
    if [ -n "${EXTRA:-}" ]; then
      while read -r line; do [ -n "$line" ] && run $line >> "$out"; done <<< "$EXTRA"
    fi
  done
done
