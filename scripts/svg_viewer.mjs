#!/usr/bin/env node
// SPDX-License-Identifier: GPL-3.0-or-later
// Chromium's own SVG renderer (an <img> drawn into a canvas, in headless Chromium driven by
// playwright-core), for bench_pdf --svg-dir's measurement of SVG as a vector output (README
// "Vector output"). Files are served from a localhost HTTP server; nothing touches the network.
//
//   node scripts/svg_viewer.mjs [--scale S] [--region x,y,w,h] IN.svg -o OUT.png ...
//
// --scale multiplies the SVG's width and height; --region crops the output (whole output
// pixels). Transparent background; RGBA PNG. Exit status: 0 done, 1 failed, 2 usage, 77
// when playwright-core or Chromium is missing.
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';

const here = path.dirname(fileURLToPath(import.meta.url));
const npmDir = path.join(here, 'npm');
const require = createRequire(path.join(npmDir, 'package.json'));

function usage(message) {
  if (message) console.error(`svg_viewer: ${message}`);
  console.error('usage: node scripts/svg_viewer.mjs [--scale S] [--region x,y,w,h] IN.svg -o OUT.png ' +
                '[[--scale ...] IN2.svg -o OUT2.png ...] [--chromium PATH]');
  process.exit(2);
}

const opts = { chromium: process.env.SDVI_CHROMIUM || '/usr/bin/chromium', scale: 1 };
const jobs = [];  // {input, out, scale, region}
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; ++i) {
  const a = argv[i];
  const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
  if (a === '-o') {
    if (jobs.length === 0 || jobs[jobs.length - 1].out) usage('-o must follow its input file');
    jobs[jobs.length - 1].out = path.resolve(value());
  } else if (a === '--scale') opts.scale = Number(value());
  else if (a === '--region') opts.region = value().split(',').map(Number);
  else if (a === '--chromium') opts.chromium = value();
  else if (a.startsWith('-')) usage(`unknown option ${a}`);
  else jobs.push({ input: path.resolve(a), scale: opts.scale, region: opts.region });
}
if (jobs.length === 0 || jobs.some((j) => !j.out)) usage('every input needs -o OUT.png');
for (const job of jobs) {
  if (!(job.scale > 0 && job.scale <= 64)) usage('--scale must lie in (0, 64]');
  if (job.region && (job.region.length !== 4 || job.region.some((v) => !Number.isInteger(v)) ||
                     job.region[2] < 1 || job.region[3] < 1 ||
                     job.region[2] > 8192 || job.region[3] > 8192)) {
    usage('--region must be x,y,w,h in whole output pixels, w and h in 1..8192');
  }
}

let playwright;
try {
  playwright = require('playwright-core');
} catch (e) {
  console.error(`svg_viewer: npm packages missing in ${npmDir} (${e.message}); run npm install there`);
  process.exit(77);
}
if (!fs.existsSync(opts.chromium)) {
  console.error(`svg_viewer: no Chromium at ${opts.chromium}`);
  process.exit(77);
}

function page(index) {
  const job = jobs[index];
  return `<!doctype html>
<html><head><meta charset="utf-8"></head><body><script type="module">
const scale = ${job.scale}, region = ${JSON.stringify(job.region ?? null)};
try {
  const img = new Image();
  const t0 = performance.now();
  img.src = ${JSON.stringify(`/file/${index}/${path.basename(job.input)}`)};
  await img.decode();
  const W = img.naturalWidth * scale, H = img.naturalHeight * scale;
  const [x, y, w, h] = region ?? [0, 0, Math.round(W), Math.round(H)];
  const canvas = document.createElement('canvas');
  canvas.width = w;
  canvas.height = h;
  const ctx = canvas.getContext('2d');
  const t1 = performance.now();
  ctx.drawImage(img, -x, -y, W, H);
  window.__sdvi = { ok: true, png: canvas.toDataURL('image/png'), width: w, height: h,
                    load_ms: t1 - t0, render_ms: performance.now() - t1 };
} catch (e) {
  window.__sdvi = { ok: false, error: String(e && e.stack || e) };
}
</script></body></html>`;
}

const types = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.svg': 'image/svg+xml',
                '.html': 'text/html', '.map': 'application/json' };
function serveFile(res, file) {
  fs.readFile(file, (err, data) => {
    if (err) { res.writeHead(404); res.end(); return; }
    res.writeHead(200, { 'content-type': types[path.extname(file)] || 'application/octet-stream' });
    res.end(data);
  });
}
const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://localhost');
  const pathname = decodeURIComponent(url.pathname);
  const file = /^\/file\/(\d+)\/([^/]+)$/.exec(pathname);
  if (pathname === '/') {
    const index = Number(url.searchParams.get('job'));
    if (!(index >= 0 && index < jobs.length)) { res.writeHead(404); res.end(); return; }
    res.writeHead(200, { 'content-type': 'text/html' });
    res.end(page(index));
  } else if (pathname === '/favicon.ico') {
    res.writeHead(204);
    res.end();
  } else if (file && Number(file[1]) < jobs.length &&
             file[2] === path.basename(jobs[Number(file[1])].input)) {
    serveFile(res, jobs[Number(file[1])].input);
  } else {
    res.writeHead(404);
    res.end();
  }
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const origin = `http://127.0.0.1:${server.address().port}`;

const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'sdvi-svg-viewer-'));
let context;
let status = 0;
try {
  context = await playwright.chromium.launchPersistentContext(userDataDir, {
    executablePath: opts.chromium,
    headless: true,
    deviceScaleFactor: 1,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const tab = context.pages()[0] ?? await context.newPage();
  tab.on('console', (m) => { if (m.type() === 'error') console.error(`page: ${m.text()}`); });
  tab.on('pageerror', (e) => console.error(`page: ${e.message}`));
  for (let i = 0; i < jobs.length; ++i) {
    const job = jobs[i];
    try {
      await tab.goto(`${origin}/?job=${i}`, { timeout: 300000 });
      await tab.waitForFunction(() => window.__sdvi !== undefined, null, { timeout: 300000 });
      const result = await tab.evaluate(() => window.__sdvi);
      if (!result.ok) throw new Error(`Chromium could not draw it: ${result.error}`);
      const png = Buffer.from(result.png.slice(result.png.indexOf(',') + 1), 'base64');
      const tmp = `${job.out}.tmp-${process.pid}`;
      fs.writeFileSync(tmp, png);
      fs.renameSync(tmp, job.out);
      console.log(JSON.stringify({ file: job.input, out: job.out, width: result.width,
                                   height: result.height, scale: job.scale,
                                   load_ms: Math.round(result.load_ms),
                                   render_ms: Math.round(result.render_ms) }));
    } catch (e) {
      console.error(`svg_viewer: ${job.input}: ${e.message}`);
      status = 1;
    }
  }
} catch (e) {
  console.error(`svg_viewer: ${e.message}`);
  status = 1;
} finally {
  if (context) await context.close();
  server.close();
  fs.rmSync(userDataDir, { recursive: true, force: true });
}
process.exit(status);
