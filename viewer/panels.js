// Two panels of the page: what is forced now (status.forced: every forced slot, who forced
// it, since when, with a release button), and the notices (models the plant names that are
// not shown, and why), said once each.

function cell(text, cls) {
  const td = document.createElement('td');
  td.textContent = text;
  if (cls) td.className = cls;
  return td;
}

export class ForcedPanel {
  constructor(table, count, none, release, readOnly) {
    this.table = table;
    this.count = count;
    this.none = none;
    this.release = release;
    this.readOnly = readOnly;
    this.key = '';
  }

  apply(forced) {
    const key = JSON.stringify(forced);
    if (key === this.key) return;
    this.key = key;
    this.table.replaceChildren();
    for (const f of forced) {
      const tr = document.createElement('tr');
      tr.dataset.forced = f.path;
      const name = cell(f.path, 'name');
      name.title = `forced ${f.how} by ${f.by} since ${Number(f.since).toFixed(2)} s`;
      const how = cell(f.how, 'how');
      const who = cell(`${f.by}, ${Number(f.since).toFixed(1)} s`, 'kind');
      const act = document.createElement('td');
      if (!this.readOnly()) {
        const b = document.createElement('button');
        b.textContent = 'release';
        b.title = `release ${f.path}`;
        b.dataset.release = f.path;
        b.addEventListener('click', () => this.release(f.path));
        act.append(b);
      }
      tr.append(name, how, who, act);
      this.table.append(tr);
    }
    this.count.textContent = String(forced.length);
    this.count.classList.toggle('on', forced.length > 0);
    this.none.hidden = forced.length > 0;
  }
}

export class Notices {
  constructor(box, list) {
    this.box = box;
    this.listEl = list;
    this.seen = new Set();
    box.querySelector('button')?.addEventListener('click', () => { box.hidden = true; });
  }

  // The scene's model problems, once per scene.
  setScene(scene) {
    this.seen.clear();
    this.listEl.replaceChildren();
    this.box.hidden = true;
    const problems = scene.model_problems ?? [];
    if (problems.length) this.add(`${problems.length} model${problems.length > 1 ? 's' : ''} not shown (the bodies' shapes are drawn instead):`);
    for (const p of problems) this.add(`${p.model}: ${p.problem}`);
  }

  add(text) {
    if (this.seen.has(text)) return;
    this.seen.add(text);
    const li = document.createElement('li');
    li.textContent = text;
    this.listEl.append(li);
    this.box.hidden = false;
  }

  list() { return [...this.seen]; }
}

// The instructor's drills (docs/training.md, "Drills"): a line in the drill syntax
// ("when line[0].s2.seen >= 10 force line[0].s2.sw.reader.bottle open", "20s force …",
// "now …"), hidden from trainees unless unticked, sent as {type:"drill", line}; the list is
// status.drills (each with its state: waiting, holding, released, repaired, done, cancelled);
// a waiting drill has a *cancel* button, sent as {type:"drill", cancel: id}.
export class DrillsPanel {
  constructor(form, table, send) {
    this.table = table;
    this.send = send;
    this.key = '';
    this.line = form.querySelector('input[type=text]');
    this.hidden = form.querySelector('input[type=checkbox]');
    form.addEventListener('submit', (e) => {
      e.preventDefault();
      const text = this.line.value.trim();
      if (!text) return;
      send({ type: 'drill', line: (this.hidden.checked ? '' : 'shown ') + text });
      this.line.value = '';
    });
  }

  apply(drills) {
    const key = JSON.stringify(drills);
    if (key === this.key) return;
    this.key = key;
    this.table.replaceChildren();
    for (const d of drills) {
      const tr = document.createElement('tr');
      tr.dataset.drill = String(d.id);
      tr.dataset.state = d.state;
      const t = (x) => `${Number(x).toFixed(1)} s`;
      const when = d.state === 'cancelled' ? ` at ${t(d.ended)}` : d.fired < 0 ? '' : d.ended < 0 ? ` since ${t(d.fired)}` : ` (${t(d.fired)} to ${t(d.ended)})`;
      const act = document.createElement('td');
      if (d.state === 'waiting') {
        const b = document.createElement('button');
        b.textContent = 'cancel';
        b.className = 'drill-cancel';
        b.title = `drop drill ${d.id} before it fires`;
        b.addEventListener('click', () => this.send({ type: 'drill', cancel: d.id }));
        act.append(b);
      }
      tr.append(cell(`${d.id}`, 'kind'), cell(d.text, 'name'), cell(`${d.state}${when}${d.shown ? '' : ' · hidden'}`, 'kind'), act);
      tr.title = `by ${d.by}`;
      this.table.append(tr);
    }
  }
}
