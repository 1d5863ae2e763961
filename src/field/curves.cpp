// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/curves.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>

#include "core/bernstein.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/portable_math.h"

namespace ramiform {
namespace {

// Upper limit on the points flatten() returns: a tolerance this far below the curve's size is a
// caller error, not a request for gigabytes.
constexpr double kMaxFlattenPoints = 1e7;

std::string kind_name(CurveKind kind) {
  switch (kind) {
    case CurveKind::kPolyline: return "polyline";
    case CurveKind::kBezier: return "bezier";
    case CurveKind::kBSpline: return "bspline";
  }
  return "unknown";
}

template <class V>
void validate_points(CurveKind kind, std::span<const V> points, bool closed, const char* what) {
  if (kind != CurveKind::kPolyline && kind != CurveKind::kBezier && kind != CurveKind::kBSpline) {
    throw InvalidArgument(std::string(what) + ": unknown curve kind " +
                          std::to_string(static_cast<int>(kind)));
  }
  const std::size_t need = closed ? 3 : 2;
  if (points.size() < need) {
    throw InvalidArgument(std::string(what) + ": a " + (closed ? "closed " : "") + kind_name(kind) +
                          " needs at least " + std::to_string(need) + " points, got " +
                          std::to_string(points.size()));
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InvalidArgument(std::string(what) + ": point " + std::to_string(i) + " is not finite");
    }
  }
}

void check_t(double t) {
  if (!(t >= 0.0 && t <= 1.0)) {
    throw InvalidArgument("curve parameter t must be in [0, 1], got " + std::to_string(t));
  }
}

// One evaluator for both dimensions; the public functions validate, this does not.
template <class V>
class CurveEval {
 public:
  CurveEval(CurveKind kind, std::span<const V> points, bool closed)
      : kind_(kind), p_(points), closed_(closed), n_(static_cast<int>(points.size())) {
    if (kind_ == CurveKind::kBSpline) degree_ = std::min(3, n_ - 1);
    if (kind_ == CurveKind::kBezier) degree_ = closed_ ? n_ : n_ - 1;
  }

  // order 0: C(t), 1: C'(t), 2: C''(t).
  V eval(double t, int order) const {
    switch (kind_) {
      case CurveKind::kPolyline: return polyline(t, order);
      case CurveKind::kBezier: return bezier(t, order);
      case CurveKind::kBSpline: return bspline(t, order);
    }
    return V::Zero();
  }

  // Flattening: parameters of the returned points (see the header).
  std::vector<double> flatten_parameters(double tol) const {
    std::vector<double> ts;
    if (kind_ == CurveKind::kPolyline) {
      const int m = pieces();
      for (int i = 0; i < n_; ++i) ts.push_back(static_cast<double>(i) / m);
      return ts;
    }
    if (kind_ == CurveKind::kBezier) {
      // C''(t) = d(d-1) sum Δ²P_i B_i,d-2(t): |C''| <= d(d-1) max |Δ²P_i|.
      double m2 = 0;
      const int d = degree_;
      for (int i = 0; i + 2 <= d; ++i) {
        m2 = std::max(m2, (ctrl(i + 2) - 2 * ctrl(i + 1) + ctrl(i)).norm());
      }
      m2 *= d * (d - 1);
      const double m = count_for(1.0, m2, tol);
      for (int i = 0; i < static_cast<int>(m); ++i) ts.push_back(i / m);
      if (!closed_) ts.push_back(1.0);
      return ts;
    }
    // B-spline: per non-empty knot span j, bound |C''(u)| by the active control points of the
    // second-derivative spline (indices j-p .. j-2) and split the span uniformly.
    const int p = degree_;
    const double u0 = domain_start(), u1 = domain_end();
    for (int j = p; j < last_span() + 1; ++j) {
      const double a = knot(j), b = knot(j + 1);
      if (!(b > a)) continue;
      double m2 = 0;
      if (p >= 2) {
        for (int i = j - p; i <= j - 2; ++i) m2 = std::max(m2, second_ctrl(i).norm());
      }
      const double m = count_for(b - a, m2, tol);
      for (int k = 0; k < static_cast<int>(m); ++k) ts.push_back((a + (b - a) * k / m - u0) / (u1 - u0));
      if (ts.size() > kMaxFlattenPoints) too_many(tol);
    }
    if (!closed_) ts.push_back(1.0);
    return ts;
  }

 private:
  int pieces() const { return closed_ ? n_ : n_ - 1; }
  const V& pt(int i) const { return p_[static_cast<std::size_t>(((i % n_) + n_) % n_)]; }
  // Bezier control point i (closed Bezier: the first point appended).
  const V& ctrl(int i) const { return pt(i); }

  static void too_many(double tol) {
    throw InvalidArgument("flatten: tolerance " + std::to_string(tol) +
                          " needs more than 1e7 points for this curve");
  }
  // Pieces of parameter length h / m with (h/m)² / 8 * m2 <= tol.
  static double count_for(double h, double m2, double tol) {
    const double m = std::max(1.0, std::ceil(h * std::sqrt(m2 / (8 * tol))));
    if (!(m <= kMaxFlattenPoints)) too_many(tol);
    return m;
  }

  V polyline(double t, int order) const {
    const int m = pieces();
    const int j = std::clamp(static_cast<int>(std::floor(t * m)), 0, m - 1);
    const V d = pt(j + 1) - pt(j);
    if (order == 0) return pt(j) + (t * m - j) * d;
    if (order == 1) return m * d;
    return V::Zero();
  }

  V bezier(double t, int order) const {
    const int d = degree_;
    if (order > d) return V::Zero();
    constexpr int kSmall = 16;
    std::array<V, kSmall> small;
    std::vector<V> large;
    V* w = small.data();
    if (d + 1 > kSmall) {
      large.resize(static_cast<std::size_t>(d) + 1);
      w = large.data();
    }
    for (int i = 0; i <= d; ++i) w[i] = ctrl(i);
    return detail::casteljau_in_place(w, d, t, order, V(V::Zero()));
  }

  // B-spline knots: open clamped over [0, 1], or uniform integers (periodic, domain [p, p+n]).
  double knot(int i) const {
    const int p = degree_;
    if (closed_) return i;
    if (i <= p) return 0.0;
    if (i >= n_) return 1.0;
    return static_cast<double>(i - p) / (n_ - p);
  }
  double domain_start() const { return closed_ ? degree_ : 0.0; }
  double domain_end() const { return closed_ ? degree_ + n_ : 1.0; }
  int last_span() const { return closed_ ? n_ + degree_ - 1 : n_ - 1; }
  // Control point i of the (extended, for periodic) control polygon.
  const V& bctrl(int i) const { return pt(i); }
  V first_ctrl(int i) const {
    const int p = degree_;
    return p * (bctrl(i + 1) - bctrl(i)) / (knot(i + p + 1) - knot(i + 1));
  }
  V second_ctrl(int i) const {
    const int p = degree_;
    return (p - 1) * (first_ctrl(i + 1) - first_ctrl(i)) / (knot(i + p + 1) - knot(i + 2));
  }

  V bspline(double t, int order) const {
    const int p = degree_;
    const double u0 = domain_start(), u1 = domain_end();
    const double u = u0 + t * (u1 - u0);
    // The span j with knot(j) <= u < knot(j + 1) (the last span at the domain's end).
    int j = closed_ ? static_cast<int>(std::floor(u)) : p + static_cast<int>(std::floor(u * (n_ - p)));
    j = std::clamp(j, p, last_span());
    while (j > p && u < knot(j)) --j;
    while (j < last_span() && !(u < knot(j + 1))) ++j;
    const int deg = p - order;
    if (deg < 0) return V::Zero();
    // de Boor on the `order`-th derivative spline: its control point i is D_i, its knot i is
    // knot(i + order); the span index shifts by `order`.
    auto control = [&](int i) -> V {
      if (order == 0) return bctrl(i);
      if (order == 1) return first_ctrl(i);
      return second_ctrl(i);
    };
    auto kn = [&](int i) { return knot(i + order); };
    const int js = j - order;
    std::array<V, 4> d;
    for (int k = 0; k <= deg; ++k) d[k] = control(k + js - deg);
    for (int r = 1; r <= deg; ++r) {
      for (int k = deg; k >= r; --k) {
        const double lo = kn(k + js - deg);
        const double hi = kn(k + 1 + js - r);
        const double alpha = (u - lo) / (hi - lo);
        d[k] = (1 - alpha) * d[k - 1] + alpha * d[k];
      }
    }
    const double chain = pm::pow(u1 - u0, order);
    return chain * d[deg];
  }

  CurveKind kind_;
  std::span<const V> p_;
  bool closed_;
  int n_;
  int degree_ = 1;
};

template <class V>
std::vector<V> points_at(const CurveEval<V>& eval, const std::vector<double>& ts) {
  std::vector<V> out;
  out.reserve(ts.size());
  for (const double t : ts) out.push_back(eval.eval(t, 0));
  return out;
}

void check_tolerance(double tolerance) {
  if (!std::isfinite(tolerance) || tolerance <= 0) {
    throw InvalidArgument("flatten: tolerance must be finite and > 0, got " + std::to_string(tolerance));
  }
}

CurveEval<Vec3> eval_of(const Curve3& c) { return {c.kind, c.points, false}; }
CurveEval<Vec2> eval_of(const Curve2& c) { return {c.kind, c.points, c.closed}; }

}  // namespace

void validate(const Curve2& curve) {
  validate_points<Vec2>(curve.kind, curve.points, curve.closed, "2-D curve");
}
void validate(const Curve3& curve) { validate_points<Vec3>(curve.kind, curve.points, false, "3-D curve"); }

namespace {

// A checked evaluation of a curve (or of its derivative of `order`) at t.
template <class Curve>
auto checked_eval(const Curve& curve, double t, int order) {
  validate(curve);
  check_t(t);
  return eval_of(curve).eval(t, order);
}

// flatten_with_parameters for either curve type: polylines keep their points as they are.
template <class Flattened, class Curve>
Flattened flatten_curve(const Curve& curve, double tolerance) {
  validate(curve);
  check_tolerance(tolerance);
  Flattened out;
  const auto eval = eval_of(curve);
  out.parameters = eval.flatten_parameters(tolerance);
  out.points = curve.kind == CurveKind::kPolyline ? curve.points : points_at(eval, out.parameters);
  return out;
}

}  // namespace

Vec3 curve_point(const Curve3& curve, double t) { return checked_eval(curve, t, 0); }
Vec2 curve_point(const Curve2& curve, double t) { return checked_eval(curve, t, 0); }
Vec3 curve_derivative(const Curve3& curve, double t) { return checked_eval(curve, t, 1); }
Vec2 curve_derivative(const Curve2& curve, double t) { return checked_eval(curve, t, 1); }
Vec3 curve_second_derivative(const Curve3& curve, double t) { return checked_eval(curve, t, 2); }

FlattenedCurve3 flatten_with_parameters(const Curve3& curve, double tolerance) {
  return flatten_curve<FlattenedCurve3>(curve, tolerance);
}

FlattenedCurve2 flatten_with_parameters(const Curve2& curve, double tolerance) {
  return flatten_curve<FlattenedCurve2>(curve, tolerance);
}

std::vector<Vec2> flatten(const Curve2& curve, double tolerance) {
  return flatten_with_parameters(curve, tolerance).points;
}
std::vector<Vec3> flatten(const Curve3& curve, double tolerance) {
  return flatten_with_parameters(curve, tolerance).points;
}

}  // namespace ramiform
