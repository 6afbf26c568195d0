// A scripted conversation with `plant lsp` as a child process (JSON-RPC over stdio):
// open the bottling plant, misspell a slot and get its diagnostic (range and code), fix
// it and get an empty list, hover a belt's `speed`, go from a Switch instance to
// stdlib/switch.plant, complete after `s1.`; format the document (`plant fmt`'s text as
// one edit), and refuse to while it has a syntax error; then bad input: malformed JSON,
// an unknown method, an unknown document, a request without a method or without a
// position, a message that is not an object; the server still answers after them.
// Usage: node conversation.mjs PLANT REPO_DIR
import { spawnSync } from 'node:child_process';
import { readFileSync, realpathSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { check, converse, start } from './client.mjs';

const [plant, repo] = process.argv.slice(2);
const file = realpathSync(path.join(repo, 'plants/bottling.plant'));
const uri = pathToFileURL(file).href;
const text = readFileSync(file, 'utf8');
const lines = text.split('\n');

const client = start(plant, repo);
const { send, next, request, diagnosticsFor } = client;

await converse(client, async () => {
  const init = await request('initialize', { processId: null, rootUri: null, capabilities: {} });
  check(init.result?.capabilities?.textDocumentSync?.change === 2, 'initialize: incremental sync', init);
  send({ method: 'initialized', params: {} });

  send({ method: 'textDocument/didOpen', params: { textDocument: { uri, languageId: 'plant', version: 1, text } } });
  let d = await diagnosticsFor(uri);
  check(d.params.diagnostics.length === 0, 'the bottling plant opens without diagnostics', d.params);

  // Misspell s1.to_working (an incremental edit deleting one character).
  const line = lines.findIndex((l) => l.includes('record s1.to_working'));
  const col = lines[line].indexOf('to_working');
  const g = col + 'to_workin'.length;
  send({ method: 'textDocument/didChange', params: { textDocument: { uri, version: 2 },
    contentChanges: [{ range: { start: { line, character: g }, end: { line, character: g + 1 } }, text: '' }] } });
  d = await diagnosticsFor(uri);
  const diag = d.params.diagnostics[0];
  check(d.params.diagnostics.length === 1, 'one diagnostic for the misspelt slot', d.params.diagnostics);
  check(diag?.code === 'E0101', 'its code is E0101 (no such member)', diag);
  check(diag?.range?.start?.line === line && diag?.range?.start?.character === col &&
        diag?.range?.end?.line === line && diag?.range?.end?.character === col + 'to_workin'.length,
        'its range is the misspelt name', diag?.range);
  check(diag?.severity === 1 && /to_workin/.test(diag?.message), 'an error naming the slot', diag);
  check(/; did you mean 'to_working'\?$/.test(diag?.message ?? ''),
        'the did-you-mean note is in the message (clients that show no related information show it)', diag);
  check(!(diag?.relatedInformation ?? []).some((r) => /did you mean/.test(r.message)),
        'and not again as related information', diag);

  // Fix it (a full-text change) and get an empty list.
  send({ method: 'textDocument/didChange', params: { textDocument: { uri, version: 3 }, contentChanges: [{ text }] } });
  d = await diagnosticsFor(uri);
  check(d.params.diagnostics.length === 0, 'the fix clears the diagnostics', d.params.diagnostics);

  // Hover `speed` in b1: Belt(length = 80 cm, speed = v).
  const bl = lines.findIndex((l) => /^\s*b1:\s+Belt\(/.test(l));
  const hover = await request('textDocument/hover', { textDocument: { uri }, position: { line: bl, character: lines[bl].indexOf('speed') + 2 } });
  const shown = hover.result?.contents?.value ?? '';
  check(/speed: velocity/.test(shown) && /unit: m\/s/.test(shown), "hover on a belt's speed: type and unit", hover);

  // From an instance of Switch to stdlib/switch.plant.
  const sl = lines.findIndex((l) => /^\s*s1:\s+RoutedSwitch\(/.test(l));
  const def = await request('textDocument/definition', { textDocument: { uri }, position: { line: sl, character: lines[sl].indexOf('RoutedSwitch') + 1 } });
  check(def.result?.uri === pathToFileURL(realpathSync(path.join(repo, 'stdlib/switch.plant'))).href,
        'definition of RoutedSwitch (a Switch with its control) is in stdlib/switch.plant', def);

  // Formatting: a buffer out of the canonical layout (the shipped plant is in it) gets one
  // edit over the whole document whose text is what `plant fmt -` prints.
  const messy = text.replace(/^(\s*b1:)\s+/m, '$1 ');
  send({ method: 'textDocument/didChange', params: { textDocument: { uri, version: 4 }, contentChanges: [{ text: messy }] } });
  await diagnosticsFor(uri);
  const fmt = await request('textDocument/formatting', { textDocument: { uri }, options: { tabSize: 2, insertSpaces: true } });
  const want = spawnSync(plant, ['fmt', '-'], { input: messy, encoding: 'utf8' }).stdout;
  const edit = fmt.result?.[0];
  check(messy !== text && fmt.result?.length === 1 && edit.newText === want && want.length > 0 && want !== messy,
        'formatting: one edit with the formatted text', fmt);
  check(want === text, 'formatting gives the shipped layout back', want.length);
  check(edit?.range?.start?.line === 0 && edit?.range?.start?.character === 0 &&
        edit?.range?.end?.line === lines.length - 1 && edit?.range?.end?.character === lines[lines.length - 1].length,
        'the edit replaces the whole document', edit?.range);
  send({ method: 'textDocument/didChange', params: { textDocument: { uri, version: 5 }, contentChanges: [{ text }] } });
  await diagnosticsFor(uri);

  // Complete after `s1.` on a new line at the end of the plant's body (a syntax error while typing).
  const close = lines.lastIndexOf('}');
  send({ method: 'textDocument/didChange', params: { textDocument: { uri, version: 6 },
    contentChanges: [{ range: { start: { line: close, character: 0 }, end: { line: close, character: 0 } }, text: '    flow s1.\n' }] } });
  d = await diagnosticsFor(uri);
  check(d.params.diagnostics.some((x) => x.code === 'E0001'), 'the half-typed line is a syntax error', d.params.diagnostics);
  const comp = await request('textDocument/completion', { textDocument: { uri }, position: { line: close, character: '    flow s1.'.length } });
  const labels = (comp.result ?? []).map((i) => i.label);
  const ports = [...readFileSync(path.join(repo, 'stdlib/switch.plant'), 'utf8').matchAll(/^\s*(?:in|out) (\w+):/gm)].map((m) => m[1]);
  check(ports.length > 0 && ports.every((p) => labels.includes(p)), "completion after s1. lists the switch's ports", { labels, ports });

  const broken = await request('textDocument/formatting', { textDocument: { uri }, options: { tabSize: 4, insertSpaces: true } });
  check(broken.error?.code === -32803 && /syntax errors/.test(broken.error?.message), 'formatting with a syntax error: refused', broken);

  // Bad input: the server answers and carries on.
  send('{"jsonrpc": "2.0", "id": 99, "method": ');
  const bad = await next((m) => m.error && m.id === null);
  check(bad.error.code === -32700, 'malformed JSON: a parse error response', bad);
  const unknown = await request('plant/nothing', {});
  check(unknown.error?.code === -32601, 'unknown method: method not found', unknown);
  const nodoc = await request('textDocument/hover', { textDocument: { uri: 'file:///nowhere.plant' }, position: { line: 0, character: 0 } });
  check(nodoc.error?.code === -32602, 'unknown document: invalid params', nodoc);
  send('{"jsonrpc": "2.0", "id": 98}');
  const nomethod = await next((m) => m.id === 98);
  check(nomethod.error?.code === -32600, 'a request without a method: invalid request', nomethod);
  const noposition = await request('textDocument/hover', { textDocument: { uri } });
  check(noposition.error?.code === -32602, 'a hover without a position: invalid params', noposition);
  // A document whose text is not UTF-8 (LSP messages are): a parse error naming the byte.
  send(Buffer.concat([Buffer.from('{"jsonrpc": "2.0", "method": "textDocument/didOpen", "params": {"textDocument": '
    + '{"uri": "file:///latin1.plant", "languageId": "plant", "version": 1, "text": "plant P {'),
    Buffer.from([0xff]), Buffer.from('}"}}}')]));
  const latin1 = await next((m) => m.error && m.id === null);
  check(latin1.error.code === -32700 && latin1.error.message.includes('not valid UTF-8: byte 0xFF at offset 167'),
    'a message that is not UTF-8: a parse error naming the byte', latin1);
  send('[1, 2]');
  const notobject = await next((m) => m.error && m.id === null && m.error.code !== -32700);
  check(notobject.error.code === -32600, 'a message that is not an object: invalid request', notobject);
  const still = await request('textDocument/documentSymbol', { textDocument: { uri } });
  check(Array.isArray(still.result) && still.result.length > 0, 'the server still answers after bad input', still);
});
