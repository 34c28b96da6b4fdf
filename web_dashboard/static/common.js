// Shared helpers of every page: API access, live polling, formatting, colours, small DOM builders.
'use strict';

const podium = {
  async api(path) {
    const r = await fetch(path, { cache: 'no-store' });
    const body = await r.json();
    if (!r.ok) throw new Error(body.error || `${r.status} ${path}`);
    return body;
  },

  // Loads the page with refresh(), then calls it again whenever the database changed: GET
  // /api/version is one PRAGMA, and nothing else is fetched while nothing changes. The version is
  // recorded only after a successful refresh, so a change during a refresh is caught next tick.
  // window.podiumLive.refreshes counts refreshes (the browser tests read it).
  live(refresh, onError = null, interval_ms = 1000) {
    window.podiumLive = { refreshes: 0, version: null };
    const status = document.getElementById('live');
    let wait_ms = interval_ms;
    const tick = async () => {
      try {
        const v = (await podium.api('/api/version')).data_version;
        if (v !== window.podiumLive.version) {
          const start = performance.now();
          await refresh();
          // A page that is slow to build (a huge running campaign) is refreshed less often.
          wait_ms = Math.max(interval_ms, 3 * (performance.now() - start));
          window.podiumLive.version = v;
          window.podiumLive.refreshes++;
        }
        if (status) status.textContent = 'live · checked ' + new Date().toLocaleTimeString();
      } catch (e) {
        if (status) status.textContent = 'error: ' + e.message;
        if (onError) onError(e);
      }
      setTimeout(tick, wait_ms);
    };
    tick();
  },

  param(name) { return new URLSearchParams(location.search).get(name); },

  num(v, digits = 4) {
    if (v === null || v === undefined || Number.isNaN(v)) return '–';
    return Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(2) : (+v).toFixed(digits).replace(/\.?0+$/, '');
  },
  time(unix_s) { return unix_s > 0 ? new Date(unix_s * 1000).toLocaleString() : '–'; },

  // Strategy colours by label (1..n per stage, so a page colours one stage's strategies): Tableau 10
  // for 0-9, then golden-angle hues (137.5 degrees apart, three lightnesses), so no two labels share
  // a colour; pages also print the label beside every swatch.
  palette: ['#4e79a7', '#f28e2b', '#e15759', '#76b7b2', '#59a14f', '#edc948', '#b07aa1', '#ff9da7', '#9c755f', '#bab0ac'],
  colour(k) {
    if (k === null || k === undefined) return '#607d8b';
    if (k >= 0 && k < 10) return podium.palette[k];
    const j = Math.abs(k - 10);
    return `hsl(${((j * 137.508 + 20) % 360).toFixed(1)}, 62%, ${[42, 58, 32][j % 3]}%)`;
  },
  swatch(k) { return podium.el('i', { class: 'swatch', style: `background:${podium.colour(k)}` }); },

  // A trial's one name, as `podium trials` prints it: "<stage name>/<index in the stage>" (the
  // API's "name"); database ids appear in URLs only.
  trialName(stageName, index) { return `${stageName}/${index}`; },
  trialLink(id, name) { return podium.link(`trial.html?id=${id}`, name); },

  // "name (unit)", or the name alone for a count or a pure number.
  axisLabel(name, unit) { return unit ? `${name} (${unit})` : name; },

  // What a trial's recorded motion `artifact` shows, after the trial's name: a get-up evaluation
  // names each speed in its result info (`speeds`: name, κ, strength; `trajectory` is the one
  // speed without an artifact of its own), a Slower trial's motion is at its config's
  // slow_test_kappa; a style-curve get-up's motions by their curves (result info `recorded_curves`:
  // trajectory, trajectory_1, ... in order); other motions by their artifact ("fast" for trajectory_fast).
  motionLabel(t, artifact = 'trajectory') {
    const speeds = t.result_info?.speeds, n = v => podium.num(v, 3);
    let what = '';
    if (Array.isArray(speeds)) {
      const own = new Set((t.artifacts || []).map(a => a.name));
      const s = artifact === 'trajectory' ? speeds.find(x => !own.has(`trajectory_${x.name}`))
        : speeds.find(x => `trajectory_${x.name}` === artifact);
      if (s && s.strength > 0) what = s.name === 'fast' ? `fast (π_weak, β = ${n(s.strength)})` : `π_weak at β = ${n(s.strength)}`;
      else if (s) what = `${s.name === 'pause' ? 'paused' : 'slowed'}, κ = ${n(s.kappa)}`;
    } else if (artifact === 'trajectory' && t.task_config?.stage === 'slower' && t.task_config.slow_test_kappa) {
      what = `slowed, κ = ${n(t.task_config.slow_test_kappa)}`;
    }
    const curves = t.result_info?.recorded_curves, k = artifact === 'trajectory' ? 0 : Number(artifact.replace(/^trajectory_/, ''));
    if (!what && Array.isArray(curves) && typeof curves[k] === 'string') what = `curve ${curves[k]}`;
    if (!what && artifact !== 'trajectory') what = artifact.replace(/^trajectory_/, '');
    return what ? `${t.name} · ${what}` : t.name;
  },

  // el('td', {class: 'num'}, 'text', childNode, ...)
  el(tag, attrs = {}, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs)) {
      if (k === 'text') e.textContent = v; else e.setAttribute(k, v);
    }
    for (const c of children) e.append(c instanceof Node ? c : document.createTextNode(String(c)));
    return e;
  },
  link(href, text) { return podium.el('a', { href }, text); },

  // Replaces the rows of a table: rows is an array of arrays of cells (strings or nodes).
  fill(table, header, rows) {
    table.replaceChildren(podium.el('tr', {}, ...header.map(h => podium.el('th', {}, h))),
      ...rows.map(r => podium.el('tr', {}, ...r.map(c => podium.el('td', typeof c === 'number' ? { class: 'num' } : {}, c)))));
  },

  // A uPlot with named axes. o: { title, x: {name, unit}, y: {name, unit}, series: [{label, colour,
  // points?, size? (of its points), dash? (a line's dash pattern, e.g. [6, 4]), stepped? (a count that holds until its next point)}], points (true: each value a point, as an evaluation over its axis; false: lines, as a
  // learning curve; a series' own `points` overrides it), rate (a fraction: the y axis is [0, 1]), width, height, hooks (uPlot's), legend (false: none,
  // the caller draws its own) }. The legend is shown only to tell several series apart (names only, no empty live values). Registered in
  // window.podiumPlots with its axes' labels and its series (label, dash, points) as uPlot holds them (the browser tests read them).
  plot(holder, o, data) {
    const padded = (lo, hi, share) => {
      if (lo === null || hi === null || !Number.isFinite(lo) || !Number.isFinite(hi)) return [0, 1];
      const pad = hi > lo ? share * (hi - lo) : Math.max(Math.abs(lo) * 0.1, 0.5);
      return [lo - pad, hi + pad];
    };
    const series = o.series.map(s => (s.points ?? o.points)
      ? { label: s.label, stroke: s.colour, paths: () => null, points: { show: true, size: s.size ?? 9, fill: s.colour, stroke: s.colour } }
      : { label: s.label, stroke: s.colour, width: 1.5, spanGaps: true, points: { show: data[0].length < 3 },
        ...(s.dash ? { dash: s.dash } : {}), ...(s.stepped ? { paths: uPlot.paths.stepped({ align: 1 }) } : {}) });
    const u = new uPlot({
      title: o.title, width: o.width || 420, height: o.height || 240,
      legend: { show: o.legend !== false && o.series.length > 1, live: false },
      scales: {
        x: { time: false, range: o.points ? (_, lo, hi) => padded(lo, hi, 0.1) : undefined },
        y: { range: o.rate ? () => [0, 1] : (_, lo, hi) => padded(lo, hi, 0.05) },
      },
      axes: [{ label: podium.axisLabel(o.x.name, o.x.unit) }, { label: podium.axisLabel(o.y.name, o.y.unit), size: 60 }],
      series: [{ label: podium.axisLabel(o.x.name, o.x.unit) }, ...series],
      ...(o.hooks ? { hooks: o.hooks } : {}),
    }, data, holder);
    window.podiumPlots = window.podiumPlots || [];
    window.podiumPlots.push({ title: o.title, kind: o.points ? 'evaluation' : 'learning_curve', holder: holder.id || holder.dataset.metric || '',
      x: u.axes[0].label, y: u.axes[1].label, yRange: o.rate ? [0, 1] : null,
      series: u.series.slice(1).map((s, i) => ({ label: s.label, dash: s.dash?.length ? s.dash : null, points: !!(o.series[i].points ?? o.points) })) });
    return u;
  },

  // One stage's finished trials from a campaign's /points columns, in the order they finished:
  // { n, samples: trials done at each (the points are every k-th trial of a stage with more than
  // the server sends: each stands for k), finished_at, objective, best: best so far, strategies:
  // distinct strategies found so far }.
  stageSeries(points, stage, done) {
    const c = points.columns;
    const order = [...c.id.keys()].filter(i => c.stage[i] === stage).sort((a, b) => c.finished_at[a] - c.finished_at[b]);
    const per = order.length && done > order.length ? done / order.length : 1;
    const out = { n: order.length, samples: [], finished_at: [], objective: [], best: [], strategies: [] };
    const seen = new Set();
    let best = -Infinity;
    order.forEach((i, k) => {
      out.samples.push(Math.round((k + 1) * per));
      out.finished_at.push(c.finished_at[i]);
      out.objective.push(c.objective[i]);
      if (c.objective[i] !== null) best = Math.max(best, c.objective[i]);
      out.best.push(Number.isFinite(best) ? best : null);
      if (c.strategy[i] !== null) seen.add(c.strategy[i]);
      out.strategies.push(seen.size);
    });
    return out;
  },

  // A summary's discovery curve ([[samples, strategies], ...], orchestrator/summary.h) as {x, y}.
  discoverySeries(discovery) { return { x: discovery.map(p => p[0]), y: discovery.map(p => p[1]) }; },

  // "name (unit)" of a summary's named value ({"name", "unit"?}).
  named(e) { return podium.axisLabel(e.name, e.unit); },

  // Several (x, y) series on one x axis: the union of their xs, each y null where it has none.
  align(list) {
    const xs = [...new Set(list.flatMap(s => s.x))].sort((a, b) => a - b);
    return [xs, ...list.map(s => { const m = new Map(s.x.map((x, i) => [x, s.y[i]])); return xs.map(x => m.has(x) ? m.get(x) : null); })];
  },

  // A stage's primary objective's name (its description's first), "objective" if it has none.
  objectiveName(stage) { return stage?.description?.objectives?.[0] || 'objective'; },

  // A task's result table ({"title", "columns": [{"name", "unit"?}], "rows": [[cell, ...]]}, a
  // trial's RunResult::info["table"], or a stage's merged ones in the summary) as a titled HTML
  // table; a null cell was not measured.
  dataTable(t) {
    const table = podium.el('table', { class: 'result' });
    podium.fill(table, t.columns.map(c => podium.axisLabel(c.name, c.unit)),
      t.rows.map(r => r.map(c => c === null ? '–' : typeof c === 'number' ? podium.num(c) : c)));
    return podium.el('div', { class: 'result-table' }, podium.el('h3', {}, t.title), table);
  },
  // A trial's result tables (its result info's "table"), none if the task gives none.
  resultTables(t) {
    const table = t.result_info?.table;
    return table && Array.isArray(table.columns) && Array.isArray(table.rows) ? [podium.dataTable(table)] : [];
  },

  // A canvas sized for the device pixel ratio; returns its 2D context in CSS pixels.
  canvas(canvas, width, height) {
    const dpr = window.devicePixelRatio || 1;
    canvas.width = width * dpr; canvas.height = height * dpr;
    canvas.style.width = width + 'px'; canvas.style.height = height + 'px';
    const ctx = canvas.getContext('2d');
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    return ctx;
  },
};
