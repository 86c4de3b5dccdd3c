// The studio's page end to end, in Debian's chromium driven headless by puppeteer-core (issue 50 item 5):
//   node studio_page.test.mjs POREHELL_EXE BUNNY.obj
// Starts `poreshell studio --no-browser --port 0`, loads the printed address, uploads the bunny (units m),
// then: changing the hole diameter changes the panel's hole count within 2 s (the figure; a
// preview takes about 1 s on a 2-core machine); a keep-out placed by clicking the surface has no hole
// centre of the next preview inside it; nor has a painted band; Make gives a closed, manifold, one-part
// 3MF; the saved project run by `poreshell --project` gives the same bytes.
// Exits 0 on success, 1 on failure, 77 (ctest's skip) without chromium or puppeteer-core.
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { createInterface } from 'node:readline';

const SKIP = 77;
const [exe, bunny] = process.argv.slice(2);
if (!exe || !bunny) {
  console.error('usage: node studio_page.test.mjs POREHELL_EXE BUNNY.obj');
  process.exit(2);
}
const chromium = [process.env.PORESHELL_CHROMIUM, '/usr/bin/chromium', '/usr/bin/chromium-browser']
  .find((p) => p && existsSync(p));
if (!chromium) {
  console.log('chromium not installed: skipped');
  process.exit(SKIP);
}
let puppeteer;
try {
  puppeteer = (await import('puppeteer-core')).default;
} catch {
  console.log('puppeteer-core not installed (npm ci in tests/io/browser): skipped');
  process.exit(SKIP);
}

const work = mkdtempSync(join(tmpdir(), 'poreshell-studio-page-'));
const failures = [];
const started = Date.now();
const expect = (ok, message) => {
  if (!ok) failures.push(message);
  console.log(`${(ok ? 'ok  ' : 'FAIL')} ${((Date.now() - started) / 1000).toFixed(1)} s: ${message}`);
};
const server = spawn(exe, ['studio', '--no-browser', '--port', '0', '--workdir', join(work, 'studio')],
                     { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  createInterface({ input: server.stdout }).once('line', (line) => {
    const m = /^studio: (http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]{32,})$/.exec(line);
    m ? resolve(m[1]) : reject(new Error('first line: ' + line));
  });
  server.once('exit', (code) => reject(new Error('studio exited with ' + code)));
});

const browser = await puppeteer.launch({
  executablePath: chromium, headless: true, defaultViewport: { width: 1280, height: 800 },
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking', '--no-first-run'],
});
try {
  const page = await browser.newPage();
  const errors = [], foreign = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('request', (r) => { if (!r.url().startsWith(new URL(url).origin) && !r.url().startsWith('blob:') && !r.url().startsWith('data:')) foreign.push(r.url()); });
  await page.goto(url);
  await page.waitForFunction(() => window.studio && window.studio.ready, { timeout: 10000 });

  // Upload the bunny in metres; the first preview (8 mm holes 14 mm apart) fills the panel.
  await page.select('#units', 'm');
  await (await page.$('#file')).uploadFile(bunny);
  await page.waitForFunction(() => window.studio.previews >= 1, { timeout: 15000 });
  const before = await page.$eval('#fig-holes', (e) => e.textContent);
  expect(Number(before) > 20, `first preview: ${before} holes`);

  // The hole diameter changed: the count changes within 2 s of the edit.
  await page.click('#opt-hole_diameter', { clickCount: 3 });
  await page.keyboard.type('10');
  const t0 = Date.now();
  await page.keyboard.press('Tab');  // the field's change event: one edit, one preview
  // PORESHELL_TIME_FACTOR stretches the limit on a machine known to be slower or loaded (default 1).
  const limit = 2000 * Number(process.env.PORESHELL_TIME_FACTOR || 1);
  await page.waitForFunction((b) => document.getElementById('fig-holes').textContent !== b, { timeout: 30000 }, before);
  const redraw = Date.now() - t0;
  const after = await page.$eval('#fig-holes', (e) => e.textContent);
  const seconds = await page.evaluate(() => window.studio.preview.seconds);
  expect(redraw <= limit, `hole count ${before} -> ${after} ${redraw} ms after the diameter 8 -> 10 (limit ${limit}; ` +
                          `the preview itself ${(1000 * seconds).toFixed(0)} ms)`);

  // A keep-out sphere by a click on the surface: no hole centre of the next preview in it.
  const canvas = await page.$('#view canvas');
  const box = await canvas.boundingBox();
  await page.click('#tool-sphere');
  let count = await page.evaluate(() => window.studio.previews);
  await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
  expect(await page.evaluate(() => window.studio.state().keepOuts.length) === 1, 'a click on the surface placed a keep-out');
  await page.waitForFunction((n) => window.studio.previews > n, { timeout: 30000 }, count);
  const sphere = await page.evaluate(() => {
    const k = window.studio.state().keepOuts[0];
    const inside = window.studio.preview.centres.filter((c) => Math.hypot(c[0] - k[0], c[1] - k[1], c[2] - k[2]) < k[3]);
    return { k, inside: inside.length, holes: window.studio.preview.holes };
  });
  expect(sphere.k && sphere.inside === 0 && sphere.holes > 0,
         `keep-out ${JSON.stringify(sphere.k)}: ${sphere.inside} of ${sphere.holes} hole centres inside`);

  // A painted band across the view: no hole centre whose nearest model vertex is painted.
  await page.click('#tool-paint');
  count = await page.evaluate(() => window.studio.previews);
  const y = box.y + box.height * 0.62;
  await page.mouse.move(box.x + box.width * 0.3, y);
  await page.mouse.down();
  for (let i = 1; i <= 8; ++i) await page.mouse.move(box.x + box.width * (0.3 + 0.05 * i), y);
  await page.mouse.up();
  await page.waitForFunction((n) => window.studio.previews > n, { timeout: 30000 }, count);
  const painted = await page.evaluate(() => (window.studio.requestBody().keep_out_mask_values || []).filter((v) => v).length);
  const inBand = await page.evaluate(() => window.studio.centresInPaint());
  expect(painted > 50 && inBand === 0, `painted band: ${painted} vertices, ${inBand} hole centres in it`);

  // Undo takes the band away, redo brings it back (each edit one step).
  await page.click('#undo');
  const undone = await page.evaluate(() => (window.studio.requestBody().keep_out_mask_values || []).length);
  count = await page.evaluate(() => window.studio.previews);
  await page.click('#redo');
  const redone = await page.evaluate(() => (window.studio.requestBody().keep_out_mask_values || []).filter((v) => v).length);
  expect(undone === 0 && redone === painted, `undo: ${undone} painted, redo: ${redone}`);
  await page.waitForFunction((n) => window.studio.previews > n, { timeout: 30000 }, count);

  // Larger holes for the Make (its grid follows the holes: 14 mm at 24 mm takes a third of 10 at 14),
  // set as one edit.
  count = await page.evaluate(() => window.studio.previews);
  await page.evaluate(() => {
    document.getElementById('opt-spacing').value = '24';
    const d = document.getElementById('opt-hole_diameter');
    d.value = '14';
    d.dispatchEvent(new Event('change'));
  });
  await page.waitForFunction((n) => window.studio.previews > n, { timeout: 30000 }, count);

  // Make: the progress ends done; the part is closed, manifold, one part.
  await page.click('#make');
  await page.waitForFunction(() => window.studio.job, { timeout: 40000 });
  const job = await page.evaluate(() => {
    const m = window.studio.job.report.mesh;
    return { closed: m.closed, manifold: m.manifold, parts: m.parts.count, holes: m.hole_table.length, id: window.studio.job.job };
  });
  expect(job.closed && job.manifold && job.parts === 1, `Make: closed ${job.closed}, manifold ${job.manifold}, ${job.parts} part(s), ${job.holes} holes`);
  // The made part's measured panel: its hole count is the report's, its part printable.
  await page.waitForFunction(() => !document.getElementById('made').hidden, { timeout: 10000 });
  const made = await page.evaluate(() => ({ holes: document.getElementById('made-holes').textContent,
                                             part: document.getElementById('made-part').textContent }));
  expect(made.holes === String(job.holes) && made.part.startsWith('closed, manifold, 1 part'),
         `the made panel says ${made.holes} holes, '${made.part}'`);
  const progress = await page.$eval('#progress-bar', (e) => parseFloat(e.style.width));
  expect(progress >= 99.9, `progress bar at ${progress}%`);
  const part = Buffer.from(await page.evaluate(async (id) => {
    const r = await fetch(`/api/jobs/${id}/files/part.3mf`);
    const bytes = new Uint8Array(await r.arrayBuffer());
    let s = '';
    for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    return btoa(s);
  }, job.id), 'base64');

  // The saved project through the command line: the same bytes.
  writeFileSync(join(work, 'p.json'), await page.evaluate(() => JSON.stringify(window.studio.project())));
  const cli = spawnSync(exe, ['--project', join(work, 'p.json'), '-o', join(work, 'out.3mf'), '-q'], { encoding: 'utf8' });
  expect(cli.status === 0, `poreshell --project: exit ${cli.status} ${cli.stderr}`);
  const same = cli.status === 0 && Buffer.compare(readFileSync(join(work, 'out.3mf')), part) === 0;
  expect(same, `project through the CLI: ${part.length} bytes from Make, the same bytes: ${same}`);

  expect(errors.length === 0, 'no page errors: ' + errors.join(' | '));
  expect(foreign.length === 0, 'no request but to the studio: ' + foreign.join(' '));
} catch (e) {
  failures.push(String(e && e.stack || e));
  console.log('FAIL ' + e);
} finally {
  await browser.close();
  server.kill('SIGTERM');
  await new Promise((resolve) => server.once('exit', resolve));
  rmSync(work, { recursive: true, force: true });
}
console.log(`${failures.length ? 'FAILED' : 'passed'} in ${((Date.now() - started) / 1000).toFixed(1)} s`);
process.exit(failures.length ? 1 : 0);
