// A minimal LSP client for the scripted conversations: starts `plant lsp` as a child
// process, frames messages (Content-Length), and waits for answers. Every message the
// server writes must be framed JSON; anything else on stdout fails the test.
import { spawn } from 'node:child_process';
import { readFileSync, realpathSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

// A file of the repository as the tests use it: its URI, text and lines.
export function readDoc(repo, rel) {
  const file = realpathSync(path.join(repo, rel));
  const text = readFileSync(file, 'utf8');
  return { uri: pathToFileURL(file).href, text, lines: text.split('\n') };
}

// Whether the Location[] `got` holds exactly the ranges `want` ({uri, line, character, end}), in any order.
const key = (l) => `${l.uri}:${l.line ?? l.range.start.line}:${l.character ?? l.range.start.character}:${l.end ?? l.range.end.character}`;
export const sameLocations = (got, want) => JSON.stringify((got ?? []).map(key).sort()) === JSON.stringify(want.map(key).sort());

let failures = 0;
export function check(ok, what, detail) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${ok ? '' : ': ' + JSON.stringify(detail)}`);
  if (!ok) failures++;
}

export function start(plant, repo) {
  const child = spawn(plant, ['lsp', '--stdlib', path.join(repo, 'stdlib')], { stdio: ['pipe', 'pipe', 'inherit'] });
  let buffer = Buffer.alloc(0);
  const messages = [];
  let waiters = [];
  child.stdout.on('data', (chunk) => {
    buffer = Buffer.concat([buffer, chunk]);
    for (;;) {
      const head = buffer.indexOf('\r\n\r\n');
      if (head < 0) return;
      const header = buffer.subarray(0, head).toString();
      const m = /^Content-Length: (\d+)$/m.exec(header);
      if (!m) { check(false, 'every message has a Content-Length header', header); process.exit(1); }
      const length = Number(m[1]);
      if (buffer.length < head + 4 + length) return;
      const body = buffer.subarray(head + 4, head + 4 + length).toString();
      buffer = buffer.subarray(head + 4 + length);
      messages.push(JSON.parse(body));  // anything but JSON on stdout fails here
      waiters.forEach((w) => w());
    }
  });

  // A message object, a string, or a Buffer (raw bytes, e.g. ones that are not UTF-8).
  function send(msg) {
    const body = Buffer.isBuffer(msg) ? msg
      : Buffer.from(typeof msg === 'string' ? msg : JSON.stringify({ jsonrpc: '2.0', ...msg }));
    child.stdin.write(Buffer.concat([Buffer.from(`Content-Length: ${body.length}\r\n\r\n`), body]));
  }
  // Waits (at most 20 s) for the first unread message that `pred` accepts.
  function next(pred) {
    return new Promise((resolve, reject) => {
      const timer = setTimeout(() => reject(new Error('timed out waiting for a message')), 20000);
      const look = () => {
        const i = messages.findIndex(pred);
        if (i < 0) return;
        const [m] = messages.splice(i, 1);
        clearTimeout(timer);
        waiters = waiters.filter((w) => w !== look);
        resolve(m);
      };
      waiters.push(look);
      look();
    });
  }
  let nextId = 1;
  async function request(method, params) {
    const id = nextId++;
    send({ id, method, params });
    return next((m) => m.id === id);
  }
  const diagnosticsFor = (u) => next((m) => m.method === 'textDocument/publishDiagnostics' && m.params.uri === u);
  // shutdown, exit, and the exit code.
  async function stop() {
    const down = await request('shutdown', null);
    check(down.result === null, 'shutdown', down);
    send({ method: 'exit' });
    return new Promise((resolve) => child.on('exit', resolve));
  }
  return { child, send, next, request, diagnosticsFor, stop };
}

// Holds a conversation: `body` talks to the server, then shutdown and exit (exit code 0).
// The process exits 1 when any check failed or the conversation broke off.
export async function converse(client, body) {
  try {
    await body();
    const code = await client.stop();
    check(code === 0, 'exit code 0 after shutdown', code);
  } catch (e) {
    check(false, 'conversation', String(e));
    client.child.kill();
  }
  process.exit(failures ? 1 : 0);
}
