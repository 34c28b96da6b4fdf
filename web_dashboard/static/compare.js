// Comparison of campaigns (compare.html?campaigns=1,2,...: ids or names): which search found more
// distinct strategies, and how fast. From /api/compare (orchestrator::compare_campaigns, as
// `podium summary A B` prints it): per stage of each campaign a table row (trials, best trial by
// its named objective, strategies), per stage name every campaign's discovery curve (distinct
// strategies against trials done) on one plot, and the task's result tables side by side; from
// each campaign's points, its best-so-far curve per stage name.
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

function renderPlots(comparison, byName) {
  const discovery = document.getElementById('compare-discovery'), best = document.getElementById('compare-best');
  discovery.replaceChildren(); best.replaceChildren();
  window.podiumPlots = [];
  const label = (name, id) => `${name} (#${id})`;
  for (const stage of comparison.stages) {
    const curves = stage.curves.filter(c => c.discovery.length);
    if (!curves.length) continue;
    const box = podium.el('div', { class: 'panel', 'data-stage': stage.name });
    discovery.append(box);
    podium.plot(box, {
      title: `${stage.name}: distinct strategies`, x: { name: 'trials done (samples)' }, y: { name: 'distinct strategies' },
      series: curves.map((c, i) => ({ label: label(c.campaign_name, c.campaign), colour: podium.colour(i), stepped: true })),
    }, podium.align(curves.map(c => podium.discoverySeries(c.discovery))));
  }
  for (const [name, list] of byName) {
    const box = podium.el('div', { class: 'panel', 'data-stage': name });
    best.append(box);
    const objective = [...new Set(list.map(e => podium.objectiveName(e.stage)))].join(' / ');
    podium.plot(box, {
      title: `${name}: best so far`, x: { name: 'trials done (samples)' }, y: { name: objective },
      series: list.map((e, i) => ({ label: label(e.campaign.name, e.campaign.id), colour: podium.colour(i) })),
    }, podium.align(list.map(e => ({ x: e.series.samples, y: e.series.best }))));
  }
}

// The campaigns' result tables, per stage name side by side.
function renderTables(comparison) {
  const holder = document.getElementById('compare-tables');
  holder.replaceChildren();
  for (const stage of comparison.stages) {
    const blocks = comparison.campaigns.flatMap(c => (c.stages.find(st => st.name === stage.name)?.tables || [])
      .map(t => podium.dataTable({ ...t, title: `${c.campaign.name} · ${stage.name}: ${t.title}` })));
    if (blocks.length) holder.append(podium.el('div', { class: 'row', 'data-stage': stage.name }, ...blocks));
  }
  document.getElementById('compare-tables-title').hidden = !holder.children.length;
}

async function refreshCompare() {
  const all = await podium.api('/api/campaigns');
  if (!document.querySelector('#picker input')) renderPicker(all);
  const ids = chosen();
  document.getElementById('none').hidden = ids.length >= 2;
  const [comparison, campaigns] = await Promise.all([
    ids.length ? podium.api(`/api/compare?campaigns=${ids.map(encodeURIComponent).join(',')}`) : { campaigns: [], stages: [] },
    Promise.all(ids.map(async id => {
      const base = `/api/campaigns/${encodeURIComponent(id)}`;
      const [detail, points] = await Promise.all([podium.api(base), podium.api(`${base}/points`)]);
      return { detail, points };
    }))]);
  document.title = `Podium · compare ${campaigns.map(c => c.detail.name).join(', ')}`;
  document.getElementById('title').textContent = `Compare ${campaigns.map(c => `${c.detail.name} (#${c.detail.id})`).join(' · ') || 'campaigns'}`;
  podium.fill(document.getElementById('compare-table'),
    ['campaign', 'stage', 'task', 'search', 'trials done', 'best trial', 'by', 'value', 'strategies'],
    comparison.campaigns.flatMap(c => c.stages.map(st => {
      const best = st.best, objective = best?.objectives[0] ?? st.objectives[0];
      return [podium.link(`campaign.html?id=${c.campaign.id}`, c.campaign.name), st.name, st.task, st.algorithm,
        `${st.trials.done}/${st.trials.budget}`, best ? podium.trialLink(best.id, best.trial) : '–', objective ? podium.named(objective) : '–',
        best ? podium.num(best.objectives[0]?.value) : '–', st.features.length ? st.strategies.length : '–'];
    })));
  renderPlots(comparison, stagesByName(campaigns));
  renderTables(comparison);
  window.podiumCompare = { campaigns: campaigns.map(c => c.detail.id) };
}

podium.live(refreshCompare, e => { document.getElementById('title').textContent = e.message; });
