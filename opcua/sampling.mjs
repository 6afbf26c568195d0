// How the plant's nodes are sampled (docs/plc.md, "OPC UA", "The server and subscriptions").
//
// node-opcua samples a monitored item on a timer of its own unless the client asked for 0;
// the plant's values change only at steps, and steps reach this server in batches whenever it
// runs behind (a loaded machine, a flood of clients): a timer then reads only each batch's
// last step, and a value that lasted one step is never seen. So an item on a plant node that
// samples at least as fast as the plant steps is driven by the node's changes, one per step
// snapshot: it gets every step's change (the revised interval stays the one node-opcua
// grants). An item that samples slower keeps node-opcua's timer, which reads the latest step
// at each interval: what sampling means, at a cost that does not grow with the step rate.
//
// This reaches into node-opcua's MonitoredItem (pinned in package-lock.json); the server
// refuses to start if the version it finds lacks what it uses.
import ua from "node-opcua";

const proto = ua.MonitoredItem.prototype;
const needs = ["setNode", "_set_parameters", "_on_value_changed", "_on_value_changed_exception_based"];

let stepMs = 1000 / 150;  // the plant's step: its declared rate, then as its steps tell (setStep)
const plantNodes = new WeakSet();

export function samplePlantNodes() {
    const missing = needs.filter((name) => typeof proto[name] !== "function");
    if (missing.length)
        throw new Error(`node-opcua's MonitoredItem lacks ${missing.join(", ")}: run scripts/setup.sh (npm ci in opcua/)`);
    // The item learns its node after its parameters (setNode), and again on a modify.
    const onChanges = (item) => {
        if (item.node && plantNodes.has(item.node) && item.itemToMonitor?.attributeId === ua.AttributeIds.Value &&
            item.samplingInterval <= stepMs)
            item._exceptionBased = true;
    };
    const setNode = proto.setNode;
    proto.setNode = function (node) {
        setNode.call(this, node);
        onChanges(this);
    };
    const setParameters = proto._set_parameters;
    proto._set_parameters = function (parameters) {
        setParameters.call(this, parameters);
        onChanges(this);
    };
    const onChange = proto._on_value_changed_exception_based;
    proto._on_value_changed_exception_based = function (dataValue, indexRange) {
        if (plantNodes.has(this.node) && this.samplingInterval <= stepMs) return this._on_value_changed(dataValue, indexRange);
        return onChange.call(this, dataValue, indexRange);
    };
}

// The plant's step in seconds (simulated time over steps).
export function setStep(seconds) {
    if (seconds > 0) stepMs = seconds * 1000;
}

// A variable whose value the plant's steps set.
export function markPlantNode(variable) {
    plantNodes.add(variable);
}
