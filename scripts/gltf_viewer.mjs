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
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';

const here = path.dirname(fileURLToPath(import.meta.url));
const npmDir = path.join(here, 'npm');
const require = createRequire(path.join(npmDir, 'package.json'));

function usage(message) {
  if (message) console.error(`gltf_viewer: ${message}`);
  console.error('usage: node scripts/gltf_viewer.mjs [--width W --height H] [--frame x0,y0,x1,y1] ' +
                'IN.glb|IN.gltf -o SHOT.png [[--width ...] IN2 -o SHOT2 ...] [--chromium PATH]');
  process.exit(2);
}

const opts = { chromium: process.env.SDVI_CHROMIUM || '/usr/bin/chromium' };
const jobs = [];  // {input, out}
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; ++i) {
  const a = argv[i];
  const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
  if (a === '-o') {
    if (jobs.length === 0 || jobs[jobs.length - 1].out) usage('-o must follow its input file');
    jobs[jobs.length - 1].out = path.resolve(value());
  } else if (a === '--width') opts.width = Number(value());
  else if (a === '--height') opts.height = Number(value());
  else if (a === '--frame') opts.frame = value().split(',').map(Number);
  else if (a === '--chromium') opts.chromium = value();
  else if (a.startsWith('-')) usage(`unknown option ${a}`);
  else jobs.push({ input: path.resolve(a), width: opts.width, height: opts.height, frame: opts.frame });
}
if (jobs.length === 0 || jobs.some((j) => !j.out)) usage('every input needs -o SHOT.png');

const threeDir = path.join(npmDir, 'node_modules', 'three');
let playwright;
try {
  playwright = require('playwright-core');
  for (const f of ['build/three.module.js', 'examples/jsm/loaders/GLTFLoader.js',
                   'examples/jsm/loaders/DRACOLoader.js', 'examples/jsm/libs/draco/draco_decoder.wasm']) {
    if (!fs.existsSync(path.join(threeDir, f))) throw new Error(`three/${f} is missing`);
  }
} catch (e) {
  console.error(`gltf_viewer: npm packages missing in ${npmDir} (${e.message}); run npm install there`);
  process.exit(77);
}
if (!fs.existsSync(opts.chromium)) {
  console.error(`gltf_viewer: no Chromium at ${opts.chromium}`);
  process.exit(77);
}

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
  const gltf = await loader.loadAsync(${JSON.stringify(`/model/${index}/${path.basename(job.input)}`)});
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

const types = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.wasm': 'application/wasm',
                '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json', '.html': 'text/html' };
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
  const model = /^\/model\/(\d+)\/([^/]+)$/.exec(pathname);
  if (pathname === '/') {
    const index = Number(url.searchParams.get('job'));
    if (!(index >= 0 && index < jobs.length)) { res.writeHead(404); res.end(); return; }
    res.writeHead(200, { 'content-type': 'text/html' });
    res.end(page(index));
  } else if (pathname === '/favicon.ico') {
    res.writeHead(204);
    res.end();
  } else if (model && Number(model[1]) < jobs.length &&
             model[2] === path.basename(jobs[Number(model[1])].input)) {
    serveFile(res, jobs[Number(model[1])].input);
  } else if (model && Number(model[1]) < jobs.length && bufferFiles(jobs[Number(model[1])].input).includes(model[2])) {
    // A .gltf's external buffer (the .bin beside it), by the name its buffers[].uri gives.
    serveFile(res, path.join(path.dirname(jobs[Number(model[1])].input), model[2]));
  } else if (pathname.startsWith('/three/')) {
    const file = path.resolve(threeDir, '.' + pathname.slice('/three'.length));
    if (!file.startsWith(threeDir + path.sep)) { res.writeHead(403); res.end(); return; }
    serveFile(res, file);
  } else {
    res.writeHead(404);
    res.end();
  }
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const origin = `http://127.0.0.1:${server.address().port}`;

const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'sdvi-gltf-viewer-'));
let context;
let status = 0;
try {
  context = await playwright.chromium.launchPersistentContext(userDataDir, {
    executablePath: opts.chromium,
    headless: true,
    deviceScaleFactor: 1,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const tab = context.pages()[0] ?? await context.newPage();
  tab.on('console', (m) => { if (m.type() === 'error') console.error(`page: ${m.text()}`); });
  tab.on('pageerror', (e) => console.error(`page: ${e.message}`));
  for (let i = 0; i < jobs.length; ++i) {
    const job = jobs[i];
    try {
      await tab.setViewportSize({ width: job.width, height: job.height });
      await tab.goto(`${origin}/?job=${i}`);
      await tab.waitForFunction(() => window.__sdvi !== undefined, null, { timeout: 120000 });
      const result = await tab.evaluate(() => window.__sdvi);
      if (!result.ok) throw new Error(`three.js could not show it: ${result.error}`);
      const png = Buffer.from(result.png.slice(result.png.indexOf(',') + 1), 'base64');
      const tmp = `${job.out}.tmp-${process.pid}`;
      fs.writeFileSync(tmp, png);
      fs.renameSync(tmp, job.out);
      console.log(JSON.stringify({ file: job.input, screenshot: job.out, width: job.width,
                                   height: job.height, frame: job.frame, vertices: result.vertices,
                                   triangles: result.triangles, lines: result.lines,
                                   load_ms: Math.round(result.load_ms),
                                   render_ms: Math.round(result.render_ms), webgl: result.webgl }));
    } catch (e) {
      console.error(`gltf_viewer: ${job.input}: ${e.message}`);
      status = 1;
    }
  }
} catch (e) {
  console.error(`gltf_viewer: ${e.message}`);
  status = 1;
} finally {
  if (context) await context.close();
  server.close();
  fs.rmSync(userDataDir, { recursive: true, force: true });
}
process.exit(status);
