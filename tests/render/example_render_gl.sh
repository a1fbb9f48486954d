# examples/render_gl: an engine's own GL code fed by libsss's GPU layout
# (sss/gpu.h, docs/gpu_layout.md) gives sss_decode_all's q to the bit, for
# every storage form (float, lloyd8, SH linear8 / lloyd8 / lloyd4 / linear16, the
# reference form with and without SH deltas), and draws a picture of it.
. "$(dirname "$0")/../integration/lib.sh"
# sanitizer builds preload Mesa's driver (tests/CMakeLists.txt)
run() { LD_PRELOAD=${SSS_VIEW_PRELOAD:-} "$SSS_RENDER_GL" "$@"; }
expect_ok "$SSS_GENMESH" blob 3 "$TMP/blob.ply"
bake() { local name=$1; shift; expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/$name.sss" --mm-per-unit 20 \
  --dirs 50 --own-term baked -q "$@"; }
SKIN=(--material skin1)
bake float "${SKIN[@]}" --quant float
bake lloyd8 "${SKIN[@]}" --quant lloyd8
bake sh_linear8 "${SKIN[@]}" --sh-order 4 --refs 0 --sh-quant linear8
bake sh_lloyd8 "${SKIN[@]}" --sh-order 3 --refs 0 --sh-quant lloyd8
bake sh_lloyd4 "${SKIN[@]}" --sh-order 4 --refs 0 --sh-quant lloyd4
bake sh_linear16 "${SKIN[@]}" --compress paper-sh
bake refs_sh "${SKIN[@]}" --sh-order 3 --refs 0.05 --sh-quant lloyd8 --weight-bits 16
bake refs_only "${SKIN[@]}" --sh-order 0 --refs 0.1 --weight-bits 8
bake grey --quant lloyd8 --sigma-a 0.01,0.01,0.01 --sigma-s 1,1,1
for name in float lloyd8 sh_linear8 sh_lloyd8 sh_lloyd4 sh_linear16 refs_sh refs_only grey; do
  for light in "0.3 0.5 0.8" "0 0 -1" "-1 0.2 0"; do
    expect_ok run "$TMP/$name.sss" "$TMP/$name.ppm" $light
    contains "$TMP/out" "= 0 (bit-identical)"
  done
  # the picture: a 512x512 PPM whose pixels are not all the background
  [ "$(head -c 15 "$TMP/$name.ppm")" = "$(printf 'P6\n512 512\n255\n')" ] || fail "$name.ppm is not a 512x512 PPM"
  [ "$(tail -c +16 "$TMP/$name.ppm" | od -An -v -tu1 -w3 | sort -u | wc -l)" -gt 50 ] || fail "$name.ppm shows no shading"
done
# each file holds the form it is meant to test
for pair in "float:float, " "lloyd8:lloyd8, " "sh_linear8:sh SH linear8, " "sh_lloyd8:sh SH lloyd8, " \
  "sh_lloyd4:sh SH lloyd4, " "sh_linear16:sh SH linear16, " "refs_sh:refs SH lloyd8, " "refs_only:refs, " "grey:x 1 channels"; do
  expect_ok run "$TMP/${pair%%:*}.sss" "$TMP/x.ppm"
  contains "$TMP/out" "${pair#*:}"
done
# no light (zero vector): q is 0 on both sides, still identical
expect_ok run "$TMP/lloyd8.sss" "$TMP/x.ppm" 0 0 0
contains "$TMP/out" "= 0 (bit-identical)"
# bad input: one line naming the file, exit 1, no image
echo "not a file" > "$TMP/bad.sss"
rm -f "$TMP/bad.ppm"
expect_fail "bad.sss" run "$TMP/bad.sss" "$TMP/bad.ppm"
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "a bad file should give one line"
[ -e "$TMP/bad.ppm" ] && fail "a bad file left an image"
echo "example_render_gl: ok"
