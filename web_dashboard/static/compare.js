// Comparison of campaigns (compare.html?campaigns=1,2,...: ids or names): which search found more
// distinct strategies, and how fast. Per stage of each campaign a table row (trials, best trial
// by its named objective, strategies); per stage name, every campaign's discovery curve
// (distinct strategies against trials done) and best-so-far curve on one plot.
'use strict';

const chosen = () => (podium.param('campaigns') || '').split(',').map(s => s.trim()).filter(Boolean);
const shown = { key: null, plots: [] };

function renderPicker(all) {
  const picked = new Set(chosen());
  const picker = document.getElementById('picker');
  picker.replaceChildren('campaigns:', ...all.map(c => podium.el('label', {},
    podium.el('input', Object.assign({ type: 'checkbox', value: c.id, 'data-name': c.name },
      picked.has(String(c.id)) || picked.has(c.name) ? { checked: '' } : {})), ` ${c.name} (#${c.id})`)));
  picker.onchange = () => {
    const ids = [...picker.querySelectorAll('input:checked')].map(i => i.value);
    history.replaceState(null, '', `compare.html?campaigns=${ids.join(',')}`);
    refreshCompare();
  };
}

// Each campaign's stages by name, for the plots: name -> [{ campaign, stage, series }].
function stagesByName(campaigns) {
  const byName = new Map();
  for (const { detail, points } of campaigns)
    for (const st of detail.stages) {
      if (!byName.has(st.name)) byName.set(st.name, []);
      byName.get(st.name).push({ campaign: detail, stage: st, series: podium.stageSeries(points, st.index, st.counts.done) });
    }
  return byName;
}

function renderPlots(byName) {
  const discovery = document.getElementById('compare-discovery'), best = document.getElementById('compare-best');
  discovery.replaceChildren(); best.replaceChildren();
  window.podiumPlots = [];
  for (const [name, list] of byName) {
    const label = e => `${e.campaign.name} (#${e.campaign.id})`;
    const colour = (_, i) => podium.colour(i);
    const withFeatures = list.filter(e => (e.stage.description?.features || []).length);
    if (withFeatures.length) {
      const box = podium.el('div', { class: 'panel', 'data-stage': name });
      discovery.append(box);
      podium.plot(box, {
        title: `${name}: distinct strategies`, x: { name: 'trials done (samples)' }, y: { name: 'distinct strategies' },
        series: withFeatures.map((e, i) => ({ label: label(e), colour: colour(e, i) })),
      }, podium.align(withFeatures.map(e => ({ x: e.series.samples, y: e.series.strategies }))));
    }
    const box = podium.el('div', { class: 'panel', 'data-stage': name });
    best.append(box);
    const objective = [...new Set(list.map(e => podium.objectiveName(e.stage)))].join(' / ');
    podium.plot(box, {
      title: `${name}: best so far`, x: { name: 'trials done (samples)' }, y: { name: objective },
      series: list.map((e, i) => ({ label: label(e), colour: colour(e, i) })),
    }, podium.align(list.map(e => ({ x: e.series.samples, y: e.series.best }))));
  }
}

async function refreshCompare() {
  const all = await podium.api('/api/campaigns');
  if (!document.querySelector('#picker input')) renderPicker(all);
  const ids = chosen();
  document.getElementById('none').hidden = ids.length >= 2;
  const campaigns = await Promise.all(ids.map(async id => {
    const base = `/api/campaigns/${encodeURIComponent(id)}`;
    const [detail, points] = await Promise.all([podium.api(base), podium.api(`${base}/points`)]);
    return { detail, points };
  }));
  document.title = `Podium · compare ${campaigns.map(c => c.detail.name).join(', ')}`;
  document.getElementById('title').textContent = `Compare ${campaigns.map(c => `${c.detail.name} (#${c.detail.id})`).join(' · ') || 'campaigns'}`;
  podium.fill(document.getElementById('compare-table'),
    ['campaign', 'stage', 'task', 'search', 'trials done', 'best trial', 'by', 'value', 'strategies'],
    campaigns.flatMap(({ detail }) => detail.stages.map(st => [podium.link(`campaign.html?id=${detail.id}`, detail.name), st.name, st.task,
      st.algorithm, `${st.counts.done}/${st.budget_trials}`, st.best ? podium.trialLink(st.best.id, st.best.name) : '–',
      st.best?.objective ?? podium.objectiveName(st), st.best ? podium.num(st.best.value) : '–', st.strategies])));
  renderPlots(stagesByName(campaigns));
  window.podiumCompare = { campaigns: campaigns.map(c => c.detail.id) };
}

podium.live(refreshCompare, e => { document.getElementById('title').textContent = e.message; });
