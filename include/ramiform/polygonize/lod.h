// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Levels of detail: one watertight mesh per level from the same field, each made by the
/// tolerance mesher (refine.h) at its own tolerance or triangle budget, so that every level is
/// closed, oriented, in one piece per skeleton part and keeps every branch (a generic decimator
/// could open holes or drop twigs); budgets below the polygonizer's coarsest mesh are met by
/// coarsen.h's collapses, which keep all of that.

#include <cstddef>
#include <span>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// One level: a deviation tolerance (ToleranceOptions::tolerance) or a triangle budget.
struct LodLevel {
  double tolerance = 0;           ///< > 0: mesh to this tolerance (budget = 0)
  std::size_t max_triangles = 0;  ///< > 0: at most this many triangles (tolerance = 0)
};

/// What polygonize_lods() did for one level.
struct LodStats {
  ToleranceStats mesher;  ///< the tolerance mesher's figures for the kept mesh
  double tolerance = 0;   ///< the tolerance it was made at (a budget level's: the one found)
  int levels = 0;         ///< the base mesh's subdivision levels
  int attempts = 0;       ///< meshes made to find a budget level's tolerance (1 for a tolerance)
  std::size_t triangles = 0;
  /// > 0: the base mesh at 0 levels was over the budget, so coarsen_to_budget() took a mesh of
  /// this many triangles (that one, or the previous level's: `levels` and `tolerance` say
  /// which) down by `collapsed` edge collapses; `mesher.deviation` is then the coarsened mesh's
  /// measure and `mesher.reached` whether its p99 is within `tolerance`.
  std::size_t coarsened_from = 0;
  std::size_t collapsed = 0;
  double seconds_coarsen = 0;  ///< wall time of the coarsening and its measure
};

/// The skeleton with its chains (runs of degree-2 nodes) simplified by Douglas-Peucker: a chain
/// node is dropped when it lies within `tolerance` times the smaller end radius of the straight
/// line between the kept nodes around it and its radius within a third of the straight taper.
/// Roots, forks and tips stay; the kept nodes keep their positions and radii. For the
/// polygonizer's bounding structure at coarse levels of detail. Throws InvalidArgument for a
/// tolerance that is not > 0.
[[nodiscard]] Skeleton simplify_chains(const Skeleton& skeleton, double tolerance);

/// Throws InvalidArgument (naming the level) unless `levels` is a valid polygonize_lods() list:
/// not empty, all tolerances in ToleranceOptions' range or all budgets, finest first.
void validate_lod_levels(std::span<const LodLevel> levels);

/// The meshes of `levels`, finest first, made by polygonize_to_tolerance() with `base` (its
/// tolerance and max_triangles replaced by each level's). A tolerance level is meshed once. A
/// budget level searches the tolerance: starting from the previous level's (or `base`'s), it
/// remeshes (at most 5 times) with the tolerance scaled by the ratio of the triangle count to
/// the budget (the count of a refined mesh goes about as 1/tolerance), keeping the finest mesh
/// within the budget; when the base mesh alone is over the budget it drops to fewer base levels
/// (down to 0, not counted as attempts). A level whose mesh so found misses the tolerance is
/// replaced by the previous level's mesh coarsened to the budget when that measures a lower
/// deviation p99 (dropping base levels coarsens far more than the budget asks: on
/// archi_Tree_1, 300 k coarsened from 679 k has p99 0.12 local radii, the 133 k mesh at 0
/// levels 0.50); and when the mesh at 0 levels is still over the budget with nothing better,
/// that mesh is coarsened. Coarsening is by edge collapses that keep the mesh closed, oriented,
/// 2-manifold, of the same genus and components, on the surface and around every skeleton node
/// (coarsen_to_budget() with its default options). Each level's budget is also capped by the
/// previous level's triangle count, so counts never increase. Throws InvalidArgument when the
/// levels are empty, mix the two kinds, are out of range or not ordered finest first
/// (tolerances increasing, budgets decreasing), or when a budget is below what the collapses
/// can reach (naming the budget); otherwise as polygonize_to_tolerance().
[[nodiscard]] std::vector<TriMesh> polygonize_lods(const Field& field, const Skeleton& skeleton,
                                                   const ToleranceOptions& base,
                                                   std::span<const LodLevel> levels,
                                                   Context* ctx = nullptr,
                                                   std::vector<LodStats>* stats = nullptr);

}  // namespace ramiform
