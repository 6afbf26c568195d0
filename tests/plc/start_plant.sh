# Sourced by the tests that run `plant run` with the link: `start_plant TAG ARGS...` runs
# "$plant run ARGS..." in the background, stdout to $work/outTAG and stderr to
# $work/errTAG, and sets `pid` and `port` (the port it printed), within 30 s or fails.
start_plant() {
  local tag="$1"
  shift
  # The files exist before the child starts: the first look for the port must not race the
  # background job's redirections (sed would fail on a missing file, and `set -e` end the test).
  : > "$work/out$tag"
  : > "$work/err$tag"
  "$plant" run "$@" > "$work/out$tag" 2> "$work/err$tag" &
  pid=$!
  port=""
  for _ in $(seq 150); do
    port=$(sed -n 's/.*Modbus TCP on 127\.0\.0\.1:\([0-9]*\).*/\1/p' "$work/err$tag")
    [ -n "$port" ] && return 0
    sleep 0.2
  done
  echo "plant run did not start its Modbus server"
  cat "$work/err$tag"
  exit 1
}
