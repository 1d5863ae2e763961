// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Radius-matched convolution surfaces: per-edge weights w_i >= 0 of a line-skeleton
/// convolution surface f = sum_i w_i lambda_i F_i (skeleton_field.h) found by non-negative
/// least squares so that the surface passes through the radii the skeleton asks for (Zhu, Guo
/// & Jin 2013, "Efficient polygonization of tree trunks modeled by convolution surfaces", Sci
/// China Inf Sci, §2.2.2, eq. 6: min_{A >= 0} |F A - T|^2). With w_i = 1 joints swell and free
/// ends pull in; the fitted weights shrink the one and feed the other. One weight per edge
/// cannot make a tapered edge (one kernel width per edge) or a long edge next to a joint follow
/// its radii: split_edges() first (see docs/fields.md for measured errors).
///
/// Constraint points lie on circles of the requested radius around every edge (several
/// stations along it, radius interpolated between the nodes' radii) and on circles of the node
/// radius around every joint, perpendicular to each incident edge. A point strictly inside the
/// requested tube of another edge (distance to that segment below its interpolated radius at
/// the closest point) is skipped: the requested surface is not there.
///
/// Near and far. Row j of the sparse matrix F holds lambda_i F_i(p_j) (unit weight, with the
/// lambda_i, s_i and cut-off of skeleton_field.h) for the edges i whose bound at p_j reaches
/// `near_level` * iso, found through a BVH over those supports (never all pairs). The rest of
/// the field at p_j (many small contributions of thick, distant edges) is a per-row offset o_j,
/// taken from the field itself with the previous round's weights (the rounds approach a fixed
/// point; with near_level = 0 it is the NNLS of the whole field, and the default 1e-3 moves
/// the weights by about 1e-4 to 2e-3, measured, for 2 to 5 times fewer entries in F). Each
/// round solves
///   min_{w >= 0} sum_j omega_j (sum_i F_ji w_i + o_j - T)^2 + mu sum_i D_i (w_i - 1)^2,
/// D_i = sum_j omega_j F_ji^2, mu = `regularization` (keeps the weights that the constraints
/// barely determine near 1 and the normal matrix N positive definite), omega_j = Huber row
/// weights (see `robust_threshold`). Solvers (core/nnls.h): Lawson–Hanson active set on dense
/// normal equations (Lawson & Hanson 1974, Solving Least Squares Problems, ch. 23; small
/// problems) or block principal pivoting (Kim & Park 2011) on the sparse normal equations with a
/// sparse LDL^T of the free block (large problems). Both stop at the
/// KKT conditions of that problem: with g = N w - b, w_i >= 0, |g_i| <= tol N_ii where w_i > 0
/// and g_i >= -tol N_ii where w_i = 0, i.e. no single coordinate step would move a weight by
/// more than tol. Results are identical for any thread count; `ctx` sets the threads of the
/// fit's own loops, while field evaluations use the field's parallelism.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/SparseCore>

#include "ramiform/core/context.h"
#include "ramiform/field/field.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Which NNLS solver fit_edge_weights() uses.
enum class NnlsSolver {
  kAuto,    ///< dense Lawson–Hanson up to `dense_limit` edges, sparse block pivoting above
  kDense,   ///< Lawson–Hanson on dense normal equations (O(n^2) memory: small problems only)
  kSparse,  ///< block principal pivoting on sparse normal equations
};

/// Options of fit_edge_weights(); validated at entry (InvalidArgument naming the option).
struct RadiusFitOptions {
  int stations_per_edge = 3;  ///< circles per edge, at t = (k + 1/2) / n along it; >= 1
  int points_per_circle = 6;  ///< constraint points per circle (evenly spaced angles); >= 3
  /// Also constrain circles of the node radius around every joint (node of degree >= 2), one
  /// perpendicular to each incident edge (points inside another edge's requested tube are
  /// skipped, see the file comment). These hold the swelling of joints down.
  bool node_circles = true;
  /// Also constrain such circles at free ends (degree 1). A straight convolution segment
  /// rounds off at its free end, so these trade the radius along the edge against the radius
  /// at the tip: off by default.
  bool tip_circles = false;
  /// Lower bound of every weight, in [0, 1) (bounded least squares: the NNLS is solved for
  /// v = w - min_weight >= 0). With 0 a short piece next to a joint may get weight 0 and the
  /// surface can neck off between its neighbours (measured: a scanned tree meshed in 4
  /// components); a small positive floor keeps every piece of the skeleton covered.
  double min_weight = 0.25;
  /// After the fit, the skeleton itself must lie inside the surface, or a twig can neck off
  /// its parent: every edge is sampled every half radius and, while some sample has
  /// f < (1 + coverage_margin) * iso, the weights of the edges whose samples fall short are
  /// raised by 25 % (at most 12 rounds). >= 0; 0 turns the repair off.
  double coverage_margin = 0.1;
  /// Tikhonov weight mu pulling each w_i toward 1, relative to |F_i|^2 (dimensionless, >= 0).
  double regularization = 1e-6;
  NnlsSolver solver = NnlsSolver::kAuto;  ///< see NnlsSolver
  std::size_t dense_limit = 64;           ///< kAuto: largest edge count solved densely
  /// KKT tolerance (dimensionless, > 0): gradient components relative to the diagonal of the
  /// normal matrix, i.e. the largest weight change a single coordinate step may still make.
  double kkt_tolerance = 1e-9;
  /// Largest number of active-set / pivoting iterations per solve; 0 = 3 * edges + 10.
  int max_iterations = 0;
  /// Huber threshold on the relative field residual |f - T| / T of a constraint point (>= 0;
  /// 0 = plain least squares). Rows beyond it get weight threshold / |residual| (iteratively
  /// reweighted least squares), so that errors no weight can remove (webbing between branches
  /// at a joint, free ends) do not skew the weights of the rest.
  double robust_threshold = 0.01;
  /// Rounds after the first solve (>= 0); each evaluates the field with the current weights,
  /// updates the far-field offsets and the Huber row weights, and solves again.
  int outer_rounds = 3;
  /// Contributions whose bound stays below this fraction of iso at a point are "far": held at
  /// the previous round's weights instead of being unknowns of F (in [0, 1); values up to
  /// tol::kKernelCutoff keep every contribution). Larger values make F much sparser.
  double near_level = 1e-3;

  /// Throws InvalidArgument naming the first bad option.
  void validate() const;
};

/// The least-squares system of a fit: constraint points and the sparse matrix F.
struct RadiusFitSystem {
  std::vector<Vec3> points;  ///< one constraint point per row, model units
  /// Per row, the edge whose circle the point lies on (station circles and node circles).
  std::vector<std::uint32_t> point_edge;
  /// F: one row per point, one column per edge; F(j, i) = lambda_i * (cut-off) Cauchy integral
  /// of edge i at point j with unit weight, exactly as the skeleton field computes it; stored
  /// only for the edges whose bound reaches near_level * iso at the point (see the file comment).
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix;
  double iso = 1.0;                    ///< T, the resolved iso value
  Skeleton skeleton;                   ///< the skeleton (for the field evaluations of the solve)
  SkeletonFieldOptions field_options;  ///< resolved field options
};

/// Outcome of a fit. `converged` is false when the iteration limit stopped the solver before
/// the KKT conditions held; the weights are then the last feasible iterate (all >= 0).
struct RadiusFitResult {
  std::vector<double> weights;        ///< one weight >= 0 per edge (pass to make_skeleton_field)
  double residual_rms = 0;            ///< rms of (f(p_j) - T) / T over the constraint points
  double unit_residual_rms = 0;       ///< the same for w = 1 (before the fit)
  int iterations = 0;                 ///< active-set (dense) or pivoting (sparse) iterations
  int coverage_rounds = 0;            ///< rounds of the skeleton coverage repair
  std::size_t coverage_raised = 0;    ///< edges whose weight the repair raised
  bool covered = true;                ///< every skeleton sample ends above the coverage level
  bool converged = false;             ///< KKT conditions hold to `kkt_tolerance`
  double kkt_violation = 0;           ///< largest scaled KKT violation of the returned weights
  std::size_t constraint_points = 0;  ///< rows of F
  std::size_t nonzeros = 0;           ///< stored entries of F
  /// The last round's problem (file comment): far-field offset o_j and Huber weight omega_j,
  /// one per constraint point; with them the KKT conditions can be checked independently.
  std::vector<double> row_offset;
  std::vector<double> row_weight;
};

/// Builds the constraint points and F of a fit (the first half of fit_edge_weights()).
/// `field_options` must describe a convolution surface (Cauchy kernel); throws InvalidArgument
/// otherwise, InputError for an invalid skeleton, Cancelled through `ctx`.
[[nodiscard]] RadiusFitSystem build_radius_fit_system(const Skeleton& skeleton,
                                                      const SkeletonFieldOptions& field_options,
                                                      const RadiusFitOptions& options = {},
                                                      Context* ctx = nullptr);

/// Solves the regularized NNLS of `system` (the second half of fit_edge_weights()).
[[nodiscard]] RadiusFitResult solve_radius_fit(const RadiusFitSystem& system,
                                               const RadiusFitOptions& options = {},
                                               Context* ctx = nullptr);

/// Per-edge weights w_i >= 0 for make_skeleton_field(skeleton, field_options, weights) so that
/// the convolution surface passes as closely as possible through the requested radii (Zhu,
/// Guo & Jin 2013, §2.2.2). Edges whose field reaches no constraint point keep weight 1. Throws as
/// build_radius_fit_system().
[[nodiscard]] RadiusFitResult fit_edge_weights(const Skeleton& skeleton,
                                               const SkeletonFieldOptions& field_options,
                                               const RadiusFitOptions& options = {},
                                               Context* ctx = nullptr);

/// Options of split_edges(); validated at entry (InvalidArgument naming the option).
struct EdgeSplitOptions {
  /// Longest piece, in multiples of the piece's mean radius (> 0). One weight per piece can
  /// then follow the swelling near joints and the pulling-in near free ends.
  double max_length = 4.0;
  /// Largest relative radius change along a piece, |r_a - r_b| / max(r_a, r_b) (in (0, 1)).
  /// A convolution segment has one kernel width (from its mean radius), so a tapered edge can
  /// only match its radii piecewise.
  double max_taper = 0.1;
  int max_pieces = 64;  ///< most pieces one edge is split into (>= 1)
};

/// A skeleton with edges split into pieces, and where each piece came from.
struct SplitSkeleton {
  /// The original nodes (same indices) followed by the new ones; each original edge replaced,
  /// in place and in order, by its chain of pieces from its first node to its second.
  Skeleton skeleton;
  std::vector<std::uint32_t> edge_origin;  ///< per edge of `skeleton`, the original edge index
};

/// Splits every edge into the fewest pieces that are each at most `max_length` mean radii
/// long and taper by at most `max_taper` (or into `max_pieces`). The new nodes lie on the edge
/// with its linearly interpolated radius (so the requested shape is unchanged), spaced so that
/// the radius changes by the same factor from piece to piece. Fitting weights on the split skeleton
/// gives one weight per piece, which lets the surface follow tapers and joints far more closely
/// (see docs/fields.md for measured errors). Throws InputError for an invalid skeleton.
[[nodiscard]] SplitSkeleton split_edges(const Skeleton& skeleton,
                                        const EdgeSplitOptions& options = {});

/// Options of measure_radius_error(); validated at entry.
struct RadiusErrorOptions {
  int stations_per_edge = 4;  ///< sample stations per edge, at t = (k + 1/2) / n; >= 1
  int directions = 8;         ///< rays per station, perpendicular to the edge; >= 1
  /// Rays search the surface out to this multiple of the requested radius (> 1); a ray that
  /// finds none there counts the search radius as the measured radius.
  double search_factor = 4.0;
  /// A ray that enters another edge's requested tube is searched only up to that entry, and
  /// skipped when the entry lies less than this many requested radii beyond the requested
  /// surface (>= 0): there the blend is meant to fill the crotch between the branches.
  double min_gap = 1.0;
};

/// Radius error of a surface against a skeleton's requested radii. Every sample is a ray from a
/// point of an edge perpendicular to it; the measured radius is the distance to the crossing of
/// the surface nearest the requested radius on the grid 0, 0.3 .. 0.9, 1, 1.1 .. 32 radii
/// (bracketed outward while f > iso and inward while f <= iso, then refined by the bracketed
/// root finder of core/roots.h to a bracket of 1e-9 of the radius, whose midpoint is the
/// measured radius; all rays in one batch per step). Samples whose requested
/// surface point lies strictly inside another edge's requested tube are skipped, and so are
/// those that enter another tube less than `min_gap` radii further out. A ray that starts
/// outside (f <= iso on the skeleton) measures radius 0.
struct RadiusErrorReport {
  /// Per edge, the largest |measured - requested| / requested over its samples (NaN when every
  /// sample of the edge was skipped).
  std::vector<double> edge_error;
  std::vector<double> errors;              ///< every measured sample's relative error, edge by edge
  std::vector<double> signed_errors;       ///< (measured - requested) / requested, per sample
  std::vector<std::uint32_t> sample_edge;  ///< per sample, its edge
  double median = 0;                       ///< median relative error over all samples
  double p90 = 0;                          ///< 90th percentile of the relative errors
  double max = 0;                          ///< largest relative error
  double mean = 0;                         ///< mean relative error
  std::size_t samples = 0;                 ///< rays measured
  std::size_t skipped = 0;                 ///< rays skipped (inside another branch)
};

/// Measures the radius error of `field` (any field; usually a skeleton field of `skeleton`).
/// Throws InvalidArgument for bad options, InputError for an invalid skeleton.
[[nodiscard]] RadiusErrorReport measure_radius_error(const Field& field, const Skeleton& skeleton,
                                                     const RadiusErrorOptions& options = {},
                                                     Context* ctx = nullptr);

}  // namespace ramiform
