// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the 2-D distance of the curve-based surfaces (sweep.h) to a flattened planar curve,
// or to the region it bounds when closed.

#include <cstddef>
#include <vector>

#include <Eigen/Geometry>

#include "ramiform/core/types.h"
#include "ramiform/field/curves.h"

namespace ramiform::detail::sweep {

using Box2 = Eigen::AlignedBox2d;

/// The Euclidean distance to a polyline (open) or to the region a closed polygon bounds, by
/// the even-odd rule (so self-overlapping polygons alternate inside and outside). Segments are
/// grouped in blocks of consecutive segments with their bounding boxes, which prune both the
/// closest-segment search and the crossing count.
class Region2 {
 public:
  /// `vertices` in order (at least 1; 2 or more for a closed polygon); `closed` joins the last
  /// vertex to the first.
  Region2(std::vector<Vec2> vertices, bool closed);

  /// d(q): 0 inside a closed region, else the distance to the nearest segment; when `grad` is
  /// set, the gradient of d (a unit vector from the nearest point towards q outside, 0 inside
  /// and on the curve).
  [[nodiscard]] double distance(const Vec2& q, Vec2* grad) const;

  /// The largest |vertex|, the distance of the farthest vertex from the origin.
  [[nodiscard]] double extent() const { return extent_; }
  /// The bounding box of the segments.
  [[nodiscard]] const Box2& box() const { return box_; }
  [[nodiscard]] const std::vector<Vec2>& vertices() const { return v_; }
  [[nodiscard]] bool closed() const { return closed_; }

 private:
  struct Block {
    Box2 box;
    std::size_t begin, end;  // segments [begin, end)
  };
  std::vector<Vec2> v_;
  bool closed_;
  std::vector<Block> blocks_;
  Box2 box_;
  double extent_ = 0;
};

/// The region of `curve` flattened with chord error `tolerance_option` (0: the default relative
/// to the curve's extent, sweep_common.h).
[[nodiscard]] Region2 make_region(const Curve2& curve, double tolerance_option);

}  // namespace ramiform::detail::sweep
