# A million-vertex mesh (docs/robustness.md): the bake's memory
# stays proportional to the vertex count and nothing overflows 32 bits.
# A 1000 x 1000 vertex plane (1,996,002 triangles) with a short scattering
# range (sigma_a = 1, sigma'_s = 10 /mm: radius ~1 mm at 1 mm spacing, about
# 5 neighbours per vertex), one grey channel and 4 directions keeps it to
# seconds; the same bake of a 500 x 500 plane gives the per-vertex memory to
# compare with. Label "large" (tests/integration/CMakeLists.txt).
. "$(dirname "$0")/lib.sh"
# The rows as floats with the paper's point weights and every term baked:
# this is the gather's memory and 32-bit arithmetic at scale; the default
# configuration's extra stages (hat weights, near terms, compression) are
# timed on the 100K and 437K dragons (docs/benchmarks.md).
bake=(--sigma-a 1,1,1 --sigma-s 10,10,10 --mm-per-unit 1000 --dirs 4 --quant float --weights point --own-term baked -q --json)
rss_of() { grep -o '"peak_rss_mib":[0-9.e+]*' "$1" | cut -d: -f2; }
expect_ok "$SSS_GENMESH" plane 499 "$TMP/p250k.ply"
expect_ok "$SSS_BAKE" "$TMP/p250k.ply" -o "$TMP/p250k.sss" "${bake[@]}"
contains "$TMP/out" '"vertices":250000,'
small=$(rss_of "$TMP/out")
expect_ok "$SSS_GENMESH" plane 999 "$TMP/p1m.ply"
t0=$(date +%s.%N)
expect_ok "$SSS_BAKE" "$TMP/p1m.ply" -o "$TMP/p1m.sss" "${bake[@]}"
t1=$(date +%s.%N)
cp "$TMP/out" "$TMP/p1m.json"
contains "$TMP/p1m.json" '"vertices":1000000,'
contains "$TMP/p1m.json" '"triangles":1996002,'
big=$(rss_of "$TMP/p1m.json")
echo "cli_million: 250,000 vertices: peak RSS ${small} MiB; 1,000,000: ${big} MiB in $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s"
# proportional: 4x the vertices may take at most 4.5x the memory (a fixed
# part makes it less), and at most 2 KiB per vertex (about 0.45 KiB measured,
# docs/robustness.md; sanitizer builds need more)
awk -v s="$small" -v b="$big" 'BEGIN { exit !(b < 4.5 * s) }' || fail "peak RSS grew faster than the vertex count: $small MiB -> $big MiB"
awk -v b="$big" 'BEGIN { exit !(b * 1048576 < 2048 * 1e6) }' || fail "peak RSS $big MiB is more than 2 KiB per vertex"
# the file reads back (the reader refuses NaN/Inf and any count that does not
# add up), and the last vertex's q is finite and agrees with the exact
# evaluator
expect_ok "$SSS_STAT" "$TMP/p1m.sss"
expect_ok "$SSS_STAT" "$TMP/p1m.sss" --query 999999 --light 0.3,0.2,1
! grep -qi 'nan\|inf' "$TMP/out" || fail "NaN or Inf at vertex 999999"
rm -f "$TMP"/p1m.* "$TMP"/p250k.*
echo "cli_million: ok"
