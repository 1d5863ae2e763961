// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// 3-D Delaunay tetrahedralization by incremental insertion (Bowyer 1981, Watson 1981) with
/// exact geometric predicates, for the bounding point set of the tetrahedral polygonizer.
///
/// Points are inserted in a biased randomized order (rounds of doubling size, each in Morton
/// order; fixed seed) inside a large enclosing tetrahedron; each one is
/// located by a visibility walk from the last tetrahedron made (which terminates on a Delaunay
/// tetrahedralization for any visiting order, Edelsbrunner 1990), its cavity (the tetrahedra
/// whose circumsphere holds it strictly) is found by a breadth-first search over face
/// neighbours, and the cavity is replaced by the cone from the point to its boundary.
///
/// The orientation and in-sphere tests are exact: a floating-point evaluation with a forward
/// error bound decides when it can (Shewchuk 1997, "Adaptive precision floating-point
/// arithmetic and fast robust geometric predicates", §4), otherwise the same determinant is
/// evaluated exactly in floating-point expansion arithmetic (the same paper, §2). So the result
/// is a valid tetrahedralization for any input, however close to degenerate; with points in
/// general position it is the unique Delaunay tetrahedralization.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/types.h"

namespace ramiform::detail {

/// Sign (-1, 0, +1) of the orientation of (a, b, c, d): +1 when d lies on the side of the plane
/// through a, b, c towards which (b - a) x (c - a) points, i.e. det[b - a, c - a, d - a] > 0.
[[nodiscard]] int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Sign of the in-sphere test: +1 when e lies strictly inside the sphere through a, b, c, d,
/// -1 outside, 0 on it; (a, b, c, d) must be positively oriented (orient3d > 0).
[[nodiscard]] int insphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                           const Vec3& e);

/// How many predicate calls the floating-point filter could not decide (process-wide counter,
/// for tests and statistics).
[[nodiscard]] std::uint64_t exact_predicate_calls();

struct DelaunayResult {
  /// Tetrahedra over the input points' indices, each with its indices ascending, the list
  /// sorted; tetrahedra touching the enclosing tetrahedron's corners are left out.
  std::vector<std::array<std::uint32_t, 4>> tets;
  /// neighbors[4 t + k]: the tetrahedron across the face of tets[t] opposite its corner k, or
  /// UINT32_MAX on the boundary.
  std::vector<std::uint32_t> neighbors;
  std::size_t duplicate_points = 0;  ///< points equal to an earlier one (left out)
  /// Points added on required edges (their midpoints, recursively), numbered from
  /// points.size() on in `tets`.
  std::vector<Vec3> steiner_points;
  /// Pieces of required edges that are still not edges after the last round (see
  /// delaunay_tetrahedralize).
  std::size_t missing_edges = 0;
};

/// Delaunay tetrahedralization of `points` (finite coordinates; at least 4 affinely independent
/// points for a non-empty result). Deterministic; single-threaded.
///
/// Every segment of `required_edges` (pairs of indices into `points`) is made a union of edges
/// of the result, as a conforming Delaunay tetrahedralization does: a segment that is not an
/// edge is split at its midpoint, which is inserted (a Steiner point), and the halves are
/// checked again, round after round until every piece is an edge. Segments meeting at a small
/// angle could be split without end; after kRecoveryRounds rounds the pieces still missing are
/// counted in `missing_edges` and left.
/// The insertion is sequential; the final renumbering runs on `ctx`'s threads (nullptr: all
/// cores). The result does not depend on the thread count.
[[nodiscard]] DelaunayResult delaunay_tetrahedralize(
    const std::vector<Vec3>& points,
    const std::vector<std::array<std::uint32_t, 2>>& required_edges = {},
    const Context* ctx = nullptr);

/// Rounds of midpoint splitting for required edges: a piece can become 1/2^kRecoveryRounds of
/// its segment.
constexpr int kRecoveryRounds = 8;

}  // namespace ramiform::detail
