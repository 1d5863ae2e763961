// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Branches that the skeleton does not join but whose tubes merge, joined for the particle
// layout. Gruber & Wallner 2014 ("Polygonization of Line Skeletons by Using Equipotential
// Surfaces – A Practical Description", §5, Figures 11–12) note that the surfaces of close
// branches merge; a mesh with the skeleton's connectivity cannot follow such a surface without
// folding over itself. This finds the places where a thinner branch runs into a thicker one
// that is not its neighbour in the skeleton (a node of it, or its closest approach, inside the
// thicker tube) and joins the two there: the thicker edge is split at the nearest point of its
// axis and the thinner branch's node (or a new node at its closest approach) is moved onto that
// point. Given the surface's field (ours), it also joins a branch that passes beside a thicker
// one, outside its tube, where their tubes overlap and the field stays above twice its iso value
// all along the segment between the two axes (the surfaces merge broadly there), and it puts
// every joined node at that segment's neck (its point of least field value) instead of on the
// thicker axis, so that the junction lies in the merged surface's waist. The layout then builds
// a junction there as at any fork, so the mesh has the merged surface's topology (each join adds
// a handle, or joins two components). A node without edges (a neuron's soma, as the SWC reader
// makes it: a sphere of its radius) takes, per other component, that component's node nearest
// its centre whose tube reaches the sphere; the layout makes the soma a junction with its own
// sphere (MergedSkeleton::node_sphere). Only the layout's skeleton changes; the field is built on
// the original one.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::detail {

/// Values of join_merging_branches()'s `force`.
inline constexpr std::uint8_t kJoinAsFound = 0;
inline constexpr std::uint8_t kJoinNearby = 1;
inline constexpr std::uint8_t kJoinNever = 2;

/// The layout's skeleton and its per-edge and per-node inputs (see ParticleLayoutInput).
struct MergedSkeleton {
  Skeleton skeleton;                   ///< nodes and edges only
  std::vector<double> edge_radius;     ///< placement radius R per edge
  std::vector<double> edge_spacing;    ///< ring spacing per edge
  std::vector<std::uint8_t> open_end;  ///< per node, or empty
  /// Links the joins add: (nodes - edges) of the skeleton minus that of the result. Each adds
  /// a handle to the mesh, or joins two of its pieces (a closed mesh's Euler characteristic is
  /// 2 (nodes - edges) of the layout's skeleton).
  std::size_t joins = 0;
  /// Per node of the skeleton, 1 when its node in the result lies elsewhere (a node joined to
  /// a thicker branch's axis, or to a class placed at a thicker member); empty without joins.
  std::vector<std::uint8_t> moved;
  /// Per node of the result, the radius of the soma sphere it carries (a node without edges
  /// that neurites were joined to; see ParticleLayoutInput::node_sphere), or 0; empty when
  /// there is none.
  std::vector<double> node_sphere;
};

/// Joins the branches of `skeleton` (validated, straight edges) that run into thicker branches
/// not adjacent to them in the skeleton (see above). `edge_radius`, `edge_spacing`: one per
/// edge; `open_end`: one per node or empty. `force`: one per node or empty, for the particle
/// mesher's repair of nodes its mesh left outside: a node marked kJoinNearby is joined to the
/// nearest thicker edge of another branch whose axis lies within 3 R of it (R that edge's),
/// even when it lies outside that edge's tube (on that edge's axis, not at a neck); a node
/// marked kJoinNever is not moved by a join of its own, and a join into it (it may still be a
/// join's target) leaves it in place when it is the thickest there. `field`: the surface's
/// field (f > iso inside), or null for the tube rules alone, on the thicker axes; it is
/// evaluated on `ctx`'s threads. Without joins the result is the input. Deterministic (the
/// field's values do not depend on the batch or the thread count).
[[nodiscard]] MergedSkeleton join_merging_branches(const Skeleton& skeleton,
                                                   const std::vector<double>& edge_radius,
                                                   const std::vector<double>& edge_spacing,
                                                   const std::vector<std::uint8_t>& open_end,
                                                   const std::vector<std::uint8_t>& force = {},
                                                   const Field* field = nullptr,
                                                   const Context* ctx = nullptr);

}  // namespace ramiform::detail
