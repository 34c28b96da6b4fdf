// Campaign list: state, stages, progress, trials per minute, the best trial and strategies per
// stage (stages have their own objectives and strategy ids: never one number across them).
'use strict';

// Strategy ids restart per stage: "explore 29 · refine 22", never their sum.
function strategiesPerStage(c) { return c.stages.map(s => `${s.name} ${s.strategies}`).join(' · '); }
// "standing: slow_success_rate 0.6 (standing/0)" per stage with a done trial.
function bestPerStage(c) {
  const shown = c.stages.filter(s => s.best);
  if (!shown.length) return '–';
  return podium.el('span', {}, ...shown.flatMap((s, k) => [k ? ' · ' : '', `${s.name}: ${s.best.objective} ${podium.num(s.best.value)} (`,
    podium.trialLink(s.best.id, s.best.name), ')']));
}

async function refreshList() {
  const campaigns = await podium.api('/api/campaigns');
  document.getElementById('empty').hidden = campaigns.length > 0;
  const rows = campaigns.slice().reverse().map(c => {
    const bar = podium.el('span', { class: 'bar' }, podium.el('span', { style: `width:${Math.min(100, 100 * c.progress)}%` }));
    return [c.id, podium.link(`campaign.html?id=${c.id}`, c.name), podium.el('span', { class: 'state-' + c.state }, c.state),
      c.stages.map(s => `${s.name} (${s.task}, ${s.algorithm})`).join(' → '),
      podium.el('span', {}, bar, ` ${c.counts.done}/${c.budget_trials}`), c.counts.failed, c.counts.running,
      podium.num(c.trials_per_minute, 1), bestPerStage(c), strategiesPerStage(c), podium.time(c.created_at)];
  });
  podium.fill(document.getElementById('campaigns'),
    ['id', 'name', 'state', 'stages', 'progress', 'failed', 'running', 'trials/min', 'best per stage', 'strategies', 'created'], rows);
}

podium.live(refreshList);
