// What the browser tests of `plant serve` share (browser.mjs, panel.mjs, training.mjs): the
// server started on a free port, a protocol client of our own (the runtime's state, apart
// from the page), Debian's Chromium started headless with puppeteer-core, checks, bounded
// waits, and a clean end (every process the test started is stopped, its profile removed).
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import puppeteer from 'puppeteer-core';

export function sleep(ms) { return new Promise((r) => setTimeout(r, ms)); }

// Polls `f` until it returns a truthy value or `ms` pass; returns its last value.
export async function until(f, ms, step = 100) {
  const end = Date.now() + ms;
  for (;;) {
    const v = await f();
    if (v || Date.now() > end) return v;
    await sleep(step);
  }
}

// One test run: its checks, the processes it started, and its end after `overallMs` at most.
export class Harness {
  constructor(name, overallMs) {
    this.name = name;
    this.started = Date.now();
    this.failures = 0;
    this.server = null;
    this.browser = null;
    this.clients = [];
    this.profile = null;
    this.serverOut = '';
    this.serverErr = '';
    this.overall = setTimeout(async () => {
      console.error(`FAIL the test took longer than ${overallMs / 1000} s`);
      await this.finish(1);
    }, overallMs);
  }

  elapsed() { return `${((Date.now() - this.started) / 1000).toFixed(1)}s`; }

  check(ok, what) {
    console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}  [${this.elapsed()}]`);
    if (!ok) this.failures++;
    return ok;
  }

  // Starts `binary serve ...args --port 0`; resolves to the printed URLs: { base, instructor, trainee }
  // (instructor and trainee are absent with --open / --no-roles).
  startServer(binary, args) {
    return new Promise((resolve, reject) => {
      this.server = spawn(binary, ['serve', ...args, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
      const timer = setTimeout(() => reject(new Error(`no URL from the server in 20 s; stdout: ${this.serverOut} stderr: ${this.serverErr}`)), 20_000);
      this.server.stdout.on('data', (d) => {
        this.serverOut += d;
        const base = this.serverOut.match(/plant serve: (https?:\/\/[^\s/]+\/)\n/);
        const instructor = this.serverOut.match(/plant serve: instructor: (\S+)\n/);
        const trainee = this.serverOut.match(/plant serve: trainees: (\S+)\n/);
        const open = /plant serve: open:/.test(this.serverOut);
        if (base && ((instructor && trainee) || open)) {
          clearTimeout(timer);
          resolve({ base: base[1], instructor: instructor?.[1], trainee: trainee?.[1] });
        }
      });
      this.server.stderr.on('data', (d) => { this.serverErr += d; if (this.serverErr.length > 20000) this.serverErr = this.serverErr.slice(-10000); });
      this.server.on('exit', (code, sig) => { clearTimeout(timer); reject(new Error(`the server exited (${code ?? sig}): ${this.serverErr}`)); });
      this.server.on('error', (e) => { clearTimeout(timer); reject(e); });
    });
  }

  // A protocol client of our own on `url`'s WebSocket (its ?token= or ?role= kept): the
  // scene, the last status, the event lines, the frames counted, errors.
  connect(url, fps = 5) {
    return new Promise((resolve, reject) => {
      const u = new URL(url);
      const ws = new WebSocket(`${u.protocol === 'https:' ? 'wss' : 'ws'}://${u.host}/ws${u.search}`);
      ws.binaryType = 'arraybuffer';
      const state = { ws, scene: null, status: null, welcome: null, events: [], errors: [], frames: 0, close: () => ws.close() };
      this.clients.push(state);
      const timer = setTimeout(() => reject(new Error('no scene on our own connection in 10 s')), 10_000);
      ws.onmessage = (e) => {
        if (typeof e.data !== 'string') { state.frames++; return; }
        const m = JSON.parse(e.data);
        if (m.type === 'scene') { state.scene = m; clearTimeout(timer); resolve(state); }
        else if (m.type === 'welcome') state.welcome = m;
        else if (m.type === 'status') state.status = m;
        else if (m.type === 'event') state.events.push(m.line);
        else if (m.type === 'error') state.errors.push(m.message);
      };
      ws.onopen = () => ws.send(JSON.stringify({ type: 'hello', fps }));
      ws.onerror = () => { clearTimeout(timer); reject(new Error('our WebSocket failed')); };
      state.send = (m) => ws.send(JSON.stringify(m));
    });
  }

  // Debian's Chromium, headless, with a fresh profile ($CHROMIUM overrides the path).
  async launch(width = 1400, height = 900) {
    this.profile = mkdtempSync(join(tmpdir(), `plant-${this.name}-chromium-`));
    this.browser = await puppeteer.launch({
      executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
      headless: true,
      protocolTimeout: 30_000,
      args: ['--headless=new', '--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader',
        '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync',
        '--disable-dev-shm-usage', `--user-data-dir=${this.profile}`, `--window-size=${width},${height}`,
        // Two pages at once (an instructor's and a trainee's): neither is throttled as a background tab.
        '--disable-background-timer-throttling', '--disable-renderer-backgrounding', '--disable-backgrounding-occluded-windows'],
    });
    return this.browser;
  }

  // A new page of the browser at `url`, its errors gathered in page.errors.
  async open(url, width = 1400, height = 900) {
    const page = await this.browser.newPage();
    page.setDefaultTimeout(30_000);
    await page.setViewport({ width, height });
    page.errors = [];
    page.on('pageerror', (e) => page.errors.push(e.message));
    page.on('console', (m) => { if (m.type() === 'error' && !/favicon/.test(m.text())) page.errors.push(m.text()); });
    await page.goto(url, { waitUntil: 'load' });
    return page;
  }

  async cleanup() {
    for (const c of this.clients) try { c.close(); } catch { /* closing anyway */ }
    if (this.browser) await Promise.race([this.browser.close().catch(() => {}), sleep(5000)]);
    if (this.browser?.process() && this.browser.process().exitCode === null) this.browser.process().kill('SIGKILL');
    if (this.server && this.server.exitCode === null) {
      this.server.kill('SIGTERM');
      await Promise.race([new Promise((r) => this.server.once('exit', r)), sleep(3000)]);
      if (this.server.exitCode === null && this.server.signalCode === null) this.server.kill('SIGKILL');
    }
    if (this.profile) try { rmSync(this.profile, { recursive: true, force: true, maxRetries: 3 }); } catch { /* a temporary folder */ }
  }

  async finish(code) {
    clearTimeout(this.overall);
    await this.cleanup();
    process.exit(code);
  }

  // The end of a test: passed or failed, with its wall time.
  async done() {
    console.log(`${this.failures ? 'FAILED' : 'passed'} in ${this.elapsed()}`);
    await this.finish(this.failures ? 1 : 0);
  }
}
