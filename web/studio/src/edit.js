// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Editing on the surfaces, as in the modeler of Kochhar 2010, *Application of implicit methods
// to the interactive modeling of trees* (M.Sc. thesis), §4.1 and Figure 4.2: a boolean
// operation between two surfaces is made by picking them in the view, its type chosen from a
// list, and a surface is moved by dragging it. Both become scene-language text
// (docs/language.md: blend, union, intersect, diff, translate, save_mesh), so the model stays a
// script. These functions are the text; main.js does the picking.
//
// Frames: the view is +Y up (glTF) and the library +Z up; a page vector (X, Y, Z) is the
// library's (X, −Z, Y) (docs/formats.md).
import { number } from './sketch.js';

// The operations of Combine: the language's command and how the comment line names it.
export const kOperations = {
  blend: 'smooth blend',
  union: 'union',
  intersect: 'intersection',
  diff: 'difference',
};

// A name `stem`, `stem2`, ... that the script does not use yet as a word.
export function freshWord(text, stem) {
  const used = new Set(text.split(/[\s#=,]+/));
  for (let i = 1; ; ++i) {
    const name = i === 1 ? stem : `${stem}${i}`;
    if (!used.has(name)) return name;
  }
}

// The lines that combine shapes `a` and `b` (picked on their surfaces) with `op` into a new
// shape and mesh it. `name` is the new shape's name.
export function combineText(op, a, b, name) {
  if (!(op in kOperations)) throw new Error(`unknown operation '${op}'`);
  return [
    `# picked on the surfaces: the ${kOperations[op]} of ${a} and ${b}`,
    `${op} ${a} ${b} ${name}`,
    `save_mesh ${name} ${name}.glb`,
  ].join('\n');
}

// The library's vector of a page vector [X, Y, Z].
export function pageToLibrary([x, y, z]) {
  return [x, -z, y];
}

// The `translate` line that moves shape `name` by the page vector `delta`, rounded to three
// significant decimals of `scale` (the moved object's size); null when the rounded move is 0.
export function translateText(name, delta, scale) {
  const places = Math.max(0, Math.min(9, 3 - Math.floor(Math.log10(Math.max(scale, 1e-9)))));
  const v = pageToLibrary(delta).map((c) => number(c, places));
  if (v.every((c) => c === '0')) return null;
  return `translate ${name} ${v.join(' ')}`;
}

// `text` with the lines `insert` added before its line `line` (1-based); at the end when `line`
// is 0 or past the last line. Whole lines: the result ends the insert with a newline.
export function insertLines(text, line, insert) {
  const lines = text.split('\n');
  if (line >= 1 && line <= lines.length) {
    lines.splice(line - 1, 0, ...insert.split('\n'));
    return lines.join('\n');
  }
  const body = text.length === 0 || text.endsWith('\n') ? text : `${text}\n`;
  return `${body}${insert}\n`;
}
