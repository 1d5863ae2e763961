// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: interpolation along the path of a skin surface (sweep.h, SkinInterpolation; Kochhar
// 2010, "Application of implicit methods to the interactive modeling of trees", §4.2.3, eq. 4.2,
// which interpolates linearly; the quadratic and cubic schemes are ramiform's).

#include <array>
#include <vector>

#include "ramiform/field/sweep.h"

namespace ramiform::detail::sweep {

/// An interpolated value as a combination of node values: f(s) = sum_c w[c] · D[index[c]],
/// with df/ds = sum_c dw[c] · D[index[c]]. At most four nodes take part.
struct Weights {
  int count = 0;
  std::array<int, 4> index{};
  std::array<double, 4> w{}, dw{};  ///< weight and its derivative d/ds

  /// Adds wi (and dwi) to node i's weight, appending the node when it is new.
  void add(int i, double wi, double dwi);
};

/// Interpolation weights at nodes s_0 < s_1 < ... (strictly ascending, at least one):
/// - kLinear: the hat functions (thesis §4.2.3);
/// - kQuadratic: per interval, the Lagrange parabola through the triple of neighbouring nodes
///   that spans less (so a close pair does not make the parabola swing); linear below 3 nodes;
/// - kCubic: cubic Hermite per interval with the slope at each interior node that of the
///   parabola through it and its two neighbours (Bessel tangents, a non-uniform Catmull–Rom
///   spline), the one-sided secant at the first and last node.
/// Before the first node and after the last the end node's value is used.
class Interpolator {
 public:
  Interpolator(std::vector<double> s, SkinInterpolation kind);

  /// The weights at s (any real).
  [[nodiscard]] Weights at(double s) const;

  /// An upper bound of sum_c |w[c](s)| over all s (a Lebesgue constant; >= 1): interpolated
  /// values never exceed it times the largest |node value|.
  [[nodiscard]] double lebesgue() const { return lebesgue_; }

 private:
  void interval_weights(int k, double s, Weights& out) const;
  void add_slope(int i, double f, double df, Weights& out) const;
  [[nodiscard]] double interval_lebesgue(int k) const;

  std::vector<double> s_;
  SkinInterpolation kind_;
  std::vector<int> quad_first_;  // kQuadratic: per interval, the first node of its triple
  double lebesgue_ = 1;
};

}  // namespace ramiform::detail::sweep
