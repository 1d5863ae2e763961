// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Basic geometric value types: `Vec3`, `Aabb`, `Interval`. Working precision is `double`.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace ramiform {

using Vec2 = Eigen::Vector2d;  ///< a texture coordinate (u, v)
using Vec3 = Eigen::Vector3d;  ///< a point or direction in model units
using Vec4 = Eigen::Vector4d;  ///< a tangent with its handedness (x, y, z, w = +-1), as glTF
using Mat3 = Eigen::Matrix3d;
using Affine3 = Eigen::Affine3d;

/// Axis-aligned box. A default-constructed box is empty (min > max); `extend` grows it.
using Aabb = Eigen::AlignedBox3d;

/// Closed interval [lo, hi] of field values; `lo > hi` never occurs for a valid bound.
struct Interval {
  double lo = 0.0;  ///< lower end
  double hi = 0.0;  ///< upper end

  /// True when `v` lies in [lo, hi].
  [[nodiscard]] bool contains(double v) const { return lo <= v && v <= hi; }
  /// True when the interval may contain a surface at `iso`, i.e. the field could take `iso` there
  /// with an inside (f > iso) and an outside (f <= iso) point: lo <= iso < hi.
  [[nodiscard]] bool straddles(double iso) const { return lo <= iso && iso < hi; }
};

/// Squared Euclidean distance between the closed box `b` and point `p` (0 inside the box).
inline double squared_distance(const Aabb& b, const Vec3& p) {
  const Vec3 d = (b.min() - p).cwiseMax(p - b.max()).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

/// Largest distance from `p` to any point of the non-empty box `b`.
inline double max_distance(const Aabb& b, const Vec3& p) {
  const Vec3 d = (p - b.min()).cwiseAbs().cwiseMax((p - b.max()).cwiseAbs());
  return d.norm();
}

/// Squared distance between two boxes (0 when they overlap).
inline double squared_distance(const Aabb& a, const Aabb& b) {
  const Vec3 d = (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

/// True when every coordinate of `p` is finite.
inline bool is_finite(const Vec3& p) { return p.allFinite(); }

}  // namespace ramiform
