#!/usr/bin/env bash
# Coverage-guided fuzzing with libFuzzer (Debian's clang 14) under ASan + UBSan.
#   scripts/fuzz.sh [TARGET...] [--time SECONDS]   (targets: compile graph events viewer_message modbus recording;
#                                                   default: all, 60 s each)
# Builds build/fuzz (clang, -DPLANT_FUZZ=ON), then runs each target for --time seconds on a
# working corpus in build/fuzz/corpus/TARGET (seeded from the tree's own files: the seed
# corpus of tests/fuzz/CMakeLists.txt) with the language's dictionary (tests/fuzz/plant.dict).
# A crash, sanitizer report or hang (30 s per input; the compile target lowers the loop limit
# to 20,000 so that loops at the limit take milliseconds) stops it: the input is in
# build/fuzz/crashes/TARGET/; add it to tests/fuzz/regressions/TARGET/ (the test suite runs
# every file there) and fix the bug. Exit 1 if any target found one. docs/testing.md.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh >/dev/null
seconds=60
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --time) seconds="$2"; shift 2 ;;
    compile|graph|events|viewer_message|modbus|recording) targets+=("$1"); shift ;;
    *) echo "fuzz: unknown argument '$1' (targets: compile graph events viewer_message modbus recording; --time SECONDS)" >&2; exit 2 ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(compile graph events viewer_message modbus recording)

cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DPLANT_FUZZ=ON -DPLANT_SANITIZE=ON -DPLANT_BENCH=OFF > build-fuzz.log 2>&1 || { cat build-fuzz.log; exit 1; }
rm -f build-fuzz.log
cmake --build build/fuzz -j "${JOBS:-$(nproc)}" --target $(printf 'fuzz_%s ' "${targets[@]}")

seeds() {  # the seed corpus of a target, as files
  case "$1" in
    compile) find stdlib examples plants tests/golden -type f -name '*.plant' ;;
    graph) find tests/golden -type f -name '*.graph' ;;
    *) [ -d "tests/fuzz/corpus/$1" ] && find "tests/fuzz/corpus/$1" -type f || true ;;
  esac
  [ -d "tests/fuzz/regressions/$1" ] && find "tests/fuzz/regressions/$1" -type f || true
}

found=0
for t in "${targets[@]}"; do
  corpus="build/fuzz/corpus/$t"
  crashes="build/fuzz/crashes/$t"
  mkdir -p "$corpus" "$crashes"
  seeds "$t" | while read -r f; do cp "$f" "$corpus/seed-$(echo "$f" | tr '/' '_')"; done
  echo "== fuzz $t for ${seconds} s"
  if ! ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      "build/fuzz/tests/fuzz/fuzz_$t" "$corpus" -dict=tests/fuzz/plant.dict -max_total_time="$seconds" \
      -timeout=30 -rss_limit_mb=4096 -max_len=65536 -artifact_prefix="$crashes/" -print_final_stats=1 \
      2> "build/fuzz/$t.log"; then
    echo "fuzz $t: FOUND A FAILURE (see build/fuzz/$t.log, input in $crashes/)"
    found=1
  fi
  grep -E '^(#[0-9]+ *DONE|stat::number_of_executed_units|stat::peak_rss_mb)' "build/fuzz/$t.log" || tail -3 "build/fuzz/$t.log"
done
exit "$found"
