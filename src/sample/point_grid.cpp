// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/point_grid.h"

namespace ramiform::sample_detail {

PointGrid::PointGrid(const Aabb& box, double radius) : r2_(radius * radius) {
  if (!(radius > 0.0) || box.isEmpty()) return;
  grid_ = VoxelGrid(box, radius);
  // A dense head array of 2^24 cells costs 64 MiB; past that, tiny radii in large boxes would
  // allocate memory for cells that stay empty.
  dense_ = grid_.size() <= (std::size_t{1} << 24);
  if (dense_) head_.assign(grid_.size(), -1);
  active_ = true;
}

bool PointGrid::cell_has_near(std::size_t cell, const Vec3& p) const {
  if (dense_) {
    for (std::int32_t q = head_[cell]; q >= 0; q = next_[static_cast<std::size_t>(q)]) {
      if ((points_[static_cast<std::size_t>(q)] - p).squaredNorm() < r2_) return true;
    }
  } else if (const auto it = sparse_.find(cell); it != sparse_.end()) {
    for (const std::uint32_t q : it->second) {
      if ((points_[q] - p).squaredNorm() < r2_) return true;
    }
  }
  return false;
}

bool PointGrid::has_near(const Vec3& p) const {
  if (!active_) return false;
  // Cells are r wide, so every point within r of p lies in the 27 cells around p's cell.
  const IndexBox b =
      neighbourhood(grid_, grid_.coord(p.x(), 0), grid_.coord(p.y(), 1), grid_.coord(p.z(), 2), 1);
  for (std::int64_t k = b.lo[2]; k < b.hi[2]; ++k) {
    for (std::int64_t j = b.lo[1]; j < b.hi[1]; ++j) {
      for (std::int64_t i = b.lo[0]; i < b.hi[0]; ++i) {
        if (cell_has_near(grid_.index(i, j, k), p)) return true;
      }
    }
  }
  return false;
}

void PointGrid::add(const Vec3& p) {
  if (!active_) return;
  const std::size_t c =
      grid_.index(grid_.coord(p.x(), 0), grid_.coord(p.y(), 1), grid_.coord(p.z(), 2));
  const auto id = static_cast<std::int32_t>(points_.size());
  points_.push_back(p);
  if (dense_) {
    next_.push_back(head_[c]);
    head_[c] = id;
  } else {
    sparse_[c].push_back(static_cast<std::uint32_t>(id));
  }
}

}  // namespace ramiform::sample_detail
