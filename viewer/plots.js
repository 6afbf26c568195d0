// Live counters and records (status.counters, status.records) as numbers and small
// time-series plots (uPlot).
import uPlot from 'uplot';

const COUNTERS = ['issued', 'taken', 'on_line', 'lost', 'stalled'];
const PALETTE = ['#2f7de1', '#2da44e', '#e8893a', '#d1242f', '#8250df', '#0aa2c0', '#bf8700', '#e85aad', '#57606a', '#1b7c83'];
const KEEP = 1200;   // samples kept per plot

class Series {
  constructor(container, names, width) {
    this.names = names;
    this.data = [[], ...names.map(() => [])];
    this.plot = new uPlot({
      width, height: 130,
      legend: { show: true, live: false },
      cursor: { show: false },
      scales: { x: { time: false } },
      axes: [{ size: 24, font: '10px sans-serif' }, { size: 34, font: '10px sans-serif' }],
      series: [{ label: 't (s)' }, ...names.map((n, i) => ({ label: n, stroke: PALETTE[i % PALETTE.length], width: 1.5, points: { show: false } }))],
    }, this.data, container);
  }
  push(t, values) {
    const last = this.data[0].length ? this.data[0][this.data[0].length - 1] : -Infinity;
    if (t < last) this.clear();                 // a restart or a seek back
    else if (t === last) return;
    this.data[0].push(t);
    values.forEach((v, i) => this.data[i + 1].push(Number.isFinite(v) ? v : null));
    if (this.data[0].length > KEEP) for (const a of this.data) a.splice(0, a.length - KEEP);
    this.dirty = true;
  }
  clear() {
    for (const a of this.data) a.length = 0;
    this.dirty = true;
  }
  redraw() {
    if (!this.dirty) return;
    this.dirty = false;
    this.plot.setData(this.data);
  }
  destroy() { this.plot.destroy(); }
}

export class Plots {
  constructor() {
    this.counterTable = document.getElementById('counters');
    this.recordTable = document.getElementById('records');
    this.counterBox = document.getElementById('plot-counters');
    this.recordBox = document.getElementById('plot-records');
    this.counters = null;
    this.records = null;
    this.cells = {};
    this.recordCells = [];
    this.lastDraw = 0;
    new ResizeObserver(() => this.resize()).observe(this.counterBox);
  }

  width() { return Math.max(200, this.counterBox.clientWidth || 300); }

  resize() {
    const size = { width: this.width(), height: 130 };
    this.counters?.plot.setSize(size);
    this.records?.plot.setSize(size);
  }

  setScene(scene) {
    this.counters?.destroy();
    this.records?.destroy();
    this.counterTable.replaceChildren();
    this.recordTable.replaceChildren();
    this.cells = {};
    for (const name of COUNTERS) {
      const tr = document.createElement('tr');
      tr.innerHTML = `<td class="name">${name.replace('_', ' ')}</td><td class="num" data-counter="${name}">–</td>`;
      this.counterTable.append(tr);
      this.cells[name] = tr.lastChild;
    }
    this.recordCells = (scene.records ?? []).map((r) => {
      const tr = document.createElement('tr');
      const name = document.createElement('td');
      name.className = 'name';
      name.textContent = r.column;
      const v = document.createElement('td');
      v.className = 'num';
      tr.append(name, v);
      this.recordTable.append(tr);
      return v;
    });
    this.counters = new Series(this.counterBox, COUNTERS, this.width());
    this.records = (scene.records ?? []).length ? new Series(this.recordBox, scene.records.map((r) => r.column), this.width()) : null;
  }

  clear() {
    this.counters?.clear();
    this.records?.clear();
  }

  applyStatus(st) {
    if (!this.counters) return;
    const c = st.counters ?? {};
    for (const name of COUNTERS) if (this.cells[name]) this.cells[name].textContent = c[name] ?? '–';
    this.counters.push(st.time, COUNTERS.map((n) => c[n]));
    if (this.records && Array.isArray(st.records)) {
      st.records.forEach((v, i) => { if (this.recordCells[i]) this.recordCells[i].textContent = typeof v === 'number' ? +v.toPrecision(6) : String(v); });
      this.records.push(st.time, st.records.map(Number));
    }
    const now = performance.now();
    if (now - this.lastDraw > 500) {   // plots redraw at most twice a second
      this.lastDraw = now;
      this.counters.redraw();
      this.records?.redraw();
    }
  }
}
