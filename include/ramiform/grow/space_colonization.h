// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Space colonization (Runions, Lane & Prusinkiewicz 2007, "Modeling trees with a space
/// colonization algorithm"; Kochhar 2010, "Application of implicit methods to the interactive
/// modeling of trees" (M.Sc. thesis), §2.5 and chapter 7): a tree grows from one or more roots
/// toward a cloud of attraction points, and pipe-model radii (Kochhar 2010 §2.6, eq. 2.1).
///
/// One iteration:
///  1. every live attraction point is associated with its closest node within the influence
///     distance d_i (ties: the node with the smaller index);
///  2. every node v with associated points S(v) proposes a new node at v + D d, where d is the
///     normalized sum of the unit vectors from v to the points of S(v), plus the tropism vector,
///     renormalized;
///  3. points within the kill distance d_k of any node die ("are reached").
///
/// Rules beyond the paper (all deterministic, see docs/growth.md):
///  - **Fallback.** When the unit vectors cancel (|sum| <= 1e-9 |S(v)|, e.g. a tip pulled
///    equally in opposite directions), d is the direction to the closest point of S(v) (ties:
///    the smaller point index). When the tropism cancels d exactly, it is ignored.
///  - **Duplicates.** A proposal within 1e-6 D of any existing node (including nodes created
///    earlier in the same iteration, in node-index order) is not created; its node is "blocked"
///    until its set S(v) changes. This is what stops a node whose points all stay closer to it
///    than to its new child from re-growing the same child forever.
///  - **Obstacle.** With `obstacle` set, a proposal inside it (f > iso) is deflected once: the
///    inward component of d along the obstacle's gradient at v is removed and the node is
///    retried at v + D d'. If that is still inside (or d' vanishes, or the gradient is 0) the
///    node is blocked like a duplicate: the tip stops there and never enters the obstacle.
///  - **Trunk.** While no node of a root's tree has ever had an associated point, its tip grows
///    straight along `direction` (not affected by tropism). A trunk whose tip is farther than
///    d_i from the points' bounding box and moving away from it stops (it can never arrive).
///  - **End.** Growth is done when every point is reached (success), when an iteration creates no
///    node (stalled: the reason names the cause, e.g. remaining points farther than d_i from
///    every node, or blocked nodes), or after `max_iterations` (stalled, reason says so).
///
/// Every new node lies exactly D from its parent (up to rounding), so the output has no
/// zero-length edges. A proposal whose position would not be finite (a huge D near the end of
/// the double range) is refused like a duplicate, so every node is finite. Work is incremental:
/// only the nodes created in an iteration can change associations or kill points, so each
/// iteration visits only the live points of a uniform grid (cells >= d_i) around the new nodes.
/// Results are identical for any thread count.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/types.h"
#include "ramiform/field/field.h"
#include "ramiform/grow/branch_cleanup.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of space colonization; `validate()` runs at entry of every function below.
struct ColonizationOptions {
  static constexpr double kMinPipeExponent = 2.0;  ///< smallest `pipe_exponent`
  static constexpr double kMaxPipeExponent = 3.0;  ///< largest `pipe_exponent`

  double step = 1.0;               ///< D, node spacing (edge length), model units, > 0
  double influence = 10.0;         ///< d_i, influence distance, model units, > kill
  double kill = 2.0;               ///< d_k, kill distance, model units, > 0 (>= step/2 advised)
  std::vector<Vec3> roots = {Vec3::Zero()};  ///< start nodes, >= 1, pairwise distinct
  Vec3 direction = Vec3::UnitZ();  ///< initial trunk direction (any non-zero length)
  Vec3 tropism = Vec3::Zero();     ///< added to each unit growth direction (its length is the weight)
  int max_iterations = 1000;       ///< upper bound on iterations (step() calls), >= 0
  double tip_radius = 0.02;        ///< pipe model radius of every tip, model units, > 0
  double pipe_exponent = 2.5;      ///< pipe model exponent n, kMinPipeExponent..kMaxPipeExponent
  /// Optional obstacle: nodes are never created where f > iso (the roots must lie outside).
  /// Not owned; must outlive the growth. Meshes can be used through a field wrapping them.
  const Field* obstacle = nullptr;
  /// Branch cleanup after growth (branch_cleanup.h; grow_space_colonization only, the
  /// step-by-step class returns the raw tree): Laplacian passes along chains, 0 = off,
  /// 0..BranchCleanupOptions::kMaxSmoothIterations.
  int smooth_iterations = 0;
  /// With smoothing: chain nodes turning by more than this are removed, degrees, (0, 180].
  double max_turn_deg = 90.0;
  /// Tip branches shorter than prune_steps * step are removed, >= 0 (0 = off).
  double prune_steps = 0.0;

  /// The cleanup part of these options (tip radius and exponent included; short = 2 steps).
  [[nodiscard]] BranchCleanupOptions cleanup() const;
  /// Throws InvalidArgument naming the first bad option.
  void validate() const;
};

/// Why growth ended (or that it has not).
enum class ColonizationStatus {
  kGrowing,        ///< not done yet
  kCompleted,      ///< every attraction point was reached (killed)
  kStalled,        ///< an iteration created no node while live points remain
  kMaxIterations,  ///< max_iterations reached while live points remain
};

/// What one step() did.
struct ColonizationStep {
  std::size_t iteration = 0;       ///< 1-based number of this iteration
  std::size_t nodes_added = 0;     ///< nodes created in this iteration
  std::size_t points_killed = 0;   ///< attraction points reached in this iteration
  std::size_t points_alive = 0;    ///< live attraction points after this iteration
  std::size_t nodes_blocked = 0;   ///< proposals rejected (duplicate or obstacle) in this iteration
  ColonizationStatus status = ColonizationStatus::kGrowing;  ///< status after this iteration
};

/// The outcome of a whole growth.
struct ColonizationResult {
  Skeleton skeleton;               ///< the tree(s); node 0 = first root, pipe-model radii
  std::size_t iterations = 0;      ///< iterations run
  std::size_t points_reached = 0;  ///< attraction points killed
  std::size_t points_total = 0;    ///< attraction points given
  bool stalled = false;            ///< true unless every point was reached
  std::string stall_reason;        ///< empty unless stalled
  ColonizationStatus status = ColonizationStatus::kGrowing;  ///< how growth ended
  /// What the branch cleanup changed, and the shape figures before and after it (short tip
  /// branches: shorter than kShortTipSteps steps). Filled on every growth, cleanup or not.
  BranchCleanupReport cleanup;
  double seconds = 0;              ///< wall-clock time of the growth
};

/// Tip branches shorter than this many growth steps count as short in ColonizationResult.
inline constexpr double kShortTipSteps = 2.0;

/// Space colonization one iteration at a time (for animation and inspection). Holds a copy of
/// the points. Not thread-safe itself; each step() may use `ctx->threads()` threads.
class SpaceColonization {
 public:
  /// Validates `options` (InvalidArgument), checks that every point is finite (InvalidArgument
  /// naming the index), that the points' coordinates, and each root together with them, span no
  /// more than double precision can hold (the bounding box's diagonal length is finite, the rule
  /// of skeleton `validate()`; InvalidArgument naming the point or root and the range), and that
  /// no root lies inside the obstacle (InvalidArgument), then associates the points with the
  /// roots. Sizing the point grid takes a bounded number of rounds on any finite input.
  /// `ctx` (may be null) must outlive this object; it gives the thread count, progress ("grow",
  /// fraction of points reached) and cancellation (checked here per round of the grid sizing,
  /// and once per step()).
  SpaceColonization(std::span<const Vec3> points, const ColonizationOptions& options,
                    Context* ctx = nullptr);
  ~SpaceColonization();
  SpaceColonization(SpaceColonization&&) noexcept;
  SpaceColonization& operator=(SpaceColonization&&) noexcept;
  SpaceColonization(const SpaceColonization&) = delete;
  SpaceColonization& operator=(const SpaceColonization&) = delete;

  /// Runs one iteration; when done() already, does nothing and returns a report with
  /// nodes_added == 0. Throws Cancelled when the context is cancelled.
  ColonizationStep step();
  /// True once status() is no longer kGrowing.
  [[nodiscard]] bool done() const;
  [[nodiscard]] ColonizationStatus status() const;
  /// Empty while growing or after success; otherwise why growth stopped.
  [[nodiscard]] const std::string& stall_reason() const;
  /// The current tree(s) with pipe-model radii (built on each call: O(nodes)).
  [[nodiscard]] Skeleton skeleton() const;
  [[nodiscard]] std::size_t iterations() const;
  [[nodiscard]] std::size_t node_count() const;
  [[nodiscard]] std::size_t points_alive() const;
  [[nodiscard]] std::size_t points_total() const;
  /// One flag per attraction point: true while it is alive (not yet reached).
  [[nodiscard]] std::vector<bool> alive() const;
  /// Parent of every node (UINT32_MAX for roots); node i's parent index is < i.
  [[nodiscard]] const std::vector<std::uint32_t>& parents() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Grows until done(), then cleans the branches (clean_branches with options.cleanup(), rooted
/// at the roots, nodes 0..R-1) and returns the tree with pipe-model radii (see
/// SpaceColonization; the same checks, InvalidArgument, and Cancelled when `ctx` is cancelled).
[[nodiscard]] ColonizationResult grow_space_colonization(std::span<const Vec3> points,
                                                         const ColonizationOptions& options,
                                                         Context* ctx = nullptr);

/// Why a growth produced no edge (`result.skeleton.edge_count() == 0`), as a clause for a
/// message. A stalled growth gives its `stall_reason`; a completed one reached every point from
/// the roots themselves, before the first iteration, and the text says so with the kill distance
/// and the distance of the farthest point from its nearest root, e.g. "all 2 attraction points
/// lie within the kill distance d_k = 2 of the root (0,0,0) (the farthest at distance 1.73205),
/// so they were reached before any branch grew". `points` and `options` are those `result` was
/// grown with. Empty when the result has an edge.
[[nodiscard]] std::string no_branch_reason(const ColonizationResult& result,
                                           std::span<const Vec3> points,
                                           const ColonizationOptions& options);

/// Pipe-model radii (Kochhar 2010 eq. 2.1): every tip (a node without children) gets `tip_radius`,
/// every other node r with r^n = sum over its children of r_child^n, n = `exponent`. Children are
/// determined by orienting every edge away from the given roots (breadth first). Works on any
/// forest: `roots` holds one node per connected component that has edges (isolated nodes not
/// listed get `tip_radius`). Throws InvalidArgument when tip_radius is not finite and > 0,
/// exponent is outside [2, 3], a root index is out of range or repeated, two roots share a
/// component, the skeleton has a cycle, or a node with edges is not reachable from any root.
void assign_pipe_radii(Skeleton& skeleton, std::span<const std::uint32_t> roots, double tip_radius,
                       double exponent);

}  // namespace ramiform
