// Labels in the 3D view: every object the plant names at its top levels (a line's switches,
// lanes, stations, separators, storage, arm, belts), above what it draws, as text that keeps
// its size at every zoom (CSS2DRenderer). Their text is the instance's own name (`s1` reads
// S1, `lane_a` lane A); belts, sensors and exits (only static shapes and volumes) are
// labelled small. A click on a label inspects the object; an object with a forced slot shows
// ⚡ in red.
import * as THREE from 'three';
import { CSS2DObject } from 'three/addons/renderers/CSS2DRenderer.js';

const MAX_LABELS = 400;   // beyond it, only the prominent ones (a plant of many lines)

// The instance's name as a label: `s1` S1, `b326` B326, `lane_a` lane A, `sep1` SEP1.
export function prettyName(path) {
  const name = path.slice(path.lastIndexOf('.') + 1);
  if (/^[a-z]{1,3}\d+$/.test(name)) return name.toUpperCase();
  return name.split('_').map((w) => (w.length === 1 ? w.toUpperCase() : w)).join(' ');
}

const _p = new THREE.Vector3(), _q = new THREE.Quaternion(), _m = new THREE.Matrix4(), _l = new THREE.Matrix4();

export class Labels {
  constructor(view, onPick) {
    this.view = view;
    this.onPick = onPick;
    this.items = [];       // {doId, path, object (CSS2DObject), element, tier}
    this.byDo = new Map();
  }

  clear() {
    for (const it of this.items) it.object.removeFromParent();
    this.items = [];
    this.byDo.clear();
  }

  // Which objects get labels: the first level below the plant with several objects (a single
  // container, like the one line of a plant, is looked through), and when those are
  // containers themselves (several lines), their objects too.
  setScene(scene) {
    this.clear();
    this.scene = scene;
    const kids = new Map(scene.dos.map((d) => [d.id, []]));
    for (const d of scene.dos) if (d.parent >= 0) kids.get(d.parent)?.push(d);
    const own = new Map(scene.dos.map((d) => [d.id, { bodies: [], graphics: [], triggers: [] }]));
    scene.bodies.forEach((b, i) => own.get(b.do)?.bodies.push(i));
    scene.graphics.forEach((g, i) => own.get(this.view.gfxDo[i])?.graphics.push(i));
    scene.triggers.forEach((t, i) => own.get(this.view.doOfPath(t.path))?.triggers.push(i));
    // Per object: whether its subtree draws anything, and anything that moves or has a model.
    const draws = new Map(), prominent = new Map();
    const visit = (d) => {
      const o = own.get(d.id);
      let any = o.bodies.length + o.graphics.length + o.triggers.length > 0;
      let big = o.graphics.length > 0 || o.bodies.some((i) => scene.bodies[i].mode !== 'static');
      for (const k of kids.get(d.id)) {
        visit(k);
        any ||= draws.get(k.id);
        big ||= prominent.get(k.id);
      }
      draws.set(d.id, any);
      prominent.set(d.id, big);
    };
    const root = scene.dos.find((d) => d.parent < 0);
    if (!root) return;
    visit(root);
    const shown = (list) => list.filter((d) => draws.get(d.id) && !d.pooled);
    let level = shown(kids.get(root.id));
    while (level.length === 1 && shown(kids.get(level[0].id)).length > 0) level = shown(kids.get(level[0].id));
    const container = (d) => { const o = own.get(d.id); return o.bodies.length + o.graphics.length + o.triggers.length === 0; };
    const picked = [];
    if (level.length > 1 && level.every(container)) {
      for (const d of level) picked.push({ d, tier: 'group' });
      for (const d of level) for (const k of shown(kids.get(d.id))) picked.push({ d: k, tier: prominent.get(k.id) ? 'major' : 'minor' });
    } else {
      for (const d of level) picked.push({ d, tier: prominent.get(d.id) ? 'major' : 'minor' });
    }
    const keep = picked.length > MAX_LABELS ? picked.filter((p) => p.tier !== 'minor').slice(0, MAX_LABELS) : picked;
    this.subtree = (id) => {
      const out = [id];
      for (let i = 0; i < out.length; i++) for (const k of kids.get(out[i])) out.push(k.id);
      return out;
    };
    this.own = own;
    for (const { d, tier } of keep) {
      const el = document.createElement('div');
      el.className = `label ${tier}`;
      el.textContent = prettyName(d.path);
      el.title = `${d.path} (${d.type}): click to inspect`;
      el.dataset.path = d.path;
      el.addEventListener('pointerdown', (e) => e.stopPropagation());
      el.addEventListener('click', (e) => { e.stopPropagation(); this.onPick(d.path); });
      const object = new CSS2DObject(el);
      object.center.set(0.5, 1);   // above its anchor
      this.view.layers.labels.add(object);
      const it = { doId: d.id, path: d.path, object, element: el, tier, text: el.textContent };
      this.items.push(it);
      this.byDo.set(d.id, it);
    }
    this.place();
  }

  // Each label over the middle of what its object draws, a little above its top. Called
  // again when a model loads (a model is taller than the point its graphics sits at).
  place() {
    for (const it of this.items) {
      const box = this.boxOf(it.doId);
      if (box.isEmpty()) continue;
      const c = box.getCenter(new THREE.Vector3());
      it.object.position.set(c.x, c.y, box.max.z + 0.03);
    }
  }

  // What an object draws, where it stands: its static bodies, volumes and models (or, for a
  // storage of pooled bottles only, where those start).
  boxOf(doId) {
    const scene = this.scene;
    const box = new THREE.Box3(), pt = new THREE.Vector3();
    for (const id of this.subtree(doId)) {
      const o = this.own.get(id);
      for (const i of o.bodies) this.addBody(box, scene.bodies[i], false);
      for (const i of o.triggers) {
        const t = scene.triggers[i];
        this.view.volumeMatrix(t, _m);
        for (const sx of [-0.5, 0.5]) for (const sy of [-0.5, 0.5]) for (const sz of [-0.5, 0.5])
          box.expandByPoint(pt.set(sx * t.extent[0], sy * t.extent[1], sz * t.extent[2]).applyMatrix4(_m));
      }
      for (const i of o.graphics) this.addGraphics(box, i);
    }
    if (box.isEmpty()) for (const id of this.subtree(doId)) for (const i of this.own.get(id).bodies) this.addBody(box, scene.bodies[i], true);
    return box;
  }

  addBody(box, b, moving) {
    if (b.mode !== 'static' && !moving) return;   // where a thing stands, not where what moves is now
    const body = new THREE.Matrix4().compose(_p.set(b.pose[0], b.pose[1], b.pose[2]), _q.set(b.pose[3], b.pose[4], b.pose[5], b.pose[6]).normalize(), new THREE.Vector3(1, 1, 1));
    for (const sh of b.shapes) {
      const l = sh.local ?? [0, 0, 0, 0, 0, 0, 1];
      _l.compose(_p.set(l[0], l[1], l[2]), _q.set(l[3], l[4], l[5], l[6]).normalize(), new THREE.Vector3(1, 1, 1));
      _m.multiplyMatrices(body, _l);
      const s = sh.size ?? [0, 0, 0];
      const half = sh.kind === 'box' ? [s[0] / 2, s[1] / 2, s[2] / 2] : sh.kind === 'hull' ? null : [s[0], s[0], sh.kind === 'sphere' ? s[0] : s[1] / 2];
      if (half) {
        for (const sx of [-1, 1]) for (const sy of [-1, 1]) for (const sz of [-1, 1])
          box.expandByPoint(new THREE.Vector3(sx * half[0], sy * half[1], sz * half[2]).applyMatrix4(_m));
      } else {
        for (const p of sh.points ?? []) box.expandByPoint(new THREE.Vector3(p[0], p[1], p[2]).applyMatrix4(_m));
      }
    }
  }

  addGraphics(box, i) {
    const g = this.scene.graphics[i];
    const pose = g.pose ?? [0, 0, 0, 0, 0, 0, 1];
    if (g.body >= 0) return;   // on a body: a bottle, which moves
    const m = new THREE.Matrix4().compose(_p.set(pose[0], pose[1], pose[2]), _q.set(pose[3], pose[4], pose[5], pose[6]).normalize(), new THREE.Vector3(1, 1, 1));
    const parts = this.view.models.get(g.model_url)?.parts;
    if (!parts) { box.expandByPoint(_p.set(pose[0], pose[1], pose[2])); return; }
    for (const part of parts) {
      const geo = part.group.mesh.geometry;
      if (!geo.boundingBox) geo.computeBoundingBox();
      box.union(geo.boundingBox.clone().applyMatrix4(new THREE.Matrix4().multiplyMatrices(m, part.local)));
    }
  }

  // Objects with a forced slot (status.forced): ⚡ and red.
  setForced(forced) {
    const marked = new Set();
    for (const f of forced ?? []) {
      let best = null;
      for (const it of this.items) if (f.path.startsWith(it.path + '.') && (!best || it.path.length > best.path.length)) best = it;
      if (best) marked.add(best);
    }
    for (const it of this.items) {
      const on = marked.has(it);
      if (it.element.classList.contains('forced') === on) continue;
      it.element.classList.toggle('forced', on);
      it.element.textContent = on ? `⚡ ${it.text}` : it.text;
    }
  }

  select(doId) {
    for (const it of this.items) it.element.classList.toggle('selected', it.doId === doId);
  }

  texts() { return this.items.map((it) => it.text); }
}
