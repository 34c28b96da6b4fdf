// Shared setup of the dashboard's browser tests: a scratch folder with the real `podium` CLI,
// `podium serve` on a free port, and headless Chromium (Debian's /usr/bin/chromium driven by
// playwright-core from web_dashboard/node_modules) kept offline: any request not to the server is
// refused and recorded, as are page errors.
// Environment (set by CTest): PODIUM_BIN, PODIUM_PLUGIN_PATH, PODIUM_WEB_NODE_MODULES, CHROMIUM.
// Exit codes of a test run through run(): 0 pass, 1 fail, 77 skipped (no Chromium).
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export async function waitFor(what, fn, timeout_ms = 20000) {
  const start = Date.now();
  for (;;) {
    const value = await fn();
    if (value) return value;
    if (Date.now() - start > timeout_ms) throw new Error(`timed out waiting for ${what}`);
    await new Promise(r => setTimeout(r, 100));
  }
}

// Runs body(h) with h = { dir, podium(args), submit(name, spec), serve(), browse() } and exits.
// The first viewport's canvas as 0xRRGGBB numbers, every `step`-th pixel (for tests that compare
// pictures: what hiding props changes, what a colour covers).
export function canvasPixels(page, step = 1) {
  return page.evaluate(step => {
    const c = document.querySelector('#viewports canvas');
    const copy = document.createElement('canvas');
    copy.width = c.width; copy.height = c.height;
    const ctx = copy.getContext('2d');
    ctx.drawImage(c, 0, 0);
    const data = ctx.getImageData(0, 0, c.width, c.height).data, out = [];
    for (let i = 0; i < data.length; i += 4 * step) out.push(data[i] << 16 | data[i + 1] << 8 | data[i + 2]);
    return out;
  }, step);
}

export function run(name, body) {
  const chromiumPath = process.env.CHROMIUM || '/usr/bin/chromium';
  if (!existsSync(chromiumPath)) {
    console.log(`SKIPPED: ${chromiumPath} not found (apt-get install chromium)`);
    process.exit(77);
  }
  const dir = mkdtempSync(join(tmpdir(), `podium-${name}-`));
  const children = [];
  let browser = null;
  const h = {
    dir,
    // `status`: the exit code expected (podium run exits 1 when a campaign it ran failed).
    podium(args, status = 0) {
      const r = spawnSync(process.env.PODIUM_BIN, args, { cwd: dir, encoding: 'utf8' });
      assert.equal(r.status, status, `podium ${args.join(' ')}: ${r.stderr}`);
      return r.stdout.trim();
    },
    submit(file, spec) {
      writeFileSync(join(dir, `${file}.json`), JSON.stringify(spec));
      return Number(h.podium(['submit', `${file}.json`]));
    },
    // Starts `podium args...` in the background (stopped at the end if still running).
    spawn(args) {
      const child = spawn(process.env.PODIUM_BIN, args, { cwd: dir, stdio: 'ignore' });
      children.push(child);
      return child;
    },
    // Starts `podium serve --port 0`; resolves to { url, api(path) }.
    async serve() {
      const serve = spawn(process.env.PODIUM_BIN, ['serve', '--port', '0'], { cwd: dir });
      children.push(serve);
      let out = '';
      serve.stdout.on('data', d => { out += d; });
      const url = await waitFor('podium serve URL', () => out.match(/http:\/\/127\.0\.0\.1:\d+\//)?.[0]);
      return { url, api: async path => (await fetch(url + path.slice(1))).json() };
    },
    // A page in a fresh offline context; `external` and `problems` collect what must stay empty.
    async browse(url) {
      const require = createRequire(join(process.env.PODIUM_WEB_NODE_MODULES, 'x.js'));
      const { chromium } = require('playwright-core');
      browser = await chromium.launch({
        executablePath: chromiumPath, headless: true,
        args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking',
          '--disable-component-update', '--disable-sync', '--enable-unsafe-swiftshader'],  // WebGL for the replay
      });
      const context = await browser.newContext();
      const external = [], problems = [];
      await context.route('**/*', route => {
        if (route.request().url().startsWith(url)) return route.continue();
        external.push(route.request().url());
        return route.abort();
      });
      const page = await context.newPage();
      h.problems = problems;  // printed when the test fails
      page.on('pageerror', e => problems.push(`page error: ${e.message}`));
      page.on('console', m => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
      return { page, external, problems };
    },
  };
  const cleanup = async () => {
    if (browser) await browser.close().catch(() => {});
    for (const c of children) if (c.exitCode === null) c.kill('SIGTERM');
    rmSync(dir, { recursive: true, force: true });
  };
  body(h).then(async () => { await cleanup(); console.log('PASS'); process.exit(0); },
    async e => {
      console.error('FAIL:', e.stack || e);
      if (h.problems?.length) console.error('page problems so far:\n' + h.problems.join('\n'));
      await cleanup();
      process.exit(1);
    });
}
