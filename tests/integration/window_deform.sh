# sss-view --scene S.json without a file, in a window (docs/deformable.md
# §4): a real GLX window on Xvfb driven by xdotool (as window_xvfb.sh),
# checked through the viewer's screenshots (P). Space pauses the scene's
# time (two shots a while apart are identical), '.' steps it forward (the
# bent tube moves) and ',' back (the picture returns).
. "$(dirname "$0")/lib.sh"
for tool in xvfb-run xauth xdotool; do
  command -v "$tool" >/dev/null 2>&1 || fail "$tool is not installed (scripts/setup.sh installs it)"
done
: "${SSS_VIEW:?}" "${SSS_PNGSTATS:?}"
expect_ok "$SSS_GENMESH" tube 6 "$TMP/tube.ply" 0.25
# a fast bend (period 2 s, 90 degrees) so that a few frames show it moving
cat > "$TMP/tube.json" <<'J'
{"objects": [{"name": "tube", "mesh": "tube.ply", "material": "skin1", "mm_per_unit": 100,
   "deform": {"type": "bend", "axis": [0, 0, 1], "angle_deg": 90, "period_s": 2}}],
 "lights": [{"type": "directional", "direction": [0.6, -0.3, 0.8]}],
 "camera": {"position": [0, -3, 0.3], "target": [0, 0, 0], "up": [0, 0, 1]}}
J
cat > "$TMP/driver.sh" <<'EOF'
set -u
T=$TMP
pid=
fail() { echo "FAIL: $*" >&2; [ -n "$pid" ] && kill "$pid" 2>/dev/null; exit 1; }
alive() { kill -0 "$pid" 2>/dev/null; }
if [ -n "${SSS_VIEW_PRELOAD:-}" ]; then
  LD_PRELOAD=$SSS_VIEW_PRELOAD "$SSS_VIEW" --scene "$T/tube.json" --time 0.3 --size 320x240 --screenshot "$T/shot.png" >"$T/view.out" 2>"$T/view.err" &
else
  "$SSS_VIEW" --scene "$T/tube.json" --time 0.3 --size 320x240 --screenshot "$T/shot.png" >"$T/view.out" 2>"$T/view.err" &
fi
pid=$!
wid=$(timeout 30 xdotool search --sync --onlyvisible --name '^sss-view' 2>/dev/null | head -n 1)
[ -n "$wid" ] || { alive || { cat "$T/view.err" >&2; fail "sss-view exited before showing a window"; }; fail "no sss-view window within 30 s"; }
xdotool mousemove --window "$wid" 160 120 windowfocus "$wid" || fail "xdotool could not reach the window"
shot() {
  local name=$1; shift
  rm -f "$T/shot.png"
  xdotool "$@" key p || fail "xdotool failed: $*"
  local i
  for i in $(seq 300); do
    [ -e "$T/shot.png" ] && break
    alive || { cat "$T/view.err" >&2; fail "sss-view died during: $*"; }
    sleep 0.05
  done
  [ -e "$T/shot.png" ] || fail "no screenshot 15 s after: $* P"
  mv "$T/shot.png" "$T/$name.png"
}
shot p0 key h key space sleep 0.3          # overlay off, time paused
shot p1 sleep 0.5
cmp -s "$T/p0.png" "$T/p1.png" || fail "paused: the picture changed"
shot p2 key --repeat 6 --delay 30 period   # +0.2 s
cmp -s "$T/p1.png" "$T/p2.png" && fail "'.' should step the bend forward"
shot p3 key --repeat 6 --delay 30 comma    # back by 0.2 s
shot p4 sleep 0.3
cmp -s "$T/p3.png" "$T/p4.png" || fail "still paused after ',': the picture changed"
shot p5 key space sleep 0.6 key space      # play 0.6 s, pause again
cmp -s "$T/p4.png" "$T/p5.png" && fail "space should play the bend"
xdotool key Escape || fail "xdotool could not send Escape"
for i in $(seq 200); do alive || break; sleep 0.05; done
alive && fail "sss-view still running 10 s after Escape"
wait "$pid"; rc=$?
pid=
[ $rc -eq 0 ] || { cat "$T/view.err" >&2; fail "sss-view exited with status $rc"; }
exit 0
EOF
export TMP SSS_VIEW SSS_VIEW_PRELOAD="${SSS_VIEW_PRELOAD:-}"
timeout 300 xvfb-run -a -e "$TMP/xvfb.err" -s "-screen 0 1024x768x24 -nolisten tcp" bash "$TMP/driver.sh"
rc=$?
[ $rc -eq 0 ] || { cat "$TMP/xvfb.err" >&2; fail "window driver failed (status $rc$([ $rc -eq 124 ] && echo ", timed out"))"; }
# ',' undid '.': the same pose within 8-bit rounding (the clock went there and back in steps of 1/30 s)
F=$("$SSS_PNGSTATS" "$TMP/p1.png" "$TMP/p3.png")
awk -v f="$F" 'BEGIN { exit !(f < 0.002) }' || fail "',' should give the picture back ($F of the pixels differ)"
F=$("$SSS_PNGSTATS" "$TMP/p1.png" "$TMP/p2.png")
awk -v f="$F" 'BEGIN { exit !(f > 0.002) }' || fail "'.' changed only $F of the pixels"
read -r w h mean sd nonbg < <("$SSS_PNGSTATS" "$TMP/p0.png")
awk -v n="$nonbg" 'BEGIN { exit !(n > 0.02) }' || fail "p0.png is nearly empty ($nonbg of the pixels drawn)"
echo ok
