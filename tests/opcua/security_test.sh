#!/usr/bin/env bash
# Issue #33 §3: the OPC UA link served on 127.0.0.2, which it treats as any address but
# 127.0.0.1 (docs/plc.md, "OPC UA", Security), with a users file made by opcua/passwd.mjs and a
# PKI folder of its own that the server fills on its first start. A client (security_test.mjs)
# finds only Basic256Sha256 endpoints; SecurityPolicy None is refused; its unknown certificate
# is refused and kept in rejected/ until moved to trusted/; then anonymous reads and is refused
# writes and calls; a wrong password is refused; the user writes and calls. The plant counts
# the one call (its record "s1 to lane A") and applies the one write.
#   tests/opcua/security_test.sh PLANT SOURCE_DIR
set -euo pipefail
plant="$1" src="$2"
work=$(mktemp -d) pid=""
trap 'kill "$pid" 2>/dev/null || true; rm -rf "$work"' EXIT
. "$(dirname "$0")/start_plant.sh"
printf 'opcua-test-%s\n' "$$" > "$work/password"
node "$src/opcua/passwd.mjs" operator < "$work/password" > "$work/users"
start_plant "" run "$src/plants/bottling_opcua.plant" --realtime --for 120s --opcua-host 127.0.0.2 --opcua-port 0 \
  --opcua-pki "$work/pki" --opcua-users "$work/users"
grep -q 'security Basic256Sha256; anonymous clients may only read' "$work/err" ||
  { echo "FAIL: the plant did not say how it serves 127.0.0.2"; cat "$work/err"; exit 1; }
timeout 120 node "$(dirname "$0")/security_test.mjs" "$url" "$work/client-pki" "$work/pki" operator "$(cat "$work/password")" \
  > "$work/client" || { echo "FAIL: the client"; cat "$work/client"; exit 1; }
kill -INT "$pid"
wait "$pid" || true
node - "$work/client" "$work/out" <<'JS'
const fs = require("fs");
const [clientFile, summaryFile] = process.argv.slice(2);
const c = JSON.parse(fs.readFileSync(clientFile, "utf8"));
const summary = fs.readFileSync(summaryFile, "utf8");
const fail = (why) => { console.log(`FAIL: ${why}\n${JSON.stringify(c)}`); process.exit(1); };
if (!c.endpoints.length || c.endpoints.some((e) => !e.startsWith("Basic256Sha256/"))) fail(`endpoints ${c.endpoints}`);
if (!c.endpoints.every((e) => /UserName/.test(e) && /Anonymous/.test(e))) fail(`user tokens ${c.endpoints}`);
console.log(`endpoints on 127.0.0.2: ${c.endpoints.join(", ")}`);
if (c.none === "Good") fail("a session over SecurityPolicy None");
if (!/^Bad/.test(c.noneByServer)) fail(`CreateSession over SecurityPolicy None: ${c.noneByServer}`);
console.log(`SecurityPolicy None: the client library refuses (${c.none.trim()}); the server answers CreateSession ${c.noneByServer}`);
if (c.unknownCertificate === "Good" || c.rejectedKept < 1) fail(`an unknown certificate: ${c.unknownCertificate}, ${c.rejectedKept} kept`);
console.log(`an unknown client certificate: ${c.unknownCertificate}, kept in pki/rejected; moved to pki/trusted/certs`);
const a = c.anonymous;
if (a.read !== "Good" || a.write !== "BadUserAccessDenied" || a.call !== "BadUserAccessDenied") fail(`anonymous: ${JSON.stringify(a)}`);
console.log(`anonymous: read ${a.read}, write ${a.write}, call ${a.call}`);
if (c.wrongPassword === "Good") fail("a wrong password was taken");
console.log(`a wrong password: ${c.wrongPassword}`);
const u = c.user;
if (u.read !== "Good" || u.write !== "Good" || u.call !== "Good") fail(`the user: ${JSON.stringify(u)}`);
const calls = Number((summary.match(/^  s1 to lane A +(\d+) events/m) || [])[1]);
if (calls !== 1) fail(`the plant counted ${calls} calls of s1.to_working\n${summary}`);
console.log(`user operator: read ${u.read}, write ${u.write}, call ${u.call}; the plant's "s1 to lane A": ${calls}`);
console.log("opcua security: ok");
JS
