#!/usr/bin/env bash
# The model error of the dipole (docs/accuracy.md, "Model error: the dipole
# against the light transport"): the radiance the viewer shows for a float
# bake with default settings, E q F_t(eta, n.w_o), against sss-ref's
# path-traced reference of the same mesh, size, material and light, next to
# the approximation error against the exact evaluator; and the pictures
# real-time | reference | difference.
#
#   data/fetch.sh                  # the Stanford meshes (once)
#   tests/bench/model_error.sh     # BUILD=build OUT=out/model_error
#
# The tessellation rows of the section: tests/bench/split_mesh bunny.ply
# bunny_sK.ply K (K = 1, 2), baked and measured as the bunny (front-lit);
# the flat half-space: tests/bench/halfspace_terms 12000.
#
# Knobs: VERTICES (64) and PATHS (4096) per sss-stat --model-error row;
# SIZE (200x150), SPP_FRONT (256), SPP_BACK (1024) for the pictures;
# PICTURES=0 skips them. Rows and pictures already in OUT are reused.
# Writes OUT/rows.jsonl (one sss-stat --model-error --json per row, with
# "case") and OUT/pictures.jsonl (ref_compare's statistics), copies both to
# docs/data/model_error/, and prints the tables of docs/accuracy.md (whose
# section is docs/data/model_error/section.md). About 40 minutes on two
# shared cores; the pictures are most of it.
set -eu
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
OUT=${OUT:-out/model_error}
VERTICES=${VERTICES:-64}
PATHS=${PATHS:-4096}
SIZE=${SIZE:-200x150}
SPP_FRONT=${SPP_FRONT:-256}
SPP_BACK=${SPP_BACK:-1024}
PICTURES=${PICTURES:-1}
BAKE=$BUILD/precompute/sss-bake STAT=$BUILD/precompute/sss-stat REF=$BUILD/precompute/sss-ref
VIEW=$BUILD/runtime/sss-view CMP=$BUILD/tests/bench/ref_compare GEN=$BUILD/data/sss-genmesh
mkdir -p "$OUT" docs/images
# Sizes: the largest side of the bounding box (sss_mesh_bounds of the
# imported mesh) is 9.9073 units for bunny.ply (x −4.9585 … 4.9489) and
# 0.20366 units for dragon_22998.ply (x −0.10767 … 0.09598): 100 mm and
# 200 mm.
declare -A MM=([bunny]=10.094 [dragon]=982.05)
declare -A PLY=([bunny]=data/stanford/bunny.ply [dragon]=data/stanford/dragon_22998.ply)
FRONT_LIGHT=0,0.3,1 BACK_LIGHT=0,0.3,-1 VIEWDIR=0,0.15,1

bake() { # MESH MATERIAL → OUT/MESH_MATERIAL.sss (float, default settings)
  local f=$OUT/$1_$2.sss
  [ -s "$f" ] || "$BAKE" "${PLY[$1]}" -o "$f" --material "$2" --mm-per-unit "${MM[$1]}" -q
}
row() { # CASE FILE LIGHT [extra sss-stat args] → a line of rows.jsonl
  local name=$1 file=$2 light=$3; shift 3
  grep -q "\"case\":\"$name\"" "$OUT/rows.jsonl" 2>/dev/null && return 0
  echo "model_error.sh: $name" >&2
  "$STAT" "$file" --model-error --light "$light" --view "$VIEWDIR" --paths "$PATHS" --json "$@" |
    jq -c --arg c "$name" '{case: $c} + .' >>"$OUT/rows.jsonl"
}

for mesh in bunny dragon; do
  for mat in marble skin1; do
    bake $mesh $mat
    row "$mesh $mat front-lit" "$OUT/${mesh}_$mat.sss" $FRONT_LIGHT --vertices "$VERTICES"
    row "$mesh $mat back-lit" "$OUT/${mesh}_$mat.sss" $BACK_LIGHT --vertices "$VERTICES"
  done
done

# The thin part of docs/robustness.md B8: a 200 x 200 x 4 mm slab, sigma_a
# = 0, sigma'_s = 1/mm, lit head-on; its top and bottom centre vertices.
[ -s "$OUT/slab.ply" ] || "$GEN" slab 20 "$OUT/slab.ply" >/dev/null
[ -s "$OUT/slab.sss" ] || "$BAKE" "$OUT/slab.ply" -o "$OUT/slab.sss" --sigma-a 0,0,0 --sigma-s 1,1,1 --mm-per-unit 200 -q
VIEWDIR=0,0,1 row "slab 4 mm top, lit head-on" "$OUT/slab.sss" 0,0,1 --query 2221
VIEWDIR=0,0,-1 row "slab 4 mm bottom, lit head-on" "$OUT/slab.sss" 0,0,1 --query 1860

picture() { # NAME FILE MESH MATERIAL LIGHT SPP
  local name=$1 file=$2 mesh=$3 mat=$4 light=$5 spp=$6
  [ -s "$OUT/$name.ref.exr" ] || "$REF" "${PLY[$mesh]}" --material "$mat" --mm-per-unit "${MM[$mesh]}" \
    --light "$light" --view "$VIEWDIR" --out "$OUT/$name.ref.exr" --size "$SIZE" --paths "$spp" -q
  "$VIEW" "$file" --offscreen --out "$OUT/$name.rt.exr" --size "$SIZE" --light "$light" --view "$VIEWDIR" \
    --no-specular >/dev/null 2>&1
  grep -q "\"picture\":\"$name\"" "$OUT/pictures.jsonl" 2>/dev/null ||
    "$CMP" "$OUT/$name.rt.exr" "$OUT/$name.ref.exr" "$OUT/$name.ref.stderr.exr" "docs/images/model_$name.png" |
    jq -c --arg c "$name" --arg spp "$spp" '{picture: $c, spp: ($spp | tonumber)} + .' >>"$OUT/pictures.jsonl"
}
if [ "$PICTURES" = 1 ]; then
  picture bunny_marble_front "$OUT/bunny_marble.sss" bunny marble $FRONT_LIGHT "$SPP_FRONT"
  picture bunny_marble_back "$OUT/bunny_marble.sss" bunny marble $BACK_LIGHT "$SPP_BACK"
fi

mkdir -p docs/data/model_error
cp "$OUT/rows.jsonl" docs/data/model_error/rows.jsonl
[ -s "$OUT/pictures.jsonl" ] && cp "$OUT/pictures.jsonl" docs/data/model_error/pictures.jsonl

# the tables (numbers to 3 significant digits)
echo
echo "| case | mean L, real-time (R / G / B) | reference (± s.e.) | model: ratio | model: rel. RMS | approximation: ratio | approximation: rel. RMS | vertices × paths, leaks |"
echo "|---|---|---|---|---|---|---|---|"
jq -r '[.case, (.mean_radiance.realtime | map(tostring) | join(" ")), (.mean_radiance.reference | map(tostring) | join(" ")),
        (.mean_radiance.reference_stderr | map(tostring) | join(" ")), (.model_error.ratio_of_means | map(tostring) | join(" ")),
        (.model_error.rel_rms | map(tostring) | join(" ")), (.approximation_error.ratio_of_means | map(tostring) | join(" ")),
        (.approximation_error.rel_rms | map(tostring) | join(" ")), "\(.sampled_vertices) × \(.paths), \(.reference_leaks)"] | join("\t")' \
  "$OUT/rows.jsonl" | awk -F'\t' '
  function three(s, f,   a, o, i) { split(s, a, " "); o = ""; for (i = 1; i <= 3; i++) o = o (i > 1 ? " / " : "") sprintf(f, a[i]); return o }
  function pm(s, e,   a, b, o, i) { split(s, a, " "); split(e, b, " "); o = "";
    for (i = 1; i <= 3; i++) o = o (i > 1 ? " / " : "") sprintf("%.3g±%.2g", a[i], b[i]); return o }
  { printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, three($2, "%.3g"), pm($3, $4), three($5, "%.3f"), three($6, "%.3f"),
      three($7, "%.3f"), three($8, "%.3f"), $9 }'
if [ -s "$OUT/pictures.jsonl" ]; then
  echo
  echo "| picture | paths per pixel | mean L real-time | mean L reference | ratio (± s.e.) | rel. RMS (noise out) | reference noise |"
  echo "|---|---|---|---|---|---|---|"
  jq -r '[.picture, (.spp | tostring), (.mean_realtime | map(tostring) | join(" ")), (.mean_reference | map(tostring) | join(" ")),
          (.ratio | map(tostring) | join(" ")), (.ratio_stderr | map(tostring) | join(" ")), (.rel_rms | map(tostring) | join(" ")),
          (.reference_noise_rel_rms | map(tostring) | join(" "))] | join("\t")' "$OUT/pictures.jsonl" | awk -F'\t' '
    function three(s, f,   a, o, i) { split(s, a, " "); o = ""; for (i = 1; i <= 3; i++) o = o (i > 1 ? " / " : "") sprintf(f, a[i]); return o }
    function pm(s, e,   a, b, o, i) { split(s, a, " "); split(e, b, " "); o = "";
      for (i = 1; i <= 3; i++) o = o (i > 1 ? " / " : "") sprintf("%.3f±%.3f", a[i], b[i]); return o }
    { printf "| %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, three($3, "%.3g"), three($4, "%.3g"), pm($5, $6), three($7, "%.3f"), three($8, "%.3f") }'
fi
