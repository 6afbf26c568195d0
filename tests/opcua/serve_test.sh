#!/usr/bin/env bash
# `plant serve` starts the plant's OPC UA link as `plant run` does (issue #33): a client
# (tests/opcua/serve_test.mjs) browses to line[0].s2.id, sees the plant's simulated time
# advance, and calls line[0].s1.to_working; the call is an event like the page's, in the
# session's /events, by the OPC UA link.
#   tests/opcua/serve_test.sh PLANT SOURCE_DIR
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
start_plant "" serve "$src/plants/bottling_opcua.plant" --port 0 --opcua-port 0
# The page's address follows the link's (the link starts with the plant, the page after it).
page=""
for _ in $(seq 100); do
  page=$(sed -n 's/^plant serve: \(http:[^ ]*\)$/\1/p' "$work/out")
  [ -n "$page" ] && break
  sleep 0.2
done
[ -n "$page" ] || { echo "FAIL: no page URL"; cat "$work/out" "$work/err"; exit 1; }
timeout 60 node "$(dirname "$0")/serve_test.mjs" "$url" > "$work/client" ||
  { echo "FAIL: the client"; cat "$work/client" "$work/err"; exit 1; }
cat "$work/client"
node -e '
const c = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
const fail = (why) => { console.log("FAIL: " + why); process.exit(1); };
if (c.type !== "String") fail(`line[0].s2.id is ${c.type}`);
if (!(c.times[1] > c.times[0])) fail(`the served plant did not advance: ${c.times}`);
if (c.call !== "Good") fail(`calling line[0].s1.to_working: ${c.call}`);
console.log(`browsed line[0].s2.id (String); simulated time ${c.times[0]} s, a second later ${c.times[1]} s; to_working called: Good`);
' "$work/client"
# The call reached the plant as an event through the one way in: the session's events file.
for _ in $(seq 50); do
  curl -sf "${page}events" > "$work/events" && grep -q 'line\[0\]\.s1\.to_working' "$work/events" && break
  sleep 0.2
done
grep 'line\[0\]\.s1\.to_working' "$work/events" || { echo "FAIL: /events lacks the call"; cat "$work/events"; exit 1; }
# At the step it fed: after the client's second reading of the simulated time, not at 0 s.
at=$(sed -n 's/^\([0-9.]*\)s line\[0\]\.s1\.to_working$/\1/p' "$work/events" | head -1)
node -e 'const [at, c] = [Number(process.argv[1]), JSON.parse(require("fs").readFileSync(process.argv[2], "utf8"))];
if (!(at >= c.times[1])) { console.log(`FAIL: the call is logged at ${at} s, before ${c.times[1]} s`); process.exit(1); }' "$at" "$work/client"
echo "opcua serve: ok"
