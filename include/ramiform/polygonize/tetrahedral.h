// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The skeleton-bounded tetrahedral polygonizer (Zhu, Guo & Jin 2013, `003` §3–5).
///
/// 1. A bounding point set follows the skeleton: a square cross-section of edge
///    `section_scale` x radius at every node and at intermediate stations along long edges, a
///    second square and a cap point beyond every tip, and the auxiliary points of §5 on both
///    sides of the plane of every pair of branches at a fork.
/// 2. The points (plus a far bounding box) are tetrahedralized by a Delaunay tetrahedralization
///    (Qhull, permissive licence; TetGen and CGAL are GPL/AGPL and not used). The region kept is
///    the set of tetrahedra whose centroid lies within the cross-sections' reach of the skeleton,
///    plus those holding a skeleton node. A Delaunay tetrahedralization is conforming, so any
///    subset of it is.
/// 3. Holes are not hoped away but verified: every boundary face of the region whose field bound
///    does not prove it outside (f <= iso) gets the tetrahedron behind it added, until none is
///    left. The surface therefore never crosses the region's boundary.
/// 4. Every kept tetrahedron is split 1:8 `levels` times exactly as Figure 4 (corner tetrahedra
///    plus the octahedron split along its shortest diagonal); a tetrahedron whose field bound
///    excludes the iso value is not split further and emits nothing (no vertex is created on its
///    faces, which keeps the mesh conforming).
/// 5. The field is evaluated at the unique vertices of the leaf tetrahedra in one batch;
///    marching tetrahedra emits 0, 1 or 2 triangles per leaf through per-leaf counts, a prefix
///    sum and compaction (the paper's data-parallel kernels, here on CPU threads); vertices are
///    shared through edge keys and placed on the surface by root finding along their edge.
///
/// The result is watertight and consistently oriented by construction; every step is
/// deterministic, so equal inputs give identical meshes for any thread count.

#include <cstddef>
#include <cstdint>

#include "ramiform/core/context.h"
#include "ramiform/field/field.h"
#include "ramiform/mesh/trimesh.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of polygonize_tetrahedral(); validated at entry (InvalidArgument naming the field).
struct TetrahedralOptions {
  int levels = 3;               ///< 1:8 subdivision levels (Figure 4), 0..6
  double section_scale = 3.0;   ///< cross-section square edge / node radius (paper: 3), >= 2
  double station_spacing = 4.0; ///< max distance between cross-sections along an edge, in radii
  int root_steps = 12;          ///< root-finding rounds per crossing edge (0 = linear)
  int max_growth_rounds = 200;  ///< rounds of hole fixing before giving up (reported)
  bool cleanup = true;          ///< collapse needle edges afterwards (mesh/cleanup.h)
  /// Remove small components (< 1 % of the triangles) that enclose no skeleton node: blobs
  /// where the field rises above the iso value away from the skeleton.
  bool drop_strays = true;
};

/// What the polygonizer did; counts and per-stage seconds.
struct TetrahedralStats {
  std::size_t polyhedron_points = 0;  ///< points of the bounding point set
  std::size_t delaunay_tets = 0;      ///< tetrahedra of the Delaunay tetrahedralization
  std::size_t region_tets = 0;        ///< tetrahedra kept before hole fixing
  std::size_t grown_tets = 0;         ///< tetrahedra added by hole fixing
  int growth_rounds = 0;              ///< rounds of hole fixing
  bool holes_left = false;            ///< true when hole fixing hit max_growth_rounds or the hull
  std::size_t skipped_tets = 0;       ///< region tetrahedra whose bound excludes the surface
  std::size_t leaf_tets = 0;          ///< leaf tetrahedra marched (8^levels per live one)
  std::size_t vertices_evaluated = 0; ///< leaf corners evaluated (unique per region tetrahedron)
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
/// skeleton the field was built from). Throws InvalidArgument for bad options, InputError for an
/// invalid (e.g. empty) skeleton, Failure if the tetrahedralization fails.
[[nodiscard]] TriMesh polygonize_tetrahedral(const Field& field, const Skeleton& skeleton,
                                             const TetrahedralOptions& options = {},
                                             Context* ctx = nullptr,
                                             TetrahedralStats* stats = nullptr);

}  // namespace ramiform
