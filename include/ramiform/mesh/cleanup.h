// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Cleanup of polygonizer output: needles, and specks (remove_small_pieces()). Marching tetrahedra (and marching cubes) make long,
/// narrow triangles wherever the surface passes close to a grid corner: the vertices on the
/// edges around that corner crowd together (Zhu, Guo & Jin 2013, "Efficient polygonization of tree
/// trunks modeled by convolution surfaces", §6, name this their method's weakness). clean_needles()
/// collapses the short edges of such triangles, each collapse on its own and only where it keeps
/// the mesh a closed, consistently oriented 2-manifold:
/// - link condition: the end points share exactly the two vertices opposite the edge, and
///   neither of those is left with fewer than three neighbours;
/// - no fold: no surviving triangle turns its normal by more than `max_normal_turn_deg` or
///   becomes degenerate;
/// - better: every changed triangle's smallest angle beats the needle's (after the first sweep:
///   the smallest angle around the removed end point before, which may be a worse neighbour's).
/// A needle whose short edge may not collapse (a cap, with one angle near 180 degrees) has its
/// longest edge flipped instead when that improves the smallest angle of the two triangles.
/// The kept end point stays where it was (a vertex already on the surface), so the surface is
/// not moved off the iso-surface.
///
/// Each sweep runs in rounds of blocks. The first round's blocks are runs of consecutive vertex
/// indices (polygonizers emit triangles cell by cell and number vertices by first use, so such a
/// run is a compact piece of surface), the second round's the cells of a coarse grid, and the
/// last round is the whole mesh. The blocks of a round run in parallel, each visiting its
/// needles in triangle order and taking only those whose end points and their neighbours all
/// lie in the block (such collapses and flips touch nothing outside it); the rest wait for the
/// next round. The result depends only on the mesh and the options, never on the thread count.

#include <cstddef>
#include <span>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"

namespace ramiform {

/// Options of clean_needles(); validated at entry (InvalidArgument naming the option).
struct NeedleCleanupOptions {
  /// A triangle is a needle when its smallest angle is below this (degrees, in (0, 60)).
  double min_angle_deg = 15.0;
  /// Largest turn of a surviving triangle's normal a collapse may cause (degrees, (0, 90]).
  double max_normal_turn_deg = 45.0;
  /// Only a needle's shortest edge shorter than this fraction of its longest edge may collapse
  /// (in (0, 1)); other needles (caps) can only have their longest edge flipped.
  double max_edge_ratio = 0.35;
  int passes = 3;  ///< sweeps over the candidates (>= 1); later sweeps catch new needles
  /// Also measure the angles afterwards (stats min/median_angle_after; costs two passes over
  /// the whole mesh, which callers that check the mesh anyway can skip).
  bool measure_after = true;
  /// Points that must stay on their side of the surface (the tetrahedral polygonizer passes the
  /// skeleton's nodes). A change is refused when one of them lies in the region swept between
  /// the old and the new triangles: the closed surface they form together has a winding
  /// number of +-1 there, and the mesh's winding number at the point would change by it.
  std::span<const Vec3> keep_sides;
};

/// What clean_needles() did, with the angle quality before and after.
struct NeedleCleanupStats {
  std::size_t collapsed_edges = 0;
  std::size_t removed_triangles = 0;
  std::size_t flipped_edges = 0;  ///< longest edges of caps flipped (counted in collapsed_edges too)
  double min_angle_before = 0, median_angle_before = 0;  ///< degrees
  double min_angle_after = 0, median_angle_after = 0;    ///< degrees (if measure_after)
};

/// Smallest and median corner angle of a mesh, degrees (0, 0 for an empty mesh). The median is
/// check_mesh()'s: the mean of the two middle angles for an even count.
struct AngleSummary {
  double min_deg = 0, median_deg = 0;
};
[[nodiscard]] AngleSummary angle_summary(const TriMesh& mesh, const Context* ctx = nullptr);

/// Collapses needle edges of `mesh` in place (see the file comment); unused vertices are
/// removed and the rest keep their relative order (with their normals, if the mesh has them).
/// `ctx` gives the thread count and cancellation (Cancelled): checked before the mesh is changed
/// and, while sweeps change it, between needles; a cancelled call leaves a valid mesh with the
/// changes made so far.
void clean_needles(TriMesh& mesh, const NeedleCleanupOptions& options = {},
                   NeedleCleanupStats* stats = nullptr, const Context* ctx = nullptr);

/// Removes the pieces (edge-connected triangle components) of `mesh` whose bounding box has a
/// diagonal below `min_diagonal`: the specks of a few grid cells that marching cubes leaves
/// where an implicit surface has a detail smaller than its cells (a lobe of an MPU's local
/// quadric off a hoof or a fingertip). Nothing is removed when every piece is that small. Unused
/// vertices go; the rest keep their relative order (with their normals). Returns how many pieces
/// were removed.
std::size_t remove_small_pieces(TriMesh& mesh, double min_diagonal);

}  // namespace ramiform
