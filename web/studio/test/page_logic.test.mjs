// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The page's logic that needs no browser (node --test): slider ranges from `param` lines, the
// `param` lines of a script, and the script text that a sketch becomes, checked against values
// worked out by hand from docs/studio.md and docs/formats.md (page (X, Y, Z) = library
// (X, −Z, Y)).
import test from 'node:test';
import assert from 'node:assert/strict';
import { decimals, sliderRange, formatValue } from '../src/params.js';
import { freshName, sketchText, skinText } from '../src/sketch.js';
import { combineText, freshWord, insertLines, pageToLibrary, translateText } from '../src/edit.js';

test('decimals of a written number', () => {
  assert.equal(decimals('200'), 0);
  assert.equal(decimals('0.250'), 3);
  assert.equal(decimals('1.0'), 1);
  assert.equal(decimals('1e-3'), 3);
  assert.equal(decimals('2.5e1'), 0);
});

test('slider ranges: the script\'s own, else 0..2×value in steps of the last decimal', () => {
  assert.deepEqual(sliderRange({ name: 'n', value: '200', min: 10, max: 1000, step: 10 }), { min: 10, max: 1000, step: 10 });
  assert.deepEqual(sliderRange({ name: 'n', value: '200' }), { min: 0, max: 400, step: 1 });
  assert.deepEqual(sliderRange({ name: 'r', value: '0.25' }), { min: 0, max: 0.5, step: 0.01 });
  assert.deepEqual(sliderRange({ name: 'd', value: '-1.5' }), { min: -3, max: 0, step: 0.1 });
  // Zero gets a range of ten steps; a word gets no slider.
  assert.deepEqual(sliderRange({ name: 'z', value: '0' }), { min: 0, max: 10, step: 1 });
  assert.equal(sliderRange({ name: 'kind', value: 'poisson' }), null);
  assert.equal(formatValue('1.5000000001', 0.1), '1.5');
  assert.equal(formatValue('7', 1), '7');
  assert.equal(formatValue('0.123456', 0.001), '0.123');
});

test('a sketched profile on the XY plane becomes curve + revolve in page X, Y', () => {
  const points = [{ x: 0.2, y: -0.8, z: 0 }, { x: 0.8, y: -0.4, z: 0 }, { x: 0.6, y: 0.5, z: 0 }];
  const text = sketchText(points, 'xy', false, 'p');
  const lines = text.split('\n');
  assert.equal(lines[1], 'curve p polyline 0.2 -0.8 0.8 -0.4 0.6 0.5');
  assert.equal(lines[2], 'revolve p_solid p radius=0.02');
  assert.equal(lines.length, 3);
});

test('a sketched cross-section on the ground becomes a closed curve in (X, −Z), swept up', () => {
  const points = [{ x: -1, y: 0, z: 1 }, { x: 1, y: 0, z: 1 }, { x: 0, y: 0, z: -2 }];
  const lines = sketchText(points, 'xz', true, 's').split('\n');
  assert.equal(lines[1], 'curve s polyline closed -1 -1 1 -1 0 2');
  assert.equal(lines[2], 'path s_path polyline 0 0 0 0 0 2');
  assert.equal(lines[3], 'sweep s_solid s s_path radius=0.05');
});

test('too few points make no text; names do not clash', () => {
  assert.equal(sketchText([{ x: 0, y: 0, z: 0 }], 'xy', false, 'a'), null);
  assert.equal(sketchText([{ x: 0, y: 0, z: 0 }, { x: 1, y: 0, z: 0 }], 'xy', true, 'a'), null);
  assert.equal(freshName('sphere s 1\n'), 'sketch');
  assert.equal(freshName('curve sketch polyline 0 0 1 1\nrevolve sketch_solid sketch\n'), 'sketch2');
  assert.equal(freshName('path sketch2_path polyline 0 0 0 0 0 1\ncurve sketch polyline 0 0 1 1\n'), 'sketch3');
});

test('combining two picked surfaces appends the operation and a save_mesh of the result', () => {
  assert.equal(
    combineText('diff', 'a', 'b', 'a_b'),
    '# picked on the surfaces: the difference of a and b\ndiff a b a_b\nsave_mesh a_b a_b.glb',
  );
  assert.equal(combineText('blend', 'crown', 'top', 'x').split('\n')[1], 'blend crown top x');
  assert.throws(() => combineText('xor', 'a', 'b', 'c'), /unknown operation 'xor'/);
  // Fresh names avoid every word of the script, option values included.
  assert.equal(freshWord('sphere a 1\nsphere b 1\n', 'a_b'), 'a_b');
  assert.equal(freshWord('blend a b a_b\nsave_mesh a_b a_b.glb\n', 'a_b'), 'a_b2');
  assert.equal(freshWord('x=a_b a_b2', 'a_b'), 'a_b3');
});

test('a dragged surface becomes translate in the library frame, before its save_mesh line', () => {
  // Page (X, Y, Z) = library (X, −Z, Y): a drag up the screen (+Y) is the library's +z, a drag
  // towards the viewer (+Z) its −y.
  assert.deepEqual(pageToLibrary([1, 2, 3]), [1, -3, 2]);
  assert.equal(translateText('s', [0.5, 0.25, -0.125], 1), 'translate s 0.5 0.125 0.25');
  // Three significant decimals of the object's size: 1.23456 on a size-1 object is 1.235.
  assert.equal(translateText('s', [1.23456, 0, 0], 1), 'translate s 1.235 0 0');
  assert.equal(translateText('s', [0.0123456, 0, 0], 0.05), 'translate s 0.01235 0 0');
  assert.equal(translateText('s', [0.0001, 0, 0], 1), null); // rounds to no move
  const text = 'sphere a 1\nsphere b 1\nsave_mesh b b.glb';
  assert.equal(insertLines(text, 3, 'translate b 1 0 0'), 'sphere a 1\nsphere b 1\ntranslate b 1 0 0\nsave_mesh b b.glb');
  // Line 0 (the server's preview mesh) or past the end: appended as whole lines.
  assert.equal(insertLines(text, 0, 'x'), `${text}\nx\n`);
  assert.equal(insertLines(`${text}\n`, 9, 'x'), `${text}\nx\n`);
  assert.equal(insertLines('', 0, 'x'), 'x\n');
});

test('sketched sections on rising horizontal planes become curves skinned along a vertical path', () => {
  // Page (X, Y, Z) = library (X, −Z, Y): a section on the plane Y = h lies in the library's
  // plane z = h, its curve in (X, −Z).
  const square = (r, h) => [[-r, -r], [r, -r], [r, r], [-r, r]].map(([x, z]) => ({ x, y: h, z }));
  const text = skinText([{ points: square(0.5, 0), height: 0 }, { points: square(0.25, 1), height: 1 }, { points: square(0.5, 2), height: 2 }], 'k');
  assert.deepEqual(text.split('\n'), [
    '# sketched cross-sections on horizontal planes (heights 0, 1, 2), skinned',
    'path k_path polyline 0 0 0 0 0 2',
    'curve k_1 polyline closed -0.5 0.5 0.5 0.5 0.5 -0.5 -0.5 -0.5',
    'curve k_2 polyline closed -0.25 0.25 0.25 0.25 0.25 -0.25 -0.25 -0.25',
    'curve k_3 polyline closed -0.5 0.5 0.5 0.5 0.5 -0.5 -0.5 -0.5',
    'skin k_solid k_path k_1@0 k_2@0.5 k_3@1 interp=cubic radius=0.05',
  ]);
  // Two sections: linear interpolation, the path from the first height to the second.
  const two = skinText([{ points: square(1, 0.5), height: 0.5 }, { points: square(1, 1.6), height: 1.6 }], 'k').split('\n');
  assert.equal(two[1], 'path k_path polyline 0 0 0.5 0 0 1.6');
  assert.equal(two.at(-1), 'skin k_solid k_path k_1@0 k_2@1 radius=0.04');
  // Fewer than two sections of three points, or a section not above the one before: nothing.
  assert.equal(skinText([{ points: square(1, 0), height: 0 }], 'k'), null);
  assert.equal(skinText([{ points: square(1, 0), height: 0 }, { points: square(1, 0).slice(0, 2), height: 1 }], 'k'), null);
  assert.equal(skinText([{ points: square(1, 1), height: 1 }, { points: square(1, 1), height: 1 }], 'k'), null);
  assert.equal(freshName('curve sketch_1 polyline closed 0 0 1 0 1 1'), 'sketch2');
});
