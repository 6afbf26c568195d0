// The plant's address space (docs/plc.md, "OPC UA"): under Objects an object for the plant
// (ns=1;s=Plant) and below it an object per step of each mapped slot's dotted path
// (ns=2;s=line[0].s2), each entry one node ns=2;i=KEY: a variable, a method (a void input)
// or a UInt32 counter whose activations are also SlotEventType events from its object;
// and the Link object (ns=1;s=Link) with the link's status and its methods.
import ua from "node-opcua";

import { markPlantNode } from "./sampling.mjs";

const { DataType, Variant, StatusCodes, WellKnownRoles, PermissionType, makeEUInformation } = ua;

const READ = PermissionType.Browse | PermissionType.Read | PermissionType.ReadRolePermissions | PermissionType.ReceiveEvents;
const ALL = READ | PermissionType.Write | PermissionType.Call;

// Who may write and call: everyone on loopback; off loopback only a user who logged in.
export function permissions(anonymousWrites) {
    return [
        { roleId: WellKnownRoles.Anonymous, permissions: anonymousWrites ? ALL : READ },
        { roleId: WellKnownRoles.AuthenticatedUser, permissions: ALL },
    ];
}

const TYPES = {
    Boolean: DataType.Boolean,
    Int32: DataType.Int32,
    Double: DataType.Double,
    String: DataType.String,
    UInt32: DataType.UInt32,
};

// A slot's SI value (a double from the plant) as the node's Variant.
export function toVariant(node, value) {
    switch (node.type) {
        case "Boolean": return { dataType: DataType.Boolean, value: value !== 0 };
        case "Int32": return { dataType: DataType.Int32, value: Math.max(-2147483648, Math.min(2147483647, Math.round(value))) };
        case "UInt32": return { dataType: DataType.UInt32, value: value % 4294967296 };
        case "Double": return { dataType: DataType.Double, value: node.unit ? value / node.unit.factor : value };
        default: return { dataType: DataType.String, value: String(value) };
    }
}

// A client's value for the node as the plant's double (SI units), or null when it is not one.
export function fromVariant(node, variant) {
    const v = variant?.value;
    switch (node.type) {
        case "Boolean": return typeof v === "boolean" ? (v ? 1 : 0) : null;
        case "Int32": return Number.isInteger(v) ? v : null;
        case "Double": return typeof v === "number" ? (node.unit ? v * node.unit.factor : v) : null;
        default: return null;
    }
}

export function buildAddressSpace(server, config, handlers) {
    const addressSpace = server.engine.addressSpace;
    const own = addressSpace.getOwnNamespace();
    const ns = addressSpace.registerNamespace(config.namespace);
    if (ns.index !== 2) throw new Error(`the plant's namespace got index ${ns.index}, not 2`);
    const objectsFolder = addressSpace.rootFolder.objects;
    const rolePermissions = permissions(config.anonymousWrites);

    const eventType = own.addEventType({ browseName: "SlotEventType", subtypeOf: "BaseEventType" });
    own.addVariable({ propertyOf: eventType, browseName: "Steps", dataType: "UInt64", modellingRule: "Mandatory" });
    own.addVariable({ propertyOf: eventType, browseName: "SimulatedTime", dataType: "Double", modellingRule: "Mandatory" });

    const root = own.addObject({
        browseName: config.plant || "Plant",
        nodeId: "s=Plant",
        organizedBy: objectsFolder,
        eventNotifier: 1,  // SubscribeToEvents
        notifierOf: objectsFolder.server,
        description: `the plant ${config.plant}: its mapped slots, by their dotted paths`,
    });
    const objects = new Map([["", root]]);
    const objectOf = (steps) => {
        let path = "";
        let parent = root;
        for (const step of steps) {
            path = path ? `${path}.${step}` : step;
            let o = objects.get(path);
            if (!o) {
                o = ns.addObject({ browseName: step, nodeId: `s=${path}`, componentOf: parent, eventSourceOf: parent, eventNotifier: 1 });
                objects.set(path, o);
            }
            parent = o;
        }
        return parent;
    };

    const nodes = config.nodes.map((n, index) => ({ ...n, index, forced: 0, value: undefined }));
    for (const n of nodes) {
        const parent = objectOf(n.browse.slice(0, -1));
        const name = n.browse[n.browse.length - 1];
        n.parent = parent;
        if (n.class === "method") {
            const m = ns.addMethod(parent, { browseName: name, nodeId: `i=${n.id}`, description: n.description, rolePermissions });
            m.bindMethod(async (_args, context) => ({ statusCode: await handlers.call(n, context) }));
            n.ua = m;
            continue;
        }
        const initial = n.type === "String" ? { dataType: DataType.String, value: "" } : toVariant(n, 0);
        const v = ns.addVariable({
            componentOf: parent,
            browseName: name,
            nodeId: `i=${n.id}`,
            dataType: n.type,
            description: n.description,
            typeDefinition: n.unit ? "AnalogUnitType" : "BaseDataVariableType",
            accessLevel: n.writable ? "CurrentRead | CurrentWrite" : "CurrentRead",
            userAccessLevel: n.writable ? "CurrentRead | CurrentWrite" : "CurrentRead",
            minimumSamplingInterval: 0,  // exception-based: each step's change is reported
            rolePermissions,
            value: new Variant(initial),
        });
        if (n.unit)
            ns.addVariable({
                propertyOf: v,
                browseName: { namespaceIndex: 0, name: "EngineeringUnits" },
                dataType: "EUInformation",
                modellingRule: "Mandatory",
                value: new Variant({
                    dataType: DataType.ExtensionObject,
                    value: makeEUInformation(n.unit.code, n.unit.symbol, n.unit.description),
                }),
            });
        if (n.writable)
            v.bindVariable({
                timestamped_get: function () { return this.$dataValue; },
                timestamped_set: async function (dataValue) {
                    const status = await handlers.write(n, dataValue.value);
                    // What the node shows is the plant's value: the write is applied at the next
                    // step boundary, and that step's value shows it.
                    const now = this.$dataValue;
                    dataValue.value = now.value;
                    dataValue.statusCode = now.statusCode;
                    dataValue.sourceTimestamp = now.sourceTimestamp;
                    dataValue.sourcePicoseconds = now.sourcePicoseconds;
                    return status;
                },
            }, true);
        markPlantNode(v);
        n.ua = v;
    }

    const link = own.addObject({ browseName: "Link", nodeId: "s=Link", organizedBy: objectsFolder,
                                 description: "the plant's link: its steps, lock-step and faults" });
    const status = (name, dataType, value, description) =>
        own.addVariable({ componentOf: link, browseName: name, nodeId: `s=Link.${name}`, dataType, description,
                          accessLevel: "CurrentRead", userAccessLevel: "CurrentRead", minimumSamplingInterval: 0,
                          value: new Variant({ dataType: DataType[dataType], value }) });
    const linkNodes = {
        steps: status("Steps", "UInt64", 0, "steps run"),
        time: status("SimulatedTime", "Double", 0, "simulated seconds at the end of the last step"),
        rate: status("Rate", "Double", 0, "steps per simulated second"),
        lockstep: status("Lockstep", "Boolean", !!config.lockstep, "true: the plant steps only as Advance grants"),
        dropped: status("Dropped", "UInt32", 0, "steps whose changes this server missed because it fell behind"),
    };
    const method = (name, description, inputArguments, outputArguments, handler) => {
        const m = own.addMethod(link, { browseName: name, nodeId: `s=Link.${name}`, description, inputArguments,
                                        outputArguments, rolePermissions });
        m.bindMethod(async (args, context) => {
            try {
                return await handler(args, context);
            } catch (err) {
                return { statusCode: StatusCodes.BadInternalError };
            }
        });
    };
    method("Advance", "lock-step: run Steps more steps; returns once they ran, with the steps run so far",
           [{ name: "Steps", dataType: DataType.UInt32, description: "steps to run" }],
           [{ name: "Steps", dataType: DataType.UInt64, description: "steps run so far" }], handlers.advance);
    method("Force", "force a node's slot from the next step: Mode \"stuck\" (at Value), \"open\" (reads as off), \"invert\" (a Boolean)",
           [{ name: "Node", dataType: DataType.NodeId, description: "a node of the plant's namespace" },
            { name: "Mode", dataType: DataType.String, description: "stuck, open or invert" },
            { name: "Value", dataType: DataType.Variant, description: "stuck: the value, of the node's type (a method or counter: Boolean)" }],
           [], (args) => handlers.force(args));
    method("Release", "release a node's slot from the next step",
           [{ name: "Node", dataType: DataType.NodeId, description: "a node of the plant's namespace" }],
           [], (args) => handlers.release(args));

    const byId = new Map(nodes.map((n) => [n.id, n]));
    return { nodes, byId, root, eventType, linkNodes, namespaceIndex: ns.index, TYPES };
}
