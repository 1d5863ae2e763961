// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// A branching skeleton from a laser-scanned tree point cloud by geodesic level sets: Xu,
/// Gossett & Chen 2007, "Knowledge and heuristic-based modeling of laser-scanned trees" (ACM
/// TOG 26(4), §3 "skeleton construction"), as AdTree also builds its initial skeleton (Du,
/// Lindenbergh, Ledoux & Ohori 2019, "AdTree: Accurate, Detailed, and Automatic Modelling of
/// Laser-Scanned Trees", Remote Sensing 11(18), §2.1). The steps of `tree_from_points`:
///  1. **Neighbour graph.** Each point is joined to its `neighbours` nearest points closer than
///     `neighbour_spacings` median point spacings (the median distance of a point to its nearest
///     neighbour). Parts of the graph that are not connected are bridged, each to the nearest
///     other part by the shortest point pair between them, until the graph is connected
///     (rounds of Borůvka's rule; the count is `bridges`).
///  2. **Geodesic distance.** The root region is the part of the graph, among the points less
///     than one bin width above the lowest point along `up`, that holds the lowest point; its
///     points start at their height above the lowest point, and Dijkstra's algorithm gives every
///     point its distance along the graph and its predecessor (ties by point index).
///  3. **Level sets.** The distances are cut into bins of `bin_width`; within a bin, the
///     connected parts of the graph restricted to the bin's points are the cross-sections of the
///     branches there. Each becomes one node at its points' centroid (the root's is moved
///     down to the lowest point's height).
///  4. **Edges.** A part's parent is the part where most of the predecessors of its points that
///     lie outside it lie (ties to the part found first); a part without one (a second root)
///     hangs from the root part.
///  5. **Radii** (after the small side branches of step 6 are dropped, so that they do not tilt
///     the axes). Each node's raw radius is the median distance of its points to the local
///     branch axis: the line through the node along the direction from its parent to its
///     children's mean (parent to node at a tip, node to children at the root); where at
///     least 8 points lie on an arc that a circle fits well (Kåsa's algebraic fit across the
///     axis: RMS residual < 20 % of its radius, radius 1 to 2.5 times the median distance,
///     centre within its radius of the centroid — a branch seen from one side), the circle's
///     radius, and the node moves to its centre. Along each
///     branch (a chain between forks) the raw radii are median-filtered (5 nodes). Then, from the
///     root out, a child never gets a larger radius than its parent, and at a fork the children
///     obey the pipe model (Shinozaki, Yoda, Hozumi & Kira 1964, "A quantitative analysis of
///     plant form — the pipe model theory", Japanese Journal of Ecology 14): when
///     sum r_child^e exceeds r_parent^e (e = `pipe_exponent`), every child is scaled by
///     (r_parent^e / sum r_child^e)^(1/e). The pipe model is a bound, not a target: the measured
///     radii are kept where they satisfy it. Radii are at least `min_radius`.
///  6. **Simplification.** At a fork, a child branch with fewer than `min_branch_points` points
///     or spanning fewer than `min_branch_bins` bins is dropped with its sub-branches (the child
///     with the most points is always kept). Chains of degree-2 nodes are then thinned: a node
///     is removed when it lies within `straight_tolerance` times its radius of the segment
///     between the chain nodes kept around it, and its radius within that share of the linear
///     interpolation there.
/// The result does not depend on the thread count (the whole computation is serial and every
/// tie is broken by point or part index).

#include <cstddef>
#include <span>
#include <vector>

#include "ramiform/core/types.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of `tree_from_points`; validated at entry (InvalidArgument naming the option).
struct TreeFromPointsOptions {
  /// The up axis: 2 (z, default) or 1 (y).
  int up_axis = 2;
  /// Bin width of the geodesic level sets, model units; 0: `bin_spacings` median spacings.
  double bin_width = 0.0;
  double bin_spacings = 6.0;           ///< the default bin width in median point spacings (> 0)
  std::size_t neighbours = 10;         ///< k of the neighbour graph (1..64)
  double neighbour_spacings = 6.0;     ///< neighbour radius in median point spacings (> 0)
  double min_radius = 0.0;             ///< smallest radius, model units; 0: half the median spacing
  double pipe_exponent = 2.0;          ///< e of the pipe model bound at forks (in [1, 4])
  std::size_t min_branch_points = 15;  ///< a side branch with fewer points is dropped
  std::size_t min_branch_bins = 3;     ///< a side branch spanning fewer bins is dropped
  /// Degree-2 chain thinning tolerance, in node radii (0 keeps every node; at most 1).
  double straight_tolerance = 0.25;
};

/// What `tree_from_points` found (for the stats).
struct TreeFromPointsReport {
  std::size_t points = 0;
  double median_spacing = 0.0;       ///< model units
  double bin_width = 0.0;            ///< model units (the option, or the default from the spacing)
  double min_radius = 0.0;           ///< model units (the option, or the default from the spacing)
  std::size_t graph_edges = 0;       ///< undirected edges of the neighbour graph, bridges included
  std::size_t graph_parts = 0;       ///< connected parts before bridging
  std::size_t bridges = 0;           ///< edges added to connect them
  std::size_t bins = 0;              ///< bins of the geodesic distance
  std::size_t raw_nodes = 0;         ///< level-set parts (nodes before simplification)
  std::size_t dropped_branches = 0;  ///< side branches dropped
  std::size_t dropped_nodes = 0;     ///< nodes in them
  std::size_t thinned_nodes = 0;     ///< degree-2 nodes removed by the chain thinning
  std::size_t nodes = 0;             ///< nodes of the result
  std::size_t tips = 0;              ///< nodes of degree 1 other than the root
  std::size_t forks = 0;             ///< nodes with two or more children
  double max_geodesic = 0.0;         ///< largest geodesic distance from the root region
  double seconds_graph = 0.0;        ///< wall time of steps 1, 2-3-4, 5-6 (not deterministic)
  double seconds_levels = 0.0;
  double seconds_radii = 0.0;
};

/// The branching skeleton of the tree scanned as `points` (see the file comment). Node 0 is the
/// root (at the base); every node's parent has a smaller index (edges are (parent, child)); the
/// skeleton is connected. Throws InvalidArgument for bad options (naming them), fewer than 10
/// points, or a non-finite point (naming its index).
[[nodiscard]] Skeleton tree_from_points(std::span<const Vec3> points,
                                        const TreeFromPointsOptions& options = {},
                                        TreeFromPointsReport* report = nullptr);

}  // namespace ramiform
