// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: a background grid of accepted points that answers "is some
/// point closer than r to p?" by looking at the 3x3x3 cells of edge r around p — the standard
/// grid of Poisson-disk dart throwing.

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "ramiform/core/geometry.h"
#include "sample/voxel_grid.h"

namespace ramiform::sample_detail {

/// Points in cubic cells of edge `radius` over a box. Up to 2^24 cells the cells are a dense
/// array of linked lists; beyond, a hash map from cell index to the points in it. Points
/// outside the box are filed in the nearest boundary cell, so queries stay exact for them.
class PointGrid {
 public:
  /// An inactive grid (every query false, add() ignored) when `radius` is not > 0 or the box
  /// is empty.
  PointGrid(const Aabb& box, double radius);

  /// True when queries and insertions are live.
  [[nodiscard]] bool is_active() const { return active_; }
  /// True when the cells are a dense array (false: a hash map).
  [[nodiscard]] bool is_dense() const { return dense_; }

  /// True when some stored point lies strictly closer than the radius to p.
  [[nodiscard]] bool has_near(const Vec3& p) const;

  /// Stores p.
  void add(const Vec3& p);

 private:
  [[nodiscard]] bool cell_has_near(std::size_t cell, const Vec3& p) const;

  double r2_ = 0.0;
  bool active_ = false;
  bool dense_ = true;
  VoxelGrid grid_;
  std::vector<std::int32_t> head_;  ///< dense: first point of each cell, -1 when none
  std::vector<std::int32_t> next_;  ///< dense: next point of the same cell, -1 at the end
  std::unordered_map<std::size_t, std::vector<std::uint32_t>> sparse_;
  std::vector<Vec3> points_;
};

}  // namespace ramiform::sample_detail
