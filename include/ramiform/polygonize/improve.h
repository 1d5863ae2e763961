// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Triangle improvement of a polygonizer's mesh that keeps it on the surface. Marching
/// tetrahedra leave needles where several roots land on one lattice point, and the splits of
/// refine_to_surface() leave caps and needles of their own (Zhu, Guo & Jin 2013, "Efficient
/// polygonization of tree trunks modeled by convolution surfaces", §6, name the long narrow
/// triangles their method's weakness). improve_triangles() works on every triangle whose
/// smallest angle is below `min_angle_deg`, worst first, with the local operations of surface
/// remeshing (Botsch, Kobbelt, Pauly, Alliez & Lévy 2010, "Polygon Mesh Processing", §6.5:
/// edge flips, edge collapses, tangential relaxation projected onto the surface). They are
/// tried in this order, each only when the ones before cannot bring the triangle to
/// `min_angle_deg`, and the best of those tried is taken:
///  1. **flip** an edge (a, b) of triangles (a, b, c), (b, a, d) to (c, d) when that raises the
///     pair's smallest angle (the local criterion of Delaunay flipping, Lawson 1977);
///  2. **relax** a corner on the triangle's shortest edge (a needle's close corners, a cap's
///     apex): it moves to the centroid of its neighbours in its tangent plane (the area vector
///     of its fan) and back onto the surface by Newton steps along the gradient; of the
///     corners, the one whose fan is best before the projection is tried;
///  3. **collapse** the shortest edge (u, v) into u, into v, or into its midpoint taken onto
///     the surface;
///  4. collapse the **cluster** of vertices joined to u, v by edges shorter than a fifth of the
///     triangle's longest edge (several roots on one lattice point) into one of them or into
///     their centroid taken onto the surface;
///  5. below 1.5 degrees only: collapse the **patch** of bad triangles joined to the triangle
///     through shared corners (at most 12 vertices) into its centroid on the surface, and
///     relax the third corner too.
///  6. below 1.5 degrees, when none of the moves before is possible: **nudge** a corner a
///     short step (half to four times the triangle's longest edge times sin 1.5 degrees, or
///     times its shortest edge) in one of 12 directions of its fan's tangent plane, along that
///     plane's normal or along the shortest edge, and back onto the surface: of the corners
///     and steps, the one whose fan gets the best smallest angle without turning a triangle
///     over. It mends the needles whose short
///     edge lies on a pinched neck of the mesh (a cycle of three edges that is no triangle, so
///     no collapse keeps it 2-manifold), where the triangles stand across the surface and any
///     larger move turns one of them against the gradient.
///  7. below 1 degree, as a last resort (see Rounds): a **small move**, judged by the geometry
///     alone. The triangle's shortest edge collapses into an end or its midpoint, or one of its
///     corners moves a quarter, half or all of the bound in one of the nudge's directions, no
///     vertex moving farther than half the tolerance times its local radius: every point of the
///     mesh then moves by no more than that, so its distance to the surface changes by less.
///     Of the conditions below, it meets the first, second and last; instead of the two tests
///     of the field (follow the surface, stay on the surface), each new triangle turns by less
///     than 60 degrees from the one it replaces (from a triangle below 1.5 degrees, whose
///     normal is noise: not against the area vector of the fan), and the new vertex stays
///     where the move puts it. It mends needles where the field's tests say little: next to
///     vertices refinement left off the surface, whose edges lie 0.75 to 6.5 radii off by the
///     first-order measure and every move puts one a hundredth of a radius farther, and where the
///     gradient nearly vanishes.
/// A collapse or a relaxation replaces a set of vertices (one, for a relaxation) by one new
/// vertex: the triangles around them must form a disk (V - E + F = 1) whose interior vertices
/// are exactly the set and whose boundary is one simple cycle with no chord; each disk triangle
/// with one vertex of the set takes the new vertex for it, the others go. For two vertices this
/// is the link condition of Dey, Edelsbrunner, Guha & Nekhayev 1999. Every change must:
///  - raise the smallest angle of the triangles it replaces;
///  - keep the mesh closed, consistently oriented and 2-manifold (by the conditions above; a
///    flip needs the edge (c, d) not to exist and a, b to keep three triangles);
///  - follow the surface: each new triangle's normal turns from the surface normal (the field's
///    gradient at the midpoint of its new edge, or at the new vertex) by less than
///    `max_turn_deg`, or by no more than the worst of the triangles it replaces, and by less
///    than 90 degrees; or, for a nudge, it turns by less than 60 degrees from the triangle it
///    replaces (any way, when that one is below 1.5 degrees);
///  - stay on the surface: every new edge's midpoint lies within `tolerance` local radii of the
///    surface (first-order distance |f - iso| / |grad f|, relative to the smaller local radius
///    of its end points, as refine_to_surface() measures edges; mesh/deviation.h's
///    local_radii()), or no farther than the farthest edge it replaces (plus half the move of
///    its end point, at most a tenth of the tolerance). A new edge from a vertex taken onto the
///    surface shorter than a quarter radius is not measured (its chord sags by less than 1/128
///    radius: refine_to_surface()'s `min_edge_radii`). New vertices lie on the surface;
///  - keep the skeleton inside: no skeleton node lies in a tetrahedron swept by a changed
///    triangle ((a, b, c, d) for a flip; for the vertices that move, one after the other, their
///    old and new positions with each of their triangles' other two corners).
/// A triangle below 1.5 degrees (none should stay below 1 degree) may be replaced by triangles
/// that turn as far as the worst of those they replace (past 90 degrees too: in a crumpled
/// patch of the refined mesh) and whose new edges lie as far from the surface as the farthest
/// edge of what they replace, plus a tenth of the tolerance.
/// Rounds: the bad triangles are found (after the first round only next to a change), every
/// operation they might take is evaluated against the current mesh in parallel, the field is
/// evaluated in batches at the points those operations need (midpoints of new and replaced
/// edges, Newton steps) in stages until every operation is decided (the local radii of the bad
/// triangles' corners and their neighbours first, in one batch; of a cluster's vertices as
/// targets, one at a time, best angle first; the widened bound of a triangle below 1.5 degrees
/// only when the edges it directly replaces do not do; candidates found not to fit are not
/// looked at again in the round's later stages; a relaxation's projection brings the midpoints
/// of the new vertex's edges with it), and then the operations
/// are applied one by one, worst triangle first (ties by index), each decided again against
/// the mesh as the earlier ones left it when they touched its neighbourhood. Rounds stop when
/// nothing changes or after `max_rounds`; the triangles then still below 1 degree get up to two
/// more rounds in which the small move (7) is allowed, so a mesh that has none is left as the
/// rounds made it. Then removed triangles and unused vertices are
/// dropped, the rest keeping their order (vertices made by the pass come last). The result
/// depends only on the inputs, never on the thread count. A mesh the pass does not change is
/// left as it is; a changed one loses its normals (as refine_to_surface() drops them).

#include <cstddef>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of improve_triangles(); validated at entry (InvalidArgument naming the option).
struct ImproveOptions {
  /// A new edge's midpoint may lie this far from the surface, in local radii (> 0, finite), or
  /// no farther than the farthest edge it replaces (polygonize_to_tolerance() passes its
  /// refinement's edge tolerance).
  double tolerance = 0.05;
  /// Triangles whose smallest angle is below this are improved (degrees, in (0, 60)).
  double min_angle_deg = 10.0;
  /// Largest turn of a new triangle's normal from the surface normal, unless the triangles it
  /// replaces turn farther (degrees, in (0, 90]).
  double max_turn_deg = 60.0;
  int max_rounds = 12;  ///< rounds of changes (>= 0; 0 does nothing, stats stay 0)
};

/// What improve_triangles() did. Angle figures are over the whole mesh, before and after.
struct ImproveStats {
  int rounds = 0;         ///< rounds that changed the mesh (the small move's last rounds included)
  std::size_t flips = 0;  ///< edges flipped
  std::size_t collapses = 0;  ///< edges and clusters collapsed into one vertex
  std::size_t clusters = 0;   ///< of which clusters of three or more vertices
  std::size_t relaxed = 0;    ///< vertices moved (by relaxations, nudges and small moves)
  std::size_t below_10_deg_before = 0, below_10_deg_after = 0;  ///< triangles under 10 degrees
  std::size_t below_1_deg_before = 0, below_1_deg_after = 0;    ///< triangles under 1 degree
  double min_angle_deg_before = 0, min_angle_deg_after = 0;     ///< smallest corner angle
  std::size_t triangles_before = 0, triangles_after = 0;        ///< triangle counts
};

/// Improves the triangles of `mesh` (a closed, consistently oriented 2-manifold mesh of the
/// surface of `field`, e.g. from polygonize_to_tolerance()) whose smallest angle is below
/// `options.min_angle_deg` (see the file comment); `skeleton` gives the local radii and its
/// nodes are kept on their side of the mesh. A change whose neighbourhood is not 2-manifold is
/// not made. Throws InvalidArgument for bad options, a skeleton without nodes or a vertex index
/// out of range; Cancelled through `ctx`, checked between rounds (the mesh is then valid, with
/// the changes made so far).
void improve_triangles(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                       const ImproveOptions& options = {}, Context* ctx = nullptr,
                       ImproveStats* stats = nullptr);

}  // namespace ramiform
