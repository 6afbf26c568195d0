// Benchmark row: `plant lsp` re-checking the bottling plant (its whole import closure)
// after a one-character edit, from didChange to publishDiagnostics; prints the median of
// N edits (issue 16's target: <= 50 ms). Usage: node bench/lsp_recheck.mjs PLANT [N]
import { spawn } from 'node:child_process';
import { readFileSync, realpathSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL, fileURLToPath } from 'node:url';

const repo = path.join(path.dirname(fileURLToPath(import.meta.url)), '..');
const plant = process.argv[2];
const n = Number(process.argv[3] ?? 21);
const file = realpathSync(path.join(repo, 'plants/bottling.plant'));
const uri = pathToFileURL(file).href;
const text = readFileSync(file, 'utf8');
const child = spawn(plant, ['lsp', '--stdlib', path.join(repo, 'stdlib')], { stdio: ['pipe', 'pipe', 'inherit'] });
let buf = Buffer.alloc(0);
let onDiag = null;
child.stdout.on('data', (c) => {
  buf = Buffer.concat([buf, c]);
  for (;;) {
    const h = buf.indexOf('\r\n\r\n');
    if (h < 0) return;
    const len = Number(/Content-Length: (\d+)/.exec(buf.subarray(0, h).toString())[1]);
    if (buf.length < h + 4 + len) return;
    const msg = JSON.parse(buf.subarray(h + 4, h + 4 + len).toString());
    buf = buf.subarray(h + 4 + len);
    if (msg.method === 'textDocument/publishDiagnostics' && msg.params.uri === uri && onDiag) onDiag();
  }
});
const send = (m) => { const b = JSON.stringify({ jsonrpc: '2.0', ...m }); child.stdin.write(`Content-Length: ${Buffer.byteLength(b)}\r\n\r\n${b}`); };
const diag = () => new Promise((r) => { onDiag = r; });
send({ id: 1, method: 'initialize', params: { capabilities: {} } });
let w = diag();
send({ method: 'textDocument/didOpen', params: { textDocument: { uri, languageId: 'plant', version: 1, text } } });
await w;
const times = [];
for (let i = 0; i < n; i++) {
  // Insert, then delete, a space at the end of the file.
  const lines = text.split('\n').length - 1;
  const change = i % 2 === 0 ? { range: { start: { line: lines, character: 0 }, end: { line: lines, character: 0 } }, text: ' ' }
                             : { range: { start: { line: lines, character: 0 }, end: { line: lines, character: 1 } }, text: '' };
  w = diag();
  const t0 = process.hrtime.bigint();
  send({ method: 'textDocument/didChange', params: { textDocument: { uri, version: i + 2 }, contentChanges: [change] } });
  await w;
  times.push(Number(process.hrtime.bigint() - t0) / 1e6);
}
times.sort((a, b) => a - b);
console.log(`lsp re-check of plants/bottling.plant after a one-character edit: median ${times[n >> 1].toFixed(1)} ms over ${n} edits (min ${times[0].toFixed(1)}, max ${times[n - 1].toFixed(1)})`);
child.kill();
process.exit(0);
