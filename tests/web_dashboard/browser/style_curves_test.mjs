// The style curves' panels in headless Chromium (setup: harness.mjs): one getup_curves train trial
// at the smoke preset records both shipped curves (faceup, facedown) with its `curves` artifact.
// Asserted: the trial page draws three plots — h (m), θ_x (°), θ_z (°) over t (s) — each with, per
// curve, a dashed target, a solid achieved line and its control points, in the curve's colour on
// the canvas, with one legend naming them; the average return rate is a learning curve on [0, 1]
// among the metrics; the replay page plots the shown motion's episode beside the 3D view. With
// PODIUM_SCREENSHOT_DIR set, the trial page's panels and the replay are saved there as PNGs.
import assert from 'node:assert/strict';
import { join } from 'node:path';

import { run, waitFor } from './harness.mjs';

const spec = {
  name: 'curves-mini', seed: 5, workers: 1, retries: 0, trial_timeout_s: 300,
  stages: [{ name: 'train', task: 'getup_curves', preset: 'smoke', config: { stage: 'train' },
    search: { algorithm: 'random' }, budget: { trials: 1 } }],
};
const features = [['h_m', 'h (m)'], ['theta_x_deg', 'θ_x (°)'], ['theta_z_deg', 'θ_z (°)']];

run('style-curves', async h => {
  const id = h.submit('curves', spec);
  h.podium(['run', '--workers', '1']);
  const { url, api } = await h.serve();
  const { page, external, problems } = await h.browse(url);
  const step = name => console.log(`-- ${name}`);
  const [trial] = (await api(`/api/campaigns/${id}/trials?limit=1`)).trials;
  assert.equal(trial.state, 'done', `${trial.name}: ${trial.error}`);
  const doc = await api(`/api/trials/${trial.id}/curves`);
  const names = doc.episodes.map(e => e.curve.name);
  assert.deepEqual(names, ['faceup', 'facedown']);
  const shots = process.env.PODIUM_SCREENSHOT_DIR;

  step('trial page: three plots, per curve a dashed target, a solid achieved line and control points');
  await page.setViewportSize({ width: 1300, height: 900 });
  await page.goto(`${url}trial.html?id=${trial.id}`);
  await waitFor('style curve plots', async () => (await page.locator('#style-curves .uplot').count()) === 3);
  const plots = (await page.evaluate(() => window.podiumPlots)).filter(p => p.holder.startsWith('style-'));
  assert.deepEqual(plots.map(p => p.holder), features.map(([key]) => `style-${key}`));
  for (const [k, p] of plots.entries()) {
    assert.equal(p.x, 't (s)');
    assert.equal(p.y, features[k][1]);
    assert.deepEqual(p.series.map(s => s.label), names.flatMap(n => [`${n} target`, `${n} achieved`, `${n} control points`]));
    for (const [i, s] of p.series.entries()) {
      const role = ['target', 'achieved', 'control points'][i % 3];
      if (role === 'target') assert.ok(Array.isArray(s.dash) && s.dash.length >= 2 && !s.points, `${p.y}: ${s.label} is not dashed`);
      if (role === 'achieved') assert.ok(!s.dash && !s.points, `${p.y}: ${s.label} is not solid`);
      if (role === 'control points') assert.ok(s.points, `${p.y}: ${s.label} are not points`);
    }
  }
  // One legend for the three plots: per curve its name, a dashed target sample and a solid achieved
  // one in its colour; and each curve's colour (podium.colour(0), (1)) is drawn on every plot.
  assert.equal(await page.locator('#style-curves .u-legend').count(), 0, 'one legend, not one per plot');
  const legend = await page.$$eval('#style-legend [data-curve]', rows => rows.map(r => ({
    curve: r.dataset.curve, lines: [...r.querySelectorAll('i.line')].map(i => [getComputedStyle(i).borderTopStyle, getComputedStyle(i).borderTopColor]),
  })));
  assert.deepEqual(legend.map(r => r.curve), names);
  const rgb = hex => `rgb(${[1, 3, 5].map(i => parseInt(hex.slice(i, i + 2), 16)).join(', ')})`;
  const colours = await page.evaluate(() => [0, 1].map(k => podium.colour(k)));
  for (const [k, r] of legend.entries()) assert.deepEqual(r.lines, [['dashed', rgb(colours[k])], ['solid', rgb(colours[k])]]);
  const drawn = await page.$$eval('#style-curves .uplot canvas', (canvases, hex) => canvases.map(c => hex.map(h => {
    const [r, g, b] = [1, 3, 5].map(i => parseInt(h.slice(i, i + 2), 16));
    const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 0; i < data.length; i += 4)
      if (Math.abs(data[i] - r) < 8 && Math.abs(data[i + 1] - g) < 8 && Math.abs(data[i + 2] - b) < 8) n++;
    return n;
  })), colours);
  console.log(`   pixels of each curve's colour per plot: ${JSON.stringify(drawn)}`);
  for (const counts of drawn) for (const n of counts) assert.ok(n > 50, `a curve's colour on a plot: ${JSON.stringify(drawn)}`);
  assert.match(await page.locator('#style-curves-caption').innerText(), /faceup: T = 3\.77 s, supine drop/);
  if (shots) await page.locator('#style-curves-section').screenshot({ path: join(shots, 'style_curves.png') });

  step('trial page: the average return rate among the learning curves, on [0, 1]');
  await waitFor('learning curves', async () => (await page.locator('#curves [data-metric="test/average_return_rate"]').count()) === 1);
  const rate = (await page.evaluate(() => window.podiumPlots)).find(p => p.title === 'test/average_return_rate');
  assert.deepEqual([rate.kind, rate.yRange], ['learning_curve', [0, 1]]);

  step('trial page: the replay links name each motion\'s curve');
  assert.match(await page.locator('#replay-href').innerText(), /train\/0 · curve faceup\)$/);
  assert.equal(await page.locator('#replay-more a').innerText(), 'curve facedown beside it');

  step('replay page: the shown motion\'s episode beside the 3D view');
  await page.goto(`${url}replay.html?trial=${trial.id}:trajectory_1`);
  await waitFor('replay frames', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 5));
  assert.equal(await page.locator('#viewports #style-curves .uplot').count(), 3);
  const beside = (await page.evaluate(() => window.podiumPlots)).filter(p => p.holder.startsWith('style-'));
  assert.deepEqual(await page.evaluate(() => window.podiumReplay.labels), ['train/0 · curve facedown']);
  for (const p of beside) assert.deepEqual(p.series.map(s => s.label), ['facedown target', 'facedown achieved', 'facedown control points']);
  if (shots) await page.screenshot({ path: join(shots, 'style_curves_replay.png') });

  assert.deepEqual(external, [], 'requests left the machine');
  assert.deepEqual(problems, [], 'errors in the pages');
});
