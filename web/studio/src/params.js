// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `param` sliders. The run reports every `param` line (name, value, and min/max/step where the
// script gave them); a missing range is 0..2×value with a step of one unit in the value's last
// decimal (`param n 200` → 0..400 step 1; `param r 0.25` → 0..0.5 step 0.01). A value that is
// not a number gets no slider.

// The number of decimals written in a numeric string ("0.250" → 3, "200" → 0, "1e-3" → 3).
export function decimals(text) {
  const m = /^[-+]?\d*(?:\.(\d*))?(?:[eE]([-+]?\d+))?$/.exec(String(text).trim());
  if (!m) return 0;
  return Math.max(0, (m[1] ? m[1].length : 0) - (m[2] ? Number(m[2]) : 0));
}

// {min, max, step} for a reported param, or null when its value is not a number.
export function sliderRange(param) {
  const value = Number(param.value);
  if (String(param.value).trim() === '' || !Number.isFinite(value)) return null;
  const step = param.step > 0 ? param.step : 10 ** -decimals(param.value);
  let min = Number.isFinite(param.min) ? param.min : Math.min(0, 2 * value);
  let max = Number.isFinite(param.max) ? param.max : Math.max(0, 2 * value);
  if (max <= min) max = min + 10 * step;
  return { min, max, step };
}

// A slider's number as the script would write it: no more decimals than the step has.
export function formatValue(value, step) {
  const places = Math.min(12, Math.max(0, Math.ceil(-Math.log10(step) - 1e-9)));
  return Number(value).toFixed(places);
}
