#!/usr/bin/env bash
# The benchmarks in one command: installs what is missing, builds in Release, runs every
# benchmark and prints one Markdown table (bench/README.md explains each row).
#   bash bench/run.sh            the full table (about 35 minutes on 2 cores)
#   bash bench/run.sh --quick    one run per figure and smaller sizes, to try the command
# Every figure is the median of several runs; ours and raw Bullet run interleaved in the
# same process. Progress goes to stderr, the table to stdout.
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[[ "${1:-}" == "--quick" ]] && quick=1
scripts/setup.sh >&2
scripts/build.sh release >&2
b=build/release/bench

if (( quick )); then
  runtime=(--reps=1 --sizes=10,100) logic=(--reps=1 --logic-cells=10000)
  vsraw=(--reps=1 --bottling-warmup=10 --bottling-window=2)
  bottling=(--runs=1 --counts=10,50 --warmup=20 --window=10)
  compile=(--runs=1 --sizes=1000,10000)
  serve=(--runs=1 --counts=50 --warmup=10 --window=5) serve_large=()
  plc=(--runs=1 --warmup=30 --window=60)
  opcua=(--runs=1 --warmup=30 --window=60)
else
  runtime=(--reps=5 --sizes=10,100,1000) logic=(--reps=5)
  vsraw=(--reps=3)
  bottling=(--runs=3 --counts=10,50,200,1000)
  compile=(--runs=3 --sizes=1000,10000,100000)
  # What a client costs: pairs in turns (bench/pairs.h), 9 where a run takes a second or two.
  serve=(--runs=9 --counts=50 --warmup=30 --window=60) serve_large=(--runs=5 --counts=1000 --warmup=30 --window=15)
  plc=(--runs=9 --warmup=60 --window=240)
  opcua=(--runs=9 --warmup=60 --window=240)
fi

cpu=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')
echo "Measured $(date -u +%Y-%m-%d) on ${cpu:-an unknown CPU}, $(nproc) cores, $(free -g | awk '/Mem:/{print $2}') GiB," \
     "$(. /etc/os-release && echo "$PRETTY_NAME"), $(c++ --version | head -1), Release build;" \
     "load average before: $(cut -d' ' -f1-3 /proc/loadavg)."
echo
echo "| area | case | measured | target | met |"
echo "|---|---|---|---|---|"
"$b/plant_bench_runtime" --rows --only=belts "${runtime[@]}"
"$b/plant_bench_runtime" --rows --only=logic "${logic[@]}"
# The bottling plant at 1,000 bottles (2 threads, all their processor time) against the raw
# loop's belts at 1,000, in turns in one process (issue 30: at most 0.6).
"$b/plant_bench_runtime" --rows --only=bottling "${vsraw[@]}"
"$b/plant_bench_bottling" --rows "${bottling[@]}"
# The largest plant again on one thread: what stepping the lines' regions on every core gives.
(( quick )) || "$b/plant_bench_bottling" --rows --no-memory --runs=3 --counts=1000 --threads=1
# The step's serial share at 1,000 bottles on 2 threads, per part of the step, and its Amdahl
# projection for 4, 8 and 16 threads (no many-core machine here: bench/README.md): the run of
# three whose projection at 16 threads is their median (one run reads 9.6x to 11.8x by the hour).
"$b/plant_bench_bottling" --rows --no-memory --profile --runs=$( (( quick )) && echo 1 || echo 3) --threads=2 \
  "$( (( quick )) && echo --counts=200 || echo --counts=1000)" --warmup=$( (( quick )) && echo 20 || echo 60) --window=10
# 5,000 bottles in circulation (417 lines) on 2 threads, once; the row gives the load average.
(( quick )) || "$b/plant_bench_bottling" --rows --no-memory --runs=1 --counts=5000 --threads=2 --window=10
"$b/plant_bench_compile" --rows "${compile[@]}"
(( quick )) || bench/compile_lines.sh build/release/app/plant
"$b/plant_bench_serve" --rows "${serve[@]}"
(( quick )) || "$b/plant_bench_serve" --rows "${serve_large[@]}"
"$b/plant_bench_plc" --rows "${plc[@]}"
# The OPC UA link (node-opcua, installed by scripts/setup.sh): one client subscribed to 100 variables.
[[ -x "$b/plant_bench_opcua" ]] && "$b/plant_bench_opcua" --rows "${opcua[@]}"
# plant sweep: runs per minute with -j 1 and -j 2 (bench/sweep.sh).
bench/sweep.sh build/release/app/plant "$( (( quick )) && echo 5s || echo 30s)"
# The page's draw calls (three.js renderer.info) with one line and with 83 (1,000 bottles in
# circulation): instanced meshes keep them from growing with the bottles. How many a frame
# makes depends on which of the models' parts some body shows then (an empty instanced mesh
# is not drawn), so the row compares the meshes the page made: the same at 83 lines as at 1,
# and no more draw calls than those.
if command -v node >/dev/null && command -v chromium >/dev/null; then
  calls() {
    node --experimental-websocket viewer/test/browser.mjs build/release/app/plant plants/bottling.plant \
      "$(mktemp --suffix=.png)" --draw-calls --set "lines=$1" 2>/dev/null |
      sed -n 's/^draw calls: \([0-9]*\) .*for \([0-9]*\) bodies.*of \([0-9]*\) meshes made$/\1 \2 \3/p'
  }
  read -r c1 b1 m1 < <(calls 1) || true
  read -r c83 b83 m83 < <(calls 83) || true
  met=$([[ -n "${m1:-}" && -n "${m83:-}" && $m83 -eq $m1 && $c83 -le $m83 ]] && echo yes || echo "**no**")
  echo "| viewer | the page's draw calls, 1 line vs 83 lines (bodies in the world drawn; meshes the page made) | ${c1:-?} (${b1:-?} bodies; ${m1:-?} meshes) vs ${c83:-?} (${b83:-?} bodies; ${m83:-?} meshes) | not growing with the bottles: as many meshes at 83 lines as at 1, no more calls than meshes | $met |"
fi
