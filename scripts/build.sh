#!/usr/bin/env bash
# Configures and builds one flavour into build/<name>.
#   scripts/build.sh release      optimised, for running plants and benchmarks
#   scripts/build.sh ci           warnings as errors, with the tests
#   scripts/build.sh asan         AddressSanitizer + UBSan, with the tests
set -euo pipefail
cd "$(dirname "$0")/.."
flavour="${1:-release}"
jobs="${JOBS:-$(nproc)}"
# The two test builds are unity builds, lightly optimised (-O1), with line tables only (-g1:
# file:line in backtraces and sanitizer reports): less than half the compile time of one
# file at a time with full debug information (docs/testing.md, "How long the suite takes").
case "$flavour" in
  release) args=(-DCMAKE_BUILD_TYPE=Release -DPLANT_TESTS=OFF) ;;
  ci)      args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DPLANT_WERROR=ON -DPLANT_UNITY=ON
                 -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG") ;;
  asan)    args=(-DCMAKE_BUILD_TYPE=Debug -DPLANT_WERROR=ON -DPLANT_SANITIZE=ON -DPLANT_BENCH=OFF
                 -DPLANT_UNITY=ON -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1") ;;
  *) echo "build: unknown flavour '$flavour' (release, ci, asan)" >&2; exit 2 ;;
esac
cmake -S . -B "build/$flavour" -G Ninja "${args[@]}" > "build-$flavour.log" 2>&1 || { cat "build-$flavour.log"; exit 1; }
rm -f "build-$flavour.log"
cmake --build "build/$flavour" -j "$jobs"
