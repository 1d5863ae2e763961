// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Sketching as in the modeler of Kochhar 2010, *Application of implicit methods to the
// interactive modeling of trees* (M.Sc. thesis), §4.1: the user draws a profile or a
// cross-section and it becomes a 2-D curve that a surface of revolution or a sweep uses. Here the
// drawing is a polyline clicked on a plane of the 3-D view, and it becomes scene-language text,
// so the model stays a script (docs/language.md: curve, revolve, path, sweep).
//
// Frames: the view is +Y up (glTF); the library is +Z up, and its .glb maps (x, y, z) to
// (x, z, −y) (docs/formats.md). So a page point (X, Y, Z) is the library's (X, −Z, Y).
// - A profile drawn on the page's XY plane (Z = 0, facing the default camera) is the library's
//   XZ plane: curve x = X (distance from the axis), y = Y (height), and `revolve` turns it about
//   the library's z axis, the page's vertical axis, so the solid appears where it was drawn.
// - A cross-section drawn on the ground plane (page Y = 0) is the library's XY plane: curve
//   x = X, y = −Z, swept along a path that starts at the origin along the library's +z (page
//   up), where the section's axes are the world's x and y (`sweep`), so the solid rises from the
//   drawn outline.

// `v` with `places` decimals, trailing zeros dropped, without "-0".
export function number(v, places) {
  const s = v.toFixed(places).replace(/\.?0+$/, '');
  return s === '-0' || s === '' ? '0' : s;
}

// A name `stem`, `stem2`, ... that the script does not use yet as a word.
export function freshName(text, stem = 'sketch') {
  const used = new Set(text.split(/[\s#]+/));
  for (let i = 1; ; ++i) {
    const name = i === 1 ? stem : `${stem}${i}`;
    if (![name, `${name}_path`, `${name}_solid`, `${name}_1`].some((n) => used.has(n))) return name;
  }
}

// The script lines for sketched page points {x, y, z} on plane 'xy' (profile) or 'xz'
// (cross-section). Returns null for fewer than 2 points (3 for a closed curve).
export function sketchText(points, plane, closed, name) {
  if (points.length < (closed ? 3 : 2)) return null;
  const coordinates = points.map((p) => (plane === 'xy' ? [p.x, p.y] : [p.x, -p.z]));
  const extent = Math.max(1e-9, ...coordinates.flat().map(Math.abs));
  const places = Math.max(0, Math.min(6, 3 - Math.floor(Math.log10(extent))));
  const list = coordinates.map(([x, y]) => `${number(x, places)} ${number(y, places)}`).join(' ');
  const kind = closed ? 'polyline closed' : 'polyline';
  const radius = number(Math.max(extent / 40, 10 ** -places), places);
  if (plane === 'xy') {
    return [
      `# sketched profile: x = distance from the vertical axis, y = height`,
      `curve ${name} ${kind} ${list}`,
      `revolve ${name}_solid ${name} radius=${radius}`,
    ].join('\n');
  }
  const height = number(extent, places);
  return [
    `# sketched cross-section on the ground plane, swept upwards`,
    `curve ${name} ${kind} ${list}`,
    `path ${name}_path polyline 0 0 0 0 0 ${height}`,
    `sweep ${name}_solid ${name} ${name}_path radius=${radius}`,
  ].join('\n');
}

// The script lines for cross-sections sketched on horizontal planes (page Y = height), skinned
// into one solid as in the thesis's skinned surfaces (§4.2, Figure 4.10): `sections` is a list of
// {points: [{x, y, z}, ...], height} from the lowest up (each closed, at least 3 points). The
// path runs up the library's z axis from the first section's height to the last's, and each
// section sits at its height's share of it. Returns null for fewer than 2 usable sections or
// sections not strictly rising.
export function skinText(sections, name) {
  const used = sections.filter((s) => s.points.length >= 3);
  if (used.length < 2) return null;
  for (let i = 1; i < used.length; ++i) if (!(used[i].height > used[i - 1].height)) return null;
  const coordinates = used.map((s) => s.points.map((p) => [p.x, -p.z]));
  const heights = used.map((s) => s.height);
  const extent = Math.max(1e-9, ...coordinates.flat(2).map(Math.abs), ...heights.map(Math.abs));
  const places = Math.max(0, Math.min(6, 3 - Math.floor(Math.log10(extent))));
  const h0 = heights[0];
  const span = heights.at(-1) - h0;
  const lines = [
    `# sketched cross-sections on horizontal planes (heights ${heights.map((h) => number(h, places)).join(', ')}), skinned`,
    `path ${name}_path polyline 0 0 ${number(h0, places)} 0 0 ${number(heights.at(-1), places)}`,
  ];
  used.forEach((s, i) => {
    const list = coordinates[i].map(([x, y]) => `${number(x, places)} ${number(y, places)}`).join(' ');
    lines.push(`curve ${name}_${i + 1} polyline closed ${list}`);
  });
  const at = heights.map((h, i) => `${name}_${i + 1}@${number((h - h0) / span, 3)}`).join(' ');
  const radius = number(Math.max(extent / 40, 10 ** -places), places);
  lines.push(`skin ${name}_solid ${name}_path ${at}${used.length > 2 ? ' interp=cubic' : ''} radius=${radius}`);
  return lines.join('\n');
}
