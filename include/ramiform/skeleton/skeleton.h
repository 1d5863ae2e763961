// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// `Skeleton`: a graph of nodes (position, radius) joined by straight edges.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform {

/// One skeleton node.
struct SkeletonNode {
  Vec3 position = Vec3::Zero();  ///< model units
  double radius = 1.0;           ///< local radius of the shape around the node, > 0
};

/// A curved edge (Rigaudière, Gesquière & Faudot, "Shape Modelling with Skeleton based Implicit
/// Primitives", §3.3): the Bezier curve from the edge's first node through the inner control
/// points `controls` to its second node, of degree controls.size() + 1. `radii`: empty (the
/// radius runs linearly in t from node to node) or one per inner control point (the radius is
/// then the Bernstein sum of the first node's radius, these, and the second node's).
struct EdgeCurve {
  std::vector<Vec3> controls;  ///< inner control points, model units (empty: a straight edge)
  std::vector<double> radii;   ///< empty, or one radius (> 0) per inner control point
};

/// A line skeleton: nodes joined by edges (unordered node-index pairs). Plain data.
struct Skeleton {
  std::vector<SkeletonNode> nodes;                 ///< one entry per node
  std::vector<std::array<std::uint32_t, 2>> edges;  ///< one node-index pair per edge
  /// Optional node types (e.g. SWC structure identifiers: 1 soma, 2 axon, 3 basal dendrite,
  /// 4 apical dendrite, others custom): empty, or one per node. Operations that build new
  /// skeletons (splitting, growth) may leave them empty.
  std::vector<std::int32_t> node_types;
  /// Optional open-end flags for the equipotential surface (field/equipotential.h): empty, or
  /// one per node, 1 where a leaf's end is open (sharp-edged) instead of closed and round.
  /// Skeleton JSON spells it `"end": "open"` on a node.
  std::vector<std::uint8_t> open_ends;
  /// Optional curved edges: empty, or one per edge (an entry without controls is straight).
  /// Skeleton JSON spells it `{"nodes": [i, j], "controls": [[x, y, z], ...], "radii": [...]}`
  /// on an edge. The fields and polygonizers take straight edges: straighten_curves() turns
  /// the curves into chains of short straight edges first (read_skeleton does it by default).
  std::vector<EdgeCurve> curves;

  [[nodiscard]] std::size_t node_count() const { return nodes.size(); }
  [[nodiscard]] std::size_t edge_count() const { return edges.size(); }
  /// True when some edge is curved.
  [[nodiscard]] bool has_curves() const;
};

/// Checks every invariant and throws `InputError` naming the first offending element (`source`
/// is the file name used in the message, may be empty): no nodes; `node_types` or `open_ends` neither
/// empty nor one per node; non-finite position; radius not finite or <= 0; edge index out of range; self-loop; duplicate edge (either orientation);
/// zero-length edge (endpoints closer than tol::kCoincident times the skeleton's extent);
/// `curves` neither empty nor one per edge; more than 14 inner control points on an edge, a
/// non-finite control point, or radii neither empty nor one per control point, or not > 0.
void validate(const Skeleton& skeleton, const std::string& source = {});

/// The full control polygon of edge `e`: its first node, the inner control points (none for a
/// straight edge), its second node; and the radius at each (interpolated linearly in the
/// control index when the curve has no radii of its own, which makes the Bernstein sum the
/// linear interpolation in t).
void edge_controls(const Skeleton& skeleton, std::size_t e, std::vector<Vec3>& points,
                   std::vector<double>& radii);

/// The skeleton with every curved edge replaced by a chain of straight edges through points of
/// the curve, uniform in t, each new node carrying the curve's radius there. An edge gets as
/// many pieces as make both the chord error (bounded through the control polygon's second
/// differences: (1 / m)^2 / 8 max|C''|) and the radius's deviation from linear between the new
/// nodes at most `relative_tolerance` times the smallest radius along it (at most 4096 pieces).
/// Original nodes keep their indices; new nodes follow them, with the first node's type and
/// closed ends. Edges keep their order, a curved one expanded in place. Returns a copy without
/// `curves`; a skeleton without curves comes back unchanged. `relative_tolerance` in (0, 1].
/// Throws InputError for an invalid skeleton (validate()), InvalidArgument for a bad tolerance or when the pieces would number more than 2^22
/// in all (a hostile file), before allocating them.
[[nodiscard]] Skeleton straighten_curves(const Skeleton& skeleton,
                                         double relative_tolerance = 0.01);

/// Connected components: one component label per node, labels 0..count-1 in order of each
/// component's smallest node index. Isolated nodes form their own components.
struct SkeletonComponents {
  std::vector<std::uint32_t> label;  ///< one label per node
  std::uint32_t count = 0;           ///< number of components
};
[[nodiscard]] SkeletonComponents connected_components(const Skeleton& skeleton);

/// Bounding box of the node spheres (position +- radius).
[[nodiscard]] Aabb bounding_box(const Skeleton& skeleton);

/// Node degrees (number of incident edges), one per node.
[[nodiscard]] std::vector<std::uint32_t> degrees(const Skeleton& skeleton);

}  // namespace ramiform
