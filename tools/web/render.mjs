#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Renders a .glb the way a web viewer shows it: three.js's GLTFLoader in headless Chromium
// (Debian's /usr/bin/chromium, driven by playwright-core), the page served from 127.0.0.1.
//
//   node tools/web/render.mjs FILE.glb OUT.png [--width W] [--height H] [--texture checker]
//                             [--azimuth DEG] [--environment none|room] [--chromium PATH] [--json]
//
// The camera is upright (+Y up, as glTF defines) and looks horizontally at the centre of the
// model's bounding box, from +Z (the glTF "front") turned by --azimuth degrees about +Y; it
// backs off until the box fits the frame. The camera never adapts to the model's orientation:
// a model whose up axis is not +Y shows lying down or seen from below. Lights: a hemisphere
// light and a key light from the upper front; --environment room adds three.js's room
// environment as image-based light (about 10 s more on SwiftShader). --texture checker replaces every material by a checkerboard mapped through
// TEXCOORD_0, to show texel density and seams.
//
// Prints the model's bounding box as three.js computes it (Box3.setFromObject, precise), the
// vertex/triangle counts and attributes the loader saw, and the pixel bounding box of the pixels
// that differ from the background (x to the right, y down, inclusive). --json prints the same as
// one JSON object. Exit code: 0 rendered, 2 the file cannot be read or loaded, 3 usage error or
// browser failure.
import { resolve } from 'node:path';
import { checkTools, formatVector, kChromium, pageHtml, parseArgs, printReport, readModels, renderPage,
         usageFunction, writeDataUrlPng } from './common.mjs';

const usage = usageFunction('render.mjs', 'FILE.glb OUT.png [--width W] [--height H] ' +
                            '[--texture checker] [--azimuth DEG] [--environment none|room] [--chromium PATH] [--json]');

const opts = { width: 800, height: 800, texture: null, azimuth: 0, environment: 'none', chromium: kChromium,
               json: false };
const positional = parseArgs(process.argv.slice(2), opts, usage, (a, { value, integer }) => {
  if (a === '--width') opts.width = integer('--width', 16, 8192);
  else if (a === '--height') opts.height = integer('--height', 16, 8192);
  else if (a === '--texture') {
    opts.texture = value();
    if (opts.texture !== 'checker') usage(`--texture supports only "checker", got ${opts.texture}`);
  } else if (a === '--azimuth') {
    const v = value();
    if (!Number.isFinite(+v) || v.trim() === '') usage(`--azimuth must be a number, got ${v}`);
    opts.azimuth = +v;
  } else if (a === '--environment') {
    opts.environment = value();
    if (!['room', 'none'].includes(opts.environment)) usage(`--environment is room or none, got ${opts.environment}`);
  } else return false;
  return true;
});
if (positional.length !== 2) usage('expected FILE.glb and OUT.png');
const [input, output] = positional;

const models = await readModels('render.mjs', [input]);
checkTools('render.mjs', opts.chromium);

// The page: the model and three.js, nothing else. The background colour is one no lit surface
// of the default material produces exactly; the page compares pixels to it.
const kBackground = [0x30, 0x38, 0x48];
const page = pageHtml({ background: '#000', width: opts.width, height: opts.height, module: `
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';

const W = ${opts.width}, H = ${opts.height}, azimuth = ${opts.azimuth} * Math.PI / 180;
const background = [${kBackground.join(',')}];
const texture = ${JSON.stringify(opts.texture)};
const environment = ${JSON.stringify(opts.environment)};

const marks = [['start', performance.now()]];
async function run() {
  const renderer = newRenderer(W, H);

  const scene = new THREE.Scene();
  scene.background = new THREE.Color().setRGB(background[0] / 255, background[1] / 255,
                                               background[2] / 255, THREE.SRGBColorSpace);
  if (environment === 'room') {
    scene.environment = new THREE.PMREMGenerator(renderer).fromScene(new RoomEnvironment()).texture;
    scene.environmentIntensity = 0.5;
  }
  marks.push(['environment', performance.now()]);

  const gltf = await new GLTFLoader().loadAsync('/model0.glb');
  const root = gltf.scene;
  scene.add(root);
  root.updateMatrixWorld(true);

  const stats = { nodes: 0, meshes: 0, vertices: 0, triangles: 0, attributes: [], extensionsUsed:
                  gltf.parser.json.extensionsUsed || [], missingUv: false };
  let checker = null;
  if (texture === 'checker') {
    const size = 512, squares = 16, c = document.createElement('canvas');
    c.width = c.height = size;
    const g = c.getContext('2d');
    for (let i = 0; i < squares; ++i) {
      for (let j = 0; j < squares; ++j) {
        g.fillStyle = (i + j) % 2 ? '#f0f0f0' : '#c03020';
        g.fillRect(i * size / squares, j * size / squares, size / squares, size / squares);
      }
    }
    checker = new THREE.CanvasTexture(c);
    checker.colorSpace = THREE.SRGBColorSpace;
    checker.wrapS = checker.wrapT = THREE.RepeatWrapping;
    checker.anisotropy = renderer.capabilities.getMaxAnisotropy();
  }
  root.traverse((o) => {
    if (o !== root) stats.nodes += 1;
    if (!o.isMesh) return;
    const g = o.geometry;
    stats.meshes += 1;
    stats.vertices += g.attributes.position.count;
    stats.triangles += (g.index ? g.index.count : g.attributes.position.count) / 3;
    for (const name of Object.keys(g.attributes)) {
      if (!stats.attributes.includes(name)) stats.attributes.push(name);
    }
    if (checker) {
      if (!g.attributes.uv) stats.missingUv = true;
      o.material = new THREE.MeshStandardMaterial({ map: checker, roughness: 0.8, metalness: 0 });
    }
  });

  const box = new THREE.Box3().setFromObject(root, true);
  if (box.isEmpty()) {
    renderer.render(scene, new THREE.PerspectiveCamera());
    return { empty: true, stats, box: null };
  }
  const center = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());

  // Upright camera on the horizontal plane through the box centre. In the camera's frame the
  // box spans half-widths hx (right), hy (up) and hz (depth); back off until the near face fits.
  const vfov = 30, tanV = Math.tan(vfov * Math.PI / 360), tanH = tanV * W / H;
  const dir = new THREE.Vector3(Math.sin(azimuth), 0, Math.cos(azimuth));  // centre -> camera
  const right = new THREE.Vector3(Math.cos(azimuth), 0, -Math.sin(azimuth));
  const corners = [];
  for (let i = 0; i < 8; ++i) {
    corners.push(new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y,
                                   i & 4 ? box.max.z : box.min.z).sub(center));
  }
  const hx = Math.max(...corners.map((p) => Math.abs(p.dot(right))));
  const hz = Math.max(...corners.map((p) => Math.abs(p.dot(dir))));
  const hy = size.y / 2;
  const distance = 1.08 * Math.max(hy / tanV, hx / tanH) + hz;
  const camera = new THREE.PerspectiveCamera(vfov, W / H, distance / 100, distance + 2 * hz + 1);
  camera.up.set(0, 1, 0);
  camera.position.copy(center).addScaledVector(dir, distance);
  camera.lookAt(center);

  scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 0.8));
  const key = new THREE.DirectionalLight(0xffffff, 1.5);
  key.position.copy(camera.position).add(new THREE.Vector3(0, distance, 0)).addScaledVector(right, distance);
  key.target.position.copy(center);
  scene.add(key, key.target);

  marks.push(['loaded', performance.now()]);
  renderer.render(scene, camera);
  marks.push(['rendered', performance.now()]);
  return { empty: false, stats, box: { min: box.min.toArray(), max: box.max.toArray(),
           size: size.toArray() }, camera: { position: camera.position.toArray(),
           target: center.toArray(), up: [0, 1, 0], fovDegrees: vfov } };
}

window.renderResult = run().then((r) => {
  // Pixel bounding box of what differs from the background (WebGL rows run bottom-up).
  const canvas = document.getElementById('c');
  const gl = canvas.getContext('webgl2');
  const px = new Uint8Array(W * H * 4);
  gl.readPixels(0, 0, W, H, gl.RGBA, gl.UNSIGNED_BYTE, px);
  let x0 = W, y0 = H, x1 = -1, y1 = -1, count = 0;
  const levels = new Set();
  for (let row = 0; row < H; ++row) {
    for (let x = 0; x < W; ++x) {
      const k = 4 * (row * W + x);
      const d = Math.abs(px[k] - background[0]) + Math.abs(px[k + 1] - background[1]) +
                Math.abs(px[k + 2] - background[2]);
      if (d <= 6) continue;
      const y = H - 1 - row;
      x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y);
      ++count;
      levels.add((px[k] >> 3) << 10 | (px[k + 1] >> 3) << 5 | px[k + 2] >> 3);
    }
  }
  r.pixels = { width: W, height: H, foreground: count, distinctColors: levels.size,
               bbox: count ? { x0, y0, x1, y1, width: x1 - x0 + 1, height: y1 - y0 + 1 } : null };
  marks.push(['read', performance.now()]);
  r.png = canvas.toDataURL('image/png');
  marks.push(['png', performance.now()]);
  r.times = marks.map(([k, t]) => [k, Math.round(t - marks[0][1])]);
  return r;
}, failure);
` });

const { result, consoleLines } = await renderPage({
  script: 'render.mjs', chromiumPath: opts.chromium, page, models, width: opts.width, height: opts.height,
  timeout: 120000, loadFailure: `${input}: three.js could not load it` });
await writeDataUrlPng(output, result.png);
delete result.png;
result.file = input;
result.png = resolve(output);
result.warnings = consoleLines;
if (result.stats.missingUv) {
  console.error(`render.mjs: ${input}: no TEXCOORD_0: the checker texture cannot be mapped ` +
                '(every point samples one texel)');
}

const f = (v) => formatVector(v, 6);
printReport({ json: opts.json, result, consoleLines, output, text: () => {
  const s = result.stats;
  console.log(`${input}: ${s.nodes} nodes, ${s.meshes} meshes, ${s.vertices} vertices, ${s.triangles} triangles; ` +
              `attributes: ${s.attributes.join(', ') || '-'}` +
              (s.extensionsUsed.length ? `; extensions: ${s.extensionsUsed.join(', ')}` : ''));
  if (result.box) {
    console.log(`three.js bounding box: min (${f(result.box.min)}) max (${f(result.box.max)}) ` +
                `size (${f(result.box.size)})`);
  } else {
    console.log('three.js bounding box: empty');
  }
  const p = result.pixels;
  console.log(p.bbox ? `pixel bounding box: x ${p.bbox.x0}..${p.bbox.x1}, y ${p.bbox.y0}..${p.bbox.y1} ` +
                       `(${p.bbox.width} x ${p.bbox.height} of ${p.width} x ${p.height}; ` +
                       `${p.foreground} pixels not background, ${p.distinctColors} colours)` :
                       'pixel bounding box: none (every pixel is background)');
} });
