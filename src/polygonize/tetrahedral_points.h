// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: step 1 of the tetrahedral polygonizer, the bounding point set that follows the
// skeleton (Zhu, Guo & Jin 2013, "Efficient polygonization of tree trunks modeled by
// convolution surfaces", §3.1, and the auxiliary points of §5).

#include <vector>

#include "polygonize/tetrahedral_types.h"
#include "ramiform/core/context.h"
#include "ramiform/field/field.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::detail::tets {

/// The bounding point set of a valid skeleton: every node's own point; a square cross-section
/// of edge `section_scale` x radius at forks, tips, isolated nodes (a cube there) and at the
/// nodes of a chain where it bends, changes radius or runs `station_spacing` radii; a second
/// square and a cap point beyond every tip; the auxiliary points of §5 on both sides of the
/// plane of every pair of branches at a fork (with `options.crotch_points`, three more in the
/// crotch of every pair meeting at less than 110°); and a square with its centre every
/// `station_spacing` radii along each edge. Points are numbered node by node, then edge by edge.
/// The gap points are searched in parallel on ctx's threads (the set does not depend on them);
/// with `field` (the surface to be meshed) a gap cross whose middle lies inside the surface
/// moves to where the field across the gap is least, if that is outside.
[[nodiscard]] BoundingPoints bounding_points(const Skeleton& skeleton,
                                             const TetrahedralOptions& options,
                                             const Context* ctx = nullptr,
                                             const Field* field = nullptr);

/// Moves every point by a deterministic pseudo-random offset of at most kJitter of its local
/// cross-section half size per axis (fixed seed), so that Delaunay sees no cospherical sets (the
/// squares are), then appends the 8 corners of a box reaching half the skeleton's diagonal
/// beyond its bounding box, so that the hull lies far outside. Returns the points.
[[nodiscard]] std::vector<Vec3> jitter_and_enclose(BoundingPoints& set, const Skeleton& skeleton);

/// Jitter of the bounding points, relative to their cross-section half size.
constexpr double kJitter = 1e-3;

}  // namespace ramiform::detail::tets
