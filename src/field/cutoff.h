// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the cut-off of infinite-support kernels, shared by the skeleton field and the radius
// fit (which must reproduce the field's values exactly).

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ramiform/core/portable_math.h"

namespace ramiform::detail {

/// The C1 fade window of an infinite-support kernel at v = (distance / cut-off distance)^2:
/// 1 up to v = 0.64 (tol::kFadeStart squared), a smoothstep to 0 at v = 1, 0 beyond.
inline double fade_of(double v) {
  if (v <= 0.64) return 1;
  if (v >= 1) return 0;
  const double s = (v - 0.64) / 0.36;
  return 1 - s * s * (3 - 2 * s);
}

/// Distance from a Cauchy segment primitive (kernel width s, length len) beyond which weight
/// times the upper bound of its integral, min(len / q^2, pi / (2 s q^(3/2))) with
/// q = 1 + s^2 d^2, stays below `level`; 0 when it never reaches `level`.
inline double cauchy_segment_reach(double s, double len, double weight, double level) {
  const double r_len = weight * len / level;                         // q^2 = r_len
  const double r_inf = weight * std::numbers::pi / (2 * s * level);  // q^(3/2) = r_inf
  const double q_len = std::sqrt(r_len);
  const double q_inf = pm::cbrt(r_inf * r_inf);
  const double q = std::min(q_len, q_inf);
  return q <= 1 ? 0.0 : std::sqrt(q - 1) / s;
}

}  // namespace ramiform::detail
