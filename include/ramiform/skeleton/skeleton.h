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

  [[nodiscard]] std::size_t node_count() const { return nodes.size(); }
  [[nodiscard]] std::size_t edge_count() const { return edges.size(); }
};

/// Checks every invariant and throws `InputError` naming the first offending element (`source`
/// is the file name used in the message, may be empty): no nodes; `node_types` or `open_ends` neither
/// empty nor one per node; non-finite position; radius not finite or <= 0; edge index out of range; self-loop; duplicate edge (either orientation);
/// zero-length edge (endpoints closer than tol::kCoincident times the skeleton's extent).
void validate(const Skeleton& skeleton, const std::string& source = {});

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
