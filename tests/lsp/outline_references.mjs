// A scripted conversation with `plant lsp` about the outline and references: the
// capabilities say both; the bottling plant's outline holds its type, the type's
// instances, components (a net with its places), flows and a `for` in the plant; the
// references of a stdlib type, of a port and of a component's slot are every use in the
// file and its imports (checked against the text, not counted by hand), with the
// declaration exactly when includeDeclaration says so; a type's references asked from the
// stdlib file reach the open plant that uses it; std.bottle's Bottle and its port `code`
// through casts, across the stdlib. Usage: node outline_references.mjs PLANT REPO_DIR
import { readdirSync } from 'node:fs';
import path from 'node:path';
import { check, converse, readDoc, sameLocations, start } from './client.mjs';

const [plant, repo] = process.argv.slice(2);
const open = (rel) => readDoc(repo, rel);
const bottling = open('plants/bottling.plant');
const storage = open('stdlib/storage.plant');
const arm = open('stdlib/arm.plant');
const switches = open('stdlib/switch.plant');

// Every place in `doc` where `re` (global, one capture group: the name) matches, as LSP ranges.
function ranges(doc, re) {
  const out = [];
  doc.lines.forEach((l, line) => {
    for (const m of l.matchAll(re)) {
      const character = m.index + m[0].indexOf(m[1]);
      out.push({ uri: doc.uri, line, character, end: character + m[1].length });
    }
  });
  return out;
}
const same = sameLocations;

const client = start(plant, repo);
const { send, request, diagnosticsFor } = client;
const references = (doc, at, includeDeclaration) =>
  request('textDocument/references', { textDocument: { uri: doc.uri }, position: { line: at.line, character: at.character + 1 },
                                       context: { includeDeclaration } });

await converse(client, async () => {
  const init = await request('initialize', { processId: null, rootUri: null, capabilities: {} });
  const caps = init.result?.capabilities ?? {};
  check(caps.documentSymbolProvider === true && caps.referencesProvider === true, 'initialize: outline and references', caps);
  send({ method: 'initialized', params: {} });
  send({ method: 'textDocument/didOpen', params: { textDocument: { uri: bottling.uri, languageId: 'plant', version: 1, text: bottling.text } } });
  await diagnosticsFor(bottling.uri);

  // The outline.
  const outline = (await request('textDocument/documentSymbol', { textDocument: { uri: bottling.uri } })).result ?? [];
  const byName = (list, name) => (list ?? []).find((s) => s.name === name);
  const line = byName(outline, 'BottlingLine'), plantSym = byName(outline, 'Bottling');
  check(line?.kind === 5 && plantSym?.kind === 2, 'the outline: the object type (class) and the plant (module)', outline.map((s) => s.name));
  const b1 = byName(line?.children, 'b1');
  const b1Line = bottling.lines.findIndex((l) => /^\s*b1:\s+Belt\(/.test(l));
  check(b1?.detail === 'Belt' && b1?.selectionRange?.start?.line === b1Line &&
        b1.selectionRange.start.character === bottling.lines[b1Line].indexOf('b1'),
        'an instance, with its type and its name selected', b1);
  check(byName(line?.children, 'storage')?.detail === 'Storage', 'the storage is an instance of std.storage Storage', byName(line?.children, 'storage'));
  const feed = byName(line?.children, 'feed');
  check(feed?.detail === 'state' && ['Ready', 'Want'].every((p) => byName(feed.children, p)) && byName(feed.children, 'issue')?.kind === 6,
        'a net, with its places and transitions', feed);
  check(byName(line?.children, 'want -> feed.Want.put')?.kind === 25, 'a flow, named by its ends', (line?.children ?? []).filter((s) => s.kind === 25).map((s) => s.name));
  check(byName(line?.children, 'bottles')?.kind === 7, "the type's parameters", line?.children?.slice(0, 4));
  const loop = byName(plantSym?.children, 'for i');
  check(byName(loop?.children, 'line[i]')?.detail === 'BottlingLine', "the plant's loop holds its instances", plantSym);
  const inside = (outer, inner) => {
    const before = (a, b) => a.line < b.line || (a.line === b.line && a.character <= b.character);
    return before(outer.start, inner.start) && before(inner.end, outer.end);
  };
  const nested = (s) => inside(s.range, s.selectionRange) && (s.children ?? []).every((c) => inside(s.range, c.range) && nested(c));
  check(outline.every(nested), 'every selection and every child lies inside its range', outline);

  // The references of a stdlib type, asked from an instance's type in the plant.
  const useOfSwitch = ranges(bottling, /:\s+(RoutedSwitch)\(/g);
  const declOfSwitch = ranges(switches, /^object (RoutedSwitch)\(/g);
  let got = (await references(bottling, useOfSwitch[0], false)).result;
  check(useOfSwitch.length === 5 && same(got, useOfSwitch), 'RoutedSwitch: its five uses', got);
  got = (await references(bottling, useOfSwitch[0], true)).result;
  check(same(got, [...useOfSwitch, ...declOfSwitch]), 'RoutedSwitch with includeDeclaration: and its declaration in stdlib/switch.plant', got);

  // A port: arm.pick_occupied in a logic connector and a flow, declared in std.arm.
  const uses = ranges(bottling, /arm\.(pick_occupied)/g);
  const decl = ranges(arm, /^\s*out (pick_occupied):/g);
  got = (await references(bottling, uses[1], false)).result;
  check(uses.length === 2 && same(got, uses), "a port's uses", got);
  got = (await references(bottling, uses[0], true)).result;
  check(decl.length === 1 && same(got, [...uses, ...decl]), "a port's uses and its declaration", got);
  // And from the declaration in std.arm (open it): the same set.
  send({ method: 'textDocument/didOpen', params: { textDocument: { uri: arm.uri, languageId: 'plant', version: 1, text: arm.text } } });
  await diagnosticsFor(arm.uri);
  got = (await references(arm, decl[0], true)).result;
  check(same(got, [...uses, ...decl]), "from the port's declaration in the open stdlib file, the plant's uses too", got);

  // A component's slot: the net's transition `issue` and its `fired` slot.
  const fired = ranges(bottling, /feed\.issue\.(fired)/g);
  got = (await references(bottling, fired[0], true)).result;
  check(fired.length >= 1 && same(got, fired), "a built-in slot of a component: its uses, no declaration", got);
  const issue = ranges(bottling, /transition (issue):/g);
  got = (await references(bottling, issue[0], true)).result;
  check(same(got, [...issue, ...ranges(bottling, /feed\.(issue)\./g)]), 'a transition: its declaration and the paths through it', got);

  // A type's references asked from the stdlib file: the open plant's use of it.
  send({ method: 'textDocument/didOpen', params: { textDocument: { uri: storage.uri, languageId: 'plant', version: 1, text: storage.text } } });
  await diagnosticsFor(storage.uri);
  const declOfStorage = ranges(storage, /^object (Storage)\(/g);
  got = (await references(storage, declOfStorage[0], false)).result;
  check(same(got, ranges(bottling, /:\s+(Storage)\(/g)), 'Storage from its declaration: the use in the open bottling plant', got);

  // Bottle, from a source's `object` in std.storage: its declaration, triggers' filters,
  // casts and that `object`, everywhere in the stdlib outside comments. Then its port
  // `code` through casts `(p as Bottle).code`.
  const stdlib = readdirSync(path.join(repo, 'stdlib')).filter((f) => f.endsWith('.plant')).map((f) => open(`stdlib/${f}`));
  const code = (doc) => ({ ...doc, lines: doc.lines.map((l) => (/^\s*\/\//.test(l) ? '' : l)) });
  const bottleUses = stdlib.flatMap((doc) => ranges(code(doc), /\b(Bottle)\b/g));
  const atObject = ranges(storage, /object = (Bottle)\(/g);
  got = (await references(storage, atObject[0], true)).result;
  check(bottleUses.length >= 8 && same(got, bottleUses), 'Bottle: its declaration, filters, casts and a source\'s object', got);
  const bottle = open('stdlib/bottle.plant');
  const codeUses = [...ranges(bottle, /^\s*out (code):/g), ...stdlib.flatMap((doc) => ranges(code(doc), /as Bottle\)\.(code)\b/g))];
  const castAt = ranges(code(switches), /as Bottle\)\.(code)\b/g)[0];
  send({ method: 'textDocument/didOpen', params: { textDocument: { uri: switches.uri, languageId: 'plant', version: 1, text: switches.text } } });
  await diagnosticsFor(switches.uri);
  got = (await references(switches, castAt, true)).result;
  check(codeUses.length >= 3 && same(got, codeUses), "a port through a cast: Bottle's code, declared and read", got);

  // Nothing under the cursor: an empty list; an unknown document: invalid params.
  got = (await request('textDocument/references', { textDocument: { uri: bottling.uri }, position: { line: 0, character: 0 },
                                                    context: { includeDeclaration: true } })).result;
  check(Array.isArray(got) && got.length === 0, 'references on a comment: none', got);
  const nodoc = await request('textDocument/documentSymbol', { textDocument: { uri: 'file:///nowhere.plant' } });
  check(nodoc.error?.code === -32602, 'outline of an unknown document: invalid params', nodoc);
});
