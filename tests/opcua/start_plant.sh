# Sourced by the tests that run `plant run` or `plant serve` with the OPC UA link:
# `start_plant TAG COMMAND ARGS...` runs "$plant COMMAND ARGS..." in the background, stdout
# to $work/outTAG and stderr to $work/errTAG, and sets `pid` and `url` (the endpoint it
# printed), within 60 s (the server loads node-opcua first) or fails.
start_plant() {
  local tag="$1"
  shift
  "$plant" "$@" > "$work/out$tag" 2> "$work/err$tag" &
  pid=$!
  url=""
  for _ in $(seq 300); do
    url=$(sed -n 's/.*OPC UA on \(opc\.tcp:[^ ]*\) .*/\1/p' "$work/err$tag" 2>/dev/null || true)
    [ -n "$url" ] && return 0
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.2
  done
  echo "plant $1 did not start its OPC UA server"
  cat "$work/err$tag"
  exit 1
}
