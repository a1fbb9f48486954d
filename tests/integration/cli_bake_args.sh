# sss-bake's command line: every refusal is the exact message below on
# stderr (one line), nothing on stdout,
# exit status 2, and nothing is imported or written; -h/--help prints the
# usage on stdout with exit status 0 wherever it stands, unless an error
# comes before it. Messages of other scripts (cli_bad_input, cli_bake_stat,
# cli_scene) are matched there by pattern and repeated here exactly.
. "$(dirname "$0")/lib.sh"
# expect_arg_error MESSAGE CMD...: exit status 2, stderr exactly MESSAGE, stdout empty
expect_arg_error() {
  local msg=$1; shift
  "$@" >"$TMP/out" 2>"$TMP/err"; local rc=$?
  [ $rc -eq 2 ] || { cat "$TMP/err" >&2; fail "expected exit status 2, got $rc: $*"; }
  [ "$(cat "$TMP/err")" = "$msg" ] && [ "$(tail -c 1 "$TMP/err")" = "" ] ||
    { printf 'got:  %s\nwant: %s\n' "$(cat "$TMP/err")" "$msg" >&2; fail "message: $*"; }
  [ ! -s "$TMP/out" ] || fail "stdout should be empty: $*"
}
expect_ok "$SSS_GENMESH" sphere 1 "$TMP/m.ply"
cd "$TMP" || fail "cd $TMP"
T=sss-bake
B=(m.ply -o x.sss)

# a value missing at the end of the line
for o in -o --out --material --sigma-a --sigma-s --g --eta --mm-per-unit --dirs --eps --quant --compress --sh-order \
         --refs --sh-quant --weight-bits --illum-refs --gather --own-term --rings --near-fraction --preset --theta --threads --scene; do
  expect_arg_error "$T: $o needs a value" "$SSS_BAKE" m.ply $o
done

# values out of range at both ends, or not numbers
expect_arg_error "$T: --eta: '0.0009' must be a number in [0.001, 1000]" "$SSS_BAKE" "${B[@]}" --eta 0.0009
expect_arg_error "$T: --eta: '1001' must be a number in [0.001, 1000]" "$SSS_BAKE" "${B[@]}" --eta 1001
expect_arg_error "$T: --eta: 'nan' must be a number in [0.001, 1000]" "$SSS_BAKE" "${B[@]}" --eta nan
expect_arg_error "$T: --mm-per-unit: '0' must be a number in [1e-12, 1e+12]" "$SSS_BAKE" "${B[@]}" --mm-per-unit 0
expect_arg_error "$T: --mm-per-unit: '1e13' must be a number in [1e-12, 1e+12]" "$SSS_BAKE" "${B[@]}" --mm-per-unit 1e13
expect_arg_error "$T: --dirs: '100001' must be an integer in [1, 100000]" "$SSS_BAKE" "${B[@]}" --dirs 100001
expect_arg_error "$T: --dirs: '-1' must be an integer in [1, 100000]" "$SSS_BAKE" "${B[@]}" --dirs -1
expect_arg_error "$T: --dirs: '1.0' must be an integer in [1, 100000]" "$SSS_BAKE" "${B[@]}" --dirs 1.0
expect_arg_error "$T: --eps: '0' must be a number in [1e-12, 0.5]" "$SSS_BAKE" "${B[@]}" --eps 0
expect_arg_error "$T: --eps: '0.6' must be a number in [1e-12, 0.5]" "$SSS_BAKE" "${B[@]}" --eps 0.6
expect_arg_error "$T: --sh-order: '-1' must be an integer in [0, 8]" "$SSS_BAKE" "${B[@]}" --sh-order -1
expect_arg_error "$T: --refs: '-0.1' must be a number in [0, 1]" "$SSS_BAKE" "${B[@]}" --refs -0.1
expect_arg_error "$T: --weight-bits: '7' must be an integer in [8, 16]" "$SSS_BAKE" "${B[@]}" --weight-bits 7
expect_arg_error "$T: --weight-bits: '17' must be an integer in [8, 16]" "$SSS_BAKE" "${B[@]}" --weight-bits 17
expect_arg_error "$T: --weight-bits: '12' must be 8 or 16" "$SSS_BAKE" "${B[@]}" --weight-bits 12
expect_arg_error "$T: --illum-refs: '0' must be a number in [1e-09, 1e+09]" "$SSS_BAKE" "${B[@]}" --illum-refs 0
expect_arg_error "$T: --illum-refs: '2e9' must be a number in [1e-09, 1e+09]" "$SSS_BAKE" "${B[@]}" --illum-refs 2e9
expect_arg_error "$T: --theta: '0' must be a number in [0.001, 0.95]" "$SSS_BAKE" "${B[@]}" --theta 0
expect_arg_error "$T: --theta: '0.96' must be a number in [0.001, 0.95]" "$SSS_BAKE" "${B[@]}" --theta 0.96
expect_arg_error "$T: --threads: '0' must be an integer in [1, 1024]" "$SSS_BAKE" "${B[@]}" --threads 0
expect_arg_error "$T: --threads: '1025' must be an integer in [1, 1024]" "$SSS_BAKE" "${B[@]}" --threads 1025
expect_arg_error "$T: --rings: '1.5' must be an integer 0 ... 8" "$SSS_BAKE" "${B[@]}" --own-term runtime --rings 1.5
# one line, not the number's message and then the row's (docs/robustness.md, item 9)
expect_arg_error "$T: --rings: '9' must be an integer 0 ... 8" "$SSS_BAKE" "${B[@]}" --own-term runtime --rings 9
expect_arg_error "$T: --rings: '1e30' must be an integer 0 ... 8" "$SSS_BAKE" "${B[@]}" --own-term runtime --rings 1e30
expect_arg_error "$T: --near-fraction: '0.3' must be a number in [0.5, 0.999]" "$SSS_BAKE" "${B[@]}" --own-term runtime --near-fraction 0.3
expect_arg_error "$T: --near-fraction: '1' must be a number in [0.5, 0.999]" "$SSS_BAKE" "${B[@]}" --own-term runtime --near-fraction 1
expect_arg_error "$T: --sigma-a: '1,2' must be three numbers X,Y,Z" "$SSS_BAKE" "${B[@]}" --sigma-a 1,2
expect_arg_error "$T: --sigma-s: 'inf,1,1' must be three numbers X,Y,Z" "$SSS_BAKE" "${B[@]}" --sigma-s inf,1,1
expect_arg_error "$T: --g: '1' must be a number in [-0.99, 0.99]" "$SSS_BAKE" "${B[@]}" --g 1
expect_arg_error "$T: --g: '-0.995' must be a number in [-0.99, 0.99]" "$SSS_BAKE" "${B[@]}" --g -0.995

# choices
expect_arg_error "$T: --quant: 'bf16' must be float or lloyd8" "$SSS_BAKE" "${B[@]}" --quant bf16
expect_arg_error "$T: --compress: 'tiny' must be paper, compact or paper-sh" "$SSS_BAKE" "${B[@]}" --compress tiny
expect_arg_error "$T: --sh-quant: 'lloyd2' must be linear8, lloyd8, lloyd4 or linear16" "$SSS_BAKE" "${B[@]}" --sh-quant lloyd2
expect_arg_error "$T: --gather: '' must be direct or tree" "$SSS_BAKE" "${B[@]}" --gather ''
expect_arg_error "$T: --own-term: 'both' must be runtime or baked" "$SSS_BAKE" "${B[@]}" --own-term both
expect_arg_error "$T: material 'jelly': unknown preset (known: apple, chicken1, chicken2, cream, ketchup, marble, potato, skimmilk, skin1, skin2, wholemilk)" \
  "$SSS_BAKE" "${B[@]}" --material jelly

# the arguments themselves
expect_arg_error "$T: unknown option '--frobnicate' (see --help)" "$SSS_BAKE" "${B[@]}" --frobnicate
expect_arg_error "$T: unknown option '--out=x.sss' (see --help)" "$SSS_BAKE" m.ply --out=x.sss
expect_arg_error "$T: unexpected argument 'n.ply' (one MESH only)" "$SSS_BAKE" m.ply n.ply -o x.sss
expect_arg_error "$T: missing MESH (see --help)" "$SSS_BAKE" -o x.sss
expect_arg_error "$T: missing MESH (see --help)" "$SSS_BAKE"
expect_arg_error "$T: missing -o OUT.sss (see --help)" "$SSS_BAKE" m.ply

# combinations, in the order they are checked
echo '{"objects": [{"name": "m", "mesh": "m.ply", "material": "marble"}]}' > s.json
expect_arg_error "$T: --plan needs --scene S.json" "$SSS_BAKE" "${B[@]}" --plan --rings 2
expect_arg_error "$T: --rings needs --own-term runtime" "$SSS_BAKE" "${B[@]}" --own-term baked --rings 2
expect_arg_error "$T: --rings needs --own-term runtime" "$SSS_BAKE" "${B[@]}" --own-term runtime --own-term baked --rings 2
expect_arg_error "$T: --near-fraction needs --own-term runtime" "$SSS_BAKE" "${B[@]}" --own-term baked --near-fraction 0.9
for x in "--dirs 200" "--weights hat" "--own-term baked" "--quant float" "--compress compact" "--sh-order 3" "--refs 0.03"; do
  # shellcheck disable=SC2086
  expect_arg_error "$T: --preset paper is the paper's configuration exactly: not with ${x%% *}" \
    "$SSS_BAKE" "${B[@]}" --preset paper $x
done
for x in "--sh-quant linear8" "--sh-order 3" "--refs 0.03" "--own-term baked"; do
  # shellcheck disable=SC2086
  expect_arg_error "$T: --preset paper-sh is the paper's configuration exactly: not with ${x%% *}" \
    "$SSS_BAKE" "${B[@]}" --preset paper-sh $x
done
expect_arg_error "$T: --preset: 'compact' must be paper or paper-sh" "$SSS_BAKE" "${B[@]}" --preset compact
expect_arg_error "$T: --preset applies to plain bakes, not to --scene" "$SSS_BAKE" --scene s.json --preset paper
for x in "--rings 1" "--near-radius 2"; do
  # shellcheck disable=SC2086
  expect_arg_error "$T: --near-fraction sizes the near terms by the material: not with --rings or --near-radius" \
    "$SSS_BAKE" "${B[@]}" --own-term runtime $x --near-fraction 0.9
done
expect_arg_error "$T: --own-term applies to plain bakes, not to --scene (a scene's \"bake\" object sets near_terms)" \
  "$SSS_BAKE" --scene s.json --own-term runtime m.ply
for x in "--weights point" "--quant float" "--compress paper" "--near-fraction 0.9" "--refs 0.1"; do
  # shellcheck disable=SC2086
  expect_arg_error "$T: ${x%% *} applies to plain bakes, not to --scene (a scene's \"bake\" object sets weights, compress and near_terms: docs/scenes.md)" \
    "$SSS_BAKE" --scene s.json $x
done
expect_arg_error "$T: --scene and a MESH argument exclude each other (the scene names the meshes)" \
  "$SSS_BAKE" --scene s.json m.ply --quant lloyd8 --sh-order 0
for c in "--compress paper" "--sh-order 3" "--refs 0.1" "--sh-quant lloyd4" "--weight-bits 8" "--ls-weights" "--illum-refs 1"; do
  expect_arg_error "$T: --quant and the compression options (--sh-order, --refs, ...) exclude each other" \
    "$SSS_BAKE" "${B[@]}" --quant float $c --sh-order 0
done
expect_arg_error "$T: --sh-order 0 needs --refs FRACTION > 0 (nothing would be stored)" "$SSS_BAKE" "${B[@]}" --sh-order 0
expect_arg_error "$T: --refs 0 (SH only) needs --sh-order >= 1" "$SSS_BAKE" "${B[@]}" --refs 0 --sh-order 0
expect_arg_error "$T: --sh-order 0 needs --refs FRACTION > 0 (nothing would be stored)" "$SSS_BAKE" --sh-order 0
expect_arg_error "$T: give either --material NAME or both --sigma-a and --sigma-s" "$SSS_BAKE" "${B[@]}" --sigma-a 1,1,1
expect_arg_error "$T: give either --material NAME or both --sigma-a and --sigma-s" \
  "$SSS_BAKE" "${B[@]}" --sigma-a 1,1,1 --sigma-s 1,1,1 --material marble
expect_arg_error "$T: --scene needs -o DIR (one NAME.sss per object) or --plan" "$SSS_BAKE" --scene s.json
[ ! -e x.sss ] || fail "a refused command line left x.sss"

# -h / --help: the usage on stdout, exit 0, wherever it stands ("-o -h" takes
# it as the file name); an error before it is reported instead
for args in "-h" "--help" "m.ply -h" "-h m.ply n.ply" "--rings 2 -h" "-o -h -h"; do
  read -r -a a <<<"$args"
  "$SSS_BAKE" "${a[@]}" >"$TMP/out" 2>"$TMP/err" || fail "$args: exit status $?"
  head -1 "$TMP/out" | grep -q '^usage: sss-bake MESH -o OUT.sss \[options\]$' || fail "$args: no usage on stdout"
  [ ! -s "$TMP/err" ] || fail "$args: stderr should be empty"
done
expect_arg_error "$T: unknown option '--frobnicate' (see --help)" "$SSS_BAKE" --frobnicate -h
expect_arg_error "$T: --dirs: '0' must be an integer in [1, 100000]" "$SSS_BAKE" "${B[@]}" --dirs 0 -h
expect_arg_error "$T: missing MESH (see --help)" "$SSS_BAKE" -o -h
# --g makes --sigma-s the scattering sigma_s: sigma'_s = sigma_s (1 - g) feeds
# the dipole, g goes to section PHAS and the file is 1.8 (docs/layers.md §2)
expect_ok "$SSS_BAKE" "${B[@]}" --sigma-a 0.1,0.1,0.1 --sigma-s 2,2,4 --g 0.5 --dirs 20 -q
expect_ok "$SSS_STAT" x.sss --json
contains "$TMP/out" '"format_version":"1.8"'
contains "$TMP/out" '"sigmap_s":\[1,1,2\],"eta":1.3,"g":0.5}'
expect_ok "$SSS_BAKE" "${B[@]}" --material marble --dirs 20 -q
expect_ok "$SSS_STAT" x.sss --json
! grep -q '"format_version":"1.8"' "$TMP/out" || fail "an isotropic bake is not 1.8"
rm -f x.sss
echo "cli_bake_args: ok"
