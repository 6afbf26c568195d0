// The 3D view: graphics as their glTF models, bodies that no model stands for from their
// collision shapes (belts as belts: belts.js), force fields and triggers, all drawn with
// instanced meshes so that the draw calls do not grow with the number of bottles. The
// world is z-up, in metres.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { ConvexGeometry } from 'three/addons/geometries/ConvexGeometry.js';
import { mergeGeometries } from 'three/addons/utils/BufferGeometryUtils.js';
import { CSS2DRenderer } from 'three/addons/renderers/CSS2DRenderer.js';
import { bodyRole, ROLE_COLOURS, chevronMaterial, chevronGeometry, rollerMatrices, turnRing } from './belts.js';

const MODE_COLOURS = {
  static: new THREE.Color(0x8b939e),     // slate grey: belts, rails, frames
  kinematic: new THREE.Color(0x3f7fd6),  // steel blue: blades, guards, grippers
  dynamic: new THREE.Color(0xe8893a),    // orange: what moves freely
};
const SELECTED = new THREE.Color(0xff2d78);
const _c = new THREE.Color();
const VARIANT_COLOURS = {
  empty: 0x52b4ea, filled: 0xf0a032, capped: 0x9a63d8, filled_capped: 0x2da44e, empty_capped: 0x9a63d8,
};
const FIELD_ON = new THREE.Color(0x1f9fb3);
const FIELD_OFF = new THREE.Color(0x7d8690);
const TRIGGER_FREE = new THREE.Color(0xd9c46a);
const TRIGGER_BUSY = new THREE.Color(0xff3b1f);
const MARKER = new THREE.Color(0x14a38b);

export function variantColour(name) {
  if (name in VARIANT_COLOURS) return new THREE.Color(VARIANT_COLOURS[name]);
  let h = 0;
  for (const c of name) h = (h * 31 + c.charCodeAt(0)) >>> 0;
  return new THREE.Color().setHSL((h % 360) / 360, 0.65, 0.55);
}

// The pose `px py pz qx qy qz qw` at `a[o..o+7]` as a matrix.
const _p = new THREE.Vector3(), _q = new THREE.Quaternion(), _s = new THREE.Vector3(1, 1, 1);
function poseMatrix(a, o, out = new THREE.Matrix4()) {
  _p.set(a[o], a[o + 1], a[o + 2]);
  _q.set(a[o + 3], a[o + 4], a[o + 5], a[o + 6]);
  if (_q.lengthSq() < 1e-12) _q.identity(); else _q.normalize();
  return out.compose(_p, _q, _s);
}

// Our cylinders and capsules have their axis along local z, three's along y.
const Y_TO_Z = new THREE.Matrix4().makeRotationX(Math.PI / 2);

function shapeGeometry(shape) {
  const s = shape.size ?? [];
  let g;
  switch (shape.kind) {
    case 'box': g = new THREE.BoxGeometry(s[0], s[1], s[2]); break;
    case 'sphere': g = new THREE.SphereGeometry(s[0], 12, 8); break;
    case 'cylinder': g = new THREE.CylinderGeometry(s[0], s[0], s[1], 20).applyMatrix4(Y_TO_Z); break;
    case 'capsule': g = new THREE.CapsuleGeometry(s[0], Math.max(0, s[1] - 2 * s[0]), 4, 12).applyMatrix4(Y_TO_Z); break;  // s[1]: total height
    case 'hull': g = new ConvexGeometry((shape.points ?? []).map((p) => new THREE.Vector3(p[0], p[1], p[2]))); break;
    default: console.warn(`unknown shape kind ${shape.kind}`); return null;
  }
  if (shape.local) g.applyMatrix4(poseMatrix(shape.local, 0));
  return g;
}

// A guard rail's box (x along the belt, z up) drawn as a guide rail: two bars, one at the
// top and one lower down, on posts, so that the bottles between the rails stay in sight.
// The collision shape stays the full box.
function railGeometry(shape) {
  const [l, t, h] = shape.size;
  const bar = (z0, z1) => new THREE.BoxGeometry(l, t, z1 - z0).translate(0, 0, (z0 + z1) / 2 - h / 2);
  const parts = [bar(0.3 * h, 0.5 * h), bar(0.8 * h, h)];
  if (l >= 0.15) {
    const n = Math.max(2, Math.ceil(l / 0.3) + 1);
    for (let k = 0; k < n; k++) parts.push(new THREE.BoxGeometry(0.006, t, h).translate(-l / 2 + 0.003 + (l - 0.006) * k / (n - 1), 0, 0));
  }
  const g = mergeGeometries(parts.map((x) => x.toNonIndexed()), false);
  if (shape.local) g.applyMatrix4(poseMatrix(shape.local, 0));
  return g;
}

// One geometry for a body's compound of shapes (with their local offsets); `rails`: a guard
// rail's boxes as guide rails.
function bodyGeometry(shapes, rails = false) {
  const parts = [];
  for (const sh of shapes) {
    const isRail = rails && sh.kind === 'box' && sh.size?.[2] >= 0.02 && sh.size[0] > 4 * sh.size[1];
    const g = isRail ? railGeometry(sh) : shapeGeometry(sh);
    if (!g) continue;
    const n = g.index ? g.toNonIndexed() : g;
    for (const name of Object.keys(n.attributes)) if (name !== 'position' && name !== 'normal') n.deleteAttribute(name);
    parts.push(n);
  }
  if (parts.length === 0) return new THREE.OctahedronGeometry(0.01);   // a body without shapes: a dot
  return parts.length === 1 ? parts[0] : mergeGeometries(parts, false);
}

// A unit arrow along +x: shaft from 0 to 0.72, head to 1.
function arrowGeometry() {
  const shaft = new THREE.CylinderGeometry(0.015, 0.015, 0.72, 6).applyMatrix4(new THREE.Matrix4().makeRotationZ(-Math.PI / 2)).translate(0.36, 0, 0);
  const head = new THREE.ConeGeometry(0.06, 0.28, 8).applyMatrix4(new THREE.Matrix4().makeRotationZ(-Math.PI / 2)).translate(0.86, 0, 0);
  return mergeGeometries([shaft.toNonIndexed(), head.toNonIndexed()], false);
}

// An InstancedMesh filled anew whenever what it shows changed: `ids` maps an instance to
// the item (body, graphics, field, trigger) it draws.
class InstanceGroup {
  constructor(kind, geometry, material, capacity, parent) {
    this.kind = kind;
    this.mesh = new THREE.InstancedMesh(geometry, material, Math.max(1, capacity));
    this.mesh.instanceMatrix.setUsage(THREE.DynamicDrawUsage);
    this.mesh.frustumCulled = false;
    this.mesh.count = 0;
    this.mesh.visible = false;
    this.mesh.userData.group = this;
    this.ids = new Int32Array(Math.max(1, capacity));
    this.n = 0;
    parent.add(this.mesh);
  }
  begin() { this.n = 0; }
  add(matrix, colour, id) {
    const i = this.n++;
    this.mesh.setMatrixAt(i, matrix);
    if (colour) this.mesh.setColorAt(i, colour);
    this.ids[i] = id;
  }
  end() {
    this.mesh.count = this.n;
    this.mesh.visible = this.n > 0;
    this.mesh.instanceMatrix.needsUpdate = true;
    if (this.mesh.instanceColor) this.mesh.instanceColor.needsUpdate = true;
    this.mesh.boundingSphere = null;   // recomputed when a ray needs it
    this.mesh.boundingBox = null;
  }
  dispose() {
    this.mesh.removeFromParent();
    this.mesh.dispose();
  }
}

export class PlantView {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.renderer.setClearColor(0xdfe6ee);
    container.appendChild(this.renderer.domElement);

    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
    this.camera.up.set(0, 0, 1);                 // the world is z-up
    this.camera.position.set(2, -4, 3);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = false;
    this.controls.screenSpacePanning = true;

    this.world = new THREE.Scene();
    const hemi = new THREE.HemisphereLight(0xffffff, 0x8a8f99, 2.2);
    hemi.position.set(0, 0, 1);
    this.world.add(hemi);
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(3, -5, 8);
    this.world.add(sun);
    const fill = new THREE.DirectionalLight(0xdde6ff, 0.6);
    fill.position.set(-4, 3, 2);
    this.world.add(fill);

    // Labels: DOM elements over the canvas, the same size at every zoom (labels.js).
    this.labelRenderer = new CSS2DRenderer();
    this.labelRenderer.domElement.className = 'labels';
    container.appendChild(this.labelRenderer.domElement);

    this.layers = {};
    for (const name of ['bodies', 'graphics', 'fields', 'triggers', 'collision', 'labels', 'ground']) {
      this.layers[name] = new THREE.Group();
      this.layers[name].name = name;
      this.world.add(this.layers[name]);
    }
    this.solid = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.55, metalness: 0.05 });
    this.ghost = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.8, transparent: true, opacity: 0.22, depthWrite: false });
    this.ghostWire = new THREE.MeshBasicMaterial({ color: 0xffffff, wireframe: true, transparent: true, opacity: 0.45, depthWrite: false });
    this.volume = new THREE.MeshBasicMaterial({ color: 0xffffff, transparent: true, opacity: 0.1, depthWrite: false });
    this.volumeEdge = new THREE.MeshBasicMaterial({ color: 0xffffff, transparent: true, opacity: 0.5, depthWrite: false, wireframe: true });
    this.arrowMaterial = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.5 });
    this.rollerMaterial = new THREE.MeshStandardMaterial({ color: 0x7d858f, roughness: 0.35, metalness: 0.7 });
    this.floorMaterial = new THREE.MeshStandardMaterial({ color: 0xd3d9e0, roughness: 0.95 });
    const chevrons = chevronMaterial();
    this.chevronMaterial = chevrons.material;
    this.chevronUniforms = chevrons.uniforms;
    this.simTime = 0;
    this.onModelFailed = null;
    this.layers.fields.visible = false;      // the belts' chevrons show them; a toggle brings the boxes
    this.layers.collision.visible = false;   // collision shapes of what models stand for
    this.loader = new GLTFLoader();
    this.raycaster = new THREE.Raycaster();
    this.groups = [];
    this.scene = null;
    this.selectedDo = -1;
    this.followBody = -1;
    this.onModelLoaded = null;
    this.resize();
    new ResizeObserver(() => this.resize()).observe(container);
  }

  resize() {
    const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h, false);
    this.labelRenderer.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  clear() {
    const geometries = new Set(this.groups.map((g) => g.mesh.geometry));
    for (const g of this.groups) g.dispose();
    for (const geometry of geometries) geometry.dispose();
    this.groups = [];
    this.layers.ground.clear();
  }

  // The object a graphics belongs to: its body's, or the object its path names.
  gfxDoOf(g) {
    const bi = this.bodyIndex.get(g.body);
    return bi !== undefined ? this.scene.bodies[bi].do : this.doOfPath(g.path);
  }

  // Builds everything from a scene message; the camera stays where it is when asked to
  // (a restart of the same plant).
  load(scene, { keepCamera = false } = {}) {
    this.clear();
    this.followBody = -1;
    this.scene = scene;
    const nb = scene.bodies.length, ng = scene.graphics.length;
    this.bodyIndex = new Map(scene.bodies.map((b, i) => [b.id, i]));
    this.gfxIndex = new Map(scene.graphics.map((g, i) => [g.id, i]));
    this.doIndex = new Map(scene.dos.map((d, i) => [d.id, i]));
    // State as the frames leave it: poses and flags by index into scene.bodies.
    this.bodyPose = new Float32Array(7 * nb);
    this.bodyState = new Uint8Array(nb);
    scene.bodies.forEach((b, i) => {
      this.bodyPose.set(b.pose, 7 * i);
      const d = scene.dos[this.doIndex.get(b.do)];
      this.bodyState[i] = (d?.pooled ? 0 : 1) | (b.collision ? 2 : 0);
    });
    this.gfxPose = new Float32Array(7 * ng);
    this.gfxVariant = new Int32Array(ng);
    this.gfxTint = new Map();    // body index -> graphics index that colours it
    scene.graphics.forEach((g, i) => {
      this.gfxPose.set(g.pose ?? [0, 0, 0, 0, 0, 0, 1], 7 * i);
      this.gfxVariant[i] = g.variant ?? -1;
      if (g.body >= 0 && this.bodyIndex.has(g.body)) this.gfxTint.set(this.bodyIndex.get(g.body), i);
    });

    // Bodies of identical shape lists share one geometry and one pair of instanced
    // meshes (collision on: solid; off: translucent).
    const byShape = new Map();
    this.bodyGroupOf = new Int32Array(nb);
    const keys = new Map();  // bodies share their shape list (scene.shape_lists): one key each
    scene.bodies.forEach((b, i) => {
      let key = keys.get(b.shapes);
      if (key === undefined) {
        key = JSON.stringify(b.shapes, (k, v) => (typeof v === 'number' ? Math.round(v * 1e6) / 1e6 : v));
        keys.set(b.shapes, key);
      }
      let entry = byShape.get(key);
      if (!entry) { entry = { shapes: b.shapes, members: [] }; byShape.set(key, entry); }
      entry.members.push(i);
    });
    this.bodyGroups = [];
    this.roles = scene.bodies.map((b) => bodyRole(b, scene.dos, this.doIndex));
    for (const { shapes, members } of byShape.values()) {
      const geometry = bodyGeometry(shapes, members.every((m) => this.roles[m] === 'rail'));
      const hullish = shapes.some((s) => s.kind !== 'box');
      const solid = new InstanceGroup('body', geometry, this.solid, members.length, this.layers.bodies);
      const ghost = new InstanceGroup('body', geometry, hullish ? this.ghost : this.ghostWire, members.length, this.layers.bodies);
      // Bodies a model stands for: their collision shapes, on the collision layer only.
      const hull = new InstanceGroup('body', geometry, this.ghostWire, members.length, this.layers.collision);
      ghost.mesh.renderOrder = 2;
      hull.mesh.renderOrder = 2;
      hull.standsIn = true;   // picked where its model is drawn, the collision layer shown or not
      const bg = { members, solid, ghost, hull, dirty: true };
      for (const m of members) this.bodyGroupOf[m] = this.bodyGroups.length;
      this.bodyGroups.push(bg);
      this.groups.push(solid, ghost, hull);
    }
    // bodies given an instance slot (all of them; those out of the world leave it empty)
    this.bodyCount = this.bodyGroups.reduce((n, g) => n + g.members.length, 0);

    // Graphics: a glTF model when the server found one, else: on a body, the body is
    // tinted with the variant's colour; free, a small blade-like marker at its pose.
    this.models = new Map();   // url -> { parts: [{group, local, fixed}] | null, state, error }
    this.gfxDo = scene.graphics.map((g) => this.gfxDoOf(g));
    this.modelled = new Set();  // objects a loaded model stands for (modelled())
    const markerGeometry = new THREE.BoxGeometry(0.12, 0.006, 0.05).translate(0.06, 0, 0.025);
    this.markers = new InstanceGroup('graphics', markerGeometry, this.solid, ng, this.layers.graphics);
    this.groups.push(this.markers);
    for (const g of scene.graphics) {
      for (const url of [g.model_url, ...(g.variants ?? []).map((v) => v.model_url)]) if (url && !this.models.has(url)) this.loadModel(url, ng);
    }

    // Force fields: translucent boxes and an arrow each; triggers: boxes lit while occupied.
    const unitBox = new THREE.BoxGeometry(1, 1, 1);
    const nf = scene.fields.length, nt = scene.triggers.length;
    this.fieldBoxes = new InstanceGroup('field', unitBox, this.volume, nf, this.layers.fields);
    this.fieldArrows = new InstanceGroup('field', arrowGeometry(), this.arrowMaterial, nf, this.layers.fields);
    this.triggerBoxes = new InstanceGroup('trigger', unitBox, this.volume, nt, this.layers.triggers);
    this.triggerEdges = new InstanceGroup('trigger', unitBox, this.volumeEdge, nt, this.layers.triggers);
    for (const g of [this.fieldBoxes, this.triggerBoxes, this.triggerEdges]) g.mesh.renderOrder = 3;
    this.groups.push(this.fieldBoxes, this.fieldArrows, this.triggerBoxes, this.triggerEdges);
    // The belts: chevrons on every running field, rollers at the bands' ends.
    this.chevrons = new InstanceGroup('belt', chevronGeometry(nf), this.chevronMaterial, nf, this.layers.bodies);
    this.chevrons.mesh.renderOrder = 1;
    const rollers = rollerMatrices(scene, poseMatrix);
    this.rollers = new InstanceGroup('belt', new THREE.CylinderGeometry(1, 1, 1, 14), this.rollerMaterial, rollers.length, this.layers.bodies);
    this.rollers.begin();
    rollers.forEach((m, i) => this.rollers.add(m, null, i));
    this.rollers.end();
    this.groups.push(this.chevrons, this.rollers);
    this.fieldState = scene.fields.map((f) => [true, f.speed]);
    this.occupied = new Set();
    this.carriers = new Set([...scene.fields, ...scene.triggers].map((v) => this.bodyIndex.get(v.body)).filter((i) => i !== undefined));
    this.volumesDirty = true;
    this.graphicsDirty = true;

    this.update();
    this.addGround();
    if (!keepCamera) this.fit();
  }

  loadModel(url, capacity) {
    const entry = { parts: null, state: 'loading', error: null };
    this.models.set(url, entry);
    this.loader.load(url, (gltf) => {
      if (this.models.get(url) !== entry) return;   // a newer scene replaced this one
      // glTF is y-up; the plant is z-up.
      gltf.scene.applyMatrix4(Y_TO_Z);
      gltf.scene.updateMatrixWorld(true);
      entry.parts = [];
      gltf.scene.traverse((o) => {
        if (!o.isMesh) return;
        // A part named static_* stays where its graphics starts (a robot's foot, a
        // station's housing) while the rest follows the animation.
        let fixed = false;
        for (let p = o; p && !fixed; p = p.parent) fixed = p.name.startsWith('static_');
        const group = new InstanceGroup('graphics', o.geometry, o.material, capacity, this.layers.graphics);
        entry.parts.push({ group, local: o.matrixWorld.clone(), fixed });
        this.groups.push(group);
      });
      entry.state = 'loaded';
      this.modelled = this.modelledObjects();
      this.graphicsDirty = true;
      for (const bg of this.bodyGroups) bg.dirty = true;
      this.update();
      this.onModelLoaded?.(url);
    }, undefined, (err) => {
      if (this.models.get(url) !== entry) return;
      entry.state = 'failed';
      entry.error = String(err?.message ?? err);
      console.warn(`model ${url}: ${entry.error}`);
      this.onModelFailed?.(url, entry.error);
    });
  }

  // The objects a loaded model stands for: those with a graphics whose model (or a variant's)
  // loaded. Their bodies that move are not drawn (the model shows them): only on the
  // collision layer.
  modelledObjects() {
    const out = new Set();
    this.scene.graphics.forEach((g, i) => {
      const urls = [g.model_url, ...(g.variants ?? []).map((v) => v.model_url)];
      if (urls.some((u) => u && this.models.get(u)?.parts)) out.add(this.gfxDo[i]);
    });
    return out;
  }

  // {url: 'loading' | 'loaded' | 'failed: ...'} of every model the scene names.
  modelStates() {
    const out = {};
    for (const [url, e] of this.models) out[url] = e.state === 'failed' ? `failed: ${e.error}` : e.state;
    return out;
  }

  // The model URL a graphics shows now, or null for primitives.
  gfxUrl(i) {
    const g = this.scene.graphics[i], v = this.gfxVariant[i];
    if (v >= 0 && g.variants?.[v]) return g.variants[v].model_url ?? null;
    return g.model_url ?? null;
  }

  gfxColour(i) {
    const g = this.scene.graphics[i], v = this.gfxVariant[i];
    if (v >= 0 && g.variants?.[v]) return variantColour(g.variants[v].name);
    return null;
  }

  applyFrame(f) {
    if (!this.scene) return;
    this.simTime = f.time;
    for (let k = 0; k < f.bodyIds.length; k++) {
      const i = this.bodyIndex.get(f.bodyIds[k]);
      if (i === undefined) continue;
      this.bodyPose.set(f.bodyPoses.subarray(7 * k, 7 * k + 7), 7 * i);
      this.bodyState[i] = f.bodyStates[k];
      this.bodyGroups[this.bodyGroupOf[i]].dirty = true;
      if (this.carriers.has(i)) this.volumesDirty = true;
    }
    for (let k = 0; k < f.gfxIds.length; k++) {
      const i = this.gfxIndex.get(f.gfxIds[k]);
      if (i === undefined) continue;
      this.gfxPose.set(f.gfxPoses.subarray(7 * k, 7 * k + 7), 7 * i);
      if (this.gfxVariant[i] !== f.gfxVariants[k]) {
        this.gfxVariant[i] = f.gfxVariants[k];
        const b = this.scene.graphics[i].body;
        if (this.bodyIndex.has(b)) this.bodyGroups[this.bodyGroupOf[this.bodyIndex.get(b)]].dirty = true;
      }
    }
    if (f.gfxIds.length) this.graphicsDirty = true;
    this.update();
  }

  applyStatus(st) {
    if (!this.scene) return;
    if (Array.isArray(st.occupied)) {
      const next = new Set(st.occupied);
      if (next.size !== this.occupied.size || [...next].some((x) => !this.occupied.has(x))) {
        this.occupied = next;
        this.volumesDirty = true;
      }
    }
    if (Array.isArray(st.fields) && JSON.stringify(st.fields) !== JSON.stringify(this.fieldState)) {
      this.fieldState = st.fields;
      this.volumesDirty = true;
    }
    this.update();
  }

  // Whether a loaded model stands for the body: a body that moves, of an object a model shows.
  showsModel(i) {
    const b = this.scene.bodies[i];
    return b.mode !== 'static' && this.modelled.has(b.do);
  }

  bodyColour(i) {
    const b = this.scene.bodies[i];
    let c = ROLE_COLOURS[this.roles[i]] ?? MODE_COLOURS[b.mode] ?? MODE_COLOURS.static;
    const gi = this.gfxTint.get(i);
    if (gi !== undefined && !this.gfxUrl(gi)) c = this.gfxColour(gi) ?? c;
    return b.do === this.selectedDo ? _c.copy(c).lerp(SELECTED, 0.55) : c;
  }

  update() {
    const m = new THREE.Matrix4();
    for (const bg of this.bodyGroups) {
      if (!bg.dirty) continue;
      bg.dirty = false;
      bg.solid.begin(); bg.ghost.begin(); bg.hull.begin();
      for (const i of bg.members) {
        const st = this.bodyState[i];
        if (!(st & 1)) continue;            // not in the world: a parked pooled object
        poseMatrix(this.bodyPose, 7 * i, m);
        // a model stands for it, or it is a curve's deck (the ring its field drives shows the
        // band): its shape on the collision layer; else solid, or translucent when its
        // collision is off
        (this.showsModel(i) || this.roles[i] === 'deck' ? bg.hull : st & 2 ? bg.solid : bg.ghost).add(m, this.bodyColour(i), i);
      }
      bg.solid.end(); bg.ghost.end(); bg.hull.end();
    }
    if (this.graphicsDirty) {
      this.graphicsDirty = false;
      this.markers.begin();
      const start = new THREE.Matrix4();
      for (const e of this.models.values()) e.parts?.forEach((p) => p.group.begin());
      const scene = this.scene;
      scene.graphics.forEach((g, i) => {
        const bi = this.bodyIndex.get(g.body);
        if (bi !== undefined && !(this.bodyState[bi] & 1)) return;   // on a parked body
        const url = this.gfxUrl(i);
        poseMatrix(this.gfxPose, 7 * i, m);
        if (url) {
          const e = this.models.get(url);
          const w = new THREE.Matrix4();
          if (e?.parts?.some((p) => p.fixed)) poseMatrix(g.pose ?? [0, 0, 0, 0, 0, 0, 1], 0, start);
          e?.parts?.forEach((p) => p.group.add(w.multiplyMatrices(p.fixed ? start : m, p.local), null, i));
        } else if (bi === undefined || this.models.get(g.model_url)?.state === 'failed') {
          this.markers.add(m, this.gfxColour(i) ?? MARKER, i);
        }
      });
      this.markers.end();
      for (const e of this.models.values()) e.parts?.forEach((p) => p.group.end());
    }
    if (this.volumesDirty) {
      this.volumesDirty = false;
      this.updateVolumes();
    }
    if (this.followBody >= 0) this.followStep();
  }

  // The world pose of a field or trigger. The scene gives it at the start; one on a body
  // keeps its place relative to the body: now = body now · body at start⁻¹ · at start.
  volumeMatrix(item, out) {
    poseMatrix(item.pose, 0, out);
    const bi = this.bodyIndex.get(item.body);
    if (bi !== undefined) {
      const start = poseMatrix(this.scene.bodies[bi].pose, 0).invert();
      out.premultiply(start).premultiply(poseMatrix(this.bodyPose, 7 * bi));
    }
    return out;
  }

  updateVolumes() {
    const m = new THREE.Matrix4(), s = new THREE.Matrix4(), pos = new THREE.Vector3(), rot = new THREE.Quaternion(), scl = new THREE.Vector3();
    const scene = this.scene;
    this.fieldBoxes.begin(); this.fieldArrows.begin();
    scene.fields.forEach((f, i) => {
      const [on, speed] = this.fieldState[i] ?? [true, f.speed];
      this.volumeMatrix(f, m);
      const colour = on ? FIELD_ON : FIELD_OFF;
      this.fieldBoxes.add(s.copy(m).multiply(new THREE.Matrix4().makeScale(...f.extent.map((x) => Math.max(x, 1e-4)))), colour, i);
      // The arrow: through the centre, along the direction (a turning field's: along its
      // circle through the centre), its length ~ the speed.
      m.decompose(pos, rot, scl);
      const dir = (f.radius > 0 ? new THREE.Vector3(f.pivot[1], -f.pivot[0], 0) : new THREE.Vector3(...f.dir)).applyQuaternion(rot);
      if (dir.lengthSq() < 1e-12) return;
      dir.normalize();
      const len = Math.min(Math.max(Math.abs(speed) * 0.4, 0.04), 1.5);
      if (speed < 0) dir.negate();
      const q = new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(1, 0, 0), dir);
      const start = pos.clone().addScaledVector(dir, -len / 2);
      this.fieldArrows.add(s.compose(start, q, new THREE.Vector3(len, 0.12, 0.12)), colour, i);
    });
    this.fieldBoxes.end(); this.fieldArrows.end();
    // Chevrons on the band under every field that is on, moving with its speed.
    const { aFlow: flow, aSize: size, aTurn: turn, aRing: ring } = this.chevrons.mesh.geometry.attributes;
    this.chevrons.begin();
    scene.fields.forEach((f, i) => {
      const [on, speed] = this.fieldState[i] ?? [true, f.speed];
      const turns = f.radius > 0;
      if (!on || (!turns && Math.hypot(f.dir[0], f.dir[1]) < 1e-6)) return;
      const k = this.chevrons.n;
      this.volumeMatrix(f, m).multiply(new THREE.Matrix4().makeTranslation(0, 0, -f.extent[2] / 2 + 0.0012))
        .multiply(new THREE.Matrix4().makeScale(f.extent[0], f.extent[1], 1));
      this.chevrons.add(m, null, i);
      flow.setXYZW(k, f.dir[0], f.dir[1], speed, 1);
      size.setXY(k, f.extent[0], f.extent[1]);
      turn.setXYZ(k, turns ? f.pivot[0] : 0, turns ? f.pivot[1] : 0, turns ? f.radius : 0);
      const [inner, outer] = turns ? turnRing(f) : [0, 0];
      ring.setXY(k, inner, outer);
    });
    this.chevrons.end();
    for (const a of [flow, size, turn, ring]) a.needsUpdate = true;
    this.triggerBoxes.begin(); this.triggerEdges.begin();
    scene.triggers.forEach((t, i) => {
      this.volumeMatrix(t, m).multiply(new THREE.Matrix4().makeScale(...t.extent.map((x) => Math.max(x, 1e-4))));
      const c = this.occupied.has(t.id) ? TRIGGER_BUSY : TRIGGER_FREE;
      this.triggerBoxes.add(m, c, i);
      this.triggerEdges.add(m, c, i);
    });
    this.triggerBoxes.end(); this.triggerEdges.end();
  }

  addGround() {
    const box = this.bounds();
    const size = box.getSize(new THREE.Vector3());
    const centre = box.getCenter(new THREE.Vector3());
    const span = Math.max(size.x, size.y) * 1.4 + 0.5;
    const cell = span <= 4 ? 0.1 : span <= 20 ? 0.5 : span <= 60 ? 1 : 5;
    const extent = Math.ceil(span / cell) * cell;
    // An opaque floor just under the lowest static body (what stands on it reaches into it: a
    // robot's column sinks into its foot), a grid on it.
    let low = Infinity;
    this.scene.bodies.forEach((b) => {
      if (b.mode !== 'static') return;
      for (const sh of b.shapes) low = Math.min(low, b.pose[2] + (sh.local?.[2] ?? 0) - (sh.kind === 'box' ? sh.size[2] / 2 : sh.size?.[0] ?? 0));
    });
    const z = Number.isFinite(low) ? Math.min(low, 0) - 0.001 : -0.02;
    const gx = Math.round(centre.x / cell) * cell, gy = Math.round(centre.y / cell) * cell;
    const floor = new THREE.Mesh(new THREE.PlaneGeometry(extent, extent), this.floorMaterial);
    floor.position.set(gx, gy, z);
    this.layers.ground.add(floor);
    const grid = new THREE.GridHelper(extent, Math.round(extent / cell), 0xaab4c0, 0xbfc7d1);
    grid.rotateX(Math.PI / 2);
    grid.position.set(gx, gy, z + 0.0005);
    this.layers.ground.add(grid);
  }

  // What the bodies, fields and triggers drawn now cover.
  bounds() {
    const box = new THREE.Box3();
    for (const g of this.groups) {
      if (g.kind === 'graphics' || g.kind === 'belt' || !g.mesh.visible) continue;
      g.mesh.computeBoundingBox();
      box.union(g.mesh.boundingBox);
    }
    if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, 0), new THREE.Vector3(1, 1, 0.5));
    box.expandByScalar(0.05);
    return box;
  }

  // An oblique view of everything, looking across the plant's longer side.
  fit() {
    const box = this.bounds();
    const c = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    const vfov = THREE.MathUtils.degToRad(this.camera.fov);
    const hfov = 2 * Math.atan(Math.tan(vfov / 2) * this.camera.aspect);
    const r = Math.max(0.3, 0.5 * Math.hypot(size.x, size.y));
    const d = r / Math.sin(Math.min(vfov, hfov) / 2) * 0.75;
    const dir = size.x >= size.y ? new THREE.Vector3(0, -0.78, 0.62) : new THREE.Vector3(-0.78, 0, 0.62);
    this.controls.target.copy(c);
    this.camera.position.copy(c).addScaledVector(dir.normalize(), d);
    this.controls.update();
  }

  topView() {
    const box = this.bounds();
    const c = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3());
    const fov = THREE.MathUtils.degToRad(this.camera.fov);
    const h = Math.max(size.y, size.x / this.camera.aspect) / 2 / Math.tan(fov / 2) * 1.1;
    this.controls.target.copy(c);
    this.camera.position.set(c.x, c.y - 1e-4 * h, c.z + h);
    this.controls.update();
  }

  // Looks straight down at a point from `height` metres above it.
  lookDownAt(p, height) {
    this.controls.target.set(p[0], p[1], p[2]);
    this.camera.position.set(p[0], p[1] - 1e-4 * height, p[2] + height);
    this.controls.update();
    this.camera.updateMatrixWorld();
  }

  select(doId) {
    this.selectedDo = doId;
    for (const bg of this.bodyGroups) bg.dirty = true;
    this.update();
  }

  bodyWorldPosition(i) {
    return new THREE.Vector3(this.bodyPose[7 * i], this.bodyPose[7 * i + 1], this.bodyPose[7 * i + 2]);
  }

  follow(bodyIndex) {
    this.followBody = bodyIndex;
    if (bodyIndex >= 0) this.followStep();
  }

  followStep() {
    const i = this.followBody;
    if (!(this.bodyState[i] & 1)) return;
    const p = this.bodyWorldPosition(i);
    const d = p.sub(this.controls.target);
    this.controls.target.add(d);
    this.camera.position.add(d);
    this.controls.update();
  }

  setLayer(name, on) {
    if (this.layers[name]) this.layers[name].visible = on;
  }

  // What is under the point (x, y) in normalized device coordinates: bodies and
  // graphics first, then fields and triggers.
  pick(x, y) {
    if (!this.scene) return null;
    this.camera.updateMatrixWorld();
    this.raycaster.setFromCamera(new THREE.Vector2(x, y), this.camera);
    const solidFirst = [], volumes = [];
    for (const g of this.groups) {
      // A model drawn for a body is picked by the body's shape too (an empty bottle seen from
      // above shows its open neck: the shape under it is still the bottle).
      const shown = g.standsIn ? this.layers.graphics.visible : g.mesh.parent?.visible;
      if (!g.mesh.visible || !shown || g.kind === 'belt') continue;
      if (g.kind === 'body' || g.kind === 'graphics') solidFirst.push(g.mesh); else volumes.push(g.mesh);
    }
    for (const list of [solidFirst, volumes]) {
      const hits = this.raycaster.intersectObjects(list, false);
      for (const h of hits) {
        const group = h.object.userData.group;
        if (h.instanceId === undefined || h.instanceId >= group.n) continue;
        const i = group.ids[h.instanceId];
        return { ...this.describe(group.kind, i), point: h.point.clone() };
      }
    }
    return null;
  }

  // {kind, index, path, doPath, doId} of an item.
  describe(kind, i) {
    const scene = this.scene;
    const item = { body: scene.bodies, graphics: scene.graphics, field: scene.fields, trigger: scene.triggers }[kind][i];
    let doId = item.do;
    if (doId === undefined) {
      const owner = kind === 'graphics' || item.body < 0 ? undefined : scene.bodies[this.bodyIndex.get(item.body)]?.do;
      doId = owner ?? this.doOfPath(item.path);
    }
    const d = scene.dos[this.doIndex.get(doId)];
    return { kind, index: i, path: item.path, doId, doPath: d?.path ?? '' };
  }

  // The object that owns a component path: the longest DO path that is a prefix of it.
  doOfPath(path) {
    let best = this.scene.dos.find((d) => d.parent < 0)?.id ?? 0, len = -1;
    for (const d of this.scene.dos) {
      if (d.path.length > len && (d.path === '' || path.startsWith(d.path + '.'))) { best = d.id; len = d.path.length; }
    }
    return best;
  }

  render() {
    this.chevronUniforms.uTime.value = this.simTime;
    this.renderer.render(this.world, this.camera);
    this.labelRenderer.render(this.world, this.camera);
  }
}
