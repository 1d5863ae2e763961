// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/field.h"

#include <array>
#include <cmath>
#include <string>

#include "ramiform/core/errors.h"

namespace ramiform {

Field::Field(double iso) : iso_(iso), counter_(std::make_shared<std::atomic<std::uint64_t>>(0)) {
  if (!std::isfinite(iso)) throw InvalidArgument("field iso value must be finite");
}

Field::Field(double iso, const Field& source) : iso_(iso), counter_(source.counter_) {}

void Field::evaluate(std::span<const Vec3> points, std::span<double> values,
                     std::span<Vec3> gradients, const Context* ctx) const {
  if (values.size() != points.size()) {
    throw InvalidArgument("Field::evaluate: " + std::to_string(values.size()) + " values for " +
                          std::to_string(points.size()) + " points");
  }
  if (!gradients.empty() && gradients.size() != points.size()) {
    throw InvalidArgument("Field::evaluate: " + std::to_string(gradients.size()) +
                          " gradients for " + std::to_string(points.size()) + " points");
  }
  counter_->fetch_add(points.size(), std::memory_order_relaxed);
  if (!points.empty()) do_evaluate(points, values, gradients, ctx);
}

double Field::value(const Vec3& p) const {
  double v = 0.0;
  evaluate(std::span<const Vec3>(&p, 1), std::span<double>(&v, 1));
  return v;
}

Vec3 Field::gradient(const Vec3& p) const {
  double v = 0.0;
  Vec3 g = Vec3::Zero();
  evaluate(std::span<const Vec3>(&p, 1), std::span<double>(&v, 1), std::span<Vec3>(&g, 1));
  return g;
}

FieldPtr Field::restrict(const Aabb& /*box*/) const { return shared_from_this(); }

Vec3 numeric_gradient(const Field& field, const Vec3& p, double h) {
  std::array<Vec3, 6> pts;
  for (int k = 0; k < 3; ++k) {
    pts[2 * k] = p;
    pts[2 * k + 1] = p;
    pts[2 * k][k] += h;
    pts[2 * k + 1][k] -= h;
  }
  std::array<double, 6> v{};
  field.evaluate(pts, v);
  return Vec3((v[0] - v[1]) / (2 * h), (v[2] - v[3]) / (2 * h), (v[4] - v[5]) / (2 * h));
}

}  // namespace ramiform
