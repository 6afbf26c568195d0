// A scripted conversation with `plant lsp` about hover, go to definition, completion and
// the references of parameters and `let`s, on the bottling plant and the stdlib files it
// imports; every expected answer is found in the files' text by the test. Then a file
// opened with a broken line still has its outline and hover.
// Usage: node navigation.mjs PLANT REPO_DIR
import { realpathSync } from 'node:fs';
import path from 'node:path';
import { pathToFileURL } from 'node:url';
import { check, converse, readDoc, sameLocations, start } from './client.mjs';

const [plant, repo] = process.argv.slice(2);
const load = (rel) => readDoc(repo, rel);
const bottling = load('plants/bottling.plant');
const stations = load('stdlib/stations.plant');
const switches = load('stdlib/switch.plant');

// The position of the `n`th match of `re` (its first group, else the whole match) on the
// first line matching `lineRe` from line `after` on.
function at(doc, lineRe, re, n = 0, after = 0) {
  const line = doc.lines.findIndex((l, i) => i >= after && lineRe.test(l));
  const m = [...(line < 0 ? '' : doc.lines[line]).matchAll(new RegExp(re, 'g'))][n];
  if (!m) return { line, character: -1 };
  return { line, character: m.index + m[0].indexOf(m[1] ?? m[0]) };
}
const code = (l) => l.replace(/\/\/.*$/, '');  // a line without its comment
// Every `\bNAME\b` in the code of lines [from, to) of `doc`, as ranges.
function uses(doc, name, from, to) {
  const out = [];
  for (let line = from; line < to; line++)
    for (const m of code(doc.lines[line]).matchAll(new RegExp(`\\b${name}\\b`, 'g')))
      out.push({ uri: doc.uri, line, character: m.index, end: m.index + name.length });
  return out;
}
// The lines of the object or plant declared on line `first`: up to its closing `}` at column 0.
const body = (doc, first) => [first, doc.lines.findIndex((l, i) => i > first && /^}/.test(l)) + 1];
const same = sameLocations;

const client = start(plant, repo);
const { send, request, diagnosticsFor } = client;
const pos = (doc, p) => ({ textDocument: { uri: doc.uri }, position: { line: p.line, character: p.character + 1 } });
const hover = async (doc, p) => (await request('textDocument/hover', pos(doc, p))).result?.contents?.value ?? '';
const definition = async (doc, p) => (await request('textDocument/definition', pos(doc, p))).result;
const isAt = (loc, doc, p, len) => loc?.uri === doc.uri && loc?.range?.start?.line === p.line &&
  loc?.range?.start?.character === p.character && loc?.range?.end?.character === p.character + len;
const complete = async (doc, line, character) =>
  (await request('textDocument/completion', { textDocument: { uri: doc.uri }, position: { line, character } })).result ?? [];
const open = async (doc, text = doc.text) => {
  send({ method: 'textDocument/didOpen', params: { textDocument: { uri: doc.uri, languageId: 'plant', version: 1, text } } });
  return diagnosticsFor(doc.uri);
};

await converse(client, async () => {
  await request('initialize', { processId: null, rootUri: null, capabilities: {} });
  send({ method: 'initialized', params: {} });
  for (const doc of [bottling, stations, switches]) await open(doc);

  // --- hover ---
  // A port named by a path segment: its direction and type, as switch.plant declares it.
  const decl = /^\s*(in|out)\s+to_working:\s*(\w+)/m.exec(switches.text.slice(switches.text.indexOf('object RoutedSwitch')));
  let h = await hover(bottling, at(bottling, /record s1\.to_working/, 'to_working'));
  check(decl && h.includes(`${decl[1]} to_working: ${decl[2]}`), 'hover on s1.to_working: its direction and type', { h, decl });
  // A component's built-in slot (the timer's tick): direction and type.
  h = await hover(stations, at(stations, /flow work\.tick/, 'tick'));
  check(/out tick: void/.test(h) && /timer work/.test(h), "hover on work.tick: the timer's slot, out and void", h);
  // A parameter's use: type, unit, default.
  const param = /StationCore\(process: (\w+) = ([^,]+),/.exec(stations.text);
  h = await hover(stations, at(stations, /timer work: oneshot \{ period = process \}/, 'process'));
  check(param && h.includes(`process: ${param[1]}`) && /unit: s\b/.test(h) && h.includes(`default: ${param[2]}`),
        "hover on a parameter's use: type, unit and default", { h, param });
  // A let's use: its expression, dimension and value with the defaults.
  const speed = /belt_speed: velocity = (\d+) cm\/s/.exec(bottling.text);
  h = await hover(bottling, at(bottling, /^\s*b1:\s+Belt\(/, '= (v)\\)'));
  check(speed && h.includes('let v = belt_speed') && /velocity \(m\/s\)/.test(h) &&
        h.includes(`: ${Number(speed[1]) / 100} m/s`), "hover on a let's use: expression, dimension, value", { h, speed });
  // An object type's /// documentation.
  const first = switches.lines.findIndex((l) => /^object RoutedSwitch/.test(l));
  let top = first;
  while (top > 0 && switches.lines[top - 1].startsWith('///')) top--;
  const docLines = switches.lines.slice(top, first).map((l) => l.replace(/^\/\/\/ ?/, ''));
  h = await hover(bottling, at(bottling, /^\s*s1:\s+RoutedSwitch/, 'RoutedSwitch'));
  check(docLines.length > 2 && docLines.every((l) => h.includes(l)) && /object RoutedSwitch\(codes: list/.test(h),
        "hover on RoutedSwitch: its signature and /// documentation", { h, docLines });
  // A component kind and a property.
  h = await hover(stations, at(stations, /timer work: oneshot/, 'timer'));
  check(/timer component/.test(h) && /`period` \(required\)/.test(h) && /`periodic` `oneshot`/.test(h),
        'hover on a component kind: its description, modes and properties', h);
  h = await hover(stations, at(stations, /^\s*extent = /, 'extent'));
  check(/property of trigger \(required\); unit: m/.test(h), "hover on a property: the kind's description of it", h);

  // --- go to definition ---
  let d = await definition(bottling, at(bottling, /^import /, 'std\\.switch'));
  check(d?.uri === switches.uri, 'definition of `import std.switch`: stdlib/switch.plant', d);
  d = await definition(bottling, at(bottling, /record s1\.to_working/, 'to_working'));
  const routed = switches.lines.findIndex((l) => /^object RoutedSwitch/.test(l));
  check(isAt(d, switches, at(switches, /^\s*(in|out)\s+to_working:/, 'to_working', 0, routed), 'to_working'.length),
        "definition of s1.to_working: RoutedSwitch's port in switch.plant", d);
  d = await definition(bottling, at(bottling, /record s1\.to_working/, '(s1)\\.'));
  check(isAt(d, bottling, at(bottling, /^\s*s1:\s+RoutedSwitch/, 's1'), 2), 'definition of s1 in a path: the instance', d);
  d = await definition(stations, at(stations, /flow eye\.on_enter -> net\.Arrived\.put/, 'net'));
  check(isAt(d, stations, at(stations, /^\s*state net \{/, 'net'), 3), "definition of `net` in a path: the component", d);
  d = await definition(stations, at(stations, /flow eye\.on_enter -> net\.Arrived\.put/, 'Arrived'));
  check(isAt(d, stations, at(stations, /^\s*place Idle = 1, Arrived/, 'Arrived'), 'Arrived'.length), "definition of net.Arrived: the place", d);
  d = await definition(stations, at(stations, /timer work: oneshot \{ period = process \}/, 'process'));
  check(isAt(d, stations, at(stations, /^object StationCore\(/, 'process'), 'process'.length), "definition of a parameter's use: the parameter", d);
  d = await definition(bottling, at(bottling, /^\s*b1:\s+Belt\(/, '= (v)\\)'));
  check(isAt(d, bottling, at(bottling, /^\s*let v = /, 'v'), 1), "definition of a let's use: the let", d);
  d = await definition(bottling, at(bottling, /^\s*b1:\s+Belt\(/, '(speed) ='));
  const beltFile = load('stdlib/belts.plant');
  check(isAt(d, beltFile, at(beltFile, /^object Belt\(/, '(speed):'), 'speed'.length), "definition of a named argument: Belt's parameter", d);

  // --- references of parameters and lets ---
  const line0 = bottling.lines.findIndex((l) => /^object BottlingLine\(/.test(l));
  const [from, to] = body(bottling, line0);
  let refs = await request('textDocument/references', { ...pos(bottling, at(bottling, /^\s+belt_speed: velocity/, 'belt_speed')), context: { includeDeclaration: true } });
  let want = uses(bottling, 'belt_speed', from, to);
  check(want.length >= 3 && same(refs.result, want), "references of BottlingLine's belt_speed: its declaration, constraint and use, not the plant's", { got: refs.result, want });
  refs = await request('textDocument/references', { ...pos(bottling, at(bottling, /^\s*let v = /, 'v')), context: { includeDeclaration: false } });
  want = uses(bottling, 'v', from, to).filter((r) => !/^\s*let v = /.test(bottling.lines[r.line]));
  check(want.length > 20 && same(refs.result, want), 'references of `let v`: every use in BottlingLine', { got: refs.result?.length, want: want.length });
  // A parameter passed by position and by name: StationCore's `process` from its declaration.
  const core = stations.lines.findIndex((l) => /^object StationCore\(/.test(l));
  const [cf, ct] = body(stations, core);
  refs = await request('textDocument/references', { ...pos(stations, at(stations, /^object StationCore\(/, 'process')), context: { includeDeclaration: true } });
  want = uses(stations, 'process', cf, ct);
  check(want.length >= 2 && same(refs.result, want), "references of StationCore's process", { got: refs.result, want });

  // --- completion ---
  const labels = (items) => items.map((i) => i.label);
  // After `work.` (a timer): its slots with direction and type.
  const wl = stations.lines.findIndex((l) => /flow work\.tick/.test(l));
  let items = await complete(stations, wl, stations.lines[wl].indexOf('work.') + 5);
  const tick = items.find((i) => i.label === 'tick');
  check(tick?.detail === 'out void' && labels(items).includes('start'), "completion after work.: the timer's slots", items);
  // After `line[i].s1.` in the plant: the switch's ports, through the line's type.
  const close = bottling.lines.lastIndexOf('}');
  const edited = bottling.lines.slice();
  edited.splice(close, 0, '    flow line[i].s1.');
  send({ method: 'textDocument/didChange', params: { textDocument: { uri: bottling.uri, version: 2 }, contentChanges: [{ text: edited.join('\n') }] } });
  await diagnosticsFor(bottling.uri);
  items = await complete(bottling, close, '    flow line[i].s1.'.length);
  const ports = [...switches.text.matchAll(/^\s*(in|out) (\w+):\s*(\w+)/gm)].filter((m) => m.index > switches.text.indexOf('object RoutedSwitch'));
  check(ports.length > 0 && ports.every((m) => items.some((i) => i.label === m[2] && i.detail === `${m[1]} ${m[3]}`)),
        'completion after line[i].s1.: the ports of RoutedSwitch with their types', labels(items));
  // After a cast `(core.bottle as Bottle).` and after a source's pooled object `store[0].`: Bottle's ports.
  const bottlePorts = [...load('stdlib/bottle.plant').text.matchAll(/^\s*(in|out)\s+(\w+):/gm)].map((m) => m[2]);
  const cl = stations.lines.findIndex((l) => /\(core\.bottle as Bottle\)\.show_filled$/.test(l));
  items = await complete(stations, cl, stations.lines[cl].indexOf('Bottle).') + 'Bottle).'.length);
  check(bottlePorts.length > 3 && bottlePorts.every((p) => labels(items).includes(p)), 'completion after a cast: the type\'s ports', labels(items));
  edited.splice(close, 1, '    flow line[0].storage.store[3].');
  send({ method: 'textDocument/didChange', params: { textDocument: { uri: bottling.uri, version: 3 }, contentChanges: [{ text: edited.join('\n') }] } });
  await diagnosticsFor(bottling.uri);
  items = await complete(bottling, close, '    flow line[0].storage.store[3].'.length);
  check(bottlePorts.every((p) => labels(items).includes(p)), "completion after storage.store[3].: the issued Bottle's ports", labels(items));
  // Property names at the start of a line in a component's braces.
  const tl = stations.lines.findIndex((l) => /^\s*extent = /.test(l));
  items = await complete(stations, tl, 8);
  check(['extent', 'filter'].every((p) => labels(items).includes(p)) && !labels(items).includes('period'), "completion in a trigger's braces: its properties", labels(items));
  // Component kinds (and object types) at the start of a member.
  const ml = stations.lines.findIndex((l) => /^\s*out started:/.test(l));
  items = await complete(stations, ml, 4);
  check(['timer', 'trigger', 'state', 'physics'].every((k) => labels(items).includes(k)) && labels(items).includes('StationCore'),
        'completion at a member: component kinds and object types', labels(items));
  // Units after a number.
  const il = bottling.lines.findIndex((l) => /^\s*let r = 30 cm/.test(l));
  items = await complete(bottling, il, bottling.lines[il].indexOf('30 ') + 3);
  check(['cm', 'mm', 'deg'].every((u) => labels(items).includes(u)), 'completion after a number: units', labels(items));
  // After `import`: the modules and the object types, which insert their module.
  items = await complete(bottling, bottling.lines.findIndex((l) => /^import /.test(l)), 'import '.length);
  const belt = items.find((i) => i.label === 'Belt');
  check(labels(items).includes('std.belts') && belt?.insertText === 'std.belts', 'completion after import: modules and types', belt);

  // --- a file opened with a broken line keeps its outline and hover ---
  const broken = load('plants/bottling.plant');
  broken.uri = pathToFileURL(path.join(path.dirname(realpathSync(path.join(repo, 'plants/bottling.plant'))), 'broken_copy.plant')).href;
  const lines = broken.lines.slice();
  const b3 = lines.findIndex((l) => /^\s*b3:\s+Belt\(/.test(l));
  lines.splice(b3, 0, '    b2x: Belt(length = , speed = ');
  const diags = await open(broken, lines.join('\n'));
  check(diags.params.diagnostics.some((x) => x.code === 'E0001'), 'the broken copy has a syntax error', diags.params.diagnostics);
  const outline = (await request('textDocument/documentSymbol', { textDocument: { uri: broken.uri } })).result ?? [];
  const names = outline.map((s) => s.name);
  const lineSym = outline.find((s) => s.name === 'BottlingLine');
  check(names.includes('BottlingLine') && names.includes('Bottling') && lineSym.children.some((c) => c.name === 'cap'),
        'outline of the broken copy: both objects, members after the broken line', names);
  const b4 = b3 + 3;  // b4 in the copy (the broken line pushed it down)
  h = (await request('textDocument/hover', { textDocument: { uri: broken.uri }, position: { line: b4, character: lines[b4].indexOf('speed') + 1 } })).result?.contents?.value ?? '';
  check(/^\s*b4:\s+Belt/.test(lines[b4]) && /speed: velocity/.test(h), 'hover after the broken line', { line: lines[b4], h });
});
