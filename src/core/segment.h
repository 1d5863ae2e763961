// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the point of a segment nearest to a point; the closest points of two segments.

#include <algorithm>
#include <utility>

#include "ramiform/core/types.h"

namespace ramiform::detail {

/// The parameter t in [0, 1] of the point a + t (b - a) of segment [a, b] nearest to p (0 when
/// the segment is a point).
inline double segment_parameter(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double dd = d.squaredNorm();
  return dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
}

/// The parameters (s on [p0, p1], t on [q0, q1]) of the closest points of two segments
/// (Ericson 2005, "Real-Time Collision Detection", §5.1.9); s starts at 0 where the segments are
/// parallel within `parallel` (denominator against a e). Both segments must have length.
inline std::pair<double, double> closest_parameters(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                                    const Vec3& q1, double parallel = 1e-12) {
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  const double c = d1.dot(r);
  const double b = d1.dot(d2);
  const double denom = a * e - b * b;
  double s = denom > parallel * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return {s, t};
}

}  // namespace ramiform::detail
