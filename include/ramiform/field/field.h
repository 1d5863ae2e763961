// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The `Field` interface: a scalar field f over R^3 with an iso value.
///
/// Convention (pinned by a test): f(p) > iso is inside, the surface is f(p) == iso, and ties
/// count as outside. The core call evaluates a batch of points; the single-point calls are
/// conveniences over it. Fields are immutable once built and shared through `FieldPtr`; one
/// field may be a child of several operators (a BlobTree is a DAG).

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>

#include "ramiform/core/context.h"
#include "ramiform/core/types.h"

namespace ramiform {

class Field;
using FieldPtr = std::shared_ptr<const Field>;

class Field : public std::enable_shared_from_this<Field> {
 public:
  virtual ~Field() = default;
  Field(const Field&) = delete;
  Field& operator=(const Field&) = delete;

  /// The iso value: the surface is f == iso, the inside f > iso.
  [[nodiscard]] double iso() const { return iso_; }

  /// Evaluates f at every point: `values[i] = f(points[i])`, and when `gradients` is non-empty
  /// also `gradients[i] = grad f(points[i])`. `values` must have the size of `points`;
  /// `gradients` that size or 0. Throws InvalidArgument on a size mismatch. Thread-safe.
  /// Adds points.size() to the evaluation counter. Large batches are split over
  /// `ctx->threads()` threads (nullptr: all cores) and check `ctx` for cancellation between
  /// chunks; the values never depend on the thread count.
  void evaluate(std::span<const Vec3> points, std::span<double> values,
                std::span<Vec3> gradients = {}, const Context* ctx = nullptr) const;

  /// f(p) (a batch of one).
  [[nodiscard]] double value(const Vec3& p) const;
  /// grad f(p) (a batch of one).
  [[nodiscard]] Vec3 gradient(const Vec3& p) const;
  /// True when p is inside: f(p) > iso.
  [[nodiscard]] bool is_inside(const Vec3& p) const { return value(p) > iso_; }

  /// Conservative range of f over the closed box: the true values never leave it.
  [[nodiscard]] virtual Interval bound(const Aabb& box) const = 0;

  /// A box containing every point where f > iso (may be empty when nothing is inside).
  [[nodiscard]] virtual Aabb bounds() const = 0;

  /// A field equal to this one everywhere inside `box` that skips primitives whose support
  /// misses the box (BVH over supports). It shares this field's evaluation counter. The default
  /// returns this field itself. The field must be owned by a shared_ptr (all make_* do so).
  [[nodiscard]] virtual FieldPtr restrict(const Aabb& box) const;

  /// A short human-readable description ("line skeleton, 12 segments, convolution/Cauchy").
  [[nodiscard]] virtual std::string describe() const = 0;

  /// Number of point evaluations made through this field and the fields restricted from it.
  [[nodiscard]] std::uint64_t evaluations() const {
    return counter_->load(std::memory_order_relaxed);
  }
  /// Sets the evaluation counter to 0.
  void reset_evaluations() const { counter_->store(0, std::memory_order_relaxed); }

 protected:
  /// `iso` must be finite (throws InvalidArgument otherwise).
  explicit Field(double iso);
  /// For restrict(): a new field that counts into `source`'s counter.
  Field(double iso, const Field& source);

  /// The evaluation itself; sizes are already checked and `gradients` is empty or full-size.
  /// Operators pass `ctx` on to their children; parallel loops run on its threads.
  virtual void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                           std::span<Vec3> gradients, const Context* ctx) const = 0;

 private:
  double iso_;
  std::shared_ptr<std::atomic<std::uint64_t>> counter_;
};

/// Central-difference gradient of `field` at p with step h (for tests and checks).
[[nodiscard]] Vec3 numeric_gradient(const Field& field, const Vec3& p, double h);

}  // namespace ramiform
