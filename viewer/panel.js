// Operator panels (docs/viewer.md, "Operator panels"): each `panel` of the plant drawn as a
// 2D panel over the scene — push buttons that go down while held, a mushroom emergency stop
// with its reset key, selector switches, lamps that light and blink, numeric displays.
// Working an element sends the ordinary `event` message on its input (`…start.press`), the
// one way in, so a press from the page is replayed like `--event`; what the page shows
// comes back in status.panel (one number per element), never from the click itself.

const COLORS = { green: '#2fb34a', red: '#d9302c', yellow: '#f2c014', white: '#f4f4f0', blue: '#2a6fd6', black: '#222' };

function el(tag, cls, text) {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text !== undefined) e.textContent = text;
  return e;
}

export class OperatorPanels {
  constructor(parent, send) {
    this.send = send;
    this.root = el('div', 'op-panels');
    this.root.id = 'op-panels';
    this.root.hidden = true;
    parent.append(this.root);
    this.elements = [];   // in status.panel's order: {spec, node, set(value)}
    this.values = [];
    this.readOnly = false;
  }

  setScene(scene) {
    this.root.replaceChildren();
    this.elements = [];
    this.values = [];
    const panels = scene.panels ?? [];
    this.root.hidden = panels.length === 0;
    for (const p of panels) {
      const box = el('section', 'op-panel');
      box.dataset.panel = p.path;
      box.append(el('h3', 'op-title', p.title || p.path));
      const grid = el('div', 'op-grid');
      for (const spec of p.elements) {
        const made = this.make(spec);
        made.node.dataset.element = spec.path;
        made.node.dataset.kind = spec.kind;
        const cell = el('div', `op-cell op-cell-${spec.kind}`);
        cell.append(made.node, el('div', 'op-label', spec.label || spec.name));
        grid.append(cell);
        this.elements.push({ spec, ...made });
        made.set(spec.kind === 'selector' ? spec.initial ?? 0 : 0);
      }
      box.append(grid);
      this.root.append(box);
    }
  }

  apply(values) {
    this.values = values;
    values.forEach((v, i) => this.elements[i]?.set(v));
  }

  event(path, value) {
    if (this.readOnly) return;
    this.send(value === undefined ? { type: 'event', path } : { type: 'event', path, value: String(value) });
  }

  make(spec) {
    switch (spec.kind) {
      case 'button': return this.button(spec);
      case 'estop': return this.estop(spec);
      case 'selector': return this.selector(spec);
      case 'lamp': return this.lamp(spec);
      default: return this.display(spec);
    }
  }

  // Down while the mouse holds it: press on pointerdown, release on pointerup or when the
  // pointer leaves it held.
  button(spec) {
    const b = el('button', 'op-button');
    b.style.setProperty('--cap', COLORS[spec.color] ?? '#8a8f96');
    b.title = `${spec.path}: press`;
    let held = false;
    const up = () => { if (held) { held = false; this.event(`${spec.path}.release`); } };
    b.addEventListener('pointerdown', (e) => { e.preventDefault(); held = true; this.event(`${spec.path}.press`); });
    b.addEventListener('pointerup', up);
    b.addEventListener('pointerleave', up);
    return { node: b, set: (v) => b.classList.toggle('down', v !== 0) };
  }

  // Struck, it latches (the server says so); the key under it resets it.
  estop(spec) {
    const node = el('div', 'op-estop-box');
    const m = el('button', 'op-estop');
    m.title = `${spec.path}: strike`;
    m.addEventListener('click', () => this.event(`${spec.path}.press`));
    const key = el('button', 'op-reset', 'reset');
    key.title = `${spec.path}: reset`;
    key.addEventListener('click', () => this.event(`${spec.path}.reset`));
    const plate = el('div', 'op-estop-plate');
    plate.append(m);
    node.append(plate, key);
    return { node, set: (v) => node.classList.toggle('engaged', v !== 0) };
  }

  // A knob turned by clicking one of its position names (or the knob: the next position).
  selector(spec) {
    const n = spec.positions === 3 ? 3 : 2;
    const names = spec.names ? spec.names.split('/') : Array.from({ length: n }, (_, i) => String(i));
    const node = el('div', 'op-selector-box');
    const knob = el('button', 'op-knob');
    knob.append(el('span', 'op-knob-bar'));
    const angle = (i) => (n === 2 ? (i === 0 ? -45 : 45) : (i - 1) * 45);
    let at = 0;
    knob.addEventListener('click', () => this.event(`${spec.path}.turn`, (at + 1) % n));
    const row = el('div', 'op-positions');
    const marks = names.map((name, i) => {
      const s = el('button', 'op-position', name);
      s.title = `${spec.path}: turn to ${name}`;
      s.addEventListener('click', () => this.event(`${spec.path}.turn`, i));
      row.append(s);
      return s;
    });
    node.append(row, knob);
    return {
      node,
      set: (v) => {
        at = v;
        knob.style.setProperty('--turn', `${angle(v)}deg`);
        marks.forEach((s, i) => s.classList.toggle('on', i === v));
      },
    };
  }

  lamp(spec) {
    const l = el('div', 'op-lamp');
    l.style.setProperty('--lens', COLORS[spec.color] ?? COLORS.green);
    return { node: l, set: (v) => { l.classList.toggle('on', v === 1); l.classList.toggle('blink', v === 2); } };
  }

  display(spec) {
    const d = el('div', 'op-display');
    const digits = Math.max(0, Math.min(6, spec.digits ?? 0));
    return { node: d, set: (v) => { d.textContent = `${Number(v).toFixed(digits)}${spec.unit ? ` ${spec.unit}` : ''}`; } };
  }

  // For tests: every element's path, kind and what it shows now.
  summary() {
    return this.elements.map((e, i) => ({ path: e.spec.path, kind: e.spec.kind, value: this.values[i] ?? null }));
  }
}
