// What bad clients do to a plant's OPC UA server (tests/unit/opcua/robustness_test.cpp runs
// it while the plant steps at real time): each mode acts for a bounded time, while one more
// client reads Link.SimulatedTime every 100 ms, and prints one JSON line: what the bad
// clients got, and how the other client was answered.
//
//   node abuse.mjs bad-input URL   malformed chunks, unknown services, unknown nodes, writes to
//                                  read-only nodes, clients gone mid-request
//   node abuse.mjs clients URL N   N clients at once, each with a session, reads and a subscription
//   node abuse.mjs flood URL S     four clients reading 30 nodes as fast as they are answered for S s
import net from "node:net";
import ua from "./ua.mjs";

const { OPCUAClient, AttributeIds, DataType } = ua;
const [mode, url, arg] = process.argv.slice(2);
const port = Number(url.split(":")[2].split("/")[0]);
const out = { mode };

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

async function connect() {
    const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0 }, requestedSessionTimeout: 30000 });
    await client.connect(url);
    return { client, session: await client.createSession() };
}

// The other client: a read every 100 ms; the answers and the longest wait for one.
function monitor() {
    const m = { answered: 0, maxWaitMs: 0, simTimes: [], stop: false };
    m.done = (async () => {
        const { client, session } = await connect();
        while (!m.stop) {
            const t0 = Date.now();
            const dv = await session.read({ nodeId: "ns=1;s=Link.SimulatedTime", attributeId: AttributeIds.Value });
            m.maxWaitMs = Math.max(m.maxWaitMs, Date.now() - t0);
            if (dv.statusCode.isGood()) {
                ++m.answered;
                m.simTimes.push(dv.value.value);
            }
            await sleep(Math.max(0, 100 - (Date.now() - t0)));
        }
        await session.close();
        await client.disconnect();
    })();
    return m;
}

// Bytes on a raw TCP connection; what the server answered (the first bytes of its message
// type and, for ERR, its status code) and whether it closed the connection within `ms`.
function raw(bytes, { vanishAfter = -1, ms = 3000 } = {}) {
    return new Promise((resolve) => {
        const sock = net.connect(port, "127.0.0.1");
        const got = [];
        let done = false;
        const finish = (closed) => {
            if (done) return;
            done = true;
            const b = Buffer.concat(got);
            resolve({ closed, reply: b.subarray(0, 3).toString("latin1"),
                      status: b.length >= 12 && b.subarray(0, 3).toString("latin1") === "ERR" ? b.readUInt32LE(8) : null });
            sock.destroy();
        };
        sock.on("connect", () => {
            for (const part of Array.isArray(bytes) ? bytes : [bytes]) sock.write(part);
            if (vanishAfter >= 0) setTimeout(() => { sock.destroy(); finish("vanished"); }, vanishAfter);
        });
        sock.on("data", (d) => got.push(d));
        sock.on("close", () => finish(true));
        sock.on("error", () => {});
        setTimeout(() => finish(false), ms);
    });
}

// A HEL message as OPC UA Part 6 7.1.2.3 has it, for `url`.
function hello() {
    const endpoint = Buffer.from(url, "utf8");
    const b = Buffer.alloc(32 + endpoint.length);
    b.write("HELF", 0, "latin1");
    b.writeUInt32LE(b.length, 4);
    b.writeUInt32LE(0, 8);            // protocol version
    b.writeUInt32LE(65536, 12);       // receive buffer
    b.writeUInt32LE(65536, 16);       // send buffer
    b.writeUInt32LE(0, 20);           // max message size
    b.writeUInt32LE(0, 24);           // max chunk count
    b.writeInt32LE(endpoint.length, 28);
    endpoint.copy(b, 32);
    return b;
}

async function badInput() {
    const chunks = {};
    chunks.notOpcUa = await raw(Buffer.from("GET / HTTP/1.1\r\nHost: plant\r\n\r\n"));
    chunks.hugeChunk = await raw(Buffer.from([0x48, 0x45, 0x4c, 0x46, 0xff, 0xff, 0xff, 0x7f, 1, 2, 3]));
    chunks.shortHello = await raw(Buffer.from([0x48, 0x45, 0x4c, 0x46, 8, 0, 0, 0]));
    const bogus = Buffer.alloc(24);  // a message on a secure channel that was never opened
    bogus.write("MSGF", 0, "latin1");
    bogus.writeUInt32LE(24, 4);
    bogus.writeUInt32LE(12345, 8);
    chunks.noChannel = await raw([hello(), bogus], { ms: 2000 });
    chunks.openHalf = await raw([hello(), Buffer.from("OPNF\x00\x10\x00\x00", "latin1")], { vanishAfter: 300 });
    out.chunks = chunks;

    const { client, session } = await connect();
    const services = {};
    for (const [name, make] of [["QueryFirst", () => new ua.QueryFirstRequest({})],
                                ["RegisterServer", () => new ua.RegisterServerRequest({})],
                                ["AddNodes", () => new ua.AddNodesRequest({ nodesToAdd: [] })],
                                ["HistoryUpdate", () => new ua.HistoryUpdateRequest({})]]) {
        try {
            const r = await session.performMessageTransaction(make());
            services[name] = r.responseHeader.serviceResult.name;
        } catch (err) {
            services[name] = (err.message.match(/Bad\w+/) || [err.message])[0];
        }
    }
    out.services = services;
    const name = (s) => s.name;
    const write = (nodeId, dataType, value) =>
        session.write({ nodeId, attributeId: AttributeIds.Value, value: { value: { dataType, value } } }).then(name);
    out.unknown = {
        read: name((await session.read({ nodeId: "ns=2;i=999", attributeId: AttributeIds.Value })).statusCode),
        write: await write("ns=2;i=999", DataType.Double, 1),
        browse: name((await session.browse("ns=2;s=no.such.object")).statusCode),
        call: name((await session.call({ objectId: "ns=2;s=line[0].s1", methodId: "ns=2;i=999", inputArguments: [] })).statusCode),
        force: name((await session.call({ objectId: "ns=1;s=Link", methodId: "ns=1;s=Link.Force", inputArguments: [
            { dataType: DataType.NodeId, value: ua.coerceNodeId("ns=2;i=999") }, { dataType: DataType.String, value: "open" },
            { dataType: DataType.Boolean, value: false }] })).statusCode),
    };
    out.readOnly = {
        code: await write("ns=2;i=12", DataType.String, "X-1"),        // line[0].s2.id, an output
        counter: await write("ns=2;i=2", DataType.UInt32, 7),          // line[0].s2.seen
        steps: await write("ns=1;s=Link.Steps", DataType.UInt64, 1),
    };
    out.badWrites = {
        wrongType: await write("ns=2;i=62", DataType.String, "fast"),  // line[0].b1.set_speed, a Double in mm/s
        beyondRange: await write("ns=2;i=62", DataType.Double, 1e12),  // 1e9 m/s
        notANumber: await write("ns=2;i=62", DataType.Double, NaN),
        good: await write("ns=2;i=62", DataType.Double, 400),
        badMode: name((await session.call({ objectId: "ns=1;s=Link", methodId: "ns=1;s=Link.Force", inputArguments: [
            { dataType: DataType.NodeId, value: ua.coerceNodeId("ns=2;i=2") }, { dataType: DataType.String, value: "melted" },
            { dataType: DataType.Boolean, value: false }] })).statusCode),
        advanceNotLockstep: name((await session.call({ objectId: "ns=1;s=Link", methodId: "ns=1;s=Link.Advance",
                                                       inputArguments: [{ dataType: DataType.UInt32, value: 1 }] })).statusCode),
    };
    await sleep(300);  // a few steps: the good write is applied
    out.speedAfterWrite = (await session.read({ nodeId: "ns=2;i=60", attributeId: AttributeIds.Value })).value.value;
    await session.close();
    await client.disconnect();

    // A client that sends a request and goes before its answer: a read of every node, then gone.
    const gone = await connect();
    const request = gone.session.read(Array.from({ length: 30 }, (_, i) => ({ nodeId: `ns=2;i=${i + 1}`, attributeId: AttributeIds.Value })));
    request.catch(() => {});
    gone.client._secureChannel?.getTransport?.()?._socket?.destroy();
    out.vanished = true;
}

async function manyClients(n) {
    const results = await Promise.allSettled(Array.from({ length: n }, async () => {
        const { client, session } = await connect();
        let reads = 0;
        const sub = await session.createSubscription2({ requestedPublishingInterval: 100, publishingEnabled: true });
        await sub.monitor({ nodeId: "ns=2;i=60", attributeId: AttributeIds.Value }, { samplingInterval: 50, queueSize: 10 },
                          ua.TimestampsToReturn.Neither);
        for (let i = 0; i < 10; ++i) {
            const dv = await session.read({ nodeId: "ns=1;s=Link.Steps", attributeId: AttributeIds.Value });
            if (dv.statusCode.isGood()) ++reads;
            await sleep(50);
        }
        await sub.terminate();
        await session.close();
        await client.disconnect();
        return reads;
    }));
    out.sessions = results.filter((r) => r.status === "fulfilled" && r.value === 10).length;
    out.failures = results.filter((r) => r.status === "rejected").map((r) => r.reason?.message?.split("\n")[0]).slice(0, 3);
}

async function flood(seconds) {
    const nodes = Array.from({ length: 30 }, (_, i) => ({ nodeId: i < 5 ? `ns=2;i=${i + 1}` : "ns=1;s=Link.Steps", attributeId: AttributeIds.Value }));
    // The four sessions first: on a loaded machine their handshakes alone can take seconds,
    // which are not the flood's.
    const sessions = await Promise.all(Array.from({ length: 4 }, connect));
    const started = Date.now();
    const until = started + seconds * 1000;
    let requests = 0;
    await Promise.all(sessions.map(({ session }) => Promise.all(Array.from({ length: 8 }, async () => {  // eight requests in flight on each
        while (Date.now() < until) {
            await session.read(nodes);
            ++requests;
        }
    }))));
    const took = (Date.now() - started) / 1000;
    for (const { client, session } of sessions) {
        await session.close();
        await client.disconnect();
    }
    out.requests = requests;
    out.perSecond = Math.round(requests / took);
}

const m = monitor();
await sleep(200);
try {
    if (mode === "bad-input") await badInput();
    else if (mode === "clients") await manyClients(Number(arg));
    else if (mode === "flood") await flood(Number(arg));
    else throw new Error(`no mode '${mode}'`);
} catch (err) {
    out.error = err.message;
}
await sleep(300);
m.stop = true;
await m.done;
out.monitor = { answered: m.answered, maxWaitMs: m.maxWaitMs, first: m.simTimes[0], last: m.simTimes[m.simTimes.length - 1] };
console.log(JSON.stringify(out));
process.exit(0);

