// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: distance-surface primitives f = weight * k(d / R) around one skeletal element (the
// modeler's primitives in primitives.cpp, the anisotropic skeletons of Rigaudière et al. in
// skeletal_elements.cpp). An Element gives the distance (or an anisotropic, normalized
// distance) and its gradient; DistancePrimitive applies the kernel, its cut-off and the weight.

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "field/cutoff.h"
#include "field/pointwise_field.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/tolerances.h"
#include "ramiform/field/field.h"
#include "ramiform/field/primitives.h"

namespace ramiform::detail {

// Relative widening of bound() results and of the distance range behind them, so that rounding
// in the evaluation (a different order of operations than the bound's) never leaves the bound.
inline constexpr double kBoundSlack = 1e-12;

// Derivative of detail::fade_of with respect to its argument v.
inline double fade_derivative(double v) {
  if (v <= 0.64 || v >= 1) return 0;
  const double s = (v - 0.64) / 0.36;
  return -6 * s * (1 - s) / 0.36;
}

// Distance from any point of a box to the skeletal element: a lower and an upper bound.
struct DistanceRange {
  double min = 0, max = 0;
};

// A skeletal element: a set of points, and the Euclidean distance to it (0 inside solids).
class Element {
 public:
  virtual ~Element() = default;
  /// Distance from p, and its gradient (a unit vector, or zero where the distance is 0).
  virtual double distance(const Vec3& p, Vec3& gradient) const = 0;
  /// distance() on every point (`out` and `gradients` of the size of `points`), equal point by
  /// point; elements with a batched projection override it.
  virtual void distances(std::span<const Vec3> points, std::span<double> out,
                         std::span<Vec3> gradients) const {
    for (std::size_t i = 0; i < points.size(); ++i) out[i] = distance(points[i], gradients[i]);
  }
  /// Bounds of the distance over a finite, non-empty box.
  virtual DistanceRange range(const Aabb& box) const = 0;
  /// The element's bounding box grown by `pad` (the box of every point closer than pad).
  virtual Aabb grown_box(double pad) const = 0;
  virtual std::string describe() const = 0;
};

// Lower bound over a box from the distance at its centre (distances are 1-Lipschitz) and the
// distance between the box and the element's own box.
inline DistanceRange lipschitz_range(const Element& e, const Aabb& box, bool convex) {
  Vec3 g;
  const double dc = e.distance(box.center(), g);
  const double half = 0.5 * box.diagonal().norm();
  DistanceRange r;
  r.min = std::max({0.0, dc - half, std::sqrt(squared_distance(box, e.grown_box(0)))});
  if (convex) {
    // The distance to a convex set is convex: its maximum over the box is at a corner.
    r.max = 0;
    for (int c = 0; c < 8; ++c) {
      r.max = std::max(r.max, e.distance(box.corner(static_cast<Aabb::CornerType>(c)), g));
    }
  } else {
    r.max = dc + half;
  }
  return r;
}

struct Resolved {
  Kernel kernel;
  double iso = 0.5;
  double weight = 1;
};

class DistancePrimitive final : public PointwiseField {
 public:
  /// `radius`: where the surface lies from the element when weight is 1; 0 for an element whose
  /// distance is already divided by its own (varying) radius, which then counts as 1.
  DistancePrimitive(std::unique_ptr<Element> element, const Resolved& o, double radius)
      : PointwiseField(o.iso), element_(std::move(element)), kernel_(o.kernel), weight_(o.weight) {
    normalized_ = radius == 0;
    R_ = (normalized_ ? 1.0 : radius) / kernel_.x_at(o.iso);
    fades_ = kernel_.kind == KernelKind::kBlinn || kernel_.kind == KernelKind::kInversePower;
    const double xc = kernel_.support(o.iso / weight_);
    support_ = xc;
    inv_cut_ = xc > 0 ? 1 / (xc * xc) : 0;
    // Inside needs weight k(x) fade(x) > iso, so k(x) > iso / weight: x < x_at(iso / weight).
    const double target = o.iso / weight_;
    if (xc > 0 && target < kernel_.value(0)) {
      const double x_in = std::min(xc, kernel_.x_at(target));
      const double pad = x_in * R_ * (1 + tol::kSupportMargin);
      inside_box_ = element_->grown_box(pad);
    }
  }

  Interval bound(const Aabb& box) const override {
    if (box.isEmpty() || support_ <= 0) return {0, 0};
    if (!box.min().allFinite() || !box.max().allFinite()) {
      return {0, weight_ * kernel_.value(0) * (1 + kBoundSlack)};
    }
    DistanceRange r = element_->range(box);
    const double slack = kBoundSlack * R_;
    r.min = std::max(0.0, r.min * (1 - kBoundSlack) - slack);
    r.max = r.max * (1 + kBoundSlack) + slack;
    const double lo = contribution(r.max / R_);
    const double hi = contribution(r.min / R_);
    return {lo * (1 - kBoundSlack), hi * (1 + kBoundSlack)};
  }

  Aabb bounds() const override { return inside_box_; }

  std::string describe() const override {
    return element_->describe() +
           (normalized_ ? std::string("; ")
                        : "; surface radius " + format_number(R_ * kernel_.x_at(iso())) + ", ") +
           kernel_name(kernel_.kind) + " kernel, iso " + format_number(iso()) + ", weight " +
           format_number(weight_);
  }

 protected:
  double at(const Vec3& p, Vec3* grad) const override {
    Vec3 grad_d;
    return from_distance(element_->distance(p, grad_d), grad_d, grad);
  }

  // The element's batched distances, then the kernel point by point (as at()).
  void at_range(std::span<const Vec3> points, std::span<double> values,
                std::span<Vec3> gradients) const override {
    constexpr std::size_t kBlock = 256;
    std::array<double, kBlock> distance;
    std::array<Vec3, kBlock> grad_d;
    for (std::size_t b = 0; b < points.size(); b += kBlock) {
      const std::size_t n = std::min(kBlock, points.size() - b);
      element_->distances(points.subspan(b, n), std::span<double>(distance.data(), n),
                          std::span<Vec3>(grad_d.data(), n));
      for (std::size_t i = 0; i < n; ++i) {
        values[b + i] =
            from_distance(distance[i], grad_d[i], gradients.empty() ? nullptr : &gradients[b + i]);
      }
    }
  }

 private:
  // The value (and gradient) from the element's distance and its gradient.
  double from_distance(double distance, const Vec3& grad_d, Vec3* grad) const {
    const double x = distance / R_;
    if (!(x < support_)) {  // beyond the support, or infinite (an anisotropic def(t) = inf)
      if (grad != nullptr) grad->setZero();
      return 0;
    }
    double k = kernel_.value(x);
    double dk = grad != nullptr ? kernel_.derivative(x) : 0.0;
    if (fades_) {
      const double v = x * x * inv_cut_;
      const double fade = fade_of(v);
      dk = dk * fade + k * fade_derivative(v) * 2 * x * inv_cut_;
      k *= fade;
    }
    if (grad != nullptr) *grad = (weight_ * dk / R_) * grad_d;
    return weight_ * k;
  }

  // weight k(x) fade(x): non-increasing in x, 0 beyond the support.
  double contribution(double x) const {
    if (x >= support_) return 0;
    double k = kernel_.value(x);
    if (fades_) k *= fade_of(x * x * inv_cut_);
    return weight_ * k;
  }

  std::unique_ptr<Element> element_;
  Kernel kernel_;
  double weight_;
  double R_ = 1;             // radius of influence: x = d / R
  double support_ = 1;       // normalized support (cut-off for infinite kernels)
  double inv_cut_ = 0;       // 1 / support^2 (fade argument scale)
  bool fades_ = false;       // infinite kernel: faded out before the cut-off
  bool normalized_ = false;  // the element's distance is divided by its own radius
  Aabb inside_box_;          // every point with f > iso (empty when none)
};

inline Resolved resolve(const DistancePrimitiveOptions& o, const std::string& what) {
  o.kernel.validate();
  if (o.kernel.kind == KernelKind::kCauchy) {
    throw InvalidArgument(what +
                          ": the cauchy kernel is a convolution kernel; use wyvill, blinn, "
                          "metaball or inverse-power");
  }
  if (!std::isfinite(o.weight) || o.weight <= 0) {
    throw InvalidArgument(what + ": weight must be finite and > 0, got " + format_number(o.weight));
  }
  if (!std::isfinite(o.iso) || o.iso < 0) {
    throw InvalidArgument(what + ": iso must be finite and > 0 (0 = kernel default), got " +
                          format_number(o.iso));
  }
  Resolved r{o.kernel, o.iso == 0 ? o.kernel.default_iso() : o.iso, o.weight};
  (void)r.kernel.x_at(r.iso);  // throws when the kernel never reaches the iso value
  return r;
}

}  // namespace ramiform::detail
