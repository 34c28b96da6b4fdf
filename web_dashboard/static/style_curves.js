// Target-vs-achieved panels of a style-curve get-up (the trial's `curves` artifact, served parsed
// and checked by GET /api/trials/ID/curves; its format in tasks/getup_curves/README.md): one plot
// per feature — h (m), θ_x and θ_z (degrees) — over the episode's control time, one colour per
// recorded curve, its target p(s) dashed, the achieved feature solid, its control points as
// markers at the spline's Greville abscissae (the knot averages: where the control points of a
// straight curve lie on it). Shared by the trial page (every recorded episode) and the replay page
// (the episode of the motion shown, with a time marker that follows the replay).
'use strict';

podium.styleFeatures = [
  { key: 'h_m', name: 'h', unit: 'm', title: 'neck-base height h' },
  { key: 'theta_x_deg', name: 'θ_x', unit: '°', title: 'θ_x: side vector to up' },
  { key: 'theta_z_deg', name: 'θ_z', unit: '°', title: 'θ_z: front vector to up' },
];

// The Greville abscissae of a cubic B-spline with n control points on uniform knots clamped at both
// ends (tasks/getup_curves/style_curve.h: 0,0,0,0, 1/6 … 5/6, 1,1,1,1 for n = 9), in [0, 1].
podium.grevilleAbscissae = n => {
  const inner = Math.max(n - 3, 1);
  const knots = [0, 0, 0, 0, ...Array.from({ length: n - 4 }, (_, k) => (k + 1) / inner), 1, 1, 1, 1];
  return Array.from({ length: n }, (_, k) => (knots[k + 1] + knots[k + 2] + knots[k + 3]) / 3);
};

// Draws the panels into `holder` (replacing its children) for the episodes of `doc` whose indices
// `only` lists (all when null). marker(): a time (s) drawn as a vertical line, or null for none.
// Returns { plots, redraw() } (redraw: after the marker's time changed).
podium.styleCurvePanels = (holder, doc, { only = null, marker = null, width = 380, height = 220 } = {}) => {
  const episodes = (only ?? doc.episodes.map((_, k) => k)).map(k => ({ k, e: doc.episodes[k] }));
  const hooks = marker ? {
    draw: [u => {
      const t = marker();
      if (t === null || t === undefined) return;
      const x = u.valToPos(t, 'x', true), ctx = u.ctx;
      ctx.save();
      ctx.strokeStyle = '#263238'; ctx.lineWidth = 1;
      ctx.beginPath(); ctx.moveTo(x, u.bbox.top); ctx.lineTo(x, u.bbox.top + u.bbox.height); ctx.stroke();
      ctx.restore();
    }],
  } : undefined;
  holder.replaceChildren();
  const plots = podium.styleFeatures.map(f => {
    const panel = podium.el('div', { class: 'panel', id: `style-${f.key}`, 'data-style-feature': f.key });
    holder.append(panel);
    const series = [], lines = [];
    for (const { k, e } of episodes) {
      const colour = podium.colour(k), name = e.curve.name, points = e.curve.control_points[f.key];
      const at = podium.grevilleAbscissae(points.length).map(s => s * e.curve.duration_s);
      series.push({ label: `${name} target`, colour, dash: [6, 4] }, { label: `${name} achieved`, colour },
        { label: `${name} control points`, colour, points: true, size: 6 });
      lines.push({ x: e.t_s, y: e.target[f.key] }, { x: e.t_s, y: e.achieved[f.key] }, { x: at, y: points });
    }
    return podium.plot(panel, { title: f.title, x: { name: 't', unit: 's' }, y: { name: f.name, unit: f.unit }, series, width, height, hooks,
      legend: false }, podium.align(lines));
  });
  holder.append(podium.styleCurveLegend(episodes));
  return { plots, redraw() { for (const u of plots) u.redraw(false); } };
};

// One legend for the three plots: a row per curve in its colour, its target dashed, achieved solid,
// control points as a dot.
podium.styleCurveLegend = episodes => podium.el('div', { class: 'panel style-legend', id: 'style-legend' },
  ...episodes.map(({ k, e }) => {
    const colour = podium.colour(k);
    return podium.el('div', { 'data-curve': e.curve.name }, podium.el('b', {}, e.curve.name), ' ',
      podium.el('i', { class: 'line dashed', style: `border-color:${colour}` }), ' target ',
      podium.el('i', { class: 'line', style: `border-color:${colour}` }), ' achieved ',
      podium.el('i', { class: 'dot', style: `background:${colour}` }), ' control points');
  }));

// A caption for the panels: each episode's curve, T, start and outcome.
podium.styleCurveCaption = (doc, only = null) => (only ?? doc.episodes.map((_, k) => k)).map(k => {
  const e = doc.episodes[k], start = e.curve.start?.drop ? `${e.curve.start.drop} drop` : e.curve.start?.clip ? 'clip frame' : '';
  const outcome = e.success === undefined ? '' : e.success ? ', got up' : ', did not get up';
  return `${e.curve.name}: T = ${podium.num(e.curve.duration_s, 2)} s${start ? ', ' + start : ''}${outcome}`
    + (e.return === undefined ? '' : `, return ${podium.num(e.return, 3)}`);
}).join(' · ');
