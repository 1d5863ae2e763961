// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/sweep_falloff.h"

#include <algorithm>
#include <cmath>

#include "field/sweep_common.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform::detail::sweep {
namespace {

bool is_infinite(KernelKind k) {
  return k == KernelKind::kBlinn || k == KernelKind::kInversePower || k == KernelKind::kCauchy;
}

void check_positive(double v, const std::string& what, const std::string& name) {
  if (!std::isfinite(v) || v <= 0) {
    throw InvalidArgument(what + ": " + name + " must be finite and > 0, got " + std::to_string(v));
  }
}

void check_options(const CurveSurfaceOptions& o, const std::string& what) {
  try {
    o.kernel.validate();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(what + ": " + e.what());
  }
  if (!std::isfinite(o.iso) || o.iso < 0) {
    throw InvalidArgument(what + ": iso must be finite and > 0 (0 = kernel default), got " +
                          std::to_string(o.iso));
  }
  check_positive(o.weight, what, "weight");
  check_positive(o.radius, what, "radius");
  if (!std::isfinite(o.tolerance) || o.tolerance < 0) {
    throw InvalidArgument(what + ": tolerance must be finite and >= 0 (0 = default), got " +
                          std::to_string(o.tolerance));
  }
}

}  // namespace

double Falloff::value(double d, double* dfdd) const {
  const double x = d / R;
  if (!(x < xc)) {
    if (dfdd != nullptr) *dfdd = 0;
    return 0;
  }
  double k = kernel.value(x);
  double dk = kernel.derivative(x) / R;
  if (fades) {
    const double v = (x / xc) * (x / xc);
    const double v0 = tol::kFadeStart * tol::kFadeStart;
    if (v > v0) {
      const double s = (v - v0) / (1 - v0);
      const double fade = 1 - s * s * (3 - 2 * s);
      const double dfade_dd = -6 * s * (1 - s) / (1 - v0) * (2 * x / (xc * xc * R));
      dk = dk * fade + k * dfade_dd;
      k *= fade;
    }
  }
  if (dfdd != nullptr) *dfdd = weight * dk;
  return weight * k;
}

Interval Falloff::range(double dmin, double dmax) const {
  const double hi = value(std::max(dmin, 0.0), nullptr);
  const double lo = value(dmax, nullptr);
  return {lo * (1 - kBoundSlack), hi * (1 + kBoundSlack)};
}

Falloff make_falloff(const CurveSurfaceOptions& o, const std::string& what) {
  check_options(o, what);
  Falloff f;
  f.kernel = o.kernel;
  f.iso = o.iso == 0 ? o.kernel.default_iso() : o.iso;
  f.weight = o.weight;
  double x_iso = 0;
  try {
    x_iso = o.kernel.x_at(f.iso);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(what + ": " + e.what());
  }
  f.R = o.radius / x_iso;
  f.fades = is_infinite(o.kernel.kind);
  f.xc = o.kernel.support(f.iso / f.weight);
  try {
    f.d_inside = std::min(f.xc, o.kernel.x_at(f.iso / f.weight)) * f.R;
  } catch (const InvalidArgument&) {
    f.d_inside = -1;  // weight k never exceeds iso
  }
  return f;
}

}  // namespace ramiform::detail::sweep
