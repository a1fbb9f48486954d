#!/bin/bash
# glTF 2.0 input at the command line (docs/robustness.md, "glTF"; README
# "glTF input"): sss-genmesh writes the assets, sss-bake imports them. A box
# bakes as its PLY does, two node instances double the vertices, texture
# coordinates and colours are reported, and damaged files (an index out of
# range, a bad accessor, a missing .bin, a truncated .glb) are refused with
# one line naming the file and the element, and no output.
. "$(dirname "$0")/lib.sh" "$1"

G=$SSS_GENMESH
expect_ok "$G" cube 2 "$TMP/box.ply"
expect_ok "$G" cube 2 "$TMP/box.gltf"
expect_ok "$G" cube 2 "$TMP/box.glb"
expect_ok "$G" cube 2 "$TMP/two.gltf" 1 two
expect_ok "$G" cube 2 "$TMP/attr.glb" 1 one+attributes
expect_fail "SCENE is for glTF output only" "$G" cube 2 "$TMP/x.ply" 1 two
[ ! -e "$TMP/x.ply" ] || fail "genmesh wrote x.ply after refusing SCENE"

# field NAME of sss-bake's JSON report, e.g. input.texcoords
field() { python3 -c 'import json,sys
d=json.load(open(sys.argv[1]))
for k in sys.argv[2].split("."): d=d[k]
print(json.dumps(d))' "$1" "$2"; }
bake() { expect_ok "$SSS_BAKE" "$TMP/$1" -o "$TMP/$2" --dirs 8 -q --json; cp "$TMP/out" "$TMP/$2.json"; }
bake box.ply box_ply.sss
bake box.gltf box_gltf.sss
bake box.glb box_glb.sss
bake two.gltf two.sss
bake attr.glb attr.sss
[ "$(field "$TMP/box_gltf.sss.json" vertices)" = 26 ] || fail "box.gltf: $(field "$TMP/box_gltf.sss.json" vertices) vertices, expected 26"
[ "$(field "$TMP/box_glb.sss.json" triangles)" = 48 ] || fail "box.glb: triangles"
[ "$(field "$TMP/two.sss.json" vertices)" = 52 ] || fail "two.gltf: $(field "$TMP/two.sss.json" vertices) vertices, expected 2 x 26"
[ "$(field "$TMP/two.sss.json" triangles)" = 96 ] || fail "two.gltf: triangles"
[ "$(field "$TMP/box_gltf.sss.json" input.texcoords)" = false ] || fail "box.gltf reports texcoords"
[ "$(field "$TMP/attr.sss.json" input.texcoords)" = true ] || fail "attr.glb: texcoords not reported"
[ "$(field "$TMP/attr.sss.json" input.colours)" = true ] || fail "attr.glb: colours not reported"
[ "$(field "$TMP/box_ply.sss.json" input.colours)" = false ] || fail "box.ply reports colours"

# The same geometry gives the same .sss: every section byte for byte, the
# provenance (PARM) too once the input's name it records is set aside.
# bake_diff A.sss B.sss NAME_A NAME_B: status 0 when they are the same.
bake_diff() { python3 - "$@" <<'PY'
import struct, sys
def sections(path, name):
    b = open(path, 'rb').read()
    n = struct.unpack_from('<I', b, 12)[0]
    out = {}
    for i in range(n):
        tag, _, off, size = struct.unpack_from('<4sIQQ', b, 24 + 40 * i)
        s = b[off:off + size]
        if tag == b'PARM':
            s = s.replace(('"mesh":"%s"' % name).encode(), b'"mesh":""')
        out[tag] = s
    return out
a, b = sections(sys.argv[1], sys.argv[3]), sections(sys.argv[2], sys.argv[4])
sys.exit(0 if a.keys() == b.keys() and all(a[t] == b[t] for t in a) else 1)
PY
}
bake_diff "$TMP/box_ply.sss" "$TMP/box_gltf.sss" box.ply box.gltf || fail "box.gltf bakes unlike box.ply"
bake_diff "$TMP/box_gltf.sss" "$TMP/box_glb.sss" box.gltf box.glb || fail "box.glb bakes unlike box.gltf"
# the comparison can fail: the sections of one box are not those of two
! bake_diff "$TMP/box_gltf.sss" "$TMP/two.sss" box.gltf two.gltf || fail "two.gltf bakes like box.gltf"

# The instances where their nodes put them (gltf_write.h): A = p + (-2, 0, 1)
# and B = (-0.5 p_y + 2, 0.5 p_x, 0.5 p_z + 1), read back from the two
# files' geometry (GEOM: nv, nf, float positions)
python3 - "$TMP/box_gltf.sss" "$TMP/two.sss" <<'PY' || fail "two.gltf: instances not where their nodes put them"
import struct, sys
def pos(path):
    b = open(path, 'rb').read()
    for i in range(struct.unpack_from('<I', b, 12)[0]):
        tag, _, off, size = struct.unpack_from('<4sIQQ', b, 24 + 40 * i)
        if tag == b'GEOM':
            nv = struct.unpack_from('<I', b, off)[0]
            return [struct.unpack_from('<3f', b, off + 8 + 12 * v) for v in range(nv)]
p, t = pos(sys.argv[1]), pos(sys.argv[2])
assert len(t) == 2 * len(p)
for v, (x, y, z) in enumerate(p):
    a, b = t[v], t[v + len(p)]
    for got, want in zip(a + b, (x - 2, y, z + 1, -0.5 * y + 2, 0.5 * x, 0.5 * z + 1)):
        assert abs(got - want) < 1e-6, (v, got, want)
PY

# damaged files: one line naming the file and the element, exit 1, no output
python3 - "$TMP" <<'PY'
import json, sys
d = sys.argv[1]
g = json.load(open(d + '/box.gltf'))
def put(name, f):
    h = json.loads(json.dumps(g)); f(h); json.dump(h, open(d + '/' + name, 'w'))
put('range.gltf', lambda h: h['accessors'][0].update(count=8))
put('accessor.gltf', lambda h: h['accessors'][0].update(componentType=5127))
put('external.gltf', lambda h: h['buffers'][0].update(uri='box.bin'))
PY
head -c 1000 "$TMP/box.glb" >"$TMP/cut.glb"
refused() {
  expect_fail "$1" "$SSS_BAKE" "$TMP/$2" -o "$TMP/bad.sss" --dirs 8
  [ "$(wc -l <"$TMP/err")" -eq 1 ] || { cat "$TMP/err" >&2; fail "$2: more than one line"; }
  contains "$TMP/err" "$TMP/$2"
  [ ! -e "$TMP/bad.sss" ] || fail "$2: an output was written"
  [ "$(find "$TMP" -name '.*' -newer "$TMP/$2" | wc -l)" -eq 0 ] || fail "$2: a temporary file was left"
}
refused "range.gltf: accessor 1: index 8 out of range \[0, 8)" range.gltf
refused "accessor.gltf: accessor 0: componentType 5127 is not one of glTF's" accessor.gltf
refused "external.gltf: buffer 0: .*box.bin" external.gltf
refused "cut.glb: GLB header: length [0-9]* but the file has 1000 bytes" cut.glb
echo "cli_gltf: ok"
