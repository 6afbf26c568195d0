// `plant serve` with the OPC UA link (serve_test.sh starts it): a client finds line[0].s2.id,
// reads the plant's simulated time twice a second apart (the served plant runs paced to the
// wall clock, so it advances), and calls the method behind line[0].s1.to_working; prints what
// it saw as one JSON line, which serve_test.sh checks against the page's /events.
//   node serve_test.mjs URL
import ua from "./ua.mjs";

const { OPCUAClient, AttributeIds, BrowseDirection } = ua;
const [url] = process.argv.slice(2);
const out = { type: null, times: [], call: null };
const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 } });
await client.connect(url);
const session = await client.createSession();
async function child(nodeId, name) {
    const r = await session.browse({ nodeId, browseDirection: BrowseDirection.Forward, resultMask: 63,
                                     referenceTypeId: "HierarchicalReferences", includeSubtypes: true });
    const hit = r.references.find((ref) => ref.browseName.name === name);
    if (!hit) throw new Error(`no '${name}' below ${nodeId.toString()} (${r.references.map((x) => x.browseName.name).join(", ")})`);
    return hit.nodeId;
}
const plant = await child("ns=0;i=85", "BottlingOpcua");
const line = await child(plant, "line[0]");
const id = await child(await child(line, "s2"), "id");
const typeNode = (await session.read({ nodeId: id, attributeId: AttributeIds.DataType })).value.value;
out.type = (await session.read({ nodeId: typeNode, attributeId: AttributeIds.BrowseName })).value.value.name;
const simTime = "ns=1;s=Link.SimulatedTime";   // the Link object (docs/plc.md)
for (let i = 0; i < 2; i++) {
    out.times.push((await session.read({ nodeId: simTime, attributeId: AttributeIds.Value })).value.value);
    if (i === 0) await new Promise((r) => setTimeout(r, 1000));
}
const s1 = await child(line, "s1");
out.call = (await session.call({ objectId: s1, methodId: await child(s1, "to_working"), inputArguments: [] })).statusCode.name;
await session.close();
await client.disconnect();
console.log(JSON.stringify(out));
