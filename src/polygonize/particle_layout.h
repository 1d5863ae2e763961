// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// The initial particles of the equipotential particle mesher and the triangles that join them
// (Gruber & Wallner 2014, "Polygonization of Line Skeletons by Using Equipotential Surfaces – A
// Practical Description", §3.3 for the placement; §3.6 leaves the triangulation open, this is
// ours). The triangles are built from the placement's structure, not from the points: rings of
// particles around each edge joined by bands of quads, half-sphere caps at closed leaves, rings
// along chains of degree-two nodes bent by at most 45 degrees, or 100 next to a short edge (normal
// to the chain's smoothed course, none crossing the next, a ring at a node kept before those
// between nodes; a chain node they still leave outside their tube gets a junction sphere in a
// rebuilt layout; in a cycle of such nodes, the paper's ring in the symmetry plane at vertices
// straighter than gamma), and at every other vertex a sphere with one hole per incident edge
// triangulated as the convex hull of its points (via the exact Delaunay tetrahedralization of
// delaunay.h); a closed leaf whose edge and cap lie inside its junction's sphere gets no particles
// of its own. So the connectivity is a valid 2-manifold whatever the geometry; moving the
// particles onto the surface later changes positions only.

#include <array>
#include <cstdint>
#include <vector>

#include "ramiform/core/types.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::detail {

struct ParticleLayoutOptions {
  int n_circ = 12;             ///< particles per ring around an edge (>= 3)
  int n_sphere = 48;           ///< particles on a junction sphere before removal (>= 4)
  double sphere_factor = 1.5;  ///< junction sphere radius / the largest incident R (> 1)
  double gamma_degrees = 160;  ///< in cycles: degree-2 vertices meeting above this get a ring
};

/// What to lay particles around. Sizes are checked (InvalidArgument).
struct ParticleLayoutInput {
  const Skeleton* skeleton = nullptr;  ///< validated skeleton (isolated nodes allowed)
  std::vector<double> edge_radius;     ///< placement radius R per edge (> 0)
  std::vector<double> edge_spacing;    ///< charge spacing d_c per edge (> 0): rings sit at charges
  std::vector<std::uint8_t> open_end;  ///< per node, 1 for a leaf whose end is open (ignored
                                       ///< on other nodes); or empty
  /// Per node, the radius of a sphere of its own (a neuron's soma that neurites were joined
  /// to), or 0; or empty. A node with such a sphere and edges is a junction whose sphere is
  /// sphere_factor times the larger of it and its edges' R; its own particles start on the
  /// node's sphere, spaced as the thinnest incident edge's ring points.
  std::vector<double> node_sphere;
};

struct ParticleLayout {
  std::vector<Vec3> positions;  ///< initial particle positions
  /// Triangles over `positions`, counter-clockwise seen from outside (normals point away from
  /// the skeleton). Every edge is shared by exactly two triangles except the edges of the open
  /// ends' loops, which belong to one; one connected piece per skeleton component.
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// Per particle, the skeleton node it was placed around (junction spheres, caps, vertex rings)
  /// or the nearer end node of its edge (edge rings).
  std::vector<std::uint32_t> node;
  /// Per particle, the edge whose ring it belongs to, or UINT32_MAX (sphere particles, poles).
  std::vector<std::uint32_t> edge;
  /// One loop per open end: particle indices in order around the loop.
  std::vector<std::vector<std::uint32_t>> open_loops;
  std::vector<std::uint32_t> open_loop_node;  ///< per loop, its leaf node
  /// Junctions (and isolated nodes) whose convex hull could not be used (two incident edges
  /// within 1e-4 rad of each other, or a hull that failed its check) and that were joined by
  /// a combinatorial patch instead: still a sphere with one hole per edge, with poorer shape.
  std::size_t fallback_junctions = 0;
};

/// Lays out the particles and their triangles. Deterministic; no randomness.
[[nodiscard]] ParticleLayout build_particle_layout(const ParticleLayoutInput& input,
                                                   const ParticleLayoutOptions& options);

}  // namespace ramiform::detail
