// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Procedural skeletons for demos, tests and benchmarks.

#include <cstddef>
#include <cstdint>

#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of branching_tree(); validated at entry (InvalidArgument naming the option).
struct BranchingTreeOptions {
  static constexpr double kMinPipeExponent = 1.0;  ///< smallest `pipe_exponent`
  static constexpr double kMaxPipeExponent = 4.0;  ///< largest `pipe_exponent`
  static constexpr std::size_t kMinSegments = 1;   ///< fewest `segments`
  static constexpr std::size_t kMaxSegments = 10'000'000;  ///< most `segments` (memory guard)
  static constexpr double kMinLengthRatio = 1e-3;          ///< smallest `length_ratio`
  static constexpr double kMaxLengthRatio = 1.0;           ///< largest `length_ratio`
  static constexpr double kMaxBranchAngleDeg = 90;  ///< `branch_angle_deg` must stay below it
  static constexpr double kMaxJitterDeg = 45;       ///< largest `jitter_deg`

  std::size_t segments = 1000;  ///< number of edges of the result, kMinSegments..kMaxSegments
  std::uint64_t seed = 1;       ///< random seed (jitter and branch rolls)
  double trunk_length = 3.0;    ///< length of the first edge, model units, > 0
  double length_ratio = 0.8;    ///< child / parent edge length, kMinLengthRatio..kMaxLengthRatio
  /// Angle between a child and its parent's direction, degrees, in [0, kMaxBranchAngleDeg).
  double branch_angle_deg = 32;
  double jitter_deg = 6;        ///< random deviation of each direction, degrees, 0..kMaxJitterDeg
  double tip_radius = 0.02;     ///< radius of every tip node, model units, > 0
  /// Pipe model exponent n of r^n = sum r_child^n, kMinPipeExponent..kMaxPipeExponent.
  double pipe_exponent = 2.0;
};

/// A binary branching tree grown breadth-first from a root at the origin pointing up (+z):
/// every edge ends in a node that forks into two children (rotated by branch_angle_deg about a
/// randomly rolled axis) until `segments` edges exist. Radii follow the pipe model from the tips
/// (tip_radius) down to the root. The result is connected, acyclic and passes validate();
/// the same options give the same tree on every platform.
[[nodiscard]] Skeleton branching_tree(const BranchingTreeOptions& options);

}  // namespace ramiform
