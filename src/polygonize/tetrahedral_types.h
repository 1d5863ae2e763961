// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the data the steps of the tetrahedral polygonizer (tetrahedral.cpp) hand on to each
// other. The steps follow Zhu, Guo & Jin 2013, "Efficient polygonization of tree trunks modeled
// by convolution surfaces", §3–5; include/ramiform/polygonize/tetrahedral.h lists them.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform::detail::tets {

/// A tetrahedron: four point indices, ascending (as delaunay_tetrahedralize returns them).
using Tet = std::array<std::uint32_t, 4>;
/// The corner positions of a tetrahedron, in the order of its point indices.
using TetPoints = std::array<Vec3, 4>;
/// "No tetrahedron / no point": a missing face neighbour, an unassigned id.
constexpr std::uint32_t kNone = UINT32_MAX;

/// The bounding point set of step 1 (§3.1 and the auxiliary points of §5).
struct BoundingPoints {
  std::vector<Vec3> points;
  std::vector<double> sizes;               ///< per point, the local cross-section half size
  std::vector<std::uint32_t> node_points;  ///< per skeleton node, the index of its own point
  /// Consecutive points on the skeleton's axis (a node's own point, the stations' centres, the
  /// next node's point), for every edge: they must be joined by edges of the tetrahedralization.
  std::vector<std::array<std::uint32_t, 2>> axis_pairs;
  std::size_t gap_points = 0;  ///< of `points`, the ones placed in gaps between branches
  std::size_t crotch_points = 0;  ///< of `points`, the ones placed in forks' crotches
};

/// The tetrahedralization of step 2 over the (jittered) bounding points.
struct Tetrahedralization {
  /// [bounding points | the 8 far box corners | Steiner points on the axis].
  std::vector<Vec3> points;
  std::size_t real_points = 0;  ///< how many bounding points lead `points`
  std::vector<Tet> tets;        ///< Delaunay tetrahedra, sorted (delaunay.h)
  /// neighbors[4 t + k]: the tetrahedron across the face of tets[t] opposite corner k, or kNone.
  std::vector<std::uint32_t> neighbors;

  /// The corner positions of tets[t].
  [[nodiscard]] TetPoints corners(std::size_t t) const {
    const Tet& c = tets[t];
    return {points[c[0]], points[c[1]], points[c[2]], points[c[3]]};
  }
};

/// One marching-tetrahedra polygon: a triangle or a quad (cyclic order), oriented outward, over
/// record indices (crossing edges).
struct Polygon {
  std::array<std::uint32_t, 4> record{};
  bool quad = false;
};

/// What steps 3 to 5 extract: polygons over `records`, and the crossing edges they refer to,
/// each (global id of the inside lattice point) << 32 | (that of the outside one), possibly
/// repeated (neighbouring region tetrahedra share crossing edges on their common faces).
struct Extraction {
  std::vector<Polygon> polygons;
  std::vector<std::uint64_t> records;
};

/// The smallest box holding the four corners.
[[nodiscard]] inline Aabb box_of(const TetPoints& t) {
  Aabb box;
  for (const Vec3& p : t) box.extend(p);
  return box;
}

}  // namespace ramiform::detail::tets
