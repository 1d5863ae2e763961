// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/common.h"

#include <algorithm>
#include <span>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "ramiform/core/parallel.h"

namespace ramiform::sample_detail {

void evaluate_parallel(const Field& field, const std::vector<Vec3>& points,
                       std::vector<double>& values, std::vector<Vec3>* gradients,
                       const Context* ctx) {
  values.resize(points.size());
  if (gradients != nullptr) gradients->resize(points.size());
  parallel::for_chunks(
      points.size(), kEvalGrain,
      [&](std::size_t b, std::size_t e) {
        field.evaluate(std::span<const Vec3>(points.data() + b, e - b),
                       std::span<double>(values.data() + b, e - b),
                       gradients != nullptr ? std::span<Vec3>(gradients->data() + b, e - b)
                                            : std::span<Vec3>());
      },
      ctx);
}

Target inside_target(const Field& field) { return Target{field.iso(), kInf}; }

CellClass classify(const Interval& b, const Target& t) {
  // Negated comparisons: a NaN bound proves nothing, so it counts as empty.
  if (!(b.hi > t.lo) || !(b.lo < t.hi)) return CellClass::kEmpty;
  if (b.lo > t.lo && b.hi < t.hi) return CellClass::kFull;
  return CellClass::kPartial;
}

StatsScope::StatsScope(const Field* field, SampleStats* out) : field_(field), out_(out) {
  if (field_ != nullptr) evals0_ = field_->evaluations();
}

StatsScope::~StatsScope() {
  if (out_ == nullptr) return;
  stats.seconds = watch_.seconds();
  if (field_ != nullptr) stats.field_evals = field_->evaluations() - evals0_;
  *out_ = stats;
}

void check_point_memory(std::size_t count, const Context* ctx, const std::string& fn) {
  check_memory(ctx, 64.0 * static_cast<double>(count),
               fn + ": " + std::to_string(count) + " points", "ask for fewer points");
}

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidArgument(message);
}

std::size_t attempt_budget(std::size_t max_attempts, std::size_t count) {
  if (max_attempts != 0) return max_attempts;
  const std::size_t cap = std::numeric_limits<std::size_t>::max() / 2000;
  return 1000 * std::min(count, cap) + 1000000;
}

void check_box(const Aabb& box, const std::string& what) {
  if (box.isEmpty()) return;
  if (!box.min().allFinite() || !box.max().allFinite()) {
    throw InvalidArgument(
        what + ": the sampling box is unbounded (" + format_number(box.min().x()) + ", " +
        format_number(box.min().y()) + ", " + format_number(box.min().z()) + ") - (" +
        format_number(box.max().x()) + ", " + format_number(box.max().y()) + ", " +
        format_number(box.max().z()) + "); intersect the field with a bounded shape first");
  }
}

}  // namespace ramiform::sample_detail
