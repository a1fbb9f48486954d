# window_lib.sh: what the window tests' drivers share. A driver runs inside
# a virtual X server (run_window_driver, below) and sources this file
# ($WINDOW_LIB): it starts sss-view in a real GLX window, sends it real X
# input (xdotool, through XTEST) and checks it through the viewer's own
# screenshots (the P key). A screenshot is also the drivers' clock: the
# viewer writes it at the end of a frame, so once it is there every input
# sent before it has been through a frame, however slow the machine.
set -u
T=$TMP
pid=
fail() { echo "FAIL: $*" >&2; [ -n "$pid" ] && kill "$pid" 2>/dev/null; exit 1; }
alive() { kill -0 "$pid" 2>/dev/null; }

# view_start W H ARGS...: sss-view ARGS in a W×H window whose screenshots go
# to $T/shot.png, focused (no window manager), the pointer at its centre;
# wid is the window. SSS_VIEW_PRELOAD: sanitizer builds only, see
# tests/integration/CMakeLists.txt.
view_start() {
  local w=$1 h=$2; shift 2
  if [ -n "${SSS_VIEW_PRELOAD:-}" ]; then
    LD_PRELOAD=$SSS_VIEW_PRELOAD "$SSS_VIEW" "$@" --size "${w}x$h" --screenshot "$T/shot.png" >"$T/view.out" 2>"$T/view.err" &
  else
    "$SSS_VIEW" "$@" --size "${w}x$h" --screenshot "$T/shot.png" >"$T/view.out" 2>"$T/view.err" &
  fi
  pid=$!
  wid=$(timeout 30 xdotool search --sync --onlyvisible --name '^sss-view' 2>/dev/null | head -n 1)
  [ -n "$wid" ] || { alive || { cat "$T/view.err" >&2; fail "sss-view exited before showing a window"; }; fail "no sss-view window within 30 s"; }
  # pointer coordinates below are relative to the window
  xdotool mousemove --window "$wid" $((w / 2)) $((h / 2)) windowfocus "$wid" || fail "xdotool could not reach the window"
}

# shot NAME [XDOTOOL-COMMANDS...]: send the commands and then P in one
# xdotool run (one X connection, so the server sees them in this order),
# wait for the PNG (the viewer renames it into place when complete) and
# keep it as $T/NAME.png.
shot() {
  local name=$1; shift
  rm -f "$T/shot.png"
  xdotool "$@" key p || fail "xdotool failed: $*"
  local i
  for i in $(seq 600); do
    [ -e "$T/shot.png" ] && break
    alive || { cat "$T/view.err" >&2; fail "sss-view died during: $*"; }
    sleep 0.05
  done
  [ -e "$T/shot.png" ] || fail "no screenshot 30 s after: $* P"
  mv "$T/shot.png" "$T/$name.png"
}
same() { cmp -s "$T/$1.png" "$T/$2.png" || fail "$1.png and $2.png should be identical ($3)"; }
differ() { cmp -s "$T/$1.png" "$T/$2.png" && fail "$1.png and $2.png should differ ($3)"; return 0; }

# view_quit [KEY]: Escape (or KEY) must end the viewer with status 0 within 10 s.
view_quit() {
  xdotool key "${1:-Escape}" || fail "xdotool could not send ${1:-Escape}"
  local i rc
  for i in $(seq 200); do alive || break; sleep 0.05; done
  alive && fail "sss-view still running 10 s after ${1:-Escape}"
  wait "$pid"; rc=$?
  pid=
  [ $rc -eq 0 ] || { cat "$T/view.err" >&2; fail "sss-view exited with status $rc"; }
}
