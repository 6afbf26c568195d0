#!/usr/bin/env node
// The routing control of the bottling line as a controller outside the plant, over OPC UA
// (node-opcua-client): what examples/plc/router.py does over Modbus, with the same rule and
// the same results.
//
// plants/bottling_opcua.plant declares the node map (`plant info --opcua` prints it), all in
// its namespace (ns=2): for switch k (S1..S5, k = 1..5) node k counts the bottles its ID
// reader saw and node 10 + k holds the code read last; method 20 + k sends the bottle into
// the switch's lane, method 30 + k straight on. Exit k (A..E): node 40 + k counts the
// bottles it took, node 50 + k holds the code of the last one. Lane k is the letter A..E the
// code starts with.
//
// The rule (the plant's own RoutedSwitch, docs/stdlib.md): a bottle goes into a lane when its
// code names that lane and it is filled and capped. New bottles are set down just before S5
// and pass it once before they reach the filling and capping stations, so a bottle is due at
// S1..S4 always and at S5 from its second pass on: the controller remembers the codes S5 saw.
//
//   node router_opcua.mjs URL                     subscribe to the readers' counters and
//                                                 route each bottle as it is seen, until the plant stops
//   node router_opcua.mjs URL --lockstep STEPS    drive `plant run --lockstep`: Link.Advance two
//                                                 steps at a time, then read and route
//   ... --lockstep STEPS --fault NODE FROM TO     and force node NODE open (Link.Force) from
//                                                 step FROM, release it at step TO
//
// It prints one line per bottle an exit took and a summary; exit status 1 if a bottle went
// into a lane its code does not name.
//
// node-opcua comes from the server's package folder (opcua/, installed by scripts/setup.sh);
// a copy of this file elsewhere needs `npm install node-opcua-client` and a plain import.
import { createRequire } from "node:module";

const require = createRequire(new URL("../../opcua/package.json", import.meta.url));
const ua = require("node-opcua");
ua.setWarningLogger(() => {});

const { OPCUAClient, AttributeIds, DataType, TimestampsToReturn } = ua;

const LANES = "ABCDE";
const NS = 2;
const node = (id) => `ns=${NS};i=${id}`;
const SEEN = (k) => node(1 + k), ID = (k) => node(11 + k), TO_LANE = (k) => node(21 + k), STRAIGHT = (k) => node(31 + k);
const EXIT_COUNT = (k) => node(41 + k), EXIT_ID = (k) => node(51 + k);
const SWITCH = (k) => `ns=${NS};s=line[0].s${k + 1}`;
const LINK = "ns=1;s=Link";

function usage(message) {
    process.stderr.write(`router_opcua: ${message}\nusage: node router_opcua.mjs URL [--lockstep STEPS [--fault NODE FROM TO]]\n`);
    process.exit(2);
}

function parseArgs(argv) {
    const a = { url: argv[0], lockstep: 0, fault: null };
    if (!a.url || !a.url.startsWith("opc.tcp://")) usage("the first argument is the server's URL, opc.tcp://HOST:PORT");
    for (let i = 1; i < argv.length; ++i) {
        const int = (s) => (/^\d+$/.test(s ?? "") ? Number(s) : usage(`'${s}' is not a whole number`));
        if (argv[i] === "--lockstep") a.lockstep = int(argv[++i]);
        else if (argv[i] === "--fault") a.fault = [int(argv[++i]), int(argv[++i]), int(argv[++i])];
        else usage(`unknown argument '${argv[i]}'`);
    }
    if (a.fault && !a.lockstep) usage("--fault needs --lockstep");
    return a;
}

// What a call gets when the run has ended under it: the server is shutting down.
const ENDED = /closed|BadSessionIdInvalid|BadConnectionClosed|BadShutdown|BadServerHalted|socket|premature/i;

const uint64 = (v) => (Array.isArray(v) ? v[0] * 4294967296 + v[1] : Number(v));

class Router {
    constructor(session) {
        this.session = session;
        this.passedS5 = new Set();  // codes S5 has seen: those bottles are on their second pass
        this.routed = 0;
        this.commissioned = Object.fromEntries([...LANES].map((l) => [l, 0]));
        this.wrong = 0;
    }

    async check(status, what) {
        if (status.isNotGood()) throw new Error(`${what}: ${status.toString()}`);
    }

    // A bottle at switch k with `code`: into the lane or straight on, a method call each.
    async route(k, code) {
        const due = k < 4 || this.passedS5.has(code);
        if (k === 4) this.passedS5.add(code);
        const lane = due && code[0] === LANES[k];
        const r = await this.session.call({ objectId: SWITCH(k), methodId: lane ? TO_LANE(k) : STRAIGHT(k), inputArguments: [] });
        await this.check(r.statusCode, `calling ${lane ? "to_working" : "to_base"} of S${k + 1}`);
        this.routed += lane ? 1 : 0;
    }

    took(k, count, previous, code) {
        this.commissioned[LANES[k]] += count - previous;
        const ok = code[0] === LANES[k];
        this.wrong += ok ? 0 : 1;
        console.log(`router: exit ${LANES[k]} took ${code}${ok ? "" : "  WRONG LANE"}`);
    }

    summary() {
        const total = Object.values(this.commissioned).reduce((x, y) => x + y, 0);
        const lanes = Object.entries(this.commissioned).map(([l, n]) => `${l} ${n}`).join(", ");
        console.log(`router: ${this.routed} bottles sent into a lane; exits took ${total} (${lanes}); ${this.wrong} in a wrong lane`);
    }
}

// Lock-step: the plant runs only the steps granted; after each grant, one Read of every
// reader and exit, and the calls it asks for, applied at the next step as router.py's writes.
async function lockstep(session, router, a) {
    const ids = [];
    for (let k = 0; k < 5; ++k) ids.push(SEEN(k), ID(k), EXIT_COUNT(k), EXIT_ID(k));
    let last = null;
    const scan = async () => {
        const values = (await session.read(ids.map((nodeId) => ({ nodeId, attributeId: AttributeIds.Value })))).map((d) => d.value.value);
        const now = [];
        for (let k = 0; k < 5; ++k) now.push({ seen: values[4 * k], id: values[4 * k + 1], taken: values[4 * k + 2], exitId: values[4 * k + 3] });
        if (!last) last = now;
        for (let k = 0; k < 5; ++k) {
            if (now[k].seen !== last[k].seen) await router.route(k, now[k].id);
            if (now[k].taken !== last[k].taken) router.took(k, now[k].taken, last[k].taken, now[k].exitId);
        }
        last = now;
    };
    const steps = uint64((await session.read({ nodeId: `${LINK}.Steps`, attributeId: AttributeIds.Value })).value.value);
    let done = steps;
    await scan();
    while (done < a.lockstep) {
        if (a.fault && (done === a.fault[1] || done === a.fault[2])) {
            const open = done === a.fault[1];
            const r = await session.call({
                objectId: LINK, methodId: `${LINK}.${open ? "Force" : "Release"}`,
                inputArguments: open ? [{ dataType: DataType.NodeId, value: ua.coerceNodeId(node(a.fault[0])) }, { dataType: DataType.String, value: "open" },
                                        { dataType: DataType.Boolean, value: false }]
                                     : [{ dataType: DataType.NodeId, value: ua.coerceNodeId(node(a.fault[0])) }],
            });
            await router.check(r.statusCode, open ? "Link.Force" : "Link.Release");
            console.log(`router: step ${done}: node ${a.fault[0]} ${open ? "open" : "released"}`);
        }
        const n = Math.min(2, a.lockstep - done);
        const last_grant = done + n === a.lockstep;
        const call = session.call({ objectId: LINK, methodId: `${LINK}.Advance`, inputArguments: [{ dataType: DataType.UInt32, value: n }] });
        if (last_grant) {
            // The run ends after its last step: the server may go before it answers.
            await call.catch(() => {});
            break;
        }
        const r = await call;
        await router.check(r.statusCode, "Link.Advance");
        done = uint64(r.outputArguments[0].value);
        await scan();
    }
}

// Real time: a subscription to every reader's and exit's counter; each change is routed as
// it arrives, in order, until the server goes (the run ended).
async function subscribe(client, session, router) {
    const sub = await session.createSubscription2({ requestedPublishingInterval: 10, requestedMaxKeepAliveCount: 20,
                                                    requestedLifetimeCount: 600, publishingEnabled: true });
    let work = Promise.resolve();
    const queue = (job) => (work = work.then(job).catch((err) => {
        if (!ENDED.test(err.message)) console.error(`router_opcua: ${err.message}`);
    }));
    for (let k = 0; k < 5; ++k) {
        for (const [nodeId, onChange] of [[SEEN(k), seenChanged(k)], [EXIT_COUNT(k), exitChanged(k)]]) {
            const item = await sub.monitor({ nodeId, attributeId: AttributeIds.Value },
                                           { samplingInterval: 0, queueSize: 100, discardOldest: false }, TimestampsToReturn.Neither);
            let previous = null;
            item.on("changed", (dv) => {
                const value = dv.value.value;
                const before = previous;
                previous = value;
                if (before !== null && value !== before) queue(() => onChange(value, before));
            });
        }
    }
    function seenChanged(k) {
        return async () => {
            const code = (await session.read({ nodeId: ID(k), attributeId: AttributeIds.Value })).value.value;
            await router.route(k, code);
        };
    }
    function exitChanged(k) {
        return async (count, before) => {
            const code = (await session.read({ nodeId: EXIT_ID(k), attributeId: AttributeIds.Value })).value.value;
            router.took(k, count, before, code);
        };
    }
    await new Promise((resolve) => {
        client.on("connection_lost", resolve);
        client.on("close", resolve);
        session.on("session_closed", resolve);
    });
    await work;
}

async function main() {
    const a = parseArgs(process.argv.slice(2));
    const client = OPCUAClient.create({ endpointMustExist: false, connectionStrategy: { maxRetry: 0, initialDelay: 100, maxDelay: 200 },
                                       requestedSessionTimeout: 60000 });
    const deadline = Date.now() + 30000;
    for (;;) {
        try {
            await client.connect(a.url);
            break;
        } catch (err) {
            if (Date.now() > deadline) {
                console.error(`router_opcua: cannot connect to ${a.url}: ${err.message}`);
                process.exit(1);
            }
            await new Promise((r) => setTimeout(r, 200));
        }
    }
    const session = await client.createSession();
    const router = new Router(session);
    try {
        if (a.lockstep) await lockstep(session, router, a);
        else await subscribe(client, session, router);
    } catch (err) {
        if (!ENDED.test(err.message)) {
            console.error(`router_opcua: ${err.message}`);
            process.exit(1);
        }
    }
    router.summary();
    await client.disconnect().catch(() => {});
    process.exit(router.wrong ? 1 : 0);
}

await main();
