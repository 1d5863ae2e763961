// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// End-to-end test of `ramiform studio` in headless Chromium (Debian's /usr/bin/chromium, driven
// by playwright-core): starts the real binary on a free loopback port, opens the page with the
// printed URL and works it as a user does.
//   1. types a script (a `param` sphere saved as .glb) and runs it with Ctrl+Enter: the sphere
//      is drawn where the camera puts it (its centre pixel is the model's, the corners and the
//      pixels just outside its projected silhouette are background, and its width on screen is
//      the projected diameter), its object and download are listed, the download is a glb;
//   2. drags the `param` slider: the script re-runs, the camera stays, the mesh's bounding box
//      and its projected width grow to the new radius; a grown tree's tolerance slider re-meshes
//      it, and the full run lists the tree's mesh early (before its bark UVs), shown in place
//      of the old one;
//   3. line mode: an SVG for the current camera arrives, sized like the canvas, whose path
//      points lie on the sphere's projected outline; after an orbit a quick drawing and then the
//      exact one arrive for the new camera;
//   4. an error on line 3: state failed, the error marker on the editor's third line;
//   5. sketching: four clicks on the XY plane become a `curve` + `revolve` at the cursor, with
//      the clicked coordinates, and the script runs;
//      Two cross-sections on rising horizontal planes become a path, two curves and a skin;
//   6. picks two spheres' surfaces with Combine (diff): the operation is appended and runs, the
//      picked meshes are hidden and the difference's bounds are right;
//   7. drags a sphere with Move: a `translate` line goes in before its save_mesh, with the
//      drag's distance in the library's frame, and the mesh moves there;
//   8. cancels a long run: state cancelled.
// Exit 0 when all pass, 1 on a failure, 77 (ctest's skip) when the binary serves no built page.
//   node e2e/studio_e2e.mjs RAMIFORM_BINARY WORK_DIR [--screenshots DIR]
import { spawn } from 'node:child_process';
import { mkdirSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { chromium } from 'playwright-core';

const args = process.argv.slice(2);
const shotsAt = args.indexOf('--screenshots');
const shots = shotsAt >= 0 ? args.splice(shotsAt, 2)[1] : null;
if (args.length !== 2) {
  console.error('usage: node e2e/studio_e2e.mjs RAMIFORM_BINARY WORK_DIR [--screenshots DIR]');
  process.exit(1);
}
const [binary, work] = args;
const t0 = Date.now();
const results = [];
const measured = {};
let server;
let browser;

function log(message) {
  console.log(`[${((Date.now() - t0) / 1000).toFixed(1)} s] ${message}`);
}

function check(condition, message) {
  if (!condition) throw new Error(`check failed: ${message}`);
}

function near(a, b, tolerance, message) {
  check(Math.abs(a - b) <= tolerance, `${message}: ${a.toFixed(3)} vs ${b.toFixed(3)} (tolerance ${tolerance.toFixed(3)})`);
}

// A small grown tree (about 500 skeleton nodes), meshed to a tolerance that a slider changes.
const kTreeScript = `param tolerance 0.05
sphere crown 1
scale crown 2 2 1.5
translate crown 0 0 3.5
point_set_gen crown poisson count=1500
grow tree from crown step=0.15 influence=1.2 kill=0.35 root=0,0,0 direction=0,0,1 tip_radius=0.02 smooth=8 prune=2
save_mesh tree tree.ply tree.glb method=tets levels=1 tolerance=$tolerance
`;

// ---- the server ------------------------------------------------------------------------------
function startServer() {
  rmSync(work, { recursive: true, force: true });
  mkdirSync(join(work, 'out'), { recursive: true });
  return new Promise((resolve, reject) => {
    const child = spawn(binary, ['studio', '--port', '0', '--out', join(work, 'out')], { stdio: ['ignore', 'pipe', 'pipe'] });
    let stdout = '';
    let stderr = '';
    const timer = setTimeout(() => reject(new Error(`no URL from the server in 20 s; stderr: ${stderr}`)), 20000);
    child.stdout.on('data', (d) => {
      stdout += d;
      const m = /^ramiform studio: (http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]{32})\n/.exec(stdout);
      if (m) {
        clearTimeout(timer);
        resolve({ child, url: m[1] });
      }
    });
    child.stderr.on('data', (d) => (stderr += d));
    child.on('exit', (code) => reject(new Error(`the server exited (${code}) before printing its URL; stderr: ${stderr}`)));
  });
}

// ---- the page --------------------------------------------------------------------------------
async function typeScript(page, text) {
  await page.click('#editor .cm-content');
  await page.keyboard.press('Control+a');
  await page.keyboard.press('Delete');
  for (const line of text.trimEnd().split('\n')) {
    await page.keyboard.type(line);
    await page.keyboard.press('Escape'); // close a completion list, so Enter makes a new line
    await page.keyboard.press('Enter');
  }
  const typed = await page.evaluate(() => window.studio.script());
  check(typed === text.trimEnd() + '\n', `the editor holds the typed script, got ${JSON.stringify(typed)}`);
}

// Waits for a full run (not a draft made while a slider moved) that ended in `state`.
async function waitForRun(page, before, state = 'done', timeout = 60000) {
  await page.waitForFunction(
    ([n, s]) => {
      const runs = window.studio.timings.runs;
      return runs.length > n && !runs[runs.length - 1].draft && document.body.dataset.state === s;
    },
    [before, state],
    { timeout },
  );
}

const runCount = (page) => page.evaluate(() => window.studio.timings.runs.length);
const camera = (page) => page.evaluate(() => window.studio.view.cameraState());

// Types a script and runs it to done; returns the run count before, the camera and the canvas's
// box.
async function typeAndRun(page, text) {
  await typeScript(page, text);
  const before = await runCount(page);
  await page.click('#run');
  await waitForRun(page, before);
  return { before, cam: await camera(page), canvas: await page.locator('#view canvas').boundingBox() };
}

// Where the camera puts a point (page frame): pixel x, y (from the top left) and depth.
function project(cam, p) {
  const sub = (a, b) => a.map((v, i) => v - b[i]);
  const dot = (a, b) => a.reduce((s, v, i) => s + v * b[i], 0);
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const unit = (a) => a.map((v) => v / Math.hypot(...a));
  const f = unit(sub(cam.target, cam.eye));
  const r = unit(cross(f, cam.up));
  const u = cross(r, f);
  const d = sub(p, cam.eye);
  const z = dot(d, f);
  const t = Math.tan((cam.fov * Math.PI) / 360);
  const aspect = cam.width / cam.height;
  return {
    x: ((dot(d, r) / (z * t * aspect) + 1) / 2) * cam.width,
    y: ((1 - dot(d, u) / (z * t)) / 2) * cam.height,
    depth: z,
  };
}

// The on-screen radius of a sphere of radius R centred at c (its outline is a circle when c is on
// the view axis): tan(asin(R / distance)) over tan(fov / 2), in pixels of half the height.
function projectedRadius(cam, c, R) {
  const distance = Math.hypot(...c.map((v, i) => v - cam.eye[i]));
  return (Math.tan(Math.asin(R / distance)) / Math.tan((cam.fov * Math.PI) / 360)) * (cam.height / 2);
}

// The canvas's pixels as the screen shows them: {width, height, at(x, y) → [r, g, b]}.
async function canvasPixels(page) {
  const png = await page.locator('#view canvas').screenshot();
  const data = await page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const rgba = g.getImageData(0, 0, img.width, img.height).data;
    let binary = '';
    for (let i = 0; i < rgba.length; i += 0x8000) binary += String.fromCharCode(...rgba.subarray(i, i + 0x8000));
    return { width: img.width, height: img.height, rgba: btoa(binary) };
  }, png.toString('base64'));
  const pixels = Buffer.from(data.rgba, 'base64');
  const at = (x, y) => {
    const i = 4 * (Math.round(y) * data.width + Math.round(x));
    return [...pixels.subarray(i, i + 3)];
  };
  return { width: data.width, height: data.height, at };
}

const kBackground = [0xf5, 0xf5, 0xf2];
const isBackground = (p) => p.every((v, i) => Math.abs(v - kBackground[i]) <= 2);

// The width of the model's pixels along the row through (x, y): from the first to the last
// pixel of that row that is not background.
function rowExtent(px, y) {
  let first = -1;
  let last = -1;
  for (let x = 0; x < px.width; ++x) {
    if (!isBackground(px.at(x, y))) {
      if (first < 0) first = x;
      last = x;
    }
  }
  return first < 0 ? 0 : last - first + 1;
}

// Checks that a sphere of radius R at the origin is drawn where the camera puts it.
async function checkSphere(page, R, what) {
  const cam = await camera(page);
  const px = await canvasPixels(page);
  check(px.width === cam.width && px.height === cam.height, `${what}: the canvas is ${px.width}x${px.height}, the camera says ${cam.width}x${cam.height}`);
  const c = project(cam, [0, 0, 0]);
  const rp = projectedRadius(cam, [0, 0, 0], R);
  check(!isBackground(px.at(c.x, c.y)), `${what}: the sphere's centre pixel (${c.x.toFixed(0)}, ${c.y.toFixed(0)}) is the model's`);
  for (const [x, y] of [[2, 2], [cam.width - 3, 2], [2, cam.height - 3], [cam.width - 3, cam.height - 3]]) {
    check(isBackground(px.at(x, y)), `${what}: the corner (${x}, ${y}) is background`);
  }
  for (const [dx, dy] of [[1, 0], [-1, 0], [0, 1], [0, -1]]) {
    const x = c.x + dx * (rp * 1.08 + 3);
    const y = c.y + dy * (rp * 1.08 + 3);
    check(isBackground(px.at(x, y)), `${what}: the pixel (${x.toFixed(0)}, ${y.toFixed(0)}) just outside the projected outline is background`);
    const xi = c.x + dx * rp * 0.9;
    const yi = c.y + dy * rp * 0.9;
    check(!isBackground(px.at(xi, yi)), `${what}: the pixel (${xi.toFixed(0)}, ${yi.toFixed(0)}) just inside the projected outline is the model's`);
  }
  const width = rowExtent(px, c.y);
  near(width, 2 * rp, 0.05 * 2 * rp + 2, `${what}: the sphere's width on screen against the projected diameter`);
  return { cam, centre: c, radiusPixels: rp, width };
}

// The points of the drawing's paths (and polylines) in the canvas's pixels: the SVG's user units
// (its viewBox) mapped onto its width × height.
async function svgPoints(page) {
  const svg = await page.evaluate(() => {
    const svg = document.querySelector('#lines-svg svg');
    const points = [];
    for (const p of svg.querySelectorAll('path')) {
      const n = (p.getAttribute('d') || '').match(/-?\d*\.?\d+(?:e[-+]?\d+)?/gi) || [];
      for (let i = 0; i + 1 < n.length; i += 2) points.push([+n[i], +n[i + 1]]);
    }
    for (const p of svg.querySelectorAll('polyline, polygon')) {
      const n = (p.getAttribute('points') || '').match(/-?\d*\.?\d+(?:e[-+]?\d+)?/gi) || [];
      for (let i = 0; i + 1 < n.length; i += 2) points.push([+n[i], +n[i + 1]]);
    }
    return {
      points,
      paths: svg.querySelectorAll('path, polyline').length,
      viewBox: svg.getAttribute('viewBox'),
      width: +svg.getAttribute('width'),
      height: +svg.getAttribute('height'),
      eye: svg.dataset.eye,
    };
  });
  const box = (svg.viewBox || '').split(/[\s,]+/).map(Number);
  check(box.length === 4 && box.every(Number.isFinite) && box[2] > 0 && box[3] > 0, `the SVG has a viewBox (${svg.viewBox})`);
  svg.box = box;
  svg.points = svg.points.map(([x, y]) => [((x - box[0]) * svg.width) / box[2], ((y - box[1]) * svg.height) / box[3]]);
  return svg;
}

// Starts a sketch on the XY plane under a script of one comment line and clicks the points
// (page frame, z = 0) where the camera shows them. Returns the canvas's box.
async function sketchProfile(page, comment, closed, points) {
  await typeScript(page, comment);
  await page.locator('#sketch-plane').selectOption('xy');
  await page.locator('#sketch-closed').setChecked(closed);
  await page.click('#sketch');
  const cam = await camera(page);
  const canvas = await page.locator('#view canvas').boundingBox();
  for (const [x, y] of points) {
    const p = project(cam, [x, y, 0]);
    await page.mouse.click(canvas.x + p.x, canvas.y + p.y);
  }
  return canvas;
}

async function step(name, body) {
  const started = Date.now();
  try {
    await body();
    results.push({ name, ok: true });
    log(`PASS ${name} (${((Date.now() - started) / 1000).toFixed(1)} s)`);
  } catch (e) {
    results.push({ name, ok: false });
    log(`FAIL ${name}: ${e.message}`);
  }
}

async function main() {
  const s = await startServer();
  server = s.child;
  log(`server at ${s.url.replace(/token=.*/, 'token=…')}`);
  const profile = join(work, 'chromium-profile');
  mkdirSync(profile, { recursive: true });
  // A fresh profile directory (playwright passes it as --user-data-dir).
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    viewport: { width: 1280, height: 800 },
    deviceScaleFactor: 1,
  });
  browser = context;
  const page = await context.newPage();
  const pageErrors = [];
  page.on('pageerror', (e) => (pageErrors.push(e.message), log(`page error: ${e.message}`)));
  // Console errors (a refused request of the error step, say) are logged, not failures.
  page.on('console', (m) => m.type() === 'error' && log(`console error: ${m.text()}`));
  await page.goto(s.url);
  if ((await page.locator('#editor').count()) === 0) {
    console.log('SKIP: the binary serves no built page (web/studio/dist was not built: run `npm ci` in web/studio, then rebuild)');
    return 77;
  }
  await page.waitForFunction(() => document.body.dataset.ready === 'yes', null, { timeout: 15000 });
  const demo = await page.evaluate(() => window.studio.script());
  log(`page loaded; the demo script has ${demo.split('\n').length} lines`);

  if (shots) await docScreenshots(page, demo);

  const script = 'param r 1.0\nsphere ball $r\nsave_mesh ball ball.glb resolution=40\n';
  let first;
  await step('type a script, run it, the sphere is where the camera puts it', async () => {
    await typeScript(page, script);
    const before = await runCount(page);
    await page.keyboard.press('Control+Enter');
    await waitForRun(page, before);
    first = await checkSphere(page, 1.0, 'run');
    const objects = await page.locator('#objects input[type=checkbox]').count();
    check(objects === 1, `one object listed in #objects, got ${objects}`);
    const href = await page.locator('#downloads a').first().getAttribute('href');
    check(/ball\.glb$/.test(href), `#downloads links ball.glb, got ${href}`);
    const body = await page.evaluate(async (h) => {
      const b = new Uint8Array(await (await fetch(h)).arrayBuffer());
      return [b.length, String.fromCharCode(...b.slice(0, 4))];
    }, href);
    check(body[0] > 1000 && body[1] === 'glTF', `the download is a glb (${body[0]} bytes, magic ${body[1]})`);
    // The visibility checkbox hides the mesh: the centre pixel becomes background.
    await page.locator('#objects input[type=checkbox]').first().uncheck();
    await page.waitForTimeout(100);
    const hidden = await canvasPixels(page);
    check(isBackground(hidden.at(first.centre.x, first.centre.y)), 'unchecking the object hides it');
    await page.locator('#objects input[type=checkbox]').first().check();
    await page.waitForTimeout(100);
  });

  await step('drag the param slider: the mesh grows, the camera stays', async () => {
    const slider = page.locator('#params input[data-param="r"]');
    check((await slider.count()) === 1, 'a slider for r');
    const range = await slider.evaluate((e) => [+e.min, +e.max, +e.step, +e.value]);
    check(range[0] === 0 && range[1] === 2 && Math.abs(range[2] - 0.1) < 1e-12 && range[3] === 1, `r's slider is 0..2 step 0.1 at 1, got ${range}`);
    const box = await slider.boundingBox();
    const before = await runCount(page);
    const cam0 = await camera(page);
    // Drag from the thumb (the middle) to three quarters: 1.5.
    const y = box.y + box.height / 2;
    const thumb = (v) => box.x + 8 + ((box.width - 16) * (v - range[0])) / (range[1] - range[0]);
    await page.mouse.move(thumb(1.0), y);
    await page.mouse.down();
    for (const v of [1.1, 1.2, 1.3, 1.4, 1.5]) await page.mouse.move(thumb(v), y, { steps: 2 });
    await page.mouse.up();
    const dragged = Date.now();
    const value = Number(await page.locator('#params output').first().textContent());
    check(value >= 1.3 && value <= 1.7, `the slider reads about 1.5, got ${value}`);
    await waitForRun(page, before);
    measured.param_rerun_seconds = (Date.now() - dragged) / 1000;
    const cam1 = await camera(page);
    check(JSON.stringify(cam0) === JSON.stringify(cam1), 'the camera did not move on a param change');
    const bounds = await page.evaluate(() => window.studio.view.bounds());
    const size = bounds.max[0] - bounds.min[0];
    near(size, 2 * value, 0.04 * 2 * value, `the mesh's bounding box is the new sphere's diameter`);
    const after = await checkSphere(page, value, 'after the drag');
    check(after.width > first.width * 1.2, `the sphere is wider on screen (${first.width} → ${after.width} px)`);
    const again = await page.locator('#params input[data-param="r"]').evaluate((e) => [+e.min, +e.max, +e.value]);
    check(again[0] === 0 && again[1] === 2 && Math.abs(again[2] - value) < 1e-9, `after the re-run the slider is still 0..2 at ${value}, got ${again}`);
    const sent = await page.evaluate(() => window.studio.result.params);
    check(sent.some((p) => p.name === 'r'), 'the run reports the param r');
  });

  await step('a grown tree: dragging its tolerance re-meshes it, the view shows the new mesh', async () => {
    await typeScript(page, kTreeScript);
    let before = await runCount(page);
    await page.click('#run');
    await waitForRun(page, before);
    const stats0 = await page.evaluate(() => window.studio.result.objects.find((o) => o.name === 'tree').stats);
    const shown0 = await page.evaluate(() => window.studio.view.triangles());
    check(shown0 === stats0.triangles, `the view shows the run's mesh (${shown0} vs ${stats0.triangles} triangles)`);
    // Drag the slider (0..0.1, step 0.01) from 0.05 to its right end.
    const slider = page.locator('#params input[data-param="tolerance"]');
    const box = await slider.boundingBox();
    before = await runCount(page);
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    await page.mouse.down();
    await page.mouse.move(box.x + box.width + 20, box.y + box.height / 2, { steps: 4 });
    await page.mouse.up();
    const dragged = Date.now();
    await waitForRun(page, before);
    measured.tree_param_rerun_seconds = (Date.now() - dragged) / 1000;
    const tolerance = await page.locator('#params output').first().textContent();
    check(tolerance === '0.10', `the slider reads 0.10, got ${tolerance}`);
    const stats1 = await page.evaluate(() => window.studio.result.objects.find((o) => o.name === 'tree').stats);
    const shown1 = await page.evaluate(() => window.studio.view.triangles());
    check(shown1 === stats1.triangles, `the view shows the new mesh (${shown1} vs ${stats1.triangles} triangles)`);
    check(stats1.triangles < 0.8 * stats0.triangles, `a coarser tolerance makes fewer triangles (${stats0.triangles} → ${stats1.triangles})`);
    check(stats1.watertight === true, 'the new mesh is watertight');
    check(await page.evaluate(() => window.studio.result.draft === false), 'the mesh shown after the release is the full run, not a draft');
    // The full run listed the tree's mesh as soon as it was polygonized (before its bark UVs and
    // files), with the final mesh's triangles, and the page showed it while the run went on when
    // its polls saw it in time (`early`, seconds from the release's run).
    const early = await page.evaluate(() => window.studio.result.early.filter((e) => e.shape === 'tree'));
    check(early.length === 1 && early[0].stats.triangles === stats1.triangles && early[0].line === 7,
      `the run listed the tree's mesh early, as polygonized: ${JSON.stringify(early)} vs ${stats1.triangles} triangles`);
    const last = await page.evaluate(() => window.studio.timings.runs.at(-1));
    measured.tree_param_early_seconds = last.early;
    check(last.early === null || (last.early > 0 && last.early <= last.wall), `the early mesh came before the run ended (${last.early} of ${last.wall} s)`);
    // Shown in place of the mesh of the same line and shape, not beside it.
    const swapped = await page.evaluate(async (info) => [await window.studio.view.showEarly(info), window.studio.view.triangles()], early[0]);
    check(swapped[0] === true && swapped[1] === stats1.triangles, `an early mesh replaces the shown one: ${swapped} vs ${stats1.triangles} triangles`);
  });

  await typeScript(page, script);
  await page.click('#run');
  await page.waitForFunction(() => document.body.dataset.state === 'done' && window.studio.result.objects.some((o) => o.name === 'ball'));

  await step('line mode: an SVG for the current camera, again after an orbit', async () => {
    const r = Number(await page.locator('#params output').first().textContent());
    await page.locator('#line-mode').check();
    await page.waitForFunction(() => document.body.dataset.linesState === 'ready', null, { timeout: 30000 });
    const cam = await camera(page);
    let svg = await svgPoints(page);
    check(svg.paths > 0 && svg.points.length > 10, `the drawing has paths (${svg.paths} paths, ${svg.points.length} points)`);
    check(svg.width === cam.width && svg.height === cam.height, `the SVG is sized like the canvas (${svg.width}x${svg.height} vs ${cam.width}x${cam.height})`);
    near(svg.box[2] / svg.box[3], cam.width / cam.height, 0.01, `the SVG's viewBox (${svg.viewBox}) has the canvas's aspect`);
    const c = project(cam, [0, 0, 0]);
    const rp = projectedRadius(cam, [0, 0, 0], r);
    const distances = svg.points.map(([x, y]) => Math.hypot(x - c.x, y - c.y));
    const outside = distances.filter((d) => d > rp * 1.06 + 2).length;
    check(outside === 0, `every line point lies on or inside the sphere's projected outline (${outside} of ${distances.length} outside radius ${rp.toFixed(1)} px)`);
    check(Math.max(...distances) > rp * 0.94 - 2, `the silhouette reaches the projected outline (${Math.max(...distances).toFixed(1)} vs ${rp.toFixed(1)} px)`);
    // Orbit: drag across the canvas, several times; each move brings a drawing for its camera.
    const canvas = await page.locator('#view canvas').boundingBox();
    const walls = [];
    const quicks = [];
    for (let i = 0; i < 4; ++i) {
      const n = await page.evaluate(() => window.studio.timings.lines.length);
      const sx = canvas.x + canvas.width / 2 + 200;
      const sy = canvas.y + canvas.height / 2 + 120;
      await page.mouse.move(sx, sy);
      await page.mouse.down();
      await page.mouse.move(sx + 60, sy + 15, { steps: 4 });
      await page.mouse.up();
      await page.waitForFunction((k) => document.body.dataset.linesState === 'ready' && window.studio.timings.lines.length > k, n, { timeout: 30000 });
      const drawn = await page.evaluate((k) => window.studio.timings.lines.slice(k), n);
      check(drawn.at(-1).visibility === 'rays', `the last drawing is the exact one (${drawn.map((d) => d.visibility)})`);
      walls.push(drawn.at(-1));
      const quick = drawn.find((d) => d.visibility === 'surfels');
      if (quick) quicks.push(quick);
    }
    const moved = await camera(page);
    check(JSON.stringify(moved.eye) !== JSON.stringify(cam.eye), 'the orbit moved the camera');
    svg = await svgPoints(page);
    check(svg.eye === moved.eye.join(','), 'the drawing shown was made for the current camera');
    const shown = await page.evaluate(() => document.querySelector('#lines-svg svg')?.dataset.visibility);
    check(shown === 'rays', `the drawing shown once ready has exact hidden lines (${shown})`);
    check(quicks.length > 0, 'quick drawings (surfels) came before the exact ones');
    check(svg.paths > 0, 'the new drawing has paths');
    measured.lines_wall_ms = walls.map((w) => Math.round(w.wall * 1000));
    measured.lines_server_ms = walls.map((w) => Math.round(w.server * 1000));
    measured.lines_quick_server_ms = quicks.map((w) => Math.round(w.server * 1000));
    await page.locator('#line-mode').uncheck();
    check((await page.evaluate(() => document.body.dataset.linesState)) === 'idle', 'line mode off: lines state idle');
  });

  await step('an error on line 3: failed, marker on the third line', async () => {
    await typeScript(page, 'sphere a 1\nsphere b 0.5\nblend a nosuch c\nsave_mesh c c.glb\n');
    const before = await runCount(page);
    await page.click('#run');
    await waitForRun(page, before, 'failed');
    const line = await page.locator('#error').getAttribute('data-line');
    check(line === '3', `#error names line 3, got ${line}`);
    const message = await page.locator('#error').textContent();
    check(/nosuch/.test(message), `the message names the unknown shape: ${message}`);
    const marked = await page.evaluate(() => {
      const lines = [...document.querySelectorAll('#editor .cm-line')];
      return {
        decorated: lines.map((l, i) => (l.classList.contains('cm-error-line') ? i + 1 : 0)).filter(Boolean),
        underlined: lines.map((l, i) => (l.querySelector('.cm-lintRange-error') ? i + 1 : 0)).filter(Boolean),
      };
    });
    check(marked.decorated.join() === '3', `the error line decoration is on line 3, got ${marked.decorated}`);
    check(marked.underlined.join() === '3', `the lint marker is on line 3, got ${marked.underlined}`);
    if (shots) await page.screenshot({ path: join(shots, 'studio_error.png') });
  });

  await step('sketch a profile on the XY plane: curve + revolve inserted, and it runs', async () => {
    const wanted = [[0.2, -0.8], [0.8, -0.4], [0.6, 0.5], [0.2, 0.9]];
    await sketchProfile(page, '# sketch\n', false, wanted);
    const picked = await page.evaluate(() => window.studio.sketchPoints());
    check(picked.length === 4, `four sketched points, got ${picked.length}`);
    await page.click('#sketch');
    const text = await page.evaluate(() => window.studio.script());
    const m = /^curve (\S+) polyline ((?:\S+ ?)+)\nrevolve (\S+) \1 radius=\S+$/m.exec(text);
    check(m, `a curve and a revolve were inserted: ${JSON.stringify(text)}`);
    const xy = m[2].trim().split(' ').map(Number);
    check(xy.length === 8, `eight coordinates, got ${xy.length}`);
    wanted.forEach(([x, y], i) => {
      near(xy[2 * i], x, 0.02, `sketched x ${i}`);
      near(xy[2 * i + 1], y, 0.02, `sketched y ${i}`);
    });
    const before = await runCount(page);
    await page.click('#run');
    await waitForRun(page, before);
    const objects = await page.evaluate(() => window.studio.result.objects.map((o) => o.name));
    check(objects.includes(m[3]), `the revolved solid ${m[3]} is shown (objects ${objects})`);
  });

  await step('sketch two cross-sections on rising planes: curves + skin inserted, and it runs', async () => {
    await typeScript(page, '# skin\n');
    await page.locator('#sketch-plane').selectOption('skin');
    await page.locator('#sketch-step').fill('1');
    await page.click('#sketch');
    const cam = await camera(page);
    const canvas = await page.locator('#view canvas').boundingBox();
    const square = (r) => [[-r, -r], [r, -r], [r, r], [-r, r]];
    for (const [r, h] of [[0.5, 0], [0.25, 1]]) {
      for (const [x, z] of square(r)) {
        const p = project(cam, [x, h, z]);
        await page.mouse.click(canvas.x + p.x, canvas.y + p.y);
      }
      if (h === 0) await page.click('#sketch-next');
    }
    const sections = await page.evaluate(() => window.studio.sketchSections());
    check(sections.length === 1 && sections[0].height === 0, `one section kept at height 0, got ${JSON.stringify(sections)}`);
    await page.click('#sketch');
    const text = await page.evaluate(() => window.studio.script());
    const m = /^path (\S+)_path polyline 0 0 0 0 0 1\ncurve \1_1 polyline closed ((?:\S+ ?)+)\ncurve \1_2 polyline closed ((?:\S+ ?)+)\nskin \1_solid \1_path \1_1@0 \1_2@1 radius=\S+$/m.exec(text);
    check(m, `a path, two curves and a skin were inserted: ${JSON.stringify(text)}`);
    // Library (x, y) = page (X, −Z); the clicks were the squares' corners.
    [[2, 0.5], [3, 0.25]].forEach(([k, r]) => {
      const xy = m[k].trim().split(' ').map(Number);
      check(xy.length === 8, `eight coordinates in section ${k - 1}, got ${xy.length}`);
      square(r).forEach(([x, z], i) => {
        near(xy[2 * i], x, 0.02, `section ${k - 1} x ${i}`);
        near(xy[2 * i + 1], -z, 0.02, `section ${k - 1} y ${i}`);
      });
    });
    const before = await runCount(page);
    await page.click('#run');
    await waitForRun(page, before);
    const objects = await page.evaluate(() => window.studio.result.objects.map((o) => o.name));
    check(objects.some((o) => o.startsWith(`${m[1]}_solid`)), `the skinned solid is shown (objects ${objects})`);
    // The solid rises from the big square at height 0 to the small one at height 1 (page y).
    const b = await page.evaluate(() => window.studio.view.bounds());
    near(b.min[1], 0, 0.1, 'the skin starts at the first section');
    near(b.max[1], 1, 0.1, 'the skin ends at the second section');
    near(b.max[0], 0.5, 0.1, 'the skin is as wide as the first section');
    if (shots) {
      // Orbit down from the top view, to see the solid in depth.
      await page.mouse.move(canvas.x + canvas.width / 2, canvas.y + canvas.height / 2);
      await page.mouse.down();
      await page.mouse.move(canvas.x + canvas.width / 2 - 60, canvas.y + canvas.height / 2 - 110, { steps: 5 });
      await page.mouse.up();
      await page.waitForTimeout(300);
      await page.screenshot({ path: join(shots, 'studio_skin.png') });
    }
    await page.locator('#sketch-plane').selectOption('xy');
  });

  await step('combine two surfaces picked in the view: diff a b becomes script text and runs', async () => {
    const { before, cam, canvas } = await typeAndRun(
      page,
      'sphere a 1\nsphere b 1 center=1.2,0,0\nsave_mesh a a.glb resolution=40\nsave_mesh b b.glb resolution=40\n',
    );
    // The sphere (page frame: the library's x is the page's x) that the ray through a point's
    // pixel meets first: the clicks are where the test means them.
    const first = (p) => {
      const o = cam.eye;
      const d = p.map((v, i) => v - o[i]);
      const n = Math.hypot(...d);
      const u = d.map((v) => v / n);
      let best = null;
      for (const [name, c] of [['a', [0, 0, 0]], ['b', [1.2, 0, 0]]]) {
        const oc = o.map((v, i) => v - c[i]);
        const b = oc.reduce((s, v, i) => s + v * u[i], 0);
        const disc = b * b - (oc.reduce((s, v) => s + v * v, 0) - 1);
        if (disc < 0) continue;
        const t = -b - Math.sqrt(disc);
        if (!best || t < best.t) best = { name, t };
      }
      return best?.name;
    };
    const onA = [-0.7, 0, 0];
    const onB = [1.9, 0, 0];
    check(first(onA) === 'a' && first(onB) === 'b', 'the clicked pixels show a and b');
    await page.locator('#edit-op').selectOption('diff');
    await page.click('#combine');
    for (const p of [onA, onB]) {
      const q = project(cam, p);
      await page.mouse.click(canvas.x + q.x, canvas.y + q.y);
    }
    await waitForRun(page, before + 1);
    const text = await page.evaluate(() => window.studio.script());
    check(text.endsWith('# picked on the surfaces: the difference of a and b\ndiff a b a_b\nsave_mesh a_b a_b.glb\n'),
      `the diff and its save_mesh were appended: ${JSON.stringify(text)}`);
    const state = await page.evaluate(() => {
      const objects = window.studio.result.objects;
      const id = (name) => objects.find((o) => o.name === name)?.id;
      return {
        names: objects.map((o) => o.name),
        shapes: objects.map((o) => o.shape),
        visible: ['a', 'b', 'a_b'].map((n) => window.studio.view.isVisible(id(n))),
        bounds: window.studio.view.bounds(),
      };
    });
    check(state.names.includes('a_b') && state.shapes.includes('a_b'), `the combined mesh is shown (objects ${state.names})`);
    check(state.visible.join() === 'false,false,true', `a and b are hidden, a_b shown: ${state.visible}`);
    // Inside a and outside b: x from -1 to the plane x = 0.6 where the spheres meet, radius 0.8
    // there; marching cubes at 40 cells over the 2-wide box: within a cell (0.05).
    near(state.bounds.min[0], -1, 0.06, 'the difference reaches x = -1');
    near(state.bounds.max[0], 0.6, 0.06, 'the difference ends at x = 0.6');
    near(state.bounds.max[1], 1, 0.06, 'the difference keeps a\'s top');
    if (shots) await page.screenshot({ path: join(shots, 'studio_combine.png') });
  });

  await step('move a surface by dragging it: translate before its save_mesh, the mesh moves', async () => {
    const { before, cam, canvas } = await typeAndRun(page, 'sphere s 1\nsave_mesh s s.glb resolution=40\n');
    await page.click('#move');
    const c = project(cam, [0, 0, 0]);
    const dx = 120;
    await page.mouse.move(canvas.x + c.x, canvas.y + c.y);
    await page.mouse.down();
    await page.mouse.move(canvas.x + c.x + dx, canvas.y + c.y, { steps: 6 });
    await page.mouse.up();
    await waitForRun(page, before + 1);
    const text = await page.evaluate(() => window.studio.script());
    const m = /^sphere s 1\ntranslate s (\S+) (\S+) (\S+)\nsave_mesh s s\.glb resolution=40\n$/.exec(text);
    check(m, `a translate line went in before save_mesh: ${JSON.stringify(text)}`);
    // The drag moves the grabbed point (on the front of the sphere, 1 nearer than its centre)
    // in the plane facing the camera: dx pixels are dx / (height / 2) · depth · tan(fov / 2)
    // along the camera's right vector.
    const sub = (a, b) => a.map((v, i) => v - b[i]);
    const f = sub(cam.target, cam.eye).map((v, _, a) => v / Math.hypot(...a));
    const r0 = [f[1] * cam.up[2] - f[2] * cam.up[1], f[2] * cam.up[0] - f[0] * cam.up[2], f[0] * cam.up[1] - f[1] * cam.up[0]];
    const r = r0.map((v) => v / Math.hypot(...r0));
    const world = (dx / (cam.height / 2)) * (c.depth - 1) * Math.tan((cam.fov * Math.PI) / 360);
    const page3 = r.map((v) => v * world);
    const library = [page3[0], -page3[2], page3[1]];
    [1, 2, 3].forEach((k) => near(Number(m[k]), library[k - 1], 0.02 * world + 0.002, `translate component ${k}`));
    const b = await page.evaluate(() => window.studio.view.bounds());
    const centre = b.min.map((v, i) => (v + b.max[i]) / 2);
    centre.forEach((v, i) => near(v, page3[i], 0.03, `the moved sphere's centre, page axis ${i}`));
  });

  await step('cancel a long run: state cancelled', async () => {
    await typeScript(page, 'sphere s 1\nsave_mesh s big.ply resolution=2000\n');
    const before = await runCount(page);
    await page.click('#run');
    await page.waitForFunction(() => window.studio.result === null || document.body.dataset.state === 'running');
    await page.waitForTimeout(1500);
    check((await page.evaluate(() => document.body.dataset.state)) === 'running', 'the long run is still running after 1.5 s');
    const clicked = Date.now();
    await page.click('#cancel');
    await waitForRun(page, before, 'cancelled', 20000);
    measured.cancel_seconds = (Date.now() - clicked) / 1000;
  });

  const uncaught = pageErrors.length === 0;
  if (!uncaught) log(`FAIL: uncaught page errors: ${pageErrors.join(' | ')}`);
  return results.every((r) => r.ok) && uncaught ? 0 : 1;
}

// The pictures of docs/studio.md: the demo crown script run, its mesh, and its line drawing.
async function docScreenshots(page, demo) {
  mkdirSync(shots, { recursive: true });
  const before = await runCount(page);
  await page.click('#run');
  await waitForRun(page, before, 'done', 120000);
  // The crown envelope hides the tree: show the tree and its skeleton.
  for (const name of ['crown']) {
    await page.locator('#objects label', { hasText: new RegExp(`^\\s*${name}\\s`) }).locator('input').uncheck();
  }
  await page.click('#frame');
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(shots, 'studio_mesh.png') });
  await page.locator('#line-mode').check();
  await page.waitForFunction(() => document.body.dataset.linesState === 'ready', null, { timeout: 60000 });
  await page.screenshot({ path: join(shots, 'studio_lines.png') });
  await page.locator('#line-mode').uncheck();
  // A vase profile sketched on the XY plane (closed: a filled region), then revolved.
  const vase = [[0, -1.2], [0.9, -1.1], [1.3, -0.3], [0.9, 0.6], [0.55, 1.1], [0.8, 1.6], [0, 1.5]];
  const canvas = await sketchProfile(page, '# a vase from a sketched profile\n', true, vase);
  await page.screenshot({ path: join(shots, 'studio_sketch.png') });
  await page.click('#sketch');
  const n = await runCount(page);
  await page.click('#run');
  await waitForRun(page, n, 'done', 60000);
  // Orbit up and around a little, to see the solid in depth.
  await page.mouse.move(canvas.x + canvas.width / 2, canvas.y + canvas.height / 2);
  await page.mouse.down();
  await page.mouse.move(canvas.x + canvas.width / 2 - 80, canvas.y + canvas.height / 2 + 70, { steps: 5 });
  await page.mouse.up();
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(shots, 'studio_sketch_run.png') });
  await page.locator('#sketch-closed').uncheck();
  log('doc screenshots written');
}

let code = 1;
try {
  code = await main();
} catch (e) {
  log(`error: ${e.stack || e.message}`);
  code = 1;
} finally {
  await browser?.close().catch(() => {});
  server?.kill('SIGTERM');
}
if (code !== 77) {
  const failed = results.filter((r) => !r.ok).length;
  console.log(`measured: ${JSON.stringify(measured)}`);
  console.log(`${results.length - failed} passed, ${failed} failed`);
  if (results.length === 0) code = 1;
}
log('finished');
process.exit(code);
