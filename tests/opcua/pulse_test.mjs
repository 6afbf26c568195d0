// A client sampling faster than the plant steps sees every one-step pulse (pulse.plant):
// node 1 is 1 for one step every 200 ms, node 2 counts the ticks that make the pulses. It
// monitors both for SECONDS, node 1 at a sampling interval of 2 ms (a step is 6.7 ms), and
// prints as JSON the steps' timestamps of the pulses it saw and of the ticks.
//   node pulse_test.mjs URL SECONDS
import ua from "./ua.mjs";

const { OPCUAClient, AttributeIds, TimestampsToReturn } = ua;
const [url, seconds] = process.argv.slice(2);
const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 } });
await client.connect(url);
const session = await client.createSession();
const sub = await session.createSubscription2({ requestedPublishingInterval: 20, requestedMaxKeepAliveCount: 50,
                                                requestedLifetimeCount: 1000, publishingEnabled: true });
const out = { revised: 0, pulses: [], ticks: [], values: 0 };
const pulse = await sub.monitor({ nodeId: "ns=2;i=1", attributeId: AttributeIds.Value },
                                { samplingInterval: 2, queueSize: 1000, discardOldest: false }, TimestampsToReturn.Both);
out.revised = pulse.result?.revisedSamplingInterval ?? pulse.monitoringParameters?.samplingInterval;
let last = null;
pulse.on("changed", (dv) => {
    ++out.values;
    if (dv.value.value === 1 && last === 0) out.pulses.push(dv.sourceTimestamp.getTime());
    last = dv.value.value;
});
const ticks = await sub.monitor({ nodeId: "ns=2;i=2", attributeId: AttributeIds.Value },
                                { samplingInterval: 0, queueSize: 1000, discardOldest: false }, TimestampsToReturn.Both);
let first = true;
ticks.on("changed", (dv) => {
    if (!first) out.ticks.push(dv.sourceTimestamp.getTime());
    first = false;
});
await new Promise((resolve) => setTimeout(resolve, Number(seconds) * 1000));
await sub.terminate();
await session.close();
await client.disconnect();
console.log(JSON.stringify(out));
