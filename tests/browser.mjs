// The demo page in Debian's headless Chromium (WebGL through SwiftShader,
// driven by puppeteer-core): waits, in real time, until the page says it is
// ready (every picture loaded, both 3D views drawn), then checks its report
// and saves a screenshot of the viewport. Usage: node tests/browser.mjs DIR, where
// DIR holds index.html written by scripts/demo-pictures.sh.
//
// The page used to be read with `chromium --dump-dom --virtual-time-budget`,
// which dumps when the virtual budget runs out: on a loaded machine that was
// before the 70 MB of pictures had decoded, and the check line was missing.
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';
const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const require = createRequire(path.join(root, 'web', 'package.json'));
const puppeteer = require('puppeteer-core');

const out = path.resolve(process.argv[2] || path.join(root, 'target', 'demo-test'));
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  headless: true,
  protocolTimeout: 600000,
  args: ['--no-sandbox', '--disable-dev-shm-usage', '--hide-scrollbars', '--use-angle=swiftshader',
         '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--allow-file-access-from-files',
         '--window-size=1300,3600'],
});
const bad = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1300, height: 3600 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto('file://' + path.join(out, 'index.html'), { waitUntil: 'load', timeout: 300000 });
  await page.waitForFunction(() => document.body.dataset.ready === 'yes', { timeout: 300000, polling: 500 })
    .catch(() => { throw new Error('browser test: the page did not report within 300 s' +
                                   (errors.length ? '; page errors: ' + errors.join('; ') : '')); });
  const text = await page.$eval('#check', (e) => e.textContent);
  const rep = JSON.parse(text.replace(/^check /, ''));
  for (const p of rep.pictures) {
    if (p.width <= 0 || p.height <= 0) bad.push(`${p.file}: not decoded`);
    else if (p.drawn < 0.2 * p.width * p.height * 0.5)
      bad.push(`${p.file}: only ${p.drawn} of ${p.width} x ${p.height} pixels drawn`);
    console.log(`  ${p.file}: ${p.width} x ${p.height}, ${p.drawn} pixels drawn`);
  }
  for (const [view, n] of Object.entries(rep.views)) {
    if (!Number.isInteger(n) || n < 20000) bad.push(`${view}: ${n} pixels drawn`);
    console.log(`  ${view}: ${n} pixels drawn`);
  }
  if (rep.pictures.length < 9) bad.push(`only ${rep.pictures.length} pictures on the page`);
  // the close-ups of the levels show their triangles: each differs from
  // the next (mean grey difference of their 32 x 32 drawings)
  const zooms = rep.pictures.filter((p) => /^zoom-level-\d+\.svg$/.test(p.file))
    .sort((a, b) => parseInt(a.file.match(/\d+/)[0]) - parseInt(b.file.match(/\d+/)[0]));
  if (zooms.length < 3) bad.push(`only ${zooms.length} close-ups of the levels`);
  for (let i = 1; i < zooms.length; i++) {
    const [a, b] = [zooms[i - 1].signature, zooms[i].signature];
    if (a.length !== 1024 || b.length !== 1024) { bad.push(`${zooms[i].file}: no signature`); continue; }
    const diff = a.reduce((s, v, k) => s + Math.abs(v - b[k]), 0) / 1024;
    console.log(`  ${zooms[i - 1].file} -> ${zooms[i].file}: mean grey difference ${diff.toFixed(1)}`);
    if (diff < 2) bad.push(`${zooms[i].file} looks like ${zooms[i - 1].file} (mean grey difference ${diff.toFixed(2)})`);
  }
  const png = path.join(out, 'screenshot.png');
  // the viewport only: the whole page (levels, close-ups, merges) is
  // taller than Chromium captures at once
  await page.screenshot({ path: png });
  if (!fs.existsSync(png) || fs.statSync(png).size < 10000) bad.push('no screenshot');
  if (!bad.length)
    console.log(`browser test: ${rep.pictures.length} pictures and ${Object.keys(rep.views).length} 3D views rendered; screenshot ${png}`);
} catch (e) {
  bad.push(e.message);
} finally {
  await browser.close();
}
if (bad.length) {
  console.error('browser test failed:\n  ' + bad.join('\n  '));
  process.exit(1);
}
