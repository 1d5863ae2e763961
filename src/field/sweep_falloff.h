// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the kernel part of the curve-based distance surfaces, f = weight · k(d / R)
// (sweep.h; distance surfaces of Kochhar 2010, "Application of implicit methods to the
// interactive modeling of trees", §3.2).

#include <string>

#include "ramiform/core/types.h"
#include "ramiform/field/kernels.h"
#include "ramiform/field/sweep.h"

namespace ramiform::detail::sweep {

/// f as a function of the distance d to the skeletal element, cut off (and, for infinite
/// kernels, faded) at its support.
struct Falloff {
  Kernel kernel;
  double iso = 0.5;
  double weight = 1;
  double R = 1;          ///< radius of influence, model units
  double xc = 1;         ///< normalized support (the cut-off for infinite kernels)
  bool fades = false;    ///< infinite kernel: C1 fade between tol::kFadeStart and 1 of the cut-off
  double d_inside = -1;  ///< f > iso only where d < d_inside; < 0: nowhere inside

  /// f at distance d >= 0, and df/dd in `dfdd` when it is set.
  [[nodiscard]] double value(double d, double* dfdd) const;
  /// A bound of f over distances in [dmin, dmax] (f is non-increasing in d), widened by
  /// kBoundSlack.
  [[nodiscard]] Interval range(double dmin, double dmax) const;
  /// The distance beyond which f == 0.
  [[nodiscard]] double support_reach() const { return R * xc; }
};

/// The falloff of `options` (iso 0 = the kernel's default), with R chosen so that weight 1
/// puts the surface `radius` from the skeletal element. Throws InvalidArgument prefixed by
/// `what` for a bad kernel, iso, weight, radius or tolerance.
[[nodiscard]] Falloff make_falloff(const CurveSurfaceOptions& options, const std::string& what);

}  // namespace ramiform::detail::sweep
