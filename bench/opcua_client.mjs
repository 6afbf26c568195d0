// The client of plant_bench_opcua (bench/opcua_bench.cpp): one session, one subscription of
// N variables ns=2;i=1..N, sampled and published every 10 ms; prints "subscribed N" once the
// items are created, then counts the notifications until stdin ends (the bench closes it),
// prints "notifications K" and exits.
//   node bench/opcua_client.mjs URL N
import { createRequire } from "node:module";

const require = createRequire(new URL("../opcua/package.json", import.meta.url));
const ua = require("node-opcua");
ua.setWarningLogger(() => {});
const { OPCUAClient, AttributeIds, TimestampsToReturn } = ua;

const [url, n] = process.argv.slice(2);
const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 } });
await client.connect(url);
const session = await client.createSession();
const sub = await session.createSubscription2({ requestedPublishingInterval: 10, requestedMaxKeepAliveCount: 100,
                                                requestedLifetimeCount: 1000, publishingEnabled: true });
const items = Array.from({ length: Number(n) }, (_, i) => ({ nodeId: `ns=2;i=${i + 1}`, attributeId: AttributeIds.Value }));
const group = await sub.monitorItems(items, { samplingInterval: 10, queueSize: 1, discardOldest: true }, TimestampsToReturn.Both);
let notifications = 0;
group.on("changed", () => ++notifications);
process.stdout.write(`subscribed ${items.length}\n`);
process.stdin.resume();
await new Promise((resolve) => process.stdin.on("end", resolve));
process.stdout.write(`notifications ${notifications}\n`);
await sub.terminate();
await session.close();
await client.disconnect();
process.exit(0);
