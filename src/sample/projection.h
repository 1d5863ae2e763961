// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: near-surface projection (NearSurfaceOptions::Method::kProject,
/// not in the thesis) — a uniform sample of a wider band |f - c| < W / 2 around the band's
/// centre c, compressed onto the band (iso - epsilon, iso) by Newton steps along the gradient.

#include <cstddef>
#include <cstdint>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/sample/point_sets.h"
#include "sample/common.h"
#include "sample/region.h"

namespace ramiform::sample_detail {

/// Top-level block side (voxels) of the projection region's descent: a band meets few of the
/// 8-voxel blocks the other samplers start from, and every block costs a bound() call, so
/// larger blocks need about 4x fewer calls here; 32 still gives dozens of parallel tasks.
constexpr std::int64_t kProjectTop = 32;

/// What one projection run keeps and when it stops.
struct ProjectSpec {
  Target band;            ///< the band (iso - epsilon, iso)
  double width = 0.0;     ///< W: the wider band is |f - c| < W / 2, c the band's centre
  double max_step = 0.0;  ///< longest Newton step (model units)
  double min_distance = 0.0;
  std::size_t count = 0;
  std::size_t max_attempts = 0;
  std::uint64_t stream = 0;  ///< sub-stream index of the candidate blocks
};

/// The automatic W: 0.2 `cell` times the median |grad f| of pilot points whose linearized
/// distance |f - c| / |grad f| to the band's centre level is below one cell, at most the
/// distance from c to the smallest and to the largest pilot value (a wider band reaching a flat
/// value, such as the 0 outside compact-support primitives, would hold whole regions), and at
/// least epsilon (epsilon when no pilot point qualifies: then projection is rejection).
[[nodiscard]] double automatic_project_width(const Field& field, const Aabb& box,
                                             const Target& band, double cell, std::uint64_t seed,
                                             Context* ctx);

/// The wider band |f - c| < W / 2 around the band's centre c.
[[nodiscard]] Target wide_band(const Target& band, double width);

/// Up to spec.count band points from candidates of `region` (a pruning of `box` against the
/// wider band), accepted in candidate order; updates st.attempts and st.saturated.
[[nodiscard]] PointSet run_project(const Field& field, const Region& region, const Aabb& box,
                                   const ProjectSpec& spec, std::uint64_t seed, Context* ctx,
                                   SampleStats& st);

}  // namespace ramiform::sample_detail
