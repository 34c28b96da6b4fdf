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

  // Strategy colours (ids restart per stage, so a page colours one stage's ids): Tableau 10 for
  // ids 0-9, then golden-angle hues (137.5 degrees apart, three lightnesses), so no two ids share a
  // colour; pages also print the id beside every swatch.
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
