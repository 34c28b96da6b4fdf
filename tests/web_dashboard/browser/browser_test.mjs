// End-to-end test of the dashboard in headless Chromium (Debian's /usr/bin/chromium driven by
// playwright-core from web_dashboard/node_modules): every page for a landscape smoke campaign and a
// trajectory-recording campaign, the scatter's point count, the 3D replay (canvas not blank,
// frame counter advancing, props and rough tiles drawn, side by side), and a live update while a
// campaign runs. Setup (scratch folder, podium serve, offline Chromium): harness.mjs.
import assert from 'node:assert/strict';

import { canvasPixels, run, waitFor } from './harness.mjs';

const stage = (name, task, trials, config = {}) =>
  ({ name, task, preset: 'smoke', config, search: { algorithm: 'random' }, budget: { trials } });
const campaign = (name, stages) => ({ name, seed: 5, workers: 2, retries: 0, trial_timeout_s: 30, stages });

run('browser', async h => {
  const { podium, submit } = h;
  const landscape = submit('landscape', campaign('landscape-smoke', [stage('explore', 'landscape', 60, { artifact: true })]));
  const physics = submit('physics', campaign('replay-smoke', [stage('swing', 'web_replay_fixture', 6)]));
  podium(['run', '--workers', '2']);
  const live = submit('live', campaign('live', [stage('explore', 'landscape', 6, { sleep_s: 0.3 })]));

  const { url, api } = await h.serve();
  const { page, external, problems } = await h.browse(url);
  const step = name => console.log(`-- ${name}`);

  step('campaign list');
  await page.goto(url);
  await waitFor('3 campaign rows', async () => (await page.locator('#campaigns tr').count()) === 4);
  assert.match(await page.locator('#campaigns').innerText(), /landscape-smoke[\s\S]*done/);

  for (const [id, expected] of [[landscape, 60], [physics, 6]]) {
    step(`campaign page ${id}: one scatter point per finished trial`);
    const done = (await api(`/api/campaigns/${id}`)).counts.done;
    assert.equal(done, expected);
    await page.goto(`${url}campaign.html?id=${id}`);
    await waitFor('scatter', async () => (await page.locator('#scatter').getAttribute('data-points')) === String(done));
    await waitFor('trial rows', async () => (await page.locator('#trials tr').count()) === Math.min(done, 50) + 1);
    assert.equal(await page.locator('#history .uplot').count(), 1);
    assert.equal(await page.locator('#stages tr').count(), 2);
    const strategies = (await api(`/api/campaigns/${id}`)).strategy_table.length;
    if (id === landscape) assert.equal(await page.locator('#legend span').count(), strategies, 'one legend entry per strategy');
  }

  step('trial page: learning curves, artifacts, attempts');
  const landscapeTrial = (await api(`/api/campaigns/${landscape}/trials?limit=1`)).trials[0];
  await page.goto(`${url}trial.html?id=${landscapeTrial.id}`);
  await waitFor('curve', async () => (await page.locator('#curves .uplot').count()) === 1);
  assert.equal(await page.locator('#attempts tr').count(), 2);
  const link = page.locator('#artifacts a');
  assert.equal(await link.count(), 1);
  const download = await page.request.get(new URL(await link.getAttribute('href'), url).href);
  assert.equal(download.status(), 200);
  assert.match(await download.text(), /"feature"/);
  await waitFor('the log', async () => /podium: attempt 1 started/.test(await page.locator('#log').innerText()));
  assert.equal(await page.locator('#log-note a').getAttribute('href'), `/api/trials/${landscapeTrial.id}/log`);

  const physicsTrials = (await api(`/api/campaigns/${physics}/trials?limit=2`)).trials;
  await page.goto(`${url}trial.html?id=${physicsTrials[0].id}`);
  await waitFor('curriculum curve', async () => (await page.locator('#curriculum .uplot').count()) === 1);
  assert.equal(await page.locator('#curves .uplot').count(), 1);
  assert.equal(await page.locator('#replay-link').isVisible(), true);

  const canvasStats = (selector = '#viewports canvas') => page.evaluate(selector => [...document.querySelectorAll(selector)].map(c => {
    const copy = document.createElement('canvas');
    copy.width = c.width; copy.height = c.height;
    const ctx = copy.getContext('2d');
    ctx.drawImage(c, 0, 0);
    const data = ctx.getImageData(0, 0, c.width, c.height).data;
    const colours = new Set();
    let differing = 0;
    for (let i = 0; i < data.length; i += 4) {
      colours.add((data[i] >> 3) << 10 | (data[i + 1] >> 3) << 5 | (data[i + 2] >> 3));
      if (Math.abs(data[i] - data[0]) + Math.abs(data[i + 1] - data[1]) + Math.abs(data[i + 2] - data[2]) > 30) differing++;
    }
    return { colours: colours.size, differing: differing / (data.length / 4) };
  }), selector);

  step('3D replay: renders, frame counter advances');
  await page.goto(`${url}replay.html?trial=${physicsTrials[0].id}`);
  await waitFor('replay frames', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 10));
  const first = await page.locator('#frame').innerText();
  await page.waitForTimeout(600);
  const second = await page.locator('#frame').innerText();
  assert.notEqual(first, second, 'frame counter did not advance');
  const [stats] = await canvasStats();
  console.log(`   canvas: ${stats.colours} colours, ${(100 * stats.differing).toFixed(1)}% non-background pixels`);
  assert.ok(stats.colours > 20 && stats.differing > 0.02, `blank canvas: ${JSON.stringify(stats)}`);
  await page.locator('#play').click();  // pause: the counter stops
  const paused = await page.locator('#frame').innerText();
  await page.waitForTimeout(300);
  assert.equal(await page.locator('#frame').innerText(), paused);

  step('3D replay: the props (bar, inclined block) and the rough tiles are drawn');
  assert.deepEqual(await page.evaluate(() => window.podiumReplay.drawn), { props: 2, terrain: 64 });
  const pixels = () => canvasPixels(page, 4);  // every 4th pixel of the (paused) first viewport
  const changed = (a, b) => a.filter((v, i) => v !== b[i]).length / a.length;
  const shown = await pixels();
  for (const [part, least] of [['terrain', 0.05], ['props', 0.002]]) {
    await page.locator(`#show-${part}`).uncheck();
    const hidden = await pixels();
    console.log(`   hiding the ${part} changes ${(100 * changed(shown, hidden)).toFixed(2)}% of the pixels`);
    assert.ok(changed(shown, hidden) > least, `the ${part} are not visible on the canvas`);
    await page.locator(`#show-${part}`).check();
    assert.ok(changed(shown, await pixels()) < 0.001, `showing the ${part} again did not restore the picture`);
  }

  step('side-by-side replay of two strategies');
  await page.goto(`${url}replay.html?trial=${physicsTrials[0].id}&compare=${physicsTrials[1].id}`);
  await waitFor('two viewports', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 5));
  const both = await canvasStats();
  assert.equal(both.length, 2);
  for (const s of both) assert.ok(s.colours > 20 && s.differing > 0.02, `blank canvas: ${JSON.stringify(s)}`);

  step('side by side, two motions that start at different times play from their first frames together');
  // trajectory_fast is trajectory's frames from t = 2 s (the fixture): every view shows the same frame.
  await page.goto(`${url}replay.html?trial=${physicsTrials[0].id}&compare=${physicsTrials[0].id}:trajectory_fast`);
  await waitFor('two viewports', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 5));
  for (const frame of [0, 30, 89]) {
    await page.evaluate(f => { const s = document.getElementById('scrub'); s.value = f; s.dispatchEvent(new Event('input')); }, frame);
    assert.deepEqual(await page.evaluate(() => window.podiumReplay.shown), [frame, frame], `scrubbed to frame ${frame}`);
  }

  step('strategy gallery: one moving replay per strategy on the campaign page');
  const strategyCount = (await api(`/api/campaigns/${physics}`)).strategy_table.length;
  assert.ok(strategyCount >= 1, 'the replay campaign has no strategies');
  await page.goto(`${url}campaign.html?id=${physics}`);
  await waitFor('a card per strategy', () => page.evaluate(n => window.podiumGallery?.cards === n, Math.min(strategyCount, 12)));
  await page.locator('#gallery').scrollIntoViewIfNeeded();  // cards are drawn only on screen
  const drawnBefore = await page.evaluate(() => window.podiumGallery.rendered);
  await waitFor('every card drawn twice', () => page.evaluate(n => window.podiumGallery.rendered >= n, drawnBefore + 2 * Math.min(strategyCount, 12)));
  assert.equal(await page.locator('#gallery .card').count(), Math.min(strategyCount, 12));
  await waitFor('the task\'s summary on a card', async () => /tip peak m: /.test(await page.locator('#gallery .card').first().innerText()));
  const galleryStats = await canvasStats('#gallery canvas');
  assert.equal(galleryStats.length, Math.min(strategyCount, 12));
  for (const s of galleryStats) assert.ok(s.colours > 20 && s.differing > 0.02, `blank gallery canvas: ${JSON.stringify(s)}`);
  const galleryPixels = () => page.evaluate(() => {
    const c = document.querySelector('#gallery canvas');
    const copy = document.createElement('canvas');
    copy.width = c.width; copy.height = c.height;
    copy.getContext('2d').drawImage(c, 0, 0);
    return Array.from(copy.getContext('2d').getImageData(0, 0, c.width, c.height).data.filter((_, i) => i % 16 === 0));
  });
  const before = await galleryPixels();
  await page.waitForTimeout(700);
  const after = await galleryPixels();
  const moved = before.filter((v, i) => v !== after[i]).length / before.length;
  console.log(`   gallery: ${strategyCount} strategies, the first card's motion changed ${(100 * moved).toFixed(2)}% of its pixels in 0.7 s`);
  assert.ok(moved > 0.001, 'the gallery replay does not move');

  step('a trial\'s second recorded motion beside its first (ID:NAME), linked from the trial page');
  await page.goto(`${url}trial.html?id=${physicsTrials[0].id}`);
  const beside = page.locator('#replay-more a');
  await waitFor('the further motion\'s link', async () => (await beside.count()) === 1);
  assert.equal(await beside.textContent(), 'fast beside it');
  await beside.click();
  await waitFor('two viewports of one trial', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 5));
  assert.equal((await canvasStats()).length, 2);
  assert.match(await page.locator('#viewports').textContent(), /fast/);

  step('live: the campaign page updates while the campaign runs, without a reload');
  await page.goto(`${url}campaign.html?id=${live}`);
  await waitFor('live page', async () => (await page.locator('#summary').getAttribute('data-done')) === '0');
  await page.evaluate(() => { window.notReloaded = true; });
  const runner = h.spawn(['run', '--workers', '2']);
  await waitFor('first finished trial on the page', async () =>
    Number(await page.locator('#summary').getAttribute('data-done')) > 0, 30000);
  await waitFor('all 6 trials on the page', async () =>
    (await page.locator('#scatter').getAttribute('data-points')) === '6', 30000);
  assert.equal(await page.evaluate(() => window.notReloaded), true, 'the page reloaded');
  await waitFor('a live refresh', () => page.evaluate(() => window.podiumLive.refreshes >= 2));  // initial load + live
  if (runner.exitCode === null) await new Promise(r => runner.on('exit', r));
  assert.equal(runner.exitCode, 0);

  assert.deepEqual(external, [], 'requests left the machine');
  assert.deepEqual(problems, [], 'errors in the pages');
});
