// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: the field cache of Kochhar 2010, *Application of implicit
/// methods to the interactive modeling of trees* (M.Sc. thesis, University of Calgary), §6.2.2 —
/// cubes along the target set with the field's values at their corners, so that most candidates
/// are rejected from a trilinear interpolation without evaluating the field.

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "sample/common.h"
#include "sample/voxel_grid.h"

namespace ramiform::sample_detail {

/// Hashed cubes of edge `cell` that the field's bound() does not exclude from the target set.
/// Full cubes accept without evaluation; partial cubes store their eight corner values.
class FieldCache {
 public:
  /// What a candidate needs.
  enum class Verdict {
    kReject,    ///< no target point can be there (outside every cube, or far from the band)
    kEvaluate,  ///< the interpolated value is near the target: evaluate the field
    kAccept,    ///< the cube is full: every point is in the target
  };

  /// Builds the cubes over `box`. `tolerance` is the slack around the target that an
  /// interpolated value may miss by and still be evaluated; 0 picks, per cube, the larger of
  /// the target's width and a quarter of the cube's corner range.
  FieldCache(const Field& field, const Aabb& box, double cell, const Target& target,
             double tolerance, const Context* ctx);

  /// Number of cubes kept.
  [[nodiscard]] std::size_t cube_count() const { return cubes_.size(); }

  /// The verdict for candidate p (a point on the far face of the grid belongs to the last cube).
  [[nodiscard]] Verdict classify(const Vec3& p) const;

  /// True when the box overlaps some cached cube (for Lane's grid initialization, §6.2.3).
  [[nodiscard]] bool overlaps(const Aabb& box) const;

 private:
  struct Cube {
    std::array<double, 8> corner{};  ///< x fastest, then y, then z
    double slack = 0.0;
    bool full = false;
  };
  struct Leaf {
    std::size_t key;  ///< the cube's voxel index
    bool full;
  };

  [[nodiscard]] std::vector<Leaf> find_cubes(const Field& field, const Target& target,
                                             const Context* ctx) const;
  void fill_corners(const Field& field, const std::vector<Leaf>& leaves, const Context* ctx);
  [[nodiscard]] static double interpolate(const Cube& cube, const Vec3& t);

  VoxelGrid grid_;
  Target target_;
  double tolerance_;
  std::vector<Cube> cubes_;
  std::unordered_map<std::size_t, std::uint32_t> index_;  ///< voxel index -> cube
};

}  // namespace ramiform::sample_detail
