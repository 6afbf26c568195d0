#!/usr/bin/env bash
# The benchmarks' flags (bench/flags.h): `--help` works, and every kind of bad input is a usage
# error (exit 2) that names the flag, never a silent default. Each binary is one argument,
# NAME=PATH; the bottling, runtime and compile ones are required, the clients' ones optional.
set -uo pipefail
declare -A bin
for a in "$@"; do bin[${a%%=*}]=${a#*=}; done
fails=0 checks=0
# expect NAME CODE PATTERN ARGS...: the binary exits with CODE and prints PATTERN (grep -E).
expect() {
  local name=$1 code=$2 pattern=$3
  shift 3
  local out rc
  out=$(timeout 20 "${bin[$name]}" "$@" 2>&1)
  rc=$?
  checks=$((checks + 1))
  if [[ $rc -ne $code ]] || ! grep -qE -- "$pattern" <<<"$out"; then
    echo "FAIL: $name $* -> exit $rc (want $code), output:"
    echo "$out" | head -5
    fails=$((fails + 1))
  fi
}
for name in "${!bin[@]}"; do
  runs=--runs
  [[ $name == runtime ]] && runs=--reps
  expect "$name" 0 "^usage: plant_bench_$name " --help
  expect "$name" 2 "^plant_bench_$name: error: unknown option '--bogus'" --bogus
  expect "$name" 2 "error: $runs: 'x' is not a whole number from 1 to 1000" $runs=x
  expect "$name" 2 "error: $runs: '0' is not a whole number from 1 to 1000" $runs 0
  expect "$name" 2 "error: $runs needs N" $runs
  expect "$name" 2 "error: $runs: '\+3' is not a whole number" $runs=+3
  expect "$name" 2 "error: $runs: ' 3' is not a whole number" "$runs= 3"
  expect "$name" 2 "error: unexpected word 'stray'" stray
done
b=bottling
expect $b 2 "error: --counts: 'abc' in '10,abc' is not a whole number from 1 to 1000000" --counts=10,abc
expect $b 2 "error: --counts: '' in '10,' is not a whole number" --counts=10,
expect $b 2 "error: --window: '0' is not a number above 0" --window=0
expect $b 2 "error: --window: 'inf' is not a number above 0" --window=inf
expect $b 2 "error: --per-line: '12x' is not a number above 0" --per-line=12x
expect $b 2 "error: --warmup: '-1' is not a number of 0 or more" --warmup=-1
expect $b 2 "error: --threads: '0' is not a whole number from 1 to 256" --threads=0
expect $b 2 "error: --steady-transport: 'maybe' is not one of on\|off" --steady-transport=maybe
expect $b 2 "error: --plant needs PATH" --plant=
expect $b 2 "error: --plant needs PATH" --plant ""  # an empty word: Flags::text's own check
r=runtime
expect $r 2 "error: --only: 'x' is not one of belts\|logic\|bottling" --only=x
expect $r 2 "error: --sizes: '1e3' in '1e3' is not a whole number" --sizes=1e3
expect $r 2 "error: --profile needs one N after it" --profile=ours
expect $r 2 "error: --profile: 'x' is not a whole number" --profile=logic x
expect $r 2 "error: --profile: 'ours2' is not one of ours\|raw\|logic" --profile=ours2 10
expect $r 2 "error: --drop-mm: '-2' is not a number of 0 or more" --drop-mm=-2
# A good line still runs: one short belts row.
expect $r 0 "^\| runtime vs raw Bullet \| 10 bottles on belts" --rows --only=belts --reps=1 --sizes=10 --steps=20
c=compile
expect $c 2 "error: --forms: 'ring' in 'loop,ring' is not loop or flat" --forms=loop,ring
expect $c 2 "error: --gen needs N, a form and an output file after it" --gen 10 loop
expect $c 2 "error: --gen: 'cubic' is not loop or flat" --gen 10 cubic out.plant
expect $c 2 "error: --gen: '0' is not a whole number" --gen 0 loop out.plant
expect $c 2 "error: --phases goes with --compile FILE" --phases
expect $c 2 "error: --max-seconds: '0' is not a number above 0" --max-seconds=0
if [[ -n "${bin[serve]:-}" ]]; then
  expect serve 2 "error: --fps: '0' is not a whole number from 1 to 240" --fps=0
fi
echo "$checks checks, $fails failed"
[[ $fails -eq 0 && $checks -gt 20 ]]
