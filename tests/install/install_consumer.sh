# The installed tree as an engine sees it (docs/install.md): `cmake --install`
# into a prefix, then a small program (tests/install/consumer/) copied to a
# directory outside the source and build trees and built from the prefix
# alone, with find_package(sss) and with pkg-config, against libsss.so and
# libsss.a. Each of the four decodes q for a light from files baked by the
# installed tools and must print what sss-stat prints, bit for bit; the
# shared ones must load the installed libsss.so.MAJOR.MINOR. A second
# program links libsss_bake and libsss_render the same four ways.
. "$(dirname "$0")/../integration/lib.sh"
: "${SSS_BUILD:?}" "${SSS_SOURCE:?}" "${SSS_CC:?}" "${SSS_LIBDIR:?}" "${SSS_VERSION:?}"
HERE=$(cd "$(dirname "$0")" && pwd)
OUTSIDE=$(mktemp -d "${TMPDIR:-/tmp}/sss-install.XXXXXX") || fail "no temporary directory"
trap 'rm -rf "$OUTSIDE"' EXIT
case "$OUTSIDE/" in "$SSS_SOURCE"/*|"$SSS_BUILD"/*) fail "$OUTSIDE lies inside the source or build tree";; esac
P=$OUTSIDE/prefix
LIB=$P/$SSS_LIBDIR

# ---- install ---------------------------------------------------------------
expect_ok cmake --install "$SSS_BUILD" --prefix "$P"
for t in sss-bake sss-stat sss-ref sss-view sss-genmesh; do
  [ -x "$P/bin/$t" ] || fail "$t not installed in $P/bin"
done
IFS=. read -r MAJ MIN _ <<<"$SSS_VERSION"
# 0.x: the SONAME carries major.minor (common/cmake/sss_library.cmake)
if [ "$MAJ" -eq 0 ]; then SOVER=$MAJ.$MIN; else SOVER=$MAJ; fi
for l in sss sss_bake sss_render; do
  [ -f "$LIB/lib$l.a" ] || fail "lib$l.a not installed"
  [ -f "$LIB/lib$l.so.$SSS_VERSION" ] && [ ! -L "$LIB/lib$l.so.$SSS_VERSION" ] || fail "lib$l.so.$SSS_VERSION not installed"
  [ "$(readlink "$LIB/lib$l.so")" = "lib$l.so.$SOVER" ] || fail "lib$l.so should link to lib$l.so.$SOVER"
  [ "$(readlink "$LIB/lib$l.so.$SOVER")" = "lib$l.so.$SSS_VERSION" ] || fail "lib$l.so.$SOVER should link to lib$l.so.$SSS_VERSION"
  readelf -d "$LIB/lib$l.so.$SSS_VERSION" | grep -q "(SONAME).*\[lib$l.so.$SOVER\]" || fail "lib$l.so: SONAME should be lib$l.so.$SOVER"
done
for f in sssConfig.cmake sssConfigVersion.cmake sss-targets.cmake sss-bake-targets.cmake sss-render-targets.cmake; do
  [ -f "$LIB/cmake/sss/$f" ] || fail "$f not installed in $LIB/cmake/sss"
done
# every installed header compiles on its own with the prefix as the only
# include directory: it includes installed headers only
# (one translation unit per file named)
headers=("$P"/include/sss/*.h)
n=${#headers[@]}
expect_ok "$SSS_CC" -std=c11 -Wall -Wextra -Werror -fsyntax-only -I"$P/include" -x c "${headers[@]}"
[ "$n" -ge 30 ] || fail "only $n headers installed in $P/include/sss"
[ -f "$P/include/sss/render.h" ] || fail "sss/render.h not installed"
echo "installed: $n headers, SONAME lib*.so.$SOVER"

# ---- files from the installed tools ---------------------------------------
# --own-term baked: q holds the near terms, so sss_decode_all gives what
# sss-stat --query reconstructs (a runtime own term is added by the reader)
expect_ok "$P/bin/sss-genmesh" blob 2 "$OUTSIDE/b.ply"
MESH=$(sed -n 's/.*: \([0-9]*\) vertices, \([0-9]*\) triangles.*/vertices \1 triangles \2/p' "$TMP/err")
[ -n "$MESH" ] || fail "sss-genmesh did not say the mesh's size"
for quant in refs float; do
  form=; [ $quant = float ] && form="--quant float" # compressed (references + SH) is the default
  expect_ok "$P/bin/sss-bake" "$OUTSIDE/b.ply" -o "$OUTSIDE/$quant.sss" --material skin1 --mm-per-unit 20 \
    --dirs 20 $form --own-term baked -q
  expect_ok "$P/bin/sss-stat" "$OUTSIDE/$quant.sss" --json
  contains "$TMP/out" "\"$quant\""
done

# ---- the consumer, built from the prefix alone -----------------------------
C=$OUTSIDE/consumer
cp -r "$HERE/consumer" "$C"
# the sanitizers' runtime, when the libraries were built with them
CF=${SSS_CONSUMER_FLAGS:-}
expect_ok cmake -S "$C" -B "$C/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER="$SSS_CC" \
  -DCMAKE_C_FLAGS="$CF" -DCMAKE_PREFIX_PATH="$P" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
expect_ok cmake --build "$C/build"
expect_ok env PKG_CONFIG_PATH="$LIB/pkgconfig" CFLAGS="$CF" make -C "$C" CC="$SSS_CC"
# nothing the builds read or wrote names the source or the build tree (text
# files: the build files, the compiler's dependency lists; the programs
# themselves carry the archives' debugging paths in a Debug build)
if grep -rlIF -e "$SSS_SOURCE/" -e "$SSS_BUILD/" "$C" >"$TMP/leak"; then
  cat "$TMP/leak" >&2; fail "the consumer's build names the source or build tree"
fi
BINS="$C/build/consumer-shared $C/build/consumer-static $C/consumer-shared $C/consumer-static"
LAYERS="$C/build/layers-shared $C/build/layers-static $C/layers-shared $C/layers-static"

# shared: needs exactly the libraries it uses, by SONAME, and loads them
# from the prefix; static: needs none of them
for b in $BINS $LAYERS; do
  needed=$(readelf -d "$b" | sed -n 's/.*(NEEDED).*\[\(libsss[^]]*\)\].*/\1/p' | sort | tr '\n' ' ')
  case "$b" in
    */consumer-shared) want="libsss.so.$SOVER ";;
    */layers-shared) want="libsss.so.$SOVER libsss_bake.so.$SOVER libsss_render.so.$SOVER ";; # sss_mesh_free: libsss
    *) want=;;
  esac
  [ "$needed" = "$want" ] || fail "$b should need '$want', needs '$needed'"
  for so in $needed; do
    got=$(ldd "$b" | sed -n "s/^[[:space:]]*$so => \([^ ]*\) .*/\1/p")
    [ -n "$got" ] && [ "$(realpath "$got")" = "$(realpath "$LIB/${so%.$SOVER}.$SSS_VERSION")" ] ||
      fail "$b loads $so from '$got', not from $LIB"
  done
done
# libsss_bake and libsss_render with everything they pull in, both ways
for b in $LAYERS; do
  expect_ok "$b" "$OUTSIDE/b.ply"
  contains "$TMP/out" "^$MESH exposure "
done
echo "libsss_bake + libsss_render: $MESH from 4 programs"

# ---- each decodes what the tools decode -------------------------------------
# sss-stat prints the float q as a double through cJSON, whose shortest form
# may stop short of the float's exact value by ~1e-15 relatively; two
# different floats differ by at least 2^-24 ≈ 6e-8 relatively, so agreeing
# within 1e-12 is being the same float.
same_floats() {
  awk -v a="$1" -v b="$2" 'BEGIN { n = split(a, x, " "); m = split(b, y, " ");
    if (n != m || n == 0) exit 1;
    for (i = 1; i <= n; i++) { d = x[i] - y[i]; if (d < 0) d = -d; s = y[i] < 0 ? -y[i] : y[i];
      if (d > 1e-12 * s) exit 1 } }'
}
for file in refs float; do
  for light in 0.3,0.5,0.8 -0.6,0.1,-0.2; do
    lit=0 sums=
    for v in 0 60 100 120; do
      expect_ok "$P/bin/sss-stat" "$OUTSIDE/$file.sss" --query $v --light $light --json
      want=$(sed -n 's/.*"reconstructed":\[\([^]]*\)\].*/\1/p' "$TMP/out" | tr ',' ' ')
      [ -n "$want" ] || fail "sss-stat --query printed no reconstructed values"
      for b in $BINS; do
        expect_ok "$b" "$OUTSIDE/$file.sss" $light $v
        got=$(sed -n 's/^q //p' "$TMP/out")
        same_floats "$got" "$want" || fail "$b $file.sss light $light vertex $v: q = $got, sss-stat says $want"
        sums="$sums$(sed -n 's/.*checksum //p' "$TMP/out")
"
      done
      awk -v a="$got" 'BEGIN { exit !(a + 0 > 0) }' && lit=$((lit + 1))
    done
    # the vertices chosen hold lit and shadowed ones: a value was compared
    [ $lit -ge 2 ] || fail "$file.sss light $light: only $lit of the vertices tried are lit"
    [ "$(printf '%s' "$sums" | sort -u | wc -l)" -eq 1 ] || fail "$file.sss light $light: the consumers' checksums differ: $sums"
    echo "$file.sss light $light: $lit of 4 vertices lit, q equal to sss-stat's; checksum $(printf '%s' "$sums" | head -1) from all 4 consumers"
  done
done

# The Python package from the prefix alone (docs/python.md §2): it finds
# the installed libsss.so, not the build's, and decodes what sss-stat says.
if [ -n "${SSS_PYTHON3:-}" ] && [ -z "${SSS_CONSUMER_FLAGS:-}" ]; then
  PYDIR=$LIB/python3/dist-packages
  [ -f "$PYDIR/sss/__init__.py" ] || fail "the Python package is not installed in $PYDIR"
  want=$(sed -n 's/.*"reconstructed":\[\([^]]*\)\].*/\1/p' <("$P/bin/sss-stat" "$OUTSIDE/float.sss" --query 1 --light 0.3,0.5,0.8 --json) | tr ',' ' ')
  expect_ok env -u SSS_LIBRARY PYTHONPATH="$PYDIR" "$SSS_PYTHON3" -c "
import os, sss
lib = os.path.realpath(sss.library_path())
assert lib.startswith(os.path.realpath('$LIB') + '/'), lib
with sss.open('$OUTSIDE/float.sss') as a:
    print(lib, *(repr(float(x)) for x in a.decode([0.3, 0.5, 0.8])[1]))"
  got=$(cut -d' ' -f2- "$TMP/out")
  same_floats "$got" "$want" || fail "installed Python package: q = $got, sss-stat says $want"
  echo "python: $(cat "$TMP/out")"
fi
echo "ok"
