// The viewer page: connects to `plant serve` (docs/viewer.md), draws the plant, and sends
// every interaction as a protocol message.
import { Connection, roleQuery } from './protocol.js';
import { PlantView } from './scene.js';
import { Inspector } from './inspector.js';
import { Plots } from './plots.js';
import { Labels } from './labels.js';
import { Hand } from './hand.js';
import { DrillsPanel, ForcedPanel, Notices } from './panels.js';
import { LostMarkers } from './lost.js';
import { OperatorPanels } from './panel.js';
import { ScenePanels } from './panel3d.js';

const $ = (id) => document.getElementById(id);
const view = new PlantView($('view'));
const debug = {
  sceneReady: false,
  framesReceived: 0,
  scenesReceived: 0,
  statusReceived: 0,
  bodyCount: 0,
  lastStatus: null,
  scene: null,
  events: [],
  errors: [],
  drawCalls: () => view.renderer.info.render.calls,
  triangles: () => view.renderer.info.render.triangles,
  // meshes the page made, drawn now or not: what bounds the draw calls (none per bottle)
  meshes: () => { let n = 0; view.world.traverse((o) => { if (o.isMesh) ++n; }); return n; },
  // bodies drawn now (in the world), counting instances
  bodiesDrawn: () => view.bodyGroups?.reduce((n, g) => n + g.solid.n + g.ghost.n + g.hull.n, 0) ?? 0,
  bodiesInWorld: () => (view.bodyState ? view.bodyState.reduce((n, s) => n + (s & 1), 0) : 0),
  bodyPose: (id) => {
    const i = view.bodyIndex?.get(id);
    return i === undefined ? null : Array.from(view.bodyPose.subarray(7 * i, 7 * i + 7));
  },
  bodyState: (id) => { const i = view.bodyIndex?.get(id); return i === undefined ? null : view.bodyState[i]; },
  send: (msg) => conn.send(msg),
  inspect: (path) => inspector.open(path),
  inspectedPath: () => inspector.path,
  modelStates: () => view.modelStates(),
  notices: () => notices.list(),
  labels: () => labels.texts(),
  lost: () => lost.list(),
  plots: () => plots.summary(),
  historiesReceived: 0,
  view,
};
window.plantViewer = debug;

let paused = false;
let replay = false;
let seeking = false;

function log(text, cls) {
  const ol = $('log');
  const li = document.createElement('li');
  li.textContent = text;
  if (cls) li.className = cls;
  ol.append(li);
  while (ol.children.length > 500) ol.firstChild.remove();
  ol.scrollTop = ol.scrollHeight;
}

const conn = new Connection({
  onConnection(state) {
    $('conn').textContent = state === 'open' ? 'connected' : state === 'refused' ? 'refused' : 'disconnected';
    $('conn').className = `badge ${state === 'open' ? 'ok' : 'bad'}`;
  },
  onScene(scene) {
    // Bodies name their shape list by index (docs/viewer.md): resolve it once.
    for (const b of scene.bodies) if (typeof b.shapes === 'number') b.shapes = scene.shape_lists[b.shapes];
    const same = debug.scene && debug.scene.plant === scene.plant && debug.scene.bodies.length === scene.bodies.length;
    debug.sceneReady = false;
    debug.scenesReceived++;
    debug.scene = scene;
    $('plant-name').textContent = scene.plant;
    document.title = `${scene.plant} · plant viewer`;
    notices.setScene(scene);
    view.load(scene, { keepCamera: same });
    labels.setScene(scene);
    lost.clear();
    hand.end();
    $('follow').classList.remove('on');
    inspector.readOnly = scene.mode === 'replay';   // a recording takes no events
    inspector.setScene(scene);
    operatorPanels.readOnly = scene.mode === 'replay';
    operatorPanels.setScene(scene);
    scenePanels.readOnly = scene.mode === 'replay';
    scenePanels.setScene(scene);
    plots.setScene(scene);
    replay = scene.mode === 'replay';
    $('timeline').hidden = !replay;
    for (const id of ['step', 'restart']) $(id).disabled = replay;
    if (replay) $('seek').max = String(scene.duration ?? 0);
    debug.bodyCount = view.bodyCount;
    debug.sceneReady = true;
    log(`scene: ${scene.plant}, ${scene.bodies.length} bodies, ${scene.rate} Hz${replay ? ', replay' : ''}`);
  },
  onWelcome(msg) { myClient = msg.client; setRole(msg); },
  onHistory(h) {
    debug.historiesReceived++;
    debug.lastHistory = { samples: h.time?.length ?? 0, first: h.time?.[0] ?? null, last: h.time?.[h.time.length - 1] ?? null };
    plots.setHistory(h);
  },
  onFrame(frame) {
    debug.framesReceived++;
    debug.lastFrame = { time: frame.time, step: frame.step, full: frame.full, paused: frame.paused, bodies: frame.bodyIds.length, graphics: frame.gfxIds.length };
    view.applyFrame(frame);
    setPaused(frame.paused);
    $('clock').textContent = `t = ${frame.time.toFixed(2)} s · step ${frame.step}`;
  },
  onStatus(st) {
    debug.statusReceived++;
    debug.lastStatus = st;
    view.applyStatus(st);
    setPaused(!!st.paused);
    markSpeed(st.speed);
    $('clock').textContent = `t = ${Number(st.time).toFixed(2)} s · step ${st.step}`;
    showPace(st);
    inspector.applyStatus(st.inspect);
    plots.applyStatus(st);
    forced.apply(st.forced ?? []);
    drills.apply(st.drills ?? []);
    labels.setForced(st.forced ?? []);
    lost.apply(st.lost ?? []);
    operatorPanels.apply(st.panel ?? []);
    scenePanels.apply(st.panel ?? []);
    if (replay && !seeking) {
      $('seek').value = String(st.time);
      $('seek-label').textContent = `${Number(st.time).toFixed(2)} s / ${Number(debug.scene?.duration ?? 0).toFixed(2)} s`;
    }
  },
  onEvent(msg) {
    debug.events.push(msg.line);
    const by = msg.by ?? (msg.client !== undefined ? `page ${msg.client}` : '');
    log(msg.line + (by ? `   (${by})` : ''), msg.planned ? 'planned' : msg.client === myClient ? 'mine' : '');
  },
  onDrill(msg) {   // a drill cancelled (or not: it had fired), the instructor's pages only
    const by = msg.by ? `   (${msg.by})` : '';
    if (msg.refused) log(`drill ${msg.id} not cancelled: ${msg.refused}${by}`, 'error');
    else log(`drill ${msg.id} cancelled at ${Number(msg.time).toFixed(2)} s${by}`, msg.client === myClient ? 'mine' : '');
  },
  onError(msg) {
    debug.errors.push(msg.message);
    log(`error: ${msg.message}`, 'error');
  },
});

const inspector = new Inspector((msg) => {
  conn.send(msg);
});
const plots = new Plots();
const notices = new Notices($('notices'), $('notice-list'));
view.onModelFailed = (url, error) => notices.add(`model ${url.replace(/^\/models\//, '')} could not be loaded (${error}): its body is drawn instead`);
view.onModelLoaded = () => labels.place();
const forced = new ForcedPanel($('forced'), $('forced-count'), $('forced-none'), (path) => conn.send({ type: 'force', path, mode: 'release' }), () => replay);
const drills = new DrillsPanel($('drill-form'), $('drills'), (msg) => conn.send(msg));
const labels = new Labels(view, (path) => debug.select(path));
const lost = new LostMarkers(view, (path) => debug.select(path));
const operatorPanels = new OperatorPanels($('view'), (msg) => conn.send(msg));
debug.panels = () => operatorPanels.summary();
const scenePanels = new ScenePanels(view, (msg) => conn.send(msg));   // panels placed in the scene (panel3d.js)
debug.scenePanels = scenePanels;
const hand = new Hand(view, (msg) => conn.send(msg), { onChange: () => showHand() });
debug.hand = hand;
// A close look at an object (the docs' close-ups): from `distance` metres, at an azimuth and
// an elevation in degrees, at the middle of what it draws.
debug.closeUp = (path, distance = 0.8, azimuth = -60, elevation = 30) => {
  const d = view.scene?.dos.find((x) => x.path === path);
  if (!d) return false;
  const box = labels.boxOf(d.id);
  if (box.isEmpty()) return false;
  const c = box.getCenter(box.min.clone());
  const a = azimuth * Math.PI / 180, e = elevation * Math.PI / 180;
  view.controls.target.copy(c);
  view.camera.position.set(c.x + distance * Math.cos(e) * Math.cos(a), c.y + distance * Math.cos(e) * Math.sin(a), c.z + distance * Math.sin(e));
  view.controls.update();
  view.camera.updateMatrixWorld();
  return true;
};
// The middle of what an object draws, [x, y, z].
debug.boxCentre = (doId) => {
  const box = labels.boxOf(doId);
  return box.isEmpty() ? [NaN, NaN, NaN] : box.getCenter(box.min.clone()).toArray();
};
let myClient = -1;

// The page's role (docs/viewer.md, "Roles"): a trainee's page hides what the server would
// refuse it (the run's controls, forces, the events file) and lists the inputs it may operate.
function setRole(msg) {
  const trainee = msg.role === 'trainee';
  debug.role = msg.role;
  document.body.classList.toggle('trainee', trainee);
  $('role').textContent = msg.role ?? '';
  $('role').hidden = !msg.role;
  $('save-events').href = `/events${roleQuery()}`;
  $('open-report').href = `/report${roleQuery()}`;
  inspector.operable = trainee ? new Set((msg.operable ?? []).map((o) => o.path)) : null;
  const list = $('controls');
  list.replaceChildren();
  for (const o of trainee ? (msg.operable ?? []).filter((x) => !x.panel) : []) {   // panels draw their own
    const row = document.createElement('tr');
    const name = document.createElement('td');
    name.textContent = o.label;
    name.title = o.path;
    const cell = document.createElement('td');
    cell.append(inspector.control({ path: o.path, type: o.type }));
    row.append(name, cell);
    list.append(row);
  }
  $('controls-panel').hidden = !trainee;
}

// The speed chosen (the buttons) and the speed achieved (over the last seconds), apart:
// "1×" chosen while the run achieves 0.8× says the machine cannot keep up.
function showPace(st) {
  const chosen = Number(st.speed) === 0 ? 'max' : `${Number(st.speed)}×`;
  const got = st.paused ? 'paused' : `${Number(st.rtf ?? 0).toFixed(2)}× achieved`;
  $('pace').textContent = `chosen ${chosen} · ${got}`;
  $('pace').classList.toggle('behind', !st.paused && Number(st.speed) > 0 && Number(st.rtf) < 0.9 * Number(st.speed));
}

function showHand() {
  $('hand').classList.toggle('on', hand.enabled);
  const text = hand.hint();
  $('hand-hint').hidden = !text;
  $('hand-hint').textContent = text;
}

function setPaused(p) {
  if (p === paused) return;
  paused = p;
  $('run').textContent = p ? 'run' : 'pause';
  $('run').classList.toggle('on', p);
}

function markSpeed(speed) {
  for (const b of $('speeds').querySelectorAll('button')) b.classList.toggle('on', Number(b.dataset.speed) === speed);
}

// ---- controls ----
$('run').addEventListener('click', () => conn.send({ type: 'control', action: paused ? 'run' : 'pause' }));
$('step').addEventListener('click', () => conn.send({ type: 'control', action: 'step' }));
$('restart').addEventListener('click', () => conn.send({ type: 'control', action: 'restart' }));
for (const b of $('speeds').querySelectorAll('button')) {
  b.addEventListener('click', () => conn.send({ type: 'control', action: 'speed', speed: Number(b.dataset.speed) }));
}
$('plant-ports').addEventListener('click', () => { view.select(-1); inspector.open(''); });
$('top-view').addEventListener('click', () => { view.follow(-1); $('follow').classList.remove('on'); view.topView(); });
$('follow').addEventListener('click', () => {
  if (view.followBody >= 0) { view.follow(-1); $('follow').classList.remove('on'); return; }
  if (selectedBody >= 0) { view.follow(selectedBody); $('follow').classList.add('on'); }
});
for (const name of ['bodies', 'graphics', 'fields', 'triggers', 'collision', 'labels', 'panels']) {
  $(`layer-${name}`).addEventListener('change', (e) => view.setLayer(name, e.target.checked));
}
$('layer-legend').addEventListener('change', (e) => { $('legend').hidden = !e.target.checked; });
$('hand').addEventListener('click', () => hand.setEnabled(!hand.enabled));
$('seek').addEventListener('input', () => {
  seeking = true;
  $('seek-label').textContent = `${Number($('seek').value).toFixed(2)} s`;
});
$('seek').addEventListener('change', () => {
  conn.send({ type: 'seek', time: Number($('seek').value) });   // the server sends the history up to there
  seeking = false;
});
window.addEventListener('keydown', (e) => {
  if (e.target instanceof HTMLInputElement || e.target instanceof HTMLButtonElement) return;
  if (e.key === ' ' && !document.body.classList.contains('trainee')) { e.preventDefault(); $('run').click(); }
});

// ---- hover label and selection ----
const canvas = view.renderer.domElement;
let pointer = null, pointerMoved = false, lastPick = 0, downAt = null;
let selectedBody = -1;
canvas.addEventListener('pointermove', (e) => {
  const r = canvas.getBoundingClientRect();
  pointer = { x: e.clientX - r.left, y: e.clientY - r.top, w: r.width, h: r.height };
  pointerMoved = true;
});
canvas.addEventListener('pointerleave', () => { pointer = null; $('hover').hidden = true; });
canvas.addEventListener('pointerdown', (e) => { downAt = { x: e.clientX, y: e.clientY }; });
canvas.addEventListener('pointerup', (e) => {
  if (!downAt || Math.hypot(e.clientX - downAt.x, e.clientY - downAt.y) > 4) return;   // a drag of the camera
  if (hand.enabled) return;   // the hand took or set down something
  const r = canvas.getBoundingClientRect();
  const hit = view.pick(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  selectHit(hit);
});

function selectHit(hit) {
  if (!hit) { view.select(-1); labels.select(-1); inspector.close(); selectedBody = -1; $('follow').disabled = true; return; }
  view.select(hit.doId);
  labels.select(hit.doId);
  inspector.open(hit.doPath);
  selectedBody = hit.kind === 'body' && view.scene.bodies[hit.index].mode === 'dynamic' ? hit.index : -1;
  $('follow').disabled = selectedBody < 0;
  if (view.followBody >= 0 && selectedBody >= 0) view.follow(selectedBody);
}
debug.select = (path) => {
  const d = view.scene?.dos.find((x) => x.path === path);
  if (!d) return false;
  const bi = view.scene.bodies.findIndex((b) => b.do === d.id);
  selectHit({ kind: bi >= 0 ? 'body' : 'do', index: bi, path, doId: d.id, doPath: path });
  return true;
};
// Where on the canvas (CSS pixels) a body's origin is drawn, for clicking it in tests.
debug.screenPoint = (id) => {
  const i = view.bodyIndex?.get(id);
  if (i === undefined) return null;
  view.camera.updateMatrixWorld();
  const p = view.bodyWorldPosition(i).project(view.camera);
  const r = canvas.getBoundingClientRect();
  return { x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height };
};
$('insp-close').addEventListener('click', () => { view.select(-1); selectedBody = -1; $('follow').disabled = true; });

function hover() {
  if (!pointer || !pointerMoved) return;
  const now = performance.now();
  if (now - lastPick < 60) return;
  lastPick = now;
  pointerMoved = false;
  const hit = view.pick((pointer.x / pointer.w) * 2 - 1, -(pointer.y / pointer.h) * 2 + 1);
  const label = $('hover');
  if (!hit) { label.hidden = true; return; }
  label.textContent = hit.path + (hit.kind === 'body' ? '' : ` (${hit.kind})`);
  label.style.left = `${pointer.x + 14}px`;
  label.style.top = `${pointer.y + 10}px`;
  label.hidden = false;
}

function loop() {
  hover();
  scenePanels.tick();
  view.render();
  requestAnimationFrame(loop);
}
requestAnimationFrame(loop);
