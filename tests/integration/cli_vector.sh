# sss-bake --vector (section QVEC, docs/format.md §5.19): refused without
# --quant and with --scene, one line and exit status 2; a float and a
# lloyd8 bake carry Q at 12 bytes per direction, vertex and channel, in
# format 1.7, the same bytes at any thread count; sss-stat reads it,
# measures Q and q side by side (--error), measures q alone with
# --no-vector, and refuses a file whose QVEC bytes were changed, naming the
# section.
. "$(dirname "$0")/lib.sh"
cd "$TMP" || fail "cd $TMP"
expect_ok "$SSS_GENMESH" blob 2 m.ply 10
B=(m.ply --material skin1 --dirs 30 -q)

"$SSS_BAKE" "${B[@]}" -o c.sss --vector >out 2>err && fail "--vector without --quant accepted"
[ "$(cat err)" = "sss-bake: --vector needs --quant float or lloyd8 (Q is not compressed)" ] || fail "message: $(cat err)"
[ ! -e c.sss ] || fail "a refused bake wrote its output"
echo '{"objects":[]}' > s.json
expect_fail "sss-bake: --vector applies to plain bakes, not to --scene" "$SSS_BAKE" --scene s.json -o s.sss --vector
expect_fail "sss-bake: --vector applies to plain bakes, not to --point-light (a scene's object has no Q)" \
    "$SSS_BAKE" m.ply --point-light 0,0,3 -o p.sss --vector

expect_ok "$SSS_BAKE" "${B[@]}" --quant float -o q.sss
expect_ok "$SSS_BAKE" "${B[@]}" --quant float --vector -o v.sss --threads 1
expect_ok "$SSS_BAKE" "${B[@]}" --quant float --vector -o v2.sss --threads 2
cmp -s v.sss v2.sss || fail "--vector: the bytes depend on the thread count"
expect_ok "$SSS_BAKE" "${B[@]}" --quant lloyd8 --vector -o l.sss
for f in v l; do
  expect_ok "$SSS_STAT" $f.sss --json
  python3 - "$TMP/out" <<'PY' || fail "$f.sss: sss-stat's sections"
import json, sys
s = json.load(open(sys.argv[1]))
sec = {e["tag"].strip(): e for e in s["sections"]}
n, nv, C = s["directions"], s["vertices"], s["channels"]
assert s["format_version"] == "1.7", s["format_version"]
assert sec["QVEC"]["bytes"] == 12 * n * nv * C and sec["QVEC"]["count"] == 3 * n * nv * C, sec["QVEC"]
PY
done
expect_ok "$SSS_STAT" q.sss --json
grep -q QVEC "$TMP/out" && fail "a bake without --vector holds QVEC"

# measured from Q, and from q with --no-vector: two different reconstructions
expect_ok "$SSS_STAT" v.sss --error --views 20 --image-views 2 --image-size 32 --json
contains "$TMP/out" '"scalar_q"'
contains "$TMP/out" '"q_vs_Q_rms_max"'
cp "$TMP/out" e_Q.json
expect_ok "$SSS_STAT" v.sss --error --views 20 --no-image --no-vector --json
cp "$TMP/out" e_q.json
python3 - e_Q.json e_q.json <<'PY' || fail "q and Q measure the same"
import json, sys
a, b = (json.load(open(p))["vertex_error"]["rel_rms_all"] for p in sys.argv[1:])
assert a > 0 and b > 0 and a != b, (a, b)
PY

# a changed value inside QVEC: its checksum no longer matches
python3 - v.sss bad.sss <<'PY'
import struct, sys
b = bytearray(open(sys.argv[1], "rb").read())
n = struct.unpack_from("<I", b, 12)[0]
for i in range(n):
    e = 24 + 40 * i
    if b[e:e + 4] == b"QVEC":
        off = struct.unpack_from("<Q", b, e + 8)[0]
        b[off + 100] ^= 0x40
open(sys.argv[2], "wb").write(b)
PY
expect_fail "bad.sss.*QVEC" "$SSS_STAT" bad.sss
[ "$(wc -l < "$TMP/err")" -eq 1 ] || fail "more than one line: $(cat "$TMP/err")"
echo "cli_vector: ok"
