#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Renders several .glb files side by side into one PNG, for the documentation's figures
// (docs/equipotential.md): three.js's GLTFLoader in headless Chromium, as render.mjs does, with
// a camera and shading chosen for comparing meshes rather than for checking a file.
//
//   node tools/web/render_grid.mjs OUT.png IN.glb[@X,Y,Z,R] ... [--cols N] [--width W]
//        [--height H] [--azimuth DEG[,DEG...]] [--elevation DEG[,DEG...]] [--ortho] [--flat]
//        [--wireframe | --wireframe-panels K[,K...]] [--frame same|each] [--labels "A|B|C"]
//        [--color RRGGBB] [--inside RRGGBB] [--background RRGGBB] [--colors N] [--chromium PATH]
//        [--json]
//
// One panel per input, W x H pixels each (default 320 x 320), --cols per row (default: all in
// one row). The camera looks at the panel's box centre from +Z (the glTF front) turned by
// --azimuth degrees about +Y and raised by --elevation degrees (one value for every panel, or
// one per panel), perspective (30 degrees) or with --ortho orthographic (the paper's figures),
// backed off until the box fits. --frame same (the default) gives every panel the camera
// distance that fits the union of all boxes, so sizes compare; --frame each fits every panel to
// its own model. IN.glb@X,Y,Z,R frames the sphere of radius R about (X, Y, Z) in glTF
// coordinates instead, a close-up (+Y up: a ramiform point (x, y, z) is (x, z, -y)).
// --color replaces the materials by one colour (smooth shading with the file's normals), --flat
// by one flat-shaded colour (default b08a64); both draw the inside, seen through an open end, in
// --inside (default e8dcc0). --wireframe draws every triangle edge over the surface (hidden edges
// stay hidden), --wireframe-panels only on the panels listed (1 is the first). --labels puts
// one caption, split at "|", at the top left of each panel. The PNG is indexed, --colors
// entries (default 256, 1-256; 0 writes the browser's truecolour PNG), for small files.
//
// Prints one line per panel (file, triangles, box) and the PNG written; --json prints the same
// as one JSON object. Exit code: 0 rendered, 2 a file cannot be read or loaded, 3 usage error or
// browser failure.
import { writeFile } from 'node:fs/promises';
import zlib from 'node:zlib';
import { checkTools, formatVector, kChromium, pageHtml, parseArgs, printReport, readModels, renderPage,
         usageFunction, writeDataUrlPng } from './common.mjs';

const usage = usageFunction('render_grid.mjs', 'OUT.png IN.glb[@X,Y,Z,R] ... [--cols N] [--width W] ' +
                            '[--height H] [--azimuth DEG[,...]] [--elevation DEG[,...]] [--ortho] [--flat] ' +
                            '[--wireframe | --wireframe-panels K[,...]] ' +
                            '[--frame same|each] [--labels "A|B"] [--color RRGGBB] [--inside RRGGBB] [--background RRGGBB] ' +
                            '[--colors N] [--chromium PATH] [--json]');

const opts = { width: 320, height: 320, cols: 0, azimuth: [0], elevation: [0], ortho: false, flat: false,
               wireframe: false, frame: 'same', labels: [], color: null, inside: 'e8dcc0', background: 'f4f4f4', colors: 256,
               chromium: kChromium, json: false };
const positional = parseArgs(process.argv.slice(2), opts, usage, (a, { value, integer, numbers, colour }) => {
  if (a === '--width') opts.width = integer('--width', 16, 4096);
  else if (a === '--height') opts.height = integer('--height', 16, 4096);
  else if (a === '--cols') opts.cols = integer('--cols', 1, 64);
  else if (a === '--azimuth') opts.azimuth = numbers('--azimuth');
  else if (a === '--elevation') {
    opts.elevation = numbers('--elevation');
    if (opts.elevation.some((e) => Math.abs(e) >= 90)) usage('--elevation must lie in (-90, 90)');
  } else if (a === '--ortho') opts.ortho = true;
  else if (a === '--flat') opts.flat = true;
  else if (a === '--wireframe') opts.wireframe = true;
  else if (a === '--wireframe-panels') opts.wireframe = numbers('--wireframe-panels');
  else if (a === '--frame') {
    opts.frame = value();
    if (!['same', 'each'].includes(opts.frame)) usage(`--frame is same or each, got ${opts.frame}`);
  } else if (a === '--labels') opts.labels = value().split('|');
  else if (a === '--color') opts.color = colour('--color');
  else if (a === '--inside') opts.inside = colour('--inside');
  else if (a === '--background') opts.background = colour('--background');
  else if (a === '--colors') opts.colors = integer('--colors', 0, 256);
  else return false;
  return true;
});
if (positional.length < 2) usage('expected OUT.png and at least one IN.glb');
const output = positional[0];
const panels = positional.slice(1).map((p) => {
  const at = p.lastIndexOf('@');
  if (at < 0) return { file: p, focus: null };
  const f = p.slice(at + 1).split(',').map(Number);
  if (f.length !== 4 || !f.every(Number.isFinite) || !(f[3] > 0)) usage(`${p}: expected FILE@X,Y,Z,R`);
  return { file: p.slice(0, at), focus: f };
});
if (!output.toLowerCase().endsWith('.png')) usage(`the output ${output} must be a .png`);
if (opts.labels.length && opts.labels.length !== panels.length) {
  usage(`--labels has ${opts.labels.length} captions for ${panels.length} panels`);
}
for (const [name, list] of [['--azimuth', opts.azimuth], ['--elevation', opts.elevation]]) {
  if (list.length !== 1 && list.length !== panels.length) {
    usage(`${name} has ${list.length} values for ${panels.length} panels (give one, or one per panel)`);
  }
}
panels.forEach((p, k) => {
  p.azimuth = opts.azimuth[opts.azimuth.length === 1 ? 0 : k];
  p.elevation = opts.elevation[opts.elevation.length === 1 ? 0 : k];
  p.wireframe = Array.isArray(opts.wireframe) ? opts.wireframe.includes(k + 1) : opts.wireframe;
});
const cols = opts.cols || panels.length;
const rows = Math.ceil(panels.length / cols);

const models = await readModels('render_grid.mjs', panels.map((p) => p.file));
checkTools('render_grid.mjs', opts.chromium);

const W = opts.width * cols, H = opts.height * rows;
const page = pageHtml({ background: '#fff', width: W, height: H, module: `
const opts = ${JSON.stringify(opts)};
const panels = ${JSON.stringify(panels)};
const cols = ${cols}, W = ${W}, H = ${H}, PW = opts.width, PH = opts.height;

async function run() {
  const renderer = newRenderer(W, H);
  renderer.setScissorTest(true);
  const background = new THREE.Color('#' + opts.background);

  const loader = new GLTFLoader();
  const items = [];
  for (let k = 0; k < panels.length; ++k) {
    const gltf = await loader.loadAsync('/model' + k + '.glb');
    const scene = new THREE.Scene();
    scene.background = background;
    const root = gltf.scene;
    scene.add(root);
    root.updateMatrixWorld(true);
    let triangles = 0;
    const meshes = [];
    root.traverse((o) => { if (o.isMesh) meshes.push(o); });
    for (const o of meshes) {
      const g = o.geometry;
      triangles += (g.index ? g.index.count : g.attributes.position.count) / 3;
      if (opts.flat || opts.color) {
        o.material = new THREE.MeshStandardMaterial({ color: new THREE.Color('#' + (opts.color || 'b08a64')),
                                                      roughness: 0.85, metalness: 0, flatShading: opts.flat });
        // The inside, seen through an open end, in a pale colour of its own.
        const inside = new THREE.Mesh(g, new THREE.MeshStandardMaterial({
          color: new THREE.Color('#' + opts.inside), roughness: 0.9, metalness: 0, flatShading: opts.flat,
          side: THREE.BackSide, polygonOffset: panels[k].wireframe, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
        inside.matrixAutoUpdate = false;
        inside.matrix.copy(o.matrixWorld);
        scene.add(inside);
      }
      if (panels[k].wireframe) {
        o.material.polygonOffset = true;
        o.material.polygonOffsetFactor = 1;
        o.material.polygonOffsetUnits = 1;
        const lines = new THREE.LineSegments(new THREE.WireframeGeometry(g),
                                             new THREE.LineBasicMaterial({ color: 0x202020 }));
        lines.matrixAutoUpdate = false;
        lines.matrix.copy(o.matrixWorld);
        scene.add(lines);
      }
    }
    const box = new THREE.Box3().setFromObject(root, true);
    items.push({ scene, box, triangles, file: panels[k].file, focus: panels[k].focus });
  }
  const union = new THREE.Box3();
  for (const it of items) union.union(it.box);

  const vfov = 30, tanV = Math.tan(vfov * Math.PI / 360);

  // The camera frame of a panel: dir from the centre to the camera, right, up.
  function frame(p) {
    const az = p.azimuth * Math.PI / 180, el = p.elevation * Math.PI / 180;
    const dir = new THREE.Vector3(Math.sin(az) * Math.cos(el), Math.sin(el), Math.cos(az) * Math.cos(el));
    const right = new THREE.Vector3(Math.cos(az), 0, -Math.sin(az));
    return { dir, right, up: new THREE.Vector3().crossVectors(dir, right) };
  }
  // Half-extents of a box (or a sphere) in the camera's frame.
  function extents(box, focus, { dir, right, up }) {
    if (focus) {
      return { center: new THREE.Vector3(focus[0], focus[1], focus[2]), hx: focus[3], hy: focus[3], hz: focus[3] };
    }
    const center = box.getCenter(new THREE.Vector3());
    let hx = 0, hy = 0, hz = 0;
    for (let i = 0; i < 8; ++i) {
      const p = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                  i & 4 ? box.max.z : box.min.z).sub(center);
      hx = Math.max(hx, Math.abs(p.dot(right)));
      hy = Math.max(hy, Math.abs(p.dot(up)));
      hz = Math.max(hz, Math.abs(p.dot(dir)));
    }
    return { center, hx, hy, hz };
  }

  const report = [];
  for (let k = 0; k < items.length; ++k) {
    const it = items[k];
    const f = frame(panels[k]), { dir, right, up } = f;
    const e = extents(opts.frame === 'same' && !it.focus ? union : it.box, it.focus, f);
    let camera;
    const fitHalfHeight = 1.06 * Math.max(e.hy, e.hx * PH / PW);
    let distance = fitHalfHeight / tanV + e.hz;
    if (opts.ortho) {
      // The view does not depend on the distance: put the camera outside every model, so no
      // near plane cuts a tube in front of a close-up (it would show the tube's inside).
      const reach = union.getBoundingSphere(new THREE.Sphere());
      const behind = reach.radius + reach.center.distanceTo(e.center);
      distance = Math.max(distance, 1.01 * behind + 0.01);
      const hh = fitHalfHeight, hw = hh * PW / PH;
      camera = new THREE.OrthographicCamera(-hw, hw, hh, -hh, distance / 1000, distance + behind + 1);
    } else {
      camera = new THREE.PerspectiveCamera(vfov, PW / PH, distance / 100, distance + 2 * e.hz + 1);
    }
    camera.up.copy(up);
    camera.position.copy(e.center).addScaledVector(dir, distance);
    camera.lookAt(e.center);
    it.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 0.9));
    const key = new THREE.DirectionalLight(0xffffff, 1.6);
    key.position.copy(camera.position).addScaledVector(up, distance).addScaledVector(right, distance);
    key.target.position.copy(e.center);
    it.scene.add(key, key.target);

    const col = k % cols, row = Math.floor(k / cols);
    const x = col * PW, y = H - (row + 1) * PH;   // WebGL viewports count from the bottom
    renderer.setViewport(x, y, PW, PH);
    renderer.setScissor(x, y, PW, PH);
    renderer.render(it.scene, camera);
    report.push({ file: it.file, triangles: it.triangles, min: it.box.min.toArray(), max: it.box.max.toArray(),
                  focus: it.focus });
  }

  // Captions on a 2-D copy of the frame.
  const out = document.createElement('canvas');
  out.width = W; out.height = H;
  const g = out.getContext('2d');
  g.drawImage(renderer.domElement, 0, 0);
  if (opts.labels.length) {
    g.font = '15px sans-serif';
    g.textBaseline = 'top';
    opts.labels.forEach((text, k) => {
      const x = (k % cols) * PW + 8, y = Math.floor(k / cols) * PH + 7;
      g.fillStyle = 'rgba(255, 255, 255, 0.8)';   // readable over a close-up too
      g.fillRect(x - 4, y - 3, g.measureText(text).width + 8, 21);
      g.fillStyle = '#202020';
      g.fillText(text, x, y);
    });
  }
  if (opts.colors === 0) return { panels: report, png: out.toDataURL('image/png') };
  // Raw RGBA for the palette encoder in node, base64 in chunks (btoa takes a string).
  const px = g.getImageData(0, 0, W, H).data;
  let bin = '';
  for (let i = 0; i < px.length; i += 0x8000) bin += String.fromCharCode.apply(null, px.subarray(i, i + 0x8000));
  return { panels: report, rgba: btoa(bin) };
}
window.renderResult = run().catch(failure);
` });

// An indexed-colour PNG of RGBA pixels (alpha dropped): median cut over a 5-bit-per-channel
// histogram down to `colors` entries, each pixel mapped to the nearest entry. Renders of a few
// shaded materials keep their look at a third of the truecolour size.
function palettePng(rgba, w, h, colors) {
  const n = w * h, bins = new Map();   // 15-bit colour -> [count, r sum, g sum, b sum]
  const key = new Uint16Array(n);
  for (let i = 0; i < n; ++i) {
    const r = rgba[4 * i], g = rgba[4 * i + 1], b = rgba[4 * i + 2];
    const k = (r >> 3) << 10 | (g >> 3) << 5 | b >> 3;
    key[i] = k;
    const e = bins.get(k);
    if (e) { e[0] += 1; e[1] += r; e[2] += g; e[3] += b; } else bins.set(k, [1, r, g, b]);
  }
  const entries = [...bins.entries()].map(([k, e]) => ({ k, n: e[0], c: [e[1] / e[0], e[2] / e[0], e[3] / e[0]] }));
  let boxes = [entries];
  while (boxes.length < colors) {
    // Split the box of the widest weighted channel range at its weighted median.
    let best = -1, bestSpread = 0, bestAxis = 0;
    boxes.forEach((box, i) => {
      if (box.length < 2) return;
      for (let a = 0; a < 3; ++a) {
        let lo = 255, hi = 0, weight = 0;
        for (const e of box) { lo = Math.min(lo, e.c[a]); hi = Math.max(hi, e.c[a]); weight += e.n; }
        const spread = (hi - lo) * Math.sqrt(weight);
        if (spread > bestSpread) { bestSpread = spread; best = i; bestAxis = a; }
      }
    });
    if (best < 0) break;
    const box = boxes[best].sort((x, y) => x.c[bestAxis] - y.c[bestAxis]);
    const total = box.reduce((t, e) => t + e.n, 0);
    let acc = 0, cut = 1;
    for (; cut < box.length - 1; ++cut) { acc += box[cut - 1].n; if (acc >= total / 2) break; }
    boxes.splice(best, 1, box.slice(0, cut), box.slice(cut));
  }
  const palette = boxes.map((box) => {
    const t = box.reduce((s, e) => [s[0] + e.n, s[1] + e.n * e.c[0], s[2] + e.n * e.c[1], s[3] + e.n * e.c[2]], [0, 0, 0, 0]);
    return [t[1] / t[0], t[2] / t[0], t[3] / t[0]].map((v) => Math.round(v));
  });
  const index = new Map();
  for (const e of entries) {
    let best = 0, bestD = Infinity;
    palette.forEach((p, i) => {
      const d = (p[0] - e.c[0]) ** 2 + (p[1] - e.c[1]) ** 2 + (p[2] - e.c[2]) ** 2;
      if (d < bestD) { bestD = d; best = i; }
    });
    index.set(e.k, best);
  }
  const raw = Buffer.alloc(h * (w + 1));
  for (let y = 0; y < h; ++y) {
    raw[y * (w + 1)] = 0;   // filter: none
    for (let x = 0; x < w; ++x) raw[y * (w + 1) + 1 + x] = index.get(key[y * w + x]);
  }
  const chunk = (type, data) => {
    const len = Buffer.alloc(4); len.writeUInt32BE(data.length);
    const body = Buffer.concat([Buffer.from(type, 'ascii'), data]);
    const crc = Buffer.alloc(4); crc.writeUInt32BE(zlib.crc32(body));
    return Buffer.concat([len, body, crc]);
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0); ihdr.writeUInt32BE(h, 4);
  ihdr[8] = 8; ihdr[9] = 3; ihdr[10] = 0; ihdr[11] = 0; ihdr[12] = 0;   // 8-bit indexed
  return Buffer.concat([Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]), chunk('IHDR', ihdr),
                        chunk('PLTE', Buffer.from(palette.flat())),
                        chunk('IDAT', zlib.deflateSync(raw, { level: 9 })), chunk('IEND', Buffer.alloc(0))]);
}

const { result, consoleLines } = await renderPage({
  script: 'render_grid.mjs', chromiumPath: opts.chromium, page, models, width: W, height: H,
  timeout: 300000, loadFailure: 'three.js could not load a model' });
if (opts.colors === 0) {
  await writeDataUrlPng(output, result.png);
} else {
  await writeFile(output, palettePng(Buffer.from(result.rgba, 'base64'), W, H, opts.colors));
  delete result.rgba;
}
result.png = output;
result.warnings = consoleLines;
printReport({ json: opts.json, result, consoleLines, output, text: () => {
  const f = (v) => formatVector(v, 4);
  for (const p of result.panels) {
    console.log(`${p.file}: ${p.triangles} triangles, box (${f(p.min)}) .. (${f(p.max)})` +
                (p.focus ? `, close-up at (${f(p.focus)})` : ''));
  }
} });
