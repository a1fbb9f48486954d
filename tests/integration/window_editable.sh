# sss-view --scene S.json on an editable object, in a window
# (docs/heterogeneous.md §9): a real GLX window on Xvfb driven by xdotool (as
# window_deform.sh), checked through the viewer's screenshots (P). K (the
# inside's absorption x1.5) changes the picture at once and J gives it back;
# U (the field's strength) and Y (the base's transport colour) change it too.
. "$(dirname "$0")/lib.sh"
for tool in xvfb-run xauth xdotool; do
  command -v "$tool" >/dev/null 2>&1 || fail "$tool is not installed (scripts/setup.sh installs it)"
done
: "${SSS_VIEW:?}" "${SSS_PNGSTATS:?}"
expect_ok "$SSS_GENMESH" cube 8 "$TMP/block.ply" 2
cat > "$TMP/edit.json" <<'J'
{"objects": [{"name": "block", "mesh": "block.ply", "mm_per_unit": 10, "editable": true,
  "material": {"preset": "marble", "inside": {"preset": "marble", "sigma_a": [0.03, 0.06, 0.12]},
               "field": {"procedural": "box", "centre_mm": [0, 0, 0], "half_mm": [4, 4, 4], "edge_mm": 1}}}],
 "lights": [{"type": "directional", "direction": [0, 0, -1], "intensity": 1}],
 "camera": {"position": [0.6, 0.5, 4.5], "target": [0, 0, 0], "up": [0, 1, 0]}}
J
cat > "$TMP/driver.sh" <<'EOF'
set -u
T=$TMP
pid=
fail() { echo "FAIL: $*" >&2; [ -n "$pid" ] && kill "$pid" 2>/dev/null; exit 1; }
alive() { kill -0 "$pid" 2>/dev/null; }
if [ -n "${SSS_VIEW_PRELOAD:-}" ]; then
  LD_PRELOAD=$SSS_VIEW_PRELOAD "$SSS_VIEW" --scene "$T/edit.json" --size 320x240 --exposure 60 --screenshot "$T/shot.png" >"$T/view.out" 2>"$T/view.err" &
else
  "$SSS_VIEW" --scene "$T/edit.json" --size 320x240 --exposure 60 --screenshot "$T/shot.png" >"$T/view.out" 2>"$T/view.err" &
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
shot p0 key h sleep 0.3                    # overlay off
shot p1 key k sleep 0.3                    # inside absorption x1.5
shot p2 key j sleep 0.3                    # and back
shot p3 key u sleep 0.3                    # strength /1.25 (the box's f = 1 falls to 0.8)
shot p4 key i key y sleep 0.3              # strength back, the next transport colour
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
diff_px() { "$SSS_PNGSTATS" "$TMP/$1.png" "$TMP/$2.png"; }
F=$(diff_px p0 p1); awk -v f="$F" 'BEGIN { exit !(f > 0.01) }' || fail "K changed only $F of the pixels"
F=$(diff_px p0 p2); awk -v f="$F" 'BEGIN { exit !(f < 0.002) }' || fail "J should give the picture back ($F differ)"
F=$(diff_px p0 p3); awk -v f="$F" 'BEGIN { exit !(f > 0.01) }' || fail "U changed only $F of the pixels"
F=$(diff_px p0 p4); awk -v f="$F" 'BEGIN { exit !(f > 0.01) }' || fail "Y changed only $F of the pixels"
read -r w h mean sd nonbg < <("$SSS_PNGSTATS" "$TMP/p0.png")
awk -v n="$nonbg" 'BEGIN { exit !(n > 0.02) }' || fail "p0.png is nearly empty ($nonbg of the pixels drawn)"
echo ok
