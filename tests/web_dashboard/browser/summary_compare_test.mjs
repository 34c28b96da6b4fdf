// What a researcher reads on the dashboard, in headless Chromium (setup: harness.mjs): a small
// demo-like campaign (the shipped get-up pair evaluated at smoke size, fast and slowed, then a
// smoke Weaker training stage) and two landscape searches. Asserted: the campaign page's summary
// panel rows and the task's table (as /api/campaigns/ID/summary, podium summary's document, has
// them), the trial page's table in place of the JSON dump; named axes with units on a learning curve and on an evaluation plot (drawn as
// points, in its own section; a rate on [0, 1]); replay labels with the trial name and κ; the
// breadcrumb naming the campaign; artifacts downloading under distinct names; no replay link on a
// landscape campaign; the discovery curve; parallel-coordinates labels inside the canvas; the
// index page's best trial per stage; the comparison view with two campaigns.
// Environment (besides harness.mjs's): PODIUM_SOURCE_DIR, the repository (the shipped policies).
import assert from 'node:assert/strict';
import { join } from 'node:path';

import { run, waitFor } from './harness.mjs';

const policies = join(process.env.PODIUM_SOURCE_DIR, 'tasks', 'getup', 'policies');
const demo = {
  name: 'getup-mini', seed: 2026, workers: 2, retries: 0, trial_timeout_s: 120,
  stages: [
    { name: 'standing', task: 'getup', preset: 'smoke', search: { algorithm: 'random' }, budget: { trials: 1 },
      config: { stage: 'evaluate', shipped: [{ weak_policy: join(policies, 'weaker_standing.pt'), weak_strength: 0.6,
        slow_policy: join(policies, 'slower_standing.pt') }] } },
    { name: 'train', task: 'getup', preset: 'smoke', search: { algorithm: 'random' }, budget: { trials: 1 }, config: { stage: 'weaker' } },
  ],
};
const landscape = (name, algorithm) => ({
  name, seed: 11, workers: 2, retries: 0, trial_timeout_s: 30,
  stages: [{ name: 'explore', task: 'landscape', preset: 'smoke', config: { family: 'plateaus', landscape_seed: 3, artifact: true },
    search: { algorithm }, budget: { trials: 24 } }],
});

run('summary', async h => {
  const getup = h.submit('getup', demo);
  const random = h.submit('random', landscape('landscape-random', 'random'));
  const bds = h.submit('bds', landscape('landscape-bds', 'bds'));
  h.podium(['run', '--workers', '2']);
  const { url, api } = await h.serve();
  const { page, external, problems } = await h.browse(url);
  const step = name => console.log(`-- ${name}`);
  const detail = await api(`/api/campaigns/${getup}`);
  const [standing] = (await api(`/api/campaigns/${getup}/trials?stage=0&limit=1`)).trials;
  const [train] = (await api(`/api/campaigns/${getup}/trials?stage=1&limit=1`)).trials;
  for (const t of [standing, train]) assert.equal(t.state, 'done', `${t.name}: ${t.error}`);

  step('campaign page: the summary panel, a row per stage and the task\'s table');
  const summary = await api(`/api/campaigns/${getup}/summary`);  // podium summary --json's document
  await page.goto(`${url}campaign.html?id=${getup}`);
  const rows = () => page.$$eval('#summary-stages tr', r => r.slice(1).map(row => [...row.cells].map(c => c.textContent)));
  await waitFor('summary rows', async () => (await rows()).length === 2);
  const [first, second] = await rows();
  assert.deepEqual(first.slice(0, 7), ['standing', 'getup', '1/1', '0', 'standing/0', 'slow_success_rate',
    String(Number(standing.objectives[0].toFixed(4)))]);
  assert.equal(first[7], String(detail.stages[0].strategies));
  assert.equal(first[8], summary.stages[0].strategies.map(s => s.representative.trial).join(', '));
  assert.deepEqual(second.slice(0, 6), ['train', 'getup', '1/1', '0', 'train/0', 'success_rate']);
  assert.equal(await page.locator('#crumb').innerText(), 'getup-mini');
  const [evaluation] = summary.stages[0].tables;  // speed × rose / stood / rise time / COM error
  const shownTable = page.locator('#summary-tables .result-table[data-stage="standing"]');
  assert.equal(await shownTable.locator('h3').innerText(), `standing: ${evaluation.title}`);
  const cells = await shownTable.locator('tr').evaluateAll(r => r.map(row => [...row.cells].map(c => c.textContent)));
  assert.deepEqual(cells[0], evaluation.columns.map(c => c.unit ? `${c.name} (${c.unit})` : c.name));
  assert.deepEqual(cells.slice(1).map(r => r.slice(0, 2)), evaluation.rows.map(r => r.slice(0, 2)));
  assert.ok(cells.slice(1).some(r => /^κ 0\.5$/.test(r[1])), `speeds: ${cells.map(r => r[1])}`);

  step('trial page: the task\'s table in place of the JSON dump, an evaluation plot over κ with units');
  await page.goto(`${url}trial.html?id=${standing.id}`);
  await waitFor('evaluation plots', async () => (await page.locator('#evaluations .uplot').count()) > 0);
  const trialTable = await page.locator('#result-table tr').evaluateAll(r => r.map(row => [...row.cells].map(c => c.textContent)));
  assert.equal(trialTable.length, evaluation.rows.length + 1);
  assert.equal(await page.locator('#result').isVisible(), false, 'the raw JSON is one click away, not shown');
  await page.locator('#result-raw summary').click();
  assert.deepEqual(JSON.parse(await page.locator('#result').innerText()), standing.result_info);
  assert.equal(await page.locator('#crumb-campaign').innerText(), 'getup-mini');
  const plots = () => page.evaluate(() => window.podiumPlots);
  const rise = (await plots()).find(p => p.title === 'eval/rise_time_s');
  assert.deepEqual([rise.kind, rise.x, rise.y], ['evaluation', 'κ', 'eval/rise_time_s (s)']);
  assert.equal(await page.locator('#evaluations [data-metric="eval/rise_time_s"]').count(), 1);
  assert.equal(await page.locator('#curves .uplot').count(), 0, 'an evaluation is not a learning curve');
  const success = (await plots()).find(p => p.title === 'eval/success_rate');
  assert.deepEqual(success.yRange, [0, 1]);
  assert.equal(await page.locator('#evaluations .u-legend').count(), 0, 'a single series needs no legend');

  step('trial page: artifacts download under distinct names; replay links name κ');
  const downloads = await page.$$eval('#artifacts a', a => a.map(x => x.getAttribute('download')));
  assert.ok(downloads.length >= 3, `artifacts: ${downloads}`);
  assert.equal(new Set(downloads).size, downloads.length, `download names repeat: ${downloads}`);
  for (const name of downloads) assert.match(name, /^getup-mini_standing-0_/);
  const href = await page.locator('#artifacts a').first().getAttribute('href');
  const disposition = (await page.request.get(new URL(href, url).href)).headers()['content-disposition'];
  assert.equal(disposition, `attachment; filename="${downloads[0]}"`);
  assert.match(await page.locator('#replay-href').innerText(), /standing\/0 · slowed, κ = 0\.5/);

  step('replay: the label is the trial name and its κ');
  await page.goto(`${url}replay.html?trial=${standing.id}&compare=${standing.id}:trajectory_fast`);
  await waitFor('replay frames', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 2));
  assert.deepEqual(await page.evaluate(() => window.podiumReplay.labels),
    ['standing/0 · slowed, κ = 0.5', 'standing/0 · fast (π_weak, β = 0.6)']);
  assert.match(await page.locator('#viewports .label').first().innerText(), /^standing\/0 · slowed, κ = 0\.5$/);
  assert.equal(await page.locator('#crumb-trial').innerText(), 'standing/0');
  assert.equal(await page.locator('#crumb-campaign').innerText(), 'getup-mini');

  step('trial page: a learning curve over environment steps with its unit');
  await page.goto(`${url}trial.html?id=${train.id}`);
  await waitFor('learning curves', async () => (await page.locator('#curves .uplot').count()) > 0);
  const wall = (await plots()).find(p => p.title === 'time/wall_s');
  assert.deepEqual([wall.kind, wall.x, wall.y], ['learning_curve', 'environment steps', 'time/wall_s (s)']);
  assert.deepEqual((await plots()).find(p => p.title === 'success_rate').yRange, [0, 1]);
  assert.equal(await page.locator('#evaluations-title').isVisible(), false);

  step('landscape campaign: no replay link, the discovery curve, parallel labels inside the canvas');
  await page.goto(`${url}campaign.html?id=${random}`);
  await waitFor('strategy rows', async () => (await page.locator('#strategies tr').count()) > 1);
  const landscapeDetail = await api(`/api/campaigns/${random}`);
  assert.equal(await page.locator('#strategies a[href^="replay.html"]').count(), 0);
  assert.equal(await page.locator('#cmp-controls').isVisible(), false);
  await waitFor('the gallery\'s note', () => page.locator('#no-gallery').isVisible());
  assert.equal(await page.locator('#gallery .card').count(), 0, 'no replay card without a motion');
  await waitFor('discovery curve', async () => (await page.locator('#discovery .uplot').count()) === 1);
  assert.equal(await page.locator('#discovery').getAttribute('data-strategies'), String(landscapeDetail.stages[0].strategies));
  const discovery = (await plots()).find(p => p.title === 'distinct strategies');
  assert.deepEqual([discovery.x, discovery.y], ['trials done (samples)', 'distinct strategies']);
  await waitFor('parallel coordinates', () => page.evaluate(() => window.podiumParallel?.labels.length > 0));
  const { width, labels } = await page.evaluate(() => window.podiumParallel);
  for (const l of labels) assert.ok(l.left >= 0 && l.right <= width, `label ${l.name} cut: ${l.left}..${l.right} of ${width}`);

  step('index page: the best trial per stage, by its objective\'s name');
  await page.goto(url);
  const row = page.locator('#campaigns tr', { hasText: 'getup-mini' });
  await waitFor('campaign row', async () => (await row.count()) === 1);
  assert.match(await row.locator('td').nth(8).innerText(), /^standing: slow_success_rate [\d.]+ \(standing\/0\) · train: success_rate [\d.–]+ \(train\/0\)$/);

  step('comparison view: two campaigns\' tables and curves overlaid');
  await page.goto(`${url}compare.html?campaigns=${random},${bds}`);
  await waitFor('comparison', () => page.evaluate(() => window.podiumCompare?.campaigns.length === 2));
  await waitFor('comparison table', async () => (await page.locator('#compare-table tr').count()) === 3);
  const table = await page.$$eval('#compare-table tr', r => r.slice(1).map(row => [...row.cells].map(c => c.textContent)));
  assert.deepEqual(table.map(r => r.slice(0, 5)), [['landscape-random', 'explore', 'landscape', 'random', '24/24'],
    ['landscape-bds', 'explore', 'landscape', 'bds', '24/24']]);
  const bdsDetail = await api(`/api/campaigns/${bds}`);
  assert.deepEqual(table.map(r => r[8]), [String(landscapeDetail.stages[0].strategies), String(bdsDetail.stages[0].strategies)]);
  assert.equal(await page.locator('#compare-discovery .uplot').count(), 1);
  const legend = await page.locator('#compare-discovery .u-legend').innerText();
  assert.match(legend, /landscape-random \(#\d+\)[\s\S]*landscape-bds \(#\d+\)/);
  assert.equal(await page.locator('#picker input:checked').count(), 2);

  assert.deepEqual(external, [], 'requests left the machine');
  assert.deepEqual(problems, [], 'errors in the pages');
});
