#!/usr/bin/env node
// The OPC UA server of a plant's `opcua` link (docs/plc.md, "OPC UA"), on node-opcua.
// `plant run` and `plant serve` start it as a child process and speak to it over fd 3
// (channel.mjs; runtime/opcua/channel.h has the format): the plant sends its configuration,
// then every step's changes; the server sends what clients write and call, which the plant
// applies as events at its next step boundary. It exits when the plant closes the channel.
//
//   node opcua/server.mjs --init-pki [DIR]   create the server's certificate (scripts/setup.sh)
import ua from "node-opcua";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

import { buildAddressSpace, fromVariant, toVariant } from "./address_space.mjs";
import { openChannel, pack } from "./channel.mjs";
import { samplePlantNodes, setStep } from "./sampling.mjs";
import { checkUser, loadUsers } from "./users.mjs";

const { OPCUAServer, OPCUACertificateManager, SecurityPolicy, MessageSecurityMode, StatusCodes, DataType, Variant,
        coerceNodeId, makeApplicationUrn } = ua;

// node-opcua's notices: ours are prefixed, the RSA PKCS#1 v1.5 one is not for us (we offer
// no Basic128Rsa15), and a flood of bad clients does not flood the plant's stderr.
let notices = 0;
const notice = (kind) => (_context, ...args) => {
    const text = args.map((a) => (a instanceof Error ? a.message : String(a))).join(" ");
    if (text.includes("NODE-OPCUA-W27") || text.includes("security-revert")) return;
    if (++notices <= 50) process.stderr.write(`plant opcua: ${kind}: ${text}\n`);
    else if (notices === 51) process.stderr.write("plant opcua: further notices are not shown\n");
};
ua.setWarningLogger(notice("warning"));
ua.setErrorLogger(notice("error"));
ua.MonitoredItem.minimumSamplingInterval = 1;  // ms: a client may sample faster than the plant steps
samplePlantNodes();  // from each step's snapshot, not on a timer (sampling.mjs)

const HERE = path.dirname(fileURLToPath(import.meta.url));
const PRODUCT = "Plant";

function identity() {
    const hostname = os.hostname();
    return { applicationUri: makeApplicationUrn(hostname, PRODUCT), productUri: "urn:plant",
             applicationName: { text: `${PRODUCT} OPC UA server (${hostname})` } };
}

async function certificates(dir, acceptUnknown) {
    const cm = new OPCUACertificateManager({ rootFolder: dir, automaticallyAcceptUnknownCertificate: acceptUnknown });
    await cm.initialize();
    return cm;
}

// --init-pki: the PKI folder and the server's own self-signed certificate, once.
async function initPki(dir) {
    const server = new OPCUAServer({ port: 0, serverCertificateManager: await certificates(dir, false), serverInfo: identity() });
    await server.initializeCM();
    process.stdout.write(`plant opcua: the server's certificate is ${server.certificateFile}\n`);
    process.exit(0);
}

if (process.argv[2] === "--init-pki") await initPki(path.resolve(process.argv[3] || path.join(HERE, "pki")));

process.on("SIGINT", () => {});  // the plant ends the run, then the channel: we go with it
// The plant's step comes first: a flood of clients slows this server, not the plant.
try {
    os.setPriority(0, Math.min(19, os.getPriority(0) + 5));
} catch {
    /* not allowed here: the plant keeps its own priority anyway */
}

const POLICIES = { None: SecurityPolicy.None, Basic256Sha256: SecurityPolicy.Basic256Sha256 };
const MODES = ["", "stuck", "open", "invert"];  // ForceMode: none, stuck, open, invert

let channel;
let server = null;
let space = null;
let config = null;
let nextRequest = 1;
const waiting = new Map();  // request id -> resolve({status, steps})
let shuttingDown = false;

function request(type, ...fields) {
    if (shuttingDown) return Promise.resolve({ status: StatusCodes.BadShutdown.value, steps: 0 });
    const id = nextRequest++ >>> 0;
    return new Promise((resolve) => {
        waiting.set(id, resolve);
        channel.send(type, pack(["u32", id], ...fields));
    });
}

const statusOf = (value) => {
    for (const [, s] of Object.entries(StatusCodes)) if (s && s.value === value) return s;
    return StatusCodes.BadInternalError;
};

const handlers = {
    async write(node, variant) {
        if (node.type === "String") {
            if (typeof variant.value !== "string") return StatusCodes.BadTypeMismatch;
            return statusOf((await request("Y", ["u32", node.index], ["text", variant.value])).status);
        }
        const v = fromVariant(node, variant);
        if (v === null) return StatusCodes.BadTypeMismatch;
        return statusOf((await request("W", ["u32", node.index], ["f64", v])).status);
    },
    async call(node) {
        return statusOf((await request("M", ["u32", node.index])).status);
    },
    async advance(args) {
        const n = args[0]?.value;
        const r = await request("A", ["u32", n]);
        const steps = Math.max(0, Math.round(r.steps));
        return { statusCode: statusOf(r.status),
                 outputArguments: [new Variant({ dataType: DataType.UInt64, value: steps })] };
    },
    async force(args) {
        const node = nodeOf(args[0]?.value);
        if (!node) return { statusCode: StatusCodes.BadNodeIdUnknown };
        const mode = MODES.indexOf(String(args[1]?.value ?? "").toLowerCase());
        if (mode <= 0) return { statusCode: StatusCodes.BadInvalidArgument };
        let value = 0;
        let text = "";
        if (mode === 1) {
            const given = args[2];
            if (node.type === "String") {
                if (typeof given?.value !== "string") return { statusCode: StatusCodes.BadTypeMismatch };
                text = given.value;
            } else {
                const asType = node.class === "variable" ? node : { ...node, type: "Boolean" };  // a method or counter: on or off
                const v = fromVariant(asType, given);
                if (v === null) return { statusCode: StatusCodes.BadTypeMismatch };
                value = v;
            }
        }
        const r = await request("F", ["u32", node.index], ["u8", mode], ["f64", value], ["text", text]);
        return { statusCode: statusOf(r.status) };
    },
    async release(args) {
        const node = nodeOf(args[0]?.value);
        if (!node) return { statusCode: StatusCodes.BadNodeIdUnknown };
        const r = await request("F", ["u32", node.index], ["u8", 0], ["f64", 0], ["text", ""]);
        return { statusCode: statusOf(r.status) };
    },
};

function nodeOf(nodeId) {
    if (!nodeId || !space) return null;
    let id;
    try {
        id = coerceNodeId(nodeId);
    } catch {
        return null;
    }
    if (id.namespace !== space.namespaceIndex || typeof id.value !== "number") return null;
    return space.byId.get(id.value) ?? null;
}

// ---- the plant's steps ----

let stepTime = new Date();
let steps = 0;
let simTime = 0;
let dropped = 0;

function setNode(node, variant) {
    node.value = variant;
    node.ua.setValueFromSource(variant, node.forced ? StatusCodes.UncertainSubstituteValue : StatusCodes.Good, stepTime);
}

function applySteps(buf) {
    let at = 0;
    const nodes = space.nodes;
    while (at < buf.length) {
        const tag = String.fromCharCode(buf[at++]);
        if (tag === "T") {
            steps = buf.readDoubleLE(at);
            simTime = buf.readDoubleLE(at + 8);
            at += 16;
            stepTime = new Date();
            if (steps > 0) setStep(simTime / steps);
        } else if (tag === "V" || tag === "E") {
            const node = nodes[buf.readUInt32LE(at)];
            const value = buf.readDoubleLE(at + 4);
            at += 12;
            setNode(node, toVariant(node, value));
            if (tag === "E")
                node.parent.raiseEvent(space.eventType, {
                    sourceNode: { dataType: DataType.NodeId, value: node.ua.nodeId },
                    sourceName: { dataType: DataType.String, value: node.path },
                    message: { dataType: DataType.LocalizedText, value: { text: `${node.path} (step ${steps})` } },
                    severity: { dataType: DataType.UInt16, value: 100 },
                    steps: { dataType: DataType.UInt64, value: steps },
                    simulatedTime: { dataType: DataType.Double, value: simTime },
                });
        } else if (tag === "X") {
            const node = nodes[buf.readUInt32LE(at)];
            const length = buf.readUInt32LE(at + 4);
            setNode(node, { dataType: DataType.String, value: buf.toString("utf8", at + 8, at + 8 + length) });
            at += 8 + length;
        } else if (tag === "Q") {
            const node = nodes[buf.readUInt32LE(at)];
            node.forced = buf[at + 4];
            at += 5;
            if (node.class !== "method" && node.value !== undefined) setNode(node, node.value);
        } else if (tag === "D") {
            dropped += buf.readUInt32LE(at);
            at += 4;
        } else {
            throw new Error(`a step record '${tag}' from the plant`);
        }
    }
    const l = space.linkNodes;
    l.steps.setValueFromSource({ dataType: DataType.UInt64, value: steps });
    l.time.setValueFromSource({ dataType: DataType.Double, value: simTime });
    if (simTime > 0) l.rate.setValueFromSource({ dataType: DataType.Double, value: Math.round(steps / simTime * 1e6) / 1e6 });
    l.dropped.setValueFromSource({ dataType: DataType.UInt32, value: dropped % 4294967296 });
}

// ---- start and stop ----

async function start(cfg) {
    config = cfg;
    setStep(cfg.step);
    let users = null;
    if (cfg.users) users = loadUsers(cfg.users);
    const loopback = cfg.anonymousWrites;
    const policies = cfg.policies.map((p) => POLICIES[p]);
    const modes = [];
    if (cfg.policies.includes("None")) modes.push(MessageSecurityMode.None);
    if (cfg.policies.includes("Basic256Sha256")) modes.push(MessageSecurityMode.Sign, MessageSecurityMode.SignAndEncrypt);
    const host = cfg.host || "127.0.0.1";
    server = new OPCUAServer({
        port: cfg.port,
        host,
        hostname: host === "0.0.0.0" ? os.hostname() : host,
        resourcePath: cfg.resource || "",
        securityPolicies: policies,
        securityModes: modes,
        allowAnonymous: true,
        // On loopback the client runs on this machine: its certificate is taken. Elsewhere an
        // unknown one is refused and kept in pki/rejected until someone trusts it.
        serverCertificateManager: await certificates(cfg.pki, loopback),
        userManager: users ? { isValidUserAsync: (name, password, callback) => checkUser(users, name, password, callback) } : undefined,
        serverInfo: identity(),
        buildInfo: { productName: PRODUCT, manufacturerName: "Plant", softwareVersion: "1.0" },
        serverCapabilities: { minSupportedSampleRate: 0, maxSessions: 200, maxSubscriptions: 1000 },
        maxConnectionsPerEndpoint: 200,
        isAuditing: false,
    });
    await server.initialize();
    space = buildAddressSpace(server, cfg, handlers);
    await server.start();
    const url = server.getEndpointUrl();
    channel.send("R", Buffer.from(JSON.stringify({ url, port: server.endpoints[0].port }), "utf8"));
}

async function stop(code) {
    if (shuttingDown) return;
    shuttingDown = true;
    for (const resolve of waiting.values()) resolve({ status: StatusCodes.BadShutdown.value, steps });
    waiting.clear();
    const watchdog = setTimeout(() => process.exit(code), 5000);
    watchdog.unref();
    try {
        if (server) await server.shutdown(100);
    } catch {
        /* going anyway */
    }
    process.exit(code);
}

function fail(message) {
    try {
        channel.send("E", Buffer.from(message, "utf8"));
    } catch {
        /* the plant has gone */
    }
    channel.close();
    setTimeout(() => process.exit(1), 100);
}

channel = openChannel(3, (type, payload) => {
    try {
        if (type === "C") {
            start(JSON.parse(payload.toString("utf8"))).catch((err) => fail(startError(err)));
        } else if (type === "S") {
            if (space) applySteps(payload);
        } else if (type === "K") {
            const id = payload.readUInt32LE(0);
            const resolve = waiting.get(id);
            waiting.delete(id);
            resolve?.({ status: payload.readUInt32LE(4), steps: payload.readDoubleLE(8) });
        }
    } catch (err) {
        process.stderr.write(`plant opcua: error: ${err.stack || err}\n`);
        stop(1);
    }
}, () => stop(0));

function startError(err) {
    const text = err?.message || String(err);
    if (/EADDRINUSE/.test(text) || err?.code === "EADDRINUSE")
        return `the OPC UA server cannot listen on ${config.host}:${config.port}: the port is in use`;
    if (/EADDRNOTAVAIL/.test(text)) return `the OPC UA server cannot listen on ${config.host}: no such address on this machine`;
    return `the OPC UA server did not start: ${text}`;
}
