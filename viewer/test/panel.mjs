// Browser test of the operator panel (docs/viewer.md, "Operator panels"; issue #32):
//
//   node --experimental-websocket viewer/test/panel.mjs PLANT_BINARY PLANT_FILE SCREENSHOT.png
//
// Starts `PLANT_BINARY serve PLANT_FILE --port 0` (the bottling plant, whose line has a
// panel `ops`), opens the page in Debian's Chromium headless (puppeteer-core) and checks:
// the page draws the panel's elements; pressing Stop on the page (mouse down, mouse up on
// the drawn button) reaches the runtime as the events `…ops.stop.press` / `…ops.stop.release`
// (seen by a protocol client of our own), the running lamp goes out on the page and in the
// status, and the feed stops: no bottle is issued for 12 s of plant time; Start lights the
// lamp again and the feed resumes. The same panel is placed in the scene: a board (drawn by
// a few instanced meshes) whose Stop, Start, emergency stop, reset key and selector, clicked
// in the 3D view, send the same events (the camera stays where it was), and whose lamp and
// display follow the status. Writes screenshots of the panel (SCREENSHOT.png) and of the board
// in the scene (SCREENSHOT-scene.png). Bounded in time; exit 1 on any failed check.
import { statSync } from 'node:fs';
import { Harness, sleep, until } from './harness.mjs';

const [binary, plantFile, screenshot] = process.argv.slice(2);
if (!binary || !plantFile || !screenshot) {
  console.error('usage: node --experimental-websocket panel.mjs PLANT_BINARY PLANT_FILE SCREENSHOT.png');
  process.exit(2);
}
const h = new Harness('panel', 150_000);
const check = (ok, what) => h.check(ok, what);

try {
  const { base: url } = await h.startServer(binary, [plantFile]);
  const client = await h.connect(url);
  const panels = client.scene.panels ?? [];
  check(panels.length === 1, `the scene lists one panel (${panels.map((p) => p.path).join(', ')})`);
  const ops = panels[0];
  const index = (name) => ops.elements.findIndex((e) => e.name === name);
  const stop = ops.elements[index('stop')], start = ops.elements[index('start')];
  const lamp = index('running');
  check(stop && start && lamp >= 0, `the panel has start, stop and a running lamp (${ops.elements.map((e) => `${e.kind} ${e.name}`).join(', ')})`);

  await h.launch();
  const page = await h.open(url);
  const pageErrors = page.errors;
  await page.waitForFunction(() => window.plantViewer?.sceneReady && window.plantViewer.statusReceived >= 2, { timeout: 30_000 });

  const drawn = await page.evaluate(() => [...document.querySelectorAll('.op-panel [data-element]')].map((e) => e.dataset.kind));
  check(drawn.length === ops.elements.length, `the page draws the panel's ${ops.elements.length} elements (${drawn.join(', ')})`);
  const lampOn = () => page.evaluate((p) => document.querySelector(`[data-element="${p}"]`)?.classList.contains('on'), ops.elements[lamp].path);
  check(await until(lampOn, 15_000), 'the running lamp is lit on the page');
  check(client.status?.panel?.[lamp] === 1, `status: the running lamp reads 1 (${client.status?.panel?.[lamp]})`);

  // As fast as the machine goes, until the first bottle is issued: the feed runs.
  await page.click('button[data-speed="0"]');
  const issued = () => client.status?.counters?.issued ?? 0;
  check(await until(() => issued() >= 2, 30_000), `bottles are issued before Stop (${issued()})`);

  // Press Stop on the page: mouse down, a moment held, mouse up.
  const box = await (await page.$(`[data-element="${stop.path}"]`)).boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  const down = await until(() => page.evaluate((p) => document.querySelector(`[data-element="${p}"]`).classList.contains('down'), stop.path), 15_000);
  check(down, 'the Stop button is drawn down while held (from the status)');
  await page.mouse.up();
  check(await until(() => client.events.some((l) => l.endsWith(`${stop.path}.press`)), 15_000),
    `the press reached the runtime as an event (${client.events.find((l) => l.includes('.stop.')) ?? 'none'})`);
  check(await until(() => client.events.some((l) => l.endsWith(`${stop.path}.release`)), 15_000), 'and the release');
  check(await until(async () => !(await lampOn()), 15_000), 'the running lamp goes out on the page');
  check(await until(() => client.status?.panel?.[lamp] === 0, 15_000), 'status: the running lamp reads 0');

  // The feed holds: nothing is issued for 12 s of plant time.
  const t0 = client.status.time, n0 = issued();
  await until(() => client.status.time > t0 + 12, 60_000);
  check(client.status.time > t0 + 12 && issued() === n0, `no bottle issued from ${t0.toFixed(1)} s to ${client.status.time.toFixed(1)} s after Stop (${n0} -> ${issued()})`);

  // Start again: the lamp lights and the feed resumes.
  const sbox = await (await page.$(`[data-element="${start.path}"]`)).boundingBox();
  await page.mouse.click(sbox.x + sbox.width / 2, sbox.y + sbox.height / 2, { delay: 80 });
  check(await until(lampOn, 15_000), 'Start lights the running lamp again');
  check(await until(() => issued() > n0, 30_000), `the feed resumes after Start (${issued()} issued)`);

  await page.click('button[data-speed="1"]');
  await sleep(500);
  await (await page.$('.op-panel')).screenshot({ path: screenshot });
  check(statSync(screenshot).size > 2_000, `screenshot of the panel written: ${screenshot}`);

  // ---- the same panel placed in the scene (docs/viewer.md): a board worked by clicks ----
  check(Array.isArray(ops.pose) && ops.pose.length === 7, `the scene places the panel (pose ${JSON.stringify(ops.pose)})`);
  const placed = () => page.evaluate(() => plantViewer.scenePanels.summary());
  const inScene = await placed();
  check(inScene.length === ops.elements.length && inScene.map((e) => e.kind).join() === ops.elements.map((e) => e.kind).join(),
    `the board has the panel's ${ops.elements.length} elements (${inScene.map((e) => e.kind).join(', ')})`);
  await page.evaluate((p) => plantViewer.scenePanels.lookAt(p, 0.75), ops.path);
  await sleep(300);
  const countAt = index('count');
  check(await until(async () => (await placed())[countAt]?.text === String(Math.round(client.status?.panel?.[countAt] ?? -1)), 15_000),
    `the board's display shows the count (${(await placed())[countAt]?.text} / ${client.status?.panel?.[countAt]})`);
  const meshes = await page.evaluate(() => plantViewer.scenePanels.meshes());
  check(meshes <= 5, `every board is drawn by at most 5 instanced meshes (${meshes})`);
  const lit3d = async () => (await placed())[lamp]?.lit === true;
  check(await until(lit3d, 15_000), 'the running lamp is lit on the board');
  const camera = () => page.evaluate(() => plantViewer.view.camera.position.toArray().map((x) => x.toFixed(6)).join());
  const cam0 = await camera();
  const at = await page.evaluate((p) => plantViewer.scenePanels.screenPoint(p), stop.path);
  const events0 = client.events.length;
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  check(await until(async () => (await placed())[index('stop')]?.down === true, 15_000), 'Stop clicked on the board is drawn down while held (from the status)');
  await sleep(200);
  await page.mouse.up();
  const sent = () => client.events.slice(events0);
  check(await until(() => sent().some((l) => l.endsWith(`${stop.path}.press`)) && sent().some((l) => l.endsWith(`${stop.path}.release`)), 15_000),
    `the board's Stop reached the runtime as the same events (${sent().filter((l) => l.includes('.stop.')).join('; ') || 'none'})`);
  check(await until(async () => !(await lit3d()), 15_000), 'the running lamp goes out on the board');
  check(await until(async () => !(await lampOn()), 15_000), 'and on the 2D panel');
  check(await camera() === cam0, 'the click on the board did not move the camera');
  check(await page.evaluate(() => document.getElementById('inspector')?.hidden !== false), 'nor select anything behind it');
  const at2 = await page.evaluate((p) => plantViewer.scenePanels.screenPoint(p), start.path);
  await page.mouse.click(at2.x, at2.y, { delay: 80 });
  check(await until(lit3d, 15_000), 'Start clicked on the board lights the running lamp again');
  // The mushroom latches, the key resets it; a click on the knob turns it to the next position.
  const halt = index('halt'), mode = index('mode');
  const clickAt = async (path, key = false) => {
    const pt = await page.evaluate((p, k) => plantViewer.scenePanels.screenPoint(p, k), path, key);
    await page.mouse.click(pt.x, pt.y, { delay: 60 });
  };
  await clickAt(ops.elements[halt].path);
  check(await until(() => client.status?.panel?.[halt] === 1, 15_000), 'the board\'s emergency stop latches');
  await clickAt(ops.elements[halt].path, true);
  check(await until(() => client.status?.panel?.[halt] === 0, 15_000), 'its reset key releases it');
  const mode0 = client.status?.panel?.[mode];
  await clickAt(ops.elements[mode].path);
  check(await until(() => client.status?.panel?.[mode] === (mode0 + 1) % 2, 15_000), `the board's selector turns (${mode0} -> ${client.status?.panel?.[mode]})`);
  // The knob's next position is the board's, which follows the plant's status: wait for it
  // (under the sanitizers the status can come after the protocol client's).
  check(await until(async () => (await placed())[mode]?.position === (mode0 + 1) % 2, 15_000), 'the board shows the new position');
  await clickAt(ops.elements[mode].path);
  check(await until(() => client.status?.panel?.[mode] === mode0, 15_000), 'and back');
  await clickAt(start.path);
  check(await until(lit3d, 15_000), 'Start after the reset lights the running lamp again');
  const sceneShot = screenshot.replace(/\.png$/, '-scene.png');
  // The board in its place in the line, the 2D panel over the view out of the way.
  await page.evaluate((p) => { plantViewer.scenePanels.lookAt(p, 1.5, 0.45, 0.35); document.getElementById('op-panels').hidden = true; }, ops.path);
  await sleep(500);
  await (await page.$('#view')).screenshot({ path: sceneShot });
  await page.evaluate(() => { document.getElementById('op-panels').hidden = false; });
  check(statSync(sceneShot).size > 2_000, `screenshot of the board in the scene written: ${sceneShot}`);
  check(pageErrors.length === 0, `no errors on the page${pageErrors.length ? ': ' + pageErrors.join(' | ') : ''}`);
} catch (e) {
  console.error(`FAIL ${e.message}`);
  h.failures++;
}
await h.done();
