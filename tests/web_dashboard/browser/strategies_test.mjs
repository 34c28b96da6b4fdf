// Strategies per stage in headless Chromium (setup: harness.mjs): a three-stage campaign whose
// first stage finds more than 10 strategies, the second is handed the best trial of each, the third
// fails. The campaign list counts strategies per stage; the scatter shows one stage, chosen with a
// selector (default: the latest stage with points); its legend lists every strategy of that stage
// in distinct colours, the same as the strategy table's; stage states, errors, hand-over and task
// configs are shown; trials are named "<stage>/<index>" and a trial links the trial it was handed.
import assert from 'node:assert/strict';
import { run, waitFor } from './harness.mjs';

const stage = (name, config, trials, extra = {}) =>
  ({ name, task: 'landscape', preset: 'smoke', config, search: { algorithm: 'random' }, budget: { trials }, ...extra });
const spec = {
  name: 'handover', seed: 5, workers: 2, retries: 0, trial_timeout_s: 30,
  stages: [
    stage('discover', { artifact: true, regions: 40 }, 40, { strategy_threshold: 0.05 }),
    stage('refine', { dim: 2 }, { per_input: 1 }, { inputs: { stage: 'discover', select: 'best_per_strategy', per_trial: 'each' } }),
    stage('broken', { failures: [{ mode: 'throw' }] }, 2, { inputs: { stage: 'refine', select: 'top', k: 2 } }),
  ],
};

run('strategies', async h => {
  const id = h.submit('handover', spec);
  h.podium(['run', '--workers', '2'], 1);  // the "broken" stage fails the campaign
  const { url, api } = await h.serve();
  const { page, external, problems } = await h.browse(url);
  const detail = await api(`/api/campaigns/${id}`);
  const strategiesOf = k => detail.strategy_table.filter(s => s.stage === k).map(s => s.strategy);
  assert.ok(strategiesOf(0).length > 10, `discover found only ${strategiesOf(0).length} strategies`);
  const step = name => console.log(`-- ${name}`);

  step('campaign list: strategies per stage, not summed');
  await page.goto(url);
  const row = page.locator('#campaigns tr', { hasText: 'handover' });
  await waitFor('campaign row', async () => (await row.count()) === 1);
  const perStage = detail.stages.map(s => `${s.name} ${strategiesOf(s.index).length}`).join(' · ');
  assert.equal(await row.locator('td').nth(9).innerText(), perStage);

  step('campaign page: the scatter shows the latest stage with points');
  await page.goto(`${url}campaign.html?id=${id}`);
  const scatter = page.locator('#scatter');
  await waitFor('scatter', async () => (await scatter.getAttribute('data-points')) !== null);
  assert.equal(await scatter.getAttribute('data-stage'), '1');
  assert.equal(await scatter.getAttribute('data-points'), String(detail.stages[1].counts.done));
  assert.equal(await page.locator('#legend span').count(), strategiesOf(1).length);

  step('stage selector: stage 0, every strategy in the legend, distinct colours');
  await page.selectOption('#scatter-stage', '0');
  await waitFor('stage 0 scatter', async () => (await scatter.getAttribute('data-stage')) === '0');
  assert.equal(await scatter.getAttribute('data-points'), String(detail.stages[0].counts.done));
  await waitFor('stage 0 legend', async () => (await page.locator('#legend').getAttribute('data-stage')) === '0');
  const legend = await page.$$eval('#legend span', spans => spans.map(s => ({
    id: Number(s.dataset.strategy), text: s.textContent, colour: getComputedStyle(s.querySelector('i')).backgroundColor })));
  assert.deepEqual(legend.map(e => e.id), strategiesOf(0), 'one legend entry per strategy of the stage, in label order');
  // Users read labels 1..n (in the order found), never the grid-cell ids the store keys them by.
  const labelOf = id => detail.strategy_table.find(s => s.stage === 0 && s.strategy === id).label;
  assert.deepEqual(legend.map(e => labelOf(e.id)), legend.map((e, k) => k + 1), 'labels 1..n');
  for (const e of legend) assert.match(e.text, new RegExp(`strategy ${labelOf(e.id)}\\b`), 'each entry names its label');
  assert.equal(new Set(legend.map(e => e.colour)).size, legend.length, `colours repeat: ${legend.map(e => e.colour)}`);
  const axes = await page.$$eval('#sx option', o => o.map(x => x.textContent));
  assert.deepEqual(axes, detail.stages[0].description.features.map(f => f.name).concat(['objective']));
  await waitFor('parallel coordinates of stage 0', async () => /discover/.test(await page.locator('#parallel-stage').innerText()));

  step('strategy table: the legend\'s colours, representatives named stage/index');
  const table = await page.$$eval('#strategies tr', rows => rows.slice(1).map(r => ({
    stage: r.cells[0].textContent, id: Number(r.cells[1].querySelector('span').dataset.strategy),
    label: Number(r.cells[1].textContent), colour: getComputedStyle(r.querySelector('i')).backgroundColor,
    representative: r.cells[4].textContent })));
  for (const e of legend) {
    const t = table.find(r => r.stage === 'discover' && r.id === e.id);
    assert.equal(t.colour, e.colour, `strategy ${e.id}: table and legend colours differ`);
    assert.equal(t.label, labelOf(e.id), `strategy ${e.id}: the table shows its label`);
    assert.match(t.representative, /^discover\/\d+$/);
  }

  step('stage table: states, the failed stage\'s error, hand-over');
  const stages = await page.$$eval('#stages tr', rows => rows.slice(1).map(r => [...r.cells].map(c => c.textContent)));
  assert.equal(stages[2][4], 'failed');
  assert.equal(stages[2][13], detail.stages[2].error);
  assert.match(stages[2][13], /all 2 trials failed/);
  assert.equal(stages[1][5], 'discover: best_per_strategy, per trial each');
  assert.equal(stages[1][6], String(strategiesOf(0).length));
  assert.equal(stages[2][5], 'refine: top 2, per trial all');
  assert.equal(stages[0][6], '–');
  assert.equal(await page.locator('details.config').count(), 3);
  assert.equal(await page.locator('details.config[open]').count(), 0, 'config blocks start collapsed');
  await page.locator('details.config summary').first().click();
  assert.match(await page.locator('details.config').first().innerText(), /family[\s\S]*one of basins/);

  step('trial names: the trial table and a trial page with its hand-over input');
  assert.equal(await page.locator('#trials tr').nth(1).locator('a').innerText(), 'discover/0');
  const refine = (await api(`/api/campaigns/${id}/trials?stage=1&limit=1`)).trials[0];
  const handed = (await api(`/api/trials/${refine.id}`)).inputs[0];
  await page.goto(`${url}trial.html?id=${refine.id}`);
  await waitFor('trial title', async () => (await page.locator('#title').innerText()) === 'Trial refine/0');
  const input = page.locator('#inputs a');
  assert.equal(await input.innerText(), handed.name);
  assert.equal(await input.getAttribute('href'), `trial.html?id=${handed.id}`);

  assert.deepEqual(external, [], 'requests left the machine');
  assert.deepEqual(problems, [], 'errors in the pages');
});
