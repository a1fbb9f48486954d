# sss-view --offscreen: PNG and EXR output, bad input gives a one-line error.
. "$(dirname "$0")/../integration/lib.sh"
# sanitizer builds preload Mesa's driver into the viewer only (tests/CMakeLists.txt)
view() { LD_PRELOAD=${SSS_VIEW_PRELOAD:-} "$SSS_VIEW" "$@"; }
expect_ok "$SSS_GENMESH" blob 3 "$TMP/blob.ply"
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/b.sss" --material skin1 --mm-per-unit 20 --dirs 50 -q
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
# bad input
head -c 200 "$TMP/b.sss" > "$TMP/trunc.sss"
expect_fail "trunc.sss" view "$TMP/trunc.sss" --offscreen --out "$TMP/x.png"
expect_fail "missing.sss" view "$TMP/missing.sss" --offscreen --out "$TMP/x.png"
expect_fail "size" view "$TMP/b.sss" --offscreen --out "$TMP/x.png" --size 0x5
expect_fail "light" view "$TMP/b.sss" --offscreen --out "$TMP/x.png" --light 0,0,0
expect_fail "unknown image type" view "$TMP/b.sss" --offscreen --out "$TMP/x.bmp"
echo "cli_view_offscreen: ok"
