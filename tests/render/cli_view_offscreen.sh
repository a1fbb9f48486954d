# sss-view --offscreen: PNG and EXR output, bad input gives a one-line error.
. "$(dirname "$0")/../integration/lib.sh"
# sanitizer builds preload Mesa's driver into the viewer only (tests/CMakeLists.txt)
view() { LD_PRELOAD=${SSS_VIEW_PRELOAD:-} "$SSS_VIEW" "$@"; }
expect_ok "$SSS_GENMESH" blob 3 "$TMP/blob.ply"
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/b.sss" --material skin1 --mm-per-unit 20 --dirs 50 --own-term baked -q
expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/a.png" --size 160x120 --light 0,0,1 --view 0,0,1
[ "$(head -c 8 "$TMP/a.png" | od -An -tx1 | tr -d ' ')" = "89504e470d0a1a0a" ] || fail "a.png is not a PNG"
expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/a.exr" --size 160x120 --light 0,1,0 --cpu
[ "$(head -c 4 "$TMP/a.exr" | od -An -tx1 | tr -d ' ')" = "762f3101" ] || fail "a.exr is not an OpenEXR file"
expect_ok view "$TMP/b.sss" --offscreen --bench 5 --size 64x64
contains "$TMP/out" '"scatter_ms_median"'
# the same light gives a different image than another light
expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/b.png" --size 160x120 --light 0,0,-1 --view 0,0,1
cmp -s "$TMP/a.png" "$TMP/b.png" && fail "changing the light did not change the image"
# a compressed file (format 1.1: 5 % references + SH order 3 deltas, Hao–Varshney 2004 §4) renders on
# both paths, is not blank, and both paths give the same picture
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/c.sss" --material skin1 --mm-per-unit 20 --dirs 50 --sh-order 3 --refs 0.05 -q
expect_ok view "$TMP/c.sss" --offscreen --out "$TMP/c.png" --size 160x120 --light 0.3,0.5,1 --view 0,0,1
read -r cw ch cmean csd cnonbg < <("$SSS_PNGSTATS" "$TMP/c.png") || fail "cannot read c.png"
[ "$cw $ch" = "160 120" ] || fail "c.png is ${cw}x${ch}, not 160x120"
awk -v m="$cmean" -v s="$csd" -v f="$cnonbg" 'BEGIN { exit !(m > 2 && s > 2 && f > 0.1) }' \
  || fail "c.png looks blank: mean $cmean, stddev $csd, non-background fraction $cnonbg"
expect_ok view "$TMP/c.sss" --offscreen --out "$TMP/c_cpu.png" --size 160x120 --light 0.3,0.5,1 --view 0,0,1 --cpu
d=$("$SSS_PNGSTATS" "$TMP/c.png" "$TMP/c_cpu.png") || fail "cannot compare c.png and c_cpu.png"
awk -v d="$d" 'BEGIN { exit !(d < 0.001) }' || fail "GPU and CPU paths differ on $d of the pixels of c.png"
expect_ok view "$TMP/c.sss" --offscreen --bench 3 --size 64x64
contains "$TMP/out" '"quant":"refs"'
# a file baked with its near terms split off (format 1.3, OWNT; sss/nearterms.h): the viewer adds them
# back with the visibility of the bake's rays (or of a shadow map), on both paths alike; --no-own-term
# draws the stored rows alone, which lack them and are darker; --bench names the split and the
# visibility, and a plain file has none
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/o.sss" --material skin1 --mm-per-unit 20 --dirs 50 --own-term runtime -q
expect_ok view "$TMP/o.sss" --offscreen --out "$TMP/o.png" --size 160x120 --light 0.6,0.5,0.6 --view 0,0,1
expect_ok view "$TMP/o.sss" --offscreen --out "$TMP/o_cpu.png" --size 160x120 --light 0.6,0.5,0.6 --view 0,0,1 --cpu
d=$("$SSS_PNGSTATS" "$TMP/o.png" "$TMP/o_cpu.png") || fail "cannot compare o.png and o_cpu.png"
awk -v d="$d" 'BEGIN { exit !(d < 0.001) }' || fail "GPU and CPU paths differ on $d of the pixels of o.png"
expect_ok view "$TMP/o.sss" --offscreen --out "$TMP/o_off.png" --size 160x120 --light 0.6,0.5,0.6 --view 0,0,1 --no-own-term
read -r _ _ omean _ _ < <("$SSS_PNGSTATS" "$TMP/o.png") || fail "cannot read o.png"
read -r _ _ offmean _ _ < <("$SSS_PNGSTATS" "$TMP/o_off.png") || fail "cannot read o_off.png"
awk -v a="$omean" -v b="$offmean" 'BEGIN { exit !(a > 2 && b < a) }' \
  || fail "near terms: image mean $omean with them, $offmean without (expected brighter with them)"
expect_ok view "$TMP/o.sss" --offscreen --bench 3 --size 64x64
contains "$TMP/out" '"own_term":"within 8.71 mm, rays"'
# rows larger than the GL's storage block go up in chunks of receivers
# (runtime/src/render/effects/near.c; SSS_NEAR_BLOCK_BYTES lowers the
# limit): the same picture on both paths; a block below one row is refused
for c in "" --cpu; do
  # shellcheck disable=SC2086
  SSS_NEAR_BLOCK_BYTES=2048 expect_ok view "$TMP/o.sss" --offscreen --out "$TMP/o_chunks.png" --size 160x120 \
    --light 0.6,0.5,0.6 --view 0,0,1 $c
  ref=$TMP/o.png; [ -n "$c" ] && ref=$TMP/o_cpu.png
  cmp -s "$TMP/o_chunks.png" "$ref" || fail "near terms in chunks ${c:-(GPU)}: the picture differs from one buffer's"
done
SSS_NEAR_BLOCK_BYTES=12 expect_fail "near terms (.* entries) exceed this GL's storage block" view "$TMP/o.sss" \
  --offscreen --out "$TMP/o_x.png" --size 32x32
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "the refusal should be one line: $(cat "$TMP/err")"
expect_ok view "$TMP/o.sss" --offscreen --bench 3 --size 64x64 --near-visibility map
contains "$TMP/out" '"own_term":"within 8.71 mm, shadow map 2048"'
expect_ok view "$TMP/o.sss" --offscreen --out "$TMP/o_map.png" --size 160x120 --light 0.6,0.5,0.6 --view 0,0,1 \
  --near-visibility map
d=$("$SSS_PNGSTATS" "$TMP/o.png" "$TMP/o_map.png") || fail "cannot compare o.png and o_map.png"
awk -v d="$d" 'BEGIN { exit !(d < 0.01) }' || fail "rays and shadow map differ on $d of the pixels of o.png"
expect_fail "near-visibility" view "$TMP/o.sss" --offscreen --out "$TMP/x.png" --near-visibility maps
expect_ok view "$TMP/b.sss" --offscreen --bench 2 --size 64x64
contains "$TMP/out" '"own_term":"none"'
# bad input
head -c 200 "$TMP/b.sss" > "$TMP/trunc.sss"
expect_fail "trunc.sss" view "$TMP/trunc.sss" --offscreen --out "$TMP/x.png"
expect_fail "missing.sss" view "$TMP/missing.sss" --offscreen --out "$TMP/x.png"
expect_fail "size" view "$TMP/b.sss" --offscreen --out "$TMP/x.png" --size 0x5
expect_fail "light" view "$TMP/b.sss" --offscreen --out "$TMP/x.png" --light 0,0,0
expect_fail "unknown image type" view "$TMP/b.sss" --offscreen --out "$TMP/x.bmp"
echo "cli_view_offscreen: ok"
# without --exposure the exposure comes from the file (1 / (I q_slab), q_slab
# the flat surface lit head-on, docs/physics.md §4): a first render with the
# default light and view is neither dark (the brightest object pixel at 192
# or more of 255) nor clipped (at most 2 % of the object's pixels at 255),
# for materials whose q differ by 3x, one channel or three, at any --intensity
# and with the normalised exit term;
# --exposure 1 is the old, dimmer picture
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/g.sss" --sigma-a 0.01,0.01,0.01 --sigma-s 1,1,1 --mm-per-unit 20 --dirs 50 -q
for m in marble skin1 ketchup grey; do
  f=$TMP/g.sss
  [ $m = grey ] || { f=$TMP/e_$m.sss; expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$f" --material $m --mm-per-unit 20 --dirs 50 -q; }
  for i in "--intensity 1" "--intensity 4" "--exit normalised"; do
    # shellcheck disable=SC2086
    expect_ok view "$f" --offscreen --out "$TMP/e.png" --size 128x96 $i
    read -r mx clip < <("$SSS_PNGSTATS" --range "$TMP/e.png") || fail "cannot read e.png"
    awk -v m="$mx" -v c="$clip" 'BEGIN { exit !(m >= 192 && c <= 0.02) }' \
      || fail "$m, $i, default exposure: brightest sample $mx, clipped fraction $clip (want >= 192, <= 0.02)"
  done
done
expect_ok view "$TMP/e_skin1.sss" --offscreen --out "$TMP/e1.png" --size 128x96 --exposure 1
read -r mx1 _ < <("$SSS_PNGSTATS" --range "$TMP/e1.png") || fail "cannot read e1.png"
[ "$mx1" -lt 160 ] || fail "skin1 at --exposure 1: brightest sample $mx1, expected the dimmer picture (< 160)"
# the surface terms (docs/viewer.md, "Direct surface light"): --diffuse adds a Lambert share of the
# reflected light, --no-surface-shadow lifts their shadow, --interp nearest4 the paper's blend of q;
# each changes the picture of the blob (which shadows itself), and --bench says which was drawn
expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/s0.png" --size 160x120 --light 1,0.2,0.3
for o in "--diffuse 0.5" "--interp nearest4" "--interp nearest4 --cpu"; do
  # shellcheck disable=SC2086
  expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/s1.png" --size 160x120 --light 1,0.2,0.3 $o
  cmp -s "$TMP/s0.png" "$TMP/s1.png" && fail "$o did not change the picture"
done
# the shadow shows in the broad Lambert lobe (the specular one need not reach a shadow)
expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/s3.png" --size 160x120 --light 1,0.2,0.3 --diffuse 1 --no-scatter
expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/s4.png" --size 160x120 --light 1,0.2,0.3 --diffuse 1 --no-scatter \
  --no-surface-shadow
cmp -s "$TMP/s3.png" "$TMP/s4.png" && fail "--no-surface-shadow did not change the picture"
expect_ok view "$TMP/b.sss" --offscreen --out "$TMP/s2.png" --size 160x120 --light 1,0.2,0.3 --interp nearest4
d=$("$SSS_PNGSTATS" "$TMP/s1.png" "$TMP/s2.png") || fail "cannot compare s1.png and s2.png"
awk -v d="$d" 'BEGIN { exit !(d < 0.001) }' || fail "4-nearest: GPU and CPU paths differ on $d of the pixels"
expect_ok view "$TMP/b.sss" --offscreen --bench 2 --size 64x64 --interp nearest4 --diffuse 0.25 --no-surface-shadow
contains "$TMP/out" '"interp":"nearest4","surface_shadow":false,"diffuse":0.25'
