// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Consistently oriented point normals (Hoppe, DeRose, Duchamp, McDonald & Stuetzle 1992,
/// "Surface reconstruction from unorganized points", SIGGRAPH, §3.2 tangent planes by principal
/// component analysis over the k nearest neighbours, §3.3 consistent orientation by propagation
/// along a minimum spanning tree of the neighbour graph with edge cost 1 - |n_i · n_j|), with the
/// consistency measure of König & Gumhold 2009, "Consistent propagation of normal orientations
/// in point clouds" (VMV), §3: n_i · n_j is replaced by n_i · n_j', n_j' = n_j - 2 (n_j · e) e the
/// normal reflected in the plane normal to the edge's unit direction e. It is n_i · n_j between
/// neighbours on one tangent plane, and +1 for consistent normals on any circle through both
/// points, across a thin sheet or a narrow gap, where the plain product is about -1 (and Hoppe's
/// propagation flips).
///
/// The neighbour graph joins every point to its k nearest neighbours (symmetrized). In each
/// connected component the propagation starts at the point with the largest x (ties: the lowest
/// index), whose normal is made to point towards +x (on a closed surface the outward normal at
/// the extreme point in x has a positive x component), and visits the minimum spanning tree in
/// Prim's order (ties by cost, then index), flipping each new point's normal when its measure with
/// its tree parent's is negative. Neighbours, costs and ties are exact functions of the input, so
/// the result does not depend on the thread count.
///
/// Weak on tubes and sheets not much thicker than the neighbour spacing (e.g. the cow's tail with
/// 20,000 points: 138 of the 20,000 given face normals come out flipped; estimated normals have
/// PCA errors there as well).

#include <cstddef>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"

namespace ramiform {

/// Options of normal estimation and orientation.
struct NormalOptions {
  int neighbours = 10;  ///< k of the k-nearest-neighbour graph (and of PCA), 3..256
};

/// What orient_normals did.
struct NormalReport {
  std::size_t estimated = 0;   ///< normals estimated by PCA (all points, or 0 when given)
  std::size_t flipped = 0;     ///< given normals whose direction was reversed
  std::size_t components = 0;  ///< connected components of the neighbour graph
};

/// Returns `points` (same positions, same order) with unit, consistently outward-oriented
/// normals.
///
/// - Without normals: estimates each by PCA over the point and its k nearest neighbours (the
///   eigenvector of the smallest eigenvalue of their covariance), then orients them by
///   propagation; `report->estimated` = point count.
/// - With normals: normalizes them and runs the same propagation (the given directions only
///   decide the costs of the graph). A piece of the cloud whose normals mostly disagree with
///   the propagation is inverted as a whole and reversed; after that, a normal is reversed only
///   where the propagation disagrees with it and so does its neighbourhood (the sum of its
///   reflected consistency with its neighbours' normals is negative). Scattered flipped normals
///   are turned back, a fully inverted cloud comes out outward, and correct normals on a tube
///   as thin as the neighbour spacing, where the propagation alone goes wrong, are kept.
///   `report->flipped` counts the normals reversed.
///
/// Needs at least neighbours + 1 points (`neighbours` is lowered to points - 1 when fewer, with
/// at least 3 points). Throws InvalidArgument for a bad `neighbours`, fewer than 3 points, a
/// normal count that is neither 0 nor the point count, and naming "point K" (K the 0-based
/// index, i.e. the line number minus one in a text file without comments) for a non-finite
/// position or a zero or non-finite normal. Runs on `ctx`'s threads and checks it for
/// cancellation.
[[nodiscard]] PointSet orient_normals(const PointSet& points, const NormalOptions& options = {},
                                      NormalReport* report = nullptr, const Context* ctx = nullptr);

}  // namespace ramiform
