// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Checks the reports of tools/web/render.mjs --json for gltf_render_upright.sh: the first one
// must show an upright model, every one a render that is not blank.
//   node check_render.mjs UPRIGHT.json [MORE.json...]
import { readFileSync } from 'node:fs';

let failures = 0;
const fail = (m) => { console.log(`FAIL: ${m}`); ++failures; };
const files = process.argv.slice(2);
files.forEach((file, index) => {
  const r = JSON.parse(readFileSync(file, 'utf8'));
  const p = r.pixels;
  console.log(`${file}: ${r.stats.vertices} vertices, attributes ${r.stats.attributes.join(', ')}; ` +
              `box size ${r.box ? r.box.size.map((v) => v.toPrecision(4)).join(' x ') : 'empty'}; ` +
              `pixel box ${p.bbox ? `${p.bbox.width} x ${p.bbox.height}` : 'none'} of ${p.width} x ${p.height}, ` +
              `${p.foreground} foreground pixels, ${p.distinctColors} colours`);
  // Not blank: the model covers a fair part of the frame and is shaded, not one flat colour.
  if (!r.box) fail(`${file}: three.js found no geometry`);
  if (p.foreground < 0.005 * p.width * p.height) {
    fail(`${file}: blank render: ${p.foreground} of ${p.width * p.height} pixels differ from the background`);
  }
  if (p.distinctColors < 8) fail(`${file}: flat render: ${p.distinctColors} colours`);
  if (p.bbox && Math.max(p.bbox.width / p.width, p.bbox.height / p.height) < 0.5) {
    fail(`${file}: the model fills only ${p.bbox.width} x ${p.bbox.height} pixels: not framed`);
  }
  if (index > 0 || !r.box) return;
  const [x, y, z] = r.box.size;
  if (!(y > x && y > z)) {
    fail(`${file}: three.js bounding box ${x.toPrecision(4)} x ${y.toPrecision(4)} x ${z.toPrecision(4)} ` +
         'is not tallest along +Y: the model does not stand up in a glTF viewer');
  }
  if (p.bbox && !(p.bbox.height > p.bbox.width)) {
    fail(`${file}: on screen the model is ${p.bbox.width} px wide and ${p.bbox.height} px tall: ` +
         'not upright');
  }
});
if (failures) process.exit(1);
console.log(`PASS: upright and not blank (${files.length} renders)`);
