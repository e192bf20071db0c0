#!/usr/bin/env node
// SPDX-License-Identifier: GPL-3.0-or-later
// A real glTF viewer for tests: three.js (GLTFLoader + DRACOLoader, both from the npm
// packages in scripts/npm) in headless Chromium, driven by playwright-core. Files are
// served from a localhost HTTP server started here; nothing touches the network.
//
//   node scripts/gltf_viewer.mjs [--width W --height H] [--frame x0,y0,x1,y1]
//        IN.glb|IN.gltf -o SHOT.png [[--width W2 --height H2] IN2.glb -o SHOT2.png ...]
//        [--chromium PATH]
//
// Each input is followed by its screenshot path; one browser shows them all in turn.
// --width, --height and --frame apply to the inputs that follow them.
// The orthographic camera looks down -Z at the rectangle [x0,x1] x [y0,y1] of glTF units;
// by default each file's image frame [0, W] x [0, H] from asset.extras.sdvi
// (spec/GLTF.md), so with the default size one screenshot pixel is one source pixel. The
// renderer writes sRGB (outputColorSpace = SRGBColorSpace) from the linear vertex colours,
// without antialiasing, on a transparent background (alpha 0 where nothing is drawn).
// Prints one JSON line per file (size, vertices, triangles, times). Exit status: 0 done,
// 1 the viewer failed, 2 usage, 77 when node modules or Chromium are missing (tests skip).
import fs from 'node:fs';
import path from 'node:path';
import { loadPlaywright, npmDir, parseJobs, runViewer, usageFor } from './viewer_common.mjs';

const usage = usageFor('gltf_viewer', '[--width W --height H] [--frame x0,y0,x1,y1] ' +
                       'IN.glb|IN.gltf -o SHOT.png [[--width ...] IN2 -o SHOT2 ...] [--chromium PATH]');
const { chromium, jobs } = parseJobs(process.argv.slice(2), usage, {
  '--width': (v) => ({ width: Number(v) }),
  '--height': (v) => ({ height: Number(v) }),
  '--frame': (v) => ({ frame: v.split(',').map(Number) }),
});
const threeDir = path.join(npmDir, 'node_modules', 'three');
const playwright = loadPlaywright('gltf_viewer', chromium,
                                  ['three/build/three.module.js', 'three/examples/jsm/loaders/GLTFLoader.js',
                                   'three/examples/jsm/loaders/DRACOLoader.js',
                                   'three/examples/jsm/libs/draco/draco_decoder.wasm']);

// The glTF JSON (from a .glb's JSON chunk or a .gltf file), for the frame in asset.extras.
function readGltfJson(file) {
  const bytes = fs.readFileSync(file);
  if (bytes.length >= 20 && bytes.toString('latin1', 0, 4) === 'glTF') {
    const length = bytes.readUInt32LE(12);
    if (bytes.readUInt32LE(16) !== 0x4e4f534a || 20 + length > bytes.length) {
      throw new Error('the first GLB chunk is not a complete JSON chunk');
    }
    return JSON.parse(bytes.toString('utf8', 20, 20 + length));
  }
  return JSON.parse(bytes.toString('utf8'));
}

// The file names of a .gltf's external buffers (relative URIs without a directory).
function bufferFiles(file) {
  if (path.extname(file) !== '.gltf') return [];
  return (readGltfJson(file).buffers || [])
    .map((b) => b.uri || '')
    .filter((uri) => uri && !uri.startsWith('data:'))
    .map((uri) => decodeURIComponent(uri))
    .filter((name) => !name.includes('/') && !name.includes('\\') && name !== '..');
}

// Frame and output size of each job.
for (const job of jobs) {
  let gltfJson;
  try {
    gltfJson = readGltfJson(job.input);
  } catch (e) {
    console.error(`gltf_viewer: ${job.input}: ${e.message}`);
    process.exit(1);
  }
  const extras = gltfJson.asset?.extras?.sdvi;
  if (!job.frame && !extras) usage(`${job.input} has no asset.extras.sdvi: pass --frame`);
  job.frame ??= [0, 0, extras.source_width, extras.source_height];
  if (job.frame.length !== 4 || job.frame.some((v) => !Number.isFinite(v)) ||
      job.frame[2] <= job.frame[0] || job.frame[3] <= job.frame[1]) {
    usage('the frame must be x0,y0,x1,y1 with x1 > x0 and y1 > y0');
  }
  job.width ??= Math.round(job.frame[2] - job.frame[0]);
  job.height ??= Math.round(job.frame[3] - job.frame[1]);
  if (!(job.width >= 1 && job.height >= 1 && job.width <= 8192 && job.height <= 8192)) {
    usage('the screenshot size must be 1..8192 pixels each way');
  }
}

function page(index) {
  const job = jobs[index];
  return `<!doctype html>
<html><head><meta charset="utf-8"><style>html,body{margin:0;background:transparent}canvas{display:block}</style>
<script type="importmap">{"imports":{"three":"/three/build/three.module.js","three/addons/":"/three/examples/jsm/"}}</script>
</head><body><script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
const [x0, y0, x1, y1] = ${JSON.stringify(job.frame)};
const width = ${job.width}, height = ${job.height};
try {
  const renderer = new THREE.WebGLRenderer({ antialias: false, alpha: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.setClearColor(0x000000, 0);
  document.body.appendChild(renderer.domElement);
  const draco = new DRACOLoader();
  draco.setDecoderPath('/three/examples/jsm/libs/draco/');
  const loader = new GLTFLoader();
  loader.setDRACOLoader(draco);
  const t0 = performance.now();
  const gltf = await loader.loadAsync(${JSON.stringify(`/file/${index}/${path.basename(job.input)}`)});
  const t1 = performance.now();
  const scene = new THREE.Scene();
  scene.add(gltf.scene);
  const camera = new THREE.OrthographicCamera(x0, x1, y1, y0, 0.1, 1000);
  camera.position.set(0, 0, 100);
  camera.lookAt(0, 0, 0);
  renderer.render(scene, camera);
  let vertices = 0, triangles = 0, lines = 0;
  gltf.scene.traverse((o) => {
    if (!o.geometry) return;
    const n = o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count;
    vertices += o.geometry.attributes.position.count;
    if (o.isLineSegments) lines += n / 2; else if (o.isMesh) triangles += n / 3;
  });
  const gl = renderer.getContext();
  window.__sdvi = { ok: true, png: renderer.domElement.toDataURL('image/png'),
                    vertices, triangles, lines, load_ms: t1 - t0, render_ms: performance.now() - t1,
                    webgl: gl.getParameter(gl.VERSION) };
  draco.dispose();
} catch (e) {
  window.__sdvi = { ok: false, error: String(e && e.stack || e) };
}
</script></body></html>`;
}

await runViewer({
  name: 'gltf_viewer', what: 'three.js', playwright, chromium, jobs, page,
  staticDirs: { three: threeDir },
  extraFiles: (job) => bufferFiles(job.input),  // a .gltf's external buffers, beside it
  chromiumArgs: ['--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  timeoutMs: 120000,
  beforeJob: (tab, job) => tab.setViewportSize({ width: job.width, height: job.height }),
  report: (job, result) => ({ file: job.input, screenshot: job.out, width: job.width, height: job.height,
                              frame: job.frame, vertices: result.vertices, triangles: result.triangles,
                              lines: result.lines, load_ms: Math.round(result.load_ms),
                              render_ms: Math.round(result.render_ms), webgl: result.webgl }),
});
