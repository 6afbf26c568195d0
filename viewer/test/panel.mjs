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
// lamp again and the feed resumes. Writes a screenshot of the panel (docs/images/panel.png
// with --docs). Bounded in time; exit 1 on any failed check.
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import puppeteer from 'puppeteer-core';

const [binary, plantFile, screenshot] = process.argv.slice(2);
if (!binary || !plantFile || !screenshot) {
  console.error('usage: node --experimental-websocket panel.mjs PLANT_BINARY PLANT_FILE SCREENSHOT.png');
  process.exit(2);
}
const OVERALL_MS = 150_000;
const started = Date.now();
const elapsed = () => `${((Date.now() - started) / 1000).toFixed(1)}s`;
let server = null, browser = null, client = null, profile = null, failures = 0;

function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures++;
  return ok;
}
function sleep(ms) { return new Promise((r) => setTimeout(r, ms)); }
async function until(f, ms, step = 100) {
  const end = Date.now() + ms;
  for (;;) {
    const v = await f();
    if (v || Date.now() > end) return v;
    await sleep(step);
  }
}
async function finish(code) {
  try { client?.close(); } catch { /* closing anyway */ }
  if (browser) await Promise.race([browser.close().catch(() => {}), sleep(5000)]);
  if (browser?.process() && browser.process().exitCode === null) browser.process().kill('SIGKILL');
  if (server && server.exitCode === null) {
    server.kill('SIGTERM');
    await Promise.race([new Promise((r) => server.once('exit', r)), sleep(3000)]);
    if (server.exitCode === null && server.signalCode === null) server.kill('SIGKILL');
  }
  if (profile) try { rmSync(profile, { recursive: true, force: true, maxRetries: 3 }); } catch { /* a temporary folder */ }
  process.exit(code);
}
const overall = setTimeout(async () => { console.error(`FAIL the test took longer than ${OVERALL_MS / 1000} s`); await finish(1); }, OVERALL_MS);

function startServer() {
  return new Promise((resolve, reject) => {
    server = spawn(binary, ['serve', plantFile, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '', err = '';
    const timer = setTimeout(() => reject(new Error(`no URL from the server in 20 s; stderr: ${err}`)), 20_000);
    server.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/plant serve: (http:\/\/[^\s/]+\/)/);
      if (m) { clearTimeout(timer); resolve(m[1]); }
    });
    server.stderr.on('data', (d) => { err += d; if (err.length > 20000) err = err.slice(-10000); });
    server.on('exit', (code, sig) => { clearTimeout(timer); reject(new Error(`the server exited (${code ?? sig}): ${err}`)); });
  });
}

// Our own protocol client: the runtime's state, independent of the page.
function connect(url) {
  return new Promise((resolve, reject) => {
    const ws = new WebSocket(url.replace(/^http/, 'ws') + 'ws');
    ws.binaryType = 'arraybuffer';
    const state = { scene: null, status: null, events: [], close: () => ws.close() };
    const timer = setTimeout(() => reject(new Error('no scene on our own connection in 10 s')), 10_000);
    ws.onmessage = (e) => {
      if (typeof e.data !== 'string') return;
      const m = JSON.parse(e.data);
      if (m.type === 'scene') { state.scene = m; clearTimeout(timer); resolve(state); }
      else if (m.type === 'status') state.status = m;
      else if (m.type === 'event') state.events.push(m.line);
    };
    ws.onopen = () => ws.send(JSON.stringify({ type: 'hello', fps: 5 }));
    ws.onerror = () => { clearTimeout(timer); reject(new Error('our WebSocket failed')); };
    state.send = (m) => ws.send(JSON.stringify(m));
  });
}

try {
  const url = await startServer();
  client = await connect(url);
  const panels = client.scene.panels ?? [];
  check(panels.length === 1, `the scene lists one panel (${panels.map((p) => p.path).join(', ')})`);
  const ops = panels[0];
  const index = (name) => ops.elements.findIndex((e) => e.name === name);
  const stop = ops.elements[index('stop')], start = ops.elements[index('start')];
  const lamp = index('running');
  check(stop && start && lamp >= 0, `the panel has start, stop and a running lamp (${ops.elements.map((e) => `${e.kind} ${e.name}`).join(', ')})`);

  profile = mkdtempSync(join(tmpdir(), 'plant-panel-chromium-'));
  browser = await puppeteer.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    headless: true,
    protocolTimeout: 30_000,
    args: ['--headless=new', '--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync', '--disable-dev-shm-usage',
      `--user-data-dir=${profile}`, '--window-size=1400,900'],
  });
  const page = await browser.newPage();
  page.setDefaultTimeout(30_000);
  await page.setViewport({ width: 1400, height: 900 });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error' && !/favicon/.test(m.text())) pageErrors.push(m.text()); });
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.plantViewer?.sceneReady && window.plantViewer.statusReceived >= 2, { timeout: 30_000 });

  const drawn = await page.evaluate(() => [...document.querySelectorAll('.op-panel [data-element]')].map((e) => e.dataset.kind));
  check(drawn.length === ops.elements.length, `the page draws the panel's ${ops.elements.length} elements (${drawn.join(', ')})`);
  const lampOn = () => page.evaluate((p) => document.querySelector(`[data-element="${p}"]`)?.classList.contains('on'), ops.elements[lamp].path);
  check(await until(lampOn, 5000), 'the running lamp is lit on the page');
  check(client.status?.panel?.[lamp] === 1, `status: the running lamp reads 1 (${client.status?.panel?.[lamp]})`);

  // As fast as the machine goes, until the first bottle is issued: the feed runs.
  await page.click('button[data-speed="0"]');
  const issued = () => client.status?.counters?.issued ?? 0;
  check(await until(() => issued() >= 2, 30_000), `bottles are issued before Stop (${issued()})`);

  // Press Stop on the page: mouse down, a moment held, mouse up.
  const box = await (await page.$(`[data-element="${stop.path}"]`)).boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.down();
  const down = await until(() => page.evaluate((p) => document.querySelector(`[data-element="${p}"]`).classList.contains('down'), stop.path), 5000);
  check(down, 'the Stop button is drawn down while held (from the status)');
  await page.mouse.up();
  check(await until(() => client.events.some((l) => l.endsWith(`${stop.path}.press`)), 5000),
    `the press reached the runtime as an event (${client.events.find((l) => l.includes('.stop.')) ?? 'none'})`);
  check(await until(() => client.events.some((l) => l.endsWith(`${stop.path}.release`)), 5000), 'and the release');
  check(await until(async () => !(await lampOn()), 5000), 'the running lamp goes out on the page');
  check(await until(() => client.status?.panel?.[lamp] === 0, 5000), 'status: the running lamp reads 0');

  // The feed holds: nothing is issued for 12 s of plant time.
  const t0 = client.status.time, n0 = issued();
  await until(() => client.status.time > t0 + 12, 60_000);
  check(client.status.time > t0 + 12 && issued() === n0, `no bottle issued from ${t0.toFixed(1)} s to ${client.status.time.toFixed(1)} s after Stop (${n0} -> ${issued()})`);

  // Start again: the lamp lights and the feed resumes.
  const sbox = await (await page.$(`[data-element="${start.path}"]`)).boundingBox();
  await page.mouse.click(sbox.x + sbox.width / 2, sbox.y + sbox.height / 2, { delay: 80 });
  check(await until(lampOn, 5000), 'Start lights the running lamp again');
  check(await until(() => issued() > n0, 30_000), `the feed resumes after Start (${issued()} issued)`);

  await page.click('button[data-speed="1"]');
  await sleep(500);
  await (await page.$('.op-panel')).screenshot({ path: screenshot });
  check(statSync(screenshot).size > 2_000, `screenshot of the panel written: ${screenshot}`);
  check(pageErrors.length === 0, `no errors on the page${pageErrors.length ? ': ' + pageErrors.join(' | ') : ''}`);
} catch (e) {
  console.error(`FAIL ${e.message}`);
  failures++;
}
clearTimeout(overall);
console.log(`${failures ? 'FAILED' : 'passed'} in ${elapsed()}`);
await finish(failures ? 1 : 0);
