// Unit test of the page's frame decoder (protocol.js) against docs/viewer.md's layout:
//   node viewer/test/protocol.mjs
// Builds frames byte by byte as the table says (little-endian, the body states padded to a
// multiple of 4) and checks every decoded field; a short or foreign frame is refused.
import assert from 'node:assert/strict';
import { parseFrame } from '../protocol.js';

function frame({ time, step, flags, bodies, graphics }) {
  const nb = bodies.length, ng = graphics.length;
  const pad = Math.ceil(nb / 4) * 4;
  const buf = new ArrayBuffer(32 + 4 * nb + 28 * nb + pad + 4 * ng + 28 * ng + 4 * ng);
  const v = new DataView(buf);
  v.setUint32(0, 1, true); v.setUint32(4, nb, true); v.setFloat64(8, time, true);
  v.setFloat64(16, step, true); v.setUint32(24, ng, true); v.setUint32(28, flags, true);
  let o = 32;
  for (const b of bodies) { v.setInt32(o, b.id, true); o += 4; }
  for (const b of bodies) for (const x of b.pose) { v.setFloat32(o, x, true); o += 4; }
  for (const b of bodies) v.setUint8(o++, b.state);
  o = 32 + 32 * nb + pad;
  for (const g of graphics) { v.setInt32(o, g.id, true); o += 4; }
  for (const g of graphics) for (const x of g.pose) { v.setFloat32(o, x, true); o += 4; }
  for (const g of graphics) { v.setInt32(o, g.variant, true); o += 4; }
  assert.equal(o, buf.byteLength);
  return buf;
}

let n = 0;
for (const nb of [0, 1, 3, 4, 5]) {
  const bodies = Array.from({ length: nb }, (_, i) => ({ id: 10 + i, pose: [i, -i, 0.5, 0, 0, 0.6, 0.8], state: i % 4 }));
  const graphics = [{ id: 7, pose: [1.5, 2.5, 3.5, 0, 0, 0, 1], variant: -1 }, { id: 9, pose: [0, 0, 0, 1, 0, 0, 0], variant: 2 }];
  const f = parseFrame(frame({ time: 12.25, step: 1837, flags: 3, bodies, graphics }));
  assert.equal(f.time, 12.25);
  assert.equal(f.step, 1837);
  assert.equal(f.full, true);
  assert.equal(f.paused, true);
  assert.deepEqual([...f.bodyIds], bodies.map((b) => b.id));
  assert.deepEqual([...f.bodyPoses], bodies.flatMap((b) => b.pose).map(Math.fround));
  assert.deepEqual([...f.bodyStates], bodies.map((b) => b.state));
  assert.deepEqual([...f.gfxIds], [7, 9]);
  assert.deepEqual([...f.gfxPoses], graphics.flatMap((g) => g.pose).map(Math.fround));
  assert.deepEqual([...f.gfxVariants], [-1, 2]);
  n++;
}
const partial = parseFrame(frame({ time: 0, step: 0, flags: 0, bodies: [], graphics: [] }));
assert.equal(partial.full, false);
assert.equal(partial.paused, false);
const good = frame({ time: 1, step: 1, flags: 1, bodies: [{ id: 1, pose: [0, 0, 0, 0, 0, 0, 1], state: 3 }], graphics: [] });
assert.throws(() => parseFrame(good.slice(0, good.byteLength - 1)), /bytes/);
assert.throws(() => parseFrame(good.slice(0, 16)), /bytes/);
const foreign = good.slice(0);
new DataView(foreign).setUint32(0, 2, true);
assert.throws(() => parseFrame(foreign), /kind 2/);
console.log(`protocol: ${n} frames decoded, 3 bad frames refused`);
