// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/pointwise_field.h"

#include "ramiform/core/parallel.h"

namespace ramiform::detail {

// Small batches stay on the calling thread: a task costs more than a few points.
void PointwiseField::do_evaluate(std::span<const Vec3> points, std::span<double> values,
                                 std::span<Vec3> gradients, const Context* ctx) const {
  const bool with_gradient = !gradients.empty();
  auto body = [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i)
      values[i] = at(points[i], with_gradient ? &gradients[i] : nullptr);
  };
  if (points.size() >= 4 * kPointwiseGrain) {
    parallel::for_chunks(points.size(), kPointwiseGrain, body, ctx);
  } else {
    body(0, points.size());
  }
}

}  // namespace ramiform::detail
