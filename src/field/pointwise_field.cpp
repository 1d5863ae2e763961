// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/pointwise_field.h"

#include "ramiform/core/parallel.h"

namespace ramiform::detail {

void PointwiseField::at_range(std::span<const Vec3> points, std::span<double> values,
                              std::span<Vec3> gradients) const {
  const bool with_gradient = !gradients.empty();
  for (std::size_t i = 0; i < points.size(); ++i)
    values[i] = at(points[i], with_gradient ? &gradients[i] : nullptr);
}

// Small batches stay on the calling thread: a task costs more than a few points.
void PointwiseField::do_evaluate(std::span<const Vec3> points, std::span<double> values,
                                 std::span<Vec3> gradients, const Context* ctx) const {
  const bool with_gradient = !gradients.empty();
  auto body = [&](std::size_t b, std::size_t e) {
    at_range(points.subspan(b, e - b), values.subspan(b, e - b),
             with_gradient ? gradients.subspan(b, e - b) : std::span<Vec3>());
  };
  if (points.size() >= 4 * kPointwiseGrain) {
    parallel::for_chunks(points.size(), kPointwiseGrain, body, ctx);
  } else {
    body(0, points.size());
  }
}

}  // namespace ramiform::detail
