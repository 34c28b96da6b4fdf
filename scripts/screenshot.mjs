// The README's picture (scripts/screenshot.sh runs this): the demo campaign's get-up replay —
// pi_weak fast beside its slowed imitation, from the same fall, paused as it stands — above the
// campaign page's strategy gallery, served by `podium serve` and shot with headless Chromium
// (Debian's /usr/bin/chromium driven by playwright-core from web_dashboard/node_modules).
// Usage: node scripts/screenshot.mjs URL CAMPAIGN_ID TRIAL_ID OUT.png
import { createRequire } from 'node:module';
import { join } from 'node:path';

const [url, campaign, trial, out] = process.argv.slice(2);
const require = createRequire(join(process.cwd(), 'web_dashboard/node_modules/x.js'));
const { chromium } = require('playwright-core');

async function waitFor(what, fn, timeout_ms = 30000) {
  for (const start = Date.now(); !(await fn());) {
    if (Date.now() - start > timeout_ms) throw new Error(`screenshot: timed out waiting for ${what}`);
    await new Promise(r => setTimeout(r, 100));
  }
}

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium', headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update', '--disable-sync',
    '--no-first-run', '--enable-unsafe-swiftshader'],  // WebGL for the replay without a GPU
});
try {
  const page = await browser.newPage({ viewport: { width: 1180, height: 900 } });
  await page.goto(`${url}replay.html?trial=${trial}:trajectory_fast&compare=${trial}:trajectory`);
  await waitFor('the replay', () => page.evaluate(() => (window.podiumReplay?.rendered ?? 0) > 2));
  // Paused near the end of the fast motion, where the shown fall's pi_weak stands.
  await page.evaluate(() => {
    const scrub = document.getElementById('scrub');
    scrub.value = Math.round(0.8 * +scrub.max);
    scrub.dispatchEvent(new Event('input'));
  });
  await page.waitForTimeout(300);
  const replay = await page.locator('#viewports').screenshot();

  await page.goto(`${url}campaign.html?id=${campaign}`);
  await waitFor('the gallery cards', () => page.evaluate(() => (window.podiumGallery?.cards ?? 0) >= 3));
  await page.locator('#gallery').scrollIntoViewIfNeeded();  // only cards on screen are drawn
  const drawn = await page.evaluate(() => window.podiumGallery.rendered);
  await waitFor('the gallery drawn', () => page.evaluate(n => window.podiumGallery.rendered > n + 30, drawn));
  const gallery = await page.locator('#gallery').screenshot();

  // One picture, scaled down to keep the file small.
  const img = b => `<img style="display:block;width:100%" src="data:image/png;base64,${b.toString('base64')}">`;
  await page.setViewportSize({ width: 1180, height: 600 });
  await page.setContent(`<body style="margin:0;background:#fff;width:1180px">${img(replay)}${img(gallery)}</body>`);
  await page.waitForLoadState('load');
  const shot = await browser.newPage({ viewport: { width: 1180, height: 600 }, deviceScaleFactor: 0.6 });
  await shot.setContent(await page.content());
  await shot.screenshot({ path: out, fullPage: true });
} finally {
  await browser.close();
}
