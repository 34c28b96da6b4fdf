// Trial page: its name (stage/index), the earlier trials it was handed, the style curves' target and
// achieved features below the replay link (a `curves` artifact: style_curves.js), parameters,
// context, the result (the task's table, the raw JSON a click away), evaluation plots, learning and
// curriculum curves (metrics named "curriculum/..."), artifacts with download links, error,
// attempts and the end of its log.
'use strict';

const trialId = podium.param('id');
const plots = new Map();  // metric name -> uPlot

// Each metric as its description declares it (the API's "metrics": x axis, unit, kind, range; a
// metric the task did not declare is a learning curve over "step"): evaluations as points over
// their axis in their own section, learning curves as lines, curriculum curves ("curriculum/...")
// apart.
function renderCurves(series, declared) {
  const info = new Map(declared.map(m => [m.name, m]));
  const byName = new Map();
  for (const s of series) { if (!byName.has(s.name)) byName.set(s.name, []); byName.get(s.name).push(s); }
  document.getElementById('no-curves').hidden = byName.size > 0;
  const shown = { curves: false, evaluations: false, curriculum: false };
  for (const [name, attempts] of byName) {
    const m = info.get(name) || { name, x: { name: 'step' }, kind: 'learning_curve' };
    // One x axis for every attempt of the metric: the union of steps, gaps as null.
    const steps = [...new Set(attempts.flatMap(a => a.steps))].sort((a, b) => a - b);
    const data = [steps, ...attempts.map(a => {
      const values = new Map(a.steps.map((s, i) => [s, a.values[i]]));
      return steps.map(s => values.has(s) ? values.get(s) : null);
    })];
    const section = m.kind === 'evaluation' ? 'evaluations' : name.startsWith('curriculum') ? 'curriculum' : 'curves';
    shown[section] = true;
    const key = name + '#' + attempts.length;
    if (plots.has(key)) { plots.get(key).setData(data); continue; }
    const holder = podium.el('div', { class: 'panel', 'data-metric': name, 'data-kind': m.kind });
    document.getElementById(section).append(holder);
    const total = attempts.reduce((n, a) => n + a.total_points, 0);
    const rate = Array.isArray(m.range) && m.range[0] === 0 && m.range[1] === 1;
    plots.set(key, podium.plot(holder, {
      title: `${name}` + (total > data[0].length ? ` (${total} points, downsampled)` : ''),
      x: m.x, y: { name, unit: m.unit }, points: m.kind === 'evaluation', rate,
      series: attempts.map((a, i) => ({ label: `attempt ${a.attempt}`, colour: podium.colour(i) })),
    }, data));
    if (m.description) holder.append(podium.el('div', { class: 'muted caption' }, m.description));
  }
  document.getElementById('evaluations-title').hidden = !shown.evaluations;
  document.getElementById('curves-title').hidden = !shown.curves && shown.evaluations;
  document.getElementById('curriculum-title').hidden = !shown.curriculum;
}

async function refreshTrial() {
  const [t, series] = await Promise.all([podium.api(`/api/trials/${encodeURIComponent(trialId)}`),
    podium.api(`/api/trials/${encodeURIComponent(trialId)}/metrics?max_points=1000`)]);
  document.title = `Podium · trial ${t.name}`;
  document.getElementById('title').textContent = `Trial ${t.name}`;
  const crumb = document.getElementById('crumb-campaign');
  crumb.href = `campaign.html?id=${t.campaign_id}`; crumb.textContent = t.campaign_name;
  const names = t.feature_names;
  document.getElementById('summary').replaceChildren(
    podium.el('span', { class: 'state-' + t.state, id: 'state' }, t.state),
    ` · task ${t.task} · ${t.attempts} attempt(s) · seed ${t.seed}`,
    ` · ${t.objectives ? t.objectives.map((o, k) => `${t.objective_names[k] || 'objective ' + k} ${podium.num(o)}`).join(', ') : 'objective –'}`,
    ` · features ${t.features.map((f, k) => `${names[k] || 'f' + k}=${podium.num(f, 3)}`).join(' ') || '–'}`,
    ' · strategy ', t.strategy_label === null ? '–' : podium.el('span', { 'data-strategy': t.strategy }, podium.swatch(t.strategy_label), t.strategy_label),
    t.info?.step ? ` · BDS step ${t.info.step}` : '');
  // The earlier trials it was handed (its stage's inputs).
  document.getElementById('inputs-title').hidden = document.getElementById('inputs').hidden = !t.inputs.length;
  podium.fill(document.getElementById('inputs'), ['earlier trial', 'objective', 'strategy'],
    t.inputs.map(i => [i.id === null ? i.name : podium.trialLink(i.id, i.name), podium.num(i.objectives[0]), i.strategy_label ?? '–']));
  document.getElementById('error').textContent = t.error;
  document.getElementById('params').textContent = JSON.stringify(t.params, null, 2);
  document.getElementById('context').textContent = JSON.stringify(t.context, null, 2);
  document.getElementById('info').textContent = JSON.stringify(t.info, null, 2);
  renderResult(t);
  // Each artifact downloads under its own name: campaign, stage, trial index, artifact.
  podium.fill(document.getElementById('artifacts'), ['name', 'file', 'size', 'sha256'],
    t.artifacts.map(a => [a.name, podium.el('a', { href: a.url, download: a.download_name }, a.download_name), a.size_bytes,
      podium.el('code', {}, a.sha256)]));
  const trajectory = t.artifacts.some(a => a.name === 'trajectory');
  document.getElementById('replay-link').hidden = !trajectory;
  document.getElementById('replay-href').href = `replay.html?trial=${t.id}`;
  document.getElementById('replay-href').textContent = `3D replay of the recorded motion (${podium.motionLabel(t)})`;
  // Further recorded motions (a get-up evaluation's fast, slowed and paused runs), each beside the
  // main one.
  const others = t.artifacts.filter(a => a.name.startsWith('trajectory_'));
  const more = document.getElementById('replay-more');
  more.replaceChildren(...others.flatMap(a => [' · ', podium.link(
    `replay.html?trial=${t.id}:${encodeURIComponent(a.name)}&compare=${t.id}`,
    `${podium.motionLabel(t, a.name).slice(t.name.length + 3)} beside it`)]));
  podium.fill(document.getElementById('attempts'), ['#', 'state', 'worker', 'host', 'job', 'exit code', 'signal', 'started', 'finished', 'error'],
    t.attempt_list.map(a => [a.number, a.state, a.worker, a.host, a.job_id, a.exit_code ?? '–', a.signal ?? '–',
      podium.time(a.started_at), podium.time(a.finished_at), podium.el('span', { class: 'error' }, a.error)]));
  await renderStyleCurves(t);
  renderCurves(series, t.metrics || []);
  await renderLog(t.log_url);
}

// The style curves of a trial with a `curves` artifact: drawn once per artifact version (its hash).
let styleCurvesShown = null;
async function renderStyleCurves(t) {
  const artifact = t.artifacts.find(a => a.name === 'curves');
  document.getElementById('style-curves-section').hidden = !artifact;
  if (!artifact || styleCurvesShown === artifact.sha256) return;
  const doc = await podium.api(`/api/trials/${encodeURIComponent(t.id)}/curves`);
  podium.styleCurvePanels(document.getElementById('style-curves'), doc);
  document.getElementById('style-curves-caption').textContent =
    podium.styleCurveCaption(doc) + (doc.control_hz ? ` · at ${podium.num(doc.control_hz)} Hz control rate` : '');
  styleCurvesShown = artifact.sha256;
}

// The trial's result: the task's table when the result carries one, the raw JSON a click away
// (open when there is no table).
function renderResult(t) {
  document.getElementById('result').textContent = JSON.stringify(t.result_info, null, 2);
  const holder = document.getElementById('result-table');
  const tables = podium.resultTables(t);
  holder.replaceChildren(...tables);
  if (!tables.length && !holder.dataset.opened) { document.getElementById('result-raw').open = true; holder.dataset.opened = '1'; }
}

// The last 20 kB of the trial's log (every attempt's output, appended), refreshed with the page.
const kLogTail = 20000;
async function renderLog(url) {
  const note = document.getElementById('log-note'), pre = document.getElementById('log');
  const res = await fetch(url, { headers: { Range: `bytes=-${kLogTail}` } });
  if (res.status === 404) { note.textContent = 'No log yet.'; pre.textContent = ''; return; }
  if (!res.ok) throw new Error(`${url}: HTTP ${res.status}`);
  const total = Number((res.headers.get('Content-Range') || '').split('/')[1]) || null;
  note.replaceChildren(podium.link(url, 'trial.log'),
    total && total > kLogTail ? ` (its last ${kLogTail / 1000} kB of ${total} bytes)` : '');
  pre.textContent = await res.text();
}

podium.live(refreshTrial, e => { document.getElementById('title').textContent = e.message; });
