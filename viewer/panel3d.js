// Operator panels placed in the scene (docs/viewer.md, "Operator panels"): a panel the plant
// places (`panel ops at (1.2 m, 0.8 m, 0.9 m) { … }`, the scene's panels[i].pose) is drawn
// there as a flat board — its title and labels printed on its face, push buttons, the
// emergency stop and its reset key, selector knobs, lamps, displays — beside the 2D panel
// over the view (panel.js). It works like the 2D one: a click sends the ordinary `event`
// message on the element's input (`…start.press`, the one way in), and what it shows comes
// back in status.panel, never from the click.
//
// The board's frame is the placement's: its centre at the placed point, upright in its x–z
// plane, its face towards −y (so `rotate z by 90 deg` turns the face towards +x), on a post
// down to the floor (z = 0) when it is placed above it.
//
// Every board is drawn by the same few instanced meshes (boxes, cylinders, lit and unlit
// lenses, one face per distinct face), so 83 lines with a panel each cost the draw calls of
// one; a display's number is a label over its window (the labels' renderer), shown from
// close by.
import * as THREE from 'three';
import { CSS2DObject } from 'three/addons/renderers/CSS2DRenderer.js';

const COLORS = { green: 0x2fb34a, red: 0xd9302c, yellow: 0xf2c014, white: 0xf4f4f0, blue: 0x2a6fd6, black: 0x222222 };
const CELL = 0.1;      // one element's square on the board, m
const PAD = 0.02;      // the board's margin
const TITLE = 0.05;    // the title's strip
const DEPTH = 0.04;    // the board's thickness
const PX = 2400;       // texture pixels per metre of the face
const FY = -DEPTH / 2 - 0.001;   // the face's plane, in the board's frame
const DISPLAY_RANGE = 4;         // a display's number is shown from this close (m)

const _m = new THREE.Matrix4(), _p = new THREE.Vector3(), _q = new THREE.Quaternion(), _s = new THREE.Vector3();
const _e = new THREE.Euler();
// A part's matrix in its board's frame: at (x, y, z), turned about y by `turn`, scaled.
function local(out, x, y, z, sx, sy, sz, turn = 0) {
  return out.compose(_p.set(x, y, z), _q.setFromEuler(_e.set(0, turn, 0)), _s.set(sx, sy, sz));
}

// One instanced mesh and the parts it draws: each {board, place(out) -> local matrix, color,
// pick ({path, act, item} or null)}.
class Parts {
  constructor(geometry, material, parent) {
    this.geometry = geometry;
    this.material = material;
    this.parent = parent;
    this.list = [];
    this.mesh = null;
  }
  add(part) { this.list.push(part); return part; }
  build() {
    if (!this.list.length) return;
    this.mesh = new THREE.InstancedMesh(this.geometry, this.material, this.list.length);
    this.mesh.frustumCulled = false;
    this.mesh.userData.parts = this;
    this.parent.add(this.mesh);
    this.list.forEach((part, i) => { if (part.color !== undefined) this.mesh.setColorAt(i, new THREE.Color(part.color)); });
    this.update();
  }
  update() {
    if (!this.mesh) return;
    this.list.forEach((part, i) => this.mesh.setMatrixAt(i, _m.multiplyMatrices(part.board.matrix, part.place(new THREE.Matrix4()))));
    this.mesh.instanceMatrix.needsUpdate = true;
    if (this.mesh.instanceColor) this.mesh.instanceColor.needsUpdate = true;
    this.mesh.boundingSphere = null;
    this.mesh.boundingBox = null;
  }
  dispose() {
    this.mesh?.removeFromParent();
    this.mesh?.dispose();
    this.geometry.dispose();
    for (const m of [this.material].flat()) { m.map?.dispose(); m.dispose(); }
  }
}

export class ScenePanels {
  constructor(view, send) {
    this.view = view;
    this.send = send;
    this.group = new THREE.Group();
    this.group.name = 'panels';
    view.world.add(this.group);
    view.layers.panels = this.group;   // a layer of its own (setLayer('panels', …))
    this.items = [];     // in status.panel's order, null for an element of a panel not placed
    this.values = [];
    this.parts = [];
    this.boards = [];
    this.displays = [];
    this.dirty = false;
    this.readOnly = false;
    this.held = null;    // the button held down by the pointer: its path
    this.ray = new THREE.Raycaster();
    // Before the hand, the camera's controls and the selection (their listeners are on the canvas).
    view.container.addEventListener('pointerdown', (e) => this.down(e), { capture: true });
    window.addEventListener('pointerup', (e) => this.up(e), { capture: true });
  }

  clear() {
    for (const p of this.parts) p.dispose();
    for (const d of this.displays) d.object.removeFromParent();
    this.group.clear();
    this.parts = [];
    this.items = [];
    this.boards = [];
    this.displays = [];
  }

  setScene(scene) {
    this.clear();
    const std = (extra = {}) => new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.45, metalness: 0.15, ...extra });
    this.boxes = new Parts(new THREE.BoxGeometry(1, 1, 1), std({ roughness: 0.6, metalness: 0.3 }), this.group);
    this.cylinders = new Parts(new THREE.CylinderGeometry(1, 1, 1, 28), std(), this.group);   // along y: out of the face
    const lens = () => new THREE.SphereGeometry(1, 24, 12, 0, Math.PI * 2, 0, Math.PI / 2).rotateX(Math.PI);
    this.lensOn = new Parts(lens(), new THREE.MeshBasicMaterial({ color: 0xffffff }), this.group);
    this.lensOff = new Parts(lens(), std({ roughness: 0.25 }), this.group);
    this.faces = new Map();   // the face's drawing (title, labels, names) -> its Parts
    this.parts = [this.boxes, this.cylinders, this.lensOn, this.lensOff];
    for (const p of scene.panels ?? []) {
      if (!Array.isArray(p.pose)) { for (const _ of p.elements) this.items.push(null); continue; }
      this.board(p);
    }
    for (const parts of this.faces.values()) this.parts.push(parts);
    for (const parts of this.parts) parts.build();
    this.targets = [this.boxes.mesh, this.cylinders.mesh].filter(Boolean);
  }

  // One board: its body, post and face, and the elements on it.
  board(p) {
    const n = p.elements.length;
    const cols = Math.max(1, n > 4 ? Math.ceil(n / 2) : n), rows = Math.max(1, Math.ceil(n / cols));
    const w = cols * CELL + 2 * PAD, h = rows * CELL + TITLE + 2 * PAD;
    const matrix = new THREE.Matrix4().compose(new THREE.Vector3(p.pose[0], p.pose[1], p.pose[2]),
      new THREE.Quaternion(p.pose[3], p.pose[4], p.pose[5], p.pose[6]).normalize(), new THREE.Vector3(1, 1, 1));
    const board = { p, w, h, matrix, cells: [] };
    this.boards.push(board);
    this.boxes.add({ board, color: 0x3b4350, place: (o) => local(o, 0, 0, 0, w + 0.01, DEPTH, h + 0.01) });
    const post = p.pose[2] - h / 2;   // down to the floor (z = 0) under a board placed above it
    if (post > 0.01) this.boxes.add({ board, color: 0x59606b, place: (o) => local(o, 0, DEPTH / 2, -h / 2 - post / 2, 0.04, 0.04, post) });
    p.elements.forEach((spec, k) => {
      const col = k % cols, row = Math.floor(k / cols);
      const cell = { spec, x: -w / 2 + PAD + CELL * (col + 0.5), z: h / 2 - PAD - TITLE - CELL * (row + 0.5) + 0.012 };
      board.cells.push(cell);
      const item = this.make(board, cell);
      this.items.push(item);
      item.value = spec.kind === 'selector' ? spec.initial ?? 0 : 0;
    });
    // Boards that print the same (every line's) share one face texture and one draw call.
    const key = JSON.stringify([p.title || p.path, p.elements.map((e) => [e.kind, e.label || e.name, e.names ?? '', e.positions ?? 0])]);
    let faces = this.faces.get(key);
    if (!faces) {
      const canvas = document.createElement('canvas');
      canvas.width = Math.round(w * PX);
      canvas.height = Math.round(h * PX);
      paintFace(canvas, board);
      const texture = new THREE.CanvasTexture(canvas);
      texture.colorSpace = THREE.SRGBColorSpace;
      texture.anisotropy = 4;
      faces = new Parts(new THREE.PlaneGeometry(1, 1).rotateX(Math.PI / 2), new THREE.MeshStandardMaterial({ map: texture, roughness: 0.8 }), this.group);
      this.faces.set(key, faces);
    }
    faces.add({ board, place: (o) => local(o, 0, -DEPTH / 2 - 0.0005, 0, w, 1, h) });
  }

  // The parts of one element; its item: {kind, cell, value, next()} with its pickable parts.
  make(board, cell) {
    const { spec, x, z } = cell;
    const item = { kind: spec.kind, cell, value: 0, lit: false, picks: [] };
    const pick = (act) => { const pk = { path: spec.path, act, item }; item.picks.push(pk); return pk; };
    const cyl = (color, place, act) => this.cylinders.add({ board, color, place, pick: act ? pick(act) : null });
    switch (spec.kind) {
      case 'button':
        cyl(0xb8bec6, (o) => local(o, x, FY - 0.003, z, 0.025, 0.006, 0.025));
        cyl(COLORS[spec.color] ?? 0x8a8f96, (o) => local(o, x, FY - (item.value ? 0.006 : 0.014), z, 0.019, 0.016, 0.019), 'button');
        break;
      case 'estop': {   // latched: the mushroom pushed in
        const ex = x - 0.008, ez = z + 0.004;
        cyl(COLORS.yellow, (o) => local(o, ex, FY - 0.002, ez, 0.03, 0.004, 0.03));
        cyl(0x333333, (o) => local(o, ex, FY - (item.value ? 0.006 : 0.012), ez, 0.011, 0.02, 0.011));
        cyl(COLORS.red, (o) => local(o, ex, FY - (item.value ? 0.016 : 0.028), ez, 0.023, 0.014, 0.023), 'estop');
        this.boxes.add({ board, color: 0x20242a, pick: pick('reset'), place: (o) => local(o, x + 0.036, FY - 0.005, z + 0.026, 0.014, 0.01, 0.01) });
        break;
      }
      case 'selector': {   // the bar turned clockwise seen from the front (−y)
        const n = spec.positions === 3 ? 3 : 2;
        const angle = (i) => (n === 2 ? (i === 0 ? -45 : 45) : (i - 1) * 45) * Math.PI / 180;
        item.next = () => (item.value + 1) % n;
        const knob = cyl(0x1d2026, (o) => local(o, x, FY - 0.008, z, 0.02, 0.016, 0.02), 'selector');
        this.boxes.add({ board, color: 0xf4f4f0, pick: knob.pick, place: (o) => local(o, x, FY - 0.017, z, 0.006, 0.004, 0.034, angle(item.value)) });
        break;
      }
      case 'lamp': {
        const color = COLORS[spec.color] ?? COLORS.green;
        cyl(0xb8bec6, (o) => local(o, x, FY - 0.002, z, 0.022, 0.006, 0.022));
        const r = (on) => (item.lit === on ? 0.017 : 0);   // the other lens: no size
        this.lensOn.add({ board, color, place: (o) => local(o, x, FY, z, r(true), r(true), r(true)) });
        this.lensOff.add({ board, color: new THREE.Color(color).multiplyScalar(0.3).getHex(), place: (o) => local(o, x, FY, z, r(false), r(false), r(false)) });
        break;
      }
      default: {   // a display: its window is printed on the face, its number a label over it
        const el = document.createElement('div');
        el.className = 'op-board-display';
        const object = new CSS2DObject(el);
        object.position.set(cell.x, FY - 0.002, cell.z).applyMatrix4(board.matrix);
        this.group.add(object);
        const digits = Math.max(0, Math.min(6, spec.digits ?? 0));
        item.show = () => { el.textContent = `${Number(item.value).toFixed(digits)}${spec.unit ? ` ${spec.unit}` : ''}`; };
        item.show();
        this.displays.push({ object, el, item });
      }
    }
    return item;
  }

  apply(values) {
    values = values ?? [];
    values.forEach((v, i) => {
      const it = this.items[i];
      if (!it || it.value === v) return;
      it.value = v;
      if (it.kind === 'lamp') it.lit = v === 1 || (v === 2 && blinkOn());
      if (it.kind === 'display') it.show();
      this.dirty = true;
    });
    this.values = values;
  }

  // Each frame: blinking lamps (once a second), what changed, the displays' numbers from close by.
  tick() {
    const on = blinkOn();
    for (const it of this.items)
      if (it?.kind === 'lamp' && it.value === 2 && it.lit !== on) { it.lit = on; this.dirty = true; }
    if (this.dirty) {
      for (const parts of [this.boxes, this.cylinders, this.lensOn, this.lensOff]) parts?.update();
      this.dirty = false;
    }
    if (this.displays.length && this.group.visible) {
      const cam = this.view.camera.position;
      for (const d of this.displays) d.object.visible = d.object.position.distanceTo(cam) < DISPLAY_RANGE;
    } else for (const d of this.displays) d.object.visible = false;
  }

  // The element under the pointer: {path, act, item}.
  hit(clientX, clientY) {
    if (!this.targets?.length || !this.group.visible) return null;
    const r = this.view.renderer.domElement.getBoundingClientRect();
    if (clientX < r.left || clientX > r.right || clientY < r.top || clientY > r.bottom) return null;
    const ndc = new THREE.Vector2(((clientX - r.left) / r.width) * 2 - 1, -((clientY - r.top) / r.height) * 2 + 1);
    this.view.camera.updateMatrixWorld();
    this.ray.setFromCamera(ndc, this.view.camera);
    const h = this.ray.intersectObjects(this.targets, false)[0];
    const pk = h && h.object.userData.parts.list[h.instanceId]?.pick;
    if (!pk) return null;   // the board itself, a rim: nothing to work
    // Nothing of the plant in front of it.
    const solid = this.view.pick(ndc.x, ndc.y);
    if (solid && solid.point.distanceTo(this.ray.ray.origin) < h.distance - 1e-3) return null;
    return pk;
  }

  event(path, value) {
    if (this.readOnly) return;
    this.send(value === undefined ? { type: 'event', path } : { type: 'event', path, value: String(value) });
  }

  down(e) {
    if (e.button !== 0 || e.target !== this.view.renderer.domElement) return;
    const h = this.hit(e.clientX, e.clientY);
    if (!h) return;
    e.stopPropagation();   // not the camera's drag, nor the hand's grab, nor a selection
    e.preventDefault();
    if (h.act === 'button') { this.held = h.path; this.event(`${h.path}.press`); }
    else if (h.act === 'estop') this.event(`${h.path}.press`);
    else if (h.act === 'reset') this.event(`${h.path}.reset`);
    else if (h.act === 'selector') this.event(`${h.path}.turn`, h.item.next());
  }

  up(e) {
    if (!this.held) return;
    this.event(`${this.held}.release`);
    this.held = null;
    e.stopPropagation();
  }

  // For tests and the docs: where an element is drawn on the screen (CSS pixels; the
  // emergency stop's reset key with `key`), or null when it is not placed in the scene.
  screenPoint(path, key = false) {
    const it = this.items.find((x) => x?.cell.spec.path === path);
    const pk = it?.picks.find((p) => (key ? p.act === 'reset' : p.act !== 'reset'));
    if (!pk) return null;
    for (const parts of [this.cylinders, this.boxes]) {
      const part = parts.list.find((x) => x.pick === pk);
      if (!part) continue;
      const p = new THREE.Vector3().setFromMatrixPosition(_m.multiplyMatrices(part.board.matrix, part.place(new THREE.Matrix4())));
      this.view.camera.updateMatrixWorld();
      p.project(this.view.camera);
      const r = this.view.renderer.domElement.getBoundingClientRect();
      return { x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height };
    }
    return null;
  }

  // For tests: every placed element's path, kind and what it shows (a lamp: lit or not; a
  // button: down or not; a display: its text), and the meshes drawing all the boards.
  summary() {
    return this.items.filter(Boolean).map((it) => ({
      path: it.cell.spec.path, kind: it.kind,
      lit: it.kind === 'lamp' ? it.lit : undefined,
      down: it.kind === 'button' ? it.value !== 0 : undefined,
      position: it.kind === 'selector' ? it.value : undefined,
      text: it.kind === 'display' ? this.displays.find((d) => d.item === it)?.el.textContent : undefined,
    }));
  }
  meshes() { return this.parts.filter((p) => p.mesh).length; }

  // The camera in front of a placed panel's face, `distance` metres out, a little to the
  // side and above, looking at its middle; false when it is not placed.
  lookAt(path, distance = 0.8, side = 0.25, above = 0.2) {
    const b = this.boards.find((x) => x.p.path === path);
    if (!b) return false;
    const c = new THREE.Vector3().setFromMatrixPosition(b.matrix);
    const out = new THREE.Vector3(side, -distance, above).applyQuaternion(new THREE.Quaternion().setFromRotationMatrix(b.matrix));
    const { camera, controls } = this.view;
    controls.target.copy(c);
    camera.position.copy(c).add(out);
    controls.update();
    camera.updateMatrixWorld();
    return true;
  }
}

// A board's face: title, each element's label, the emergency stop's `reset`, the selectors'
// position names, the displays' windows.
function paintFace(canvas, board) {
  const c = canvas.getContext('2d');
  const u = (x) => (x + board.w / 2) * PX, v = (z) => (board.h / 2 - z) * PX;
  const font = (size, bold = false, face = '"DejaVu Sans", sans-serif') => { c.font = `${bold ? 'bold ' : ''}${Math.round(size * PX)}px ${face}`; };
  c.fillStyle = '#4a5361';
  c.fillRect(0, 0, canvas.width, canvas.height);
  c.fillStyle = '#e8ecf1';
  c.textAlign = 'center';
  c.textBaseline = 'middle';
  font(0.026, true);
  c.fillText(board.p.title || board.p.path, canvas.width / 2, (PAD + TITLE / 2) * PX);
  for (const cell of board.cells) {
    const { spec } = cell;
    c.fillStyle = '#e8ecf1';
    font(0.0135);
    c.fillText(spec.label || spec.name, u(cell.x), v(cell.z - 0.044), CELL * PX * 0.95);
    if (spec.kind === 'estop') {
      font(0.01);
      c.fillText('reset', u(cell.x + 0.036), v(cell.z + 0.012));
    } else if (spec.kind === 'selector') {
      const n = spec.positions === 3 ? 3 : 2;
      const names = spec.names ? spec.names.split('/') : Array.from({ length: n }, (_, i) => String(i));
      font(0.012);
      c.fillStyle = '#d6dce3';
      names.forEach((name, i) => {
        const a = (n === 2 ? (i === 0 ? -45 : 45) : (i - 1) * 45) * Math.PI / 180;
        c.fillText(name, u(cell.x + Math.sin(a) * 0.036), v(cell.z + Math.cos(a) * 0.033));
      });
    } else if (spec.kind === 'display') {
      c.fillStyle = '#101418';
      c.fillRect(u(cell.x - 0.042), v(cell.z + 0.016), 0.084 * PX, 0.032 * PX);
    }
  }
}

function blinkOn() { return performance.now() % 1000 < 500; }
