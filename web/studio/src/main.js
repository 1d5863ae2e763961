// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The page of `ramiform studio` (docs/studio.md): the script editor beside the 3-D view, as in
// the modeler of Kochhar 2010 (§4.1), talking to the server's API (the contract in issue 22)
// with relative URLs. Test hooks: element ids, document.body.dataset.state (idle, running,
// done, failed, cancelled) and dataset.linesState (idle, loading, ready), and window.studio.
import './style.css';
import { EditorState, Prec, StateEffect, StateField, RangeSetBuilder } from '@codemirror/state';
import {
  EditorView, keymap, lineNumbers, highlightActiveLine, highlightActiveLineGutter, drawSelection,
  Decoration,
} from '@codemirror/view';
import { defaultKeymap, history, historyKeymap, indentWithTab } from '@codemirror/commands';
import { autocompletion, completionKeymap } from '@codemirror/autocomplete';
import { lintGutter, setDiagnostics } from '@codemirror/lint';
import { searchKeymap, highlightSelectionMatches } from '@codemirror/search';
import { sceneSupport, completionSource, scriptParams } from './language.js';
import { sliderRange, formatValue } from './params.js';
import { createView } from './view3d.js';
import { freshName, sketchText, skinText } from './sketch.js';
import { combineText, freshWord, insertLines, translateText } from './edit.js';
import * as THREE from 'three';

const $ = (id) => document.getElementById(id);
const token = new URLSearchParams(location.search).get('token');

// ---- the API ---------------------------------------------------------------------------------
async function api(path, body, { signal, raw = false } = {}) {
  const headers = {};
  if (token) headers['X-Ramiform-Token'] = token;
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const response = await fetch(path.replace(/^\//, ''), {
    method: body === undefined ? 'GET' : 'POST',
    headers,
    body: body === undefined ? undefined : JSON.stringify(body),
    signal,
  });
  if (raw) return response;
  const text = await response.text();
  let data;
  try {
    data = JSON.parse(text);
  } catch {
    data = { error: text };
  }
  if (!response.ok) throw new Error(data.error || `${response.status} ${response.statusText}`);
  return data;
}

// ---- the editor ------------------------------------------------------------------------------
let commands = [];
const setErrorLine = StateEffect.define();
const errorLineField = StateField.define({
  create: () => Decoration.none,
  update(decorations, tr) {
    decorations = decorations.map(tr.changes);
    for (const e of tr.effects) {
      if (!e.is(setErrorLine)) continue;
      const builder = new RangeSetBuilder();
      if (e.value !== null && e.value >= 1 && e.value <= tr.state.doc.lines) {
        const line = tr.state.doc.line(e.value);
        builder.add(line.from, line.from, Decoration.line({ class: 'cm-error-line' }));
      }
      decorations = builder.finish();
    }
    return decorations;
  },
  provide: (f) => EditorView.decorations.from(f),
});

const editor = new EditorView({
  parent: $('editor'),
  state: EditorState.create({
    doc: '',
    extensions: [
      lineNumbers(),
      highlightActiveLineGutter(),
      history(),
      drawSelection(),
      highlightActiveLine(),
      highlightSelectionMatches(),
      EditorView.lineWrapping,
      sceneSupport(),
      autocompletion({ override: [completionSource(() => commands)], icons: false }),
      lintGutter(),
      errorLineField,
      Prec.highest(keymap.of([{ key: 'Mod-Enter', run: () => (run({ frame: true }), true) }])),
      keymap.of([...completionKeymap, ...defaultKeymap, ...historyKeymap, ...searchKeymap, indentWithTab]),
      EditorView.updateListener.of((u) => {
        if (u.docChanged) forgetEditedOverrides();
      }),
    ],
  }),
});

function script() {
  return editor.state.doc.toString();
}

function setScript(text) {
  editor.dispatch({ changes: { from: 0, to: editor.state.doc.length, insert: text } });
}

function showError(error) {
  const box = $('error');
  if (!error) {
    box.hidden = true;
    box.textContent = '';
    delete box.dataset.line;
    delete box.dataset.column;
    editor.dispatch(setDiagnostics(editor.state, []), { effects: setErrorLine.of(null) });
    return;
  }
  const doc = editor.state.doc;
  const lineNo = Number.isInteger(error.line) && error.line >= 1 && error.line <= doc.lines ? error.line : null;
  box.hidden = false;
  // The server's message may start with its own `FILE:LINE:COLUMN: `; the box says the place once.
  const message = lineNo ? String(error.message).replace(/^[^\s:]*:\d+:\d+:\s*/, '') : error.message;
  box.textContent = lineNo ? `line ${lineNo}, column ${error.column ?? 1}: ${message}` : message;
  if (lineNo) {
    box.dataset.line = lineNo;
    box.dataset.column = error.column ?? 1;
    const line = doc.line(lineNo);
    const from = Math.min(line.to, line.from + Math.max(0, (error.column ?? 1) - 1));
    const word = /^\S*/.exec(line.text.slice(from - line.from))[0].length;
    const to = Math.min(line.to, from + Math.max(1, word));
    editor.dispatch(setDiagnostics(editor.state, [{ from, to: Math.max(to, from), severity: 'error', message: error.message }]), {
      effects: setErrorLine.of(lineNo),
    });
  } else {
    editor.dispatch(setDiagnostics(editor.state, []), { effects: setErrorLine.of(null) });
  }
}

// ---- params ----------------------------------------------------------------------------------
// Slider values the user chose (name → {value, scriptValue}); sent with every run until the
// script's own `param` line for that name is edited.
const overrides = new Map();

function forgetEditedOverrides() {
  const declared = scriptParams(script());
  for (const [name, o] of overrides) {
    const d = declared.get(name);
    if (!d || d.value !== o.scriptValue) overrides.delete(name);
  }
}

let rerunTimer = null;
function renderParams(params) {
  const box = $('params');
  box.replaceChildren();
  if (!params || params.length === 0) return;
  const declared = scriptParams(script());
  for (const p of params) {
    const row = document.createElement('div');
    row.className = 'param';
    const label = document.createElement('label');
    label.textContent = p.name;
    const output = document.createElement('output');
    // The range comes from the script's own value (the run reports the value it used, which
    // after a drag is the slider's), so dragging does not move the slider's ends.
    const range = sliderRange({ ...p, value: declared.get(p.name)?.value ?? p.value });
    const current = overrides.has(p.name) ? overrides.get(p.name).value : String(p.value);
    output.textContent = current;
    row.append(label);
    if (range) {
      const slider = document.createElement('input');
      slider.type = 'range';
      slider.min = range.min;
      slider.max = range.max;
      slider.step = range.step;
      slider.value = current;
      slider.dataset.param = p.name;
      label.htmlFor = slider.id = `param-${p.name}`;
      slider.addEventListener('input', () => {
        const value = formatValue(slider.value, range.step);
        output.textContent = value;
        overrides.set(p.name, { value, scriptValue: declared.get(p.name)?.value ?? String(p.value) });
        // While dragging: draft runs (coarse meshes, no drawings: ScriptOptions::draft); on
        // release the full run. The server cancels whichever run is older.
        clearTimeout(rerunTimer);
        rerunTimer = setTimeout(() => run({ frame: false, draft: true }), 150);
      });
      slider.addEventListener('change', () => run({ frame: false }));
      row.append(slider);
    }
    row.append(output);
    box.append(row);
  }
}

function paramValues() {
  const declared = scriptParams(script());
  const values = {};
  for (const [name, o] of overrides) if (declared.has(name)) values[name] = o.value;
  return values;
}

// ---- runs ------------------------------------------------------------------------------------
const view = createView($('view'));
let currentRun = null; // id of the latest run
let runTicket = 0; // counts Run presses: an older loop that sees a newer ticket stops
let lastResult = null;
let lastScript = null; // the script text of lastResult's run
const timings = { runs: [], lines: [] };

function setState(state) {
  document.body.dataset.state = state;
  $('cancel').disabled = state !== 'running';
}

async function run({ frame = true, draft = false } = {}) {
  clearTimeout(rerunTimer);
  const ticket = ++runTicket;
  const started = performance.now();
  showError(null);
  setState('running');
  $('progress').value = 0;
  $('stage').textContent = 'starting';
  let id;
  const sent = script();
  try {
    ({ run: id } = await api('api/run', { script: sent, params: paramValues(), draft }));
  } catch (e) {
    if (ticket !== runTicket) return;
    setState('failed');
    showError({ message: e.message });
    return;
  }
  if (ticket !== runTicket) return;
  currentRun = id;
  let earlyShown = 0; // entries of status.early already on their way to the view
  let earlyAt = null; // seconds from Run to the first of them shown
  for (;;) {
    let status;
    try {
      status = await api(`api/run/${id}`);
    } catch (e) {
      if (ticket !== runTicket) return;
      setState('failed');
      showError({ message: e.message });
      return;
    }
    if (ticket !== runTicket) return; // a newer run took over
    const progress = status.progress || {};
    $('progress').value = Number.isFinite(progress.fraction) ? progress.fraction : 0;
    $('stage').textContent = `${progress.stage || status.state} ${(status.seconds ?? 0).toFixed(1)} s`;
    if (status.state === 'running') {
      // A mesh polygonized already is shown while its bark UVs and files are made.
      for (const info of (status.early || []).slice(earlyShown)) {
        earlyShown += 1;
        view.showEarly(info).then((shown) => {
          if (shown && ticket === runTicket && earlyAt === null) {
            earlyAt = (performance.now() - started) / 1000;
          }
        }, () => {}); // the run's own objects follow anyway
      }
      await new Promise((r) => setTimeout(r, 50));
      continue;
    }
    await finish(status, frame, sent);
    if (ticket !== runTicket) return;
    timings.runs.push({ run: id, state: status.state, draft, server: status.seconds, wall: (performance.now() - started) / 1000, early: earlyAt });
    setState(status.state);
    return;
  }
}

async function finish(status, frame, sent) {
  lastResult = status;
  lastScript = sent;
  $('progress').value = status.state === 'done' ? 1 : $('progress').value;
  $('stage').textContent = `${status.state} ${(status.seconds ?? 0).toFixed(2)} s`;
  renderLog(status);
  if (status.state === 'failed') showError(status.error || { message: 'the run failed' });
  if (status.state !== 'done') return;
  renderParams(status.params);
  renderDownloads(status.outputs || []);
  renderShapes(status.shapes || []);
  try {
    if (!(await view.setObjects(status.objects || [], { frame }))) return; // a newer run's came first
  } catch (e) {
    showError({ message: `could not show the results: ${e.message}` });
  }
  renderObjects(status.objects || []);
  if (linesOn()) requestLines();
}

async function cancel() {
  if (!currentRun) return;
  try {
    await api(`api/run/${currentRun}/cancel`, {});
  } catch (e) {
    showError({ message: e.message });
  }
}

// ---- panels ----------------------------------------------------------------------------------
function cell(row, text, className) {
  const td = document.createElement('td');
  td.textContent = text;
  if (className) td.className = className;
  row.append(td);
}

function statsText(stats) {
  return Object.entries(stats || {})
    .map(([k, v]) => `${k.replace(/_/g, ' ')} ${typeof v === 'boolean' ? (v ? 'yes' : 'no') : typeof v === 'number' ? v.toLocaleString('en-US', { maximumFractionDigits: 4 }) : v}`)
    .join(', ');
}

function renderLog(status) {
  const table = document.createElement('table');
  const head = table.insertRow();
  ['line', 'command', 'message', 's'].forEach((h) => cell(head, h, 'head'));
  for (const entry of status.log || []) {
    const row = table.insertRow();
    cell(row, entry.line ?? '', 'num');
    cell(row, entry.command ?? '');
    cell(row, entry.message ?? '', 'message');
    cell(row, Number.isFinite(entry.seconds) ? entry.seconds.toFixed(3) : '', 'num');
  }
  const total = table.insertRow();
  total.className = 'total';
  cell(total, '');
  cell(total, 'total');
  cell(total, status.state);
  cell(total, Number.isFinite(status.seconds) ? status.seconds.toFixed(3) : '', 'num');
  const stats = document.createElement('ul');
  stats.className = 'stats';
  for (const o of status.objects || []) {
    const li = document.createElement('li');
    li.textContent = `${o.name} (${o.kind}${o.preview ? ', preview' : ''}): ${statsText(o.stats)}`;
    stats.append(li);
  }
  $('log').replaceChildren(table, stats);
}

const hiddenDrawings = new Set(); // names of `draw` pictures the user hid

function renderObjects(objects) {
  const box = $('objects');
  box.replaceChildren();
  const drawings = $('drawings');
  drawings.replaceChildren();
  for (const o of objects) {
    const label = document.createElement('label');
    const check = document.createElement('input');
    check.type = 'checkbox';
    check.checked = o.kind === 'drawing' ? !hiddenDrawings.has(o.name) : view.isVisible(o.id);
    check.dataset.object = o.id;
    label.append(check, ` ${o.name} `);
    const kind = document.createElement('span');
    kind.className = 'kind';
    kind.textContent = o.kind + (o.preview ? ' (preview)' : '');
    label.append(kind);
    box.append(label);
    if (o.kind === 'drawing') {
      const img = document.createElement('img');
      img.src = o.view.replace(/^\//, '');
      img.alt = o.name;
      img.dataset.object = o.id;
      img.hidden = !check.checked;
      drawings.append(img);
      check.addEventListener('change', () => {
        img.hidden = !check.checked;
        if (check.checked) hiddenDrawings.delete(o.name);
        else hiddenDrawings.add(o.name);
      });
    } else {
      check.addEventListener('change', () => view.setVisible(o.id, check.checked));
    }
  }
}

function renderDownloads(outputs) {
  const list = $('downloads');
  list.replaceChildren();
  for (const o of outputs) {
    const li = document.createElement('li');
    const a = document.createElement('a');
    a.href = o.url.replace(/^\//, '');
    a.download = o.path.split('/').pop();
    a.textContent = o.path;
    const size = document.createElement('span');
    size.className = 'bytes';
    size.textContent = ` ${formatBytes(o.bytes)}`;
    li.append(a, size);
    list.append(li);
  }
}

function formatBytes(n) {
  if (!Number.isFinite(n)) return '';
  if (n < 1024) return `${n} B`;
  if (n < 1024 * 1024) return `${(n / 1024).toFixed(1)} KiB`;
  return `${(n / 1024 / 1024).toFixed(1)} MiB`;
}

// ---- line mode -------------------------------------------------------------------------------
const linesShape = document.createElement('select');
linesShape.id = 'lines-shape';
linesShape.title = 'The shape drawn in line mode';
$('lines-mesh').after(linesShape);

function renderShapes(shapes) {
  const keep = linesShape.value;
  linesShape.replaceChildren(...shapes.map((s) => new Option(s, s)));
  if (shapes.includes(keep)) linesShape.value = keep;
  else if (shapes.length > 0) linesShape.value = shapes[shapes.length - 1];
}

const linesOn = () => $('line-mode').checked;
let linesTimer = null;
let linesAbort = null;
let linesSeq = 0;
let linesAsked = 0; // counts requestLines calls: a drawing asked for before the last one is stale

function setLinesState(s) {
  document.body.dataset.linesState = s;
}

function requestLines() {
  clearTimeout(linesTimer);
  if (!linesOn()) return;
  ++linesAsked;
  setLinesState('loading');
  linesTimer = setTimeout(fetchLines, 120);
}

async function fetchLines() {
  if (!linesOn() || !lastResult || !linesShape.value) {
    setLinesState('idle'); // nothing to draw yet: the next run's results ask again
    return;
  }
  linesAbort?.abort();
  const abort = (linesAbort = new AbortController());
  const seq = ++linesSeq;
  const asked = linesAsked;
  const camera = view.cameraState();
  // A shape's first drawing spreads its particles (seconds on a large tree): while it takes
  // long, the toolbar shows the server's stage for it.
  const poll = setInterval(async () => {
    if (seq !== linesSeq || document.body.dataset.state === 'running') return;
    try {
      const p = await api('api/lines/progress');
      if (seq !== linesSeq || !p.busy) return;
      $('progress').value = Number.isFinite(p.fraction) ? p.fraction : 0;
      $('stage').textContent = `${p.stage} ${p.seconds.toFixed(1)} s`;
    } catch {}
  }, 250);
  try {
    // First a quick drawing (hidden lines by the particles' disks, tens of milliseconds), then
    // the exact one (hidden lines by rays), unless the camera moved meanwhile.
    for (const visibility of ['surfels', 'rays']) {
      const started = performance.now();
      const response = await api(
        'api/lines',
        { run: lastResult.run, shape: linesShape.value, camera, lines: ['silhouette', 'suggestive', 'feature'], count: 10000, visibility },
        { signal: abort.signal, raw: true },
      );
      const text = await response.text();
      // The camera moved (or the shape changed) while this was drawn: the next one is on its way.
      if (seq !== linesSeq || asked !== linesAsked) return;
      if (!response.ok) {
        let message = text;
        try {
          message = JSON.parse(text).error;
        } catch {}
        throw new Error(message);
      }
      const svg = new DOMParser().parseFromString(text, 'image/svg+xml').documentElement;
      if (svg.nodeName !== 'svg') throw new Error('the server sent no SVG');
      svg.querySelectorAll('script, foreignObject').forEach((n) => n.remove());
      svg.setAttribute('width', camera.width);
      svg.setAttribute('height', camera.height);
      svg.dataset.eye = camera.eye.join(',');
      svg.dataset.visibility = visibility;
      $('lines-svg').replaceChildren(document.importNode(svg, true));
      $('lines-svg').hidden = false;
      const server = Number(response.headers.get('X-Ramiform-Seconds'));
      const wall = (performance.now() - started) / 1000;
      timings.lines.push({ server, wall, visibility });
      $('progress').value = 1;
      $('stage').textContent = `lines ${visibility === 'rays' ? '' : '(quick) '}${Number.isFinite(server) ? `${(server * 1000).toFixed(0)} ms server, ` : ''}${(wall * 1000).toFixed(0)} ms`;
    }
    setLinesState('ready');
  } catch (e) {
    if (e.name === 'AbortError' || seq !== linesSeq) return;
    showError({ message: `line mode: ${e.message}` });
    setLinesState('idle');
  } finally {
    clearInterval(poll);
  }
}

function updateLineMode() {
  const on = linesOn();
  view.setMeshMode(on ? $('lines-mesh').value : 'shown');
  if (on) requestLines();
  else {
    linesAbort?.abort();
    clearTimeout(linesTimer);
    $('lines-svg').replaceChildren();
    setLinesState('idle');
  }
}

view.onCameraChange(() => {
  if (!linesOn()) return;
  $('lines-svg').hidden = true; // the old drawing no longer fits the camera
  requestLines();
});

// ---- sketching -------------------------------------------------------------------------------
// A profile ('xy'), a cross-section ('xz'), or cross-sections on rising horizontal planes
// skinned together ('skin': Next section raises the plane by the step).
const sketch = { on: false, points: [], down: null, sections: [], height: 0 };
const planeNormal = () => ($('sketch-plane').value === 'xy' ? new THREE.Vector3(0, 0, 1) : new THREE.Vector3(0, 1, 0));
const skinning = () => $('sketch-plane').value === 'skin';

function showSketch() {
  view.showSketch(sketch.on ? $('sketch-plane').value : null, sketch.points, {
    height: sketch.height,
    sections: sketch.sections.map((s) => s.points),
  });
}

function setSketch(on) {
  sketch.on = on;
  sketch.points = [];
  sketch.sections = [];
  sketch.height = 0;
  $('sketch').textContent = on ? 'Finish sketch' : 'Sketch';
  $('sketch').classList.toggle('active', on);
  $('sketch-hint').hidden = !on;
  $('sketch-hint').textContent = skinning()
    ? 'Skin: click a section’s points, “Next section” raises the plane by the step, “Finish sketch” skins them (Esc cancels).'
    : 'Sketch: click points on the plane, then click “Finish sketch” (Esc cancels).';
  $('sketch-next').hidden = !(on && skinning());
  document.body.dataset.sketch = on ? 'on' : 'off';
  if (on) view.facePlane($('sketch-plane').value);
  showSketch();
}

// Skin: the section drawn so far is kept and the plane rises by the step.
function nextSection() {
  if (!sketch.on || !skinning() || sketch.points.length < 3) return;
  sketch.sections.push({ points: sketch.points, height: sketch.height });
  sketch.points = [];
  const step = Number($('sketch-step').value);
  sketch.height += Number.isFinite(step) && step > 0 ? step : 1;
  showSketch();
}

function finishSketch() {
  const plane = $('sketch-plane').value;
  const name = freshName(script());
  let text;
  if (plane === 'skin') {
    const sections = [...sketch.sections];
    if (sketch.points.length >= 3) sections.push({ points: sketch.points, height: sketch.height });
    text = skinText(sections, name);
  } else {
    text = sketchText(sketch.points, plane, $('sketch-closed').checked, name);
  }
  setSketch(false);
  if (!text) return;
  const { from, to } = editor.state.selection.main;
  const line = editor.state.doc.lineAt(from);
  // Whole lines: start on a fresh line and end with a newline.
  const prefix = from === line.from ? '' : '\n';
  const insert = `${prefix}${text}\n`;
  editor.dispatch({ changes: { from, to, insert }, selection: { anchor: from + insert.length } });
  editor.focus();
}

view.canvas.addEventListener('pointerdown', (e) => {
  sketch.down = { x: e.clientX, y: e.clientY };
});
view.canvas.addEventListener('pointerup', (e) => {
  if (!sketch.down) return;
  const moved = Math.hypot(e.clientX - sketch.down.x, e.clientY - sketch.down.y);
  sketch.down = null;
  if (moved > 4) return; // a drag orbits the camera
  if (edit.mode === 'combine') return combineClick(e);
  if (!sketch.on) return;
  const hit = view.pick(e.clientX, e.clientY, planeNormal(), skinning() ? sketch.height : 0);
  if (!hit) return;
  sketch.points.push(hit);
  showSketch();
});
$('sketch').addEventListener('click', () => {
  if (edit.mode) setEdit(null);
  sketch.on ? finishSketch() : setSketch(true);
});
$('sketch-plane').addEventListener('change', () => {
  $('sketch-step').hidden = !skinning();
  $('sketch-closed').parentElement.hidden = skinning(); // skin sections are always closed
  if (sketch.on) setSketch(true);
});
$('sketch-next').addEventListener('click', nextSection);
window.addEventListener('keydown', (e) => {
  if (e.key === 'Escape' && sketch.on) setSketch(false);
  if (e.key === 'Escape' && edit.mode) setEdit(null);
});

// ---- editing on the surfaces ----------------------------------------------------------------
// Combine: click two surfaces, the chosen operation between their shapes is appended to the
// script (and their meshes hidden); Move: drag a surface, a `translate` line goes in before the
// `save_mesh` line that made it (edit.js). Both run the script again.
const edit = { mode: null, first: null, drag: null };

function setEdit(mode) {
  if (sketch.on) setSketch(false);
  if (edit.drag) view.setOffset(edit.drag.id, new THREE.Vector3());
  edit.mode = mode;
  edit.first = null;
  edit.drag = null;
  view.controls.enabled = true;
  $('combine').classList.toggle('active', mode === 'combine');
  $('move').classList.toggle('active', mode === 'move');
  document.body.dataset.edit = mode || 'off';
  editHint();
}

function editHint(text) {
  const hint = $('edit-hint');
  const texts = {
    combine: edit.first ? `Combine: click the second surface (the first is ${edit.first.info.shape}).` : 'Combine: click the first surface.',
    move: 'Move: drag a surface (Esc cancels).',
  };
  hint.textContent = text || texts[edit.mode] || '';
  hint.hidden = !hint.textContent;
}

// The picked object's shape, or null with a message (not a script's mesh, or the view is stale).
function pickedShape(e) {
  const hit = view.pickObject(e.clientX, e.clientY);
  if (!hit) return null;
  if (!hit.info.shape) {
    editHint('That mesh was not made by save_mesh of a shape; pick another.');
    return null;
  }
  if (lastScript !== script()) {
    showError({ message: 'The view shows an older version of the script: Run it first, then pick.' });
    setEdit(null);
    return null;
  }
  return hit;
}

function applyEdit(text) {
  setScript(text);
  setEdit(null);
  run({ frame: false });
}

function combineClick(e) {
  const hit = pickedShape(e);
  if (!hit) return;
  if (!edit.first) {
    edit.first = hit;
    editHint();
    return;
  }
  const a = edit.first.info.shape;
  const b = hit.info.shape;
  if (a === b) {
    editHint(`Both clicks picked ${a}: click a surface of another shape.`);
    return;
  }
  const op = $('edit-op').value;
  const name = freshWord(script(), `${a}_${b}`);
  view.setVisible(edit.first.id, false); // visibility carries over to the new run's meshes
  view.setVisible(hit.id, false);
  applyEdit(insertLines(script(), 0, combineText(op, a, b, name)));
}

// Move: the pointer goes down on a surface (before OrbitControls sees it, which would orbit).
view.canvas.parentElement.addEventListener(
  'pointerdown',
  (e) => {
    if (edit.mode !== 'move' || e.button !== 0) return;
    const hit = pickedShape(e);
    if (!hit) return;
    view.controls.enabled = false;
    edit.drag = { id: hit.id, info: hit.info, start: hit.point, delta: new THREE.Vector3() };
    e.preventDefault();
  },
  { capture: true },
);
window.addEventListener('pointermove', (e) => {
  if (!edit.drag) return;
  const p = view.pointOnViewPlane(e.clientX, e.clientY, edit.drag.start);
  if (!p) return;
  edit.drag.delta = p.sub(edit.drag.start);
  view.setOffset(edit.drag.id, edit.drag.delta);
});
window.addEventListener('pointerup', () => {
  if (!edit.drag) return;
  const { id, info, delta } = edit.drag;
  edit.drag = null;
  view.controls.enabled = true;
  const line = translateText(info.shape, delta.toArray(), view.objectSize(id));
  if (!line) {
    view.setOffset(id, new THREE.Vector3());
    return;
  }
  applyEdit(insertLines(script(), info.line, line));
});

// ---- wiring ----------------------------------------------------------------------------------
$('run').addEventListener('click', () => run({ frame: true }));
$('cancel').addEventListener('click', cancel);
$('frame').addEventListener('click', () => view.frameAll());
$('flat').addEventListener('change', (e) => view.setFlat(e.target.checked));
$('wireframe').addEventListener('change', (e) => view.setWireframe(e.target.checked));
$('line-mode').addEventListener('change', updateLineMode);
$('lines-mesh').addEventListener('change', updateLineMode);
linesShape.addEventListener('change', requestLines);
$('combine').addEventListener('click', () => setEdit(edit.mode === 'combine' ? null : 'combine'));
$('move').addEventListener('click', () => setEdit(edit.mode === 'move' ? null : 'move'));

window.studio = {
  view,
  editor,
  timings,
  script,
  setScript,
  run,
  get result() {
    return lastResult;
  },
  sketchPoints: () => sketch.points.map((p) => p.toArray()),
  sketchSections: () => sketch.sections.map((s) => ({ height: s.height, points: s.points.map((p) => p.toArray()) })),
};

(async () => {
  setState('idle');
  setLinesState('idle');
  // Keep the token out of sight; a reload of index.html is let in by the cookie.
  if (token) window.history.replaceState(null, '', 'index.html');
  try {
    const info = await api('api/info');
    commands = info.commands || [];
    $('script-name').textContent = info.script_name || '';
    document.title = `${info.script_name ? `${info.script_name} — ` : ''}ramiform studio ${info.version || ''}`;
    setScript(info.script || '');
    document.body.dataset.ready = 'yes';
  } catch (e) {
    showError({ message: `cannot reach the server: ${e.message}` });
  }
})();
