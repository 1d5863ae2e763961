// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the batched projection on a Bezier curve's certified arcs (BezierProjector, degree
// 1..7), vectorized across query points with Highway and dispatched at run time like the
// skeleton fields (field/skeleton_field_simd.h). Each lane runs, with masks, exactly the
// operations of BezierProjector::project_arcs<N> on its own point (same order, same roundings,
// no fused multiply-adds), so a point's result does not depend on the batch, on its neighbours
// in the vector, or on the CPU's instruction set.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace ramiform::detail {

// Constants of the arc path, shared by the scalar (bezier_curve.cpp) and the batched code.
/// Newton on an arc stops when the step or the bracket is below this in t.
inline constexpr double kBezierRootTolerance = 1e-15;
inline constexpr int kBezierMaxRootIterations = 200;
/// Rounding bound of the dot product E·(c - P) in the arc certificate, per unit of
/// max|E_i| * |c - P|_1 (a generous multiple of 3 eps).
inline constexpr double kBezierSlopeRounding = 16 * std::numeric_limits<double>::epsilon();
/// An arc whose sphere is farther than the best point found, inflated by this, is skipped.
inline constexpr double kBezierPruneSlack = 1e-9;
/// Arcs per group of BezierArcTable::gx, ... (see there).
inline constexpr int kBezierGroup = 4;
/// Batched path: a point whose two nearest candidates are within this (relative, in squared
/// distance) is projected one by one (far above choose()'s tie limit of about 2e-12).
inline constexpr double kBezierNearTie = 1e-9;

/// The arcs of a projector as flat arrays (structure of arrays). K arcs; coordinates are
/// relative to the projector's origin. Built once by BezierProjector::build_arcs().
struct BezierArcTable {
  int degree = 0;  ///< N, 1..7
  int count = 0;   ///< K, the number of arcs
  // Per arc (K entries): bounding sphere (radius inflated for rounding: 1e-9 relative and 1e-12
  // of the coordinates), parameter range, certificate and Newton constants.
  std::vector<double> cx, cy, cz, radius;
  /// Chord (end - start), 1 / |chord|² (0 for a closed arc), largest distance of the arc from
  /// the chord segment (inflated): a second lower bound of the distance to the arc.
  std::vector<double> ux, uy, uz, inv_chord2, deviation;
  std::vector<double> t0, span, tolerance;  ///< tolerance = 1e-15 / span (Newton's stop in s)
  /// Arcs in groups of kBezierGroup consecutive ones ((K + 3) / 4 groups): a sphere holding the
  /// spheres of the group (its radius inflated for rounding), so that the batched path skips a
  /// group that no lane of a vector can need.
  std::vector<double> gx, gy, gz, gradius;
  std::vector<double> floor, second_max, g2_fixed, g2_per_distance;
  // Per arc and index j: controls of C'' (j < N - 1) and power-basis coefficients of C (j <= N),
  // at [j * K + arc].
  std::vector<double> ex, ey, ez;
  std::vector<double> ax, ay, az;
  // Per arc end (K + 1 entries): C(t_k), C'(t_k), C''(t_k).
  std::vector<double> px, py, pz, tx, ty, tz, sx, sy, sz;
};

/// The exact isolation (Rigaudière et al. §3.4) of g on one arc for the query q (relative to
/// the origin), for the arcs that the certificate does not cover: the stationary parameters s in
/// the arc's own [0, 1] into `roots` (sorted, at most 32), their count returned; `skipped`
/// receives the number of maxima of the distance not located. `projector` is passed through.
using BezierArcIsolation = int (*)(const void* projector, int arc, const double* q, double* roots,
                                   int* skipped);

/// What the batched projection found for one point. No default values: project_arcs_batch
/// writes every field of its `n` results (a block of them is not cleared before each call).
struct BezierLaneResult {
  double t;                ///< parameter of the nearest candidate
  double d2;               ///< its squared distance
  double distance;         ///< sqrt(d2) (correctly rounded, as std::sqrt)
  double x, y, z;          ///< its point, relative to the origin
  int counted;             ///< candidates counted (stationary parameters located or skipped)
  bool redo;  ///< the second nearest candidate within kBezierNearTie of the nearest: the tie
              ///< rule may matter, so the caller projects this point one by one
};

/// Most points per call of project_arcs_batch.
inline constexpr std::size_t kBezierBatch = 256;

/// The certified-arc projection of `n` <= kBezierBatch points (qx, qy, qz: relative to the
/// origin) into `out[0..n)`, in the order given. Arcs that are not certified for a point go to
/// `isolate`.
void project_arcs_batch(const BezierArcTable& table, const double* qx, const double* qy,
                        const double* qz, std::size_t n, BezierArcIsolation isolate,
                        const void* projector, BezierLaneResult* out);

/// The Highway target that project_arcs_batch dispatches to now.
[[nodiscard]] std::int64_t bezier_dispatched_target();

}  // namespace ramiform::detail
