// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: the candidate region — the cells of a box that the field's
/// bound() does not exclude from a target set, drawn from in proportion to their volume.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/core/random.h"
#include "ramiform/field/field.h"
#include "sample/common.h"

namespace ramiform::sample_detail {

/// One cell of a Region.
struct Cell {
  Aabb box;
  bool full = false;  ///< every point of the cell is in the target set
};

/// The bound-pruned cells of a box, with their cumulative volumes for uniform drawing.
class Region {
 public:
  /// Cuts `box` into cubes of edge longest side / `resolution` and keeps the cells the bound
  /// does not exclude (full boxes are kept whole). `resolution` 0: one partial cell, the whole
  /// box (no pruning). `top` is the side of the descent's parallel blocks (voxels). An empty or
  /// flat box gives an empty region.
  Region(const Field& field, const Aabb& box, const Target& target, int resolution,
         const Context* ctx, std::int64_t top = 8);

  /// True when no cell of positive volume is left.
  [[nodiscard]] bool is_empty() const { return cells_.empty() || !(volume_ > 0.0); }
  /// Total volume of the cells.
  [[nodiscard]] double volume() const { return volume_; }
  /// Number of cells.
  [[nodiscard]] std::size_t cell_count() const { return cells_.size(); }

  /// A point uniform in the union of the cells (four draws from `rng`: the cell, then three
  /// for the point in it); `full` says whether its cell is full. Precondition: !is_empty().
  Vec3 draw(Rng& rng, bool& full) const;

 private:
  std::vector<Cell> cells_;
  std::vector<double> cdf_;  ///< cumulative volume, one per cell
  double volume_ = 0.0;
};

}  // namespace ramiform::sample_detail
