#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Runs the Khronos glTF validator (npm package gltf-validator) over .glb/.gltf files and prints
// every message it reports with its severity, code and JSON pointer.
//
//   node tools/web/validate.mjs FILE.glb... [--json]
//
// Exit code: 0 when every file has no error and no warning (infos and hints are printed but
// allowed), 1 when some file has an error or a warning, 2 when some file cannot be read or is not
// glTF at all (the validator cannot even detect its format), 3 for a usage error.
import { readFile } from 'node:fs/promises';
import { createRequire } from 'node:module';
import { basename } from 'node:path';

const require = createRequire(import.meta.url);
const validator = require('gltf-validator');

const kSeverity = ['error', 'warning', 'info', 'hint'];

function usage(message) {
  if (message) console.error(`validate.mjs: ${message}`);
  console.error('usage: node validate.mjs FILE.glb... [--json]');
  console.error('  exit 0: no errors and no warnings; 1: errors or warnings; 2: unreadable input');
  process.exit(3);
}

const files = [];
let json = false;
for (const arg of process.argv.slice(2)) {
  if (arg === '--json') json = true;
  else if (arg === '--help' || arg === '-h') usage();
  else if (arg.startsWith('--')) usage(`unknown option ${arg}`);
  else files.push(arg);
}
if (files.length === 0) usage('no input file');

let unreadable = false;
let failed = false;
const reports = [];
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(await readFile(file));
  } catch (e) {
    console.error(`${file}: cannot read: ${e.message}`);
    unreadable = true;
    continue;
  }
  let report;
  try {
    report = await validator.validateBytes(bytes, {
      uri: basename(file),
      maxIssues: 0,  // every message, not only the first 100
      writeTimestamp: false,
      // A .glb from ramiform is self-contained; a .gltf naming external files gets them
      // reported as unloadable rather than read from disk.
      externalResourceFunction: (uri) => Promise.reject(`external resource ${uri} not loaded`),
    });
  } catch (e) {
    console.error(`${file}: not a glTF asset: ${e}`);
    unreadable = true;
    continue;
  }
  const issues = report.issues;
  if (json) {
    reports.push({ file, report });
  } else {
    const info = report.info || {};
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos, ${issues.numHints} hints ` +
                `(glTF Validator ${report.validatorVersion})`);
    const used = info.extensionsUsed && info.extensionsUsed.length ?
        ` extensions: ${info.extensionsUsed.join(', ')};` : '';
    console.log(`  generator: ${info.generator ?? '-'};${used} draw calls: ${info.drawCallCount ?? 0}, ` +
                `vertices: ${info.totalVertexCount ?? 0}, triangles: ${info.totalTriangleCount ?? 0}`);
    for (const m of issues.messages) {
      const where = m.pointer !== undefined ? ` at ${m.pointer}` :
                    m.offset !== undefined ? ` at byte ${m.offset}` : '';
      console.log(`  ${kSeverity[m.severity] ?? m.severity} ${m.code}${where}: ${m.message}`);
    }
  }
  if (issues.numErrors > 0 || issues.numWarnings > 0) failed = true;
}
if (json) console.log(JSON.stringify(reports, null, 2));
process.exit(unreadable ? 2 : failed ? 1 : 0);
