// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: a Bezier function (points or numbers) and its derivatives by de Casteljau's
// algorithm, shared by the curves (field/curves.h), the Bezier-curve skeletons
// (field/bezier_curve.h), the Bezier deformation functions (field/anisotropic.h) and the
// straightening of curved skeleton edges (skeleton/skeleton.h).

namespace ramiform::detail {

/// The `order`-th derivative at t of the Bezier function of degree d with coefficients
/// work[0..d]: forward differences `order` times, then de Casteljau, times d! / (d - order)!.
/// `work` is overwritten (it holds the coefficients on entry). `zero` is returned when order > d.
template <class V>
V casteljau_in_place(V* work, int d, double t, int order, const V& zero) {
  if (order > d) return zero;
  double scale = 1;
  for (int o = 0; o < order; ++o) {
    for (int i = 0; i < d - o; ++i) work[i] = work[i + 1] - work[i];
    scale *= d - o;
  }
  const int deg = d - order;
  for (int r = 1; r <= deg; ++r) {
    for (int i = 0; i <= deg - r; ++i) work[i] = (1 - t) * work[i] + t * work[i + 1];
  }
  return V(scale * work[0]);
}

}  // namespace ramiform::detail
