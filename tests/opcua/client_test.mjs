// Issue #33's client checks, with node-opcua-client in its own process against
// `plant run plants/bottling_opcua.plant --lockstep` (client_test.sh starts it):
//   - browse from Objects to line[0].s2.id by browse names, and find its type (String);
//   - call the method behind line[0].s1.to_working;
//   - a monitored item on S2's `seen` counter (sampling 0: every change) and a subscription
//     to the plant object's events; the client advances the plant STEPS steps, a few at a time,
//     and after each Advance reads S2's counter and its reader's code: a bottle's code while
//     it passes;
// and prints what it saw as one JSON line, which client_test.sh checks against the run's summary.
//   node client_test.mjs URL STEPS
import ua from "./ua.mjs";

const { OPCUAClient, AttributeIds, DataType, TimestampsToReturn, NodeClass, BrowseDirection } = ua;
const [url, stepsArg] = process.argv.slice(2);
const total = Number(stepsArg);
const out = { browsed: null, type: null, nodeClass: null, access: null, call: null, codes: [], counter: [], events: [],
              eventSteps: [], advanced: 0, lastSeen: null };

const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 } });
await client.connect(url);
const session = await client.createSession();

// Browse by names only, as a client that knows the plant's paths and nothing else would.
async function child(nodeId, name) {
    const r = await session.browse({ nodeId, browseDirection: BrowseDirection.Forward, resultMask: 63,
                                     referenceTypeId: "HierarchicalReferences", includeSubtypes: true });
    const hit = r.references.find((ref) => ref.browseName.name === name);
    if (!hit) throw new Error(`no '${name}' below ${nodeId.toString()} (${r.references.map((x) => x.browseName.name).join(", ")})`);
    return hit.nodeId;
}
const objects = "ns=0;i=85";
const plantName = (await session.browse(objects)).references.map((r) => r.browseName.name).find((n) => n === "BottlingOpcua");
let at = await child(objects, plantName);
for (const step of ["line[0]", "s2", "id"]) at = await child(at, step);
out.browsed = at.toString();
const attrs = await session.read([AttributeIds.DataType, AttributeIds.NodeClass, AttributeIds.AccessLevel]
    .map((attributeId) => ({ nodeId: at, attributeId })));
const typeNode = attrs[0].value.value;
out.type = (await session.read({ nodeId: typeNode, attributeId: AttributeIds.BrowseName })).value.value.name;
out.nodeClass = NodeClass[attrs[1].value.value];
out.access = attrs[2].value.value;

let s1 = await child(await child(objects, plantName), "line[0]");
s1 = await child(s1, "s1");
const toWorking = await child(s1, "to_working");
out.call = (await session.call({ objectId: s1, methodId: toWorking, inputArguments: [] })).statusCode.name;

const sub = await session.createSubscription2({ requestedPublishingInterval: 10, requestedMaxKeepAliveCount: 50,
                                                requestedLifetimeCount: 1000, publishingEnabled: true,
                                                maxNotificationsPerPublish: 0 });
const seen = await sub.monitor({ nodeId: "ns=2;i=2", attributeId: AttributeIds.Value },
                               { samplingInterval: 0, queueSize: 1000, discardOldest: false }, TimestampsToReturn.Both);
seen.on("changed", (dv) => out.counter.push(dv.value.value));
const fields = ["SourceName", "1:Steps", "1:SimulatedTime", "EventType"];  // ours are in the server's namespace
const events = await sub.monitor({ nodeId: "ns=1;s=Plant", attributeId: AttributeIds.EventNotifier },
                                 { queueSize: 1000, discardOldest: false, filter: ua.constructEventFilter(fields) },
                                 TimestampsToReturn.Both);
events.on("changed", (f) => {
    if (f[0].value !== "line[0].s2.seen") return;
    out.events.push(f[0].value);
    const s = f[1].value;
    out.eventSteps.push(Array.isArray(s) ? s[0] * 4294967296 + s[1] : Number(s));
});

const uint64 = (v) => (Array.isArray(v) ? v[0] * 4294967296 + v[1] : Number(v));
let lastCount = 0;
let done = 0;
while (done < total) {
    const n = Math.min(15, total - done);
    const r = await session.call({ objectId: "ns=1;s=Link", methodId: "ns=1;s=Link.Advance",
                                   inputArguments: [{ dataType: DataType.UInt32, value: n }] });
    if (r.statusCode.isNotGood()) throw new Error(`Advance: ${r.statusCode.toString()}`);
    done = uint64(r.outputArguments[0].value);
    ++out.advanced;
    const [count, code] = await session.read([{ nodeId: "ns=2;i=2", attributeId: AttributeIds.Value },
                                              { nodeId: "ns=2;i=12", attributeId: AttributeIds.Value }]);
    if (count.value.value !== lastCount) out.codes.push(code.value.value);  // the bottle in S2's reader now
    lastCount = count.value.value;
}
out.lastSeen = lastCount;
await new Promise((resolve) => setTimeout(resolve, 300));  // the last publish
await sub.terminate();
await session.close();
await client.disconnect();
console.log(JSON.stringify(out));
