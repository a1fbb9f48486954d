# Every tool on hostile paths and hostile values (docs/robustness.md,
# "Paths"; items 2 and 6 of the adversarial pass): a FIFO, a device node
# (/dev/null, and a private one when root), a directory, a loop of symbolic
# links, a dangling link, the input itself (by name, hard link and symbolic
# link), an unwritable directory and a full small tmpfs (root only: skipped
# with a message where mounting is not permitted), as inputs and as outputs
# of sss-bake (plain and --scene), sss-stat, sss-view, sss-genmesh and
# sss-ref; and
# bad values of their options. Each refusal must be one line on stderr with
# an exit status below 128 within 20 s (a FIFO must not block), leave every
# input as it was (checksums and file types) and write nothing (the output
# directories list the same files before and after: no output, no
# temporary).
# the scratch tmpfs mounts (root only) are unmounted on every exit, and a
# run killed before its trap leaves none for the next one to trip over
unmount_scratch() {
  local d
  for d in "${1:-}/ro" "${1:-}/full"; do
    while mountpoint -q "$d" 2>/dev/null; do umount "$d" || break; done
  done
}
unmount_scratch "${1:-}"
. "$(dirname "$0")/lib.sh"
trap 'unmount_scratch "$TMP"' EXIT
# sanitizer builds preload Mesa's driver into the viewer (tests/CMakeLists.txt);
# a command, not a function, so that timeout can run it
VIEW=(env "LD_PRELOAD=${SSS_VIEW_PRELOAD:-}" "$SSS_VIEW")
# sss-stat --error draws with EGL too: lib.sh wraps it in a function for
# sanitizer builds, which timeout cannot run; the binary and its preload here
STAT=("$SSS_STAT")
[ -n "${SSS_STAT_BIN:-}" ] && STAT=(env "LD_PRELOAD=${SSS_GL_PRELOAD:-}" "$SSS_STAT_BIN")
IN=$TMP/fix OUT=$TMP/dst
mkdir -p "$IN" "$OUT"

# ---- fixtures: the inputs every run must leave as they are -----------------
"$SSS_GENMESH" sphere 2 "$IN/s.ply" >/dev/null 2>&1 || fail "genmesh"
"$SSS_BAKE" "$IN/s.ply" -o "$IN/s.sss" --dirs 12 -q 2>/dev/null || fail "bake fixture"
"$SSS_MKEXR" "$IN/sky.exr" 16 8 half RGBA 0.5 || fail "probe fixture"
cat > "$IN/scene.json" <<EOF
{"objects": [{"name": "ball", "mesh": "s.ply", "material": "marble", "mm_per_unit": 20}],
 "lights": [{"type": "directional", "direction": [0, 0, 1], "moving": true},
            {"type": "environment", "probe": "sky.exr", "intensity": 0.3}],
 "bake": {"dirs": 12, "sh_order": 2}}
EOF
ln "$IN/s.ply" "$IN/hard.ply"            # a hard link to the mesh
ln -s s.ply "$IN/link.ply"               # a symbolic link to the mesh
mkfifo "$IN/fifo.ply" "$IN/fifo.sss" "$IN/fifo.exr" "$IN/fifo.json" "$IN/fifo.png"
ln -s loop_b "$IN/loop_a.ply"; ln -s loop_a.ply "$IN/loop_b"
ln -s nothing.sss "$IN/dangling.sss"
mkdir "$IN/dir.ply" "$IN/dir.sss" "$IN/dir.png"
cp "$IN/s.sss" "$IN/keep.sss"            # an output that exists: kept unless written whole
ln -s keep.sss "$IN/keeplink.sss"
cp "$IN/scene.json" "$IN/fifo_probe.json"; sed -i 's/sky.exr/fifo.exr/' "$IN/fifo_probe.json"
cp "$IN/scene.json" "$IN/dev_probe.json"; sed -i 's#"sky.exr"#"/dev/null"#' "$IN/dev_probe.json"

state() { # the type of every entry and the checksum of every regular file, of both directories
  find "$IN" "$OUT" -mindepth 1 -printf '%P %y %l\n' | LC_ALL=C sort
  find "$IN" "$OUT" -mindepth 1 -type f -exec md5sum {} + | LC_ALL=C sort
}
state > "$TMP/state0"

# HOSTILE_KEEP_GOING=1: count the failures and go on (to see every one at
# once, e.g. against an older build); the test fails at the end.
nbad=0
bad() {
  if [ -n "${HOSTILE_KEEP_GOING:-}" ]; then echo "FAIL: $*" >&2; nbad=$((nbad + 1)); state > "$TMP/state0"; return 0; fi
  fail "$@"
}
# refused DESC CMD...: exit status 1 ... 127 within 20 s, exactly one line on
# stderr naming something, nothing on stdout, inputs and outputs unchanged.
refused() {
  local desc=$1; shift
  local t0=$SECONDS
  timeout 20 "$@" >"$TMP/so" 2>"$TMP/se"; local rc=$?
  [ -z "${HOSTILE_TIMES:-}" ] || echo "$((SECONDS - t0)) s: $desc" >&2
  n=$((n + 1))
  [ $rc -ne 124 ] || { bad "$desc: still running after 20 s (blocked?): $*"; return; }
  [ $rc -ne 126 ] && [ $rc -ne 127 ] || { bad "$desc: could not run: $*"; return; }
  [ $rc -ne 0 ] || { bad "$desc: accepted: $*"; return; }
  [ $rc -lt 128 ] || { bad "$desc: killed by signal $((rc - 128)): $*"; return; }
  [ "$(wc -l < "$TMP/se")" -eq 1 ] || { head -c 2000 "$TMP/se" >&2; bad "$desc: stderr is not one line: $*"; return; }
  [ ! -s "$TMP/so" ] || { bad "$desc: printed on stdout: $*"; return; }
  state > "$TMP/state1"
  cmp -s "$TMP/state0" "$TMP/state1" || { diff "$TMP/state0" "$TMP/state1" | head -20 >&2; bad "$desc: changed a file: $*"; }
}
n=0

# ---- hostile inputs ----------------------------------------------------------
for m in fifo.ply dir.ply loop_a.ply /dev/null missing.ply; do
  case $m in /*) p=$m ;; *) p=$IN/$m ;; esac
  refused "mesh $m" "$SSS_BAKE" "$p" -o "$OUT/x.sss" -q
done
for f in fifo.sss dir.sss dangling.sss /dev/null; do
  case $f in /*) p=$f ;; *) p=$IN/$f ;; esac
  refused "stat $f" "${STAT[@]}" "$p"
  refused "stat --query $f" "${STAT[@]}" "$p" --query 0 --light 0,0,1
  refused "view $f" "${VIEW[@]}" "$p" --offscreen --out "$OUT/x.png" --size 16x16
done
REF=("$SSS_REF" --paths 4 --threads 1 -q)
for m in fifo.ply dir.ply loop_a.ply /dev/null missing.ply; do
  case $m in /*) p=$m ;; *) p=$IN/$m ;; esac
  refused "ref mesh $m" "${REF[@]}" "$p" --light 0,0,1 --query 0 --view 0,0,1
done
for e in fifo.exr dir.ply /dev/null; do
  case $e in /*) p=$e ;; *) p=$IN/$e ;; esac
  refused "ref --env $e" "${REF[@]}" "$IN/s.ply" --env "$p" --query 0 --view 0,0,1
done
for sc in fifo.json dir.sss /dev/null fifo_probe.json dev_probe.json; do
  case $sc in /*) p=$sc ;; *) p=$IN/$sc ;; esac
  refused "scene $sc --plan" "$SSS_BAKE" --scene "$p" --plan
  refused "scene $sc" "$SSS_BAKE" --scene "$p" -o "$OUT"
  refused "view --scene $sc" "${VIEW[@]}" "$IN/s.sss" --scene "$p" --offscreen --out "$OUT/x.png" --size 16x16
done

# ---- hostile outputs ---------------------------------------------------------
for o in fifo.sss dir.sss loop_a.ply dangling.sss s.ply hard.ply link.ply; do
  refused "bake -o $o" "$SSS_BAKE" "$IN/s.ply" -o "$IN/$o" --dirs 12 -q
done
for o in fifo.png dir.png s.sss loop_a.ply dangling.sss; do
  refused "view --out $o" "${VIEW[@]}" "$IN/s.sss" --offscreen --out "$IN/$o" --size 16x16
done
refused "view --out the scene" "${VIEW[@]}" "$IN/s.sss" --scene "$IN/scene.json" --offscreen --out "$IN/scene.json" --size 16x16
# sss-ref's image and its standard error (IMG.stderr.exr): each checked
# before a path is traced, neither written when either is refused
ln -s s.ply "$IN/mesh.exr"; mkfifo "$IN/img.stderr.exr"; mkdir "$IN/dir.exr"; state > "$TMP/state0"
for o in fifo.exr dir.exr mesh.exr img.exr; do
  refused "ref --out $o" "${REF[@]}" "$IN/s.ply" --light 0,0,1 --out "$IN/$o" --size 4x4
done
refused "ref --out the probe" "${REF[@]}" "$IN/s.ply" --env "$IN/sky.exr" --out "$IN/sky.exr" --size 4x4
refused "genmesh to a FIFO" "$SSS_GENMESH" sphere 1 "$IN/fifo.ply"
refused "genmesh to a directory" "$SSS_GENMESH" sphere 1 "$IN/dir.ply"
refused "genmesh to a loop" "$SSS_GENMESH" sphere 1 "$IN/loop_a.ply"
# scene outputs: DIR/NAME.sss, checked for every object before anything is baked
ln -s ../fix/s.ply "$OUT/ball.sss"
state > "$TMP/state0"
refused "scene output is its own mesh" "$SSS_BAKE" --scene "$IN/scene.json" -o "$OUT"
rm "$OUT/ball.sss"; mkfifo "$OUT/ball.sss"; state > "$TMP/state0"
refused "scene output is a FIFO" "$SSS_BAKE" --scene "$IN/scene.json" -o "$OUT"
rm "$OUT/ball.sss"; state > "$TMP/state0"
# sss-stat --error-images: each of its six images
mkdir "$OUT/img" && mkfifo "$OUT/img/error.exr"; state > "$TMP/state0"
refused "stat --error-images with a FIFO" "${STAT[@]}" "$IN/s.sss" --error --views 2 --image-size 16 --error-images "$OUT/img"
rm -r "$OUT/img"; state > "$TMP/state0"

# a symbolic link to a regular file is followed: the link stays a link and
# the file it names is replaced whole (the policy, sss/fileio.h)
expect_ok "$SSS_BAKE" "$IN/s.ply" -o "$IN/keeplink.sss" --dirs 8 -q
[ -L "$IN/keeplink.sss" ] || fail "the output link was replaced by a file"
"$SSS_STAT" "$IN/keep.sss" | grep -q "directions 8" || fail "the link's target was not rewritten"
state > "$TMP/state0"

# device nodes as outputs: a private one first (root), then /dev/null itself
# only if the private one was refused, so a regression cannot break the
# machine's /dev/null
if [ "$(id -u)" -eq 0 ] && mknod "$TMP/node" c 1 3 2>/dev/null; then
  mv "$TMP/node" "$IN/node"; state > "$TMP/state0"
  refused "bake -o a device node" "$SSS_BAKE" "$IN/s.ply" -o "$IN/node" --dirs 8 -q
  refused "view --out a device node" "${VIEW[@]}" "$IN/s.sss" --offscreen --out "$IN/node" --size 16x16
  refused "genmesh to a device node" "$SSS_GENMESH" sphere 1 "$IN/node"
  [ -c "$IN/node" ] || fail "the private device node was replaced"
else
  echo "cli_hostile: not root (or mknod refused): the private device node part is skipped" >&2
fi
for t in "$SSS_BAKE $IN/s.ply -o /dev/null --dirs 8 -q" "$SSS_GENMESH sphere 1 /dev/null"; do
  # shellcheck disable=SC2086
  refused "/dev/null as output" $t
  [ -c /dev/null ] || fail "/dev/null is no longer a device"
done
refused "view --out /dev/null" "${VIEW[@]}" "$IN/s.sss" --offscreen --out /dev/null --size 16x16

# an unwritable directory: read-only for everyone (a read-only tmpfs when
# root, whom permission bits do not stop)
RO=$TMP/ro; mkdir -p "$RO"
ro_ok=0
if [ "$(id -u)" -eq 0 ]; then
  mount -t tmpfs -o ro,size=64k tmpfs "$RO" 2>/dev/null && ro_ok=1
else
  chmod 555 "$RO" && ro_ok=1
fi
if [ $ro_ok -eq 1 ]; then
  refused "bake into a read-only directory" "$SSS_BAKE" "$IN/s.ply" -o "$RO/x.sss" --dirs 8 -q
  refused "view into a read-only directory" "${VIEW[@]}" "$IN/s.sss" --offscreen --out "$RO/x.png" --size 16x16
  refused "genmesh into a read-only directory" "$SSS_GENMESH" sphere 1 "$RO/x.ply"
  refused "ref into a read-only directory" "${REF[@]}" "$IN/s.ply" --light 0,0,1 --out "$RO/x.exr" --size 4x4
  [ -z "$(ls -A "$RO")" ] || fail "files left in the read-only directory"
  [ "$(id -u)" -eq 0 ] && umount "$RO"
else
  echo "cli_hostile: cannot make a read-only directory (mount refused): that part is skipped" >&2
fi

# a full disk: a 64 KiB tmpfs (root only); the old file stays, nothing partial
FULL=$TMP/full; mkdir -p "$FULL"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o size=64k tmpfs "$FULL" 2>/dev/null; then
  # 60000 bytes: all but one 4 KiB page of the 64 KiB
  head -c 60000 /dev/zero > "$FULL/old.sss"; cp "$FULL/old.sss" "$TMP/old.copy"
  refused "bake onto a full disk" "$SSS_BAKE" "$IN/s.ply" -o "$FULL/old.sss" --dirs 200 -q
  refused "view onto a full disk" "${VIEW[@]}" "$IN/s.sss" --offscreen --out "$FULL/big.exr" --size 256x256
  refused "genmesh onto a full disk" "$SSS_GENMESH" sphere 6 "$FULL/big.ply"
  refused "ref onto a full disk" "$SSS_REF" "$IN/s.ply" --light 0,0,1 --paths 1 --out "$FULL/big.exr" --size 128x128 -q
  refused "stat images onto a full disk" "${STAT[@]}" "$IN/s.sss" --error --views 2 --image-size 128 --error-images "$FULL/img"
  cmp -s "$FULL/old.sss" "$TMP/old.copy" || fail "the old file on the full disk changed"
  left=$(ls -A "$FULL" | grep -v '^old.sss$' | grep -v '^img$' || true)
  [ -z "$left" ] || fail "partial or temporary files left on the full disk: $left"
  [ -z "$(ls -A "$FULL/img" 2>/dev/null)" ] || fail "partial images left on the full disk"
  umount "$FULL"
else
  echo "cli_hostile: mounting a tmpfs is not permitted here (not root?): the full-disk part is skipped" >&2
fi

# ---- hostile values ------------------------------------------------------------
for a in "--dirs 1e10" "--dirs -1" "--mm-per-unit nan" "--mm-per-unit 1e300" "--eps 2" "--eta 0" \
         "--sigma-a 1,1,1 --sigma-s nan,1,1" "--threads 99999999999" "--rings 1e30" "--theta inf"; do
  # shellcheck disable=SC2086
  refused "bake $a" "$SSS_BAKE" "$IN/s.ply" -o "$OUT/x.sss" $a
done
refused "bake sigma'_t below the dipole's range" "$SSS_BAKE" "$IN/s.ply" -o "$OUT/x.sss" --sigma-a 0,0,0 --sigma-s 1e-160,1e-160,1e-160
for a in "--size 4294967396x100" "--size 100x99999999999" "--exposure 1e38" "--intensity 1e300" \
         "--light 1e200,1e200,1e200" "--light 1e-200,0,0" "--view nan,0,1" "--shadow-size 1e9" "--bench -5"; do
  # shellcheck disable=SC2086
  refused "view $a" "${VIEW[@]}" "$IN/s.sss" --offscreen --out "$OUT/x.png" $a
done
for a in "--query -1 --light 0,0,1" "--query 99999999999999999999 --light 0,0,1" "--query 0 --light 1e200,0,0" \
         "--query 0 --light nan,0,0" "--error --views 0" "--error --exposure 1e38" "--error --image-size 99999"; do
  # shellcheck disable=SC2086
  refused "stat $a" "${STAT[@]}" "$IN/s.sss" $a
done
for a in "--size 4294967396x100" "--size 100x99999" "--paths 0" "--seconds -1" "--light 0,0,0" \
         "--light nan,0,1" "--mm-per-unit 1e300" "--eta 0" "--g 1" "--sigma-a 1,1,1 --sigma-s inf,1,1" "--threads 99999"; do
  # shellcheck disable=SC2086
  refused "ref $a" "$SSS_REF" "$IN/s.ply" --light 0,0,1 --out "$OUT/x.exr" $a
done
for a in "sphere -1" "sphere 99999999999" "nosuchshape 2" "torus 1e9" "sphere 2 inf" "sphere 2 1e300"; do
  # shellcheck disable=SC2086
  set -- $a
  refused "genmesh $a" "$SSS_GENMESH" "$1" "$2" "$OUT/x.ply" ${3:+"$3"}
done
# a file name holding a newline and an escape, in every tool's message:
# still one line, and no escape reaches the terminal
bad=$TMP/$(printf 'new\nline\033[31m')
refused "a newline in a mesh name" "$SSS_BAKE" "$bad.ply" -o "$OUT/x.sss" -q
grep -q $'\033' "$TMP/se" && fail "an escape character reached the terminal"
refused "a newline in an output name" "$SSS_BAKE" "$IN/s.ply" -o "$IN/fifo.sss/$(printf 'a\nb')" -q
refused "a newline in a .sss name" "${STAT[@]}" "$bad.sss"
refused "a newline in an option value" "${VIEW[@]}" "$IN/s.sss" --offscreen --out "$OUT/x.png" --size "$(printf '1\n2x3')"
refused "a newline in a scene name" "$SSS_BAKE" --scene "$bad.json" --plan
[ $nbad -eq 0 ] || fail "$nbad of $n checks failed"
echo "cli_hostile: ok ($n refusals)"
