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
import path from 'node:path';
import { checkScaleRegion, loadPlaywright, parseJobs, runViewer, scaleRegionOptions, usageFor }
  from './viewer_common.mjs';

const usage = usageFor('svg_viewer', '[--scale S] [--region x,y,w,h] IN.svg -o OUT.png ' +
                       '[[--scale ...] IN2.svg -o OUT2.png ...] [--chromium PATH]');
const { chromium, jobs } = parseJobs(process.argv.slice(2), usage, scaleRegionOptions);
checkScaleRegion(jobs, usage);
const playwright = loadPlaywright('svg_viewer', chromium);

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

await runViewer({
  name: 'svg_viewer', what: 'Chromium', playwright, chromium, jobs, page,
  report: (job, result) => ({ file: job.input, out: job.out, width: result.width, height: result.height,
                              scale: job.scale, load_ms: Math.round(result.load_ms),
                              render_ms: Math.round(result.render_ms) }),
});
