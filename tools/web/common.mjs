// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// What render.mjs and render_grid.mjs share: a page that renders .glb files with three.js's
// GLTFLoader in headless Chromium (Debian's /usr/bin/chromium, driven by playwright-core),
// served from 127.0.0.1, and the command-line plumbing around it.
//
//   usageFunction    the usage message of a script (exit code 3)
//   parseArgs        the option loop: value checks, --chromium, --json, --help, positionals
//   readModels       the input files (exit code 2 when one cannot be read)
//   checkTools       three.js in node_modules and the browser present (exit code 3)
//   pageHtml         the page: an import map for three.js, a canvas and the page's module, which
//                    may use THREE, GLTFLoader, newRenderer(W, H) and failure(e)
//   renderPage       serves the page, three.js and the models (/model0.glb, /model1.glb, ...),
//                    runs it in the browser and returns what it left in window.renderResult
//                    (exit code 3 on a browser failure, 2 when three.js could not load a model)
//   writeDataUrlPng  writes the PNG of a data: URL (canvas.toDataURL)
//   formatVector     numbers for the text report
//   printReport      the report on stdout: one JSON object, or text lines
import { readFile, writeFile } from 'node:fs/promises';
import { createServer } from 'node:http';
import { dirname, join, normalize } from 'node:path';
import { fileURLToPath } from 'node:url';
import { existsSync } from 'node:fs';
import { chromium } from 'playwright-core';

export const here = dirname(fileURLToPath(import.meta.url));
const threeDir = join(here, 'node_modules', 'three');

export const kChromium = '/usr/bin/chromium';

// A usage(message) for `script`: prints the message (if any) and the synopsis, exits with 3.
export function usageFunction(script, synopsis) {
  return (message) => {
    if (message) console.error(`${script}: ${message}`);
    console.error(`usage: node ${script} ${synopsis}`);
    process.exit(3);
  };
}

// Walks the arguments: option(a, helpers) handles a script's own options (true when it took
// a); --chromium PATH, --json and --help are common; the rest are positional (returned). The
// helpers read the option's value and check it, calling usage on a bad one.
export function parseArgs(argv, opts, usage, option) {
  const positional = [];
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    const value = () => {
      if (i + 1 >= argv.length) usage(`${a} needs a value`);
      return argv[++i];
    };
    const integer = (name, lo, hi) => {
      const v = value();
      if (!/^\d+$/.test(v) || +v < lo || +v > hi) usage(`${name} must be an integer in [${lo}, ${hi}], got ${v}`);
      return +v;
    };
    const numbers = (name) => {
      const v = value().split(',');
      if (v.some((x) => x.trim() === '' || !Number.isFinite(+x))) usage(`${name} must be numbers, got ${v}`);
      return v.map(Number);
    };
    const colour = (name) => {
      const v = value();
      if (!/^[0-9a-fA-F]{6}$/.test(v)) usage(`${name} must be six hex digits, got ${v}`);
      return v;
    };
    if (option(a, { value, integer, numbers, colour })) continue;
    if (a === '--chromium') opts.chromium = value();
    else if (a === '--json') opts.json = true;
    else if (a === '--help' || a === '-h') usage();
    else if (a.startsWith('--')) usage(`unknown option ${a}`);
    else positional.push(a);
  }
  return positional;
}

// The contents of the files, in order; exits with 2 at the first that cannot be read.
export async function readModels(script, files) {
  const models = [];
  for (const file of files) {
    try {
      models.push(await readFile(file));
    } catch (e) {
      console.error(`${script}: ${file}: cannot read: ${e.message}`);
      process.exit(2);
    }
  }
  return models;
}

// Exits with 3 when three.js is not installed (npm ci) or there is no browser at chromiumPath.
export function checkTools(script, chromiumPath) {
  if (!existsSync(join(threeDir, 'build', 'three.module.js'))) {
    console.error(`${script}: three.js is missing: run "npm ci" in ${here}`);
    process.exit(3);
  }
  if (!existsSync(chromiumPath)) {
    console.error(`${script}: no browser at ${chromiumPath} (Debian: apt-get install chromium)`);
    process.exit(3);
  }
}

// The page: three.js and a width x height canvas (id "c") on a `background` (CSS colour) body,
// and `module`, the page's script, after the imports and helpers it may use.
export function pageHtml({ background, width, height, module }) {
  return `<!doctype html>
<html><head><meta charset="utf-8"><style>html,body{margin:0;background:${background}}</style>
<script type="importmap">{"imports":{"three":"/three/build/three.module.js",
  "three/addons/":"/three/examples/jsm/"}}</script></head>
<body><canvas id="c" width="${width}" height="${height}"></canvas>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

// A WebGL renderer on the canvas, W x H pixels, sRGB output with neutral tone mapping.
function newRenderer(W, H) {
  const canvas = document.getElementById('c');
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(W, H, false);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = THREE.NeutralToneMapping;
  return renderer;
}
// What window.renderResult holds when the page fails.
function failure(e) {
  return { error: String(e && e.message || e) };
}
${module}
</script></body></html>`;
}

// Serves the page, three.js and the models (/model0.glb, ...) on 127.0.0.1 (an ephemeral port)
// and nothing else.
async function serve(page, models) {
  const types = { '.js': 'text/javascript', '.html': 'text/html', '.glb': 'model/gltf-binary' };
  const server = createServer(async (req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    try {
      const m = /^\/model(\d+)\.glb$/.exec(url.pathname);
      if (url.pathname === '/favicon.ico') {
        res.writeHead(204).end();
      } else if (url.pathname === '/') {
        res.writeHead(200, { 'content-type': types['.html'] }).end(page);
      } else if (m && +m[1] < models.length) {
        res.writeHead(200, { 'content-type': types['.glb'] }).end(models[+m[1]]);
      } else if (url.pathname.startsWith('/three/')) {
        const file = normalize(join(threeDir, decodeURIComponent(url.pathname.slice(7))));
        if (!file.startsWith(threeDir + '/')) throw new Error('outside three.js');
        const body = await readFile(file);
        res.writeHead(200, { 'content-type': types[file.slice(file.lastIndexOf('.'))] ??
                                              'application/octet-stream' }).end(body);
      } else {
        res.writeHead(404).end();
      }
    } catch {
      res.writeHead(404).end();
    }
  });
  await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
  return server;
}

// Runs the page in headless Chromium at `chromiumPath` with a width x height viewport and waits
// (up to `timeout` ms) for window.renderResult. Returns { result, consoleLines } (the page's
// errors and warnings). A browser failure exits with 3; a result { error } exits with 2, the
// message starting with `loadFailure`.
export async function renderPage({ script, chromiumPath, page, models, width, height, timeout, loadFailure }) {
  const server = await serve(page, models);
  const origin = `http://127.0.0.1:${server.address().port}`;
  let browser;
  let result;
  const consoleLines = [];
  try {
    // SwiftShader gives WebGL without a GPU (a CI machine has none).
    browser = await chromium.launch({
      executablePath: chromiumPath,
      headless: true,
      args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
             '--no-sandbox'],
    });
    const tab = await browser.newPage({ viewport: { width, height }, deviceScaleFactor: 1 });
    tab.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') consoleLines.push(m.text()); });
    tab.on('pageerror', (e) => consoleLines.push(String(e)));
    await tab.goto(`${origin}/`);
    await tab.waitForFunction(() => window.renderResult !== undefined, null, { timeout });
    result = await tab.evaluate(() => window.renderResult);
  } catch (e) {
    console.error(`${script}: browser failure: ${e.message}`);
    for (const l of consoleLines) console.error(`  page: ${l}`);
    process.exitCode = 3;
  } finally {
    if (browser) await browser.close();
    server.close();
  }
  if (process.exitCode) process.exit(process.exitCode);
  if (result.error) {
    console.error(`${script}: ${loadFailure}: ${result.error}`);
    for (const l of consoleLines) console.error(`  page: ${l}`);
    process.exit(2);
  }
  return { result, consoleLines };
}

// Writes the PNG that a data:image/png;base64 URL holds.
export async function writeDataUrlPng(output, url) {
  await writeFile(output, Buffer.from(url.slice(url.indexOf(',') + 1), 'base64'));
}

// "x, y, z" to `digits` significant digits.
export const formatVector = (v, digits) => v.map((x) => +x.toPrecision(digits)).join(', ');

// The report: with json the result as one JSON object; else text() prints the script's lines,
// then come the page's warnings and the file written.
export function printReport({ json, result, consoleLines, output, text }) {
  if (json) {
    console.log(JSON.stringify(result, null, 2));
  } else {
    text();
    for (const w of consoleLines) console.log(`page: ${w}`);
    console.log(`wrote ${output}`);
  }
}
