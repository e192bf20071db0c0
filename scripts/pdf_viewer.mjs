#!/usr/bin/env node
// SPDX-License-Identifier: GPL-3.0-or-later
// pdf.js (npm pdfjs-dist, the viewer of Firefox) in headless Chromium, driven by
// playwright-core, for the PDF tests and scripts/pdf_report.sh. Files are served from a
// localhost HTTP server started here; nothing touches the network.
//
//   node scripts/pdf_viewer.mjs [--webgpu] [--scale S] [--region x,y,w,h] IN.pdf -o OUT.png
//        [[--scale S2] [--region ...] IN2.pdf -o OUT2.png ...] [--chromium PATH]
//
// Each input is followed by its output path; one browser draws them all in turn. --scale
// (output pixels per point, 1 = 72 dpi) and --region (output pixels, like pdftoppm's -x -y
// -W -H) apply to the inputs that follow them; without --region the whole page, rounded to
// whole pixels. Page 1 is drawn on a transparent canvas (alpha 0 where nothing is painted)
// and saved as an RGBA PNG. Prints one JSON line per file (size, times). Exit status: 0
// done, 1 the viewer failed, 2 usage, 77 when node modules or Chromium are missing.
//
// --webgpu draws mesh shadings with pdf.js's WebGPU path (getDocument's enableWebGPU, on
// SwiftShader's Vulkan adapter) instead of its default canvas path, which samples each
// triangle at the corners of its pixels (drawTriangle in pdf.js's pattern_helper), half a
// pixel of its 1.1x scratch canvas off where poppler, MuPDF and `sdvi render` sample
// (spec/PDF.md, "Viewers"). A job fails when Chromium offers no WebGPU adapter.
import path from 'node:path';
import { checkScaleRegion, loadPlaywright, npmDir, parseJobs, runViewer, scaleRegionOptions, usageFor }
  from './viewer_common.mjs';

const webgpu = process.argv.includes('--webgpu');
const usage = usageFor('pdf_viewer', '[--webgpu] [--scale S] [--region x,y,w,h] IN.pdf -o OUT.png ' +
                       '[[--scale ...] IN2.pdf -o OUT2.png ...] [--chromium PATH]');
const { chromium, jobs } = parseJobs(process.argv.slice(2).filter((a) => a !== '--webgpu'), usage,
                                     scaleRegionOptions);
checkScaleRegion(jobs, usage);
const playwright = loadPlaywright('pdf_viewer', chromium, ['pdfjs-dist/build/pdf.mjs', 'pdfjs-dist/build/pdf.worker.mjs']);

function page(index) {
  const job = jobs[index];
  return `<!doctype html>
<html><head><meta charset="utf-8"><style>html,body{margin:0;background:transparent}</style>
</head><body><script type="module">
import * as pdfjs from '/pdfjs/build/pdf.mjs';
pdfjs.GlobalWorkerOptions.workerSrc = '/pdfjs/build/pdf.worker.mjs';
const scale = ${job.scale}, region = ${JSON.stringify(job.region ?? null)};
try {
  if (${webgpu} && !(navigator.gpu && await navigator.gpu.requestAdapter())) {
    throw new Error('--webgpu: Chromium offers no WebGPU adapter');
  }
  const t0 = performance.now();
  const doc = await pdfjs.getDocument({ url: ${JSON.stringify(`/file/${index}/${path.basename(job.input)}`)},
                                        isEvalSupported: false, enableWebGPU: ${webgpu} }).promise;
  const pdfPage = await doc.getPage(1);
  const viewport = pdfPage.getViewport({ scale });
  const t1 = performance.now();
  const [x, y, w, h] = region ?? [0, 0, Math.round(viewport.width), Math.round(viewport.height)];
  const canvas = document.createElement('canvas');
  canvas.width = w;
  canvas.height = h;
  document.body.appendChild(canvas);
  const canvasContext = canvas.getContext('2d');
  await pdfPage.render({ canvas, canvasContext, viewport, transform: [1, 0, 0, 1, -x, -y],
                         background: 'rgba(0,0,0,0)' }).promise;
  window.__sdvi = { ok: true, png: canvas.toDataURL('image/png'), width: w, height: h,
                    load_ms: t1 - t0, render_ms: performance.now() - t1 };
} catch (e) {
  window.__sdvi = { ok: false, error: String(e && e.stack || e) };
}
</script></body></html>`;
}

await runViewer({
  name: 'pdf_viewer', what: 'pdf.js', playwright, chromium, jobs, page,
  staticDirs: { pdfjs: path.join(npmDir, 'node_modules', 'pdfjs-dist') },
  gpu: webgpu,
  chromiumArgs: webgpu ? ['--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader',
                          '--use-webgpu-adapter=swiftshader', '--use-angle=swiftshader'] : [],
  report: (job, result) => ({ file: job.input, out: job.out, width: result.width, height: result.height,
                              scale: job.scale, load_ms: Math.round(result.load_ms),
                              render_ms: Math.round(result.render_ms), webgpu }),
});
