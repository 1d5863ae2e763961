// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the point-in-tetrahedron test with which refinement and triangle improvement keep
// the skeleton's nodes on their side of a moved vertex (a node inside a swept tetrahedron).

#include "ramiform/core/geometry.h"

namespace ramiform::detail {

/// Whether p lies in the closed tetrahedron (a, b, c, d); never for a flat one.
inline bool in_tetrahedron(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                           const Vec3& d) {
  const double v = (b - a).cross(c - a).dot(d - a);
  if (v == 0.0) return false;
  const double s = v > 0 ? 1.0 : -1.0;
  return s * (b - p).cross(c - p).dot(d - p) >= 0 && s * (p - a).cross(c - a).dot(d - a) >= 0 &&
         s * (b - a).cross(p - a).dot(d - a) >= 0 && s * (b - a).cross(c - a).dot(p - a) >= 0;
}

}  // namespace ramiform::detail
