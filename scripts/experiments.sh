#!/usr/bin/env bash
# The three measurements of the original work (docs/experiments.md), in one command:
#
#   bash scripts/experiments.sh [--only NAME]... [--set NAME=VALUE]... [--out DIR]
#
# Installs what is missing (scripts/setup.sh: gnuplot among it), builds optimised, runs
# every plant of plants/experiments over its sweep and writes, per experiment, into
# DIR/NAME/ (default out/experiments/NAME/): NAME.csv (the series), NAME.png and NAME.svg
# (the plot), summary.md (the headline numbers), and runs/ (each run's compiled graph and
# raw trace).
#
#   traction  a bottle let go on a belt at 50 cm/s, k = 1, 4, 16 kg/s          (1 s each;
#             again at 600, 2400 and 9600 Hz for the step-by-step table and traction_rates.png)
#   tipping   a bottle put on a belt at 100 cm/s, 20, 40, 80 g, k = 16, 4, 0.5 kg/s (3 s each)
#   spacing   two bottles 20 cm apart on a loop of 5 belts, on right-angle Corners and
#             on arcs, side by side                                           (50 s)
#   rocking   a probe: a 20 g bottle let go leaning back 8 to 20° on a belt at rest, on a
#             bare band and with k = 0.1, 1, 16 kg/s: does it swing a second time? (1 s each)
#
# Every measurement runs with the original, unlimited conveyor law (max_force = 1 kN, never
# reached) and again with std.belts' slip limit (max_force = 0.3 N per body), side by side
# in its summary; `--set max_force=0.3N` runs only the second. (Rocking runs with std.belts'
# default, 0.3 N: at rest the law stays under it.)
#
# --set NAME=VALUE sets a plant parameter (a value with its unit: k=4kg/s, "mass=20 g",
# speed=60cm/s) in every selected experiment whose plant declares NAME. For a parameter an
# experiment sweeps (traction: k; tipping: k and mass; rocking: k and tilt; the measurements: max_force) the
# values given replace its sweep:
# `--set k=2kg/s --set k=8kg/s` runs traction with k = 2 and 8 kg/s. Elsewhere the last
# value given counts. --only NAME (repeatable) runs only those experiments.
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { sed -n '2,30p' "$0" | sed 's/^# \{0,1\}//'; }

out=out/experiments
only=()
set_names=()
set_values=()
add_set() {
  case "$1" in
    *=*) set_names+=("$(echo "${1%%=*}" | tr -d ' ')"); set_values+=("${1#*=}") ;;
    *) echo "experiments: --set needs NAME=VALUE, got '$1'" >&2; exit 2 ;;
  esac
}
while [ $# -gt 0 ]; do
  case "$1" in
    --only) [ $# -ge 2 ] || { usage >&2; exit 2; }; only+=("$2"); shift 2 ;;
    --only=*) only+=("${1#--only=}"); shift ;;
    --set) [ $# -ge 2 ] || { usage >&2; exit 2; }; add_set "$2"; shift 2 ;;
    --set=*) add_set "${1#--set=}"; shift ;;
    --out) [ $# -ge 2 ] || { usage >&2; exit 2; }; out="$2"; shift 2 ;;
    --out=*) out="${1#--out=}"; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "experiments: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done
[ ${#only[@]} -gt 0 ] || only=(traction tipping spacing rocking)
for name in "${only[@]}"; do
  case "$name" in traction|tipping|spacing|rocking) ;; *) echo "experiments: no experiment '$name' (traction, tipping, spacing, rocking)" >&2; exit 2 ;; esac
done

scripts/setup.sh
scripts/build.sh release
plant=build/release/app/plant
analyse=build/release/tools/plant-analyse

# The parameters a plant declares, from its syntax tree: "k mass speed ...".
# (The tree is read whole first: a reader that stops early would kill the writer with SIGPIPE.)
declared() {
  local ast
  ast="$("$plant" check --emit=ast "$1")"
  sed -n '/^ *plant /{p;q}' <<< "$ast" | grep -oE '[(,] *[A-Za-z_][A-Za-z_0-9]*:' | tr -d '(,: '
}

# Every --set name must be declared by at least one selected plant.
for n in "${set_names[@]+"${set_names[@]}"}"; do
  found=0
  for name in "${only[@]}"; do
    for p in $(plants_of "$name"); do
      if declared "plants/experiments/$p.plant" | grep -qx "$n"; then found=1; fi
    done
  done
  [ $found -eq 1 ] || { echo "experiments: no selected experiment has a parameter '$n'" >&2; exit 2; }
done

# values NAME: the values given for NAME, one per line (none when not given).
values() {
  local i
  for i in "${!set_names[@]}"; do [ "${set_names[$i]}" = "$1" ] && printf '%s\n' "${set_values[$i]}"; done
  return 0
}

# The plants of an experiment: spacing runs on two loops, right angles (the original's
# kind) and arcs, side by side.
plants_of() {
  case "$1" in
    spacing) echo spacing_corners spacing ;;
    *) echo "$1" ;;
  esac
}

# run_experiment NAME SECONDS SWEPT_NAME:DEFAULTS...  (DEFAULTS separated by '|')
run_experiment() {
  local name="$1" seconds="$2"; shift 2
  local dir="$out/$name"
  rm -rf "$dir"
  mkdir -p "$dir/runs"
  local pairs=() plant_name
  for plant_name in $(plants_of "$name"); do
    local file="plants/experiments/$plant_name.plant"
    local params; params="$(declared "$file")"
    # Fixed values: the last value of every name this plant declares and does not sweep.
    local fixed=() swept=() n
    for spec in "$@"; do swept+=("${spec%%:*}"); done
    for n in $(printf '%s\n' "${set_names[@]+"${set_names[@]}"}" | awk '!seen[$0]++'); do
      echo "$params" | grep -qx "$n" || continue
      printf '%s\n' "${swept[@]+"${swept[@]}"}" | grep -qx "$n" && continue
      fixed+=(--set "$n=$(values "$n" | tail -n 1)")
    done
    # The sweep: the cartesian product of the swept names' values.
    local combos=("")
    for spec in "$@"; do
      local sname="${spec%%:*}" defaults="${spec#*:}" list=() next=() c v
      mapfile -t list < <(values "$sname")
      [ ${#list[@]} -gt 0 ] || IFS='|' read -r -a list <<< "$defaults"
      for c in "${combos[@]}"; do
        for v in "${list[@]}"; do next+=("$c"$'\t'"$sname=$v"); done
      done
      combos=("${next[@]}")
    done
    echo
    echo "== $name: $plant_name (${#combos[@]} run(s), $seconds s each)"
    local combo tag sets
    for combo in "${combos[@]}"; do
      sets=()
      tag="$plant_name"
      IFS=$'\t' read -r -a parts <<< "${combo#$'\t'}"
      for p in "${parts[@]+"${parts[@]}"}"; do
        [ -n "$p" ] || continue
        sets+=(--set "$p")
        tag+="_$(echo "$p" | tr -c 'A-Za-z0-9.=\n' '_' | tr '=' '-')"
      done
      echo "   $plant run $file$(printf ' %q' "${fixed[@]+"${fixed[@]}"}" "${sets[@]+"${sets[@]}"}" | sed 's/ '"''"'//g') --for ${seconds}s"
      "$plant" build "$file" "${fixed[@]+"${fixed[@]}"}" "${sets[@]+"${sets[@]}"}" -o "$dir/runs/$tag.graph"
      "$plant" run "$dir/runs/$tag.graph" --for "${seconds}s" --trace "$dir/runs/$tag.csv" --quiet > "$dir/runs/$tag.summary"
      pairs+=("$dir/runs/$tag.graph" "$dir/runs/$tag.csv")
    done
  done
  # Traction: the same runs at finer steps, for the summary's step-by-step table.
  if [ "$name" = traction ]; then
    local graphs=() g r base
    for ((i = 0; i < ${#pairs[@]}; i += 2)); do graphs+=("${pairs[$i]}"); done
    base="$(sed -n 's/^settings rate=\([^ ]*\).*/\1/p' "${graphs[0]}")"
    for r in 600 2400 9600; do
      [ "$r" = "$base" ] && continue
      echo "   (each again with --rate ${r}Hz)"
      for g in "${graphs[@]}"; do
        "$plant" run "$g" --rate "${r}Hz" --for "${seconds}s" --trace "${g%.graph}_${r}Hz.csv" --quiet > "${g%.graph}_${r}Hz.summary"
        pairs+=("$g" "${g%.graph}_${r}Hz.csv")
      done
    done
  fi
  "$analyse" "$name" "$dir" "${pairs[@]}"
  (cd "$dir" && gnuplot "$name.gp")
  [ "$name" != traction ] || (cd "$dir" && gnuplot traction_rates.gp)
  echo "   wrote $dir/$name.csv, $name.png, $name.svg, summary.md"
}

# Every experiment runs twice: with the original, unlimited law (max_force = 1 kN, never
# reached) and with std.belts' slip limit (0.3 N per body); `--set max_force=...` replaces the pair.
limits="max_force:1 kN|0.3 N"
for name in "${only[@]}"; do
  case "$name" in
    traction) run_experiment traction 1 "k:1 kg/s|4 kg/s|16 kg/s" "$limits" ;;
    tipping)  run_experiment tipping 3 "k:16 kg/s|4 kg/s|0.5 kg/s" "mass:20 g|40 g|80 g" "$limits" ;;
    spacing)  run_experiment spacing 50 "$limits" ;;
    rocking)  run_experiment rocking 1 "k:0 kg/s|0.1 kg/s|1 kg/s|16 kg/s" "tilt:8 deg|10 deg|12 deg|15 deg|20 deg" ;;
  esac
done

echo
for name in "${only[@]}"; do
  echo "=================================================================="
  cat "$out/$name/summary.md"
done
