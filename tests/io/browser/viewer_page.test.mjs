// Browser checks of the viewer page, in Debian's chromium driven headless by puppeteer-core:
//   node viewer_page.test.mjs CHECKS PAGE.html EXPECTED.json
// CHECKS: a comma-separated list, run in order on one load of the page in one browser (starting the
// browser and loading the page take most of the time; no check below changes what a later one reads),
// or `all`:
// loads (no console errors, no requests but the page's own), canvas (the screenshot's view is
// not blank), hole_edge (a hole's colour ends in a sharp edge on the surface, not in a blend of vertex
// colours over a triangle or two), fold (a run page's second sheet under the sphere, seen through its
// holes, keeps the surface's colour: no hole's colour reaches a sheet its cut does not join), hole_count (the panel's count is the data's), click_hole (clicking a hole's centre shows
// its diameter), click_surface (clicking the surface shows the point's coordinates), panel (a full
// run's panel shows its solid: wall, triangles, volume; a preview's says it is one and shows none of
// them, nor a wall that was not asked for).
// Exits 0 on success, 1 on failure, 77 (ctest's skip) without chromium or puppeteer-core.
import { existsSync, readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';
import { inflateSync } from 'node:zlib';

const SKIP = 77;
const ALL = ['loads', 'canvas', 'hole_edge', 'fold', 'hole_count', 'click_hole', 'click_surface', 'panel'];
const [checkList, pagePath, expectedPath] = process.argv.slice(2);
if (!checkList || !pagePath || !expectedPath) {
  console.error('usage: node viewer_page.test.mjs CHECKS PAGE.html EXPECTED.json');
  process.exit(2);
}

const chromium = [process.env.PORESHELL_CHROMIUM, '/usr/bin/chromium', '/usr/bin/chromium-browser']
  .find((p) => p && existsSync(p));
if (!chromium) {
  console.log('chromium not installed (apt-get install chromium, or scripts/install-deps): skipped');
  process.exit(SKIP);
}
let puppeteer;
try {
  puppeteer = (await import('puppeteer-core')).default;
} catch {
  console.log('puppeteer-core not installed (npm ci in tests/io/browser, or scripts/install-deps): skipped');
  process.exit(SKIP);
}

const expected = JSON.parse(readFileSync(expectedPath, 'utf8'));
const url = pathToFileURL(pagePath).href;
const checks = checkList === 'all' ? ALL : checkList.split(',');
const failures = [];
let check = '';
const expect = (ok, message) => { if (!ok) failures.push(check + ': ' + message); };

const browser = await puppeteer.launch({
  executablePath: chromium,
  headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--hide-scrollbars',
         '--disable-background-networking', '--no-first-run'],
  defaultViewport: { width: 1280, height: 800 },
});
try {
  const page = await browser.newPage();
  const errors = [], requests = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('requestfailed', (r) => errors.push('request failed: ' + r.url()));
  page.on('request', (r) => { if (r.url() !== url) requests.push(r.url()); });
  await page.goto(url, { waitUntil: 'load', timeout: 30000 });
  await page.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
  // The holes in view that face the camera, most squarely first: index and screen position.
  const facingHoles = async () => {
    const found = [];
    for (const [i, h] of expected.holes.entries()) {
      const s = await page.evaluate((c, n) => window.poreshellViewer.project(...c, ...n), h.centre, h.normal);
      if (!s.inView || !s.facing) continue;
      const cam = await page.evaluate((c, n) => window.poreshellViewer.facing(...c, ...n), h.centre, h.normal);
      found.push({ i, s, cam });
    }
    return found.sort((a, b) => b.cam - a.cam);
  };
  // Where the point of the sphere `radii` hole radii from hole h's centre (in a fixed direction) lands.
  const onSphere = async (h, radii) => {
    const { centre, radius } = expected.sphere;
    const side = Math.abs(h.normal[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    let t = side.map((c, k) => c - h.normal[k] * side.reduce((a, v, j) => a + v * h.normal[j], 0));
    t = t.map((c) => c / Math.hypot(...t));
    let p = h.centre.map((c, k) => c + radii * 0.5 * h.diameter_mm * t[k] - centre[k]);
    p = p.map((c, k) => centre[k] + radius * c / Math.hypot(...p));
    return page.evaluate((q, n) => window.poreshellViewer.project(...q, ...n), p, h.normal);
  };
  const far = (a, b) => Math.hypot(...a.map((c, k) => c - b[k]));
  const screenshot = async () => {
    const box = await (await page.$('#view canvas')).boundingBox();
    const image = decodePng(await page.screenshot({ clip: box, type: 'png' }));
    return { box, at: (s) => image.pixel(Math.round(s.x - box.x), Math.round(s.y - box.y)) };
  };
  for (check of checks) {

    if (check === 'loads') {
      expect(errors.length === 0, 'console errors: ' + errors.join(' | '));
      expect(requests.length === 0, 'requests besides the page: ' + requests.join(' '));
      expect(await page.$('#view canvas') !== null, 'no canvas');
    } else if (check === 'canvas') {
      const box = await (await page.$('#view canvas')).boundingBox();
      const png = await page.screenshot({ clip: box, type: 'png' });
      const image = decodePng(png);
      // The view's background is one colour (its top-left corner); the model is what differs from it.
      const bg = image.pixel(2, 2);
      let differing = 0, tinted = 0;
      for (let y = 0; y < image.height; y += 2)
        for (let x = 0; x < image.width; x += 2) {
          const [r, g, b] = image.pixel(x, y);
          if (Math.abs(r - bg[0]) + Math.abs(g - bg[1]) + Math.abs(b - bg[2]) > 40) differing++;
          if (Math.max(r, g, b) - Math.min(r, g, b) > 60) tinted++;  // the holes' colours, the zones' lines
        }
      const samples = Math.ceil(image.width / 2) * Math.ceil(image.height / 2);
      console.log(`canvas ${image.width}x${image.height}: ${(100 * differing / samples).toFixed(1)} % model, ` +
                  `${(100 * tinted / samples).toFixed(2)} % coloured`);
      expect(differing / samples > 0.1, 'the canvas is nearly blank');
      expect(tinted / samples > 0.002, 'no coloured holes in view');
    } else if (check === 'fold') {
      if (!expected.fold_radius) {
        console.log('a preview page: no fold');
      } else {
        // Through the middle of each of the three holes facing the camera the sheet under the sphere
        // shows: its colour must be nearer the surface's (2 radii out) than the hole's (its rim, 1.2
        // radii out). Painted by distance alone, every hole's colour reached the sheet.
        const shot = await screenshot();
        for (const best of (await facingHoles()).slice(0, 3)) {
          const h = expected.holes[best.i];
          const through = shot.at(best.s), rim = shot.at(await onSphere(h, 1.2));
          const surface = shot.at(await onSphere(h, 2.0));
          console.log(`hole ${best.i}: through it ${through}, its rim ${rim}, the surface ${surface}`);
          expect(far(through, surface) < far(through, rim), `hole ${best.i}'s colour reaches the sheet under it`);
        }
      }
    } else if (check === 'hole_count') {
      const text = await page.$eval('#hole-count', (e) => e.textContent.trim());
      expect(text === String(expected.hole_count), `panel says ${text} holes, the data has ${expected.hole_count}`);
      const count = await page.evaluate(() => window.poreshellViewer.holeCount);
      expect(count === expected.hole_count, `the page read ${count} holes, the data has ${expected.hole_count}`);
    } else if (check === 'hole_edge') {
      // From inside each of the three holes facing the camera (a preview: its centre; a run: just past
      // its cut, on the coloured rim) out to 1.6 radii along the surface: the pixels that are neither
      // the hole's colour nor the surface's (further than a quarter of their difference from each).
      const facing = (await facingHoles()).slice(0, 3);
      expect(facing.length === 3, 'fewer than 3 holes face the camera');
      const shot = await screenshot();
      let blended = 0;
      for (const best of facing) {
        const h = expected.holes[best.i];
        const start = expected.preview ? best.s : await onSphere(h, 1.2), end = await onSphere(h, 1.6);
        const at = (f) => shot.at({ x: start.x + f * (end.x - start.x), y: start.y + f * (end.y - start.y) });
        const inside = at(0), outside = at(1);
        const contrast = far(inside, outside);
        const steps = Math.ceil(Math.hypot(end.x - start.x, end.y - start.y));
        let between = 0;
        for (let i = 0; i <= steps; ++i) {
          const p = at(i / steps);
          if (far(p, inside) > 0.25 * contrast && far(p, outside) > 0.25 * contrast) between++;
        }
        console.log(`hole ${best.i}: ${steps} pixels out to 1.6 radii, ${between} between its colour and the surface's`);
        expect(contrast > 60, `hole ${best.i} is not coloured apart from the surface`);
        blended += between;
      }
      // Sharp edges give 0-2 in all (antialiasing); vertex colours blended over the triangles gave 7 (run)
      // and 19 (preview).
      expect(blended <= 2, `${blended} pixels blend the holes into the surface: frayed edges`);
    } else if (check === 'click_hole') {
      const best = (await facingHoles())[0] ?? null;
      expect(best !== null, 'no hole faces the camera');
      if (best) {
        await page.mouse.click(best.s.x, best.s.y);
        const shown = await page.$eval('#selection', (e) => ({ hole: e.dataset.hole, text: e.textContent }));
        const diameter = expected.holes[best.i].diameter_mm.toFixed(2) + ' mm';
        expect(shown.hole === String(best.i), `clicked hole ${best.i}, the panel shows hole ${shown.hole}`);
        expect(shown.text.includes(diameter), `the panel does not show ${diameter}: ${shown.text}`);
        const asked = 'Asked' + expected.holes[best.i].asked_mm.toFixed(2) + ' mm';
        expect(shown.text.includes(asked), `the panel does not show the hole's asked size, ${asked}: ${shown.text}`);
      }
    } else if (check === 'click_surface') {
      // A point on the sphere facing the camera, halfway between the two holes nearest the view's centre.
      const { centre, radius } = expected.sphere;
      const camera = await page.evaluate(() => window.poreshellViewer.cameraPosition());
      const toward = camera.map((c, k) => c - centre[k]);
      const n = Math.hypot(...toward);
      const holes = expected.holes.map((h) => ({ h, d: Math.hypot(...h.normal.map((c, k) => c - toward[k] / n)) }))
        .sort((a, b) => a.d - b.d);
      let normal = holes[0].h.normal.map((c, k) => c + holes[1].h.normal[k]);
      const len = Math.hypot(...normal);
      normal = normal.map((c) => c / len);
      const point = centre.map((c, k) => c + radius * normal[k]);
      const s = await page.evaluate((p, q) => window.poreshellViewer.project(...p, ...q), point, normal);
      expect(s.inView && s.facing, 'the point is not in view');
      await page.mouse.click(s.x, s.y);
      const shown = await page.$eval('#selection', (e) => e.dataset.point || '');
      const xyz = shown.split(',').map(Number);
      const error = xyz.length === 3 ? Math.hypot(...xyz.map((c, k) => c - point[k])) : Infinity;
      console.log(`clicked (${point.map((c) => c.toFixed(2))}), shown (${shown}), ${error.toFixed(3)} mm apart`);
      expect(error < 1.0, `the panel shows (${shown}) for the point (${point.map((c) => c.toFixed(2))})`);
      const arg = await page.$eval('#keep-out-arg', (e) => e.textContent);
      expect(arg.startsWith('--keep-out ' + shown + ','), 'no --keep-out argument: ' + arg);
    } else if (check === 'panel') {
      const labels = (id) => page.$$eval('#' + id + ' dt', (dts) => dts.map((d) => d.textContent));
      const request = await labels('request'), measured = await labels('measured');
      const note = await page.$eval('#print', (e) => e.textContent);
      const volume = await page.$eval('#volume', (e) => e.textContent).catch(() => '');
      console.log(`request: ${request.join(', ')}; measured: ${measured.join(', ')}; print: ${note.trim()}`);
      if (expected.preview) {
        expect(note.includes('a preview'), 'the panel does not say it is a preview: ' + note);
        for (const label of ['Wall', 'Triangles'])
          expect(!measured.includes(label), `a preview's panel shows a measured ${label}`);
        expect(!request.includes('Wall'), 'a preview\'s request shows a wall that was not asked for');
        expect(volume === '', 'a preview\'s panel shows a volume: ' + volume);
      } else {
        for (const label of ['Wall', 'Triangles'])
          expect(measured.includes(label), `the panel shows no measured ${label}`);
        expect(request.includes('Wall'), 'the request shows no wall');
        // The percentiles, and the probes through solid apart from them (the test data has 3, up to 6.08).
        const wall = await page.$$eval('#measured dt', (dts) => {
          const dt = dts.find((d) => d.textContent === 'Wall');
          return dt ? dt.nextElementSibling.textContent : '';
        });
        // The zones as asked and as the holes left them (the test data: rim 2 mm, 2.74 left; 1.83 mm off).
        const zones = await page.$eval('#zones', (e) => e.textContent);
        expect(zones.includes('Rim left2.7 mm') && zones.includes('Keep-out clearance1.8 mm'),
               'the zones show no measured rim or keep-out clearance: ' + zones);
        expect(wall.includes('1.97–2.04') && wall.includes('6.08 mm') && wall.includes('thinner than two walls'),
               'the wall row shows no percentiles and merged probes: ' + wall);
        expect(/\d cm³/.test(volume), 'the panel shows no volume: ' + volume);
      }
    } else {
      failures.push('unknown check ' + check);
    }
    console.log(`viewer ${check}: ${failures.some((f) => f.startsWith(check + ': ')) ? 'FAILED' : 'passed'}`);
  }
} finally {
  await browser.close();
}

if (failures.length) {
  for (const f of failures) console.error('FAIL: ' + f);
  process.exit(1);
}
console.log(`viewer ${checks.join(', ')}: passed`);

// A PNG decoder for 8-bit RGB/RGBA non-interlaced images (what Chromium writes).
function decodePng(buffer) {
  let at = 8, width = 0, height = 0, channels = 0;
  const idat = [];
  while (at < buffer.length) {
    const length = buffer.readUInt32BE(at), type = buffer.toString('ascii', at + 4, at + 8);
    const body = buffer.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      if (body[8] !== 8 || body[12] !== 0) throw new Error('unsupported PNG');
      channels = { 2: 3, 6: 4 }[body[9]];
      if (!channels) throw new Error('unsupported PNG colour type ' + body[9]);
    } else if (type === 'IDAT') {
      idat.push(body);
    }
    at += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const pixels = Buffer.alloc(height * stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    for (let x = 0; x < stride; ++x) {
      const v = raw[y * (stride + 1) + 1 + x];
      const a = x >= channels ? pixels[y * stride + x - channels] : 0;
      const b = y > 0 ? pixels[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? pixels[(y - 1) * stride + x - channels] : 0;
      let p;
      if (filter === 0) p = 0;
      else if (filter === 1) p = a;
      else if (filter === 2) p = b;
      else if (filter === 3) p = (a + b) >> 1;
      else {
        const e = a + b - c, pa = Math.abs(e - a), pb = Math.abs(e - b), pc = Math.abs(e - c);
        p = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      pixels[y * stride + x] = (v + p) & 255;
    }
  }
  return {
    width, height,
    pixel: (x, y) => [...pixels.subarray(y * stride + x * channels, y * stride + x * channels + 3)],
  };
}
