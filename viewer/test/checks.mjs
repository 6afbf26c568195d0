// The browser test's checks of what a trainee sees and does (browser.mjs runs them): the
// stdlib's models all loaded, the labels, a bottle taken by the hand and set down on a belt
// further on (then the session's events replayed headless to the same poses, bit for bit),
// the history a late page plots, and a page told about missing and refused models.
import { spawn, spawnSync } from 'node:child_process';
import { copyFileSync, mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync, truncateSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseFrame } from '../protocol.js';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');

// Every model the scene names is loaded (none fell back to primitives), and no notice.
export async function modelsLoaded({ page, scene, check, until }) {
  const named = new Set();
  for (const g of scene.graphics) for (const m of [g.model, ...(g.variants ?? []).map((v) => v.model)]) if (m) named.add(m);
  const unserved = scene.graphics.filter((g) => !g.model_url || (g.variants ?? []).some((v) => !v.model_url)).length;
  check(unserved === 0 && (scene.model_problems ?? []).length === 0, `the server found every model the stdlib names (${[...named].sort().join(', ')})`);
  const states = await until(() => page.evaluate(() => {
    const s = plantViewer.modelStates();
    return Object.values(s).every((x) => x !== 'loading') ? s : null;
  }), 30_000, 200);
  const loaded = Object.entries(states ?? {}).filter(([, s]) => s === 'loaded').length;
  check(states && loaded === named.size, `the page loaded all ${named.size} models (${loaded} loaded${states ? '' : ', timed out'}: ${JSON.stringify(states)})`);
  const notices = await page.evaluate(() => plantViewer.notices());
  check(notices.length === 0, `no notice on the page${notices.length ? ': ' + notices.join(' | ') : ''}`);
}

export async function labelsShown({ page, check }) {
  const labels = await page.evaluate(() => plantViewer.labels());
  const want = ['S1', 'S2', 'S3', 'S4', 'S5', 'lane A', 'lane B', 'lane C', 'lane D', 'lane E', 'fill', 'cap', 'storage', 'arm'];
  const missing = want.filter((w) => !labels.includes(w));
  check(missing.length === 0, `labels in the scene: ${want.join(', ')}${missing.length ? ` (missing: ${missing.join(', ')})` : ''} among ${labels.length}`);
}

// Applies a recording's frames in order: the poses at its end (Float32, as the page's).
function lastPoses(recPath, nBodies) {
  const buf = readFileSync(recPath);
  const poses = new Float32Array(7 * nBodies), states = new Uint8Array(nBodies);
  let o = 'plant-rec 1\n'.length, step = -1;
  while (o + 5 <= buf.length) {
    const tag = String.fromCharCode(buf[o]), n = buf.readUInt32LE(o + 1);
    if (tag === 'F') {
      const f = parseFrame(buf.buffer.slice(buf.byteOffset + o + 5, buf.byteOffset + o + 5 + n));
      for (let k = 0; k < f.bodyIds.length; k++) {
        poses.set(f.bodyPoses.subarray(7 * k, 7 * k + 7), 7 * f.bodyIds[k]);
        states[f.bodyIds[k]] = f.bodyStates[k];
      }
      step = f.step;
    }
    o += 5 + n;
  }
  return { poses, states, step };
}

// A bottle on the belt after the arm (B6, S5, B7) is taken with the mouse, lifted and set
// down on B8, further on; the run goes on with nothing lost; the session's events replay
// headless (plant run --events --record) to the same poses of every body, bit for bit.
export async function handCarries({ page, client, scene, url, binary, plantFile, serveArgs, check, until, sleep, elapsed }) {
  const bodies = scene.bodies;
  const isBottle = (b) => b.mode === 'dynamic' && b.path.endsWith('.main');
  await page.click('button[data-speed="1"]');
  // A bottle standing on the right side of the loop, past the arm's drop point.
  const pick = await until(() => page.evaluate((ids) => {
    for (const id of ids) {
      const p = plantViewer.bodyPose(id);
      if ((plantViewer.bodyState(id) & 1) && Math.abs(p[0] - 5.3) < 0.02 && p[1] > 0.6 && p[1] < 1.5 && p[2] < 0.05) return id;
    }
    return null;
  }, bodies.filter(isBottle).map((b) => b.id)), 30_000, 50);
  if (!check(pick !== null, `a bottle stands on the belt after the arm (${elapsed()})`)) return;
  await page.click('#run');   // pause: the bottle stays under the mouse while it is taken
  const paused0 = await until(() => page.evaluate(() => plantViewer.lastStatus?.paused), 15_000);
  const path = bodies.find((b) => b.id === pick).path;
  await page.click('#hand');
  // Aimed from above; on a loaded machine the first frame after the camera turned may come
  // late, so a press that finds nothing under it (the hand takes nothing: the press turns the
  // camera instead) is tried again, up to three times, each time aimed anew; what the ray met
  // is reported when none takes it. The press must reach the canvas: a label drawn over the
  // bottle takes it (labels open the inspector), so the aim moves off the label, over the
  // bottle, where one covers its origin.
  let taken = null, met = null;
  for (let attempt = 0; attempt < 3 && taken !== path; attempt++) {
    await page.evaluate((id) => plantViewer.view.lookDownAt(plantViewer.bodyPose(id), 1.6), pick);
    await sleep(400 + 600 * attempt);
    const origin = await page.evaluate((id) => plantViewer.screenPoint(id), pick);
    const aim = await page.evaluate(({ p, want }) => {
      const canvas = plantViewer.view.renderer.domElement;
      const what = (q) => {
        const at = plantViewer.hand.bodyAt({ clientX: q.x, clientY: q.y });
        return at ? plantViewer.view.scene.bodies[at.index].path : 'nothing it can take';
      };
      for (const [dx, dy] of [[0, 0], [0, 5], [0, -5], [5, 0], [-5, 0], [0, 10], [0, -10], [10, 0], [-10, 0]]) {
        const q = { x: p.x + dx, y: p.y + dy };
        if (document.elementFromPoint(q.x, q.y) === canvas && what(q) === want) return { q, met: want };
      }
      const el = document.elementFromPoint(p.x, p.y);
      return { q: p, met: `${what(p)}, the press going to ${el === canvas ? 'the canvas' : `${el?.tagName}.${el?.className} '${el?.textContent?.slice(0, 20)}'`}` };
    }, { p: origin, want: path });
    const from = aim.q;
    met = `${aim.met}; paused ${paused0 ? 'yes' : 'not seen'}`;
    await page.mouse.move(from.x, from.y);
    await page.mouse.down();
    taken = await until(() => page.evaluate(() => plantViewer.hand.held?.path ?? null), 2000, 50);
    if (taken !== path) {
      await page.mouse.up();
      if (taken) await page.evaluate(() => plantViewer.hand.drop());
    }
  }
  if (!check(taken === path, `the hand took ${path} (${taken}; under the pointer: ${met})`)) return;
  const grabZ = await page.evaluate(() => plantViewer.hand.held.grabZ);
  await page.evaluate(() => plantViewer.send({ type: 'control', action: 'run' }));   // the mouse stays held
  // Carry it over belt B8 (at y = 2.1 m, heading -x from x = 5.0 m), 10 cm above its grab height.
  const target = [4.95, 2.1, grabZ + 0.1];
  await page.evaluate((t) => plantViewer.view.lookDownAt([5.1, 1.5, 0], 2.4), target);
  await sleep(200);
  const to = await page.evaluate((t) => {
    const v = plantViewer.view, r = v.renderer.domElement.getBoundingClientRect();
    const p = new v.camera.position.constructor(t[0], t[1], t[2]).project(v.camera);
    return { x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height };
  }, target);
  const start = await page.evaluate(() => { const t = plantViewer.hand.held.target; return [t.x, t.y, t.z]; });
  const startScreen = await page.evaluate((t) => {
    const v = plantViewer.view, r = v.renderer.domElement.getBoundingClientRect();
    const p = new v.camera.position.constructor(t[0], t[1], t[2]).project(v.camera);
    return { x: r.left + (p.x + 1) / 2 * r.width, y: r.top + (1 - p.y) / 2 * r.height };
  }, start);
  for (let i = 1; i <= 20; i++) {
    await page.mouse.move(startScreen.x + (to.x - startScreen.x) * i / 20, startScreen.y + (to.y - startScreen.y) * i / 20);
    await sleep(90);
  }
  const over = await until(() => page.evaluate((id) => { const p = plantViewer.bodyPose(id); return Math.hypot(p[0] - 4.95, p[1] - 2.1) < 0.03 ? p : null; }, pick), 8000, 50);
  check(!!over && over[2] > grabZ - 0.04 + 0.05, `the bottle is carried over B8, lifted (z ${over?.[2]?.toFixed(3)}, ${elapsed()})`);
  // Released while the plant is paused, it stays held: nothing lowers it while nothing runs.
  // (The hand used to measure its hold at its first look while setting down, with the bottle
  // still lifted, find it 'down' at once and let it fall from there: on a busy machine, where
  // little of the plant's time passes before that look, it fell 10 cm and could tip over.)
  await page.evaluate(() => plantViewer.send({ type: 'control', action: 'pause' }));
  const pausedToSet = await until(() => page.evaluate(() => plantViewer.lastStatus?.paused && plantViewer.lastFrame?.paused), 5000, 50);
  await page.mouse.up();
  await sleep(600);
  const held = await page.evaluate(() => ({ settingDown: !!plantViewer.hand.held?.settingDown, paused: plantViewer.lastFrame?.paused }));
  check(pausedToSet && held.settingDown, `released while the plant is paused, the hand holds it until the plant lowers it (${JSON.stringify(held)})`);
  await page.evaluate(() => plantViewer.send({ type: 'control', action: 'run' }));
  const dropped = await until(() => page.evaluate(() => !plantViewer.hand.held), 5000, 50);
  check(dropped, 'released, the hand sets it down and lets go');
  await sleep(1500);
  const after = await page.evaluate((id) => ({ p: plantViewer.bodyPose(id), lost: plantViewer.lastStatus?.counters?.lost }), pick);
  const up = after.p && 1 - 2 * (after.p[3] ** 2 + after.p[4] ** 2);   // the body's z axis, its world z component
  const setDown = check(after.p && Math.abs(after.p[1] - 2.1) < 0.025 && after.p[0] < 4.95 && Math.abs(after.p[2] - 0.04) < 0.01 && up > 0.95,
    `set down on B8, upright, carried on by it (at ${after.p?.slice(0, 3).map((v) => v.toFixed(3))}, up ${up?.toFixed(3)})`);
  if (!setDown) {   // the session so far, to replay headless (plant run --events FILE --trace-bodies)
    const keep = join(mkdtempSync(join(tmpdir(), 'plant-hand-failed-')), 'session.events');
    writeFileSync(keep, await (await fetch(url + 'events')).text());
    console.log(`     the session's events so far: ${keep}`);
  }
  check(after.lost === 0, `nothing lost (${after.lost})`);
  await page.click('#hand');
  // Pause; the session's events replayed headless to the same step.
  await page.click('#run');
  const paused = await until(() => page.evaluate(() => (plantViewer.lastStatus?.paused && plantViewer.lastFrame?.paused ? plantViewer.lastFrame.step : null)), 5000, 50);
  await sleep(300);
  const pagePoses = await page.evaluate((ids) => ids.map((id) => [plantViewer.bodyState(id), ...plantViewer.bodyPose(id)]), bodies.map((b) => b.id));
  const events = await (await fetch(url + 'events')).text();
  check(/ grab \S+ at /.test(events) && / move \S+ to /.test(events) && / drop /.test(events), `/events holds the grab, the moves and the drop (${events.trim().split('\n').length - 1} lines)`);
  const dir = mkdtempSync(join(tmpdir(), 'plant-hand-'));
  try {
    writeFileSync(join(dir, 'session.events'), events);
    const run = spawnSync(binary, ['run', plantFile, ...serveArgs, '--events', join(dir, 'session.events'), '--for', `${paused / scene.rate}s`,
      '--record', join(dir, 'replay.rec'), '--record-compress', 'none', '--quiet'], { encoding: 'utf8', timeout: 120_000 });
    check(run.status === 0, `plant run --events replays the session (${run.status}: ${run.stderr.trim().slice(-300)})`);
    check(/lost \(left the world\): 0/.test(run.stdout), `the replay's summary counts no loss (${(run.stdout.match(/lost.*$/m) ?? [''])[0]})`);
    const rec = lastPoses(join(dir, 'replay.rec'), bodies.length);
    check(rec.step === paused, `the replay ran to the paused step ${paused} (${rec.step})`);
    let same = 0, differ = 0;
    for (const b of bodies) {
      if (b.mode === 'static') continue;
      const p = pagePoses[b.id];
      const ok = (rec.states[b.id] & 1) === (p[0] & 1) && [...rec.poses.subarray(7 * b.id, 7 * b.id + 7)].every((v, k) => Object.is(v, p[k + 1]));
      if (ok) same++; else differ++;
    }
    check(differ === 0, `the headless replay ends with every body where the page has it, bit for bit (${same} same, ${differ} differ)`);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
  void client;
}

// A page opened 120 s into the run plots from 0 s.
export async function lateHistory({ browser, page, url, check, until }) {
  await page.click('button[data-speed="0"]');
  if (await page.evaluate(() => plantViewer.lastStatus?.paused)) await page.click('#run');
  const t = await until(() => page.evaluate(() => (plantViewer.lastStatus?.time ?? 0) >= 120 && plantViewer.lastStatus.time), 90_000, 200);
  await page.click('button[data-speed="1"]');
  if (!check(!!t, `the run reached 120 s (${t})`)) return;
  const late = await browser.newPage();
  try {
    await late.setViewport({ width: 1200, height: 800 });
    await late.goto(url, { waitUntil: 'load' });
    const plots = await until(() => late.evaluate(() => {
      if (!window.plantViewer?.historiesReceived) return null;
      const p = plantViewer.plots();
      return p.length && p.every((c) => c.last !== null) ? p : null;
    }), 20_000, 200);
    const first = plots?.map((c) => c.first), last = plots?.map((c) => c.last);
    check(!!plots && first.every((x) => x === 0) && last.every((x) => x >= 119),
      `a page opened at ${t.toFixed(1)} s plots every chart from 0 s (${plots?.length} charts, from ${first?.[0]} to ${last?.[0]?.toFixed(1)} s, ${plots?.[0]?.points} points)`);
    const most = plots ? Math.max(...plots.map((c) => c.names.length)) : 99;
    check(most <= 5, `at most five lines a chart (${most})`);
  } finally {
    await late.close();
  }
}

// A second server on a copy of the stdlib without one model, with --models holding a model
// that is not glTF and one of 200 MB: the page says so, names the files, and stays usable.
export async function badModels({ browser, binary, plantFile, check, until, sleep }) {
  const dir = mkdtempSync(join(tmpdir(), 'plant-models-'));
  const stdlib = join(dir, 'stdlib'), mine = join(dir, 'mine');
  let server = null;
  try {
    mkdirSync(join(stdlib, 'models'), { recursive: true });
    mkdirSync(mine);
    for (const f of readdirSync(join(root, 'stdlib'))) if (f.endsWith('.plant')) copyFileSync(join(root, 'stdlib', f), join(stdlib, f));
    for (const f of readdirSync(join(root, 'stdlib', 'models'))) if (f !== 'gate_pin.glb') copyFileSync(join(root, 'stdlib', 'models', f), join(stdlib, 'models', f));
    writeFileSync(join(mine, 'station.glb'), 'a station drawn in a word processor');
    writeFileSync(join(mine, 'switch_blade.glb'), Buffer.from('glTF\x02\x00\x00\x00\x00\x00\x00\x0c', 'latin1'));
    truncateSync(join(mine, 'switch_blade.glb'), 200 * 1024 * 1024);   // sparse: 200 MB unwritten
    server = spawn(binary, ['serve', plantFile, '--port', '0', '--stdlib', stdlib, '--models', mine], { stdio: ['ignore', 'pipe', 'pipe'] });
    let err = '';
    server.stderr.on('data', (d) => { err += d; });
    const url = await new Promise((resolve, reject) => {
      let out = '';
      const timer = setTimeout(() => reject(new Error(`no URL: ${err}`)), 20_000);
      server.stdout.on('data', (d) => { out += d; const m = out.match(/plant serve: (http:\/\/[^\s/]+\/)/); if (m) { clearTimeout(timer); resolve(m[1]); } });
    });
    check(/gate_pin\.glb: 'gate_pin\.glb' was not found/.test(err) && /station\.glb: .*not a glTF binary/.test(err) && /switch_blade\.glb: .*more than a model may be/.test(err),
      `the server logs the missing and refused models once (${err.trim().split('\n').length} lines)`);
    const page = await browser.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(e.message));
    try {
      await page.setViewport({ width: 1200, height: 800 });
      await page.goto(url, { waitUntil: 'load' });
      await page.waitForFunction(() => window.plantViewer?.sceneReady && plantViewer.framesReceived >= 3, { timeout: 30_000 });
      const notices = await until(() => page.evaluate(() => (plantViewer.notices().length >= 4 ? plantViewer.notices() : null)), 10_000, 100);
      const text = (notices ?? []).join('\n');
      check(/gate_pin\.glb.*was not found/.test(text) && /station\.glb.*not a glTF binary/.test(text) && /switch_blade\.glb.*MB, more than a model may be/.test(text),
        `the page names the missing and refused models: ${(notices ?? []).slice(1).join(' | ')}`);
      const visible = await page.evaluate(() => !document.getElementById('notices').hidden);
      check(visible, 'the notice is shown');
      // Still usable: frames come, the rest of the models load, a click inspects a switch.
      const n0 = await page.evaluate(() => plantViewer.framesReceived);
      await sleep(800);
      const states = await until(() => page.evaluate(() => { const s = plantViewer.modelStates(); return Object.values(s).every((x) => x !== 'loading') ? s : null; }), 20_000, 200);
      const n1 = await page.evaluate(() => plantViewer.framesReceived);
      check(n1 > n0 && states && Object.values(states).every((s) => s === 'loaded'), `the page goes on: frames (${n1 - n0} more), the other ${Object.keys(states ?? {}).length} models loaded`);
      const selected = await page.evaluate(() => plantViewer.select('line[0].s2.sw') && plantViewer.inspectedPath());
      check(selected === 'line[0].s2.sw' && errors.length === 0, `the inspector still opens, no error on the page${errors.length ? ': ' + errors.join(' | ') : ''}`);
    } finally {
      await page.close();
    }
  } finally {
    if (server && server.exitCode === null) server.kill('SIGTERM');
    await sleep(200);
    rmSync(dir, { recursive: true, force: true });
  }
}

// A bottle lost on purpose (a hand carries it off the line, over the empty middle of the
// loop, and lets go: it falls out of the world): the page marks where it was lost, with a
// label that names it, from the status's `lost` list.
export async function lostMarked({ page, scene, check, until, sleep, elapsed }) {
  const isBottle = (b) => b.mode === 'dynamic' && b.path.endsWith('.main');
  if (await page.evaluate(() => plantViewer.lastStatus?.paused)) await page.click('#run');
  const pick = await until(() => page.evaluate((ids) => {
    for (const id of ids) {
      const p = plantViewer.bodyPose(id);
      // On the right side of the loop, past the arm: no station or gripper holds a bottle
      // there (a held one is not free to take, and the hand would be refused).
      if ((plantViewer.bodyState(id) & 1) && p[0] > 5.2 && p[1] > 0.6 && p[1] < 1.5 && p[2] < 0.05 && p[2] > 0.02) return { id, p: p.slice(0, 3) };
    }
    return null;
  }, scene.bodies.filter(isBottle).map((b) => b.id)), 30_000, 50);
  if (!check(pick !== null, `a bottle on a belt to lose (${elapsed()})`)) return;
  const path = scene.bodies.find((b) => b.id === pick.id).path;
  const lostBefore = await page.evaluate(() => plantViewer.lastStatus?.counters?.lost ?? 0);
  await page.evaluate((path, p) => plantViewer.send({ type: 'hand', action: 'grab', path, point: p }), path, pick.p);
  // Lifted, then over the middle of the loop (nothing below it there), then let go.
  const over = [3.0, 1.2, pick.p[2] + 0.3];
  for (let i = 1; i <= 10; i++) {
    const t = i / 10;
    await page.evaluate((path, q) => plantViewer.send({ type: 'hand', action: 'move', path, point: q }), path,
      [pick.p[0] + (over[0] - pick.p[0]) * t, pick.p[1] + (over[1] - pick.p[1]) * t, over[2]]);
    await sleep(150);
  }
  // The hand follows at a bounded speed (1 m/s): let go only once the bottle is over the
  // middle of the loop. The hand holds the point it took, where the page last drew the
  // bottle: the belt has carried the bottle on by the time the grab arrives, so its origin
  // hangs a few centimetres from the target (nothing lies within 0.2 m of it).
  const above = await until(() => page.evaluate((id, q) => {
    const p = plantViewer.bodyPose(id);
    return Math.hypot(p[0] - q[0], p[1] - q[1]) < 0.2 ? p.slice(0, 3) : null;
  }, pick.id, over), 15_000, 50);
  const at = await page.evaluate((id) => plantViewer.bodyPose(id).slice(0, 3), pick.id);
  if (!check(above !== null, `the hand carries ${path} over the middle of the loop (at ${at.map((v) => v.toFixed(2))}, ${elapsed()})`)) return;
  await page.evaluate((path) => plantViewer.send({ type: 'hand', action: 'drop', path }), path);
  const lost = await until(() => page.evaluate((n) => ((plantViewer.lastStatus?.counters?.lost ?? 0) > n ? plantViewer.lost() : null), lostBefore), 30_000, 100);
  if (!check(lost !== null, `the bottle let go over nothing is counted lost (${elapsed()})`)) return;
  const object = path.slice(0, path.lastIndexOf('.'));
  const name = object.slice(object.lastIndexOf('.') + 1);
  const mark = lost.find((m) => object.endsWith(m.path) || m.path === object);
  check(!!mark && mark.text.includes(`${name} lost`) && mark.place.every(Number.isFinite),
    `a marker where ${object} was lost, labelled '${mark?.text}' at ${mark?.place?.map((v) => v.toFixed(2))}`);
  await page.evaluate(() => plantViewer.view.fit());   // the whole plant in view: the marker's label drawn
  await sleep(500);
  const shown = await page.evaluate(() => [...document.querySelectorAll('.label.lost')].filter((e) => e.style.display !== 'none' && e.getClientRects().length > 0).length);
  check(shown >= 1, `the lost marker's label is on the page (${shown})`);
}
