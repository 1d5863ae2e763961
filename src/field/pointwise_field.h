// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: a base for fields that evaluate one point at a time.

#include <span>

#include "ramiform/core/context.h"
#include "ramiform/field/field.h"

namespace ramiform::detail {

/// A field given by its value (and gradient) at one point; batches are evaluated point by
/// point, in parallel chunks of kPointwiseGrain points on `ctx`'s threads when the batch has at
/// least 4 chunks (the values do not depend on the split).
class PointwiseField : public Field {
 protected:
  using Field::Field;

  /// f(p), and grad f(p) in `*grad` when `grad` is set. Thread-safe.
  [[nodiscard]] virtual double at(const Vec3& p, Vec3* grad) const = 0;

  /// at() on a range of points (`gradients` empty or the size of `points`): one point after
  /// another by default; a field with a faster batched evaluation overrides it, with values
  /// equal point by point to at()'s.
  virtual void at_range(std::span<const Vec3> points, std::span<double> values,
                        std::span<Vec3> gradients) const;

  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const final;
};

/// Points per parallel chunk of a PointwiseField batch.
constexpr std::size_t kPointwiseGrain = 64;

}  // namespace ramiform::detail
