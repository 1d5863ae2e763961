// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: a cubic voxel grid over a box, and the bound-driven descent
/// that classifies its voxels against a target set (the space skipping of every sampler).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/core/parallel.h"
#include "ramiform/field/field.h"
#include "sample/common.h"

namespace ramiform::sample_detail {

/// Cubic voxels of edge `h` from `origin`, `n` voxels per axis (at least one), covering a box.
/// Voxel (i, j, k) has linear index i + n0 (j + n1 k).
struct VoxelGrid {
  Vec3 origin = Vec3::Zero();
  double h = 0.0;                          ///< voxel edge (model units)
  std::array<std::int64_t, 3> n{0, 0, 0};  ///< voxels per axis

  VoxelGrid() = default;
  /// The smallest grid of `cell`-sized voxels from box.min() that covers `box` (a relative
  /// slack of 1e-9 cells keeps an exact multiple from gaining a voxel).
  VoxelGrid(const Aabb& box, double cell) : origin(box.min()), h(cell) {
    const Vec3 size = box.sizes();
    for (int a = 0; a < 3; ++a) {
      n[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(size[a] / h - 1e-9)));
    }
  }
  /// Number of voxels.
  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(n[0] * n[1] * n[2]); }
  /// The box of voxels [i0, i1) x [j0, j1) x [k0, k1).
  [[nodiscard]] Aabb box(std::int64_t i0, std::int64_t j0, std::int64_t k0, std::int64_t i1,
                         std::int64_t j1, std::int64_t k1) const {
    return Aabb(origin + h * Vec3(double(i0), double(j0), double(k0)),
                origin + h * Vec3(double(i1), double(j1), double(k1)));
  }
  /// The linear index of voxel (i, j, k).
  [[nodiscard]] std::size_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>(i + n[0] * (j + n[1] * k));
  }
  /// The voxel coordinate of x along axis a, clamped to the grid.
  [[nodiscard]] std::int64_t coord(double x, int a) const {
    const auto c = static_cast<std::int64_t>(std::floor((x - origin[a]) / h));
    return std::clamp<std::int64_t>(c, 0, n[a] - 1);
  }
};

/// A box of voxel indices: lo inclusive, hi exclusive, per axis.
struct IndexBox {
  std::array<std::int64_t, 3> lo;
  std::array<std::int64_t, 3> hi;  ///< exclusive
};

/// The non-empty halves-by-halves children of `b` (up to 8), x fastest, then y, then z; the
/// lower half of an odd extent is the larger one.
[[nodiscard]] std::vector<IndexBox> octants(const IndexBox& b);

/// Top-level block `t` of side `top` voxels (x fastest) of a grid with `blocks` blocks per axis,
/// cut to the grid.
[[nodiscard]] IndexBox top_block(const VoxelGrid& grid, const std::array<std::int64_t, 3>& blocks,
                                 std::size_t t, std::int64_t top);

/// Recursively classifies index boxes of `grid` against `target` by field.bound(): calls
/// `emit(IndexBox, CellClass, out)` for every non-empty leaf (a full box at any level, or a
/// single partial voxel). Top-level blocks of `top` voxels a side run in parallel; each block's
/// emits go to its own vector, returned in block order, so the result does not depend on the
/// thread count.
template <class Leaf>
std::vector<std::vector<Leaf>> descend(
    const Field& field, const VoxelGrid& grid, const Target& target,
    const std::function<void(const IndexBox&, CellClass, std::vector<Leaf>&)>& emit,
    const Context* ctx, std::int64_t top = 8) {
  std::array<std::int64_t, 3> blocks{};
  for (int a = 0; a < 3; ++a) blocks[a] = (grid.n[a] + top - 1) / top;
  const auto count = static_cast<std::size_t>(blocks[0] * blocks[1] * blocks[2]);
  std::vector<std::vector<Leaf>> out(count);
  std::function<void(const IndexBox&, std::vector<Leaf>&)> rec = [&](const IndexBox& b,
                                                                     std::vector<Leaf>& o) {
    const CellClass c = classify(
        field.bound(grid.box(b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2])), target);
    if (c == CellClass::kEmpty) return;
    const bool single = b.hi[0] - b.lo[0] == 1 && b.hi[1] - b.lo[1] == 1 && b.hi[2] - b.lo[2] == 1;
    if (c == CellClass::kFull || single) {
      emit(b, c, o);
      return;
    }
    for (const IndexBox& child : octants(b)) rec(child, o);
  };
  parallel::for_each(
      count, 1, [&](std::size_t t) { rec(top_block(grid, blocks, t, top), out[t]); }, ctx);
  return out;
}

/// Calls `fn(i, j, k)` for every voxel of `b`, x fastest.
template <class Fn>
void for_each_voxel(const IndexBox& b, Fn&& fn) {
  for (std::int64_t k = b.lo[2]; k < b.hi[2]; ++k) {
    for (std::int64_t j = b.lo[1]; j < b.hi[1]; ++j) {
      for (std::int64_t i = b.lo[0]; i < b.hi[0]; ++i) fn(i, j, k);
    }
  }
}

/// The voxels of `grid` within `r` voxels of (ci, cj, ck) along every axis, cut to the grid.
[[nodiscard]] IndexBox neighbourhood(const VoxelGrid& grid, std::int64_t ci, std::int64_t cj,
                                     std::int64_t ck, std::int64_t r);

}  // namespace ramiform::sample_detail
