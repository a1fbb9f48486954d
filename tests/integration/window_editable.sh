# sss-view --scene S.json on an editable object, in a window
# (docs/heterogeneous.md §9): a real GLX window on Xvfb driven by xdotool (as
# window_deform.sh), checked through the viewer's screenshots (P). K (the
# inside's absorption x1.5) changes the picture at once and J gives it back;
# U (the field's strength) and Y (the base's transport colour) change it too.
# The panel (G) shows the live material: a click at the strength slider's
# low end fades the box, so the picture, the panel closed again, is
# brighter, and its "write the scene (E)" button writes it (to
# --save-scene's path, the strength folded into the inside). E writes the
# edited scene next to the input (NAME.edited.json,
# docs/heterogeneous.md §9.6), leaving the input byte for byte: it loads
# with the edited numbers and draws the edited picture; a strength above 1
# is written as the field's "strength", which only the run-time path takes.
. "$(dirname "$0")/lib.sh"
: "${SSS_VIEW:?}" "${SSS_PNGSTATS:?}"
expect_ok "$SSS_GENMESH" cube 8 "$TMP/block.ply" 2
cat > "$TMP/edit.json" <<'J'
{"objects": [{"name": "block", "mesh": "block.ply", "mm_per_unit": 10, "editable": true,
  "material": {"preset": "marble", "inside": {"preset": "marble", "sigma_a": [0.03, 0.06, 0.12]},
               "field": {"procedural": "box", "centre_mm": [0, 0, 0], "half_mm": [4, 4, 4], "edge_mm": 1}}}],
 "lights": [{"type": "directional", "direction": [0, 0, -1], "intensity": 1}],
 "camera": {"position": [0.6, 0.5, 4.5], "target": [0, 0, 0], "up": [0, 1, 0]}}
J
cp "$TMP/edit.json" "$TMP/input.json"
cat > "$TMP/driver.sh" <<'EOF'
. "$WINDOW_LIB"
view_start 320 240 --scene "$T/edit.json" --exposure 60
shot p0 key h sleep 0.3                    # overlay off
shot p1 key k sleep 0.3                    # inside absorption x1.5
shot p2 key j sleep 0.3                    # and back
shot p3 key u sleep 0.3                    # strength /1.25 (the box's f = 1 falls to 0.8)
shot p4 key i key y sleep 0.3              # strength back, the next transport colour
shot p5 key k key u sleep 0.3              # inside absorption x1.5, strength 0.8
shot p6 key e                              # the scene written: edit.edited.json
view_quit
cp "$T/view.err" "$T/e1.err"
view_start 320 240 --scene "$T/edit.edited.json" --exposure 60 --save-scene "$T/strong.json"
shot r0 key h sleep 0.3                    # the written scene as loaded, overlay off
shot r1 key i key i key e                  # strength 1.5625, written to strong.json
view_quit
view_start 560 320 --scene "$T/edit.json" --exposure 60 --save-scene "$T/button.json"
shot s0 key h                              # overlay off
shot s1 key g                              # the panel: its live material under Light
shot s2 mousemove --window "$wid" 270 205 sleep 0.2 click 1   # strength slider, low end (1/64 ... 64, logarithmic)
shot s2b mousemove --window "$wid" 330 295 sleep 0.2 click 1  # "write the scene (E)"
shot s3 key g                              # the panel closed, the edit kept
view_quit
EOF
run_window_driver "$TMP/driver.sh" 300
diff_px() { "$SSS_PNGSTATS" "$TMP/$1.png" "$TMP/$2.png"; }
F=$(diff_px p0 p1); awk -v f="$F" 'BEGIN { exit !(f > 0.01) }' || fail "K changed only $F of the pixels"
F=$(diff_px p0 p2); awk -v f="$F" 'BEGIN { exit !(f < 0.002) }' || fail "J should give the picture back ($F differ)"
F=$(diff_px p0 p3); awk -v f="$F" 'BEGIN { exit !(f > 0.01) }' || fail "U changed only $F of the pixels"
F=$(diff_px p0 p4); awk -v f="$F" 'BEGIN { exit !(f > 0.01) }' || fail "Y changed only $F of the pixels"
# E: the input untouched, the edits in the written scene's numbers, its picture the edited one
cmp -s "$TMP/edit.json" "$TMP/input.json" || fail "the input scene changed"
grep -q "sss-view: edited scene written to $TMP/edit.edited.json" "$TMP/e1.err" || fail "E: $(cat "$TMP/e1.err")"
grep -q "sss-view: edited scene written to $TMP/button.json" "$TMP/view.err" || fail "the panel's button: $(cat "$TMP/view.err")"
python3 - "$TMP/edit.edited.json" "$TMP/strong.json" "$TMP/button.json" <<'P' || fail "the written scenes' materials"
import json, sys
b = json.load(open(sys.argv[3]))["objects"][0]["material"]   # the button, after the strength slider's low end:
assert "strength" not in b["field"] and all(abs(i - a) < abs(0.03 * k - a) / 16   # the inside folded near the base
                                            for i, a, k in zip(b["inside"]["sigma_a"], b["sigma_a"], (1, 2, 4))), b
m = json.load(open(sys.argv[1]))["objects"][0]["material"]
assert "preset" not in m and "strength" not in m["field"], m
assert m["sigma_a"] != [0.0021, 0.0041, 0.0071] and m["sigmap_s"] == [2.19, 2.62, 3], m   # Y: the base's sigma_a
assert all(a > 0.03 * k for a, k in zip(m["inside"]["sigma_a"], (1, 2, 4))), m   # K, then U folded in
s = json.load(open(sys.argv[2]))["objects"][0]["material"]
assert s["field"]["strength"] == 1.5625 and s["inside"] == m["inside"], s
P
F=$(diff_px p6 r0); awk -v f="$F" 'BEGIN { exit !(f < 0.002) }' || fail "the written scene draws differently ($F of the pixels)"
F=$(diff_px r0 r1); awk -v f="$F" 'BEGIN { exit !(f > 0.01) }' || fail "I I changed only $F of the pixels"
read -r w h M0 sd nonbg < <("$SSS_PNGSTATS" "$TMP/s0.png")
read -r w h M3 sd nonbg < <("$SSS_PNGSTATS" "$TMP/s3.png")
awk -v a="$M3" -v b="$M0" 'BEGIN { exit !(a > 1.05 * b) }' || fail "the panel's strength slider: mean $M3 against $M0 before"
read -r w h mean sd nonbg < <("$SSS_PNGSTATS" "$TMP/p0.png")
awk -v n="$nonbg" 'BEGIN { exit !(n > 0.02) }' || fail "p0.png is nearly empty ($nonbg of the pixels drawn)"
echo ok
