// Generates the standard library's glTF models (stdlib/models/*.glb) from the stdlib's own
// dimensions: low-poly, recognisable at a glance. Geometry from three.js's generators, the
// files written by @gltf-transform/core (npm, pinned in viewer/package-lock.json).
//
//   node viewer/models/make-models.mjs [OUT_DIR]   # default stdlib/models (scripts/make-models.sh)
//   node viewer/models/make-models.mjs --check     # exit 1 when a committed file differs
//
// Models are authored in the plant's frame (z up, metres) and turned into glTF's (y up).
// A node whose name starts with `static_` stays where its graphics starts while the rest
// follows the graphics' animation (docs/viewer.md, "Models"): a robot's foot, a station's
// housing.
import { Document, NodeIO } from '@gltf-transform/core';
import * as THREE from 'three';
import { mergeGeometries, mergeVertices } from 'three/addons/utils/BufferGeometryUtils.js';
import { readFileSync, writeFileSync, mkdirSync, existsSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../..');
const cm = 0.01, mm = 0.001;

// ---- the stdlib's dimensions: each is checked against the stdlib's text below ----
const D = {
  bottle: { r: 2 * cm, h: 8 * cm },                              // std.bottle Bottle(radius, height)
  arm: { reach: 45 * cm, handZ: 10 * cm },                        // std.arm Arm(reach), graphics hand at (reach, 0, 10 cm)
  station: { pinX: 6 * mm, width: 8 * cm, pinH: 5 * cm, eyeX: -2 * cm },  // std.stations StationCore
  gate: { width: 5.4 * cm, pinH: 5.5 * cm },                      // std.separator Gate in a Separator: lane + 1 cm
  wedge: { base: 1 * cm, length: 1.5 * cm, height: 5 * cm },       // std.separator Wedge
  blade: { length: 0.2878, t: 4 * mm, bottom: -3 * mm, top: 6 * cm },  // std.switch Switch: bl2 at the defaults
};
const EXPECT = [  // the stdlib text these dimensions come from
  ['stdlib/bottle.plant', 'radius: length = 2 cm'], ['stdlib/bottle.plant', 'height: length = 8 cm'],
  ['stdlib/arm.plant', 'reach: length = 45 cm'], ['stdlib/arm.plant', 'graphics hand at (reach, 0 m, 10 cm)'],
  ['stdlib/stations.plant', 'shape box(6 mm, width, 5 cm) at (3 mm, 0 m, 2.5 cm)'],
  ['stdlib/stations.plant', 'width: length = 8 cm'], ['stdlib/stations.plant', 'trigger eye at (-2 cm, 0 m, 4 cm)'],
  ['stdlib/separator.plant', 'shape box(6 mm, width, 5.5 cm) at (0 m, 0 m, 2.5 cm)'],
  ['stdlib/separator.plant', 'wp: Gate(width = lane + 1 cm'], ['stdlib/separator.plant', 'let lane = 2 * radius + 4 mm'],
  ['stdlib/separator.plant', 'Wedge(side: real = 1, travel: length = 9 mm, base: length = 1 cm, length: length = 1.5 cm,'],
  ['stdlib/separator.plant', 'height: length = 5 cm'],
  ['stdlib/switch.plant', 'blade_angle: angle = 20 deg'], ['stdlib/switch.plant', 'blade_top: length = 6 cm'],
  ['stdlib/switch.plant', 'blade_bottom: length = -3 mm'], ['stdlib/switch.plant', 'let bl2 = (hw + reach) / sin(th) + 1 cm'],
];
for (const [file, text] of EXPECT) {
  if (!readFileSync(join(root, file), 'utf8').includes(text)) {
    console.error(`make-models: ${file} no longer says '${text}': update the dimensions in ${fileURLToPath(import.meta.url)}`);
    process.exit(1);
  }
}
{  // the blade's length, bl2, at the switch's defaults (width 8 cm, rail 5 mm, 20 deg)
  const hw = 4 * cm, reach = hw + 5 * mm + 1 * cm;
  const bl2 = (hw + reach) / Math.sin(20 * Math.PI / 180) + 1 * cm;
  if (Math.abs(bl2 - D.blade.length) > 1e-4) throw new Error(`blade length ${bl2}`);
}

// ---- materials (glTF metallic-roughness) ----
const MAT = {
  glass: { color: [0.24, 0.56, 0.84, 0.72], metal: 0.1, rough: 0.1, blend: true },   // tinted, to stand out on grey belts
  contents: { color: [0.93, 0.56, 0.14, 1], metal: 0, rough: 0.75 },
  label: { color: [0.96, 0.96, 0.92, 1], metal: 0, rough: 0.9 },
  capPurple: { color: [0.56, 0.33, 0.82, 1], metal: 0.1, rough: 0.45 },
  capGreen: { color: [0.16, 0.62, 0.3, 1], metal: 0.1, rough: 0.45 },
  robot: { color: [0.95, 0.5, 0.08, 1], metal: 0.15, rough: 0.45 },
  joint: { color: [0.2, 0.22, 0.25, 1], metal: 0.5, rough: 0.45 },
  steel: { color: [0.72, 0.74, 0.77, 1], metal: 0.8, rough: 0.3 },
  foot: { color: [0.3, 0.32, 0.35, 1], metal: 0.3, rough: 0.6 },
  frame: { color: [0.68, 0.71, 0.75, 1], metal: 0.6, rough: 0.35 },
  housing: { color: [0.2, 0.42, 0.68, 1], metal: 0.2, rough: 0.5 },
  stop: { color: [0.78, 0.16, 0.14, 1], metal: 0.2, rough: 0.5 },
  lamp: { color: [0.3, 0.9, 0.35, 1], metal: 0, rough: 0.3 },
  blade: { color: [0.28, 0.5, 0.78, 1], metal: 0.4, rough: 0.4 },
};

// ---- geometry in the plant's frame (z up) ----
const Y_TO_Z = new THREE.Matrix4().makeRotationX(Math.PI / 2);   // three's cylinders run along y
function box(cx, cy, cz, sx, sy, sz) {
  return new THREE.BoxGeometry(sx, sy, sz).translate(cx, cy, cz);
}
// A vertical cylinder (along z) from z0 to z1 at (x, y); r1 the top radius if it differs.
function cyl(r, z0, z1, x = 0, y = 0, seg = 16, r1 = r) {
  return new THREE.CylinderGeometry(r1, r, z1 - z0, seg).applyMatrix4(Y_TO_Z).translate(x, y, (z0 + z1) / 2);
}
// A cylinder along x (from x0 to x1) or y, at the given other coordinates.
function cylX(r, x0, x1, y, z, seg = 12) {
  return new THREE.CylinderGeometry(r, r, x1 - x0, seg).rotateZ(-Math.PI / 2).translate((x0 + x1) / 2, y, z);
}
// A solid of revolution about z: profile [[r, z], ...] from bottom to top.
function lathe(profile, seg = 16) {
  return new THREE.LatheGeometry(profile.map(([r, z]) => new THREE.Vector2(r, z)), seg).applyMatrix4(Y_TO_Z);
}
// A prism: the polygon [[x, y], ...] (counter-clockwise) from z0 to z1.
function prism(points, z0, z1) {
  const shape = new THREE.Shape(points.map(([x, y]) => new THREE.Vector2(x, y)));
  return new THREE.ExtrudeGeometry(shape, { depth: z1 - z0, bevelEnabled: false }).translate(0, 0, z0);
}

// One part: the geometries of one material, merged, indexed, turned into glTF's y up.
const TO_GLTF = new THREE.Matrix4().makeRotationX(-Math.PI / 2);   // (x, y, z) -> (x, z, -y)
function merged(geoms) {
  const parts = geoms.map((g) => {
    const n = g.index ? g.toNonIndexed() : g;
    for (const a of Object.keys(n.attributes)) if (a !== 'position' && a !== 'normal') n.deleteAttribute(a);
    return n;
  });
  const g = mergeGeometries(parts, false).applyMatrix4(TO_GLTF);
  return mergeVertices(g, 1e-6);
}

// A model: named parts {name, mat, geoms}, written as one node and mesh per part.
async function write(file, parts) {
  const doc = new Document();
  doc.getRoot().getAsset().generator = 'plant viewer/models/make-models.mjs';
  const buffer = doc.createBuffer();
  const scene = doc.createScene('model');
  const mats = new Map();
  for (const p of parts) {
    const m = MAT[p.mat];
    if (!mats.has(p.mat)) {
      const mat = doc.createMaterial(p.mat).setBaseColorFactor(m.color).setMetallicFactor(m.metal).setRoughnessFactor(m.rough);
      if (m.blend) mat.setAlphaMode('BLEND').setDoubleSided(true);
      mats.set(p.mat, mat);
    }
    const g = merged(p.geoms);
    const pos = doc.createAccessor().setType('VEC3').setArray(new Float32Array(g.attributes.position.array)).setBuffer(buffer);
    const nor = doc.createAccessor().setType('VEC3').setArray(new Float32Array(g.attributes.normal.array)).setBuffer(buffer);
    const idx = doc.createAccessor().setType('SCALAR').setArray(new Uint16Array(g.index.array)).setBuffer(buffer);
    const prim = doc.createPrimitive().setAttribute('POSITION', pos).setAttribute('NORMAL', nor).setIndices(idx).setMaterial(mats.get(p.mat));
    scene.addChild(doc.createNode(p.name).setMesh(doc.createMesh(p.name).addPrimitive(prim)));
  }
  return { file, bytes: await new NodeIO().writeBinary(doc) };
}

// ---- the bottle: origin at the main body's centre, the bottle's mid-height ----
function bottleParts({ filled, cap }) {
  const { r, h } = D.bottle, z0 = -h / 2, z1 = h / 2;
  const glass = lathe([[0, z0], [r * 0.94, z0], [r, z0 + 2 * mm], [r, z0 + 0.048], [r * 0.86, z0 + 0.058],
    [r * 0.52, z0 + 0.066], [r * 0.42, z0 + 0.07], [r * 0.42, z1 - 4 * mm], [r * 0.5, z1 - 3 * mm], [r * 0.5, z1],
    [r * 0.36, z1], [r * 0.36, z1 - 6 * mm]], 16);
  const parts = [{ name: 'glass', mat: 'glass', geoms: [glass] }];
  // The bar-code label: a paper band round the body.
  parts.push({ name: 'label', mat: 'label', geoms: [lathe([[r * 1.01, z0 + 0.016], [r * 1.01, z0 + 0.034]], 16)] });
  if (filled) {  // the solid parts it is filled with: a heap inside, up to the shoulder
    parts.push({ name: 'contents', mat: 'contents', geoms: [lathe([[0, z0 + 1.5 * mm], [r * 0.88, z0 + 1.5 * mm],
      [r * 0.88, z0 + 0.044], [r * 0.6, z0 + 0.049], [0, z0 + 0.051]], 12)] });
  }
  if (cap) {
    parts.push({ name: 'cap', mat: cap, geoms: [cyl(r * 0.56, z1 - 7 * mm, z1 + 2.5 * mm, 0, 0, 16), cyl(r * 0.46, z1 + 2.5 * mm, z1 + 3.5 * mm, 0, 0, 16)] });
  }
  return parts;
}

// ---- the arm: its foot stays, the rest lifts and turns (std.arm's animations) ----
function armParts() {
  const { reach } = D.arm;
  const elbow = reach * 0.5;
  return [
    { name: 'static_foot', mat: 'foot', geoms: [cyl(0.095, -0.02, 0.012, 0, 0, 24), cyl(0.07, 0.012, 0.05, 0, 0, 24),
      ...[0, 1, 2, 3].map((i) => cyl(0.008, 0.012, 0.018, 0.08 * Math.cos(i * Math.PI / 2 + Math.PI / 4), 0.08 * Math.sin(i * Math.PI / 2 + Math.PI / 4), 8))] },
    { name: 'column', mat: 'robot', geoms: [cyl(0.045, -0.11, 0.27, 0, 0, 20), box(0.01, 0, 0.3, 0.13, 0.1, 0.07)] },
    { name: 'links', mat: 'robot', geoms: [
      box(elbow / 2 + 0.02, 0, 0.3, elbow + 0.04, 0.07, 0.05),           // upper arm
      box((elbow + reach) / 2, 0, 0.315, reach - elbow, 0.055, 0.04),   // forearm
    ] },
    { name: 'joints', mat: 'joint', geoms: [cyl(0.052, 0.335, 0.35, 0, 0, 20), cyl(0.04, 0.27, 0.345, elbow, 0, 20),
      cyl(0.032, 0.29, 0.345, reach, 0, 16), cylX(0.012, -0.07, -0.055, 0, 0.3)] },
    { name: 'quill', mat: 'steel', geoms: [cyl(0.011, 0.115, 0.295, reach, 0, 12)] },
  ];
}

// ---- the gripper at the hand, 10 cm over the bottle's foot: fingers round the neck ----
function gripperParts() {
  const f = 0.0135;   // the fingers' inner faces, just outside the neck and the cap
  return [
    { name: 'wrist', mat: 'joint', geoms: [box(0, 0, 0.022, 0.05, 0.06, 0.018), cyl(0.016, 0.013, 0.03, 0, 0, 12)] },
    { name: 'fingers', mat: 'steel', geoms: [box(0, f + 0.003, -0.012, 0.014, 0.006, 0.05), box(0, -f - 0.003, -0.012, 0.014, 0.006, 0.05),
      box(0, f + 0.012, 0.012, 0.012, 0.012, 0.012), box(0, -f - 0.012, 0.012, 0.012, 0.012, 0.012)] },
    { name: 'pads', mat: 'stop', geoms: [box(0, f - 0.001, -0.03, 0.012, 0.003, 0.012), box(0, -f + 0.001, -0.03, 0.012, 0.003, 0.012)] },
  ];
}

// ---- a process station over a belt: its housing stays, its stop pin lifts ----
function stationParts() {
  const { pinX, width, pinH, eyeX } = D.station;
  const post = 0.075;   // outside the belt's rails (4 cm + 5 mm)
  return [
    { name: 'static_frame', mat: 'frame', geoms: [box(eyeX, post, 0.1, 0.02, 0.02, 0.24), box(eyeX, -post, 0.1, 0.02, 0.02, 0.24),
      box(eyeX, post, -0.015, 0.09, 0.05, 0.01), box(eyeX, -post, -0.015, 0.09, 0.05, 0.01)] },
    { name: 'static_housing', mat: 'housing', geoms: [box(eyeX + 0.005, 0, 0.2, 0.12, 0.17, 0.08)] },
    { name: 'static_tool', mat: 'steel', geoms: [cyl(0.013, 0.1, 0.16, eyeX, 0, 16), cyl(0.006, 0.092, 0.1, eyeX, 0, 12),
      cyl(0.004, 0.09, 0.16, pinX / 2 + 0.012, 0, 8)] },
    { name: 'static_lamp', mat: 'lamp', geoms: [cyl(0.008, 0.24, 0.256, eyeX + 0.04, 0.06, 12)] },
    { name: 'pin', mat: 'stop', geoms: [box(pinX / 2, 0, pinH / 2, pinX, width, pinH)] },
    { name: 'rod', mat: 'steel', geoms: [cyl(0.004, pinH, 0.16, pinX / 2 + 0.012, 0, 8), box(pinX / 2 + 0.006, 0, pinH - 0.004, 0.012, 0.012, 0.008)] },
  ];
}

// ---- a separator's gate pin, across the narrow lane: lifts out of the way ----
function gateParts() {
  const { width, pinH } = D.gate;
  const side = width / 2 + 0.022;   // its bracket's posts, outside the guides
  return [
    { name: 'static_bracket', mat: 'frame', geoms: [box(0, side, 0.06, 0.012, 0.012, 0.12), box(0, -side, 0.06, 0.012, 0.012, 0.12),
      box(0, 0, 0.125, 0.014, 2 * side + 0.012, 0.012)] },
    { name: 'static_cylinder', mat: 'joint', geoms: [cyl(0.011, 0.131, 0.17, 0, 0, 12)] },
    { name: 'pin', mat: 'stop', geoms: [box(0, 0, pinH / 2, 0.006, width, pinH)] },
    { name: 'rod', mat: 'steel', geoms: [cyl(0.0035, pinH, 0.125, 0, 0, 8)] },
  ];
}

// ---- a separator's side pin (a wedge), side = 1 (+y) or -1 (mirrored) ----
function wedgeParts(side) {
  const { base, length, height } = D.wedge;
  let pts = [[0, 0], [0, side * length], [-base, side * length], [-0.001, 0]];
  if (side < 0) pts = pts.reverse();   // counter-clockwise either way
  return [
    { name: 'pin', mat: 'steel', geoms: [prism(pts, 0.005, 0.005 + height)] },
    { name: 'actuator', mat: 'joint', geoms: [box(-base / 2, side * (length + 0.009), 0.03, 0.014, 0.018, 0.03)] },
  ];
}

// ---- a track switch's blade: a flap hinged at the far rail, swinging into the lane ----
function bladeParts() {
  const { length, t, bottom, top } = D.blade;
  return [
    { name: 'blade', mat: 'blade', geoms: [box(length / 2 - 0.01, 0, (bottom + top) / 2, length, t, top - bottom)] },
    { name: 'static_hinge', mat: 'joint', geoms: [cyl(0.009, -0.01, top + 0.015, 0, 0, 12)] },
  ];
}

const MODELS = [
  ['bottle.glb', bottleParts({})],
  ['bottle_empty.glb', bottleParts({})],
  ['bottle_filled.glb', bottleParts({ filled: true })],
  ['bottle_empty_capped.glb', bottleParts({ cap: 'capPurple' })],
  ['bottle_filled_capped.glb', bottleParts({ filled: true, cap: 'capGreen' })],
  ['arm_base.glb', armParts()],
  ['arm_gripper.glb', gripperParts()],
  ['station.glb', stationParts()],
  ['gate_pin.glb', gateParts()],
  ['separator_pin.glb', wedgeParts(1)],
  ['separator_pin_mirrored.glb', wedgeParts(-1)],
  ['switch_blade.glb', bladeParts()],
];

const check = process.argv[2] === '--check';
const out = check ? join(root, 'stdlib/models') : resolve(process.argv[2] ?? join(root, 'stdlib/models'));
const made = await Promise.all(MODELS.map(([file, parts]) => write(file, parts)));
let differ = 0;
for (const { file, bytes } of made) {
  const path = join(out, file);
  if (check) {
    const same = existsSync(path) && Buffer.compare(readFileSync(path), Buffer.from(bytes)) === 0;
    if (!same) {
      console.error(`make-models: ${path} is not what the script makes (run scripts/make-models.sh)`);
      differ++;
    }
  } else {
    mkdirSync(out, { recursive: true });
    writeFileSync(path, bytes);
  }
}
console.log(check ? `make-models: ${made.length - differ} of ${made.length} committed models are the script's` : `make-models: ${made.length} models written to ${out}`);
process.exit(differ ? 1 : 0);
