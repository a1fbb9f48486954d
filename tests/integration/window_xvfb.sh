# sss-view window mode, end to end: a real GLX window on a virtual X server
# (Xvfb), driven by real X input events (xdotool, through XTEST), checked
# through the viewer's own screenshots (P key). Fails if the viewer crashes,
# hangs, draws nothing or ignores input; also checks --help and the
# one-line errors of window mode.
. "$(dirname "$0")/lib.sh"
: "${SSS_VIEW:?}" "${SSS_PNGSTATS:?}"

# --help lists the window controls
expect_ok "$SSS_VIEW" --help
contains "$TMP/out" "screenshot"
contains "$TMP/out" "wireframe"
contains "$TMP/out" "orbit"
contains "$TMP/out" "toggle the panel"

expect_ok "$SSS_GENMESH" blob 3 "$TMP/blob.ply"
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/b.sss" --material skin1 --mm-per-unit 20 --dirs 50 -q

# Window-mode errors: exit status exactly 1 and exactly one line on stderr,
# nothing on stdout. No display is given, so none of these may need one
# (bad files are rejected before any window is opened).
expect_exit1() {
  local pat=$1; shift
  timeout 30 env -u DISPLAY -u WAYLAND_DISPLAY "$@" >"$TMP/out" 2>"$TMP/err"; local rc=$?
  [ $rc -eq 1 ] || { cat "$TMP/err" >&2; fail "expected exit status 1, got $rc: $*"; }
  [ "$(wc -l < "$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "expected one line on stderr: $*"; }
  [ ! -s "$TMP/out" ] || fail "printed on stdout: $*"
  grep -q -- "$pat" "$TMP/err" || { cat "$TMP/err" >&2; fail "message should match '$pat': $*"; }
}
cp "$TMP/b.sss" "$TMP/flip.sss"
printf '\x55' | dd of="$TMP/flip.sss" bs=1 seek=300 conv=notrunc status=none
expect_exit1 "flip.sss" "$SSS_VIEW" "$TMP/flip.sss"
head -c 200 "$TMP/b.sss" > "$TMP/trunc.sss"
expect_exit1 "trunc.sss" "$SSS_VIEW" "$TMP/trunc.sss"
expect_exit1 "missing.sss" "$SSS_VIEW" "$TMP/missing.sss"
expect_exit1 "cannot open a window (no display?); use --offscreen" "$SSS_VIEW" "$TMP/b.sss"

# The driver runs inside the virtual X server. Every step that should
# change the picture is followed by a screenshot and compared with the one
# before it (overlay hidden, so only the scene is compared: the overlay's
# fps numbers change by themselves); steps that undo another must give back
# the earlier picture byte for byte, which also shows that rendering is
# deterministic, so "differs" really means "input was applied".
cat > "$TMP/driver.sh" <<'EOF'
. "$WINDOW_LIB"
view_start 640 480 "$T/b.sss"

shot overlay0 sleep 0.3                     # overlay on, as the user first sees it
shot s0 key h                               # overlay off from here
shot s0b sleep 0.1
same s0 s0b "nothing changed in between"
shot s1 mousemove --window "$wid" 200 240 mousedown 1 mousemove --window "$wid" 330 300 mouseup 1
differ s0 s1 "left drag should orbit the camera"
shot s2 mousemove --window "$wid" 320 240 mousedown 3 mousemove --window "$wid" 360 270 mouseup 3
differ s1 s2 "right drag should pan"
shot s3 mousemove --window "$wid" 300 200 keydown ctrl mousedown 1 mousemove --window "$wid" 420 260 mouseup 1 keyup ctrl
differ s2 s3 "Ctrl+drag should move the light"
shot s3l mousemove --window "$wid" 300 200 keydown l mousedown 1 mousemove --window "$wid" 260 240 mouseup 1 keyup l
differ s3 s3l "L+drag should move the light"
shot s3s mousemove --window "$wid" 300 200 keydown shift mousedown 1 mousemove --window "$wid" 280 190 mouseup 1 keyup shift
differ s3l s3s "Shift+drag should pan"
shot s4 mousemove --window "$wid" 320 240 click --repeat 3 --delay 20 4
differ s3 s4 "scrolling should zoom"
shot s5 key w
differ s4 s5 "W should draw the wireframe"
shot s6 key w
same s4 s6 "W twice should give the picture back"
shot sx1 key x                              # a plain bake has no single-scattering bit: X adds it
differ s6 sx1 "X should add single scattering"
shot sx2 key x
same s6 sx2 "X twice should give the picture back"
shot s7 key c                               # CPU path: compared with s6 below
shot s8 key c
same s6 s8 "C twice should give the GPU picture back"
shot s9 key --repeat 3 --delay 20 Right
differ s8 s9 "the Right arrow should rotate the light"
shot s10 key t
differ s9 s10 "T should switch the tone map"
shot s11 key t key 1
differ s9 s11 "1 should leave scattering only"
shot s12 key 3 key r
same s0 s12 "R should reset camera and light"
shot s13 key equal
differ s12 s13 "+ should raise the light intensity"
shot s14 key minus
same s12 s14 "- should undo +"
shot s15 key bracketright
differ s14 s15 "] should raise the exposure"
shot s16 key bracketleft
same s14 s16 "[ should undo ]"
# The panel (G, runtime/src/view/panel.h): hidden at start, drawn over the
# right of the picture only, and gone again without a trace. Its layout is
# fixed (top right, 300 px wide, ImGui 1.86's default font and style), so
# the controls sit at known window coordinates: in a 640x480 window the
# scatter box at (348, 297), the exposure slider from x 340 to 520 at y 182
# (docs/images/viewer_panel.png shows them). A click is taken in on the
# frame after it arrives and applied on the one after that, so every click
# is followed by one more screenshot before the panel is hidden.
shot p0 key g
differ s16 p0 "G should show the panel"
d=$("$SSS_PNGSTATS" "$T/s16.png" "$T/p0.png") || fail "cannot compare s16/p0"
awk -v d="$d" 'BEGIN { exit !(d > 0.15 && d < 0.46) }' ||
  fail "the panel changed a fraction $d of the pixels; its 300x464 rectangle is 0.45 of them"
shot p1 key g
same s16 p1 "G twice should hide the panel and leave the picture as it was"
# The scatter box switches scattering off as the 2 key does.
shot k2 key 2
shot k3 key 3
same s16 k3 "3 should undo 2"
shot p2a key g sleep 0.2 mousemove --window "$wid" 348 297 sleep 0.2 click 1
shot p2b sleep 0.1
shot p2 key g
same k2 p2 "the panel's scatter box should leave reflection only, as the 2 key does"
# The keys still work with the panel open and the pointer over it.
shot p3a key g sleep 0.2 mousemove --window "$wid" 348 297 sleep 0.2 click 1
shot p3b key w
shot p3 key g
differ s16 p3 "W should draw the wireframe with the panel open"
shot p4 key w
same s16 p4 "the scatter box twice and W twice should give the picture back"
# The exposure slider: a click near its left end darkens the picture, near
# its right end brightens it; a drag on it ends where a click there does
# and turns no camera (the pointer is the panel's while it is over it).
mean() { "$SSS_PNGSTATS" "$T/$1.png" | awk '{ print $3 }'; }
shot p5a key g sleep 0.2 mousemove --window "$wid" 380 182 sleep 0.2 click 1
shot p5b sleep 0.1
shot p5 key g
shot p6a key g sleep 0.2 mousemove --window "$wid" 500 182 sleep 0.2 click 1
shot p6b sleep 0.1
shot p6 key g
awk -v lo="$(mean p5)" -v mid="$(mean s16)" -v hi="$(mean p6)" 'BEGIN { exit !(lo < mid && mid < hi) }' ||
  fail "the exposure slider: mean levels $(mean p5) (left), $(mean s16) (before), $(mean p6) (right) should rise"
# ImGui 1.86 reads the pointer once per frame and a slider takes the
# pointer's place only on frames the button is still down, so every step
# of the drag is held for longer than a frame of the slowest (sanitizer)
# build before the button is let go.
shot p7a key g sleep 0.2 mousemove --window "$wid" 400 182 sleep 0.3 mousedown 1 sleep 0.6 mousemove --window "$wid" 450 200 sleep 0.6 mousemove --window "$wid" 500 182 sleep 1 mouseup 1
shot p7b sleep 0.1
shot p7 key g
same p6 p7 "a drag on the exposure slider should end at the value a click there gives, camera unmoved"
shot overlay1 key h
# Resizing: the next frame uses the new framebuffer size (down to 1x1),
# and unmapping/mapping the window (what minimising does) is survived.
shot tiny windowsize "$wid" 1 1 sleep 0.3
shot wide windowsize "$wid" 800 500 sleep 0.3 windowunmap --sync "$wid" sleep 0.3 windowmap --sync "$wid" sleep 0.3 mousemove --window "$wid" 400 250 windowfocus "$wid"

view_quit
EOF
run_window_driver "$TMP/driver.sh" 360
[ ! -s "$TMP/view.out" ] || fail "sss-view printed on stdout"
contains "$TMP/view.err" "sss-view: saved $TMP/shot.png"

# The pictures are not blank: the mesh covers a good part of the frame and
# has shading (not one flat colour), with and without the overlay.
for name in s0 overlay0 overlay1; do
  read -r w h mean sd nonbg < <("$SSS_PNGSTATS" "$TMP/$name.png") || fail "cannot read $name.png"
  [ "$w" = 640 ] && [ "$h" = 480 ] || fail "$name.png is ${w}x$h, expected 640x480"
  awk -v sd="$sd" -v f="$nonbg" 'BEGIN { exit !(sd > 10 && f >= 0.05) }' ||
    fail "$name.png looks blank: mean $mean, stddev $sd, non-background fraction $nonbg"
done
for pair in "tiny 1 1" "wide 800 500"; do
  set -- $pair
  read -r w h _ < <("$SSS_PNGSTATS" "$TMP/$1.png") || fail "cannot read $1.png"
  [ "$w" = "$2" ] && [ "$h" = "$3" ] || fail "$1.png is ${w}x$h after resizing to $2x$3"
done
# CPU and GPU evaluation draw the same picture (up to rounding).
d=$("$SSS_PNGSTATS" "$TMP/s6.png" "$TMP/s7.png") || fail "cannot compare s6/s7"
awk -v d="$d" 'BEGIN { exit !(d < 0.01) }' || fail "CPU path picture differs from GPU path in a fraction $d of pixels"
# A light change moves the shading over a visible area, not a few pixels.
d=$("$SSS_PNGSTATS" "$TMP/s8.png" "$TMP/s9.png") || fail "cannot compare s8/s9"
awk -v d="$d" 'BEGIN { exit !(d > 0.02) }' || fail "a 15 degree light turn changed only a fraction $d of pixels"
echo "window_xvfb: ok"
