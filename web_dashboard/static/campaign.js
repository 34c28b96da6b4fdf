// Campaign page: the summary (per stage: trials, best trial by its named objective, strategies),
// stages (state, error, hand-over, task config), strategy-feature scatter of one stage (colour:
// strategy cluster; marker: BDS step), search history and discovery curve per stage, strategy
// table, parallel coordinates, trial table with paging, events.
'use strict';

const campaignId = podium.param('id');
const base = `/api/campaigns/${encodeURIComponent(campaignId)}`;
const state = { detail: null, points: null, offset: 0, limit: 50, history: null };

// The scatter and the parallel coordinates show one stage at a time: stages have their own
// features and parameters, and strategy ids restart per stage.
function featureNames(stage) {
  const d = state.detail.stages[stage]?.description || {};
  return (d.features || []).map(f => f.name);
}

function inputsText(inputs) {
  if (!inputs) return '–';
  const select = inputs.select === 'top' ? `top ${inputs.k}` : inputs.select;
  return `${inputs.stages.join(', ')}: ${select}, per trial ${inputs.per_trial}`;
}

function renderSummary() {
  const c = state.detail;
  document.title = `Podium · ${c.name}`;
  document.getElementById('title').textContent = `${c.name} (#${c.id})`;
  document.getElementById('crumb').textContent = c.name;
  const s = document.getElementById('summary');
  s.replaceChildren(podium.el('span', { class: 'state-' + c.state }, c.state),
    c.state === 'stopped' ? ' (no scheduler is running it: podium run resumes it)' : '',
    ` · ${c.counts.done}/${c.budget_trials} done, ${c.counts.failed} failed, ${c.counts.running} running, ${c.counts.pending} pending`,
    ` · ${podium.num(c.trials_per_minute, 1)} trials/min · seed ${c.seed}`,
    c.error ? podium.el('div', { class: 'error' }, c.error) : '');
  s.dataset.done = c.counts.done;
  podium.fill(document.getElementById('stages'),
    ['#', 'name', 'task', 'search', 'state', 'inputs', 'input trials', 'done', 'failed', 'running', 'budget', 'strategies', 'elapsed s', 'error'],
    c.stages.map(st => [st.index, st.name, st.task, st.algorithm, podium.el('span', { class: 'state-' + st.state }, st.state),
      inputsText(st.inputs), st.input_trials ?? '–', st.counts.done, st.counts.failed, st.counts.running, st.budget_trials,
      st.strategies, podium.num(st.elapsed_s, 1), podium.el('span', { class: 'error' }, st.error)]));
  const stageSelect = document.getElementById('f-stage');
  if (stageSelect.options.length === 1)
    for (const st of c.stages) stageSelect.append(podium.el('option', { value: st.index }, st.name));
  renderConfigs();
}

// Each stage's task config, collapsed: the keys the task accepts (its description's "config":
// key, type, default, allowed values) beside the value the stage runs with. Built once, so an
// opened block stays open across live refreshes.
function configRows(keys, values, prefix = '') {
  const rows = [];
  for (const k of keys || []) {
    const key = prefix + k.key, value = values?.[k.key];
    let type = k.type;
    if (k.type === 'array' && k.items) type = `array of ${k.items.type}s`;
    const allowed = k.choices ? `one of ${k.choices.join(', ')}` : rangeText(k.type === 'array' && k.items ? k.items : k);
    rows.push([key, type, k.required ? 'required' : JSON.stringify(k.default ?? null), allowed,
      value === undefined ? '' : JSON.stringify(value), k.doc || '']);
    if (k.keys) rows.push(...configRows(k.keys, value, key + '.'));
    if (k.items?.keys) rows.push(...configRows(k.items.keys, undefined, key + '[].'));
  }
  return rows;
}
function rangeText(k) {
  const lo = k.min !== undefined, hi = k.max !== undefined;
  if (lo && hi) return `${k.exclusive_min ? '(' : '['}${k.min}, ${k.max}]`;
  if (lo) return `${k.exclusive_min ? '>' : '≥'} ${k.min}`;
  return hi ? `≤ ${k.max}` : '';
}
function renderConfigs() {
  const holder = document.getElementById('stage-configs');
  if (holder.children.length) return;
  for (const st of state.detail.stages) {
    const keys = st.description.config || [];
    const table = podium.el('table');
    podium.fill(table, ['key', 'type', 'default', 'allowed', 'value', ''], configRows(keys, st.task_config));
    holder.append(podium.el('details', { class: 'config', 'data-stage': st.index },
      podium.el('summary', {}, `${st.name}: task config of ${st.task} (${keys.length} keys)`), table));
  }
}

// The stage the scatter shows: the one chosen, else the latest stage with points.
function scatterStage() {
  const select = document.getElementById('scatter-stage');
  if (select.options.length !== state.detail.stages.length) {
    select.replaceChildren(...state.detail.stages.map(st => podium.el('option', { value: st.index }, st.name)));
    select.onchange = () => { state.chosenStage = +select.value; state.axesStage = null; renderStage(); };
  }
  if (state.chosenStage === undefined) {
    const withPoints = state.points.columns.stage;
    select.value = withPoints.length ? Math.max(...withPoints) : 0;
  }
  return +select.value;
}

// A strategy as users read it: its label (1..n per stage in the order the strategies were found;
// the strategy table's "label"), the store's id staying the key. A strategy the table does not yet
// list (points read a moment later) shows its id.
function strategyLabel(stage, id) {
  if (id === null || id === undefined) return null;
  const s = state.detail.strategy_table.find(x => x.stage === stage && x.strategy === id);
  return s ? s.label : `#${id}`;
}
const strategyColour = (stage, id) => { const l = strategyLabel(stage, id); return podium.colour(typeof l === 'number' ? l : null); };

// The strategies of a stage: every id its points or its strategy table rows carry, in label order.
function stageStrategies(stage) {
  const cols = state.points.columns, trials = new Map();
  for (let i = 0; i < cols.id.length; i++) if (cols.stage[i] === stage && cols.strategy[i] !== null) trials.set(cols.strategy[i], null);
  for (const s of state.detail.strategy_table) if (s.stage === stage) trials.set(s.strategy, s.trials);
  const order = id => { const l = strategyLabel(stage, id); return typeof l === 'number' ? l : Infinity; };
  return [...trials.entries()].sort((a, b) => order(a[0]) - order(b[0]) || a[0] - b[0]);
}

// Axis choices: every feature of the shown stage, then the objective.
function axisValue(choice, i) {
  const cols = state.points.columns;
  return choice === 'objective' ? cols.objective[i] : cols.features[i][+choice];
}

function renderScatter() {
  const stage = scatterStage(), stageName = state.detail.stages[stage]?.name ?? String(stage);
  const sx = document.getElementById('sx'), sy = document.getElementById('sy');
  if (state.axesStage !== stage) {  // features differ between stages
    state.axesStage = stage;
    const names = featureNames(stage);
    const opts = names.map((n, k) => [String(k), n]).concat([['objective', 'objective']]);
    for (const sel of [sx, sy]) sel.replaceChildren(...opts.map(([v, n]) => podium.el('option', { value: v }, n)));
    sy.value = names.length > 1 ? '1' : 'objective';
    sx.onchange = sy.onchange = renderScatter;
  }
  const cols = state.points.columns;
  const shown = [...cols.id.keys()].filter(i => cols.stage[i] === stage);
  const W = 480, H = 400, pad = 40;
  const canvas = document.getElementById('scatter');
  const ctx = podium.canvas(canvas, W, H);
  const xs = shown.map(i => axisValue(sx.value, i)), ys = shown.map(i => axisValue(sy.value, i));
  const finite = a => a.filter(v => v !== null && v !== undefined && Number.isFinite(v));
  // Padded by a tenth of the range each side, so no point sits on the frame.
  const range = a => {
    const f = finite(a); let lo = Math.min(...f), hi = Math.max(...f);
    const pad = hi > lo ? 0.1 * (hi - lo) : Math.max(0.5, 0.1 * Math.abs(lo));
    return [lo - pad, hi + pad];
  };
  const [x0, x1] = finite(xs).length ? range(xs) : [0, 1], [y0, y1] = finite(ys).length ? range(ys) : [0, 1];
  const px = v => pad + (v - x0) / (x1 - x0) * (W - 2 * pad), py = v => H - pad - (v - y0) / (y1 - y0) * (H - 2 * pad);
  ctx.strokeStyle = '#9e9e9e'; ctx.strokeRect(pad, pad, W - 2 * pad, H - 2 * pad);
  ctx.fillStyle = '#555'; ctx.font = '11px sans-serif';
  ctx.fillText(podium.num(x0, 2), pad, H - pad + 14); ctx.fillText(podium.num(x1, 2), W - pad - 20, H - pad + 14);
  ctx.fillText(podium.num(y0, 2), 2, H - pad); ctx.fillText(podium.num(y1, 2), 2, pad + 8);
  ctx.fillText(sx.options[sx.selectedIndex]?.text ?? '', W / 2 - 10, H - 8);
  ctx.save(); ctx.translate(12, H / 2); ctx.rotate(-Math.PI / 2); ctx.fillText(sy.options[sy.selectedIndex]?.text ?? '', 0, 0); ctx.restore();
  state.screen = [];
  shown.forEach((i, k) => {
    if (!Number.isFinite(xs[k]) || !Number.isFinite(ys[k])) return;
    const x = px(xs[k]), y = py(ys[k]);
    ctx.fillStyle = ctx.strokeStyle = strategyColour(stage, cols.strategy[i]);
    ctx.beginPath();
    if (cols.step[i] === 'diversity') {  // BDS diversity step: diamond
      ctx.moveTo(x, y - 4.5); ctx.lineTo(x + 4.5, y); ctx.lineTo(x, y + 4.5); ctx.lineTo(x - 4.5, y); ctx.closePath(); ctx.fill();
    } else if (cols.step[i] === 'explore') {  // BDS exploration step: ring
      ctx.arc(x, y, 3.5, 0, 2 * Math.PI); ctx.lineWidth = 1.5; ctx.stroke();
    } else {
      ctx.arc(x, y, 3, 0, 2 * Math.PI); ctx.fill();
    }
    state.screen.push({ x, y, id: cols.id[i], name: podium.trialName(stageName, cols.index[i]), strategy: strategyLabel(stage, cols.strategy[i]) });
  });
  canvas.dataset.points = state.screen.length;
  canvas.dataset.stage = stage;
  const done = state.detail.stages[stage]?.counts.done ?? shown.length;
  document.getElementById('scatter-count').textContent =
    `${state.screen.length} points` + (done > shown.length && shown.length ? ` (every ${Math.ceil(done / shown.length)}th of ${done})` : '');
  const strategies = stageStrategies(stage);
  const legend = document.getElementById('legend');
  legend.dataset.stage = stage;
  legend.replaceChildren(...strategies.map(([id, trials]) => {
    const label = strategyLabel(stage, id);
    return podium.el('span', { 'data-strategy': id, 'data-label': label, title: `${stageName} · strategy ${label}` },
      podium.el('i', { class: 'swatch', style: `background:${strategyColour(stage, id)}` }), `strategy ${label}` + (trials === null ? '' : ` (${trials})`));
  }));
  if (shown.some(i => cols.step[i] === 'explore' || cols.step[i] === 'diversity')) legend.append(podium.el('div', {}, '○ BDS exploration  ◆ BDS diversity'));
  if (!strategies.length) legend.append(podium.el('div', { class: 'muted' }, 'no strategy clusters in this stage yet'));
}

function nearestPoint(ev) {
  const r = ev.target.getBoundingClientRect(), x = ev.clientX - r.left, y = ev.clientY - r.top;
  let best = null, bestD = 64;
  for (const p of state.screen || []) { const d = (p.x - x) ** 2 + (p.y - y) ** 2; if (d < bestD) { bestD = d; best = p; } }
  return best;
}
const scatter = document.getElementById('scatter');
scatter.addEventListener('click', ev => { const p = nearestPoint(ev); if (p) location.href = `trial.html?id=${p.id}`; });
scatter.addEventListener('mousemove', ev => {
  const p = nearestPoint(ev);
  const text = p ? `trial ${p.name} · strategy ${p.strategy ?? '–'}` : '\u00a0';
  document.getElementById('scatter-hover').textContent = text;
  scatter.title = p ? text : '';
});

// Search history, one plot per stage (stages have their own objectives): each finished trial's
// objective against the time since the campaign started, and the best so far.
function renderHistory() {
  const holder = document.getElementById('history'), stages = state.detail.stages;
  const t0 = state.detail.started_at;
  state.history = state.history || new Map();
  for (const st of stages) {
    const series = podium.stageSeries(state.points, st.index, st.counts.done);
    if (!series.n) continue;
    const start = t0 || series.finished_at[0];
    const data = [series.finished_at.map(t => t - start), series.objective, series.best];
    if (state.history.has(st.index)) { state.history.get(st.index).setData(data); continue; }
    const box = podium.el('div', { 'data-stage': st.index });
    holder.append(box);
    const objective = podium.objectiveName(st);
    state.history.set(st.index, podium.plot(box, {
      title: `${st.name}: ${objective}`, width: 420, height: 220,
      x: { name: 'time since the campaign started', unit: 's' }, y: { name: objective },
      series: [{ label: objective, colour: '#4e79a7', points: true, size: 4 }, { label: 'best so far', colour: '#e15759' }],
    }, data));
  }
}

// Discovery: per stage with strategy features, the distinct strategies found against the trials
// done (the summary's exact step curve), one line per stage on one plot (ids restart per stage:
// each line counts its own stage's).
function renderDiscovery(summary) {
  const stages = summary.stages.filter(st => st.features.length);
  const list = stages.map(st => podium.discoverySeries(st.discovery));
  const holder = document.getElementById('discovery');
  holder.dataset.stages = stages.map(st => st.name).join(',');
  holder.dataset.strategies = list.map(l => l.y[l.y.length - 1] ?? 0).join(',');
  if (!stages.length) {
    if (state.discovery !== null) holder.replaceChildren(podium.el('p', { class: 'muted' }, 'No stage has strategy features.'));
    state.discovery = null;
    return;
  }
  const data = podium.align(list);
  const key = stages.map(st => st.index).join(',');
  if (state.discovery?.key === key) { state.discovery.plot.setData(data); return; }
  holder.replaceChildren();
  state.discovery = { key, plot: podium.plot(holder, {
    title: 'distinct strategies', x: { name: 'trials done (samples)' }, y: { name: 'distinct strategies' },
    series: stages.map(st => ({ label: st.name, colour: podium.colour(st.index), stepped: true })),
  }, data) };
}

// The summary (store/summary.h, as `podium summary` prints it): per stage the trials done,
// the best trial by its named objective, the strategies found with their representatives, and the
// task's result tables of the stage's trials.
function renderSummaryPanel(summary) {
  const c = state.detail;
  document.getElementById('compare-link').href = `compare.html?campaigns=${c.id}`;
  const representatives = st => st.strategies.slice(0, 6).map(x => x.representative.trial).join(', ') + (st.strategies.length > 6 ? ', …' : '');
  podium.fill(document.getElementById('summary-stages'), ['stage', 'task', 'trials done', 'failed', 'best trial', 'by', 'value', 'strategies', 'representatives'],
    summary.stages.map(st => {
      const best = st.best, objective = best?.objectives[0] ?? st.objectives[0];
      return [st.name, st.task, `${st.trials.done}/${st.trials.budget}`, st.trials.failed,
        best ? podium.trialLink(best.id, best.trial) : '–', objective ? podium.named(objective) : '–',
        best ? podium.num(best.objectives[0]?.value) : '–', st.features.length ? st.strategies.length : '–', representatives(st) || '–'];
    }));
  const tables = document.getElementById('summary-tables');
  const key = JSON.stringify(summary.stages.map(st => st.tables));
  if (tables.dataset.key === key) return;  // unchanged: keep the DOM (and a reader's selection)
  tables.dataset.key = key;
  tables.replaceChildren(...summary.stages.flatMap(st => st.tables.map(t => {
    const block = podium.dataTable({ ...t, title: `${st.name}: ${t.title}` });
    block.dataset.stage = st.name;
    return block;
  })));
}

// Every stage's strategies, grouped by stage (the same id in two stages is two strategies).
function renderStrategies(list) {
  document.getElementById('no-strategies').hidden = list.length > 0;
  const stages = state.detail.stages;
  window.podiumStrategies = { list, stages };  // for gallery.js
  document.dispatchEvent(new CustomEvent('podium-strategies', { detail: window.podiumStrategies }));
  // A technique column when a task names its strategies' nearest captured technique; a replay
  // link only for a representative that recorded a motion.
  const techniques = list.some(s => s.technique);
  podium.fill(document.getElementById('strategies'), ['stage', 'strategy', 'trials', 'best objective', 'representative trial', 'features',
    ...(techniques ? ['nearest captured technique'] : []), ''],
    list.map(s => {
      const names = featureNames(s.stage);
      return [stages[s.stage]?.name ?? s.stage, podium.el('span', { 'data-strategy': s.strategy }, podium.swatch(s.label), ` ${s.label}`),
        s.trials, `${podium.objectiveName(stages[s.stage])} ${podium.num(s.best_objective)}`,
        podium.trialLink(s.representative_trial, s.representative_name),
        s.features.map((f, k) => `${names[k] || 'f' + k}=${podium.num(f, 3)}`).join(' '),
        ...(techniques ? [s.technique ?? '–'] : []),
        s.motion ? podium.link(`replay.html?trial=${s.representative_trial}`, 'replay') : ''];
    }));
  const moving = list.filter(s => s.motion);
  document.getElementById('cmp-controls').hidden = moving.length < 2;
  if (moving.length >= 2 && !document.getElementById('cmp-a').value) {
    document.getElementById('cmp-a').value = moving[0].representative_trial;
    document.getElementById('cmp-b').value = moving[1].representative_trial;
  }
}
document.getElementById('cmp-go').addEventListener('click', ev => {
  ev.preventDefault();
  location.href = `replay.html?trial=${encodeURIComponent(document.getElementById('cmp-a').value)}&compare=${encodeURIComponent(document.getElementById('cmp-b').value)}`;
});

// Parallel coordinates of the scatter's stage: one axis per parameter, then one per feature; one
// line per done trial (the stage's first 1,000).
function renderParallel(stage, trials) {
  const W = 980, H = 280, pad = 30, bottom = 48;
  const ctx = podium.canvas(document.getElementById('parallel'), W, H);
  document.getElementById('parallel-stage').textContent = `· stage ${state.detail.stages[stage]?.name ?? stage}`;
  if (!trials.length) return;
  const params = Object.keys(trials[0].params), names = featureNames(stage);
  const axes = params.map(p => ({ name: p, get: t => t.params[p] }))
    .concat(names.map((n, k) => ({ name: n, get: t => t.features[k] })));
  for (const a of axes) {
    const v = trials.map(a.get).filter(Number.isFinite);
    a.lo = Math.min(...v); a.hi = Math.max(...v); if (!(a.hi > a.lo)) { a.lo -= 0.5; a.hi += 0.5; }
  }
  const left = 50, right = 50;  // room for the first and last axes' labels
  const ax = i => left + i * (W - left - right) / Math.max(1, axes.length - 1);
  const yOf = (a, v) => H - bottom - (v - a.lo) / (a.hi - a.lo) * (H - bottom - pad);
  ctx.globalAlpha = 0.35;
  for (const t of trials) {
    ctx.strokeStyle = strategyColour(t.stage, t.strategy);
    ctx.beginPath();
    axes.forEach((a, i) => { const y = yOf(a, a.get(t)); i ? ctx.lineTo(ax(i), y) : ctx.moveTo(ax(i), y); });
    ctx.stroke();
  }
  ctx.globalAlpha = 1; ctx.strokeStyle = '#333'; ctx.fillStyle = '#333'; ctx.font = '11px sans-serif';
  // Labels centred under their axes, on two rows when neighbours would touch; none is cut.
  const gap = axes.length > 1 ? ax(1) - ax(0) : W;
  const tight = axes.some(a => ctx.measureText(a.name).width + 6 > gap);
  const placed = [];
  axes.forEach((a, i) => {
    ctx.beginPath(); ctx.moveTo(ax(i), pad); ctx.lineTo(ax(i), H - bottom); ctx.stroke();
    const width = ctx.measureText(a.name).width;
    const x = Math.min(W - width - 2, Math.max(2, ax(i) - width / 2)), y = H - bottom + 16 + (tight && i % 2 ? 14 : 0);
    ctx.textAlign = 'left';
    ctx.fillText(a.name, x, y);
    placed.push({ name: a.name, left: x, right: x + width });
    ctx.fillText(podium.num(a.hi, 2), ax(i) + 3, pad); ctx.fillText(podium.num(a.lo, 2), ax(i) + 3, H - bottom);
  });
  window.podiumParallel = { width: W, labels: placed };  // the browser tests check that none is cut
}

async function renderTrials() {
  const q = new URLSearchParams({ offset: state.offset, limit: state.limit, order: document.getElementById('f-order').value,
    desc: document.getElementById('f-desc').checked ? '1' : '0' });
  for (const [key, id] of [['stage', 'f-stage'], ['state', 'f-state']]) {
    const v = document.getElementById(id).value; if (v !== '') q.set(key, v);
  }
  const page = await podium.api(`${base}/trials?${q}`);
  document.getElementById('page').textContent = ` ${page.total ? state.offset + 1 : 0}–${state.offset + page.trials.length} of ${page.total} `;
  // The objective by its stage's name for it: the table may list several stages.
  podium.fill(document.getElementById('trials'), ['trial', 'state', 'attempts', 'objective', 'features', 'strategy', 'step', 'error'],
    page.trials.map(t => [podium.trialLink(t.id, t.name), podium.el('span', { class: 'state-' + t.state }, t.state),
      t.attempts, t.objectives ? `${podium.objectiveName(state.detail.stages[t.stage])} ${podium.num(t.objectives[0])}` : '–',
      t.features.map(f => podium.num(f, 3)).join(', '), strategyLabel(t.stage, t.strategy) ?? '–',
      t.info?.step ?? '', t.error.slice(0, 80)]));
  state.total = page.total;
}
for (const id of ['f-stage', 'f-state', 'f-order', 'f-desc']) document.getElementById(id).addEventListener('change', () => { state.offset = 0; renderTrials(); });
document.getElementById('prev').onclick = () => { state.offset = Math.max(0, state.offset - state.limit); renderTrials(); };
document.getElementById('next').onclick = () => { if (state.offset + state.limit < state.total) { state.offset += state.limit; renderTrials(); } };

// What follows the stage selector: the scatter with its legend, and the parallel coordinates.
async function renderStage() {
  renderScatter();
  const stage = scatterStage();
  const parallel = await podium.api(`${base}/trials?limit=1000&order=index&state=done&stage=${stage}`);
  if (stage === scatterStage()) renderParallel(stage, parallel.trials);
}

async function refreshCampaign() {
  const [detail, points, events, summary] = await Promise.all([
    podium.api(base), podium.api(`${base}/points`), podium.api(`${base}/events?last=50`), podium.api(`${base}/summary`)]);
  state.detail = detail; state.points = points;
  renderSummary(); renderSummaryPanel(summary); await renderStage(); renderHistory(); renderDiscovery(summary);
  renderStrategies(detail.strategy_table);
  podium.fill(document.getElementById('events'), ['time', 'kind', 'details'],
    events.slice().reverse().map(e => [podium.time(e.time), e.kind, JSON.stringify(e.payload).slice(0, 160)]));
  await renderTrials();
}

podium.live(refreshCampaign, e => { document.getElementById('title').textContent = e.message; });
