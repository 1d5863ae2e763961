// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Refinement of a polygonizer's mesh towards a deviation tolerance. Zhu, Guo & Jin 2013
/// ("Efficient polygonization of tree trunks modeled by convolution surfaces", §4) refine the
/// whole lattice uniformly, 1:8 per level, so that each level multiplies the work by eight
/// everywhere although only thin or strongly curved parts need it. Here the surface mesh itself
/// is refined where it is far from the surface, in rounds:
///  1. every edge's midpoint gets the first-order distance |f - iso| / |grad f| to the surface
///     (one batch evaluation), relative to the local skeleton radius (mesh/deviation.h; the
///     smaller of its end points' radii); after the first round only the edges at the last
///     round's new vertices, and of those not the ones whose sag bound is within the tolerance
///     (`inherited`): the halves of a split edge and the edges joining two edge midpoints inside
///     a split triangle, parallel to its third edge at half its length, are taken to sag at most
///     half as much as the edge they halve or parallel (a chord of half the length sags about a
///     quarter as much); nor the edges at a vertex that step 4 left off the surface (splitting
///     them meets the same fold);
///  2. the edges whose midpoint lies farther than `edge_tolerance` radii (and which are longer
///     than `min_edge_radii` radii) are split, except those a `spare_area` lets stay (the ones
///     whose split would bring the least area within the tolerance, as long as the area they
///     leave beyond it, estimated from a quadratic chord, fits in that share of the mesh's
///     area over all rounds; polygonize_to_tolerance() spares a twentieth of the 1 % a p99
///     leaves in its first pass): the new
///     vertex is the midpoint taken onto the surface by Newton steps along the gradient (batched),
///     kept at the midpoint when the steps do not converge close by;
///  3. each triangle is replaced by 2, 3 or 4 triangles by the number of its split edges (the
///     quadrilateral of two splits along its shorter diagonal), in its own orientation, so the
///     mesh stays closed, consistently oriented and 2-manifold by construction;
///  4. a projected vertex goes half way back to its edge's midpoint, and then all the way (where
///     the split is flat, so nothing can fold), when one of its new triangles turns against its
///     parent triangle by more than `max_turn_deg` while some triangle of its fan lies farther
///     than `max_normal_deg` from the surface's outward normal at its centroid (a fan that
///     follows the surface is kept however far it turned: its parent stood across the surface),
///     or when the move would carry a protected point (the skeleton's nodes) across the surface
///     (the point lies in one of the tetrahedra swept by the vertex's fan).
///  5. after the rounds (`reproject`), the vertices step 4 left off the surface go onto it where
///     their fan, refined around them by the later rounds, now lets them (reproject_off_surface
///     in refine.cpp); then (`settle_rounds` times at most) rounds on the edges at the vertices
///     this brought onto the surface, whose fans stayed coarse while they were off, and the
///     same reprojection of what those rounds left off.
/// Rounds stop when no edge is split, after `max_rounds`, or when the next round would exceed
/// `max_triangles`. Deterministic: the result depends only on the inputs, never on the thread
/// count.

#include <cstddef>
#include <functional>
#include <span>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/polygonize/improve.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of refine_to_surface(); validated at entry (InvalidArgument naming the option).
struct RefineOptions {
  /// Split an edge whose midpoint lies farther than this from the surface, in local radii (> 0).
  double edge_tolerance = 0.05;
  /// Never split an edge shorter than this, in local radii (>= 0): its chord sags by less than
  /// L^2 / 8 r, so a midpoint still far from the surface is not one splitting can bring closer.
  /// polygonize_to_tolerance() sets it to sqrt(5 edge_tolerance) (0.5 at 0.05).
  double min_edge_radii = 0.25;
  int max_rounds = 6;                  ///< rounds of splitting (>= 0)
  /// No round may take the mesh beyond this; the memory budget (Context::max_memory, else the
  /// memory available) lowers it to budget / 256 bytes per triangle.
  std::size_t max_triangles = 20'000'000;
  double max_turn_deg = 80.0;          ///< largest turn of a new triangle's normal, (0, 180)
  /// A new triangle turning farther than max_turn_deg against its parent is still taken when
  /// every triangle of its vertex's fan lies within this angle of the surface's outward normal
  /// at its centroid (the parent stood across the surface), (0, 90).
  double max_normal_deg = 60.0;
  /// Share of the mesh's area, in [0, 0.01], that may stay farther from the surface than the
  /// edge tolerance: each round leaves unsplit the edges whose split would bring the least area
  /// within it, as long as the area they leave beyond it (estimated from their midpoints'
  /// distances) fits in what is left of this share. 0 splits every edge beyond the tolerance.
  double spare_area = 0.0;
  /// After the rounds, take the new vertices that step 4 left off the surface onto it where
  /// their fan, refined around them by the later rounds, now lets them go: each triangle of the
  /// fan facing outward and no worse than now against the surface's normal at its centroid
  /// (within max_normal_deg, or no farther than now from it), its centroid no farther from the
  /// surface, no node swept; the whole way, else half of it, in passes (two vertices of one fan
  /// never in the same pass). false leaves them, as the paper-style refinement did.
  bool reproject = true;
  /// With `reproject`: how many times at most rounds follow a reprojection, on the edges at the
  /// vertices it brought onto the surface (their sag measured afresh; each set of rounds is
  /// followed by another reprojection). A round never splits an edge at a vertex left off the
  /// surface, so without these the fan of a vertex reprojected at the end stays as coarse as
  /// when the vertex was left, and sags between corners now on the surface (>= 0; 0: one
  /// reprojection and no more rounds).
  int settle_rounds = 3;
};

/// What refine_to_surface() did.
struct RefineStats {
  int rounds = 0;                    ///< rounds that split at least one edge (settling ones too)
  std::size_t split_edges = 0;       ///< edges split over all rounds
  std::size_t flat_splits = 0;       ///< new vertices left at their edge's midpoint, of which
  std::size_t unprojected = 0;       ///< the Newton steps did not converge close by
  std::size_t reverted = 0;          ///< a fold or a protected point sent back
  std::size_t halfway = 0;           ///< new vertices left half way to the surface
  /// Of those left off the surface (flat or half way), the ones `reproject` took onto it once
  /// the rounds had refined their neighbourhood (every reprojection counted).
  std::size_t reprojected = 0;
  /// Edges not evaluated: halves of an edge whose first-order distance was small enough that
  /// theirs (taken as half of it) is within the tolerance.
  std::size_t inherited = 0;
  std::size_t spared = 0;            ///< edges beyond the tolerance left unsplit (spare_area)
  std::size_t triangles_before = 0;  ///< triangles before refinement
  std::size_t triangles_after = 0;   ///< triangles after it
  bool budget_reached = false;       ///< a round was skipped for max_triangles
};

/// Refines `mesh` (a closed mesh of the surface of `field`, e.g. from the tetrahedral
/// polygonizer) where it lies far from the surface; `skeleton` gives the local radii and its
/// nodes are kept on their side of the mesh. Throws InvalidArgument for bad options or a
/// skeleton without nodes, Cancelled through `ctx`.
void refine_to_surface(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                       const RefineOptions& options = {}, Context* ctx = nullptr,
                       RefineStats* stats = nullptr);

/// Options of polygonize_to_tolerance(); validated at entry (InvalidArgument naming the option).
struct ToleranceOptions {
  static constexpr double kMinTolerance = 1e-3;  ///< smallest `tolerance`
  static constexpr double kMaxTolerance = 1.0;   ///< largest `tolerance`
  /// The deviation p99 to reach, relative to the local radius (measure_deviation's `p99`),
  /// kMinTolerance..kMaxTolerance.
  double tolerance = 0.05;
  /// The base mesh: the tetrahedral polygonizer at these options (1 level by default).
  TetrahedralOptions tets = [] {
    TetrahedralOptions o;
    o.levels = 1;
    return o;
  }();
  std::size_t samples = 10000;  ///< points of each deviation measure (>= 100)
  std::uint64_t seed = 1;       ///< their seed
  int max_passes = 4;           ///< refine-and-measure passes (>= 1)
  /// The refinement's triangle budget (RefineOptions::max_triangles; the memory budget may
  /// lower it). Where it stops the refinement, `reached` may be false.
  std::size_t max_triangles = RefineOptions{}.max_triangles;
  /// The triangle improvement after each refinement pass (its `tolerance` is set to the pass's
  /// edge tolerance; `max_rounds = 0` turns it off).
  ImproveOptions improve;
  /// When set, called with the mesh of each pass once it is refined and improved, before its
  /// deviation is measured: the result, unless the measure finds the tolerance missed and
  /// another pass follows (a viewer shows it while the measure runs). Runs on the calling
  /// thread; must not keep the reference.
  std::function<void(const TriMesh& mesh)> on_pass;
};

/// What polygonize_to_tolerance() did.
struct ToleranceStats {
  TetrahedralStats tets;      ///< the base mesh
  RefineStats refine;         ///< all refinement passes together
  /// All improvement passes together (the figures before: the first pass's; after: the last's).
  ImproveStats improve;
  DeviationReport deviation;  ///< the last measure (samples only)
  int passes = 0;             ///< refine-and-measure passes made
  bool reached = false;       ///< deviation.samples.p99 <= tolerance
  double edge_tolerance = 0;  ///< the last pass's RefineOptions::edge_tolerance
  /// Wall time per stage.
  double seconds_tets = 0, seconds_refine = 0, seconds_improve = 0, seconds_measure = 0;
};

/// A mesh of the surface of `field` whose measured deviation p99 stays under `tolerance`: the
/// tetrahedral polygonizer at `tets` (which keeps every branch and makes the mesh closed), then
/// passes of refine_to_surface() with an edge tolerance equal to the tolerance (the edge
/// midpoints' first-order distance is a close proxy: on generated trees it gives a p99 of about
/// 0.75 of it), each followed by improve_triangles() at the same edge tolerance, times 0.7 after
/// each pass whose measure (measure_deviation over `samples` points, of the improved mesh) is
/// still above the tolerance. `reached`
/// says whether it was met within `max_passes` (or the triangle budget). Throws as
/// polygonize_tetrahedral() and InvalidArgument for bad options.
[[nodiscard]] TriMesh polygonize_to_tolerance(const Field& field, const Skeleton& skeleton,
                                              const ToleranceOptions& options = {},
                                              Context* ctx = nullptr,
                                              ToleranceStats* stats = nullptr);

}  // namespace ramiform
