# Shared helpers for the integration scripts: fail with a message, expect
# success/failure of a command, check a file contains a pattern.
set -u
TMP=${1:?scratch dir}
rm -rf "$TMP" && mkdir -p "$TMP"
fail() { echo "FAIL: $*" >&2; exit 1; }
expect_ok() { "$@" >"$TMP/out" 2>"$TMP/err" || { cat "$TMP/err" >&2; fail "expected success: $*"; }; }
# expect_fail PATTERN CMD...: non-zero exit, a one-line message matching PATTERN, no crash (exit < 128)
expect_fail() {
  local pat=$1; shift
  "$@" >"$TMP/out" 2>"$TMP/err"; local rc=$?
  [ $rc -ne 0 ] || fail "expected failure: $*"
  [ $rc -lt 128 ] || fail "crashed with signal $((rc - 128)): $*"
  grep -q -- "$pat" "$TMP/err" || { cat "$TMP/err" >&2; fail "message should match '$pat': $*"; }
}
contains() { grep -q -- "$2" "$1" || { cat "$1" >&2; fail "$1 should contain '$2'"; }; }
# Sanitizer builds: sss-stat --error creates an EGL context, so it runs with
# Mesa's driver preloaded (SSS_GL_PRELOAD, see tests/CMakeLists.txt);
# "$SSS_STAT" then names this function.
if [ -n "${SSS_GL_PRELOAD:-}" ] && [ -n "${SSS_STAT:-}" ]; then
  SSS_STAT_BIN=$SSS_STAT
  sss_stat_preloaded() { LD_PRELOAD=$SSS_GL_PRELOAD "$SSS_STAT_BIN" "$@"; }
  SSS_STAT=sss_stat_preloaded
fi
# run_window_driver DRIVER SECONDS [SCREEN]: the window test's driver script
# (which sources $WINDOW_LIB, window_lib.sh) inside a virtual X server,
# within SECONDS; SCREEN defaults to 1024x768x24.
run_window_driver() {
  local drv=$1 secs=$2 screen=${3:-1024x768x24} rc
  for tool in xvfb-run xauth xdotool; do
    command -v "$tool" >/dev/null 2>&1 || fail "$tool is not installed (scripts/setup.sh installs it)"
  done
  export TMP SSS_VIEW SSS_VIEW_PRELOAD="${SSS_VIEW_PRELOAD:-}" WINDOW_LIB="$(dirname "${BASH_SOURCE[0]}")/window_lib.sh"
  timeout "$secs" xvfb-run -a -e "$TMP/xvfb.err" -s "-screen 0 $screen -nolisten tcp" bash "$drv"
  rc=$?
  [ $rc -eq 0 ] || { cat "$TMP/xvfb.err" >&2; fail "window driver $(basename "$drv") failed (status $rc$([ $rc -eq 124 ] && echo ", timed out"))"; }
}
