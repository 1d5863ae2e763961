// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Topological and geometric checks of a `TriMesh`: watertight, oriented, manifold, connected
/// components, Euler characteristic, angle quality, signed volume.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"

namespace ramiform {

/// What `check_mesh` found. Edges are undirected vertex pairs of a triangle; a pair with equal
/// indices (from a triangle with a repeated index) is not an edge.
struct MeshReport {
  std::size_t vertices = 0;   ///< vertex count (used or not)
  std::size_t triangles = 0;  ///< triangle count
  /// At least one triangle, and every edge lies in exactly two triangles.
  bool watertight = false;
  /// Consistent orientation: no edge is used twice in the same direction, and every edge shared
  /// by two triangles is used once in each direction. (A closed oriented mesh has every edge
  /// once in each direction.) True for an empty mesh.
  bool oriented = false;
  /// Edge-manifold (no edge in more than two triangles), vertex-manifold (the triangles around
  /// each vertex form a single fan or disk) and no triangle repeats a vertex index.
  bool manifold = false;
  std::size_t components = 0;  ///< connected components of triangles sharing a vertex
  long long euler = 0;         ///< V - E + F over the vertices used by triangles
  /// Smallest corner angle in degrees; a zero-area triangle contributes 0. 0 without triangles.
  double min_angle_deg = 0.0;
  /// Median of all corner angles in degrees (mean of the two middle ones for an even count);
  /// a zero-area triangle contributes three 0 angles. 0 without triangles.
  double median_angle_deg = 0.0;
  /// Triangles whose smallest corner angle is below 10 degrees, and below 1 degree (long narrow
  /// "needles"; zero-area triangles included).
  std::size_t triangles_below_10_deg = 0;
  std::size_t triangles_below_1_deg = 0;

  std::size_t edges = 0;                 ///< distinct edges
  std::size_t boundary_edges = 0;        ///< edges in exactly one triangle
  std::size_t nonmanifold_edges = 0;     ///< edges in more than two triangles
  std::size_t misoriented_edges = 0;     ///< edges breaking `oriented`
  std::size_t nonmanifold_vertices = 0;  ///< used vertices whose triangles are not one fan
  std::size_t degenerate_triangles = 0;  ///< triangles with a repeated vertex index
  std::size_t zero_area_triangles = 0;   ///< triangles of (relatively) zero area, incl. repeated
};

/// Checks `mesh` (see `MeshReport`). A textured mesh whose vertices are split along seams
/// (`mesh.welded` non-empty) is checked through its copies: its surface, as `welded_topology`
/// gives it. Throws InvalidArgument when a triangle refers to a vertex index out of range
/// (naming the triangle) or `welded` breaks its invariants. Parallel where it pays; the result
/// does not depend on the thread count. Cost O(T log T) for T triangles.
[[nodiscard]] MeshReport check_mesh(const TriMesh& mesh, Context* ctx = nullptr);

/// The mesh with every triangle corner replaced by the original of its seam copy
/// (`mesh.welded`): the surface's topology without the texture's seams. Positions are kept
/// (copies become unused vertices); a mesh without `welded` comes back as it is, without its
/// attributes. Throws InvalidArgument for indices out of range or a broken `welded`.
[[nodiscard]] TriMesh welded_topology(const TriMesh& mesh);

/// Sets `mesh.welded` so that vertices at bit-identical positions are copies of the one with the
/// smallest index: how a textured mesh read from a PLY file (which has no seam information)
/// gets its seams back. Deterministic; O(V log V).
void weld_coincident(TriMesh& mesh);

/// Connected components of triangles that share a vertex.
struct TriangleComponents {
  std::vector<std::uint32_t> label;  ///< one label per triangle, 0..count-1
  std::uint32_t count = 0;           ///< number of components
};

/// Labels triangles by connected component (sharing a vertex connects). Labels are numbered in
/// order of each component's first triangle. Throws InvalidArgument for an index out of range.
[[nodiscard]] TriangleComponents triangle_components(const TriMesh& mesh);

/// Signed volume enclosed by the mesh (sum of signed tetrahedron volumes); positive for a closed
/// mesh oriented counter-clockwise seen from outside, in model units cubed. Meaningful only for
/// closed meshes. Throws InvalidArgument for an index out of range.
[[nodiscard]] double signed_volume(const TriMesh& mesh);

/// Total surface area in model units squared.
[[nodiscard]] double surface_area(const TriMesh& mesh);

}  // namespace ramiform
