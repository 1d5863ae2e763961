// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The extent rule of the point and skeleton readers and of the curve and surface skeletons: the
/// coordinates must span no more than a double can hold (their box's diagonal has a finite
/// length). Beyond it (e.g. points at +-1e308, where max - min is inf) every distance downstream
/// (fields, grids) is inf or NaN. The box grows point by point so that the message can name the
/// first point that breaks the rule.

#include <cmath>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/types.h"

namespace ramiform::detail {

/// Grows a box point by point and says when the span overflows.
class ExtentCheck {
 public:
  /// Adds `p`; false when the coordinates seen so far span more than a double can hold.
  bool add(const Vec3& p) {
    box_.extend(p);
    return std::isfinite(box_.diagonal().norm());
  }
  /// The problem text for the point whose add() returned false, `it` naming it ("this point").
  [[nodiscard]] std::string problem(const std::string& it) const {
    return "with " + it + " the coordinates span more than double precision can hold (from " +
           format_number(box_.min().minCoeff()) + " to " + format_number(box_.max().maxCoeff()) +
           ")";
  }
  /// The box of the points added.
  [[nodiscard]] const Aabb& box() const { return box_; }

 private:
  Aabb box_;
};

}  // namespace ramiform::detail
