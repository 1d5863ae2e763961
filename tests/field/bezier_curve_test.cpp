// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/bezier_curve.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

constexpr int kSamples = 20000;

double binomial(int n, int k) {
  double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

double bernstein_basis(int n, int i, double t) {
  return binomial(n, i) * std::pow(t, i) * std::pow(1 - t, n - i);
}

BezierCurve random_curve(Rng& rng, int degree) {
  BezierCurve c;
  for (int i = 0; i <= degree; ++i) {
    c.controls.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  }
  return c;
}

BezierCurve planar(const std::vector<Vec2>& points) {
  BezierCurve c;
  for (const Vec2& p : points) c.controls.emplace_back(p.x(), p.y(), 0.0);
  return c;
}

// g(t) = C'(t)·(C(t) - P) from the checked evaluation functions.
double g_of(const BezierCurve& c, const Vec3& p, double t) {
  return bezier_derivative(c, t).dot(bezier_point(c, t) - p);
}

// Reference nearest distance: 20,000 + 1 samples, every sampled local minimum within a margin of
// the best refined by golden section on the squared distance (whose value converges to rounding
// level even though t converges only to ~sqrt(eps)).
class DenseReference {
 public:
  explicit DenseReference(const BezierCurve& c) : curve_(c) {
    for (int i = 0; i <= kSamples; ++i)
      samples_.push_back(bezier_point(c, static_cast<double>(i) / kSamples));
  }

  double distance(const Vec3& p) const {
    std::vector<double> d2(samples_.size());
    for (std::size_t i = 0; i < samples_.size(); ++i) d2[i] = (samples_[i] - p).squaredNorm();
    const double best_sample = *std::min_element(d2.begin(), d2.end());
    const double margin = 1e-4 * best_sample + 1e-12;
    double best = best_sample;
    const int last = kSamples;
    for (int i = 0; i <= last; ++i) {
      if (d2[i] > best_sample + margin) continue;
      if (i > 0 && d2[i] > d2[i - 1]) continue;
      if (i < last && d2[i] > d2[i + 1]) continue;
      const double lo = static_cast<double>(std::max(0, i - 1)) / kSamples;
      const double hi = static_cast<double>(std::min(last, i + 1)) / kSamples;
      best = std::min(best, golden(p, lo, hi));
    }
    return std::sqrt(best);
  }

 private:
  double f(const Vec3& p, double t) const { return (bezier_point(curve_, t) - p).squaredNorm(); }
  double golden(const Vec3& p, double a, double b) const {
    const double r = (std::sqrt(5.0) - 1) / 2;
    double x1 = b - r * (b - a), x2 = a + r * (b - a);
    double f1 = f(p, x1), f2 = f(p, x2);
    double best = std::min({f(p, a), f(p, b), f1, f2});
    for (int it = 0; it < 80; ++it) {
      if (f1 < f2) {
        b = x2;
        x2 = x1;
        f2 = f1;
        x1 = b - r * (b - a);
        f1 = f(p, x1);
      } else {
        a = x1;
        x1 = x2;
        f1 = f2;
        x2 = a + r * (b - a);
        f2 = f(p, x2);
      }
      best = std::min({best, f1, f2});
    }
    return best;
  }

  const BezierCurve& curve_;
  std::vector<Vec3> samples_;
};

// Every sign change of g seen on a dense grid has a stationary parameter inside it, and every
// stationary parameter is a root of g (relative to |C'| |C - P|).
void expect_every_root(const BezierProjector& proj, const Vec3& p, const std::string& label) {
  const BezierCurve& c = proj.curve();
  const std::vector<double> roots = proj.stationary_parameters(p);
  EXPECT_TRUE(std::is_sorted(roots.begin(), roots.end())) << label;
  for (const double t : roots) {
    ASSERT_GE(t, 0.0) << label;
    ASSERT_LE(t, 1.0) << label;
    const double scale = bezier_derivative(c, t).norm() * (bezier_point(c, t) - p).norm() + 1e-300;
    EXPECT_LE(std::abs(g_of(c, p, t)), 1e-9 * scale + 1e-13) << label << " t=" << t;
  }
  double prev = g_of(c, p, 0.0);
  for (int i = 1; i <= kSamples; ++i) {
    const double a = static_cast<double>(i - 1) / kSamples, b = static_cast<double>(i) / kSamples;
    const double v = g_of(c, p, b);
    if ((prev < 0 && v > 0) || (prev > 0 && v < 0)) {
      const bool found = std::any_of(roots.begin(), roots.end(),
                                     [&](double t) { return t >= a - 1e-9 && t <= b + 1e-9; });
      EXPECT_TRUE(found) << label << ": sign change of g in [" << a << ", " << b << "] missed";
    }
    prev = v;
  }
}

TEST(BezierValidate, NamesTheProblemAndControlIndex) {
  auto message = [](const BezierCurve& c) {
    try {
      validate(c, "skeleton curve 4");
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  BezierCurve ok = planar({{0, 0}, {1, 1}, {2, 0}});
  EXPECT_NO_THROW(validate(ok, "x"));
  BezierCurve one = planar({{0, 0}});
  EXPECT_NE(message(one).find("skeleton curve 4: "), std::string::npos);
  EXPECT_NE(message(one).find("got 1"), std::string::npos);
  BezierCurve many;
  for (int i = 0; i < 17; ++i) many.controls.emplace_back(i, 0, 0);
  EXPECT_NE(message(many).find("got 17"), std::string::npos);
  BezierCurve nan = ok;
  nan.controls[2].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(nan).find("control 2 is not finite"), std::string::npos) << message(nan);
  BezierCurve radii = ok;
  radii.radii = {1, 2};
  EXPECT_NE(message(radii).find("2 radii for 3 controls"), std::string::npos) << message(radii);
  radii.radii = {1, 2, 0};
  EXPECT_NE(message(radii).find("radius of control 2"), std::string::npos) << message(radii);
  radii.radii = {1, std::numeric_limits<double>::infinity(), 1};
  EXPECT_NE(message(radii).find("radius of control 1"), std::string::npos) << message(radii);
  BezierCurve wide = planar({{0, 0}, {1e308, 1}, {-1e308, 0}});
  EXPECT_NE(message(wide).find("control 1: with it the coordinates span more than double"),
            std::string::npos)
      << message(wide);
  BezierCurve far = planar({{1e150, 0}, {1e150 + 1e145, 1e145}, {1e150 + 2e145, 0}});
  EXPECT_NO_THROW(validate(far, "x"));  // large, but its span fits
  BezierCurve point = planar({{5, 5}, {5, 5}, {5, 5 + 1e-13}});
  EXPECT_NE(message(point).find("degenerate"), std::string::npos) << message(point);
  BezierCurve almost = planar({{5, 5}, {5, 5}, {5, 5 + 1e-9}});
  EXPECT_NO_THROW(validate(almost, "x"));
  EXPECT_THROW((void)BezierProjector(point), InvalidArgument);
  EXPECT_THROW((void)bezier_point(ok, 1.5), InvalidArgument);
  EXPECT_THROW((void)BezierProjector(ok).project(Vec3(0, std::nan(""), 0)), InvalidArgument);
  EXPECT_THROW((void)BezierProjector(ok).project_newton(Vec3(0, 0, 0), 1), InvalidArgument);
}

TEST(BezierEval, PointMatchesBernsteinAndDerivativesMatchFiniteDifferences) {
  Rng rng(11);
  for (const int degree : {1, 2, 3, 5, 9, 15}) {
    const BezierCurve c = random_curve(rng, degree);
    for (const double t : {0.0, 0.13, 0.5, 0.77, 1.0}) {
      Vec3 ref = Vec3::Zero();
      for (int i = 0; i <= degree; ++i) ref += bernstein_basis(degree, i, t) * c.controls[i];
      EXPECT_LE((bezier_point(c, t) - ref).norm(), 1e-12) << degree << " " << t;
      const double h = 1e-6;
      const double a = std::max(0.0, t - h), b = std::min(1.0, t + h);
      const Vec3 fd1 = (bezier_point(c, b) - bezier_point(c, a)) / (b - a);
      const Vec3 fd2 = (bezier_derivative(c, b) - bezier_derivative(c, a)) / (b - a);
      const double s1 = 1 + bezier_derivative(c, t).norm();
      const double s2 = 1 + bezier_second_derivative(c, t).norm();
      // One-sided differences at the ends are first-order: the tolerance allows h |C''| etc.
      EXPECT_LE((bezier_derivative(c, t) - fd1).norm(), 1e-5 * s1 * degree * degree)
          << degree << " " << t;
      EXPECT_LE((bezier_second_derivative(c, t) - fd2).norm(), 1e-5 * s2 * degree * degree * degree)
          << degree << " " << t;
    }
  }
  const BezierCurve line = planar({{0, 0}, {2, 1}});
  EXPECT_EQ(bezier_second_derivative(line, 0.3), Vec3::Zero());
  EXPECT_TRUE(bezier_derivative(line, 0.3).isApprox(Vec3(2, 1, 0)));
}

TEST(BezierRadius, ExactAtEndsAndEqualToBernsteinSum) {
  Rng rng(5);
  BezierCurve c = random_curve(rng, 5);
  EXPECT_EQ(bezier_radius(c, 0.4), 1.0);
  EXPECT_EQ(bezier_radius_derivative(c, 0.4), 0.0);
  c.radii = {0.5, 2.0, 0.1, 3.0, 1.0, 0.25};
  EXPECT_EQ(bezier_radius(c, 0.0), 0.5);
  EXPECT_EQ(bezier_radius(c, 1.0), 0.25);
  for (const double t : {0.1, 0.35, 0.5, 0.9}) {
    double ref = 0;
    for (int i = 0; i <= 5; ++i) ref += bernstein_basis(5, i, t) * c.radii[i];
    EXPECT_NEAR(bezier_radius(c, t), ref, 1e-14);
    const double h = 1e-6;
    EXPECT_NEAR(bezier_radius_derivative(c, t),
                (bezier_radius(c, t + h) - bezier_radius(c, t - h)) / (2 * h), 1e-6);
  }
}

TEST(BezierProjector, AccessorsAndBoxContainsCurve) {
  Rng rng(3);
  const BezierProjector proj(random_curve(rng, 4));
  EXPECT_EQ(proj.degree(), 4);
  EXPECT_EQ(proj.curve().controls.size(), 5u);
  for (int i = 0; i <= 100; ++i) {
    EXPECT_TRUE(proj.box().contains(bezier_point(proj.curve(), i / 100.0)));
  }
}

TEST(BezierProject, MatchesDenseSamplingOnRandomCurves) {
  Rng rng(2026);
  for (const int degree : {1, 2, 3, 5, 9}) {
    for (int curve = 0; curve < 4; ++curve) {
      const BezierProjector proj(random_curve(rng, degree));
      const DenseReference reference(proj.curve());
      for (int k = 0; k < 40; ++k) {
        // Points near the curve and farther away.
        const double spread = k < 30 ? 0.3 : 2.0;
        const Vec3 on = bezier_point(proj.curve(), rng.uniform());
        const Vec3 p =
            on + spread * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const BezierProjection r = proj.project(p);
        const double ref = reference.distance(p);
        EXPECT_NEAR(r.distance, ref, 1e-9 * ref + 1e-14) << "degree " << degree << " point " << k;
        EXPECT_GE(r.t, 0.0);
        EXPECT_LE(r.t, 1.0);
        EXPECT_LE((r.point - bezier_point(proj.curve(), r.t)).norm(), 1e-12);
        EXPECT_NEAR((r.point - p).norm(), r.distance, 1e-14);
        EXPECT_GE(r.candidates, 2);
        // kLast gives the same distance.
        EXPECT_NEAR(proj.project(p, TieRule::kLast).distance, r.distance, 1e-12 * (1 + r.distance));
      }
    }
  }
}

TEST(BezierProject, DegreeOneEqualsPointSegmentDistance) {
  Rng rng(8);
  for (int k = 0; k < 200; ++k) {
    const Vec3 a(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const Vec3 b(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const Vec3 p(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    const BezierProjector proj(BezierCurve{{a, b}, {}});
    const Vec3 ab = b - a;
    const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    const double ref = (a + s * ab - p).norm();
    const BezierProjection r = proj.project(p);
    EXPECT_NEAR(r.distance, ref, 1e-14 * (1 + ref));
    EXPECT_NEAR(r.t, s, 1e-12);
  }
}

TEST(BezierStationary, FindsEveryRootOnCircleArcsAtTheirCentre) {
  const double k = 4.0 / 3.0 * (std::sqrt(2.0) - 1);
  const BezierProjector quarter(planar({{1, 0}, {1, k}, {k, 1}, {0, 1}}));
  const BezierProjector half(planar({{1, 0}, {1, 4.0 / 3}, {-1, 4.0 / 3}, {-1, 0}}));
  for (const BezierProjector* proj : {&quarter, &half}) {
    const DenseReference reference(proj->curve());
    for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1e-9, 0, 0), Vec3(0, 1e-6, 0), Vec3(0.01, 0.02, 0),
                          Vec3(0, 0, 0.5), Vec3(-1e-3, 1e-3, 0)}) {
      expect_every_root(*proj, p, "arc");
      const double ref = reference.distance(p);
      EXPECT_NEAR(proj->project(p).distance, ref, 1e-9 * ref);
    }
    // From the centre the arc has several projections: both ends (|C| = 1) and interior ones.
    EXPECT_GE(proj->stationary_parameters(Vec3::Zero()).size(), 3u);
  }
}

TEST(BezierStationary, SCurveAndItsCentreOfCurvature) {
  const BezierProjector s(planar({{0, 0}, {1, 2}, {2, -2}, {3, 0}}));
  const BezierCurve& c = s.curve();
  const DenseReference reference(c);
  for (const double t0 : {0.15, 0.3, 0.8}) {
    const Vec3 d1 = bezier_derivative(c, t0), d2 = bezier_second_derivative(c, t0);
    const double speed = d1.norm();
    const Vec3 normal_acc = d2 - d2.dot(d1) / (speed * speed) * d1;  // curvature direction * |C'|²κ
    const double kappa = normal_acc.norm() / (speed * speed);
    const Vec3 centre = bezier_point(c, t0) + normal_acc.normalized() / kappa;
    // At the centre g has a double root at t0 (g = g' = 0): it must be reported.
    const std::vector<double> roots = s.stationary_parameters(centre);
    EXPECT_TRUE(
        std::any_of(roots.begin(), roots.end(), [&](double t) { return std::abs(t - t0) < 1e-4; }))
        << "t0 = " << t0;
    for (const double shift : {0.0, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3, -1e-3}) {
      const Vec3 p = centre + shift * normal_acc.normalized();
      expect_every_root(s, p, "S-curve centre of curvature");
      const double ref = reference.distance(p);
      EXPECT_NEAR(s.project(p).distance, ref, 1e-9 * ref) << t0 << " " << shift;
    }
  }
  // The curve is y = 6t(1-t)(1-2t), x = 3t; a point inside the upper lobe, beyond the centre of
  // curvature of its peak, sees both flanks (minima) and the peak (a maximum).
  expect_every_root(s, Vec3(0.633, 0.05, 0), "S-curve lobe");
  EXPECT_GE(s.stationary_parameters(Vec3(0.633, 0.05, 0)).size(), 3u);
  // project() searches only the arcs that may hold the nearest point: the two ends and at least
  // the nearer flank and the peak are counted (the farther flank's arcs may be pruned).
  const BezierProjection lobe = s.project(Vec3(0.633, 0.05, 0));
  EXPECT_GE(lobe.candidates, 4);
  const double lobe_ref = reference.distance(Vec3(0.633, 0.05, 0));
  EXPECT_NEAR(lobe.distance, lobe_ref, 1e-9 * lobe_ref);
}

TEST(BezierProject, NearCentresOfCurvatureOfRandomCurves) {
  // Where a minimum and a maximum of the distance merge (a point near a centre of curvature, g
  // with a near-double root) the nearest point must not be lost.
  Rng rng(404);
  for (const int degree : {3, 5}) {
    for (int curve = 0; curve < 6; ++curve) {
      const BezierProjector proj(random_curve(rng, degree));
      const BezierCurve& c = proj.curve();
      const DenseReference reference(c);
      for (int k = 0; k < 8; ++k) {
        const double t0 = rng.uniform(0.05, 0.95);
        const Vec3 d1 = bezier_derivative(c, t0), d2 = bezier_second_derivative(c, t0);
        const Vec3 normal_acc = d2 - d2.dot(d1) / d1.squaredNorm() * d1;
        const double kappa = normal_acc.norm() / d1.squaredNorm();
        if (!(kappa > 1e-3)) continue;
        const Vec3 centre = bezier_point(c, t0) + normal_acc.normalized() / kappa;
        for (const double shift : {0.0, 1e-12, -1e-12, 1e-8, -1e-8, 1e-4, -1e-4}) {
          const Vec3 p =
              centre + shift * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
          const double ref = reference.distance(p);
          EXPECT_NEAR(proj.project(p).distance, ref, 1e-9 * ref)
              << degree << " " << t0 << " " << shift;
          EXPECT_NEAR(proj.project(p, TieRule::kLast).distance, ref, 1e-9 * ref);
        }
      }
    }
  }
}

TEST(BezierProject, HighDegreeAndFarFromTheOrigin) {
  Rng rng(15);
  const Vec3 offset(1e4, -2e4, 3e4);
  for (const int degree : {9, 15}) {
    BezierCurve c = random_curve(rng, degree);
    for (Vec3& p : c.controls) p += offset;
    const BezierProjector proj(c);
    const DenseReference reference(proj.curve());
    for (int k = 0; k < 30; ++k) {
      const Vec3 p = bezier_point(c, rng.uniform()) +
                     0.3 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      const double ref = reference.distance(p);
      EXPECT_NEAR(proj.project(p).distance, ref, 1e-9 * ref + 1e-11) << degree << " " << k;
      expect_every_root(proj, p, "far curve");
    }
  }
}

TEST(BezierProject, TieBetweenTwoLobesFollowsTheRule) {
  // An M-shaped quartic, mirror-symmetric (x -> -x, t -> 1-t); a point on the mirror plane
  // above it is equally near both humps.
  const BezierProjector m(planar({{-2, 0}, {-1, 4}, {0, -4}, {1, 4}, {2, 0}}));
  const Vec3 p(0, 5, 0);
  const BezierProjection first = m.project(p, TieRule::kFirst);
  const BezierProjection last = m.project(p, TieRule::kLast);
  EXPECT_TRUE(first.tie);
  EXPECT_TRUE(last.tie);
  EXPECT_LT(first.t, 0.5);
  EXPECT_GT(last.t, 0.5);
  EXPECT_NEAR(first.t + last.t, 1.0, 1e-9);
  EXPECT_NEAR(first.distance, last.distance, 1e-12 * first.distance);
  EXPECT_GE(first.candidates, 4);  // two minima, two ends (the arc path skips the maximum)
  const std::vector<double> roots = m.stationary_parameters(p);
  EXPECT_NEAR(roots.front(), first.t, 1e-12);
  EXPECT_NEAR(roots.back(), last.t, 1e-12);
  // Off the mirror plane the tie is broken.
  const BezierProjection off = m.project(Vec3(0.01, 5, 0));
  EXPECT_FALSE(off.tie);
  EXPECT_GT(off.t, 0.5);
  // The ends of a symmetric arch tie from a point on its axis below it.
  const BezierProjector arch(planar({{-2, 0}, {-2, 1}, {2, 1}, {2, 0}}));
  const BezierProjection a0 = arch.project(Vec3(0, -3, 0));
  const BezierProjection a1 = arch.project(Vec3(0, -3, 0), TieRule::kLast);
  EXPECT_TRUE(a0.tie);
  EXPECT_EQ(a0.t, 0.0);
  EXPECT_EQ(a1.t, 1.0);
}

// The nearest of the stationary parameters (whole-curve isolation, the path project() takes
// above degree 7) and the two ends.
double nearest_by_isolation(const BezierProjector& proj, const Vec3& p) {
  double best = std::min((proj.curve().controls.front() - p).norm(),
                         (proj.curve().controls.back() - p).norm());
  for (const double t : proj.stationary_parameters(p))
    best = std::min(best, (bezier_point(proj.curve(), t) - p).norm());
  return best;
}

// A point near the curve (a random offset up to `spread` in each coordinate), near a centre of
// curvature, or far away.
Vec3 query_point(Rng& rng, const BezierCurve& c, int k) {
  const double t0 = rng.uniform(0.02, 0.98);
  const Vec3 on = bezier_point(c, t0);
  if (k % 5 == 3) {
    const Vec3 d1 = bezier_derivative(c, t0), d2 = bezier_second_derivative(c, t0);
    const Vec3 normal_acc = d2 - d2.dot(d1) / d1.squaredNorm() * d1;
    const double kappa = normal_acc.norm() / d1.squaredNorm();
    if (kappa > 1e-3) {
      return on + normal_acc.normalized() / kappa +
             1e-6 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    }
  }
  const double spread = k % 5 == 4 ? 3.0 : 0.3;
  return on + spread * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
}

TEST(BezierProject, ArcPathMatchesDenseSampling) {
  // The certified arc path (degree <= 7) against the brute-force reference: 5,000 points.
  Rng rng(7070);
  for (const int degree : {2, 3, 4, 5, 7}) {
    for (int curve = 0; curve < 4; ++curve) {
      const BezierProjector proj(random_curve(rng, degree));
      ASSERT_GT(proj.arc_count(), 0);
      const DenseReference reference(proj.curve());
      for (int k = 0; k < 250; ++k) {
        const Vec3 p = query_point(rng, proj.curve(), k);
        const BezierProjection r = proj.project(p);
        const double ref = reference.distance(p);
        ASSERT_NEAR(r.distance, ref, 1e-9 * ref + 1e-14) << "degree " << degree << " point " << k;
        ASSERT_LE((r.point - bezier_point(proj.curve(), r.t)).norm(), 1e-12);
        ASSERT_NEAR(proj.project(p, TieRule::kLast).distance, r.distance, 1e-12 * (1 + r.distance));
      }
    }
  }
}

TEST(BezierProject, ArcPathMatchesWholeCurveIsolation) {
  // 10,000 points near random cubics and quintics: the arc path never misses the nearest point
  // that the whole-curve isolation finds (and is never farther).
  Rng rng(5151);
  int misses = 0;
  for (const int degree : {3, 5}) {
    for (int curve = 0; curve < 50; ++curve) {
      const BezierProjector proj(random_curve(rng, degree));
      for (int k = 0; k < 100; ++k) {
        const Vec3 p = query_point(rng, proj.curve(), k);
        const double fast = proj.project(p).distance;
        const double whole = nearest_by_isolation(proj, p);
        if (std::abs(fast - whole) > 1e-10 * (1 + whole)) ++misses;
        EXPECT_LE(fast, whole * (1 + 1e-10) + 1e-14) << degree << " " << curve << " " << k;
      }
    }
  }
  EXPECT_EQ(misses, 0);
}

TEST(BezierProject, ArcPathOnCuspsFoldedLinesAndExtremePoints) {
  // Curves where |C'| vanishes (a cusp; collinear controls that fold back; a repeated control),
  // and queries on the curve, at its ends, and far away, against the brute-force reference.
  const std::vector<BezierCurve> curves = {
      planar({{0, 0}, {2, 2}, {0, 2}, {2, 0}}),                  // cusp
      planar({{0, 0}, {3, 0}, {-1, 0}, {2, 0}}),                 // folded straight line
      planar({{0, 0}, {0, 0}, {1, 1}, {2, 0}}),                  // C'(0) = 0
      planar({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}}),  // straight quintic
      BezierCurve{{{0, 0, 0},
                   {1, 2, 3},
                   {-2, 1, 0},
                   {3, -1, 2},
                   {0, 0, 1},
                   {1, 1, 1},
                   {2, 0, -1},
                   {0, 3, 0}},
                  {}},
  };
  Rng rng(606);
  for (std::size_t ci = 0; ci < curves.size(); ++ci) {
    const BezierProjector proj(curves[ci]);
    const DenseReference reference(proj.curve());
    std::vector<Vec3> points = {proj.curve().controls.front(), proj.curve().controls.back(),
                                Vec3(1e3, -2e3, 5e2)};
    for (int k = 0; k < 200; ++k) {
      const Vec3 on = bezier_point(proj.curve(), rng.uniform());
      points.push_back(
          k % 4 == 0 ? on
                     : on + (k % 4) * 0.2 *
                                Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    }
    for (const Vec3& p : points) {
      const double ref = reference.distance(p);
      const BezierProjection r = proj.project(p);
      EXPECT_NEAR(r.distance, ref, 1e-9 * ref + 1e-12) << "curve " << ci;
      EXPECT_LE(r.distance, nearest_by_isolation(proj, p) * (1 + 1e-10) + 1e-14) << "curve " << ci;
    }
  }
}

TEST(BezierProject, BatchEqualsOneByOneAndArcsOnlyUpToDegreeSeven) {
  Rng rng(31);
  const BezierProjector cubic(random_curve(rng, 3));
  std::vector<Vec3> points;
  for (int k = 0; k < 50; ++k) points.push_back(query_point(rng, cubic.curve(), k));
  std::vector<BezierProjection> out(points.size());
  cubic.project(points, out, TieRule::kLast);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const BezierProjection one = cubic.project(points[k], TieRule::kLast);
    EXPECT_EQ(out[k].t, one.t);
    EXPECT_EQ(out[k].distance, one.distance);
  }
  std::vector<BezierProjection> short_out(3);
  EXPECT_THROW(cubic.project(points, short_out), InvalidArgument);
  EXPECT_EQ(BezierProjector(random_curve(rng, 9)).arc_count(), 0);
  EXPECT_EQ(BezierProjector(random_curve(rng, 1)).arc_count(), 1);
}

// Bit pattern of a double (so that -0 and +0 differ).
std::uint64_t bits(double v) { return std::bit_cast<std::uint64_t>(v); }

// Whether two projections are the same bit for bit: parameter, distance, point, candidates, tie.
bool same_bits(const BezierProjection& a, const BezierProjection& b) {
  return bits(a.t) == bits(b.t) && bits(a.distance) == bits(b.distance) &&
         bits(a.point.x()) == bits(b.point.x()) && bits(a.point.y()) == bits(b.point.y()) &&
         bits(a.point.z()) == bits(b.point.z()) && a.candidates == b.candidates && a.tie == b.tie;
}

// Hard and easy queries for a curve: near it, near centres of curvature (within 1e-6), far (up to
// 3 away and at 1e3), on the curve, at and beyond its ends, and at its controls.
std::vector<Vec3> batch_queries(Rng& rng, const BezierCurve& c, int count) {
  std::vector<Vec3> points;
  const Vec3 a = c.controls.front(), b = c.controls.back();
  const Vec3 ta = bezier_derivative(c, 0).normalized(), tb = bezier_derivative(c, 1).normalized();
  for (int k = 0; points.size() < static_cast<std::size_t>(count); ++k) {
    switch (k % 10) {
      case 0:
        points.push_back(bezier_point(c, rng.uniform()));
        break;
      case 1:  // near an end, beyond it or just inside
        points.push_back((k % 20 == 1 ? a : b) +
                         rng.uniform(-1e-3, 1e-3) * (k % 20 == 1 ? ta : tb) +
                         1e-6 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
        break;
      case 2:
        points.push_back(1e3 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
        break;
      case 5:
        points.push_back(c.controls[static_cast<std::size_t>(k / 10) % c.controls.size()]);
        break;
      default:
        points.push_back(query_point(rng, c, k));  // k % 5 == 3: a centre of curvature
    }
  }
  return points;
}

TEST(BezierProject, BatchedPathEqualsOneByOneBitForBit) {
  // The batched path (SIMD across points, field/bezier_curve_simd.cpp) against project(p):
  // 10,400 queries (200 per curve) of degrees 1-7 (the arc path) and 9 (whole-curve isolation),
  // both tie rules, batches of odd sizes and the reversed order; plus curves with ties (a closed
  // loop, a symmetric M and arch). Every field must be identical.
  Rng rng(2718);
  std::vector<BezierCurve> curves;
  for (const int degree : {1, 2, 3, 4, 5, 6, 7, 9}) {
    for (int k = 0; k < 6; ++k) curves.push_back(random_curve(rng, degree));
  }
  curves.push_back(planar({{0, 0}, {2, 2}, {-2, 2}, {0, 0}}));            // closed loop
  curves.push_back(planar({{-2, 0}, {-1, 4}, {0, -4}, {1, 4}, {2, 0}}));  // symmetric M
  curves.push_back(planar({{-2, 0}, {-2, 1}, {2, 1}, {2, 0}}));           // symmetric arch
  curves.push_back(planar({{0, 0}, {2, 2}, {0, 2}, {2, 0}}));             // cusp
  const std::vector<int> sizes = {1, 7, 9, 255, 257};
  int compared = 0, different = 0;
  for (std::size_t ci = 0; ci < curves.size(); ++ci) {
    const BezierProjector proj(curves[ci]);
    std::vector<Vec3> points = batch_queries(rng, proj.curve(), 200);
    if (ci >= curves.size() - 4) {
      // On the symmetry axes: exact ties between the ends or the lobes.
      points.emplace_back(0, 5, 0);
      points.emplace_back(0, -3, 0);
      points.emplace_back(0, 1, 0);
      points.emplace_back(0, 0, 0);
    }
    for (const TieRule rule : {TieRule::kFirst, TieRule::kLast}) {
      // One batch of everything, then batches of several sizes over the same points.
      std::vector<BezierProjection> all(points.size());
      proj.project(points, all, rule);
      // The same points in reverse order (other neighbours in every vector, other Newton runs
      // sharing a vector in the queue): a point's result does not depend on its batch.
      {
        const std::vector<Vec3> reversed(points.rbegin(), points.rend());
        std::vector<BezierProjection> back(points.size());
        proj.project(reversed, back, rule);
        for (std::size_t k = 0; k < points.size(); ++k) {
          if (!same_bits(back[points.size() - 1 - k], all[k])) ++different;
        }
      }
      std::size_t begin = 0;
      for (std::size_t s = 0; begin < points.size(); ++s) {
        const std::size_t n =
            std::min(points.size() - begin, static_cast<std::size_t>(sizes[s % sizes.size()]));
        std::vector<BezierProjection> part(n);
        proj.project(std::span<const Vec3>(points).subspan(begin, n), part, rule);
        for (std::size_t k = 0; k < n; ++k) {
          if (!same_bits(part[k], all[begin + k])) ++different;
        }
        begin += n;
      }
      for (std::size_t k = 0; k < points.size(); ++k) {
        const BezierProjection one = proj.project(points[k], rule);
        ++compared;
        if (!same_bits(all[k], one)) {
          ++different;
          ADD_FAILURE() << "curve " << ci << " point " << k << ": batched t " << all[k].t
                        << " distance " << all[k].distance << " candidates " << all[k].candidates
                        << " tie " << all[k].tie << "; one by one t " << one.t << " distance "
                        << one.distance << " candidates " << one.candidates << " tie " << one.tie;
          if (different > 10) return;
        }
      }
    }
  }
  EXPECT_GE(compared, 2 * 10000);
  EXPECT_EQ(different, 0);
}

TEST(BezierProject, PointsOnTheCurveAtArcEndsAreAtDistanceZero) {
  // A query on the curve at a dyadic parameter (the arcs' ends are at multiples of 1/64) lies on
  // an arc's bounding sphere (the end is the control farthest from its centre) while the first
  // visit's ends bound the distance by 0: the arc holding the root was once pruned by a
  // rounding (the loop below at t = 1/4 and 3/8 gave t = 1 at distance 1.89 and 2.27).
  Rng rng(6464);
  std::vector<BezierCurve> curves = {planar({{0, 0}, {3, 3}, {-1, 3}, {2, 0}}),
                                     planar({{0, 0}, {2, 2}, {0, 2}, {2, 0}})};
  for (const int degree : {2, 3, 3, 4, 5, 6, 7}) curves.push_back(random_curve(rng, degree));
  for (std::size_t ci = 0; ci < curves.size(); ++ci) {
    const BezierProjector proj(curves[ci]);
    std::vector<Vec3> points;
    for (int j = 0; j <= 64; ++j) points.push_back(bezier_point(proj.curve(), j / 64.0));
    std::vector<BezierProjection> batch(points.size());
    proj.project(points, batch);
    for (std::size_t j = 0; j < points.size(); ++j) {
      const double scale = 1e-13 * (1 + points[j].norm());
      EXPECT_LE(batch[j].distance, scale) << "curve " << ci << " t " << j << "/64";
      EXPECT_LE(proj.project(points[j]).distance, scale) << "curve " << ci << " t " << j << "/64";
    }
  }
}

// A guard for any shortcut in the arc path (pruning by bounds, a cheaper first arc, early
// outs): points placed where a wrong rejection of an arc would show. On a medial axis (the
// midpoint of two curve points, nudged by 1e-12 .. 1e-4 towards either: two arcs nearly equally
// near, the bound that prunes one found on the other), at centres of curvature (the evolute:
// many arcs at about the same distance, uncertified arcs), on the curve and along its normal at
// dyadic parameters (the arcs' ends, where two arcs share the nearest point), at the double
// point of a loop (distance 0 on two arcs), near the seam of a closed curve, at a circle's
// centre (every point of the arc equally near) and far away. Batched (project(points, out),
// every tie rule) and one by one, against the dense reference (1e-9 relative) and the
// whole-curve isolation (never farther).
TEST(BezierProject, AdversarialPointsAgainstDenseSamplingBatchedAndOneByOne) {
  Rng rng(16016);
  const double k = 4.0 / 3.0 * (std::sqrt(2.0) - 1);
  std::vector<BezierCurve> curves = {
      planar({{1, 0}, {1, k}, {k, 1}, {0, 1}}),             // a quarter circle (centre: the origin)
      planar({{0, 0}, {3, 3}, {-1, 3}, {2, 0}}),            // a loop crossing itself
      planar({{0, 0}, {2, 2}, {-2, 2}, {0, 0}}),            // closed: its ends meet
      planar({{0, 0}, {2, 2}, {0, 2}, {2, 0}}),             // a cusp
      planar({{0, 0}, {1, 2}, {2, -2}, {3, 0}}),            // an S (inflection)
      planar({{-2, 0}, {-1, 4}, {0, -4}, {1, 4}, {2, 0}}),  // a symmetric M (degree 4)
  };
  for (const int degree : {3, 3, 5, 5, 7}) curves.push_back(random_curve(rng, degree));
  int checked = 0;
  for (std::size_t ci = 0; ci < curves.size(); ++ci) {
    const BezierProjector proj(curves[ci]);
    const BezierCurve& c = proj.curve();
    std::vector<Vec3> points;
    // Medial axis: equidistant from two curve points, and nudged towards either.
    for (int j = 0; j < 10; ++j) {
      const double t1 = rng.uniform(0.0, 0.45), t2 = rng.uniform(0.55, 1.0);
      const Vec3 a = bezier_point(c, t1), b = bezier_point(c, t2);
      const Vec3 mid = 0.5 * (a + b);
      const Vec3 side = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      const Vec3 lift = side - side.dot(b - a) / std::max((b - a).squaredNorm(), 1e-300) * (b - a);
      for (const double nudge : {0.0, 1e-12, -1e-12, 1e-6, -1e-6, 1e-4}) {
        points.push_back(mid + nudge * (b - a) + 0.1 * (j % 3) * lift);
      }
    }
    // Centres of curvature, and 1e-9 .. 1e-5 off them.
    for (int j = 0; j < 6; ++j) {
      const double t0 = rng.uniform(0.02, 0.98);
      const Vec3 d1 = bezier_derivative(c, t0), d2 = bezier_second_derivative(c, t0);
      if (!(d1.squaredNorm() > 1e-12)) continue;
      const Vec3 normal_acc = d2 - d2.dot(d1) / d1.squaredNorm() * d1;
      const double kappa = normal_acc.norm() / d1.squaredNorm();
      if (!(kappa > 1e-3)) continue;
      const Vec3 centre = bezier_point(c, t0) + normal_acc.normalized() / kappa;
      for (const double shift : {0.0, 1e-9, -1e-7, 1e-5}) {
        points.push_back(centre + shift * normal_acc.normalized());
      }
    }
    // On the curve and off it along the normal at dyadic parameters (where arcs meet).
    for (int j = 0; j <= 64; j += 3) {
      const double t = j / 64.0;
      const Vec3 on = bezier_point(c, t);
      points.push_back(on);
      const Vec3 d1 = bezier_derivative(c, t);
      Vec3 normal = d1.cross(Vec3(0, 0, 1));
      if (!(normal.squaredNorm() > 1e-20)) normal = d1.cross(Vec3(1, 0, 0));
      if (normal.squaredNorm() > 1e-20) {
        points.push_back(on + 0.05 * normal.normalized());
        points.push_back(on - 0.3 * normal.normalized());
      }
    }
    // The circle's centre, the loop's double point (found on the dense samples), the seam, far.
    points.emplace_back(0, 0, 0);
    points.emplace_back(1e-9, -1e-9, 0);
    points.push_back(c.controls.front() + Vec3(1e-7, -1e-7, 0));
    points.push_back(1e3 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    points.push_back(c.controls.back() + 10 * (c.controls.back() - c.controls.front()));
    if (ci == 1) {
      // The loop's double point: C(t1) = C(t2) for t1 != t2, by symmetry on x = 1 (the loop's
      // axis), refined by bisection on the x coordinate of the first branch.
      double lo = 0.0, hi = 0.5;
      for (int it = 0; it < 200; ++it) {
        const double m = 0.5 * (lo + hi);
        (bezier_point(c, m).x() < 1.0 ? lo : hi) = m;
      }
      const Vec3 crossing = bezier_point(c, lo);
      points.push_back(crossing);
      points.push_back(crossing + Vec3(0, 1e-9, 0));
      points.push_back(crossing + Vec3(0, -1e-6, 0));
    }

    const DenseReference reference(c);
    std::vector<double> ref(points.size()), whole(points.size());
    for (std::size_t j = 0; j < points.size(); ++j) {
      ref[j] = reference.distance(points[j]);
      whole[j] = nearest_by_isolation(proj, points[j]);
    }
    for (const TieRule rule : {TieRule::kFirst, TieRule::kLast}) {
      std::vector<BezierProjection> batch(points.size());
      proj.project(points, batch, rule);
      for (std::size_t j = 0; j < points.size(); ++j) {
        const Vec3& p = points[j];
        for (const BezierProjection& r : {batch[j], proj.project(p, rule)}) {
          ASSERT_NEAR(r.distance, ref[j], 1e-9 * ref[j] + 1e-12)
              << "curve " << ci << " point " << j << " at " << p.transpose() << " t " << r.t;
          ASSERT_LE(r.distance, whole[j] * (1 + 1e-10) + 1e-14) << "curve " << ci << " point " << j;
          ASSERT_LE((r.point - bezier_point(c, r.t)).norm(), 1e-12) << "curve " << ci;
          ASSERT_NEAR((r.point - p).norm(), r.distance, 1e-12 * (1 + r.distance));
          ++checked;
        }
      }
    }
  }
  EXPECT_GE(checked, 6000);
  RecordProperty("checked", checked);
}

TEST(BezierProject, NeverFartherThanNewtonAndCountsNewtonMisses) {
  Rng rng(99);
  int misses = 0, total = 0;
  for (int curve = 0; curve < 50; ++curve) {
    const BezierProjector proj(random_curve(rng, 3));
    for (int k = 0; k < 100; ++k) {
      const Vec3 p = bezier_point(proj.curve(), rng.uniform()) +
                     0.3 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      const double iso = proj.project(p).distance;
      const double newton = proj.project_newton(p).distance;
      EXPECT_LE(iso, newton + 1e-12);
      if (newton > iso * (1 + 1e-9)) ++misses;
      ++total;
    }
  }
  std::cout << "Newton (4 starts) missed the nearest point on " << misses << " of " << total
            << " points near random cubics\n";
  RecordProperty("newton_misses", misses);
}

}  // namespace
}  // namespace ramiform
