#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Opens line drawings (.svg, as `ramiform draw` writes them) in headless Chromium, as a user's
// browser does, and puts them side by side into one PNG for the documentation (docs/drawing.md).
//
//   node tools/web/svg_grid.mjs OUT.png IN.svg ... [--cols N] [--width W] [--height H]
//        [--labels "A|B|C"] [--chromium PATH]
//
// One panel per input, W x H pixels (default 360 x 360), --cols per row (default: all in one
// row), each drawing scaled to fit its panel on white, with an optional caption. Every SVG must
// load as an image in the browser (a file Chromium cannot parse or render fails the run: exit 2);
// prints each file with its natural size and the PNG written. Exit code 3: usage or browser
// failure.
import { readFile } from 'node:fs/promises';
import { chromium } from 'playwright-core';
import { checkTools, kChromium, parseArgs, usageFunction, writeDataUrlPng } from './common.mjs';

const usage = usageFunction('svg_grid.mjs', 'OUT.png IN.svg ... [--cols N] [--width W] [--height H] ' +
                            '[--labels "A|B"] [--chromium PATH]');
const opts = { width: 360, height: 360, cols: 0, labels: [], chromium: kChromium, json: false };
const positional = parseArgs(process.argv.slice(2), opts, usage, (a, { value, integer }) => {
  if (a === '--width') opts.width = integer('--width', 16, 4096);
  else if (a === '--height') opts.height = integer('--height', 16, 4096);
  else if (a === '--cols') opts.cols = integer('--cols', 1, 64);
  else if (a === '--labels') opts.labels = value().split('|');
  else return false;
  return true;
});
if (positional.length < 2) usage('an output .png and at least one .svg are needed');
const [output, ...files] = positional;
checkTools('svg_grid.mjs', opts.chromium);

const svgs = [];
for (const f of files) {
  try {
    svgs.push((await readFile(f)).toString('base64'));
  } catch (e) {
    console.error(`svg_grid.mjs: cannot read ${f}: ${e.message}`);
    process.exit(2);
  }
}
const cols = opts.cols || files.length;
const rows = Math.ceil(files.length / cols);
const panels = svgs.map((b64, i) => `<div class="p"><img id="i${i}" src="data:image/svg+xml;base64,${b64}">` +
  `<span>${(opts.labels[i] || '').replace(/[<&]/g, (c) => (c === '<' ? '&lt;' : '&amp;'))}</span></div>`).join('');
const html = `<!doctype html><html><head><style>
  body { margin: 0; background: #fff; }
  #g { display: grid; grid-template-columns: repeat(${cols}, ${opts.width}px); }
  .p { position: relative; width: ${opts.width}px; height: ${opts.height}px; }
  .p img { width: 100%; height: 100%; object-fit: contain; }
  .p span { position: absolute; left: 8px; top: 6px; font: 14px sans-serif; color: #333; }
</style></head><body><div id="g">${panels}</div></body></html>`;

let browser;
try {
  browser = await chromium.launch({ executablePath: opts.chromium, args: ['--no-sandbox'] });
  const page = await browser.newPage({ viewport: { width: cols * opts.width, height: rows * opts.height } });
  await page.setContent(html);
  const sizes = await page.evaluate(async () => Promise.all([...document.images].map((img) =>
    img.decode().then(() => [img.naturalWidth, img.naturalHeight], () => null))));
  let bad = false;
  sizes.forEach((s, i) => {
    if (!s || !s[0]) {
      console.error(`svg_grid.mjs: ${files[i]}: the browser cannot render it as SVG`);
      bad = true;
    } else {
      console.log(`${files[i]}: ${s[0]} x ${s[1]}`);
    }
  });
  if (bad) {
    await browser.close();
    process.exit(2);
  }
  const png = await page.screenshot({ type: 'png' });
  await writeDataUrlPng(output, `data:image/png;base64,${png.toString('base64')}`);
  console.log(`wrote ${output}`);
} catch (e) {
  console.error(`svg_grid.mjs: browser failure: ${e.message}`);
  process.exit(3);
} finally {
  if (browser) await browser.close();
}
