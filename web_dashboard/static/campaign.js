// Campaign page: summary, stages, strategy-feature scatter (colour: strategy cluster; marker: BDS
// step), search history, strategy table, parallel coordinates, trial table with paging, events.
'use strict';

const campaignId = podium.param('id');
const base = `/api/campaigns/${encodeURIComponent(campaignId)}`;
const state = { detail: null, points: null, offset: 0, limit: 50, history: null };

function featureNames() {
  const d = state.detail.stages[0]?.description || {};
  return (d.features || []).map(f => f.name);
}

function renderSummary() {
  const c = state.detail;
  document.title = `Podium · ${c.name}`;
  document.getElementById('title').textContent = `${c.name} (#${c.id})`;
  document.getElementById('crumb').textContent = c.name;
  const s = document.getElementById('summary');
  s.replaceChildren(podium.el('span', { class: 'state-' + c.state }, c.state),
    ` · ${c.counts.done}/${c.budget_trials} done, ${c.counts.failed} failed, ${c.counts.running} running, ${c.counts.pending} pending`,
    ` · ${podium.num(c.trials_per_minute, 1)} trials/min · best objective ${podium.num(c.best_objective)}`,
    ` · ${c.strategies} strategies · seed ${c.seed}`, c.error ? podium.el('div', { class: 'error' }, c.error) : '');
  s.dataset.done = c.counts.done;
  podium.fill(document.getElementById('stages'),
    ['#', 'name', 'task', 'search', 'state', 'done', 'failed', 'running', 'budget', 'elapsed s'],
    c.stages.map(st => [st.index, st.name, st.task, st.algorithm, st.state, st.counts.done, st.counts.failed,
      st.counts.running, st.budget_trials, podium.num(st.elapsed_s, 1)]));
  const stageSelect = document.getElementById('f-stage');
  if (stageSelect.options.length === 1)
    for (const st of c.stages) stageSelect.append(podium.el('option', { value: st.index }, st.name));
}

// Strategy ids are per stage (each stage groups its own trials), so colours belong to
// (stage, id) pairs, numbered in stage-then-id order; scatter, legend, table and parallel
// coordinates all colour through here.
function indexStrategies() {
  const pairs = new Map();
  const cols = state.points.columns;
  for (let i = 0; i < cols.id.length; i++) if (cols.strategy[i] !== null) pairs.set(`${cols.stage[i]}:${cols.strategy[i]}`, [cols.stage[i], cols.strategy[i]]);
  for (const s of state.detail.strategy_table) pairs.set(`${s.stage}:${s.strategy}`, [s.stage, s.strategy]);
  const sorted = [...pairs.entries()].sort(([, a], [, b]) => a[0] - b[0] || a[1] - b[1]);
  state.strategies = sorted.map(([, pair]) => pair);
  state.strategyIndex = new Map(sorted.map(([key], k) => [key, k]));
}
function strategyColour(stage, strategy) {
  return podium.colour(strategy === null || strategy === undefined ? null : state.strategyIndex.get(`${stage}:${strategy}`));
}
function strategyLabel([stage, strategy]) {
  return state.detail.stages.length > 1 ? `${state.detail.stages[stage]?.name ?? stage} · strategy ${strategy}` : `strategy ${strategy}`;
}

// Axis choices: every feature, then the objective.
function axisValue(choice, i) {
  const cols = state.points.columns;
  return choice === 'objective' ? cols.objective[i] : cols.features[i][+choice];
}

function renderScatter() {
  const sx = document.getElementById('sx'), sy = document.getElementById('sy');
  if (sx.options.length === 0) {
    const names = featureNames();
    const opts = names.map((n, k) => [String(k), n]).concat([['objective', 'objective']]);
    for (const sel of [sx, sy]) for (const [v, n] of opts) sel.append(podium.el('option', { value: v }, n));
    sy.value = names.length > 1 ? '1' : 'objective';
    sx.onchange = sy.onchange = renderScatter;
  }
  const cols = state.points.columns, n = cols.id.length;
  const W = 480, H = 400, pad = 40;
  const canvas = document.getElementById('scatter');
  const ctx = podium.canvas(canvas, W, H);
  const xs = [], ys = [];
  for (let i = 0; i < n; i++) { xs.push(axisValue(sx.value, i)); ys.push(axisValue(sy.value, i)); }
  const finite = a => a.filter(v => v !== null && Number.isFinite(v));
  const range = a => { const f = finite(a); let lo = Math.min(...f), hi = Math.max(...f); if (!(hi > lo)) { lo -= 0.5; hi += 0.5; } return [lo, hi]; };
  const [x0, x1] = n ? range(xs) : [0, 1], [y0, y1] = n ? range(ys) : [0, 1];
  const px = v => pad + (v - x0) / (x1 - x0) * (W - 2 * pad), py = v => H - pad - (v - y0) / (y1 - y0) * (H - 2 * pad);
  ctx.strokeStyle = '#9e9e9e'; ctx.strokeRect(pad, pad, W - 2 * pad, H - 2 * pad);
  ctx.fillStyle = '#555'; ctx.font = '11px sans-serif';
  ctx.fillText(podium.num(x0, 2), pad, H - pad + 14); ctx.fillText(podium.num(x1, 2), W - pad - 20, H - pad + 14);
  ctx.fillText(podium.num(y0, 2), 2, H - pad); ctx.fillText(podium.num(y1, 2), 2, pad + 8);
  ctx.fillText(sx.options[sx.selectedIndex].text, W / 2 - 10, H - 8);
  ctx.save(); ctx.translate(12, H / 2); ctx.rotate(-Math.PI / 2); ctx.fillText(sy.options[sy.selectedIndex].text, 0, 0); ctx.restore();
  let drawn = 0;
  state.screen = [];
  for (let i = 0; i < n; i++) {
    if (xs[i] === null || ys[i] === null) continue;
    const x = px(xs[i]), y = py(ys[i]);
    ctx.fillStyle = strategyColour(cols.stage[i], cols.strategy[i]);
    ctx.strokeStyle = ctx.fillStyle;
    ctx.beginPath();
    if (cols.step[i] === 'diversity') {  // BDS diversity step: diamond
      ctx.moveTo(x, y - 4.5); ctx.lineTo(x + 4.5, y); ctx.lineTo(x, y + 4.5); ctx.lineTo(x - 4.5, y); ctx.closePath(); ctx.fill();
    } else if (cols.step[i] === 'explore') {  // BDS exploration step: ring
      ctx.arc(x, y, 3.5, 0, 2 * Math.PI); ctx.lineWidth = 1.5; ctx.stroke();
    } else {
      ctx.arc(x, y, 3, 0, 2 * Math.PI); ctx.fill();
    }
    state.screen.push([x, y, cols.id[i]]);
    drawn++;
  }
  canvas.dataset.points = drawn;
  document.getElementById('scatter-count').textContent =
    `${drawn} points` + (state.points.total > state.points.returned ? ` (every ${Math.ceil(state.points.total / state.points.returned)}th of ${state.points.total})` : '');
  const strategies = state.strategies;
  const legend = document.getElementById('legend');
  legend.replaceChildren(...strategies.slice(0, 20).map(p => podium.el('span', {}, podium.el('i', { style: `background:${strategyColour(...p)}` }), strategyLabel(p))));
  if (cols.step.some(s => s === 'explore' || s === 'diversity')) legend.append(podium.el('span', {}, '○ BDS exploration  ◆ BDS diversity'));
  if (!strategies.length) legend.append(podium.el('span', { class: 'muted' }, 'no strategy clusters yet'));
}

document.getElementById('scatter').addEventListener('click', ev => {
  const r = ev.target.getBoundingClientRect(), x = ev.clientX - r.left, y = ev.clientY - r.top;
  let best = null, bestD = 64;
  for (const [px, py, id] of state.screen || []) { const d = (px - x) ** 2 + (py - y) ** 2; if (d < bestD) { bestD = d; best = id; } }
  if (best !== null) location.href = `trial.html?id=${best}`;
});

function renderHistory() {
  const cols = state.points.columns, n = cols.id.length;
  const order = [...Array(n).keys()].sort((a, b) => cols.finished_at[a] - cols.finished_at[b]);  // points come in trial order
  const t0 = state.detail.started_at || (n ? cols.finished_at[order[0]] : 0);
  const t = [], obj = [], best = [];
  let b = -Infinity;
  for (const i of order) {
    t.push(cols.finished_at[i] - t0);
    obj.push(cols.objective[i]);
    if (cols.objective[i] !== null) b = Math.max(b, cols.objective[i]);
    best.push(Number.isFinite(b) ? b : null);
  }
  const data = [t, obj, best];
  if (state.history) { state.history.setData(data); return; }
  state.history = new uPlot({
    width: 480, height: 360, scales: { x: { time: false } },
    axes: [{ label: 'seconds since start' }, { label: 'objective' }],
    series: [{}, { label: 'objective', stroke: '#4e79a7', paths: () => null, points: { show: true, size: 4, fill: '#4e79a7' } },
      { label: 'best so far', stroke: '#e15759', width: 2 }],
  }, data, document.getElementById('history'));
}

function renderStrategies(list) {
  document.getElementById('no-strategies').hidden = list.length > 0;
  const names = featureNames();
  podium.fill(document.getElementById('strategies'), ['stage', 'strategy', 'trials', 'best objective', 'representative trial', 'features', ''],
    list.map(s => [s.stage, podium.el('span', {}, podium.el('i', { style: `display:inline-block;width:10px;height:10px;background:${strategyColour(s.stage, s.strategy)}` }), ` ${s.strategy}`),
      s.trials, podium.num(s.best_objective), podium.link(`trial.html?id=${s.representative_trial}`, `#${s.representative_trial}`),
      s.features.map((f, k) => `${names[k] || 'f' + k}=${podium.num(f, 3)}`).join(' '),
      podium.link(`replay.html?trial=${s.representative_trial}`, 'replay')]));
  if (list.length >= 2 && !document.getElementById('cmp-a').value) {
    document.getElementById('cmp-a').value = list[0].representative_trial;
    document.getElementById('cmp-b').value = list[1].representative_trial;
  }
}
document.getElementById('cmp-go').addEventListener('click', ev => {
  ev.preventDefault();
  location.href = `replay.html?trial=${encodeURIComponent(document.getElementById('cmp-a').value)}&compare=${encodeURIComponent(document.getElementById('cmp-b').value)}`;
});

// Parallel coordinates: one axis per parameter, then one per feature; one line per done trial.
function renderParallel(trials) {
  const W = 980, H = 260, pad = 30;
  const ctx = podium.canvas(document.getElementById('parallel'), W, H);
  if (!trials.length) return;
  const params = Object.keys(trials[0].params), names = featureNames();
  const axes = params.map(p => ({ name: p, get: t => t.params[p] }))
    .concat(names.map((n, k) => ({ name: n, get: t => t.features[k] })));
  for (const a of axes) {
    const v = trials.map(a.get).filter(Number.isFinite);
    a.lo = Math.min(...v); a.hi = Math.max(...v); if (!(a.hi > a.lo)) { a.lo -= 0.5; a.hi += 0.5; }
  }
  const ax = i => pad + i * (W - 2 * pad) / Math.max(1, axes.length - 1);
  ctx.globalAlpha = 0.35;
  for (const t of trials) {
    ctx.strokeStyle = strategyColour(t.stage, t.strategy);
    ctx.beginPath();
    axes.forEach((a, i) => { const y = H - pad - (a.get(t) - a.lo) / (a.hi - a.lo) * (H - 2 * pad); i ? ctx.lineTo(ax(i), y) : ctx.moveTo(ax(i), y); });
    ctx.stroke();
  }
  ctx.globalAlpha = 1; ctx.strokeStyle = '#333'; ctx.fillStyle = '#333'; ctx.font = '11px sans-serif';
  axes.forEach((a, i) => {
    ctx.beginPath(); ctx.moveTo(ax(i), pad); ctx.lineTo(ax(i), H - pad); ctx.stroke();
    ctx.fillText(a.name, ax(i) - 8, H - 8); ctx.fillText(podium.num(a.hi, 2), ax(i) + 3, pad); ctx.fillText(podium.num(a.lo, 2), ax(i) + 3, H - pad);
  });
}

async function renderTrials() {
  const q = new URLSearchParams({ offset: state.offset, limit: state.limit, order: document.getElementById('f-order').value,
    desc: document.getElementById('f-desc').checked ? '1' : '0' });
  for (const [key, id] of [['stage', 'f-stage'], ['state', 'f-state']]) {
    const v = document.getElementById(id).value; if (v !== '') q.set(key, v);
  }
  const page = await podium.api(`${base}/trials?${q}`);
  const names = state.detail.stages.map(s => s.name);
  document.getElementById('page').textContent = ` ${page.total ? state.offset + 1 : 0}–${state.offset + page.trials.length} of ${page.total} `;
  podium.fill(document.getElementById('trials'), ['stage', 'trial', 'state', 'attempts', 'objective', 'features', 'strategy', 'step', 'error'],
    page.trials.map(t => [names[t.stage], podium.link(`trial.html?id=${t.id}`, t.index), podium.el('span', { class: 'state-' + t.state }, t.state),
      t.attempts, podium.num(t.objectives?.[0]), t.features.map(f => podium.num(f, 3)).join(', '), t.strategy ?? '–',
      t.info?.step ?? '', t.error.slice(0, 80)]));
  state.total = page.total;
}
for (const id of ['f-stage', 'f-state', 'f-order', 'f-desc']) document.getElementById(id).addEventListener('change', () => { state.offset = 0; renderTrials(); });
document.getElementById('prev').onclick = () => { state.offset = Math.max(0, state.offset - state.limit); renderTrials(); };
document.getElementById('next').onclick = () => { if (state.offset + state.limit < state.total) { state.offset += state.limit; renderTrials(); } };

async function refreshCampaign() {
  const [detail, points, parallel, events] = await Promise.all([
    podium.api(base), podium.api(`${base}/points`),
    podium.api(`${base}/trials?limit=1000&order=index&state=done`), podium.api(`${base}/events?last=50`)]);
  state.detail = detail; state.points = points;
  indexStrategies();
  renderSummary(); renderScatter(); renderHistory(); renderStrategies(detail.strategy_table); renderParallel(parallel.trials);
  podium.fill(document.getElementById('events'), ['time', 'kind', 'details'],
    events.slice().reverse().map(e => [podium.time(e.time), e.kind, JSON.stringify(e.payload).slice(0, 160)]));
  await renderTrials();
}

podium.live(refreshCampaign, e => { document.getElementById('title').textContent = e.message; });
