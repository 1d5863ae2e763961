// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: Lane and Prusinkiewicz's method in 3-D (Lane & Prusinkiewicz
/// 2002, *Generating spatial distributions for multilevel models of plant communities*, Graphics
/// Interface), as Kochhar 2010, *Application of implicit methods to the interactive modeling of
/// trees* (M.Sc. thesis, University of Calgary), uses it in §5.2.2, §6.1 and §6.2.3: a
/// piecewise-constant pdf on a voxel grid, sampled by inverse CDF, multiplied by a radial kernel
/// around every accepted point.

#include <cstddef>
#include <cstdint>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/sample/point_sets.h"
#include "sample/common.h"
#include "sample/field_cache.h"

namespace ramiform::sample_detail {

/// What one run of Lane's method keeps and when it stops.
struct LaneSpec {
  Target target;
  LaneKernel kernel;
  std::size_t grid = 64;  ///< voxels along the box's longest axis
  bool prune = true;      ///< start the pdf at 0 in voxels the field's bound() excludes
  std::size_t count = 0;
  std::size_t max_attempts = 0;
  const FieldCache* cache = nullptr;  ///< optional §6.2.2 cache (§6.2.3); not owned
};

/// Up to spec.count points in the target set, drawn sequentially from Rng(seed) (the pdf
/// changes after each point); updates st.attempts and st.saturated (also when the pdf's total
/// reaches 0).
[[nodiscard]] PointSet run_lane(const Field& field, const Aabb& box, const LaneSpec& spec,
                                std::uint64_t seed, Context* ctx, SampleStats& st);

}  // namespace ramiform::sample_detail
