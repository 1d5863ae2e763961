// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Bark texture coordinates along the branches of a tree mesh: u once around each branch, v along
/// it in units of the local circumference, so that a square bark texture keeps square texels on
/// the trunk and on the twigs alike. Zhu, Guo & Jin 2013 ("Efficient polygonization of tree
/// trunks modeled by convolution surfaces", Sci China Inf Sci, §5, Figure 10) texture the trunks
/// their polygonizer extracts but do not say how; the chart here is ramiform's own
/// (docs/texturing.md has the details and the measured numbers).
///
/// 1. Branches: each connected part of the skeleton is rooted at its thickest leaf node (ties:
///    the lower index); from the root, chains of edges are followed: at a fork the child with the
///    largest node radius (ties: the one best aligned with the incoming edge, then the lower edge
///    index) continues the chain, every other child starts a chain of its own. Edges that close
///    a cycle are chains of one edge each.
/// 2. Frames: along each chain a rotation-minimizing frame (discrete parallel transport: the
///    frame is constant along an edge and turned at a node by the smallest rotation that takes
///    one edge's direction to the next), so u does not twist. Each chain's angle origin (u = 0,
///    the u seam) is the length-weighted mean direction of -`facing` seen in that frame.
/// 3. Vertices: each belongs to the edge with the least relative distance
///    (|p - q| + overshoot) / r, q the nearest point of the edge, overshoot how far the
///    projection on the edge's line falls beyond the edge, r the node radius interpolated at q.
///    u is the angle of p's offset from the axis in the edge's frame, over 2 pi (then
///    corrected slightly, step 4).
/// 4. v: the local radius rho of the *surface* is measured along each chain (median distance of
///    the chain's vertices from the axis, in bins of `radius_bin` node radii), and a first v
///    advances by ds / (2 pi rho(s)) along the chain's arc length s, going on over the caps at
///    free ends as Mercator's latitude; a child chain's v starts at its parent's v at the fork.
///    With `measure_radius`, v is then solved for on the mesh, chart by chart (after step 5's
///    splits): first the least-squares conjugate of u (the v whose gradient is closest to
///    n x grad u, Mercator's v = integral of dl / (2 pi rho) with each point's own rho, which
///    follows caps, blend bulges and non-round cross-sections), then a few robust Gauss-Newton
///    steps that even out |grad v| / |grad u| (the stretch) triangle by triangle, adjusting v and
///    u (u by at most 0.05 from the angle, the same on both sides of a u seam, so original u
///    may leave [0, 1) by that much) while keeping a conformal term. Each chart's constant
///    follows the first v near the chart's start plus the drift its parent has at the fork.
/// 5. Seams: a triangle whose corners belong to different chains takes the chain of most of its
///    corners (ties: the earliest chain) and gets copies of the other corners with (u, v)
///    computed in that chain (fork seams, a short loop around the base of each side branch); a
///    triangle whose u spans the wrap gets copies of its corners with u < 1/2 at u + 1 (the
///    u seam of each chain). Copies are appended after the original vertices.
/// 6. Tangents: the direction of increasing u (axis x offset) projected orthogonal to the vertex
///    normal (the normals of `mesh`, else area-weighted triangle normals), w the sign that makes
///    cross(normal, tangent) * w point along the triangles' mean dP/dv (glTF TANGENT).

#include <cstddef>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of add_bark_uvs(); validated at entry (InvalidArgument naming the option).
struct BarkUvOptions {
  /// Each branch's u seam lies on the side facing away from this direction (its outward normal
  /// along -facing), e.g. the side away from a viewer at -y. Finite; the zero vector means no
  /// preference (the seam stays where the transported frame starts).
  Vec3 facing{0, -1, 0};
  /// Length of the bins along a branch in which the surface's radius is measured, in node radii
  /// (> 0, at most 1000). Smaller bins follow the surface more closely but hold fewer vertices.
  double radius_bin = 1.0;
  /// Measure the surface's radius from the mesh and solve v (and a small correction of u) on
  /// the mesh itself (true; file comment, step 4), or take the skeleton's node radii as the
  /// radius of the surface and v from them alone (false: right only where the surface was
  /// fitted to them).
  bool measure_radius = true;
};

/// What add_bark_uvs() did.
struct BarkUvStats {
  std::size_t branches = 0;         ///< chains that got their own (u, v) chart
  std::size_t seam_edges = 0;       ///< mesh edges whose two sides have different (u, v)
  std::size_t wrap_seam_edges = 0;  ///< of those, on a chain's u seam (sides differ by u +- 1)
  std::size_t fork_seam_edges = 0;  ///< of those, on a boundary between two chains' charts
  std::size_t split_vertices = 0;   ///< vertices added by splitting along seams
  /// Median over triangles of uv_stretch() (triangles with a finite stretch; nearest rank).
  double stretch_p50 = 0;
  /// Share of the triangles (by count) with stretch in [0.9, 1.1]; triangles with degenerate
  /// (u, v) count as outside.
  double within_10_percent = 0;
  /// The same share of the surface (triangles weighted by area).
  double within_10_percent_area = 0;
};

/// Returns `mesh` with vertices split along the seams and `uvs`, `tangents` and `welded` filled
/// (one per vertex of the result; see the file comment for the chart). Triangles keep their
/// count and order and refer to the copies where they lie on the far side of a seam; the
/// original vertices keep their indices, and positions and normals (if present) are copied to
/// the split copies. `skeleton` is the skeleton the surface was made from (every node with a
/// finite position and a radius > 0). Deterministic and independent of the thread count.
/// Throws InvalidArgument for bad options, an empty skeleton, a skeleton edge index out of range,
/// a non-positive or non-finite radius, a mesh with indices out of range or normals whose count
/// is neither 0 nor the vertex count; Cancelled through `ctx`.
[[nodiscard]] TriMesh add_bark_uvs(const TriMesh& mesh, const Skeleton& skeleton,
                                   const BarkUvOptions& options = {}, BarkUvStats* stats = nullptr,
                                   const Context* ctx = nullptr);

/// Per-triangle stretch of a textured mesh: |dP/du| / |dP/dv| from the triangle's
/// (u, v) -> 3D Jacobian, the ratio of the texel size along u to the texel size along v (1 =
/// square texels). One value per triangle; NaN where the triangle's (u, v) are degenerate (zero
/// area in (u, v)) or dP/dv vanishes. Throws InvalidArgument when `uvs` is not one per vertex
/// or an index is out of range.
[[nodiscard]] std::vector<double> uv_stretch(const TriMesh& textured);

}  // namespace ramiform
