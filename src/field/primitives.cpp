// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/primitives.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "field/cutoff.h"
#include "field/distance_primitive.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using detail::DistancePrimitive;
using detail::DistanceRange;
using detail::Element;
using detail::fade_of;
using detail::lipschitz_range;
using detail::resolve;
using detail::Resolved;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string vec(const Vec3& v) {
  return "(" + format_number(v.x()) + " " + format_number(v.y()) + " " + format_number(v.z()) + ")";
}

class CircleElement final : public Element {
 public:
  CircleElement(const Vec3& center, const Vec3& normal, double radius)
      : center_(center), normal_(normal), radius_(radius) {}
  double distance(const Vec3& p, Vec3& gradient) const override {
    const Vec3 w = p - center_;
    const double h = normal_.dot(w);
    const Vec3 q = w - h * normal_;
    const double rho = q.norm();
    const double dr = rho - radius_;
    const double d = std::sqrt(h * h + dr * dr);
    if (d > 0) {
      // On the axis (rho = 0) every point of the circle is closest; the in-plane part of the
      // gradient vanishes there by symmetry.
      gradient = (h * normal_ + (rho > 0 ? Vec3(dr / rho * q) : Vec3::Zero())) / d;
    } else {
      gradient.setZero();
    }
    return d;
  }
  DistanceRange range(const Aabb& box) const override { return lipschitz_range(*this, box, false); }
  Aabb grown_box(double pad) const override {
    const Vec3 extent = (Vec3::Ones() - normal_.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt() * radius_;
    return {center_ - extent - Vec3::Constant(pad), center_ + extent + Vec3::Constant(pad)};
  }
  std::string describe() const override {
    return "torus primitive: circle of radius " + format_number(radius_) + " around " +
           vec(center_) + ", normal " + vec(normal_);
  }

 private:
  Vec3 center_, normal_;
  double radius_;
};

class SolidBoxElement final : public Element {
 public:
  SolidBoxElement(const Vec3& center, const Vec3& half) : center_(center), half_(half) {}
  double distance(const Vec3& p, Vec3& gradient) const override {
    const Vec3 w = p - center_;
    const Vec3 o = (w.cwiseAbs() - half_).cwiseMax(0.0);
    const double d = o.norm();
    if (d > 0) {
      for (int k = 0; k < 3; ++k) gradient[k] = (w[k] < 0 ? -o[k] : o[k]) / d;
    } else {
      gradient.setZero();
    }
    return d;
  }
  DistanceRange range(const Aabb& box) const override {
    DistanceRange r = lipschitz_range(*this, box, true);
    r.min = std::max(r.min, std::sqrt(squared_distance(box, grown_box(0))));
    return r;
  }
  Aabb grown_box(double pad) const override {
    return {center_ - half_ - Vec3::Constant(pad), center_ + half_ + Vec3::Constant(pad)};
  }
  std::string describe() const override {
    return "rounded box primitive: inner box " + vec(center_) + " ± " + vec(half_);
  }

 private:
  Vec3 center_, half_;
};

// Closest point on the 2D segment [a, b] to p (a == b allowed).
Eigen::Vector2d closest_on_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                   const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// A solid truncated cone (cylinder when r0 == r1, a disk when t0 == t1, a segment when both
// radii are 0): axis a + t u for t in [t0, t1], radius r0 at t0 and r1 at t1. The distance is
// computed in the meridian half-plane (t, rho): the closest point of a convex solid of
// revolution lies in the meridian plane of p.
class ConeElement final : public Element {
 public:
  ConeElement(const Vec3& a, const Vec3& u, double t0, double t1, double r0, double r1,
              std::string name)
      : a_(a), u_(u), t0_(t0), t1_(t1), r0_(r0), r1_(r1), name_(std::move(name)) {}
  double distance(const Vec3& p, Vec3& gradient) const override {
    const Vec3 w = p - a_;
    const double t = u_.dot(w);
    const Vec3 q = w - t * u_;
    const double rho = q.norm();
    if (t >= t0_ && t <= t1_) {
      const double len = t1_ - t0_;
      const double s = len > 0 ? r0_ + (t - t0_) * ((r1_ - r0_) / len) : std::max(r0_, r1_);
      if (rho <= s) {
        gradient.setZero();
        return 0;
      }
    }
    const Eigen::Vector2d p2(t, rho);
    const Eigen::Vector2d corners[4] = {{t0_, 0}, {t0_, r0_}, {t1_, r1_}, {t1_, 0}};
    Eigen::Vector2d best = closest_on_segment(p2, corners[0], corners[1]);
    double best_d2 = (p2 - best).squaredNorm();
    for (int e = 1; e < 3; ++e) {
      const Eigen::Vector2d c = closest_on_segment(p2, corners[e], corners[e + 1]);
      const double d2 = (p2 - c).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best = c;
      }
    }
    const double d = std::sqrt(best_d2);
    if (d > 0) {
      const Eigen::Vector2d diff = p2 - best;
      gradient = (diff.x() * u_ + (rho > 0 ? Vec3(diff.y() / rho * q) : Vec3::Zero())) / d;
    } else {
      gradient.setZero();
    }
    return d;
  }
  DistanceRange range(const Aabb& box) const override { return lipschitz_range(*this, box, true); }
  Aabb grown_box(double pad) const override {
    const Vec3 across = (Vec3::Ones() - u_.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
    const Vec3 ca = a_ + t0_ * u_;
    const Vec3 cb = a_ + t1_ * u_;
    Aabb box(ca - r0_ * across, ca + r0_ * across);
    box.extend(Aabb(cb - r1_ * across, cb + r1_ * across));
    box.min().array() -= pad;
    box.max().array() += pad;
    return box;
  }
  std::string describe() const override {
    return name_ + " primitive: inner solid from " + vec(a_ + t0_ * u_) + " (radius " +
           format_number(r0_) + ") to " + vec(a_ + t1_ * u_) + " (radius " + format_number(r1_) +
           ")";
  }

 private:
  Vec3 a_, u_;
  double t0_, t1_, r0_, r1_;
  std::string name_;
};

// The half-space {n·(p - point) <= -falloff}.
class HalfSpaceElement final : public Element {
 public:
  HalfSpaceElement(const Vec3& point, const Vec3& normal, double falloff)
      : point_(point), normal_(normal), falloff_(falloff) {}
  double distance(const Vec3& p, Vec3& gradient) const override {
    const double s = normal_.dot(p - point_) + falloff_;
    if (s > 0) {
      gradient = normal_;
      return s;
    }
    gradient.setZero();
    return 0;
  }
  DistanceRange range(const Aabb& box) const override {
    // n·p is linear: its extremes over the box are at corners, taken per component.
    double lo = 0, hi = 0;
    for (int k = 0; k < 3; ++k) {
      const double a = normal_[k] * (box.min()[k] - point_[k]);
      const double b = normal_[k] * (box.max()[k] - point_[k]);
      lo += std::min(a, b);
      hi += std::max(a, b);
    }
    return {std::max(0.0, lo + falloff_), std::max(0.0, hi + falloff_)};
  }
  Aabb grown_box(double pad) const override {
    // Points closer than pad satisfy n·(p - point) < pad - falloff: bounded only along an axis
    // that the normal is parallel to.
    Aabb box(Vec3::Constant(-kInf), Vec3::Constant(kInf));
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = Vec3::Unit(k);
      if (normal_ == e) box.max()[k] = point_[k] + pad - falloff_;
      if (normal_ == -e) box.min()[k] = point_[k] - (pad - falloff_);
    }
    return box;
  }
  std::string describe() const override {
    return "half-space primitive: plane through " + vec(point_) + ", outward normal " +
           vec(normal_) + ", falloff " + format_number(falloff_) +
           "; unbounded (infinite bounds())";
  }

 private:
  Vec3 point_, normal_;
  double falloff_;
};


// ---- validation ----

void check_point(const Vec3& p, const std::string& what) {
  if (!p.allFinite()) throw InvalidArgument(what + " must be finite, got " + vec(p));
}

void check_positive(double v, const std::string& what) {
  if (!std::isfinite(v) || v <= 0) {
    throw InvalidArgument(what + " must be finite and > 0, got " + format_number(v));
  }
}

Vec3 unit_normal(const Vec3& n, const std::string& what) {
  check_point(n, what);
  const double len = n.norm();
  if (!(len > 0)) throw InvalidArgument(what + " must be non-zero, got " + vec(n));
  return n / len;
}


FieldPtr make_cone_like(const Vec3& a, double ra, const Vec3& b, double rb, double rounding,
                        const Resolved& o, const std::string& name) {
  const Vec3 ab = b - a;
  const double len = ab.norm();
  const Vec3 u = ab / len;
  // Inward offset of the meridian trapezoid (0, ±ra), (len, ±rb) by `rounding`: the caps move to
  // t = rounding and t = len - rounding, the side line moves inward by rounding along its
  // normal, i.e. its radius drops by rounding * slant / len.
  const double slope = (rb - ra) / len;
  const double slant = std::sqrt(len * len + (rb - ra) * (rb - ra));
  const double r_at_0 = ra - rounding * (slant / len);  // inner side radius extended to t = 0
  double t0 = rounding;
  double t1 = len - rounding;
  if (slope > 0) t0 = std::max(t0, -r_at_0 / slope);
  if (slope < 0) t1 = std::min(t1, -r_at_0 / slope);
  auto side = [&](double t) { return r_at_0 + slope * t; };
  const double scale = std::max({len, ra, rb});
  const double tiny = tol::kCoincident * scale;
  if (t0 > t1 + tiny || std::max(side(t0), side(t1)) < -tiny) {
    throw InvalidArgument(name + ": rounding " + format_number(rounding) +
                          " is larger than the inradius of the shape (no ball of that radius "
                          "fits inside)");
  }
  t1 = std::max(t0, t1);
  const double r0 = std::max(0.0, side(t0));
  const double r1 = std::max(0.0, side(t1));
  return std::make_shared<DistancePrimitive>(
      std::make_unique<ConeElement>(a, u, t0, t1, r0, r1, name), o, rounding);
}

}  // namespace

FieldPtr make_circle_field(const Vec3& center, const Vec3& normal, double circle_radius,
                           double radius, const DistancePrimitiveOptions& options) {
  const std::string what = "circle primitive";
  check_point(center, what + ": center");
  const Vec3 n = unit_normal(normal, what + ": normal");
  check_positive(circle_radius, what + ": circle_radius");
  check_positive(radius, what + ": radius");
  const Resolved o = resolve(options, what);
  return std::make_shared<DistancePrimitive>(
      std::make_unique<CircleElement>(center, n, circle_radius), o, radius);
}

FieldPtr make_box_field(const Vec3& center, const Vec3& half_size, double rounding,
                        const DistancePrimitiveOptions& options) {
  const std::string what = "box primitive";
  check_point(center, what + ": center");
  check_point(half_size, what + ": half_size");
  for (int k = 0; k < 3; ++k) {
    check_positive(half_size[k], what + ": half_size[" + std::to_string(k) + "]");
  }
  check_positive(rounding, what + ": rounding");
  if (rounding > half_size.minCoeff()) {
    throw InvalidArgument(what + ": rounding " + format_number(rounding) +
                          " exceeds the smallest half size " + format_number(half_size.minCoeff()));
  }
  const Resolved o = resolve(options, what);
  const Vec3 inner = (half_size - Vec3::Constant(rounding)).cwiseMax(0.0);
  return std::make_shared<DistancePrimitive>(std::make_unique<SolidBoxElement>(center, inner), o,
                                             rounding);
}

FieldPtr make_cylinder_field(const Vec3& a, const Vec3& b, double radius, double rounding,
                             const DistancePrimitiveOptions& options) {
  const std::string what = "cylinder primitive";
  check_point(a, what + ": a");
  check_point(b, what + ": b");
  const double len = (b - a).norm();
  if (!(len > 0)) throw InvalidArgument(what + ": a and b coincide at " + vec(a));
  check_positive(radius, what + ": radius");
  check_positive(rounding, what + ": rounding");
  if (rounding > radius || rounding > 0.5 * len) {
    throw InvalidArgument(what + ": rounding " + format_number(rounding) + " exceeds min(radius " +
                          format_number(radius) + ", length / 2 " + format_number(0.5 * len) + ")");
  }
  const Resolved o = resolve(options, what);
  return make_cone_like(a, radius, b, radius, rounding, o, "rounded cylinder");
}

FieldPtr make_cone_field(const Vec3& a, double ra, const Vec3& b, double rb, double rounding,
                         const DistancePrimitiveOptions& options) {
  const std::string what = "cone primitive";
  check_point(a, what + ": a");
  check_point(b, what + ": b");
  if (!((b - a).norm() > 0)) throw InvalidArgument(what + ": a and b coincide at " + vec(a));
  if (!std::isfinite(ra) || ra < 0)
    throw InvalidArgument(what + ": ra must be finite and >= 0, got " + format_number(ra));
  if (!std::isfinite(rb) || rb < 0)
    throw InvalidArgument(what + ": rb must be finite and >= 0, got " + format_number(rb));
  if (ra == 0 && rb == 0) throw InvalidArgument(what + ": ra and rb are both 0");
  check_positive(rounding, what + ": rounding");
  const Resolved o = resolve(options, what);
  return make_cone_like(a, ra, b, rb, rounding, o, "rounded cone");
}

FieldPtr make_plane_field(const Vec3& point, const Vec3& normal, double falloff,
                          const DistancePrimitiveOptions& options) {
  const std::string what = "plane primitive";
  check_point(point, what + ": point");
  const Vec3 n = unit_normal(normal, what + ": normal");
  check_positive(falloff, what + ": falloff");
  const Resolved o = resolve(options, what);
  return std::make_shared<DistancePrimitive>(std::make_unique<HalfSpaceElement>(point, n, falloff),
                                             o, falloff);
}

}  // namespace ramiform
