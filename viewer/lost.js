// Where objects were lost: a red marker at the place each lost object last rode a conveyor
// (the rail it went over, the belt end it fell off; where it left the world when it rode
// none), from the status message's `lost` list (docs/viewer.md), with a label that says what,
// when and off which conveyor. The markers stay until the run restarts or a replay seeks back
// before the loss; a click on a label inspects the conveyor it fell off.
import * as THREE from 'three';
import { CSS2DObject } from 'three/addons/renderers/CSS2DRenderer.js';

const ringGeometry = new THREE.TorusGeometry(0.035, 0.006, 8, 24);
const ringMaterial = new THREE.MeshBasicMaterial({ color: 0xd7263d });

// "store[12]" from "line[0].storage.store[12]": the object's own name.
function shortName(path) {
  return path.slice(path.lastIndexOf('.') + 1);
}

export class LostMarkers {
  constructor(view, onPick) {
    this.view = view;
    this.onPick = onPick;
    this.group = new THREE.Group();
    this.group.name = 'lost';
    view.world.add(this.group);
    this.items = new Map();   // key "do@time" → {object, ring, entry}
    this.fieldPath = (id) => (id === null || id === undefined ? null : view.scene?.fields?.[id]?.path ?? null);
  }

  clear() {
    for (const it of this.items.values()) { it.object.removeFromParent(); it.ring.removeFromParent(); }
    this.items.clear();
  }

  // The status's `lost` list: markers for new entries, none for entries no longer listed (a
  // restart, a seek back in a replay).
  apply(lost) {
    const keep = new Set();
    for (const e of lost ?? []) {
      const key = `${e.do}@${e.time}`;
      keep.add(key);
      if (this.items.has(key)) continue;
      const [x, y, z] = e.place ?? e.out ?? [0, 0, 0];
      const ring = new THREE.Mesh(ringGeometry, ringMaterial);
      ring.position.set(x, y, z);
      this.group.add(ring);
      const field = this.fieldPath(e.field);
      const el = document.createElement('div');
      el.className = 'label lost';
      el.textContent = `✕ ${shortName(e.path)} lost ${Number(e.left ?? e.time).toFixed(1)} s`;
      el.title = field
        ? `${e.path}: off ${field} at ${Number(e.left).toFixed(3)} s, left the world at ${Number(e.time).toFixed(3)} s (click: inspect the conveyor)`
        : `${e.path}: on no conveyor, left the world at ${Number(e.time).toFixed(3)} s`;
      el.dataset.path = e.path;
      el.addEventListener('pointerdown', (ev) => ev.stopPropagation());
      if (field) el.addEventListener('click', (ev) => { ev.stopPropagation(); this.onPick(field.slice(0, field.lastIndexOf('.'))); });
      const object = new CSS2DObject(el);
      object.center.set(0.5, 1);
      object.position.set(x, y, z + 0.06);
      this.group.add(object);
      this.items.set(key, { object, ring, entry: e });
    }
    for (const [key, it] of this.items) {
      if (keep.has(key)) continue;
      it.object.removeFromParent();
      it.ring.removeFromParent();
      this.items.delete(key);
    }
  }

  // What the markers say, for the browser test: [{path, text, place}].
  list() {
    return [...this.items.values()].map((it) => ({ path: it.entry.path, text: it.object.element.textContent, place: it.ring.position.toArray() }));
  }
}
