// The hand: a trainee takes a bottle (any dynamic body) with the mouse, as at a real line.
// With the hand on (toolbar, or H), press on a bottle: it is lifted and follows the pointer
// in a plane above where it was; the wheel raises and lowers it; let go of the button and it
// is set down where it is (lowered to the height it was taken at, then let go). Shift while
// taking it: push it along without lifting. Delete takes it out of the plant (back to its
// pool); Escape lets it fall. Every grab, move and release is a `hand` message: an event of
// the run, logged and saved like any other (docs/runtime.md, "Hands").
import * as THREE from 'three';

const LIFT = 0.1;          // m a taken body rises
const MOVE_EVERY = 50;     // ms between two move messages
// At most this long lowering before letting go: in the plant's time (a plant that runs slower
// than the wall clock, on a busy machine, still lowers it all the way), and a bound on the
// wall clock for a plant that does not run (paused).
const SET_DOWN_S = 1.5;
const SET_DOWN_WALL_MS = 10_000;

export class Hand {
  constructor(view, send, { onChange } = {}) {
    this.view = view;
    this.send = send;
    this.onChange = onChange;
    this.enabled = false;
    this.held = null;   // {body (index), path, grabZ, offsetZ, lift, target, push, lastSent, settingDown}
    this.ray = new THREE.Raycaster();
    this.marker = this.makeMarker();
    view.layers.graphics.parent.add(this.marker);
    const canvas = view.renderer.domElement;
    canvas.addEventListener('pointerdown', (e) => this.down(e), { capture: true });
    canvas.addEventListener('pointermove', (e) => this.move(e));
    window.addEventListener('pointerup', (e) => this.up(e));
    canvas.addEventListener('wheel', (e) => this.wheel(e), { capture: true, passive: false });
    window.addEventListener('keydown', (e) => this.key(e));
  }

  makeMarker() {
    const g = new THREE.Group();
    const ring = new THREE.Mesh(new THREE.TorusGeometry(0.03, 0.004, 6, 24), new THREE.MeshBasicMaterial({ color: 0xff2d78 }));
    const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3(0, 0, -1)]),
      new THREE.LineDashedMaterial({ color: 0xff2d78, dashSize: 0.01, gapSize: 0.01 }));
    line.computeLineDistances();
    g.add(ring, line);
    g.visible = false;
    this.markerLine = line;
    return g;
  }

  setEnabled(on) {
    this.enabled = on;
    this.view.renderer.domElement.classList.toggle('hand', on);
    if (!on && this.held) this.release(false);
    this.onChange?.();
  }

  ndc(e) {
    const r = this.view.renderer.domElement.getBoundingClientRect();
    return new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  }

  // The dynamic body under the pointer (a bottle's model stands for its body), and the point hit.
  bodyAt(e) {
    const hit = this.view.pick(...this.ndc(e).toArray());
    if (!hit) return null;
    const scene = this.view.scene;
    let index = -1;
    if (hit.kind === 'body') index = hit.index;
    else if (hit.kind === 'graphics') index = this.view.bodyIndex.get(scene.graphics[hit.index].body) ?? -1;
    if (index < 0 || scene.bodies[index].mode !== 'dynamic') return null;
    return { index, point: hit.point };
  }

  // Where the pointer's ray meets the horizontal plane at height z.
  onPlane(e, z) {
    this.view.camera.updateMatrixWorld();
    this.ray.setFromCamera(this.ndc(e), this.view.camera);
    const p = new THREE.Vector3();
    return this.ray.ray.intersectPlane(new THREE.Plane(new THREE.Vector3(0, 0, 1), -z), p) ? p : null;
  }

  message(action, point) {
    const msg = { type: 'hand', action, path: this.held.path };
    if (point) msg.point = [point.x, point.y, point.z].map((v) => Math.round(v * 1e4) / 1e4);   // 0.1 mm
    this.send(msg);
  }

  down(e) {
    if (!this.enabled || e.button !== 0 || this.held) return;
    const at = this.bodyAt(e);
    if (!at) return;   // not on a body it can take: the camera moves as usual
    e.stopPropagation();
    e.preventDefault();
    this.view.controls.enabled = false;
    const b = this.view.scene.bodies[at.index];
    const push = e.shiftKey;
    // offsetZ: the grab point's height above the body's origin, as it was taken (heldPointZ).
    this.held = { body: at.index, path: b.path, grabZ: at.point.z, offsetZ: at.point.z - this.view.bodyPose[7 * at.index + 2],
                  lift: push ? 0 : LIFT, target: at.point.clone(), push, lastSent: 0 };
    this.message('grab', at.point);
    this.target(at.point.clone().setZ(at.point.z + this.held.lift));
    this.onChange?.();
  }

  target(p) {
    const h = this.held;
    h.target.copy(p);
    const now = performance.now();
    if (now - h.lastSent >= MOVE_EVERY) {
      h.lastSent = now;
      this.message('move', p);
      h.pending = false;
    } else if (!h.pending) {   // the last position is sent when the pointer rests
      h.pending = true;
      setTimeout(() => { if (this.held === h && h.pending) { h.pending = false; h.lastSent = performance.now(); this.message('move', h.target); } }, MOVE_EVERY);
    }
    this.marker.visible = true;
    this.marker.position.copy(p);
    const floor = this.view.layers.ground.children[0]?.position.z ?? 0;
    this.markerLine.scale.set(1, 1, Math.max(0.001, p.z - floor));
    this.markerLine.computeLineDistances();
  }

  move(e) {
    const h = this.held;
    if (!h || h.settingDown) return;
    const p = this.onPlane(e, h.grabZ + h.lift);
    if (p) this.target(p);
  }

  wheel(e) {
    const h = this.held;
    if (!h || h.settingDown) return;
    e.preventDefault();
    e.stopPropagation();
    h.lift = Math.min(0.5, Math.max(0, h.lift + (e.deltaY < 0 ? 0.01 : -0.01)));
    this.target(h.target.clone().setZ(h.grabZ + h.lift));
  }

  up(e) {
    if (!this.held || e.button !== 0 || this.held.settingDown) return;
    this.release(!this.held.push);
  }

  // Lets go: set down first (lowered to the height it was taken at, then let go when it is
  // there or after a while), or at once.
  release(setDown) {
    const h = this.held;
    if (!setDown || h.lift <= 0.002) return this.drop();
    h.settingDown = true;
    h.lift = 0;
    h.lastSent = 0;
    this.target(h.target.clone().setZ(h.grabZ));
    const started = performance.now(), startedAt = this.view.simTime;
    const check = () => {
      if (this.held !== h) return;
      const i = h.body, pose = this.view.bodyPose;
      const low = pose && Math.abs(this.heldPointZ(i) - h.grabZ) < 0.004;
      if (low || this.view.simTime - startedAt > SET_DOWN_S || performance.now() - started > SET_DOWN_WALL_MS) this.drop();
      else setTimeout(check, 50);
    };
    setTimeout(check, 100);
    this.onChange?.();
  }

  // The height of the point it holds now: the body's origin's, moved by where it was taken.
  // (Measured when it is taken: measured at the first look while setting down, when it is
  // still lifted, it found the body 'low' at once, and let it fall from where it was.)
  heldPointZ(i) {
    return this.view.bodyPose[7 * i + 2] + this.held.offsetZ;
  }

  drop() {
    if (!this.held) return;
    this.message('drop');
    this.end();
  }

  remove() {
    if (!this.held) return;
    const b = this.view.scene.bodies[this.held.body];
    const d = this.view.scene.dos[this.view.doIndex.get(b.do)];
    this.send({ type: 'hand', action: 'remove', path: d?.path ?? this.held.path });
    this.end();
  }

  end() {
    this.held = null;
    this.marker.visible = false;
    this.view.controls.enabled = true;
    this.onChange?.();
  }

  key(e) {
    if (e.target instanceof HTMLInputElement) return;
    if (e.key === 'h' || e.key === 'H') { this.setEnabled(!this.enabled); return; }
    if (!this.held) return;
    if (e.key === 'Delete' || e.key === 'Backspace') { e.preventDefault(); this.remove(); }
    else if (e.key === 'Escape') this.drop();
  }

  // What the hint line says.
  hint() {
    if (!this.enabled) return '';
    if (!this.held) return 'hand: press on a bottle to take it (Shift: push it along)';
    if (this.held.settingDown) return `setting ${this.held.path} down…`;
    return `holding ${this.held.path}: release to set it down · wheel: higher / lower · Delete: take it out · Esc: let it fall`;
  }
}
