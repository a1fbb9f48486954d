# sss-view --scene (docs/scenes.md): the scene's lights, summed from the
# effects the file records, drawn offscreen with the shading program only;
# a light the file has no data for is refused by its JSON path.
. "$(dirname "$0")/lib.sh"
VIEW() { if [ -n "${SSS_VIEW_PRELOAD:-}" ]; then LD_PRELOAD="$SSS_VIEW_PRELOAD" "$SSS_VIEW" "$@"; else "$SSS_VIEW" "$@"; fi; }
expect_ok "$SSS_GENMESH" blob 2 "$TMP/blob.ply"
cat > "$TMP/sun.json" <<'J'
{"objects": [{"name": "blob", "mesh": "blob.ply", "material": "skin1", "mm_per_unit": 10}],
 "lights": [{"type": "directional", "direction": [0, 0, 1], "intensity": 2}],
 "camera": {"position": [0, -3, 1], "target": [0, 0, 0], "fov_deg": 40}}
J
sed 's/"intensity": 2}/"intensity": 2}, {"type": "point", "position": [0, 0, 2], "moving": true}/' "$TMP/sun.json" > "$TMP/both.json"
expect_ok "$SSS_BAKE" --scene "$TMP/sun.json" -o "$TMP" -q
expect_ok VIEW "$TMP/blob.sss" --scene "$TMP/sun.json" --offscreen --out "$TMP/sun.png" --size 96x72
contains "$TMP/err" 'scene .*sun.json: directional-exact$'
read -r W H MEAN SD NONBG < <("$SSS_PNGSTATS" "$TMP/sun.png")
awk -v m="$MEAN" -v n="$NONBG" 'BEGIN { exit !(m > 5 && n > 0.1) }' || fail "sun.png is empty (mean $MEAN, lit $NONBG)"
expect_ok VIEW "$TMP/blob.sss" --scene "$TMP/sun.json" --offscreen --bench 3 --size 64x48
contains "$TMP/out" '"paths":"directional-exact"'
# summed on the GPU with the row program only: no shell or environment program
contains "$TMP/out" '"eval":"gpu","gpu_programs":"rows"'
# the file has no shells: a scene with a moving point light is refused by path
expect_fail 'both.json: /lights/1: the file has no data for this moving point light' \
  VIEW "$TMP/blob.sss" --scene "$TMP/both.json" --offscreen --out "$TMP/x.png"
expect_ok "$SSS_BAKE" --scene "$TMP/both.json" -o "$TMP" -q
expect_ok VIEW "$TMP/blob.sss" --scene "$TMP/both.json" --offscreen --out "$TMP/both.png" --size 96x72
contains "$TMP/err" 'directional-exact + point-shells'
contains "$TMP/err" 'summed on the gpu (programs: rows + shells)'
# the CPU sum (--cpu) draws the same image
expect_ok VIEW "$TMP/blob.sss" --scene "$TMP/both.json" --offscreen --out "$TMP/both_cpu.png" --size 96x72 --cpu
contains "$TMP/err" 'summed on the cpu'
cmp -s "$TMP/both.png" "$TMP/both_cpu.png" || fail "GPU and CPU scene sums draw different images"
# brighter with the second light
read -r W H MEAN2 SD NONBG < <("$SSS_PNGSTATS" "$TMP/both.png")
awk -v a="$MEAN" -v b="$MEAN2" 'BEGIN { exit !(b > a) }' || fail "adding a light did not brighten ($MEAN -> $MEAN2)"
# a plain bake with near terms at run time (OWNT), viewed with a scene of
# one moving light from the front: the GPU and the CPU sum draw the picture
# the plain view draws for that light (the GPU sum added the near terms
# twice, a mean 1.05 instead of 0.54 on the bunny), and --no-own-term
# removes them on both paths (docs/robustness.md item 10)
expect_ok "$SSS_BAKE" "$TMP/blob.ply" -o "$TMP/own.sss" --material skin1 --mm-per-unit 10 --own-term runtime --dirs 40 -q
cat > "$TMP/front.json" <<'J'
{"objects": [{"name": "blob", "mesh": "blob.ply", "material": "skin1", "mm_per_unit": 10}],
 "lights": [{"type": "directional", "direction": [0, 0, 1], "moving": true}]}
J
expect_ok VIEW "$TMP/own.sss" --offscreen --out "$TMP/own_plain.png" --size 96x72 --light 0,0,1
expect_ok VIEW "$TMP/own.sss" --offscreen --out "$TMP/own_rows.png" --size 96x72 --light 0,0,1 --no-own-term
for o in "" --no-own-term; do
  for c in "" --cpu; do
    # shellcheck disable=SC2086
    expect_ok VIEW "$TMP/own.sss" --scene "$TMP/front.json" --offscreen --out "$TMP/own_scene.png" --size 96x72 $c $o
    ref=$TMP/own_plain.png; [ -n "$o" ] && ref=$TMP/own_rows.png
    d=$("$SSS_PNGSTATS" "$TMP/own_scene.png" "$ref")
    [ "$d" = "0.000000" ] || fail "--scene ${c:---gpu} ${o:-(near terms on)}: $d of the pixels differ from the plain view's"
  done
done
[ "$("$SSS_PNGSTATS" "$TMP/own_plain.png" "$TMP/own_rows.png")" != "0.000000" ] || fail "--no-own-term changed nothing"
# window mode (when Xvfb and xdotool are there): the scene's lights every
# frame; a screenshot (P) is lit and the viewer quits on q
if command -v xvfb-run >/dev/null && command -v xdotool >/dev/null && command -v xauth >/dev/null; then
  cat > "$TMP/driver.sh" <<'D'
. "$WINDOW_LIB"
view_start 320 240 "$T/blob.sss" --scene "$T/both.json"
shot win key h
view_quit q
D
  run_window_driver "$TMP/driver.sh" 120 640x480x24
  [ -e "$TMP/win.png" ] || fail "no screenshot from the window"
  read -r W H MEANW SD NONBG < <("$SSS_PNGSTATS" "$TMP/win.png")
  awk -v m="$MEANW" 'BEGIN { exit !(m > 5) }' || fail "window screenshot is dark (mean $MEANW)"
  # The panel (G) switches each light kind of the scene (sss_scene_eval_set_kinds).
  # In a 640x480 window its boxes sit at (348, 364) "static suns (exact)" and
  # (348, 387) "point lights (shells)". Both off leave q = 0: the picture the
  # 2 key (scatter off) draws, reflection only, whatever time the moving
  # light has reached. The overlay and the panel (with its live frame-time
  # graph) are hidden for every screenshot that is compared; the others
  # (sync) only wait for a frame, so that the panel is drawn before the
  # pointer moves onto it and each click has been through a frame,
  # however long the frames take.
  cat > "$TMP/kinds.sh" <<'D'
. "$WINDOW_LIB"
view_start 640 480 "$T/blob.sss" --scene "$T/both.json"
click() { shot sync mousemove --window "$wid" "$1" "$2"; shot sync click 1; }
shot sync key h key g
click 348 364; click 348 387
shot off key g
shot sync key g
click 348 364; click 348 387
shot on key g
shot refl key 2
view_quit q
D
  run_window_driver "$TMP/kinds.sh" 180 800x600x24
  [ "$("$SSS_PNGSTATS" "$TMP/off.png" "$TMP/refl.png")" = "0.000000" ] ||
    fail "both light kinds off in the panel should leave reflection only, as the 2 key does"
  [ "$("$SSS_PNGSTATS" "$TMP/on.png" "$TMP/off.png")" != "0.000000" ] ||
    fail "switching the light kinds back on in the panel changed nothing"
fi
echo "view_scene: ok"
