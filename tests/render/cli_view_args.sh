# sss-view's command line: every bad argument is refused before the file is
# read, with exit status 2, nothing on stdout and exactly one line on
# stderr, the same line for the same mistake; -h and --help print the usage
# on stdout unless an earlier argument was already refused.
. "$(dirname "$0")/../integration/lib.sh"
# Nothing here makes a GL context, so nothing here needs the preload of
# Mesa's driver that sanitizer builds give the viewer elsewhere
# (tests/CMakeLists.txt): without it a refusal starts in half the time
# under ASan, and a context made by mistake would show up as that driver's
# leak (the test then fails, as it should).
view() { "$SSS_VIEW" "$@"; }
# expect_msg LINE ARGS...: exit status 2, stdout empty, stderr exactly LINE
expect_msg() {
  local msg=$1; shift
  view "$@" >"$TMP/out" 2>"$TMP/err"; local rc=$?
  [ $rc -eq 2 ] || { cat "$TMP/err" >&2; fail "exit status $rc, not 2: sss-view $*"; }
  [ ! -s "$TMP/out" ] || fail "printed on stdout: sss-view $*"
  printf '%s\n' "$msg" | cmp -s - "$TMP/err" || { cat "$TMP/err" >&2; fail "stderr should be exactly '$msg': sss-view $*"; }
}
# the file is never opened for these, so it need not exist
F=$TMP/none.sss
# a value missing at the end of the line
for o in --out --screenshot --size --light --view --exposure --intensity --tonemap --exit --scene --near-visibility \
         --shadow-size --bench --diffuse --interp --sh-tables; do
  expect_msg "sss-view: $o needs a value" "$F" "$o"
done
# a value is the next argument, whatever it looks like
expect_msg "sss-view: --bench: '--size' must be an integer in [1, 100000]" "$F" --bench --size 8x8
# --size: WxH, each 1 ... 16384
# (beyond int too: 4294967396 wrapped to 100 when sscanf read it; docs/robustness.md, item 5)
for v in 0x10 10x0 10x 99999x2 2x16385 -1x5 10X10 '10x10 ' '' 4294967396x100 100x4294967396 \
         99999999999999999999x10; do
  expect_msg "sss-view: --size: '$v' must be WxH with each in [1, 16384]" "$F" --size "$v"
done
# --light and --view: three finite numbers, not all zero
for v in 1,2 1,2,3,4 1,,2 a,b,c 1,2,inf 1e-400,0,1 ''; do
  expect_msg "sss-view: --light: '$v' must be three numbers X,Y,Z" "$F" --light "$v"
done
expect_msg "sss-view: --light: '0,0,0' is not a direction" "$F" --light 0,0,0
expect_msg "sss-view: --light: '-0,0,0' is not a direction" "$F" --light -0,0,0
expect_msg "sss-view: --view: '0,0,0' is not a direction" "$F" --view 0,0,0
expect_msg "sss-view: --view: 'x,0,1' must be three numbers X,Y,Z" "$F" --view x,0,1
# a direction whose length overflows or underflows when squared: no direction
# (a huge --light drew NaN; docs/robustness.md, item 5)
for v in 1e200,1e200,1e200 1e300,0,0 1e-200,0,0; do
  expect_msg "sss-view: --light: '$v' is not a direction" "$F" --light "$v"
done
# --exposure and --intensity: a finite number > 0
# and at most 1e12 (1e38, 1e300 drew Inf/NaN; docs/robustness.md, item 5)
for v in 0 -1 inf nan 1e-310 1x '' 1e38 1e300 1.000001e12; do
  expect_msg "sss-view: --exposure: '$v' must be a number > 0 and <= 1e+12" "$F" --exposure "$v"
  expect_msg "sss-view: --intensity: '$v' must be a number > 0 and <= 1e+12" "$F" --intensity "$v"
done
# the choices
expect_msg "sss-view: --tonemap: 'Clamp' must be clamp or reinhard" "$F" --tonemap Clamp
expect_msg "sss-view: --tonemap: '' must be clamp or reinhard" "$F" --tonemap ''
expect_msg "sss-view: --exit: 'normalized' must be jensen or normalised" "$F" --exit normalized
expect_msg "sss-view: --near-visibility: 'maps' must be rays or map" "$F" --near-visibility maps
expect_msg "sss-view: --interp: 'nearest' must be triangle or nearest4" "$F" --interp nearest
expect_msg "sss-view: --sh-tables: 'ssbo' must be uniform or storage" "$F" --sh-tables ssbo
# single scattering (docs/layers.md section 8)
for o in --single --single-samples --single-march; do expect_msg "sss-view: $o needs a value" "$F" "$o"; done
expect_msg "sss-view: --single: 'maybe' must be on or off" "$F" --single maybe
expect_msg "sss-view: --single-samples: '0' must be an integer 1 ... 1024" "$F" --single-samples 0
expect_msg "sss-view: --single-samples: '2000' must be an integer 1 ... 1024" "$F" --single-samples 2000
expect_msg "sss-view: --single-march: 'x' must be segments or seed" "$F" --single-march x
# --diffuse: a share of the reflected light, in [0, 1]
for v in -0.1 1.01 nan x ''; do
  expect_msg "sss-view: --diffuse: '$v' must be a number in [0, 1]" "$F" --diffuse "$v"
done
# --shadow-size: an integer 256 ... 8192; --bench: an integer in [1, 100000]
for v in 255 8193 -512 512x 1e3 ''; do
  expect_msg "sss-view: --shadow-size: '$v' must be an integer 256 ... 8192" "$F" --shadow-size "$v"
done
for v in 0 100001 -1 1.5 99999999999999999999 ''; do
  expect_msg "sss-view: --bench: '$v' must be an integer in [1, 100000]" "$F" --bench "$v"
done
# unknown options: no --opt=value and no "--"
for a in --jsn -x -- --size=8x8 --HELP; do
  expect_msg "sss-view: unknown option '$a' (see --help)" "$F" "$a"
done
# one FILE.sss
expect_msg "sss-view: unexpected argument '$TMP/two.sss'" "$F" "$TMP/two.sss"
expect_msg "sss-view: missing FILE.sss (see --help)"
expect_msg "sss-view: missing FILE.sss (see --help)" --offscreen --size 8x8
# --offscreen needs something to do; --bench alone is enough
expect_msg "sss-view: --offscreen needs --out IMG.png|IMG.exr or --bench N" "$F" --offscreen
expect_msg "sss-view: --offscreen needs --out IMG.png|IMG.exr or --bench N" "$F" --offscreen --screenshot "$TMP/s.png"
# the first mistake is the one reported, -h included
expect_msg "sss-view: --size: '0x0' must be WxH with each in [1, 16384]" "$F" --size 0x0 --light 0,0,0
expect_msg "sss-view: --light: '0,0,0' is not a direction" "$F" --light 0,0,0 --size 0x0
expect_msg "sss-view: --size: '0x0' must be WxH with each in [1, 16384]" "$F" --size 0x0 -h
expect_msg "sss-view: unexpected argument '$TMP/two.sss'" "$F" "$TMP/two.sss" --help
for h in -h --help; do
  view "$h" --size 0x0 >"$TMP/out" 2>"$TMP/err" || fail "$h before a bad value: exit status $?"
  [ "$(head -n 1 "$TMP/out")" = "usage: sss-view FILE.sss [options]" ] || fail "$h: no usage on stdout"
  [ ! -s "$TMP/err" ] || fail "$h: printed on stderr"
done
echo "cli_view_args: ok"
