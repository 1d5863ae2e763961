// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: what the tetrahedral polygonizer checks before it does any work.

#include <cstddef>

#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::detail::tets {

/// Throws InvalidArgument naming the first option out of its range (tetrahedral.h).
void validate_options(const TetrahedralOptions& options);

/// Throws InvalidArgument, naming the node or edge, for a skeleton the bounding point set cannot
/// resolve: a node whose cross-section would vanish in the rounding of its coordinates (radius
/// below 1e-11 of its largest coordinate), radii or coordinates outside [1e-50, 1e50] (where the
/// exact predicates of delaunay.h could underflow or overflow), or more than 2^24 cross-sections
/// in all. `skeleton` must be valid (validate()).
void validate_resolution(const Skeleton& skeleton, const TetrahedralOptions& options);

/// Throws ResourceLimit when `points` bounding points at `options.levels` would need more memory
/// than memory_budget(ctx) (about 600 * 4^levels bytes per point at the peak); does nothing
/// where the budget is unknown.
void check_memory(std::size_t points, const TetrahedralOptions& options, const Context* ctx);

}  // namespace ramiform::detail::tets
