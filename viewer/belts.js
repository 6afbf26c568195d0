// What makes a belt look like a belt: the band's rubber and the rails' aluminium (by the
// body's role, from its name in the standard library), rollers at a band's ends, and on
// every running conveyor field a chevron pattern that moves with the band's speed in its
// direction of travel (and stands still when the belt stops); on a turning field (a curve's)
// the chevrons follow its circles, on the ring of rubber it drives. The world is z-up, metres.
import * as THREE from 'three';

// A body's role, from its component's name (std.belts, std.switch, std.separator, std.arm):
// a band, a rail, a curve's deck (drawn with the shapes only), a storage table, or nothing special.
export function bodyRole(body, dos, doIndex) {
  const name = body.path.slice(body.path.lastIndexOf('.') + 1);
  if (body.mode !== 'static') return '';
  if (name === 'band' || name === 'bands' || name === 'square') return 'band';
  if (name === 'rail' || name === 'rails' || name === 'guides') return 'rail';
  if (name === 'deck') return 'deck';   // a Curve's level slab: its turning field's ring shows the band
  const d = dos[doIndex.get(body.do)];
  if (d?.type === 'Table') return 'table';
  return '';
}

export const ROLE_COLOURS = {
  band: new THREE.Color(0x33383e),   // rubber
  rail: new THREE.Color(0xc0c7d0),   // aluminium
  deck: new THREE.Color(0x33383e),   // rubber, on the shapes layer
  table: new THREE.Color(0xc49a66),  // a wooden top
};

// A unit quad in the xy plane whose fragments draw chevrons pointing along the instance's
// direction, moving at its speed (simulated time: a paused plant's belts stand still).
export function chevronMaterial() {
  const uniforms = { uTime: { value: 0 } };
  const material = new THREE.ShaderMaterial({
    uniforms,
    transparent: true,
    depthWrite: false,
    polygonOffset: true,
    polygonOffsetFactor: -2,
    vertexShader: /* glsl */`
      attribute vec4 aFlow;    // direction in the field's frame (x, y), speed (m/s), on (1/0)
      attribute vec2 aSize;    // the field's extent in x and y (m)
      attribute vec3 aTurn;    // a turning field: its pivot (x, y) and radius (m); radius 0: straight
      attribute vec2 aRing;    // ... the ring it is drawn on, from its pivot (turnRing)
      varying vec2 vMetric;
      varying vec4 vFlow;
      varying vec3 vTurn;
      varying vec2 vRing;
      void main() {
        vMetric = position.xy * aSize;
        vFlow = aFlow;
        vTurn = aTurn;
        vRing = aRing;
        gl_Position = projectionMatrix * modelViewMatrix * instanceMatrix * vec4(position, 1.0);
      }`,
    fragmentShader: /* glsl */`
      uniform float uTime;
      varying vec2 vMetric;
      varying vec4 vFlow;
      varying vec3 vTurn;
      varying vec2 vRing;
      void main() {
        float along, across, speed = vFlow.z;
        bool turns = vTurn.z > 0.0;
        if (turns) {
          // Along the circle through this point (arc length on the radius where the speed
          // applies: the pattern moves at the speed there), across: off that circle.
          vec2 rel = vMetric - vTurn.xy;
          float r = length(rel);
          if (r < vRing.x || r > vRing.y) discard;
          along = atan(rel.y, rel.x) * vTurn.z;
          across = r - (vRing.x + vRing.y) / 2.0;
        } else {
          vec2 d = normalize(vFlow.xy);
          along = dot(vMetric, d);
          across = dot(vMetric, vec2(-d.y, d.x));
        }
        float pitch = 0.06;
        float s = fract((along - uTime * speed + abs(across) * 0.5) / pitch);
        float line = smoothstep(0.0, 0.04, s) * (1.0 - smoothstep(0.14, 0.2, s));
        vec3 colour = speed != 0.0 ? vec3(0.86, 0.9, 0.95) : vec3(0.55, 0.58, 0.62);
        float alpha = line * (speed != 0.0 ? 0.75 : 0.45);
        if (turns) {  // the ring is the band: rubber under the chevrons
          gl_FragColor = vec4(mix(vec3(0.2, 0.22, 0.243), colour, alpha), 1.0);
          return;
        }
        if (line < 0.02) discard;
        gl_FragColor = vec4(colour, alpha);
      }`,
  });
  return { material, uniforms };
}

export function chevronGeometry(capacity) {
  const g = new THREE.PlaneGeometry(1, 1);
  g.setAttribute('aFlow', new THREE.InstancedBufferAttribute(new Float32Array(4 * Math.max(1, capacity)), 4));
  g.setAttribute('aSize', new THREE.InstancedBufferAttribute(new Float32Array(2 * Math.max(1, capacity)), 2));
  g.setAttribute('aTurn', new THREE.InstancedBufferAttribute(new Float32Array(3 * Math.max(1, capacity)), 3));
  g.setAttribute('aRing', new THREE.InstancedBufferAttribute(new Float32Array(2 * Math.max(1, capacity)), 2));
  return g;
}

// The ring a turning field's chevrons are drawn on, in its frame: [inner, outer] distance from
// its pivot. Its outer edge is the box's face farthest from the pivot (a std.belts Curve's
// outer edge), and it lies as far inside the circle of `radius` as outside (the band's
// width); where that circle reaches the farthest face (a turntable), the whole disc.
export function turnRing(f) {
  const hx = f.extent[0] / 2, hy = f.extent[1] / 2, [px, py] = f.pivot;
  const outer = Math.max(Math.abs(hx - px), Math.abs(-hx - px), Math.abs(hy - py), Math.abs(-hy - py));
  const h = outer - f.radius;
  return h > 1e-9 ? [Math.max(0, f.radius - h), outer] : [0, outer];
}

// Rollers at both ends of every straight band (a single long box, std.belts' Belt): their
// axes across the band, in the band's frame. Returns world matrices for three's unit
// cylinder (radius 1, length 1, along its y: across the band).
export function rollerMatrices(scene, poseMatrix) {
  const out = [];
  const m = new THREE.Matrix4(), local = new THREE.Matrix4(), s = new THREE.Matrix4();
  for (const b of scene.bodies) {
    if (b.mode !== 'static' || !b.path.endsWith('.band') || b.shapes.length !== 1) continue;
    const sh = b.shapes[0];
    if (sh.kind !== 'box' || sh.size[0] < 3 * sh.size[1]) continue;
    const [lx, ly, lz] = sh.size;
    poseMatrix(b.pose, 0, m);
    poseMatrix(sh.local, 0, local);
    for (const end of [-1, 1]) {
      s.makeTranslation(end * (lx / 2 - lz * 0.55), 0, 0).multiply(new THREE.Matrix4().makeScale(lz * 0.62, ly + 0.008, lz * 0.62));
      out.push(new THREE.Matrix4().multiplyMatrices(m, local).multiply(s));
    }
  }
  return out;
}
