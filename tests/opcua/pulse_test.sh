#!/usr/bin/env bash
# Subscriptions are served from every step: a client sampling faster than the plant steps
# (2 ms against 6.7 ms) sees each one-step pulse of tests/opcua/pulse.plant, run in real
# time — one for each tick of the timer that makes them, with the same step's timestamp.
#   tests/opcua/pulse_test.sh PLANT SOURCE_DIR
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
start_plant "" run "$src/tests/opcua/pulse.plant" --realtime --opcua-port 0 --for 12s
timeout 60 node "$(dirname "$0")/pulse_test.mjs" "$url" 5 > "$work/client" || { echo "FAIL: the client"; cat "$work/client"; exit 1; }
kill "$pid" 2>/dev/null || true
node - "$work/client" <<'JS'
const c = JSON.parse(require("fs").readFileSync(process.argv[2], "utf8"));
const fail = (why) => { console.log(`FAIL: ${why}\n${JSON.stringify(c)}`); process.exit(1); };
if (!(c.revised > 0 && c.revised < 1000 / 150)) fail(`the sampling interval was revised to ${c.revised} ms`);
// The ticks seen after the first notification; a pulse seen before the first tick is not counted.
const pulses = c.pulses.filter((t) => c.ticks.length && t >= c.ticks[0]);
if (c.ticks.length < 15) fail(`${c.ticks.length} ticks in 5 s`);
if (JSON.stringify(pulses) !== JSON.stringify(c.ticks)) fail(`pulses at ${pulses}, ticks at ${c.ticks}`);
console.log(`sampling every ${c.revised} ms: ${pulses.length} one-step pulses seen, one per tick (${c.values} values)`);
console.log("opcua pulses: ok");
JS
