// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The skeleton-bounded tetrahedral polygonizer (Zhu, Guo & Jin 2013, "Efficient polygonization
/// of tree trunks modeled by convolution surfaces", Sci China Inf Sci, §3–5).
///
/// 1. A bounding point set follows the skeleton: every node; a square cross-section of edge
///    `section_scale` x radius at forks, tips and every `station_spacing` radii along chains
///    (with its centre); a second square and a cap point beyond every tip; the auxiliary points
///    of §5 on both sides of the plane of every pair of branches at a fork.
/// 2. The points (plus a far bounding box) get a Delaunay tetrahedralization (ramiform's own
///    Bowyer-Watson with exact predicates, src/polygonize/delaunay.h; TetGen and CGAL are
///    GPL/AGPL and not used). The region is the set of tetrahedra whose centroid lies within the
///    cross-sections' reach of the skeleton, plus those with a skeleton node's point as a
///    corner and the one holding each node. A Delaunay tetrahedralization is conforming, and so
///    is every subset of it.
/// 3. Every region tetrahedron is split 1:8 `levels` times exactly as Figure 4 (corner
///    tetrahedra plus the octahedron split along its shortest diagonal), over integer barycentric
///    coordinates, so that neighbours compute bit-identical points on their shared faces. A
///    region tetrahedron whose field bound excludes the iso value is skipped whole (levels >= 4;
///    below, the bound costs more than the lattice it could save).
/// 4. The field once per distinct lattice point (neighbours share the points on their common
///    corners, edges and faces; one parallel batch per round). Per chunk of region tetrahedra
///    (the paper's data-parallel kernels, here tasks on CPU threads): marching tetrahedra per
///    leaf, crossing edges keyed by the global ids of their end points; then one global dedupe,
///    vertices placed by root finding along their edge, quads split along the shorter diagonal.
/// 5. Holes are verified, not hoped away: a region-boundary face with an inside lattice point
///    gets the tetrahedron behind it added and extracted, round after round, until no boundary
///    face has one; the mesh is then closed by construction (`holes_left` reports the growth
///    limit or the far box being reached).
/// 6. Needle cleanup (mesh/cleanup.h; no change may move a skeleton node across the surface)
///    and removal of small components that enclose no skeleton node.
///
/// The result is watertight, consistently oriented (orientation is decided in barycentric
/// space, so slivers cannot flip it) and 2-manifold; every step is deterministic, so equal
/// inputs give identical meshes for any thread count. docs/polygonize.md has the details and
/// the measured numbers.

#include <cstddef>
#include <cstdint>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of polygonize_tetrahedral(); validated at entry (InvalidArgument naming the field).
struct TetrahedralOptions {
  static constexpr int kMinLevels = 0;  ///< fewest `levels`: region tetrahedra marched unsplit
  static constexpr int kMaxLevels = 6;  ///< most `levels`: 8^6 leaves per region tetrahedron
  /// Smallest `section_scale` (radii): a narrower square would not contain the branch's section.
  static constexpr double kMinSectionScale = 2.0;
  static constexpr double kMaxSectionScale = 1000.0;  ///< largest `section_scale` (radii)

  int levels = 3;  ///< 1:8 subdivision levels (Figure 4), kMinLevels..kMaxLevels
  /// Cross-section square edge / node radius (the paper's 3R), kMinSectionScale..kMaxSectionScale.
  double section_scale = 3.0;
  double station_spacing = 4.0; ///< max distance between cross-sections along an edge, in radii
  int root_steps = 16;          ///< root-finding rounds per crossing edge (0 = linear; most
                                ///< edges stop after 3 or 4, see marching_cubes.h)
  /// An edge's root finding also stops once |f - iso| <= root_value |iso| at its last point
  /// (kMinRootValue..kMaxRootValue; the default is tol::kRootValue). polygonize_to_tolerance()
  /// raises it to 1e-4: its vertices then lie a few 1e-5 local radii off the surface, far below the
  /// tolerance it meshes to, for 30 % fewer root evaluations (docs/polygonize.md).
  double root_value = 1e-8;
  static constexpr double kMinRootValue = 1e-16;  ///< smallest `root_value`
  static constexpr double kMaxRootValue = 1e-2;   ///< largest `root_value`
  int max_growth_rounds = 200;  ///< rounds of hole fixing before giving up (reported)
  bool cleanup = true;          ///< collapse needle edges afterwards (mesh/cleanup.h)
  /// Remove small components (< 1 % of the triangles) that enclose no skeleton node: blobs
  /// where the field rises above the iso value away from the skeleton.
  bool drop_strays = true;
  /// Three more bounding points in the crotch of every pair of branches leaving a fork at less
  /// than 110° (docs/polygonize.md, step 1). They serve the refinement, whose splits in a crotch
  /// crossed by the coarse lattice fold and stay off the surface: polygonize_to_tolerance()
  /// always turns them on. Off here, the uniform levels are the paper's (with the gap points):
  /// at level 1 the crotch points' small tetrahedra left more needles for the cleanup (63
  /// against 42 below 1° on the tests' 4 mm tree).
  bool crotch_points = false;
};

/// What the polygonizer did; counts and per-stage seconds.
struct TetrahedralStats {
  std::size_t polyhedron_points = 0;  ///< points of the bounding point set
  /// Of those, the points placed across narrow gaps between branches the skeleton does not join
  /// (five per place), so that no lattice edge spans the gap inside-to-inside.
  std::size_t gap_points = 0;
  /// The points placed in the crotch between two branches leaving a fork at less than 110°
  /// (three per pair), so that the lattice there is as fine as the saddle the surface makes.
  std::size_t crotch_points = 0;
  std::size_t delaunay_tets = 0;      ///< tetrahedra of the Delaunay tetrahedralization
  std::size_t axis_points_added = 0;  ///< Steiner points that make consecutive axis points
                                      ///< edges of the tetrahedralization
  std::size_t axis_edges_missing = 0; ///< pieces of the axis still not edges (normally 0)
  std::size_t region_tets = 0;        ///< tetrahedra kept before hole fixing
  std::size_t grown_tets = 0;         ///< tetrahedra added by hole fixing
  int growth_rounds = 0;              ///< rounds of hole fixing
  bool holes_left = false;            ///< true when hole fixing hit max_growth_rounds or the hull
  std::size_t skipped_tets = 0;       ///< region tetrahedra whose bound excludes the surface
  std::size_t leaf_tets = 0;          ///< leaf tetrahedra marched (8^levels per region tetrahedron
                                      ///< with lattice points on both sides)
  std::size_t vertices_evaluated = 0;  ///< distinct lattice points evaluated (each once)
  std::size_t crossing_edges = 0;     ///< mesh vertices
  std::uint64_t root_evaluations = 0; ///< evaluations spent placing vertices
  std::size_t collapsed_edges = 0;    ///< needle edges collapsed by the cleanup pass
  std::size_t stray_components = 0;   ///< components removed by drop_strays
  double min_angle_before = 0;        ///< smallest triangle angle before cleanup, degrees
  double median_angle_before = 0;     ///< median triangle angle before cleanup, degrees
  double seconds_cleanup = 0;
  double seconds_polyhedron = 0, seconds_tetrahedralize = 0, seconds_region = 0,
         seconds_subdivide = 0, seconds_field = 0, seconds_extract = 0;
};

/// Polygonizes the surface of `field` inside the region that `skeleton` bounds (normally the
/// skeleton the field was built from). Throws InvalidArgument for bad options and, before any
/// work, for a skeleton the bounding point set cannot resolve (a radius below 1e-11 of the node's
/// largest coordinate, radii or coordinates outside [1e-50, 1e50], more than 2^24
/// cross-sections, or an estimated peak memory above the machine's); InputError for an invalid
/// (e.g. empty) skeleton; Failure if the tetrahedralization fails.
[[nodiscard]] TriMesh polygonize_tetrahedral(const Field& field, const Skeleton& skeleton,
                                             const TetrahedralOptions& options = {},
                                             Context* ctx = nullptr,
                                             TetrahedralStats* stats = nullptr);

}  // namespace ramiform
