// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Coarsening of a polygonizer's mesh to a triangle budget by edge collapses that keep it a
/// closed, oriented 2-manifold on the surface with the skeleton inside: for levels of detail
/// below the coarsest mesh the polygonizer makes (lod.h). A generic decimator could open holes,
/// join branches or drop twigs; this one only collapses an edge (u, v) into one new vertex when
///  - the link condition holds (Dey, Edelsbrunner, Guha & Nekhayev 1999: the common neighbours
///    of u and v are exactly the two opposite corners of the edge's triangles) and those two
///    corners keep at least three neighbours, so the mesh stays a closed 2-manifold of the same
///    genus and component count, without duplicate triangles;
///  - the new vertex lies on the surface: the edge's midpoint taken onto f == iso by Newton steps
///    along the gradient (as refine_to_surface() and improve_triangles() project), or else u or
///    v taken onto the surface the same way (a vertex on it stays where it is);
///  - no new triangle flips against the one it replaces, or turns more than `max_turn_deg` from
///    the surface normal (the field's gradient at its centroid);
///  - no new triangle's smallest angle falls below `min_angle_deg`, unless it is no smaller
///    than the smallest angle of the triangles around u and v before;
///  - every new triangle's centroid and every new edge's midpoint lies within `max_deviation`
///    local radii of the surface (first-order distance |f - iso| / |grad f| over the smallest
///    local radius of its corners; mesh/deviation.h's local_radii(), a merged vertex taking the
///    smaller of its two);
///  - no skeleton node lies in a tetrahedron swept by a changed triangle (u moving to the new
///    vertex with each of its triangles' other two corners, then v), so every node stays on its
///    side of the surface.
/// Edges are taken in the order of `priority` (by default least quadric error first; ties by
/// vertex index), from a heap with lazy invalidation: a
/// collapse re-queues the edges of the new vertex and of its neighbours, so an edge refused
/// once is tried again when its neighbourhood changes. The pass is serial and depends only on
/// its inputs (never on the thread count). It stops when the mesh has at most `max_triangles`
/// triangles or when no edge may collapse (an outcome, not an error: `reached` says which).

#include <cstddef>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// The order in which coarsen_to_budget() tries edges.
enum class CoarsenPriority {
  /// Least quadric error first: the squared distances of the edge's midpoint to the planes of
  /// the triangles around its end points when the pass began (Garland & Heckbert 1997, a
  /// merged vertex summing its two), plus 0.01 times the squared edge length, both in squared
  /// local radii.
  kQuadric,
  kShortestEdge,  ///< shortest first, relative to the smaller radius of its end points
};

/// Options of coarsen_to_budget(); validated at entry (InvalidArgument naming the option).
struct CoarsenOptions {
  std::size_t max_triangles = 0;  ///< stop at or below this many triangles (> 0)
  /// New triangles' smallest angle floor, unless they improve on the triangles they replace
  /// (degrees, in [0, 60)).
  double min_angle_deg = 5.0;
  /// Largest turn of a new triangle's normal from the surface normal (degrees, in (0, 90]).
  double max_turn_deg = 60.0;
  /// Largest first-order distance of a new triangle's centroid or a new edge's midpoint from
  /// the surface, in local radii (> 0, finite).
  double max_deviation = 0.5;
  CoarsenPriority priority = CoarsenPriority::kQuadric;  ///< which edges go first
};

/// What coarsen_to_budget() did.
struct CoarsenStats {
  std::size_t triangles_before = 0, triangles_after = 0;
  std::size_t collapsed = 0;  ///< edges collapsed (each removes two triangles)
  std::size_t refused = 0;    ///< collapses tried and refused (an edge may count several times)
  bool reached = false;       ///< triangles_after <= max_triangles
};

/// Coarsens `mesh` (a closed, consistently oriented 2-manifold mesh of the surface of `field`,
/// e.g. from polygonize_to_tolerance(), with every node of `skeleton` inside) by edge
/// collapses until it has at most `options.max_triangles` triangles or no collapse is allowed
/// (see the file comment). Removed triangles and unused vertices are dropped, the rest keeping
/// their order; a changed mesh loses its normals and texture data. Throws InvalidArgument for
/// bad options, a skeleton without nodes or a vertex index out of range; Cancelled through
/// `ctx` (checked every few thousand edges; the mesh is then valid, with the collapses made so
/// far).
void coarsen_to_budget(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                       const CoarsenOptions& options, Context* ctx = nullptr,
                       CoarsenStats* stats = nullptr);

}  // namespace ramiform
