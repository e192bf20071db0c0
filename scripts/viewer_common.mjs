// SPDX-License-Identifier: GPL-3.0-or-later
// What the headless-Chromium viewers (gltf_viewer.mjs, pdf_viewer.mjs, svg_viewer.mjs)
// share: the command line (inputs each followed by -o OUT.png, options that apply to the
// inputs after them), the npm packages in scripts/npm, a localhost HTTP server (nothing
// touches the network), one Chromium driven by playwright-core that draws every job in turn
// and the atomic write of each PNG. Each viewer supplies its page, its options and its
// report line. Exit status: 0 done, 1 a job failed, 2 usage, 77 when node modules or
// Chromium are missing (tests skip).
import fs from 'node:fs';
import http from 'node:http';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';

export const npmDir = path.join(path.dirname(fileURLToPath(import.meta.url)), 'npm');
const require = createRequire(path.join(npmDir, 'package.json'));

// A usage function for viewer `name`: prints the message and the usage line, exits 2.
export function usageFor(name, line) {
  return (message) => {
    if (message) console.error(`${name}: ${message}`);
    console.error(`usage: node scripts/${name}.mjs ${line}`);
    process.exit(2);
  };
}

// Parses `[options] IN -o OUT [[options] IN2 -o OUT2 ...] [--chromium PATH]`. `sticky` maps
// an option to a function (value string -> { key: value }) whose result is merged into every
// job that follows it. Returns { chromium, jobs }, each job { input, out, ...sticky values }.
export function parseJobs(argv, usage, sticky) {
  let chromium = process.env.SDVI_CHROMIUM || '/usr/bin/chromium';
  let current = {};
  const jobs = [];
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
    if (a === '-o') {
      if (jobs.length === 0 || jobs[jobs.length - 1].out) usage('-o must follow its input file');
      jobs[jobs.length - 1].out = path.resolve(value());
    } else if (a === '--chromium') chromium = value();
    else if (Object.hasOwn(sticky, a)) current = { ...current, ...sticky[a](value()) };
    else if (a.startsWith('-')) usage(`unknown option ${a}`);
    else jobs.push({ input: path.resolve(a), ...current });
  }
  if (jobs.length === 0 || jobs.some((j) => !j.out)) usage('every input needs -o OUT.png');
  return { chromium, jobs };
}

// The sticky --scale and --region options of the PDF and SVG viewers, checked.
export const scaleRegionOptions = {
  '--scale': (v) => ({ scale: Number(v) }),
  '--region': (v) => ({ region: v.split(',').map(Number) }),
};
export function checkScaleRegion(jobs, usage) {
  for (const job of jobs) {
    job.scale ??= 1;
    if (!(job.scale > 0 && job.scale <= 64)) usage('--scale must lie in (0, 64]');
    if (job.region && (job.region.length !== 4 || job.region.some((v) => !Number.isInteger(v)) ||
                       job.region[2] < 1 || job.region[3] < 1 ||
                       job.region[2] > 8192 || job.region[3] > 8192)) {
      usage('--region must be x,y,w,h in whole output pixels, w and h in 1..8192');
    }
  }
}

// playwright-core, after checking that `files` (paths under scripts/npm/node_modules) and
// Chromium exist; exits 77 otherwise.
export function loadPlaywright(name, chromium, files = []) {
  let playwright;
  try {
    playwright = require('playwright-core');
    for (const f of files) {
      if (!fs.existsSync(path.join(npmDir, 'node_modules', f))) throw new Error(`${f} is missing`);
    }
  } catch (e) {
    console.error(`${name}: npm packages missing in ${npmDir} (${e.message}); run npm install there`);
    process.exit(77);
  }
  if (!fs.existsSync(chromium)) {
    console.error(`${name}: no Chromium at ${chromium}`);
    process.exit(77);
  }
  return playwright;
}

const types = { '.js': 'text/javascript', '.mjs': 'text/javascript', '.wasm': 'application/wasm',
                '.html': 'text/html', '.map': 'application/json', '.pdf': 'application/pdf',
                '.svg': 'image/svg+xml', '.glb': 'model/gltf-binary', '.gltf': 'model/gltf+json' };
function serveFile(res, file) {
  fs.readFile(file, (err, data) => {
    if (err) { res.writeHead(404); res.end(); return; }
    res.writeHead(200, { 'content-type': types[path.extname(file)] || 'application/octet-stream' });
    res.end(data);
  });
}

// Draws every job in one Chromium and exits with the status. The server answers
//   /?job=I                 page(I), the HTML that sets window.__sdvi = { ok, png, ... }
//   /file/I/NAME            job I's input (NAME its base name), or a file beside it that
//                           extraFiles(job) names
//   /PREFIX/...             the files under staticDirs[PREFIX] (a folder of node_modules)
// Each job's PNG (result.png, a data URL) is written atomically to job.out and
// report(job, result) printed as one JSON line. `beforeJob(tab, job)` may size the tab.
// Chromium runs with --disable-gpu unless `gpu` is set (then `chromiumArgs` name the software
// adapter, e.g. SwiftShader's Vulkan for WebGPU).
export async function runViewer({ name, what, playwright, chromium, jobs, page, staticDirs = {},
                                  extraFiles = () => [], chromiumArgs = [], gpu = false, timeoutMs = 300000,
                                  beforeJob = async () => {}, report }) {
  const server = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://localhost');
    const pathname = decodeURIComponent(url.pathname);
    const file = /^\/file\/(\d+)\/([^/]+)$/.exec(pathname);
    const prefix = pathname.split('/')[1];
    if (pathname === '/') {
      const index = Number(url.searchParams.get('job'));
      if (!(index >= 0 && index < jobs.length)) { res.writeHead(404); res.end(); return; }
      res.writeHead(200, { 'content-type': 'text/html' });
      res.end(page(index));
    } else if (pathname === '/favicon.ico') {
      res.writeHead(204);
      res.end();
    } else if (file && Number(file[1]) < jobs.length) {
      const job = jobs[Number(file[1])];
      if (file[2] === path.basename(job.input)) serveFile(res, job.input);
      else if (extraFiles(job).includes(file[2])) serveFile(res, path.join(path.dirname(job.input), file[2]));
      else { res.writeHead(404); res.end(); }
    } else if (Object.hasOwn(staticDirs, prefix)) {
      const dir = staticDirs[prefix];
      const f = path.resolve(dir, '.' + pathname.slice(prefix.length + 1));
      if (!f.startsWith(dir + path.sep)) { res.writeHead(403); res.end(); return; }
      serveFile(res, f);
    } else {
      res.writeHead(404);
      res.end();
    }
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  const origin = `http://127.0.0.1:${server.address().port}`;

  const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), `sdvi-${name}-`));
  let context;
  let status = 0;
  try {
    context = await playwright.chromium.launchPersistentContext(userDataDir, {
      executablePath: chromium,
      headless: true,
      deviceScaleFactor: 1,
      args: ['--headless', '--no-sandbox', ...(gpu ? [] : ['--disable-gpu']), '--disable-quic', '--no-first-run',
             '--disable-background-networking', '--disable-component-update', '--disable-sync',
             ...chromiumArgs],
    });
    const tab = context.pages()[0] ?? await context.newPage();
    tab.on('console', (m) => { if (m.type() === 'error') console.error(`page: ${m.text()}`); });
    tab.on('pageerror', (e) => console.error(`page: ${e.message}`));
    for (let i = 0; i < jobs.length; ++i) {
      const job = jobs[i];
      try {
        await beforeJob(tab, job);
        await tab.goto(`${origin}/?job=${i}`, { timeout: timeoutMs });
        await tab.waitForFunction(() => window.__sdvi !== undefined, null, { timeout: timeoutMs });
        const result = await tab.evaluate(() => window.__sdvi);
        if (!result.ok) throw new Error(`${what} could not draw it: ${result.error}`);
        const png = Buffer.from(result.png.slice(result.png.indexOf(',') + 1), 'base64');
        const tmp = `${job.out}.tmp-${process.pid}`;
        fs.writeFileSync(tmp, png);
        fs.renameSync(tmp, job.out);
        console.log(JSON.stringify(report(job, result)));
      } catch (e) {
        console.error(`${name}: ${job.input}: ${e.message}`);
        status = 1;
      }
    }
  } catch (e) {
    console.error(`${name}: ${e.message}`);
    status = 1;
  } finally {
    if (context) await context.close();
    server.close();
    fs.rmSync(userDataDir, { recursive: true, force: true });
  }
  process.exit(status);
}
