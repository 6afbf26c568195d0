#!/usr/bin/env bash
# The whole test suite, as CI runs it: install what is missing, build with warnings as
# errors, run every test (unit, golden, examples), then again under ASan + UBSan.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
start=$(date +%s)

echo "== build (warnings are errors)"
scripts/build.sh ci
echo "== tests"
ctest --test-dir build/ci --output-on-failure -j "$(nproc)"

echo "== build (AddressSanitizer + UBSan)"
scripts/build.sh asan
echo "== tests under sanitizers"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$(nproc)"

echo "== all tests passed in $(( $(date +%s) - start )) s"
