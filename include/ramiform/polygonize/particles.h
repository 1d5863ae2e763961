// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The equipotential particle mesher (Gruber & Wallner 2014, "Polygonization of Line Skeletons
/// by Using Equipotential Surfaces – A Practical Description", J. Geometry and Graphics 18(1)):
/// particles placed around a line skeleton (§3.3) are moved onto the surface f == iso of a field
/// built around that skeleton (§3.5), and the triangles that join them come from the placement's
/// structure, not from the moved points (§3.6 leaves the triangulation open; ours is in
/// src/polygonize/particle_layout.h).
///
/// Placement (§3.3): n_circ particles on a ring of radius R around every edge charge and at
/// every leaf, half-spheres at closed leaves, and n_sphere particles on a sphere of radius
/// sphere_factor x R at every junction, less those inside the union of the cylinders and spheres.
/// The rings sit at the charge positions (edge_charge_count() of field/equipotential.h with the
/// edge's d_c). Two departures from §3.3, both against folds (docs/equipotential.md): a degree-two
/// node whose edges bend by at most 45 degrees, or by at most 100 with its shorter edge under
/// sphere_factor x R, gets no sphere and no ring in its symmetry plane (the paper's gamma rule);
/// instead the rings of a whole chain of such nodes sit at its charges
/// and nodes, each normal to the chain's chord over 1.5 R on either side and left out when it
/// would cross the previous ring (scaled by 1.5), so zig-zags of short edges and tight bends do
/// not cross rings. And a closed leaf whose edge plus cap lies inside its junction's sphere gets
/// no particles: the sphere's cover its bulge. gamma applies only to cycles of degree-two nodes.
/// Branches that run into a thicker branch the skeleton does not join them to (a node, or an
/// edge's closest approach, inside its tube; two alike branches whose tubes overlap; or beside
/// it, the tubes overlapping, where the field stays above twice the iso value between the two
/// axes) are joined to it for the layout first (polygonize/particle_merge.h): its edge is split
/// at the nearest axis point, and the joined node, placed at the neck between the axes (the
/// least field value on the segment between them), becomes an ordinary junction, so the mesh
/// takes the merged surface's topology (stats joined_branches). Likewise each neurite that starts
/// on a node without edges (an SWC soma: a sphere of its radius) is joined to it, and the soma
/// becomes a junction with one hole per neurite. The triangles are a 2-manifold
/// by construction: closed where every leaf is closed, with one boundary loop (the leaf's ring)
/// per open end, one component per connected component of the joined skeleton.
///
/// Movement (§3.5, our variant): every round evaluates all particles not yet converged in one
/// batch (values and gradients) and moves each along the normalized gradient by the Newton step
/// (iso - f) / |grad f|, clamped to max_step times the particle's local R; a particle's clamp is
/// halved whenever the sign of f - iso flips, so nothing oscillates, and grows by half after it
/// has bound 8 rounds in a row in one direction (a long way). A particle whose clamp falls below
/// 2^-40 R (at a jump of f) is moved sideways by 0.05 R, 0.10 R, ... and projected again, at
/// most four times. The paper's move by a fixed
/// delta in the direction sgn(potential - lambda) is the case of a clamp that always binds. The
/// paper stops at |potential - lambda| <= delta, which compares a potential with the step length
/// it also calls delta; here the step is the clamp and convergence is relative to the iso value:
/// |f - iso| <= delta |iso|. Converged particles no longer move.
///
/// Relaxation (ours; it replaces the particle repulsion §5 suggests for acute forks and close
/// branches): each round moves every particle toward the centroid of its mesh neighbours,
/// projected onto its tangent plane (the plane orthogonal to grad f), all at once from the old
/// positions, and then projects all of them back onto the surface with the same Newton steps. A
/// particle that does not converge again goes back to where it was before the round. Open-end
/// loops stay where the movement put them.
///
/// Folds: the triangles come from the (joined) skeleton's structure, so where the surface's
/// topology departs from it, the mesh folds over itself: where the surfaces of two branches
/// that are not joined merge (a thin twig beside a thicker branch, within the blend but where
/// the field between them is below twice the iso value; crowded crowns; the rest of a long
/// stretch along which two branches merge, joined at one point), the rings of both land on the
/// merged surface, and no triangulation with that connectivity can lie on it without crossing
/// itself. Junctions closer together than their spheres (scanned trees) fold a little too. The
/// folded triangles face into the surface; they are counted in the stats (inverted_triangles).
/// The tetrahedral polygonizer meshes the same field without folds.
///
/// Every skeleton node (open leaves aside) is kept inside the mesh: after the movement, the
/// nodes the mesh leaves outside (generalized winding number, mesh/winding.h, tested on the
/// nodes a join moved or a triangle swept on its way to the surface) are repaired by a
/// rebuilt layout, at most three times (a node no join moved is joined to a thicker branch
/// nearby, a join that moved one is undone, and a node still outside then takes the way it
/// has not tried; polygonize/particle_merge.h), every particle that
/// starts where it did before taking its earlier projection; and relaxation moves that would
/// carry a triangle across a node are undone, which keeps the winding number at every node.
///
/// The result is deterministic and byte-identical for any thread count.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of polygonize_particles() (the paper's Table 1 where it has them). Validated at
/// entry: InvalidArgument naming the option.
struct ParticleMeshOptions {
  int n_circ = 12;    ///< n_circ: particles on each ring around an edge (3..4096)
  int n_sphere = 48;  ///< n_sphere: particles on a junction sphere before removal (4..65536)
  double sphere_factor = 1.5;  ///< junction sphere radius / the largest incident R (> 1)
  /// gamma: in a cycle of degree-two nodes (which has no end for a chain's rings to start
  /// from), a vertex whose two edges meet at more than this angle (degrees, (0, 180]) gets one
  /// ring in their symmetry plane instead of a sphere.
  double gamma_degrees = 160;
  /// R, the placement radius (model units, > 0), or 0: per edge placement_factor times the mean
  /// radius of its two nodes. An isolated node's sphere has the node's radius.
  double placement_radius = 0;
  double placement_factor = 1.0;  ///< R per edge when placement_radius is 0 (> 0)
  /// Convergence: a particle is on the surface when |f - iso| <= delta |iso| (relative, in
  /// (0, 1); the paper's |potential - lambda| <= delta mixes a step length and a potential).
  double delta = 1e-3;
  /// Largest move per round, times the particle's local R (its edge's R; at a vertex, the
  /// largest R of its edges; at an isolated node its radius). > 0.
  double max_step = 0.25;
  int max_iterations = 200;  ///< evaluation rounds of one projection at most (>= 1)
  /// Rounds of tangential relaxation after convergence (0..100; 0 = the paper's pure method).
  int relax = 2;
};

/// What one polygonize_particles() run did.
struct ParticleMeshStats {
  std::size_t particles = 0;  ///< particles (= mesh vertices)
  std::size_t converged = 0;  ///< particles with |f - iso| <= delta |iso| at the end
  /// Evaluation rounds of the first projection (the movement of §3.5; <= max_iterations).
  int iterations = 0;
  /// The first (at most 100) particles not converged, ascending vertex indices.
  std::vector<std::uint32_t> unconverged;
  /// Junctions joined by the layout's combinatorial patch instead of a convex hull (poorer
  /// triangles, still a valid surface).
  std::size_t fallback_junctions = 0;
  std::size_t open_loops = 0;  ///< boundary loops (one per open end)
  /// Links added where branches that the skeleton does not join run into each other's tubes
  /// and were joined for the triangulation (see polygonize/particle_merge.h): each adds a
  /// handle to the mesh, or joins two of its pieces. The mesh's Euler characteristic is
  /// 2 (nodes - edges - joined_branches) minus the open loops.
  std::size_t joined_branches = 0;
  /// Skeleton nodes (other than open leaves) that the first layout's mesh left outside and a
  /// rebuilt layout brought inside (the repair; see polygonize_particles()).
  std::size_t repaired_nodes = 0;
  /// Skeleton nodes (other than open leaves) outside the mesh at the end (generalized winding
  /// number at most 0.5): 0 on every skeleton we measured (generated trees of 10 to 5,000
  /// segments, seeds 1-5 and 41-48 at 5,000, the L-systems, both scanned trees).
  std::size_t nodes_outside = 0;
  /// The first (at most 100) of them, ascending node indices of the skeleton meshed.
  std::vector<std::uint32_t> outside_nodes;
  /// Particles whose relaxation was undone because a triangle of theirs would have swept
  /// across a skeleton node (see polygonize_particles()).
  std::size_t unrelaxed = 0;
  /// Triangles facing into the surface (normal along the summed gradient of their corners):
  /// folds where the surfaces of two branches not joined in the skeleton merge. 0 without.
  std::size_t inverted_triangles = 0;
  std::uint64_t evaluations = 0;  ///< field evaluations made (each with a gradient)
  double min_angle = 0;           ///< smallest triangle corner angle, degrees
  double median_angle = 0;        ///< median triangle corner angle, degrees
  double seconds_layout = 0;      ///< wall time of the placement and triangulation
  double seconds_move = 0;        ///< wall time of the first projection
  double seconds_relax = 0;       ///< wall time of the relaxation rounds
};

/// Meshes the surface f == iso of `field` around `skeleton`, the skeleton the field was built
/// around (validated: InputError; isolated nodes allowed). `edge_spacing`: per edge, the charge
/// spacing d_c where the rings go (model units, > 0), or empty: per edge 0.5 times the smaller
/// radius of its two nodes. `open_end`: per node, non-zero for a leaf whose end is open (ignored
/// on other nodes), or empty: every end closed. The field's iso value must be non-zero (the
/// convergence test is relative to it). Vertices are the particles (normals left empty),
/// triangles counter-clockwise seen from outside. Particles that did not converge stay in the
/// mesh at their last position and are listed in `stats` (which may be null). Throws
/// InvalidArgument for bad options (naming the option) or sizes, Cancelled through `ctx`.
[[nodiscard]] TriMesh polygonize_particles(const Field& field, const Skeleton& skeleton,
                                           std::span<const double> edge_spacing,
                                           std::span<const std::uint8_t> open_end,
                                           const ParticleMeshOptions& options = {},
                                           Context* ctx = nullptr,
                                           ParticleMeshStats* stats = nullptr);

/// The same for the equipotential surface of field/equipotential.h: uses eq.field, the charge
/// spacings eq.charges.edge_spacing (rings at the charges) and the open ends eq.charges.open.
/// `skeleton` is the one `eq` was made from. Throws InvalidArgument when eq has no field.
[[nodiscard]] TriMesh polygonize_particles(const Equipotential& eq, const Skeleton& skeleton,
                                           const ParticleMeshOptions& options = {},
                                           Context* ctx = nullptr,
                                           ParticleMeshStats* stats = nullptr);

}  // namespace ramiform
