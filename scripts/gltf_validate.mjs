#!/usr/bin/env node
// SPDX-License-Identifier: GPL-3.0-or-later
// Validates glTF files with the Khronos glTF-Validator (npm gltf-validator, validateBytes).
//   node scripts/gltf_validate.mjs FILE.glb|FILE.gltf... [--json REPORT.json]
// Prints one line per file (errors, warnings, infos, hints) and every error/warning
// message. Exit status: 0 when every file has zero errors and zero warnings, 1 when any
// has one, 2 on usage or read errors, 77 when the npm packages are not installed (run
// `npm install` in scripts/npm; tests treat 77 as skipped).
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { createRequire } from 'node:module';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, 'npm', 'package.json'));

let validator;
try {
  validator = require('gltf-validator');
} catch (e) {
  console.error(`gltf_validate: gltf-validator is not installed in ${path.join(here, 'npm')}: ${e.message}`);
  process.exit(77);
}

const files = [];
let jsonOut = null;
const argv = process.argv.slice(2);
for (let i = 0; i < argv.length; ++i) {
  if (argv[i] === '--json') jsonOut = argv[++i];
  else files.push(argv[i]);
}
if (files.length === 0) {
  console.error('usage: node scripts/gltf_validate.mjs FILE.glb|FILE.gltf... [--json REPORT.json]');
  process.exit(2);
}

const severityName = ['error', 'warning', 'info', 'hint'];
let failed = false;
const reports = {};
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(fs.readFileSync(file));
  } catch (e) {
    console.error(`gltf_validate: ${file}: cannot read: ${e.message}`);
    process.exit(2);
  }
  const dir = path.dirname(path.resolve(file));
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,  // report everything
    // External buffers/images (sdvi writes none) resolve next to the file, never the network.
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      const target = path.resolve(dir, decodeURIComponent(uri));
      if (!target.startsWith(dir + path.sep)) return reject(new Error(`${uri} is outside ${dir}`));
      fs.readFile(target, (err, data) => (err ? reject(err) : resolve(new Uint8Array(data))));
    }),
  });
  const is = report.issues;
  console.log(`${file}: ${is.numErrors} errors, ${is.numWarnings} warnings, ${is.numInfos} infos, ` +
              `${is.numHints} hints (${report.validatorVersion})`);
  for (const m of is.messages) {
    if (m.severity <= 1 || process.env.SDVI_GLTF_VALIDATE_VERBOSE) {
      console.log(`  ${severityName[m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
    }
  }
  if (is.numErrors > 0 || is.numWarnings > 0) failed = true;
  reports[file] = report;
}
if (jsonOut) fs.writeFileSync(jsonOut, JSON.stringify(reports, null, 2));
process.exit(failed ? 1 : 0);
