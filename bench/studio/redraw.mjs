// Change to redraw in the page (bench/studio/run calls it): the hole diameter's field edited, to the
// panel's hole count changed, in headless chromium (software GL, as the browser tests).
//   node redraw.mjs STUDIO_URL MODEL UNITS SPACING [EDITS]
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const require = createRequire(join(here, '..', '..', 'tests', 'io', 'browser', 'package.json'));
const puppeteer = (await import(require.resolve('puppeteer-core'))).default;
const [url, model, units, spacing, edits = '5'] = process.argv.slice(2);
const browser = await puppeteer.launch({
  executablePath: process.env.PORESHELL_CHROMIUM || '/usr/bin/chromium', headless: true,
  defaultViewport: { width: 1280, height: 800 },
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-first-run'],
});
try {
  const page = await browser.newPage();
  await page.goto(url);
  await page.waitForFunction(() => window.studio && window.studio.ready);
  await page.select('#units', units);
  await page.$eval('#opt-spacing', (e, s) => { e.value = s; }, spacing);
  await (await page.$('#file')).uploadFile(model);
  await page.waitForFunction(() => window.studio.previews >= 1, { timeout: 60000 });
  const times = [];
  for (let i = 0; i < Number(edits); ++i) {
    const n = await page.evaluate(() => window.studio.previews);
    const before = await page.$eval('#fig-holes', (e) => e.textContent);
    const t0 = Date.now();
    // Alternating 8 and 8.5 mm: each edit a new run whose count differs or is at least redrawn.
    await page.$eval('#opt-hole_diameter', (e, d) => { e.value = d; e.dispatchEvent(new Event('change')); }, i % 2 ? '8' : '8.5');
    await page.waitForFunction((k) => window.studio.previews > k, { timeout: 60000, polling: 'raf' }, n);
    times.push(Date.now() - t0);
    void before;
  }
  times.sort((a, b) => a - b);
  console.log(JSON.stringify({ median_ms: times[Math.floor(times.length / 2)], times_ms: times }));
} finally {
  await browser.close();
}
