// The inspector: an object's dotted path, type, slots with live values (status.inspect),
// its state components' markings, and a control for each input slot. Every control sends
// an `event` message: the same event `plant run --event` applies.

const $ = (id) => document.getElementById(id);

function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else if (k === 'dataset') Object.assign(e.dataset, v);
    else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c);
  return e;
}

function formatValue(v) {
  if (v === null || v === undefined) return '';
  if (typeof v === 'number') return Number.isInteger(v) ? String(v) : v.toPrecision(5).replace(/\.?0+$/, '');
  if (Array.isArray(v)) return v.map(formatValue).join(' ');
  return String(v);
}

export class Inspector {
  constructor(send) {
    this.send = send;
    this.scene = null;
    this.path = null;
    this.readOnly = false;
    this.operable = null;   // a trainee's page: the only inputs it may operate (a Set of paths), no forces
    this.valueCells = new Map();   // slot path -> {row, cell}
    this.placeChips = new Map();   // place id -> chip
    $('insp-close').addEventListener('click', () => this.close());
  }

  setScene(scene) {
    this.scene = scene;
    this.owned = null;
    if (this.path !== null) {
      // After a restart, keep inspecting the same object if it still exists.
      const p = this.path;
      this.path = null;
      if (scene.dos.some((d) => d.path === p)) this.open(p); else this.close();
    }
  }

  // The object that owns a slot or place path: its longest prefix that is an object's path
  // (the plant's own, "", when none is).
  ownerOf(path) {
    const parts = path.split('.');
    for (let i = parts.length - 1; i > 0; i--) {
      const p = parts.slice(0, i).join('.');
      if (this.doPaths.has(p)) return p;
    }
    return '';
  }

  // Slots and places by the object that owns them: its ports (path.port) and its
  // components' slots (path.comp.slot), not those of the objects inside it.
  index() {
    if (this.owned) return;
    this.doPaths = new Set(this.scene.dos.map((d) => d.path));
    this.owned = new Map();
    const bucket = (owner) => {
      if (!this.owned.has(owner)) this.owned.set(owner, { slots: [], places: [] });
      return this.owned.get(owner);
    };
    this.doByPath = new Map(this.scene.dos.map((d) => [d.path, d]));
    for (const p of this.scene.places) bucket(this.ownerOf(p.path)).places.push(p);
  }

  slotsOf(path) {
    this.index();
    // The object's own list (shared by its type) in scene.slot_lists, names relative to it.
    const d = this.doByPath.get(path);
    const prefix = path === '' ? '' : path + '.';
    const owned = (d ? this.scene.slot_lists[d.slots] ?? [] : [])
      .map(([name, type, dir, port]) => ({ path: prefix + name, type, dir, port }));
    // ports first, then inputs, then the rest, each in declaration order
    const rank = (s) => (s.port ? 0 : 2) + (s.dir === 'in' ? 0 : 1);
    return owned.map((s, i) => [s, i]).sort((a, b) => rank(a[0]) - rank(b[0]) || a[1] - b[1]).map(([s]) => s);
  }

  open(path) {
    if (!this.scene) return;
    const d = this.scene.dos.find((x) => x.path === path);
    if (!d) return;
    this.path = path;
    // Live values come for a live run's objects ("" is the plant's own; a replay has none).
    if (!this.readOnly) this.send({ type: 'inspect', path });
    $('inspector').hidden = false;
    $('insp-path').textContent = path === '' ? `${this.scene.plant} (the plant)` : path;
    $('insp-type').textContent = `${d.type}${d.pooled ? ' · pooled' : ''}`;
    const table = $('insp-slots');
    table.replaceChildren();
    this.valueCells.clear();
    const prefix = path === '' ? '' : path + '.';
    const slots = this.slotsOf(path);
    const ports = slots.filter((s) => s.port);
    const others = slots.filter((s) => !s.port);
    // The object's declared ports up front; its components' slots folded away below (all
    // of them when the object declares no ports).
    const rest = $('insp-components');
    rest.replaceChildren();
    const restTable = el('table');
    if (ports.length) rest.append(el('details', { class: 'components' }, el('summary', {}, `component slots (${others.length})`), restTable));
    for (const s of slots) {
      const into = ports.length && !s.port ? restTable : table;
      const cell = el('td', { class: 'num' });
      const row = el('tr', { dataset: { slot: s.path } },
        el('td', { class: 'name', title: s.path }, s.path.slice(prefix.length),
          el('div', { class: 'kind' }, `${s.dir} ${s.type}${s.port ? ' · port' : ''}`)),
        cell,
        el('td', {}, s.dir === 'in' && !this.readOnly && (!this.operable || this.operable.has(s.path)) ? this.control(s) : ''),
        el('td', {}, this.readOnly || this.operable ? '' : this.forceMenu(s)));
      into.append(row);
      this.valueCells.set(s.path, { row, cell });
    }
    // Places grouped by their state component.
    const box = $('insp-places');
    box.replaceChildren();
    this.placeChips.clear();
    const nets = new Map();
    for (const p of this.owned.get(path)?.places ?? []) {
      const parts = p.path.slice(prefix.length).split('.');
      if (parts.length !== 2) continue;
      if (!nets.has(parts[0])) nets.set(parts[0], []);
      nets.get(parts[0]).push({ ...p, name: parts[1] });
    }
    for (const [net, places] of nets) {
      box.append(el('div', { class: 'kind' }, `state ${net}: marking`));
      const chips = el('div', { class: 'places' });
      for (const p of places) {
        const chip = el('span', { class: 'place', title: p.path, dataset: { place: p.path } }, `${p.name} ${p.initial}`);
        chip.dataset.name = p.name;
        if (p.initial > 0) chip.classList.add('marked');
        chips.append(chip);
        this.placeChips.set(p.id, chip);
      }
      box.append(chips);
    }
  }

  // A control matching the input slot's type.
  control(s) {
    const fire = (value) => this.send(value === undefined ? { type: 'event', path: s.path } : { type: 'event', path: s.path, value: String(value) });
    switch (s.type) {
      case 'void':
        return el('button', { dataset: { slot: s.path }, title: `fire ${s.path}`, onclick: () => fire() }, 'fire');
      case 'bool': {
        const box = el('input', { type: 'checkbox', dataset: { slot: s.path }, title: `set ${s.path}` });
        box.addEventListener('change', () => fire(box.checked ? 'true' : 'false'));
        return box;
      }
      case 'real': case 'int': {
        const input = el('input', { type: 'number', step: s.type === 'int' ? '1' : 'any', dataset: { slot: s.path } });
        const go = () => { if (input.value !== '') fire(input.value); };
        input.addEventListener('keydown', (e) => { if (e.key === 'Enter') go(); });
        return el('span', {}, input, el('button', { onclick: go, title: `set ${s.path}` }, 'set'));
      }
      default: {   // string, ref, vec3, quat, pose: the text of an events file
        const input = el('input', { type: 'text', dataset: { slot: s.path }, placeholder: s.type });
        const go = () => fire(input.value);
        input.addEventListener('keydown', (e) => { if (e.key === 'Enter') go(); });
        return el('span', {}, input, el('button', { onclick: go, title: `set ${s.path}` }, 'set'));
      }
    }
  }

  // Fault forcing (docs/runtime.md, "Forced slots"): stuck at a value, open (reads as off),
  // inverted (bool), released; sent as a force message, logged and replayed like events.
  forceMenu(s) {
    const ways = s.type === 'void' ? [['stuck on', 'stuck', 'on'], ['stuck off', 'stuck', 'off'], ['open', 'open']]
      : s.type === 'bool' ? [['stuck true', 'stuck', 'true'], ['stuck false', 'stuck', 'false'], ['open', 'open'], ['invert', 'invert']]
      : ['vec3', 'quat', 'pose'].includes(s.type) ? [['stuck at…', 'stuck', null]]
      : [['stuck at…', 'stuck', null], ['open', 'open']];
    const menu = el('select', { dataset: { force: s.path }, title: `force ${s.path}` },
      el('option', { value: '' }, 'force…'),
      ...ways.map(([label], i) => el('option', { value: String(i) }, label)),
      el('option', { value: 'release' }, 'release'));
    menu.addEventListener('change', () => {
      const pick = menu.value;
      menu.value = '';
      if (pick === 'release') return this.send({ type: 'force', path: s.path, mode: 'release' });
      const way = ways[Number(pick)];
      if (!way) return;
      let value = way[2];
      if (value === null) {   // the value typed into the slot's own box, or asked for
        const box = menu.closest('tr')?.querySelector(`input[data-slot="${CSS.escape(s.path)}"]`);
        value = box && box.value !== '' ? box.value : window.prompt(`force ${s.path} stuck at (${s.type})`);
        if (value === null || value === '') return;
      }
      this.send(value === undefined ? { type: 'force', path: s.path, mode: way[1] } : { type: 'force', path: s.path, mode: way[1], value: String(value) });
    });
    return menu;
  }

  close() {
    if (this.path !== null) this.send({ type: 'inspect', path: null });
    this.path = null;
    $('inspector').hidden = true;
  }

  applyStatus(inspect) {
    if (!inspect || inspect.path !== this.path) return;
    for (const s of inspect.slots ?? []) {
      const c = this.valueCells.get(s.path);
      if (!c) continue;
      c.cell.textContent = formatValue(s.value) + (s.forced ? ` (${s.forced})` : '');
      c.row.classList.toggle('active', !!s.active);
      c.row.classList.toggle('forced', !!s.forced);
    }
    for (const p of inspect.places ?? []) {
      const chip = this.placeChips.get(p.id);
      if (!chip) continue;
      chip.textContent = `${chip.dataset.name} ${p.tokens}`;
      chip.classList.toggle('marked', p.tokens > 0);
    }
  }
}
