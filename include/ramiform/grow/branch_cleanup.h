// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Cleaning up grown branch skeletons: smoothing of unbranched chains and pruning of stubs.
///
/// Space colonization (Runions et al. 2007; Kochhar 2010, "Application of implicit methods to
/// the interactive modeling of trees" (M.Sc. thesis), §2.5 and chapter 7) moves every tip by one
/// step D toward the mean direction of its attraction points, so chains kink wherever that mean
/// jumps, and a tip whose points die after one or two steps leaves a stub. The smooth
/// convolution surface reproduces both. The passes here are ours (docs/growth.md, "Branch
/// cleanup"):
///
///  - **Chains.** With the edges oriented away from the roots, a *chain node* is a node of degree
///    2 that is not a root. Roots, forks (degree >= 3) and tips (degree 1) are *fixed*.
///  - **Smoothing** (`smooth_iterations` = N > 0): N Jacobi passes of Laplacian smoothing with
///    weight 1/2, x <- x/2 + (x_parent + x_child)/4, on every chain node; fixed nodes never move.
///    Each pass removes the zig-zag (alternating) component of a chain completely and does not
///    increase the sum of squared edge lengths; as N grows a chain tends to the straight segment
///    between its fixed ends with equal spacing. Positions are always smoothed from the input
///    positions, so the result depends only on N and the final topology.
///  - **Kinks.** Smoothing cannot unfold a chain that doubles back on itself. After smoothing,
///    every chain node whose turn angle (the angle between the edge in and the edge out, 0 for
///    straight) exceeds `max_turn_deg`, or one of whose edges is shorter than tol::kCoincident
///    times the skeleton's extent, is removed: its parent and child are joined.
///  - **Stubs** (`prune_length` > 0): a *tip branch* is the path from a tip up to the first node
///    that is not a chain node; its length is the sum of its (smoothed) edge lengths. A tip
///    branch shorter than `prune_length` (here and in the report, a length equal to the limit
///    up to a relative 1e-6 counts as shorter, so that a stub of exactly 2 steps, 2 D up to
///    rounding, is always shorter than 2 steps) that ends at a fork, or at a root with two or more
///    children, is removed, except that a node never loses all its children: when every child
///    branch of a node is such a stub, the longest stays (ties: the smaller tip index).
///  - **Rounds.** Removing kinks and stubs changes the chains, so smoothing, kink removal and
///    pruning repeat until a round removes nothing (at most one round per node). On return, no
///    chain node turns by more than `max_turn_deg` (when smoothing) and no removable tip branch
///    is shorter than `prune_length`.
///  - **Radii.** When a node was removed, every radius is recomputed by the pipe model
///    (assign_pipe_radii with `tip_radius` and `pipe_exponent`, Kochhar 2010 §2.6 eq. 2.1), so
///    r_parent^n = Σ r_child^n holds at every fork; otherwise radii are unchanged (smoothing does
///    not change the topology, so pipe-model radii stay exact).
///
/// The passes are serial and deterministic: same input, same output, on any thread count.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "ramiform/core/context.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of clean_branches(); validate() runs at its entry.
struct BranchCleanupOptions {
  static constexpr int kMaxSmoothIterations = 1000;  ///< largest `smooth_iterations`

  int smooth_iterations = 0;  ///< Laplacian passes along chains, 0..kMaxSmoothIterations, 0 = off
  /// With smoothing: chain nodes turning by more than this are removed, degrees, (0, 180]
  double max_turn_deg = 90.0;
  /// Tip branches shorter than this are removed, model units, >= 0 (0 = off)
  double prune_length = 0.0;
  double tip_radius = 0.02;    ///< pipe model radius of every tip, when radii are recomputed, > 0
  double pipe_exponent = 2.5;  ///< pipe model exponent n, when radii are recomputed, 2..3
  /// The report's `short_tip_branches` counts tip branches shorter than this, model units, >= 0
  /// (+inf allowed; 0: `prune_length`)
  double short_length = 0.0;

  /// Throws InvalidArgument naming the first bad option and its value.
  void validate() const;
};

/// Shape figures of a skeleton's chains and tip branches (see the file comment for the terms).
/// Turn angles are measured at every node of degree 2 (roots included), in degrees.
struct BranchShape {
  std::size_t chain_nodes = 0;         ///< nodes of degree 2
  double turn_p50_deg = 0;             ///< median turn angle at them (0 when there is none)
  double turn_p90_deg = 0;             ///< 90th percentile (linear interpolation between ranks)
  double turn_max_deg = 0;             ///< largest
  std::size_t tip_branches = 0;        ///< tips (degree 1, not a root), one tip branch each
  std::size_t short_tip_branches = 0;  ///< tip branches shorter than the given length

  /// short_tip_branches / tip_branches (0 when there is no tip).
  [[nodiscard]] double short_share() const {
    return tip_branches == 0
               ? 0.0
               : static_cast<double>(short_tip_branches) / static_cast<double>(tip_branches);
  }
};

/// What clean_branches() changed.
struct BranchCleanupReport {
  std::size_t nodes_moved = 0;    ///< surviving nodes whose position changed
  std::size_t nodes_removed = 0;  ///< nodes removed (kinks + the nodes of pruned stubs)
  std::size_t kinks_removed = 0;  ///< chain nodes removed for turning more than max_turn_deg
  std::size_t stubs_pruned = 0;   ///< tip branches removed
  std::size_t rounds = 0;         ///< smoothing/pruning rounds run (1 when nothing was removed)
  BranchShape before;             ///< figures of the input (short: `short_length`)
  BranchShape after;              ///< figures of the result (short: `short_length`)
};

/// Smooths the chains and prunes the stubs of `skeleton` in place (see the file comment).
/// `roots` holds one node per connected component that has edges, as for assign_pipe_radii.
/// When nothing is removed only positions change. Otherwise the surviving nodes keep their
/// relative order (so roots listed first stay first, and a parent index below its child's stays
/// below) and edges are rewritten as (parent, child) pairs in the order of the child. Throws
/// InvalidArgument for bad options or a bad skeleton (edge index out of range, self-loop, cycle, a
/// root out of range or repeated, two roots in one component, a node with edges no root reaches),
/// and Cancelled when `ctx` is cancelled (checked once per round).
BranchCleanupReport clean_branches(Skeleton& skeleton, std::span<const std::uint32_t> roots,
                                   const BranchCleanupOptions& options, Context* ctx = nullptr);

/// The shape figures of `skeleton`, counting tip branches shorter than `short_length` (model
/// units) as short. `roots` as for clean_branches (the same InvalidArgument).
[[nodiscard]] BranchShape measure_branches(const Skeleton& skeleton,
                                           std::span<const std::uint32_t> roots,
                                           double short_length);

/// One clause for messages: what changed (only when something did) and the figures before and
/// after, e.g. "cleanup: 700 nodes moved, 60 removed (8 kinks, 41 stubs pruned); turn at chain
/// nodes p50/p90/max 18.0/55.0/179.0 deg -> 4.1/12.3/80.2 deg; tip branches shorter than 2
/// steps 153 of 246 (62.2 %) -> 0 of 205 (0.0 %)". `short_what` names the short length
/// ("2 steps"). Angles and shares are rounded to one decimal.
[[nodiscard]] std::string cleanup_summary(const BranchCleanupReport& report,
                                          const std::string& short_what);

}  // namespace ramiform
