// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/warps.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/field/operators.h"

namespace ramiform {
namespace {

using Vec2 = Eigen::Vector2d;
using Box2 = Eigen::AlignedBox2d;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;
// Relative growth (times the largest coordinate magnitude) of every box passed down or up, so
// that rounding in the maps (different operation order than the enclosures) stays inside.
constexpr double kBoxSlack = 1e-9;

Aabb padded(Aabb b) {
  if (b.isEmpty()) return b;
  double scale = 0;
  for (int k = 0; k < 3; ++k) {
    if (std::isfinite(b.min()[k])) scale = std::max(scale, std::abs(b.min()[k]));
    if (std::isfinite(b.max()[k])) scale = std::max(scale, std::abs(b.max()[k]));
  }
  const double pad = kBoxSlack * scale + std::numeric_limits<double>::min();
  for (int k = 0; k < 3; ++k) {
    b.min()[k] -= pad;
    b.max()[k] += pad;
  }
  return b;
}

// Rotation of (x, y) by phi (counter-clockwise).
Vec2 rotate(const Vec2& p, double phi) {
  const double c = pm::cos(phi), s = pm::sin(phi);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

// Box of the arc {rotate(p, phi) : phi in [phi0, phi1]}: its end points and the points where it
// crosses a coordinate axis (multiples of pi/2 of the polar angle).
Box2 arc_box(const Vec2& p, double phi0, double phi1) {
  const double rho = p.norm();
  Box2 box;
  if (!(phi1 - phi0 < 2 * kPi)) {
    box.extend(Vec2(-rho, -rho));
    box.extend(Vec2(rho, rho));
    return box;
  }
  box.extend(rotate(p, phi0));
  box.extend(rotate(p, phi1));
  if (rho == 0) return box;
  const double alpha = pm::atan2(p.y(), p.x());
  const double quarter = kPi / 2;
  // Every multiple of pi/2 in [alpha + phi0, alpha + phi1] (widened by rounding: extra axis
  // points only make the box larger).
  const double lo = (alpha + phi0) / quarter - 1e-12;
  const double hi = (alpha + phi1) / quarter + 1e-12;
  for (double k = std::ceil(lo); k <= hi; k += 1) {
    const long q = static_cast<long>(k);
    switch (((q % 4) + 4) % 4) {
      case 0:
        box.extend(Vec2(rho, 0));
        break;
      case 1:
        box.extend(Vec2(0, rho));
        break;
      case 2:
        box.extend(Vec2(-rho, 0));
        break;
      default:
        box.extend(Vec2(0, -rho));
        break;
    }
  }
  return box;
}

// The map behind a warp field: W^-1 with its Jacobian, and conservative boxes both ways.
class WarpMap {
 public:
  virtual ~WarpMap() = default;
  /// W^-1(p) and, when `jacobian` is not null, its Jacobian d W^-1 / dp.
  virtual Vec3 inverse(const Vec3& p, Mat3* jacobian) const = 0;
  /// A box containing W^-1(box) (box non-empty).
  virtual Aabb inverse_box(const Aabb& box) const = 0;
  /// A box containing W(box) (box non-empty).
  virtual Aabb forward_box(const Aabb& box) const = 0;
  virtual std::string describe() const = 0;
};

// A CompositeField: warps count towards the nesting depth limit of operators.h.
class WarpField final : public CompositeField {
 public:
  WarpField(FieldPtr child, std::shared_ptr<const WarpMap> map, const char* what)
      : CompositeField(child->iso(), std::span<const FieldPtr>(&child, 1), what),
        child_(std::move(child)),
        map_(std::move(map)) {}
  WarpField(const WarpField& source, FieldPtr child)
      : CompositeField(source.iso(), source), child_(std::move(child)), map_(source.map_) {}

  Interval bound(const Aabb& box) const override {
    if (box.isEmpty()) return child_->bound(box);
    return child_->bound(padded(map_->inverse_box(box)));
  }
  Aabb bounds() const override {
    const Aabb b = child_->bounds();
    if (b.isEmpty()) return b;
    return padded(map_->forward_box(b));
  }
  FieldPtr restrict(const Aabb& box) const override {
    if (box.isEmpty()) return shared_from_this();
    FieldPtr r = child_->restrict(padded(map_->inverse_box(box)));
    if (r == child_) return shared_from_this();
    return std::make_shared<WarpField>(*this, std::move(r));
  }
  std::string describe() const override {
    // The child's description cut short: a chain of warps stays linear in its length.
    constexpr std::size_t kMaxChildText = 200;
    std::string child = child_->describe();
    if (child.size() > kMaxChildText) {
      child.resize(kMaxChildText);
      child += "...";
    }
    return map_->describe() + " of (" + child + ")";
  }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    const std::size_t n = points.size();
    std::vector<Vec3> local(n);
    if (gradients.empty()) {
      for (std::size_t i = 0; i < n; ++i) local[i] = map_->inverse(points[i], nullptr);
      child_->evaluate(local, values, {}, ctx);
      return;
    }
    std::vector<Mat3> jacobians(n);
    for (std::size_t i = 0; i < n; ++i) local[i] = map_->inverse(points[i], &jacobians[i]);
    child_->evaluate(local, values, gradients, ctx);
    for (std::size_t i = 0; i < n; ++i) gradients[i] = jacobians[i].transpose() * gradients[i];
  }

 private:
  FieldPtr child_;
  std::shared_ptr<const WarpMap> map_;
};

// ---- taper ----

double taper_scale(double t, const TaperOptions& o, double* derivative) {
  const double u = (t - o.start) / (o.end - o.start);
  if (derivative != nullptr) {
    *derivative = u > 0 && u < 1 ? (o.scale_end - o.scale_start) / (o.end - o.start) : 0.0;
  }
  const double c = std::clamp(u, 0.0, 1.0);
  return o.scale_start + c * (o.scale_end - o.scale_start);
}

class TaperMap final : public WarpMap {
 public:
  explicit TaperMap(const TaperOptions& o) : o_(o) {}
  Vec3 inverse(const Vec3& p, Mat3* jacobian) const override {
    double dr = 0;
    const int a = o_.axis;
    const double r = taper_scale(p[a], o_, &dr);
    Vec3 q = p / r;
    q[a] = p[a];
    if (jacobian != nullptr) {
      Mat3& J = *jacobian;
      J.setZero();
      for (int k = 0; k < 3; ++k) {
        if (k == a) continue;
        J(k, k) = 1 / r;
        J(k, a) = -p[k] * dr / (r * r);
      }
      J(a, a) = 1;
    }
    return q;
  }
  Aabb inverse_box(const Aabb& box) const override { return scaled(box, true); }
  Aabb forward_box(const Aabb& box) const override { return scaled(box, false); }
  std::string describe() const override {
    return "taper along axis " + std::to_string(o_.axis) + " (scale " +
           format_number(o_.scale_start) + " at " + format_number(o_.start) + " to " +
           format_number(o_.scale_end) + " at " + format_number(o_.end) + ")";
  }

 private:
  // The coordinates across the axis times r(t) (forward) or divided by it (inverse), over every
  // t of the box: r is monotone, so its range is spanned by the two ends of the t range, and
  // x s for s > 0 is monotone in s with the sign of x.
  Aabb scaled(const Aabb& box, bool inverse) const {
    const int a = o_.axis;
    const double r0 = taper_scale(box.min()[a], o_, nullptr);
    const double r1 = taper_scale(box.max()[a], o_, nullptr);
    double s_lo = std::min(r0, r1), s_hi = std::max(r0, r1);
    if (inverse) {
      const double lo = 1 / s_hi, hi = 1 / s_lo;
      s_lo = lo;
      s_hi = hi;
    }
    Aabb out = box;
    for (int k = 0; k < 3; ++k) {
      if (k == a) continue;
      out.min()[k] = std::min(box.min()[k] * s_lo, box.min()[k] * s_hi);
      out.max()[k] = std::max(box.max()[k] * s_lo, box.max()[k] * s_hi);
    }
    return out;
  }

  TaperOptions o_;
};

// ---- twist ----

class TwistMap final : public WarpMap {
 public:
  explicit TwistMap(const TwistOptions& o) : o_(o) {}
  Vec3 inverse(const Vec3& p, Mat3* jacobian) const override {
    const Vec3 q = twist_inverse(p, o_);
    if (jacobian != nullptr) {
      const int t = o_.axis, u = (t + 1) % 3, v = (t + 2) % 3;
      const double theta = o_.rate * (p[t] - o_.origin);
      const double c = pm::cos(theta), s = pm::sin(theta);
      Mat3& J = *jacobian;
      J.setZero();
      J(u, u) = c;
      J(u, v) = s;
      J(u, t) = o_.rate * q[v];
      J(v, u) = -s;
      J(v, v) = c;
      J(v, t) = -o_.rate * q[u];
      J(t, t) = 1;
    }
    return q;
  }
  Aabb inverse_box(const Aabb& box) const override { return rotated(box, -1); }
  Aabb forward_box(const Aabb& box) const override { return rotated(box, 1); }
  std::string describe() const override {
    return "twist about axis " + std::to_string(o_.axis) + " (" + format_number(o_.rate) +
           " rad per unit from " + format_number(o_.origin) + ")";
  }

 private:
  // Union of the arcs swept by the box's corners (across the axis) over every angle of the box's
  // t range: the box of each rotated rectangle is the box of its rotated corners.
  Aabb rotated(const Aabb& box, double sign) const {
    const int t = o_.axis, u = (t + 1) % 3, v = (t + 2) % 3;
    if (o_.rate == 0) return box;
    Aabb out = box;
    if (!std::isfinite(box.min()[u]) || !std::isfinite(box.max()[u]) ||
        !std::isfinite(box.min()[v]) || !std::isfinite(box.max()[v])) {
      out.min()[u] = out.min()[v] = -kInf;
      out.max()[u] = out.max()[v] = kInf;
      return out;
    }
    const double a0 = sign * o_.rate * (box.min()[t] - o_.origin);
    const double a1 = sign * o_.rate * (box.max()[t] - o_.origin);
    const double phi0 = std::min(a0, a1), phi1 = std::max(a0, a1);
    Box2 uv;
    for (int cu = 0; cu < 2; ++cu) {
      for (int cv = 0; cv < 2; ++cv) {
        const Vec2 p(cu ? box.max()[u] : box.min()[u], cv ? box.max()[v] : box.min()[v]);
        uv.extend(arc_box(p, phi0, phi1));
      }
    }
    out.min()[u] = uv.min().x();
    out.max()[u] = uv.max().x();
    out.min()[v] = uv.min().y();
    out.max()[v] = uv.max().y();
    return out;
  }

  TwistOptions o_;
};

// ---- bend ----

// Barr's bend, written so that it stays accurate for small rates: S/k = sin(theta)/k and
// (1 - C)/k = 2 sin^2(theta/2)/k instead of differences with 1/k.
struct BendParts {
  double theta = 0, c = 1, s = 0;
  double s_over_k = 0, one_minus_c_over_k = 0;
};

BendParts bend_parts(double y_hat, const BendOptions& o) {
  BendParts b;
  const double k = o.rate;
  b.theta = k * (y_hat - o.center);
  b.c = pm::cos(b.theta);
  b.s = pm::sin(b.theta);
  const double h = pm::sin(0.5 * b.theta);
  b.s_over_k = b.s / k;
  b.one_minus_c_over_k = 2 * h * h / k;
  return b;
}

// The angle of (Y, Z) around the centre of curvature (y0, 1/k) in Barr's sense: the theta that
// the unclamped bend would give, measured within pi of the middle of the bent region so that
// the straight continuations on both sides stay on their own side of the branch cut.
double bend_angle(double Y, double Z, const BendOptions& o) {
  const double k = o.rate;
  const double s = k * (Y - o.center);  // m k sin(theta), m = 1/k - z
  const double c = 1 - k * Z;           // m k cos(theta)
  const double mid = k * (0.5 * (o.min + o.max) - o.center);
  const double cm = pm::cos(mid), sm = pm::sin(mid);
  return mid + pm::atan2(s * cm - c * sm, c * cm + s * sm);
}

// The inverse with a fixed (clamped or not) y^.
Vec3 bend_inverse_at(const Vec3& p, double y_hat, const BendOptions& o) {
  const BendParts b = bend_parts(y_hat, o);
  const double a = p.y() - o.center;
  // (y - y^, z - 1/k) = R(-theta) (Y - y0, Z - 1/k).
  const double y = o.center + (b.theta / o.rate - b.s_over_k) + b.c * a + b.s * p.z();
  const double z = b.c * p.z() + b.one_minus_c_over_k - b.s * a;
  return {p.x(), y, z};
}

double bend_y_hat(const Vec3& p, const BendOptions& o, bool* clamped) {
  const double eta = o.center + bend_angle(p.y(), p.z(), o) / o.rate;
  const double y_hat = std::clamp(eta, o.min, o.max);
  if (clamped != nullptr) *clamped = !(eta > o.min && eta < o.max);
  return y_hat;
}

class BendMap final : public WarpMap {
 public:
  explicit BendMap(const BendOptions& o) : o_(o) {}
  Vec3 inverse(const Vec3& p, Mat3* jacobian) const override {
    if (o_.rate == 0) {
      if (jacobian != nullptr) jacobian->setIdentity();
      return p;
    }
    bool clamped = false;
    const double y_hat = bend_y_hat(p, o_, &clamped);
    const Vec3 q = bend_inverse_at(p, y_hat, o_);
    if (jacobian != nullptr) {
      const BendParts b = bend_parts(y_hat, o_);
      Mat3& J = *jacobian;
      J.setZero();
      J(0, 0) = 1;
      J(1, 1) = b.c;
      J(1, 2) = b.s;
      J(2, 1) = -b.s;
      J(2, 2) = b.c;
      if (!clamped) {
        // theta = atan2(k (Y - y0), 1 - k Z) moves with the point: dy/dtheta = z,
        // dz/dtheta = -(y - y^).
        const double k = o_.rate;
        const double s = k * (p.y() - o_.center), c = 1 - k * p.z();
        const double r2 = s * s + c * c;
        if (r2 > 0) {
          const double dY = c * k / r2, dZ = s * k / r2;
          J(1, 1) += q.z() * dY;
          J(1, 2) += q.z() * dZ;
          J(2, 1) -= (q.y() - y_hat) * dY;
          J(2, 2) -= (q.y() - y_hat) * dZ;
        }
      }
    }
    return q;
  }

  Aabb inverse_box(const Aabb& box) const override {
    if (o_.rate == 0) return box;
    Aabb out = box;
    if (!yz_finite(box)) return infinite_yz(box);
    const double k = o_.rate;
    const double y0 = o_.center;
    const Vec2 centre(y0, 1 / k);
    Vec3 corners[4];
    for (int i = 0; i < 4; ++i) {
      corners[i] =
          Vec3(0, i & 1 ? box.max().y() : box.min().y(), i & 2 ? box.max().z() : box.min().z());
    }
    // Range of the unclamped y^ (eta) over the rectangle: from its corners unless the rectangle
    // holds the centre of curvature or crosses the branch cut of bend_angle (then everything).
    double eta_lo = -kInf, eta_hi = kInf;
    const bool holds_centre = box.min().y() <= centre.x() && centre.x() <= box.max().y() &&
                              box.min().z() <= centre.y() && centre.y() <= box.max().z();
    if (!holds_centre) {
      const double mid = k * (0.5 * (o_.min + o_.max) - y0);
      double a_lo = kInf, a_hi = -kInf;
      for (const Vec3& c : corners) {
        const double a = bend_angle(c.y(), c.z(), o_);
        a_lo = std::min(a_lo, a);
        a_hi = std::max(a_hi, a);
      }
      // A rectangle not holding the centre subtends less than pi from it; a larger spread of
      // the corner angles means that it straddles the cut (at mid ± pi).
      const double near_cut = kPi - 1e-9;
      if (a_hi - a_lo < kPi && a_lo - mid > -near_cut && a_hi - mid < near_cut) {
        const double e0 = y0 + a_lo / k, e1 = y0 + a_hi / k;
        eta_lo = std::min(e0, e1);
        eta_hi = std::max(e0, e1);
      }
    }
    Box2 yz;
    auto rigid = [&](double y_hat) {
      for (const Vec3& c : corners) {
        const Vec3 q = bend_inverse_at(c, y_hat, o_);
        yz.extend(Vec2(q.y(), q.z()));
      }
    };
    if (eta_lo < o_.min) rigid(o_.min);
    if (eta_hi > o_.max) rigid(o_.max);
    const double y_lo = std::max(eta_lo, o_.min), y_hi = std::min(eta_hi, o_.max);
    if (y_lo <= y_hi) {
      // In the bent region y = y^ and z = 1/k - sign(k) |(Y, Z) - centre|.
      const Vec2 lo(box.min().y(), box.min().z()), hi(box.max().y(), box.max().z());
      const double r_min = (lo - centre).cwiseMax(centre - hi).cwiseMax(Vec2::Zero()).norm();
      double r_max = 0;
      for (const Vec3& c : corners) r_max = std::max(r_max, (Vec2(c.y(), c.z()) - centre).norm());
      const double slack = 1e-12 * (std::abs(1 / k) + r_max);
      const double z0 = k > 0 ? 1 / k - r_max : 1 / k + r_min;
      const double z1 = k > 0 ? 1 / k - r_min : 1 / k + r_max;
      yz.extend(Vec2(y_lo, z0 - slack));
      yz.extend(Vec2(y_hi, z1 + slack));
    }
    out.min().y() = yz.min().x();
    out.max().y() = yz.max().x();
    out.min().z() = yz.min().y();
    out.max().z() = yz.max().y();
    return out;
  }

  Aabb forward_box(const Aabb& box) const override {
    if (o_.rate == 0) return box;
    if (!yz_finite(box)) return infinite_yz(box);
    const double k = o_.rate;
    Box2 yz;
    const double ylo = box.min().y(), yhi = box.max().y();
    const double zlo = box.min().z(), zhi = box.max().z();
    // The straight parts move rigidly: the box of the mapped corners of their sub-box.
    auto rigid = [&](double y_a, double y_b) {
      for (const double y : {y_a, y_b}) {
        for (const double z : {zlo, zhi}) {
          const Vec3 q = bend_forward(Vec3(0, y, z), o_);
          yz.extend(Vec2(q.y(), q.z()));
        }
      }
    };
    if (ylo < o_.min) rigid(ylo, std::min(yhi, o_.min));
    if (yhi > o_.max) rigid(std::max(ylo, o_.max), yhi);
    const double y1 = std::max(ylo, o_.min), y2 = std::min(yhi, o_.max);
    if (y1 <= y2) {
      // The bent part: (Y - y0, Z - 1/k) = R(theta) (0, z - 1/k), arcs of the two z extremes.
      const double t1 = k * (y1 - o_.center), t2 = k * (y2 - o_.center);
      const Vec2 centre(o_.center, 1 / k);
      const double slack = 1e-12 * (std::abs(1 / k) + std::abs(zlo) + std::abs(zhi));
      for (const double z : {zlo, zhi}) {
        const Box2 arc = arc_box(Vec2(0, z - 1 / k), std::min(t1, t2), std::max(t1, t2));
        yz.extend(Vec2(arc.min() + centre - Vec2::Constant(slack)));
        yz.extend(Vec2(arc.max() + centre + Vec2::Constant(slack)));
      }
    }
    Aabb out = box;
    out.min().y() = yz.min().x();
    out.max().y() = yz.max().x();
    out.min().z() = yz.min().y();
    out.max().z() = yz.max().y();
    return out;
  }

  std::string describe() const override {
    return "bend (rate " + format_number(o_.rate) + " about y = " + format_number(o_.center) +
           ", region y in [" + format_number(o_.min) + ", " + format_number(o_.max) + "])";
  }

 private:
  static bool yz_finite(const Aabb& b) {
    return std::isfinite(b.min().y()) && std::isfinite(b.max().y()) && std::isfinite(b.min().z()) &&
           std::isfinite(b.max().z());
  }
  static Aabb infinite_yz(Aabb b) {
    b.min().y() = b.min().z() = -kInf;
    b.max().y() = b.max().z() = kInf;
    return b;
  }

  BendOptions o_;
};

void check_child(const FieldPtr& child, const char* what) {
  if (!child) throw InvalidArgument(std::string(what) + ": null child");
}

void check_finite(double v, const std::string& what) {
  if (!std::isfinite(v)) throw InvalidArgument(what + " must be finite, got " + format_number(v));
}

void check_axis(int axis, const std::string& what) {
  if (axis < 0 || axis > 2) {
    throw InvalidArgument(what + " must be 0, 1 or 2, got " + std::to_string(axis));
  }
}

}  // namespace

Vec3 taper_forward(const Vec3& p, const TaperOptions& options) {
  const double r = taper_scale(p[options.axis], options, nullptr);
  Vec3 q = p * r;
  q[options.axis] = p[options.axis];
  return q;
}

Vec3 taper_inverse(const Vec3& p, const TaperOptions& options) {
  const double r = taper_scale(p[options.axis], options, nullptr);
  Vec3 q = p / r;
  q[options.axis] = p[options.axis];
  return q;
}

namespace {

// The twist's rotation about its axis at p's height, by the angle times `sign` (+1: the
// forward map, -1: its inverse).
Vec3 twist_by(const Vec3& p, const TwistOptions& options, double sign) {
  if (options.rate == 0) return p;
  const int t = options.axis, u = (t + 1) % 3, v = (t + 2) % 3;
  const double theta = options.rate * (p[t] - options.origin);
  const double c = pm::cos(theta), s = sign * pm::sin(theta);
  Vec3 q = p;
  q[u] = c * p[u] - s * p[v];
  q[v] = s * p[u] + c * p[v];
  return q;
}

}  // namespace

Vec3 twist_forward(const Vec3& p, const TwistOptions& options) { return twist_by(p, options, 1.0); }

Vec3 twist_inverse(const Vec3& p, const TwistOptions& options) {
  return twist_by(p, options, -1.0);
}

Vec3 bend_forward(const Vec3& p, const BendOptions& options) {
  if (options.rate == 0) return p;
  const double y_hat = std::clamp(p.y(), options.min, options.max);
  const BendParts b = bend_parts(y_hat, options);
  const double along = p.y() - y_hat;
  // Y = -S (z - 1/k) + y0 + C (y - y^),  Z = C (z - 1/k) + 1/k + S (y - y^).
  const double Y = options.center + b.s_over_k - b.s * p.z() + b.c * along;
  const double Z = b.c * p.z() + b.one_minus_c_over_k + b.s * along;
  return {p.x(), Y, Z};
}

Vec3 bend_inverse(const Vec3& p, const BendOptions& options) {
  if (options.rate == 0) return p;
  return bend_inverse_at(p, bend_y_hat(p, options, nullptr), options);
}

FieldPtr make_taper(FieldPtr child, const TaperOptions& options) {
  check_child(child, "taper");
  check_axis(options.axis, "taper: axis");
  check_finite(options.start, "taper: start");
  check_finite(options.end, "taper: end");
  if (!(options.start < options.end)) {
    throw InvalidArgument("taper: start (" + format_number(options.start) +
                          ") must be below end (" + format_number(options.end) + ")");
  }
  for (const auto& [v, name] :
       {std::pair{options.scale_start, "scale_start"}, std::pair{options.scale_end, "scale_end"}}) {
    if (!std::isfinite(v) || v <= 0) {
      throw InvalidArgument(std::string("taper: ") + name + " must be finite and > 0, got " +
                            format_number(v));
    }
  }
  return std::make_shared<WarpField>(std::move(child), std::make_shared<TaperMap>(options),
                                     "taper");
}

FieldPtr make_twist(FieldPtr child, const TwistOptions& options) {
  check_child(child, "twist");
  check_axis(options.axis, "twist: axis");
  check_finite(options.rate, "twist: rate");
  check_finite(options.origin, "twist: origin");
  return std::make_shared<WarpField>(std::move(child), std::make_shared<TwistMap>(options),
                                     "twist");
}

FieldPtr make_bend(FieldPtr child, const BendOptions& options) {
  check_child(child, "bend");
  check_finite(options.rate, "bend: rate");
  check_finite(options.center, "bend: center");
  check_finite(options.min, "bend: min");
  check_finite(options.max, "bend: max");
  if (!(options.min <= options.center && options.center <= options.max)) {
    throw InvalidArgument("bend: need min <= center <= max, got min " + format_number(options.min) +
                          ", center " + format_number(options.center) + ", max " +
                          format_number(options.max));
  }
  return std::make_shared<WarpField>(std::move(child), std::make_shared<BendMap>(options), "bend");
}

}  // namespace ramiform
