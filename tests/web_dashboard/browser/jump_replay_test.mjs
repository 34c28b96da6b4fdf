// A real jump in headless Chromium (setup: harness.mjs): the jump task's evaluate stage jumps two
// shipped high-jump policies (tasks/jump/policies) at the quick preset (150 Hz simulation, 10–15 Hz
// control) and records the deterministic jump. The replay plays at least 60 frames per simulated
// second, draws the bar as a crossbar (on its standards) and the block as a landing mat, and both
// are on the canvas; the strategy gallery draws the same props. With PODIUM_SCREENSHOT_DIR set, the
// replay and the gallery are saved there as PNGs (to look at).
// Environment (besides harness.mjs's): PODIUM_SOURCE_DIR, the repository (the shipped policies).
import assert from 'node:assert/strict';
import { join } from 'node:path';

import { canvasPixels, run, waitFor } from './harness.mjs';

const policies = join(process.env.PODIUM_SOURCE_DIR, 'tasks', 'jump', 'policies');
const shipped = (name, takeoff) => ({
  policy: join(policies, `highjump_${name}_like.pt`), pose_vae: join(policies, 'athlete_pose_vae.pt'), takeoff, z_m: 0.58,
});
// The take-off features of the shipped policies (tasks/jump/policies/MANIFEST.json).
const spec = {
  name: 'jump-replay', seed: 7, workers: 2, retries: 0, trial_timeout_s: 120,
  stages: [{
    name: 'jumps', task: 'jump', preset: 'quick', search: { algorithm: 'random' }, budget: { trials: 2 },
    config: {
      stage: 'evaluate', kind: 'high_jump', final_jumps: 1,
      shipped: [shipped('flop', [1.6019032283293728, -2.171672507792453, -1.440066801205806, 1.5953253280695927]),
        shipped('scissor', [0.8412021253398421, 2.853518502672843, 2.752445423420406, 0.6074222516131468])],
    },
  }],
};

run('jump-replay', async h => {
  const id = h.submit('jumps', spec);
  h.podium(['run', '--workers', '2']);
  const { url, api } = await h.serve();
  const { page, external, problems } = await h.browse(url);
  const step = name => console.log(`-- ${name}`);
  const trials = (await api(`/api/campaigns/${id}/trials?limit=2`)).trials;
  assert.equal(trials.length, 2);
  for (const t of trials) assert.equal(t.state, 'done', `trial ${t.id}: ${t.error}`);
  const shots = process.env.PODIUM_SCREENSHOT_DIR;

  step('replay: at least 60 frames per simulated second');
  await page.setViewportSize({ width: 1000, height: 720 });
  await page.goto(`${url}replay.html?trial=${trials[0].id}`);
  await waitFor('replay frames', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 5));
  const { frames, duration, kinds, drawn } = await page.evaluate(() => window.podiumReplay);
  const rate = (frames - 1) / duration;
  console.log(`   ${frames} frames over ${duration.toFixed(3)} s of simulation: ${rate.toFixed(1)} frames per second`);
  assert.ok(duration > 0.2, `a jump of ${duration} s`);
  assert.ok(rate >= 60, `${rate} frames per simulated second`);

  step('replay: the bar is a crossbar, the block a landing mat, both on the canvas');
  assert.deepEqual(kinds, ['crossbar', 'mat']);
  assert.equal(drawn.props, 2);
  await page.locator('#play').click();  // paused: the picture changes only with the checkbox
  await page.evaluate(() => { const s = document.getElementById('scrub'); s.value = 0; s.dispatchEvent(new Event('input')); });
  const pixels = () => canvasPixels(page);
  const shown = await pixels();
  // The bar's red bands (the crossbar is the only red in the scene): visible, and gone with the props.
  const red = px => px.filter(v => (v >> 16) > 150 && ((v >> 8) & 255) < 90 && (v & 255) < 90).length;
  if (shots) await page.screenshot({ path: join(shots, 'jump_replay.png') });
  await page.locator('#show-props').uncheck();
  const hidden = await pixels();
  const changed = shown.filter((v, i) => v !== hidden[i]).length / shown.length;
  console.log(`   ${red(shown)} red bar pixels; hiding the props changes ${(100 * changed).toFixed(2)}% of the pixels`);
  assert.ok(red(shown) > 100, 'the crossbar is not on the canvas');
  assert.equal(red(hidden), 0, 'red pixels without the props');
  assert.ok(changed > 0.02, 'the props are not on the canvas');

  step('strategy gallery: the same props on every card');
  const strategies = (await api(`/api/campaigns/${id}`)).strategy_table.length;
  await page.goto(`${url}campaign.html?id=${id}`);
  await waitFor('a card per strategy', () => page.evaluate(n => window.podiumGallery?.cards === n, strategies));
  const cardKinds = await page.evaluate(() => window.podiumGallery.kinds);
  assert.equal(Object.keys(cardKinds).length, strategies);
  for (const k of Object.values(cardKinds)) assert.deepEqual(k, ['crossbar', 'mat']);
  if (shots) {
    await page.locator('#gallery').scrollIntoViewIfNeeded();
    await page.waitForTimeout(500);  // a few gallery frames drawn (only for the picture)
    await page.locator('#gallery').screenshot({ path: join(shots, 'jump_gallery.png') });
  }

  assert.deepEqual(external, [], 'requests left the machine');
  assert.deepEqual(problems, [], 'errors in the pages');
});
