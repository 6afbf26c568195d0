// Counters and records as numbers (with throughput per minute) and as small multiples of
// time series (uPlot): a handful of lines per chart, distinct colours, the legend beside
// it (click a name to hide its line). The series start at t = 0: the server sends the run's
// history when the page connects, after a restart and after a seek (docs/viewer.md), and
// each status adds a point.
import uPlot from 'uplot';

const COUNTERS = ['issued', 'taken', 'on_line', 'lost', 'stalled', 'removed'];
const COUNTER_CHART = ['issued', 'taken', 'on_line', 'lost', 'removed'];
const PER_MINUTE = new Set(['issued', 'taken', 'removed']);   // events, not states
const PALETTE = ['#2f7de1', '#e8893a', '#2da44e', '#d1242f', '#8250df', '#0aa2c0'];
const MAX_SERIES = 5;
const KEEP = 6000;   // points kept per chart (the server's history is bounded the same way)

// Records whose names differ only in numbers and single letters ("s1 to lane A", "s2 to
// lane B") share a chart; single ones are gathered up to four a chart.
export function groupColumns(columns) {
  const byPattern = new Map();
  for (const c of columns) {
    const key = c.name.replace(/\d+/g, '#').replace(/\b[A-Z]\b/g, '#');
    if (!byPattern.has(key)) byPattern.set(key, []);
    byPattern.get(key).push(c);
  }
  const charts = [], singles = [];
  for (const [key, cols] of byPattern) {
    if (cols.length === 1) { singles.push(cols[0]); continue; }
    for (let i = 0; i < cols.length; i += MAX_SERIES) charts.push({ title: key.replace(/#/g, '…'), cols: cols.slice(i, i + MAX_SERIES) });
  }
  for (let i = 0; i < singles.length; i += 4) charts.unshift({ title: '', cols: singles.slice(i, i + 4) });
  return charts;
}

// One chart: a few series of the same times.
class Chart {
  constructor(container, title, names, width) {
    this.names = names;
    this.data = [[], ...names.map(() => [])];
    const box = document.createElement('div');
    box.className = 'chart';
    if (title) {
      const h = document.createElement('div');
      h.className = 'chart-title';
      h.textContent = title;
      box.append(h);
    }
    const row = document.createElement('div');
    row.className = 'chart-row';
    const plotBox = document.createElement('div'), legendBox = document.createElement('div');
    legendBox.className = 'chart-legend';
    row.append(plotBox, legendBox);
    box.append(row);
    container.append(box);
    this.box = box;
    this.plot = new uPlot({
      width, height: 96,
      legend: { show: true, live: false, mount: (self, el) => legendBox.append(el) },
      cursor: { show: false },
      scales: { x: { time: false } },
      axes: [{ size: 22, font: '10px sans-serif', gap: 2 }, { size: 30, font: '10px sans-serif', gap: 2 }],
      series: [{ label: 't (s)' }, ...names.map((n, i) => ({ label: n, stroke: PALETTE[i % PALETTE.length], width: 1.5, points: { show: false } }))],
    }, this.data, plotBox);
  }
  // Replaces the data (the history); `cols` one array per series.
  load(time, cols) {
    this.data[0] = time.slice(-KEEP);
    cols.forEach((c, i) => { this.data[i + 1] = c.slice(-KEEP).map((v) => (Number.isFinite(v) ? v : null)); });
    this.dirty = true;
  }
  push(t, values) {
    const last = this.data[0].length ? this.data[0][this.data[0].length - 1] : -Infinity;
    if (t <= last) return;   // the history already has it (or a restart's history comes next)
    this.data[0].push(t);
    values.forEach((v, i) => this.data[i + 1].push(Number.isFinite(v) ? v : null));
    if (this.data[0].length > KEEP) for (const a of this.data) a.splice(0, a.length - KEEP);
    this.dirty = true;
  }
  clear() { for (const a of this.data) a.length = 0; this.dirty = true; }
  redraw() {
    if (!this.dirty) return;
    this.dirty = false;
    this.plot.setData(this.data);
  }
  resize(width) { this.plot.setSize({ width, height: 96 }); }
  destroy() { this.plot.destroy(); this.box.remove(); }
}

export class Plots {
  constructor() {
    this.counterTable = document.getElementById('counters');
    this.recordTable = document.getElementById('records');
    this.counterBox = document.getElementById('plot-counters');
    this.recordBox = document.getElementById('plot-records');
    this.charts = [];
    this.cells = {};
    this.lastDraw = 0;
    this.series = { time: [] };   // every column's points, for the rates per minute
    new ResizeObserver(() => this.resize()).observe(this.counterBox);
  }

  width() { return Math.max(160, (this.counterBox.clientWidth || 360) - 118); }
  resize() { for (const c of this.charts) c.chart.resize(this.width()); }

  row(table, name, key, title) {
    const tr = document.createElement('tr');
    const n = document.createElement('td');
    n.className = 'name';
    n.textContent = name;
    if (title) n.title = title;
    const v = document.createElement('td'), r = document.createElement('td');
    v.className = 'num';
    r.className = 'num rate';
    v.dataset.value = key;
    r.dataset.rate = key;
    tr.append(n, v, r);
    table.append(tr);
    return { value: v, rate: r };
  }

  setScene(scene) {
    for (const c of this.charts) c.chart.destroy();
    this.charts = [];
    this.counterTable.replaceChildren();
    this.recordTable.replaceChildren();
    this.cells = {};
    // Records of one column (one per line of a plant of several) are summed.
    this.columns = [];
    const byName = new Map();
    (scene.records ?? []).forEach((r, i) => {
      let c = byName.get(r.column);
      if (!c) { c = { name: r.column, type: r.type, records: [] }; byName.set(r.column, c); this.columns.push(c); }
      c.records.push(i);
    });
    const head = (table) => {
      const tr = document.createElement('tr');
      tr.className = 'head';
      tr.innerHTML = '<td></td><td class="num">total</td><td class="num">per min</td>';
      table.append(tr);
    };
    head(this.counterTable);
    for (const name of COUNTERS) this.cells[name] = this.row(this.counterTable, name.replace('_', ' '), name, name === 'removed' ? 'taken out by a hand' : '');
    if (this.columns.length) head(this.recordTable);
    for (const c of this.columns) c.cells = this.row(this.recordTable, c.name, c.name);
    this.charts.push({ chart: new Chart(this.counterBox, '', COUNTER_CHART.map((n) => n.replace('_', ' ')), this.width()), keys: COUNTER_CHART.map((n) => ['counter', n]) });
    for (const g of groupColumns(this.columns)) {
      this.charts.push({ chart: new Chart(this.recordBox, g.title, g.cols.map((c) => c.name), this.width()), keys: g.cols.map((c) => ['record', c]) });
    }
    this.series = { time: [], counter: Object.fromEntries(COUNTERS.map((n) => [n, []])), record: this.columns.map(() => []) };
  }

  valueOf(st, [kind, key]) {
    if (kind === 'counter') return Number(st.counters?.[key] ?? NaN);
    return key.records.reduce((s, i) => s + Number(st.records?.[i] ?? 0), 0);
  }

  // The run's series from t = 0 (a history message).
  setHistory(h) {
    const time = h.time ?? [];
    const counters = h.counters ?? {};
    const column = (c) => time.map((_, k) => c.records.reduce((s, i) => s + Number(h.records?.[i]?.[k] ?? 0), 0));
    this.series = { time: time.slice(), counter: Object.fromEntries(COUNTERS.map((n) => [n, (counters[n] ?? []).slice()])), record: this.columns.map(column) };
    for (const { chart, keys } of this.charts) {
      chart.load(time, keys.map(([kind, key]) => (kind === 'counter' ? this.series.counter[key] : this.series.record[this.columns.indexOf(key)])));
    }
    this.draw(true);
  }

  clear() {
    for (const c of this.charts) c.chart.clear();
    this.series.time = [];
  }

  // Events per minute over the last minute of simulated time (over what there is after the
  // first 10 s; nothing before).
  rate(values, t) {
    const times = this.series.time;
    const n = times.length;
    if (n < 2 || times[n - 1] !== t) return null;
    let k = n - 1;
    while (k > 0 && times[k - 1] >= t - 60) k--;
    const dt = t - times[k];
    return dt >= 10 ? ((values[n - 1] - values[k]) / dt) * 60 : null;
  }

  applyStatus(st) {
    if (!this.charts.length) return;
    const t = Number(st.time);
    const last = this.series.time.length ? this.series.time[this.series.time.length - 1] : -Infinity;
    if (t > last) {
      this.series.time.push(t);
      for (const n of COUNTERS) this.series.counter[n].push(Number(st.counters?.[n] ?? 0));
      this.columns.forEach((c, i) => this.series.record[i].push(this.valueOf(st, ['record', c])));
      if (this.series.time.length > 4 * KEEP) {   // a long session: the older half goes
        const cut = (a) => a.splice(0, a.length - 2 * KEEP);
        cut(this.series.time);
        for (const n of COUNTERS) cut(this.series.counter[n]);
        for (const a of this.series.record) cut(a);
      }
    }
    const fmt = (v) => (v === null || !Number.isFinite(v) ? '' : v >= 100 ? v.toFixed(0) : v.toFixed(1));
    for (const n of COUNTERS) {
      const c = this.cells[n];
      c.value.textContent = st.counters?.[n] ?? '–';
      c.rate.textContent = PER_MINUTE.has(n) ? fmt(this.rate(this.series.counter[n], t)) : '';
    }
    this.columns.forEach((c, i) => {
      const v = this.valueOf(st, ['record', c]);
      c.cells.value.textContent = Number.isFinite(v) ? +v.toPrecision(6) : '';
      c.cells.rate.textContent = c.type === 'void' ? fmt(this.rate(this.series.record[i], t)) : '';
    });
    for (const { chart, keys } of this.charts) chart.push(t, keys.map((k) => this.valueOf(st, k)));
    this.draw(false);
  }

  draw(now) {
    const t = performance.now();
    if (!now && t - this.lastDraw < 500) return;   // plots redraw at most twice a second
    this.lastDraw = t;
    for (const { chart } of this.charts) chart.redraw();
  }

  // For tests: the first and last time each chart has, and its series' names.
  summary() {
    return this.charts.map(({ chart }) => ({ names: chart.names, first: chart.data[0][0] ?? null, last: chart.data[0][chart.data[0].length - 1] ?? null, points: chart.data[0].length }));
  }
}
