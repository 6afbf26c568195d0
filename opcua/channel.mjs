// The server's end of the local channel to the plant (runtime/opcua/channel.h has the
// whole format): frames `[u32 length][u8 type][payload]`, little-endian, on fd 3, one end
// of a Unix stream socket pair the plant made.
import net from "node:net";

export const MAX_FRAME = 64 * 1024 * 1024;

// Calls onFrame(type, payload) for each whole frame; onEnd(reason) once, when the plant
// closes its end (reason "") or the stream breaks.
export function openChannel(fd, onFrame, onEnd) {
    const socket = new net.Socket({ fd, readable: true, writable: true });
    let pending = [];
    let pendingBytes = 0;
    let ended = false;
    const end = (reason) => {
        if (ended) return;
        ended = true;
        onEnd(reason);
    };
    socket.on("data", (chunk) => {
        pending.push(chunk);
        pendingBytes += chunk.length;
        if (pendingBytes < 5) return;
        let buf = pending.length === 1 ? pending[0] : Buffer.concat(pending, pendingBytes);
        let at = 0;
        while (buf.length - at >= 5) {
            const length = buf.readUInt32LE(at);
            if (length < 1 || length > MAX_FRAME) {
                socket.destroy();
                end(`a frame of ${length} bytes from the plant`);
                return;
            }
            if (buf.length - at < 4 + length) break;
            const type = String.fromCharCode(buf[at + 4]);
            onFrame(type, buf.subarray(at + 5, at + 4 + length));
            at += 4 + length;
        }
        buf = buf.subarray(at);
        pending = buf.length ? [buf] : [];
        pendingBytes = buf.length;
    });
    socket.on("end", () => end(""));
    socket.on("error", (err) => end(err.message));
    socket.on("close", () => end(""));
    return {
        send(type, payload) {
            const head = Buffer.alloc(5);
            head.writeUInt32LE(payload.length + 1, 0);
            head[4] = type.charCodeAt(0);
            socket.write(Buffer.concat([head, payload]));
        },
        close() {
            socket.end();
        },
    };
}

// Builds a request's payload: u32 fields, f64 fields and length-prefixed UTF-8 texts, in order.
export function pack(...fields) {
    const parts = [];
    for (const [kind, value] of fields) {
        if (kind === "u8") parts.push(Buffer.from([value]));
        else if (kind === "u32") {
            const b = Buffer.alloc(4);
            b.writeUInt32LE(value >>> 0, 0);
            parts.push(b);
        } else if (kind === "f64") {
            const b = Buffer.alloc(8);
            b.writeDoubleLE(value, 0);
            parts.push(b);
        } else {
            const t = Buffer.from(value, "utf8");
            const n = Buffer.alloc(4);
            n.writeUInt32LE(t.length, 0);
            parts.push(n, t);
        }
    }
    return Buffer.concat(parts);
}
