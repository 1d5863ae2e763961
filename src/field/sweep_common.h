// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: what the pieces of the curve-based surfaces (sweep.cpp and the sweep_*.h it uses)
// share: the default flattening tolerance and the slack of their bounds.

#include <vector>

#include <Eigen/Geometry>

namespace ramiform::detail::sweep {

/// Default flattening chord error, relative to the curve's extent (CurveSurfaceOptions).
constexpr double kDefaultRelativeTolerance = 1e-3;
/// Relative widening of bound() results (and of the projection's distance test) against
/// rounding.
constexpr double kBoundSlack = 1e-12;
/// Relative widening of support reaches against rounding.
constexpr double kReachMargin = 1e-9;

/// The diagonal of the bounding box of `pts` (2-D or 3-D Eigen vectors); 0 when empty.
template <class V>
[[nodiscard]] double extent_of(const std::vector<V>& pts) {
  Eigen::AlignedBox<double, V::RowsAtCompileTime> box;
  for (const auto& p : pts) box.extend(p);
  return box.isEmpty() ? 0.0 : box.diagonal().norm();
}

/// The flattening chord error: `option` when > 0, else kDefaultRelativeTolerance × `extent`
/// (1 for a curve of extent 0, a point, where any tolerance is exact).
[[nodiscard]] inline double tolerance_for(double option, double extent) {
  if (option > 0) return option;
  return extent > 0 ? kDefaultRelativeTolerance * extent : 1.0;
}

}  // namespace ramiform::detail::sweep
