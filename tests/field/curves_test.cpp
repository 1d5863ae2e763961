// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/curves.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

double binomial(int n, int k) {
  double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

// Bezier point by the Bernstein formula sum C(d, i) t^i (1 - t)^(d - i) P_i.
template <class V>
V bernstein(const std::vector<V>& p, double t) {
  const int d = static_cast<int>(p.size()) - 1;
  V out = V::Zero();
  for (int i = 0; i <= d; ++i) out += binomial(d, i) * std::pow(t, i) * std::pow(1 - t, d - i) * p[i];
  return out;
}

// Cox–de Boor recursion for the basis function N_{i,p}(u) (right-open spans; the last span is
// closed so that u = the last knot evaluates).
double cox_de_boor(const std::vector<double>& U, int i, int p, double u) {
  if (p == 0) {
    const double last = U.back();
    if (u == last) return U[i] < last && U[i + 1] == last ? 1.0 : 0.0;
    return U[i] <= u && u < U[i + 1] ? 1.0 : 0.0;
  }
  double a = 0, b = 0;
  if (U[i + p] > U[i]) a = (u - U[i]) / (U[i + p] - U[i]) * cox_de_boor(U, i, p - 1, u);
  if (U[i + p + 1] > U[i + 1]) b = (U[i + p + 1] - u) / (U[i + p + 1] - U[i + 1]) * cox_de_boor(U, i + 1, p - 1, u);
  return a + b;
}

// Clamped uniform B-spline of degree min(3, n-1) by the basis functions.
Vec2 reference_clamped(const std::vector<Vec2>& P, double t) {
  const int n = static_cast<int>(P.size());
  const int p = std::min(3, n - 1);
  std::vector<double> U;
  for (int i = 0; i <= p; ++i) U.push_back(0);
  for (int i = 1; i < n - p; ++i) U.push_back(static_cast<double>(i) / (n - p));
  for (int i = 0; i <= p; ++i) U.push_back(1);
  Vec2 out = Vec2::Zero();
  for (int i = 0; i < n; ++i) out += cox_de_boor(U, i, p, t) * P[i];
  return out;
}

// Uniform periodic cubic B-spline by the basis matrix: segment k (t in [k/n, (k+1)/n]) uses
// P_k .. P_k+3 (indices modulo n).
Vec2 reference_periodic_cubic(const std::vector<Vec2>& P, double t) {
  const int n = static_cast<int>(P.size());
  const int k = std::min(n - 1, static_cast<int>(std::floor(t * n)));
  const double u = t * n - k;
  auto at = [&](int i) { return P[static_cast<std::size_t>(i % n)]; };
  return ((1 - u) * (1 - u) * (1 - u) * at(k) + (3 * u * u * u - 6 * u * u + 4) * at(k + 1) +
          (-3 * u * u * u + 3 * u * u + 3 * u + 1) * at(k + 2) + u * u * u * at(k + 3)) /
         6.0;
}

// Convex hull (monotone chain), counter-clockwise.
std::vector<Vec2> convex_hull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Vec2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// Signed margin of q inside a counter-clockwise convex polygon (>= 0 inside).
double hull_margin(const std::vector<Vec2>& h, const Vec2& q) {
  double m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < h.size(); ++i) {
    const Vec2 a = h[i], b = h[(i + 1) % h.size()];
    const Vec2 e = (b - a).normalized();
    m = std::min(m, e.x() * (q - a).y() - e.y() * (q - a).x());
  }
  return m;
}

template <class V>
double segment_distance(const V& q, const V& a, const V& b) {
  const V ab = b - a;
  const double l2 = ab.squaredNorm();
  const double u = l2 > 0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (q - (a + u * ab)).norm();
}

template <class V>
double polyline_distance(const V& q, const std::vector<V>& pts, bool closed) {
  double best = std::numeric_limits<double>::infinity();
  const std::size_t segs = closed ? pts.size() : pts.size() - 1;
  for (std::size_t i = 0; i < segs; ++i) {
    best = std::min(best, segment_distance(q, pts[i], pts[(i + 1) % pts.size()]));
  }
  return best;
}

std::vector<Vec2> random_points2(Rng& rng, int n, double scale = 1.0) {
  std::vector<Vec2> p;
  for (int i = 0; i < n; ++i) p.emplace_back(scale * rng.uniform(-1, 1), scale * rng.uniform(-1, 1));
  return p;
}

std::vector<Vec3> random_points3(Rng& rng, int n) {
  std::vector<Vec3> p;
  for (int i = 0; i < n; ++i) p.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  return p;
}

TEST(CurveBezier, MatchesBernsteinFormula) {
  Rng rng(11);
  for (int n = 2; n <= 9; ++n) {
    Curve3 c{CurveKind::kBezier, random_points3(rng, n)};
    for (int i = 0; i <= 40; ++i) {
      const double t = i / 40.0;
      EXPECT_LT((curve_point(c, t) - bernstein(c.points, t)).norm(), 1e-13) << n << " " << t;
      // Derivative: d sum (P_i+1 - P_i) B_i,d-1 (Bernstein form of the hodograph).
      std::vector<Vec3> hodo;
      for (int k = 0; k + 1 < n; ++k) hodo.push_back((n - 1) * (c.points[k + 1] - c.points[k]));
      EXPECT_LT((curve_derivative(c, t) - bernstein(hodo, t)).norm(), 1e-12) << n << " " << t;
      if (t > 0.01 && t < 0.99) {
        const double h = 1e-5;
        const Vec3 fd = (curve_derivative(c, t + h) - curve_derivative(c, t - h)) / (2 * h);
        EXPECT_LT((curve_second_derivative(c, t) - fd).norm(), 1e-5 * (1 + fd.norm()));
      }
    }
    EXPECT_EQ(curve_point(c, 0), c.points.front());
    EXPECT_EQ(curve_point(c, 1), c.points.back());
  }
  // Closed: the first point is appended as the last control point.
  Curve2 closed{CurveKind::kBezier, random_points2(rng, 4), true};
  std::vector<Vec2> ctrl = closed.points;
  ctrl.push_back(ctrl.front());
  for (int i = 0; i <= 20; ++i) {
    EXPECT_LT((curve_point(closed, i / 20.0) - bernstein(ctrl, i / 20.0)).norm(), 1e-13);
  }
}

TEST(CurveBSpline, ClampedMatchesCoxDeBoorPassesEndsAndStaysInHull) {
  Rng rng(12);
  for (int n = 2; n <= 9; ++n) {
    for (int rep = 0; rep < 3; ++rep) {
      Curve2 c{CurveKind::kBSpline, random_points2(rng, n), false};
      EXPECT_LT((curve_point(c, 0) - c.points.front()).norm(), 1e-14);
      EXPECT_LT((curve_point(c, 1) - c.points.back()).norm(), 1e-14);
      const auto hull = convex_hull(c.points);
      for (int i = 0; i <= 100; ++i) {
        const double t = i / 100.0;
        const Vec2 q = curve_point(c, t);
        EXPECT_LT((q - reference_clamped(c.points, t)).norm(), 1e-12) << n << " t " << t;
        if (hull.size() >= 3) {
          EXPECT_GE(hull_margin(hull, q), -1e-12) << n << " t " << t;
        }
        if (t > 0.005 && t < 0.995) {
          const double h = 1e-6;
          const Vec2 fd = (curve_point(c, std::min(1.0, t + h)) - curve_point(c, std::max(0.0, t - h))) / (2 * h);
          EXPECT_LT((curve_derivative(c, t) - fd).norm(), 1e-5 * (1 + fd.norm())) << n << " t " << t;
        }
      }
    }
  }
}

TEST(CurveBSpline, PeriodicCubicMatchesBasisMatrixAndCloses) {
  Rng rng(13);
  for (int n = 4; n <= 8; ++n) {
    Curve2 c{CurveKind::kBSpline, random_points2(rng, n), true};
    for (int i = 0; i <= 97; ++i) {
      const double t = i / 97.0;
      EXPECT_LT((curve_point(c, t) - reference_periodic_cubic(c.points, t)).norm(), 1e-13) << n << " " << t;
    }
    EXPECT_LT((curve_point(c, 0) - curve_point(c, 1)).norm(), 1e-13);
    EXPECT_LT((curve_derivative(c, 0) - curve_derivative(c, 1)).norm(), 1e-11);
  }
}

TEST(CurvePolyline, UniformParameterPerPiece) {
  Curve3 c{CurveKind::kPolyline, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 2, 0)}};
  EXPECT_LT((curve_point(c, 0.25) - Vec3(0.5, 0, 0)).norm(), 1e-15);
  EXPECT_LT((curve_point(c, 0.75) - Vec3(1, 1, 0)).norm(), 1e-15);
  EXPECT_LT((curve_derivative(c, 0.25) - Vec3(2, 0, 0)).norm(), 1e-15);
  EXPECT_LT((curve_derivative(c, 0.5) - Vec3(0, 4, 0)).norm(), 1e-15);  // the piece starting at t
  EXPECT_EQ(curve_second_derivative(c, 0.3), Vec3::Zero());
  Curve2 sq{CurveKind::kPolyline, {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)}, true};
  EXPECT_LT((curve_point(sq, 0.875) - Vec2(0, 0.5)).norm(), 1e-15);  // closing piece
  EXPECT_LT((curve_point(sq, 1.0) - Vec2(0, 0)).norm(), 1e-15);
}

TEST(CurveFlatten, ChordErrorBelowTolerance) {
  Rng rng(14);
  for (const double tol : {1e-2, 1e-3, 1e-4}) {
    for (const CurveKind kind : {CurveKind::kBezier, CurveKind::kBSpline}) {
      for (const bool closed : {false, true}) {
        for (int n : {3, 5, 8}) {
          Curve2 c{kind, random_points2(rng, n), closed};
          const FlattenedCurve2 flat = flatten_with_parameters(c, tol);
          ASSERT_EQ(flat.points.size(), flat.parameters.size());
          ASSERT_GE(flat.points.size(), 2U);
          EXPECT_EQ(flat.parameters.front(), 0.0);
          if (!closed) {
            EXPECT_EQ(flat.parameters.back(), 1.0);
          }
          for (std::size_t i = 0; i < flat.points.size(); ++i) {
            EXPECT_LT((flat.points[i] - curve_point(c, flat.parameters[i])).norm(), 1e-14);
            if (i > 0) {
              EXPECT_LT(flat.parameters[i - 1], flat.parameters[i]);
            }
          }
          double worst = 0;
          for (int k = 0; k <= 4000; ++k) {
            const Vec2 q = curve_point(c, k / 4000.0);
            worst = std::max(worst, polyline_distance(q, flat.points, closed));
          }
          EXPECT_LE(worst, tol) << static_cast<int>(kind) << " closed " << closed << " n " << n;
          // Not absurdly over-refined: the error is at least 1/200 of the tolerance, or the
          // polyline is short.
          EXPECT_TRUE(worst > tol / 200 || flat.points.size() < 40) << worst << " " << flat.points.size();
        }
      }
    }
  }
  // 3-D as well.
  Curve3 c3{CurveKind::kBSpline, random_points3(rng, 7)};
  const auto pts = flatten(c3, 1e-3);
  for (int k = 0; k <= 3000; ++k) EXPECT_LE(polyline_distance(curve_point(c3, k / 3000.0), pts, false), 1e-3);
  // Polylines are returned as is.
  Curve2 poly{CurveKind::kPolyline, random_points2(rng, 6), true};
  EXPECT_EQ(flatten(poly, 1e-3), poly.points);
  EXPECT_THROW((void)flatten(poly, 0.0), InvalidArgument);
  EXPECT_THROW((void)flatten(poly, std::nan("")), InvalidArgument);
  EXPECT_THROW((void)flatten(c3, 1e-300), InvalidArgument);  // would need too many points
}

TEST(CurveValidate, NamesTheProblem) {
  auto message = [](auto&& fn) {
    try {
      fn();
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  Curve2 one{CurveKind::kBezier, {Vec2(0, 0)}, false};
  EXPECT_NE(message([&] { validate(one); }).find("at least 2 points"), std::string::npos);
  Curve2 two_closed{CurveKind::kPolyline, {Vec2(0, 0), Vec2(1, 0)}, true};
  EXPECT_NE(message([&] { validate(two_closed); }).find("at least 3 points"), std::string::npos);
  Curve3 bad{CurveKind::kBSpline, {Vec3(0, 0, 0), Vec3(1, std::nan(""), 0), Vec3(2, 0, 0)}};
  EXPECT_NE(message([&] { validate(bad); }).find("point 1 is not finite"), std::string::npos);
  Curve3 ok{CurveKind::kBSpline, {Vec3(0, 0, 0), Vec3(1, 0, 0)}};
  EXPECT_NO_THROW(validate(ok));
  EXPECT_THROW((void)curve_point(ok, 1.5), InvalidArgument);
  EXPECT_THROW((void)curve_point(ok, std::nan("")), InvalidArgument);
  EXPECT_THROW((void)curve_point(bad, 0.5), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
