// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: step 2 of the tetrahedral polygonizer (tetrahedral.h), the Delaunay
// tetrahedralization of the bounding point set and the region of it that the skeleton bounds.
// Zhu, Guo & Jin 2013, "Efficient polygonization of tree trunks modeled by convolution
// surfaces", §3.2.1, mesh a
// skeleton-bounded polyhedron with TetGen (GPL); here the region is a set of Delaunay tetrahedra
// near the skeleton (delaunay.h), which is conforming as every subset of a tetrahedralization is.

#include <vector>

#include "polygonize/tetrahedral_types.h"
#include "ramiform/core/context.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::detail::tets {

/// Delaunay tetrahedralization of `points` (`real_points` bounding points, then the far box's
/// 8 corners) in which every pair of `axis_pairs` is joined by edges: a pair that is not an
/// edge gets Steiner points on the axis, appended to the points. Fills the stats'
/// `axis_points_added`, `axis_edges_missing` and `delaunay_tets`. Throws Failure when bounding
/// points coincide (the jitter makes them distinct, so this means a skeleton the checks missed).
[[nodiscard]] Tetrahedralization tetrahedralize(
    std::vector<Vec3> points, std::size_t real_points,
    const std::vector<std::array<std::uint32_t, 2>>& axis_pairs, const Context* ctx,
    TetrahedralStats& stats);

/// Per tetrahedron of `tz`, 1 when it belongs to the initial region: its centroid lies within
/// the cross-sections' reach (section_scale / sqrt 2 radii, plus 5 %) of an edge or an
/// isolated node, or one of its corners is a node's own point (`node_points`), or it holds a
/// node's exact position. Tetrahedra with a far box corner are left out.
[[nodiscard]] std::vector<char> initial_region(const Skeleton& skeleton,
                                               const Tetrahedralization& tz,
                                               const std::vector<std::uint32_t>& node_points,
                                               const TetrahedralOptions& options,
                                               const Context* ctx);

}  // namespace ramiform::detail::tets
