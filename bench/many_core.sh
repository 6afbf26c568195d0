#!/usr/bin/env bash
# The bottling plant on 1 to N threads on a many-core machine that has nothing installed
# (bench/README.md, "Regions that scale on 16 cores"): a Release binary runs there when carried
# with its shared libraries and the loader (ld.so --library-path lib BINARY).
#
# Here, once per measurement: a folder with this checkout's plant_bench_bottling (Release), and
# optionally a baseline commit's, each with its plants and stdlib, their libraries and the loader:
#   bash bench/many_core.sh bundle DIR [--base COMMIT]
# There (copy DIR over, or carry it; nothing else is needed):
#   bash DIR/run.sh [--quick]
# run.sh prints, on stdout, one Markdown table: each binary's real-time factor and processor time
# per bottle-step at 1,000 bottles on 1, 2, 4, 8, ... threads up to the machine's cores (the
# binaries in turns at each count), then 5,000 bottles on all cores and the profile of the step
# on all cores (each loop's jobs against the least they could take). Single runs, a 20 s warm-up
# and a 5 s window (--quick: 5 s and 2 s, 200 bottles). Progress and the full outputs go to
# DIR/log.txt.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  echo "usage: bench/many_core.sh bundle DIR [--base COMMIT]" >&2
  exit 2
}
[[ "${1:-}" == "bundle" && -n "${2:-}" ]] || usage
dir=$2
shift 2
base=""
while (($#)); do
  case "$1" in
    --base) [[ -n "${2:-}" ]] || usage; base=$2; shift 2 ;;
    *) usage ;;
  esac
done
if [[ -n "$base" ]] && ! git rev-parse --verify -q "$base^{commit}" > /dev/null; then
  echo "many_core.sh: --base $base: no such commit" >&2
  exit 2
fi

mkdir -p "$dir/lib"
dir=$(cd "$dir" && pwd)

# One binary and what it runs: DIR/NAME/{plant_bench_bottling,plants,stdlib}.
put() {  # name source-tree binary
  mkdir -p "$dir/$1"
  cp "$3" "$dir/$1/plant_bench_bottling"
  rm -rf "$dir/$1/plants" "$dir/$1/stdlib"
  cp -r "$2/plants" "$2/stdlib" "$dir/$1/"
  ldd "$3" | awk '/=> \//{print $3}' | while read -r l; do cp -L "$l" "$dir/lib/"; done
}

scripts/build.sh release >&2
put this . build/release/bench/plant_bench_bottling
echo "this: $(git rev-parse --short HEAD)$(git diff --quiet HEAD || echo ' (with changes)')" > "$dir/what.txt"
if [[ -n "$base" ]]; then
  wt=$(mktemp -d)
  git worktree add -q --detach "$wt" "$base"
  trap 'git worktree remove --force "$wt"' EXIT
  cmake -S "$wt" -B "$wt/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLANT_TESTS=OFF > /dev/null
  cmake --build "$wt/build" -j "${JOBS:-$(nproc)}" --target plant_bench_bottling >&2
  put base "$wt" "$wt/build/bench/plant_bench_bottling"
  echo "base: $(git rev-parse --short "$base")" >> "$dir/what.txt"
fi
cp -L /lib64/ld-linux-x86-64.so.2 "$dir/ld.so"
cp bench/many_core_run.sh "$dir/run.sh"
echo "bundled in $dir ($(du -sh "$dir" | cut -f1)): $(paste -sd, "$dir/what.txt")" >&2
echo "there: bash $dir/run.sh [--quick]" >&2
