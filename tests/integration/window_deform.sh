# sss-view --scene S.json without a file, in a window (docs/deformable.md
# §4): a real GLX window on Xvfb driven by xdotool (as window_xvfb.sh),
# checked through the viewer's screenshots (P). Space pauses the scene's
# time (two shots a while apart are identical), '.' steps it forward (the
# bent tube moves) and ',' back (the picture returns).
. "$(dirname "$0")/lib.sh"
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
. "$WINDOW_LIB"
view_start 320 240 --scene "$T/tube.json" --time 0.3
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
view_quit
EOF
run_window_driver "$TMP/driver.sh" 300
# ',' undid '.': the same pose within 8-bit rounding (the clock went there and back in steps of 1/30 s)
F=$("$SSS_PNGSTATS" "$TMP/p1.png" "$TMP/p3.png")
awk -v f="$F" 'BEGIN { exit !(f < 0.002) }' || fail "',' should give the picture back ($F of the pixels differ)"
F=$("$SSS_PNGSTATS" "$TMP/p1.png" "$TMP/p2.png")
awk -v f="$F" 'BEGIN { exit !(f > 0.002) }' || fail "'.' changed only $F of the pixels"
read -r w h mean sd nonbg < <("$SSS_PNGSTATS" "$TMP/p0.png")
awk -v n="$nonbg" 'BEGIN { exit !(n > 0.02) }' || fail "p0.png is nearly empty ($nonbg of the pixels drawn)"
echo ok
