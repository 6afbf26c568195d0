// The page's side of the viewer protocol, version 1 (docs/viewer.md): one WebSocket at
// /ws, JSON control messages, binary pose frames.

export const PROTOCOL_VERSION = 1;

// Decodes a binary frame (kind 1). Returns typed arrays that view copies of the data.
export function parseFrame(buffer) {
  const v = new DataView(buffer);
  if (buffer.byteLength < 32) throw new Error(`frame of ${buffer.byteLength} bytes`);
  const kind = v.getUint32(0, true);
  if (kind !== 1) throw new Error(`frame kind ${kind}`);
  const nb = v.getUint32(4, true);
  const time = v.getFloat64(8, true);
  const step = v.getFloat64(16, true);
  const ng = v.getUint32(24, true);
  const flags = v.getUint32(28, true);
  const statePad = Math.ceil(nb / 4) * 4;
  const need = 32 + 32 * nb + statePad + 36 * ng;
  if (buffer.byteLength < need) throw new Error(`frame of ${buffer.byteLength} bytes, ${need} expected`);
  let o = 32;
  const bodyIds = new Int32Array(nb);
  for (let i = 0; i < nb; i++, o += 4) bodyIds[i] = v.getInt32(o, true);
  const bodyPoses = new Float32Array(7 * nb);
  for (let i = 0; i < 7 * nb; i++, o += 4) bodyPoses[i] = v.getFloat32(o, true);
  const bodyStates = new Uint8Array(buffer.slice(o, o + nb));
  o += statePad;
  const gfxIds = new Int32Array(ng);
  for (let i = 0; i < ng; i++, o += 4) gfxIds[i] = v.getInt32(o, true);
  const gfxPoses = new Float32Array(7 * ng);
  for (let i = 0; i < 7 * ng; i++, o += 4) gfxPoses[i] = v.getFloat32(o, true);
  const gfxVariants = new Int32Array(ng);
  for (let i = 0; i < ng; i++, o += 4) gfxVariants[i] = v.getInt32(o, true);
  return { time, step, full: (flags & 1) !== 0, paused: (flags & 2) !== 0,
           bodyIds, bodyPoses, bodyStates, gfxIds, gfxPoses, gfxVariants };
}

// The page's ?token= and ?role=, as a query to pass on ("" when it has neither).
export function roleQuery() {
  const page = new URLSearchParams(location.search);
  const q = new URLSearchParams();
  for (const key of ['token', 'role']) if (page.has(key)) q.set(key, page.get(key));
  const text = q.toString();
  return text ? `?${text}` : '';
}

// One connection to the server; reconnects after a drop, but not after the server refused
// it at the door (a wrong token: trying again would only lock this address out). Handlers: onScene(scene),
// onHistory(history), onFrame(frame), onStatus(status), onEvent(msg), onError(msg),
// onConnection(state).
export class Connection {
  constructor(handlers, { fps = 30 } = {}) {
    this.handlers = handlers;
    this.fps = fps;
    this.ws = null;
    this.retry = 500;
    this.open();
  }

  // The page's own ?token= (the instructor's URL) and ?role= go with it to /ws: the server
  // decides the page's role from them (docs/viewer.md, "Roles").
  url() {
    const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
    return `${scheme}//${location.host}/ws${roleQuery()}`;
  }

  open() {
    const ws = new WebSocket(this.url());
    ws.binaryType = 'arraybuffer';
    this.ws = ws;
    this.welcomed = false;
    ws.onopen = () => {
      this.retry = 500;
      this.handlers.onConnection?.('open');
      this.send({ type: 'hello', fps: this.fps });
    };
    ws.onclose = () => {
      this.handlers.onConnection?.(this.refused ? 'refused' : 'closed');
      if (this.refused) return;
      setTimeout(() => this.open(), this.retry);
      this.retry = Math.min(this.retry * 2, 5000);
    };
    ws.onmessage = (e) => this.receive(e.data);
  }

  receive(data) {
    if (data instanceof ArrayBuffer) {
      let frame;
      try { frame = parseFrame(data); } catch (err) { this.handlers.onError?.({ message: `bad frame: ${err.message}` }); return; }
      this.handlers.onFrame?.(frame);
      return;
    }
    let msg;
    try { msg = JSON.parse(data); } catch { this.handlers.onError?.({ message: 'bad JSON from the server' }); return; }
    switch (msg.type) {
      case 'scene':
        if (msg.version !== PROTOCOL_VERSION)
          this.handlers.onError?.({ message: `server speaks protocol ${msg.version}, this page ${PROTOCOL_VERSION}` });
        this.handlers.onScene?.(msg); break;
      case 'status': this.handlers.onStatus?.(msg); break;
      case 'history': this.handlers.onHistory?.(msg); break;
      case 'welcome': this.welcomed = true; this.handlers.onWelcome?.(msg); break;
      case 'event': this.handlers.onEvent?.(msg); break;
      case 'drill': this.handlers.onDrill?.(msg); break;
      case 'error':
        if (!this.welcomed) this.refused = true;   // refused before the welcome: at the door
        this.handlers.onError?.(msg); break;
      default: break;   // newer servers may send more; ignore
    }
  }

  send(msg) {
    if (this.ws?.readyState !== WebSocket.OPEN) return false;
    this.ws.send(JSON.stringify(msg));
    return true;
  }
}
