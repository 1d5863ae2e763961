// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the index check every mesh/ entry point makes before touching positions, and the
// solid angle of a triangle (winding numbers, cleanup).

#include <cmath>
#include <numbers>

#include "ramiform/core/geometry.h"
#include "ramiform/core/portable_math.h"

namespace ramiform::detail {

/// Throws InvalidArgument, naming `who`, the triangle and the vertex, when a triangle refers to
/// a vertex that `mesh.positions` does not hold.
void check_triangle_indices(const TriMesh& mesh, const char* who);

/// Signed solid angle of triangle (a, b, c) seen from the origin, over 4 pi (van Oosterom and
/// Strackee 1983): positive when the triangle is counter-clockwise seen from the origin's side
/// opposite its normal, i.e. the origin is behind it.
inline double solid_angle_fraction(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm();
  const double lb = b.norm();
  const double lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return pm::atan2(num, den) / (2 * std::numbers::pi);
}

}  // namespace ramiform::detail
