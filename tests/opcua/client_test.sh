#!/usr/bin/env bash
# Issue #33's "must show" with a real OPC UA client (tests/opcua/client_test.mjs,
# node-opcua-client in its own process) against plants/bottling_opcua.plant in lock-step for
# 60 s of plant time: line[0].s2.id found by browsing, with its type; the method behind
# line[0].s1.to_working called (the plant's record "s1 to lane A" counts it); every bottle's
# code read in S2's reader while it passes; a monitored item on S2's `seen` counter sees
# every bottle, one change each, as many as S2 routed (the summary's records), and an
# event for each.
#   tests/opcua/client_test.sh PLANT SOURCE_DIR
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
start_plant "" run "$src/plants/bottling_opcua.plant" --lockstep --opcua-port 0 --for 60s
timeout 300 node "$(dirname "$0")/client_test.mjs" "$url" 9000 > "$work/client" ||
  { echo "FAIL: the client"; cat "$work/client"; exit 1; }
wait "$pid"
node - "$work/client" "$work/out" <<'JS'
const fs = require("fs");
const [clientFile, summaryFile] = process.argv.slice(2);
const c = JSON.parse(fs.readFileSync(clientFile, "utf8"));
const summary = fs.readFileSync(summaryFile, "utf8");
const record = (name) => Number((summary.match(new RegExp(`^  ${name} +(\\d+) events`, "m")) || [])[1]);
const fail = (why) => { console.log(`FAIL: ${why}\n${JSON.stringify(c)}`); process.exit(1); };
if (c.browsed !== "ns=2;i=12") fail(`browsing to line[0].s2.id found ${c.browsed}`);
if (c.type !== "String" || c.nodeClass !== "Variable" || c.access !== 1) fail(`line[0].s2.id: ${c.type} ${c.nodeClass} access ${c.access}`);
console.log(`browsed Objects/BottlingOpcua/line[0]/s2/id: ${c.browsed}, ${c.nodeClass} of ${c.type}, read only`);
if (c.call !== "Good" || record("s1 to lane A") !== 1) fail(`calling s1.to_working: ${c.call}; the plant counted ${record("s1 to lane A")}`);
console.log(`called line[0].s1.to_working: ${c.call}; the plant's "s1 to lane A": ${record("s1 to lane A")}`);
const passed = record("s2 to lane B") + record("s2 straight on");
if (!(passed >= 5)) fail(`S2 routed ${passed} bottles in 60 s`);
if (c.lastSeen !== passed) fail(`S2's counter ends at ${c.lastSeen}, S2 routed ${passed}`);
const expected = Array.from({ length: passed + 1 }, (_, i) => i);
if (JSON.stringify(c.counter) !== JSON.stringify(expected)) fail(`the monitored counter went ${c.counter}, not 0..${passed} one by one`);
if (c.events.length !== passed) fail(`${c.events.length} events from S2's counter, ${passed} bottles`);
if (c.eventSteps.some((s, i) => i > 0 && s <= c.eventSteps[i - 1])) fail(`event steps not increasing: ${c.eventSteps}`);
console.log(`S2's counter, monitored: ${c.counter.join(",")}; ${c.events.length} events; S2 routed ${passed}`);
if (c.codes.length !== passed || !c.codes.every((code) => /^[A-E]-\d+$/.test(code))) fail(`codes read in S2's reader: ${c.codes}`);
console.log(`codes read in S2's reader as the bottles passed: ${c.codes.join(" ")}`);
console.log("opcua client: ok");
JS
