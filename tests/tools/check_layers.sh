#!/usr/bin/env bash
# The include arrows of docs/architecture.md §1, checked: common includes
# nothing of precompute or runtime (and no GL or C++ library); runtime and
# precompute meet only in their tools; the precompute stages include only
# their own stage and the stages below it (effects/ and bake/, the passes
# and the pipeline that runs them, share one rank); no file outside runtime/
# includes a header of runtime/src. Prints every arrow that breaks a rule.
# Files are read and names taken apart by bash itself: a grep, sed or
# basename per file and include (thousands of processes) took 16 s of CI.
# usage: check_layers.sh SOURCE_DIR
set -u
cd "${1:?source dir}" || exit 2
bad=0
complain() { echo "check_layers: $*"; bad=1; }

# the stage of a precompute public header, by name
declare -A hstage=(
  [import]=input [probe]=input [fieldio]=input [depthmap]=input
  [nbhd]=kernels [visibility]=kernels [transfer]=kernels [lloyd]=kernels
  [gather]=gather
  [refs]=compress [compress]=compress
  [bake]=bake [planner]=bake [bake_scene]=bake [perframe]=bake [layer_depths]=bake
  [exact]=measure [reconstruct]=measure [vertex_error]=measure [env_error]=measure
  [reference]=reference
)
declare -A rank=([input]=0 [kernels]=1 [gather]=2 [compress]=3 [effects]=4 [bake]=4 [measure]=5 [reference]=5)

# includes FILE: INC, the files FILE includes with #include "..." (at the
# start of a line, one space), in order
includes() {
  INC=()
  local l re='^#include "([^"]+)"'
  while IFS= read -r l || [ -n "$l" ]; do
    [[ $l =~ $re ]] && INC+=("${BASH_REMATCH[1]}")
  done < "$1"
}
# stage_of_include INCLUDE: STAGE, the stage it belongs to: public headers
# by name, internal ones by folder; empty if none
stage_of_include() {
  STAGE=
  case "$1" in
    sss/*.h) local n=${1#sss/}; n=${n%.h}; STAGE=${hstage[$n]:-};;
    input/*|kernels/*|gather/*|effects/*|bake/*|compress/*|measure/*|reference/*) STAGE=${1%%/*};;
  esac
}

# 1. common: C only, nothing above it
while IFS= read -r f; do
  includes "$f"
  for i in ${INC[@]+"${INC[@]}"}; do
    case "$i" in sss/*) [ -e "common/include/$i" ] || [ -e "common/cli/$i" ] || complain "$f includes $i, which is not in common";; esac
  done
done < <(find common -name '*.[ch]')
while IFS= read -r f; do
  complain "$f includes a GL, C++ or precompute library header"
done < <(find common -name '*.[ch]' -exec grep -lE '^#include <(epoxy|GL|GLFW|EGL|embree|flann|OpenMesh|CGAL|openvdb|assimp|imgui)' {} +)
[ -z "$(find common -name '*.cpp' -o -name '*.hpp')" ] || complain "common holds C++ files"

# 2. precompute stages
for s in input kernels gather compress effects bake measure reference; do
  while IFS= read -r f; do
    includes "$f"
    for i in ${INC[@]+"${INC[@]}"}; do
      stage_of_include "$i"; t=$STAGE
      [ -n "$t" ] || continue
      [ "${rank[$t]}" -le "${rank[$s]}" ] || complain "$f ($s) includes $i ($t, a higher stage)"
    done
  done < <(find "precompute/src/$s" -type f)
done
for h in precompute/include/sss/*.h; do
  n=${h##*/}; n=${n%.h}; s=${hstage[$n]:-}
  [ "$n" = precompute ] && continue
  [ -n "$s" ] || { complain "$h has no stage in check_layers.sh"; continue; }
  includes "$h"
  for i in ${INC[@]+"${INC[@]}"}; do
    stage_of_include "$i"; t=$STAGE; [ -n "$t" ] || continue
    [ "${rank[$t]}" -le "${rank[$s]}" ] || complain "$h ($s) includes $i ($t, a higher stage)"
  done
done

# 3. runtime's own headers stay in runtime; precompute's library never
#    includes the renderer (only its tools do: sss-stat's image error)
declare -A rt_header=()
while IFS= read -r h; do rt_header[${h##*/}]=1; done < <(find runtime/src -name '*.h')
while IFS= read -r f; do
  includes "$f"
  for i in ${INC[@]+"${INC[@]}"}; do
    [ -n "${rt_header[${i##*/}]:-}" ] || continue
    [ -e "${f%/*}/$i" ] || [ -e "common/include/$i" ] || [ -e "precompute/include/$i" ] ||
      complain "$f includes $i from runtime/src (use sss/render.h)"
  done
done < <(find common precompute tests data -name '*.[ch]' -o -name '*.cpp')
while IFS= read -r f; do
  complain "$f (the precompute library) includes the renderer"
done < <(find precompute/src precompute/include -type f -exec grep -lE '^#include "sss/render.h"' {} +)
while IFS= read -r f; do
  includes "$f"
  for i in ${INC[@]+"${INC[@]}"}; do
    case "$i" in sss/*) [ -e "precompute/include/$i" ] && complain "$f (runtime) includes $i of precompute";; esac
  done
done < <(find runtime -name '*.[ch]' -not -path 'runtime/src/view/pose.[ch]' -not -path 'runtime/src/view/edit.[ch]')
# pose.c and edit.c are sss-view's tool code for a deforming or an editable
# scene without a file: a tool may link both libraries (docs/architecture.md
# §1), as sss-stat does
exit $bad
