#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Runs the Khronos glTF validator (npm package gltf-validator) over .glb/.gltf files and prints
// every message it reports with its severity, code and JSON pointer.
//
//   node tools/web/validate.mjs FILE.glb... [--json]
//
// The validator does not check the MSFT_lod extension (it reports UNSUPPORTED_EXTENSION, an
// info), so this script checks it itself and reports its findings as errors coded
// RAMIFORM_MSFT_LOD_* (see msftLodIssues below).
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

// The JSON of a GLB (or of a .gltf file), or null when it cannot be parsed.
function gltfJson(bytes) {
  try {
    const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    if (bytes.length >= 20 && view.getUint32(0, true) === 0x46546c67) {
      const length = view.getUint32(12, true);
      return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length)));
    }
    return JSON.parse(new TextDecoder().decode(bytes));
  } catch {
    return null;
  }
}

// MSFT_lod (Microsoft's vendor extension): a node's extensions.MSFT_lod.ids lists the nodes of
// its coarser levels, finest first; extras.MSFT_screencoverage, when present, has one
// decreasing value in (0, 1] per level (the node itself and each id).
function msftLodIssues(json) {
  const issues = [];
  const nodes = Array.isArray(json?.nodes) ? json.nodes : [];
  const inScene = new Set();
  for (const scene of json?.scenes ?? []) for (const n of scene.nodes ?? []) inScene.add(n);
  const used = (json?.extensionsUsed ?? []).includes('MSFT_lod');
  let any = false;
  nodes.forEach((node, i) => {
    const lod = node?.extensions?.MSFT_lod;
    if (lod === undefined) return;
    any = true;
    const at = `/nodes/${i}/extensions/MSFT_lod`;
    const add = (code, pointer, message) => issues.push({ code: `RAMIFORM_MSFT_LOD_${code}`, pointer, message, severity: 0 });
    const ids = lod.ids;
    if (!Array.isArray(ids) || ids.length === 0) {
      add('IDS', `${at}/ids`, 'ids must be a non-empty array of node indices');
      return;
    }
    ids.forEach((id, k) => {
      if (!Number.isInteger(id) || id < 0 || id >= nodes.length) {
        add('IDS', `${at}/ids/${k}`, `${id} is not a node index (${nodes.length} nodes)`);
      } else if (id === i || ids.indexOf(id) !== k) {
        add('IDS', `${at}/ids/${k}`, `node ${id} is the node itself or listed twice`);
      } else {
        if (inScene.has(id)) add('IN_SCENE', `${at}/ids/${k}`, `level node ${id} is also a scene root: viewers without MSFT_lod draw it on top of level 0`);
        if (nodes[id].mesh === undefined && node.mesh !== undefined) add('NO_MESH', `/nodes/${id}`, `level node ${id} has no mesh`);
      }
    });
    const coverage = node?.extras?.MSFT_screencoverage;
    if (coverage !== undefined) {
      const at2 = `/nodes/${i}/extras/MSFT_screencoverage`;
      if (!Array.isArray(coverage) || coverage.length !== ids.length + 1) {
        add('COVERAGE', at2, `needs ${ids.length + 1} values (one per level), got ${JSON.stringify(coverage)}`);
      } else if (coverage.some((c, k) => !(typeof c === 'number' && c > 0 && c <= 1 && (k === 0 || c < coverage[k - 1])))) {
        add('COVERAGE', at2, `values must decrease within (0, 1]: ${JSON.stringify(coverage)}`);
      }
    }
  });
  if (any && !used) {
    issues.push({ code: 'RAMIFORM_MSFT_LOD_NOT_DECLARED', pointer: '/extensionsUsed', severity: 0,
                  message: 'a node uses MSFT_lod but extensionsUsed does not list it' });
  }
  return issues;
}

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
  const lodIssues = msftLodIssues(gltfJson(bytes));
  if (lodIssues.length) {
    issues.messages.push(...lodIssues);
    issues.numErrors += lodIssues.length;
  }
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
