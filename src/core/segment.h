// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the point of a segment nearest to a point.

#include <algorithm>

#include "ramiform/core/types.h"

namespace ramiform::detail {

/// The parameter t in [0, 1] of the point a + t (b - a) of segment [a, b] nearest to p (0 when
/// the segment is a point).
inline double segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double dd = d.squaredNorm();
  return dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
}

}  // namespace ramiform::detail
