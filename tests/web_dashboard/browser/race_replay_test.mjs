// A sprint race in headless Chromium (setup: harness.mjs): campaigns/sprint.json's start,
// accelerate and race stages at the smoke preset (seconds, nothing learnt) record a race from the
// blocks. The replay draws the two starting blocks as boxes and the start line, the finish line and
// the lane's edges as painted lines, all on the canvas, and its camera runs beside the runner. With
// PODIUM_SCREENSHOT_DIR set, the replay is saved there as a PNG (to look at).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';

import { canvasPixels, run, waitFor } from './harness.mjs';

const campaign = JSON.parse(readFileSync(join(process.env.PODIUM_SOURCE_DIR, 'campaigns', 'sprint.json'), 'utf8'));
const stages = campaign.stages.filter(s => s.name !== 'dip').map(s => ({ ...s, preset: 'smoke' }));
stages.find(s => s.name === 'race').inputs.stage = ['start', 'accelerate'];  // the dip is optional
for (const s of stages.filter(s => s.name !== 'race')) s.budget = { trials: 1 };
// The smoke preset leaves r_primitive off: its clips (paths relative to the campaign file) go.
for (const s of stages) delete s.config.primitive_clips;
const spec = { ...campaign, name: 'race-replay', workers: 2, retries: 0, trial_timeout_s: 120, stages };

run('race-replay', async h => {
  const id = h.submit('race', spec);
  h.podium(['run', '--workers', '2']);
  const { url, api } = await h.serve();
  const { page, external, problems } = await h.browse(url);
  const step = name => console.log(`-- ${name}`);
  const trials = (await api(`/api/campaigns/${id}/trials?limit=10`)).trials;
  for (const t of trials) assert.equal(t.state, 'done', `trial ${t.name}: ${t.error}`);
  const race = trials.find(t => t.name.startsWith('race/'));
  assert.ok(race, 'no race trial');

  step('replay: the blocks as boxes, the lines painted, all on the canvas');
  await page.setViewportSize({ width: 1000, height: 720 });
  await page.goto(`${url}replay.html?trial=${race.id}`);
  await waitFor('replay frames', () => page.evaluate(() => window.podiumReplay && window.podiumReplay.rendered > 5));
  const { kinds, drawn } = await page.evaluate(() => window.podiumReplay);
  assert.deepEqual(kinds, ['box', 'box', 'line', 'line', 'line', 'line']);
  assert.equal(drawn.props, 6);
  await page.locator('#play').click();  // paused
  const scrubTo = f => page.evaluate(v => {
    const s = document.getElementById('scrub');
    s.value = v === 'last' ? s.max : v;
    s.dispatchEvent(new Event('input'));
  }, f);
  await scrubTo(0);
  const pixels = () => canvasPixels(page);
  // The lines are near-black (0x263238, lit) on the light floor: dark pixels that go with the props
  // (the runner's shaded side is dark too, and stays).
  const isDark = v => (v >> 16) < 80 && ((v >> 8) & 255) < 90 && (v & 255) < 90;
  const shown = await pixels();
  if (process.env.PODIUM_SCREENSHOT_DIR) await page.screenshot({ path: join(process.env.PODIUM_SCREENSHOT_DIR, 'race_replay.png') });
  await page.locator('#show-props').uncheck();
  const hidden = await pixels();
  const lines = shown.filter((v, i) => isDark(v) && !isDark(hidden[i])).length;
  console.log(`   ${lines} dark pixels go with the props (of ${shown.filter(isDark).length} dark ones)`);
  assert.ok(lines > 500, 'the lines are not on the canvas');
  await page.locator('#show-props').check();

  step('replay: the camera runs beside the runner');
  const camera = () => page.evaluate(() => window.podiumReplay.camera_x);
  const first = await camera();
  await scrubTo('last');
  const last = await camera();
  const { root_x } = await page.evaluate(() => window.podiumReplay);
  console.log(`   camera x ${first.toFixed(3)} m at the first frame, ${last.toFixed(3)} m at the last (root ${root_x[0].toFixed(3)} → ${root_x[1].toFixed(3)} m)`);
  assert.ok(Math.abs((last - first) - (root_x[1] - root_x[0])) < 1e-9, 'the camera does not move with the root');

  assert.deepEqual(external, [], 'requests left the machine');
  assert.deepEqual(problems, [], 'errors in the pages');
});
