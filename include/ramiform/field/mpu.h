// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Multi-level partition of unity implicits (Ohtake, Belyaev, Alexa, Turk & Seidel, "Multi-level
/// Partition of Unity Implicits", ACM TOG 22(3) (SIGGRAPH) 2003, §2 partition of unity, §3
/// local approximations and the adaptive octree, §4 sharp features), as used for point-set
/// modelling by Proença, Jorge & Sousa 2008, "Suggestive contours over point-set implicits"
/// (GRAPP), §2.1.
///
/// An octree over the points' bounding cube (enlarged by 10 %) is subdivided while a cell's local
/// fit misses its points by more than ε0 (`tolerance` × the points' bounding-box diagonal). A cell
/// of diagonal d has a ball of radius R = α d (α = `support`) around its centre; to fit, the ball
/// grows by 10 % steps (R ← R + 0.1 R) until it holds at least N_min (`min_points`) points, and
/// the local function Q is fitted to the points in it, each weighted by b(3 r / (2 R)):
///
///   - a bivariate quadratic polynomial over the tangent plane (w = h(u, v) in the frame of the
///     weighted mean normal), Q = w - h(u, v), when every normal in the ball is within 90° of
///     the mean normal;
///   - otherwise, with `sharp_features`, when the ball holds at least 2 N_min points whose
///     normals form two (an edge) or three (a corner) tight clusters (every normal within 20° of
///     its cluster's mean, means more than 40° apart): one bivariate quadratic per cluster,
///     combined with max (convex) or min (concave), Ohtake §4's Boolean combination; corners
///     that are neither all convex nor all concave use a general quadric;
///   - otherwise a general quadric Q(x) = x^T A x + b^T x + c.
///
/// The local error is ε = max |Q(p_i)| / |grad Q(p_i)| (Taubin's first-order distance) over the
/// points within α d. Deviations from the paper, each for robustness far from the points:
///
///   - the general quadric is fitted to Q(p_i) = 0 and grad Q(p_i) = n_i together (weighted least
///     squares), and the bivariate polynomial also matches the slopes the normals give, instead of
///     Ohtake's auxiliary off-surface values; both make Q close to a signed distance near its
///     points;
///   - Ohtake's auxiliary points serve as a check: at the cell's centre (and its corners for a
///     general quadric or a sparse cell) where the 6 nearest points' tangent planes agree on a
///     side, Q must agree. A cell that fails is subdivided; a sparse cell (fewer than N_min points
///     within α d, which is never subdivided: depth follows the sampling density) that fails
///     gets the tangent plane of the point p nearest to its centre, or when no point is within
///     α d, σ |x - p| with σ = ±1 the side of the centre most of the 6 nearest tangent planes
///     give (no zero in the support, where a tangent plane extrapolated sideways can cut);
///   - the support (the weight's radius) stays α d even when the fitting ball grew: a grown
///     support reaches where Q extrapolates (a concave patch's paraboloid is negative all around).
///
/// The leaves blend as f_mpu = sum_i w_i Q_i / sum_i w_i with w_i(x) = b(3 |x - c_i| / (2 R_i)),
/// b the quadratic B-spline (C^1, support |t| < 3/2; α > 0.5 makes the leaves' supports cover
/// the root cube). Outside the root cube a background term (the distance s to the cube) is
/// blended in with weight (s / (0.25 × cube edge))^3, and beyond every support f_mpu = s. Then
/// f_mpu is clipped from below by the signed distance to the points' box padded by 2 % of its
/// diagonal (this never moves the surface of an exact signed distance, and nothing outside the
/// box is inside). Q_i are negative inside, so the field returned is iso - f_mpu: > iso inside,
/// |grad| ≈ 1 near the surface, gradients exact (one-sided at the max/min of sharp fits and at
/// the clip). bound(box) is [min lo_i, max hi_i] over the local functions whose supports meet
/// the box, each bounded on the box clipped to its support by the centred form of the quadric.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"

namespace ramiform {

/// Options of the MPU fit.
struct MpuOptions {
  double iso = 0.0;  ///< iso of the returned field (finite)
  /// ε0: largest local fit error, a fraction of the points' bounding-box diagonal (> 0).
  double tolerance = 1e-3;
  /// α: support radius / cell diagonal, in (0.5, 100] (above 0.5 the leaves' supports cover
  /// the root cube with a positive weight everywhere).
  double support = 0.75;
  int min_points = 15;  ///< N_min: fewest points in a fitting ball, 6..100000
  int max_depth = 12;   ///< deepest octree level (root = 0), 0..20
  /// Piecewise quadrics at edges and corners (Ohtake §4); false: plain quadrics only.
  bool sharp_features = true;
};

/// What the fit did.
struct MpuStats {
  std::size_t points = 0;            ///< input points
  std::size_t cells = 0;             ///< octree cells, leaves included
  std::size_t leaves = 0;            ///< cells with a local function
  std::size_t general_quadrics = 0;  ///< leaf fits by kind: general quadric,
  std::size_t bivariate = 0;         ///< bivariate quadratic over the tangent plane,
  std::size_t sharp = 0;             ///< piecewise (edge or corner)
  /// Sparse leaves whose fit failed the auxiliary-point check, replaced by a tangent plane or a
  /// signed point distance (counted among general_quadrics).
  std::size_t fallbacks = 0;
  int depth = 0;               ///< deepest level used
  double fit_error_max = 0.0;  ///< largest leaf error ε, model units
  double seconds = 0.0;        ///< wall-clock time of the fit
};

/// One octree leaf and the input points inside its cell (each point belongs to exactly one leaf:
/// cells are half-open, [min, max) on every axis, except on the root's max faces). `points` may
/// be empty: every child of a subdivided cell is a leaf with its own fit, also where it holds
/// no point.
struct MpuCell {
  Aabb box;                           ///< the cubic cell, model units
  int depth = 0;                      ///< octree level, root = 0
  std::vector<std::uint32_t> points;  ///< indices into the input points, ascending
};

/// Fits an MPU implicit to oriented points. `points.normals` are required, one outward normal
/// per point (any non-zero length; the caller orients them, see point_normals.h). Throws
/// InvalidArgument for bad options (naming the option), for fewer than `min_points` points, for a
/// normal count different from the point count, and naming "point K" (0-based index) for a
/// non-finite position or a zero or non-finite normal. The fit runs on `ctx`'s threads (level by
/// level, identical results on any thread count) and checks it for cancellation; `stats`, when
/// set, receives the counts.
[[nodiscard]] FieldPtr make_mpu_field(const PointSet& points, const MpuOptions& options = {},
                                      MpuStats* stats = nullptr, const Context* ctx = nullptr);

/// The octree leaves of an MPU field in depth-first order (children in z-, y-, x-major order:
/// child index x + 2 y + 4 z), e.g. to seed surface particles k per leaf with a repulsion radius
/// from the depth (Proença et al. 2008, §4). Empty when `field` is not an MPU field (a
/// restricted or wrapped MPU field is not one).
[[nodiscard]] std::vector<MpuCell> mpu_leaf_cells(const Field& field);

}  // namespace ramiform
