// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/sweep.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

using test::grown;
using test::random_point;
using test::reference_kernel;

constexpr double kPi = std::numbers::pi;

Curve2 square(double cx, double cy, double h) {
  return {CurveKind::kPolyline,
          {Vec2(cx - h, cy - h), Vec2(cx + h, cy - h), Vec2(cx + h, cy + h), Vec2(cx - h, cy + h)},
          true};
}

Curve2 ngon(double r, int n, double phase = 0) {
  Curve2 c{CurveKind::kPolyline, {}, true};
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * kPi * i / n;
    c.points.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return c;
}

Curve2 star(double outer, double inner, int tips) {
  Curve2 c{CurveKind::kPolyline, {}, true};
  for (int i = 0; i < 2 * tips; ++i) {
    const double a = kPi * i / tips + 0.1;
    const double r = i % 2 == 0 ? outer : inner;
    c.points.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return c;
}

// Independent 2-D distance to a polygon's region (closed; crossing parity) or to a polyline.
double region_distance(const Vec2& q, const std::vector<Vec2>& v, bool closed) {
  const std::size_t n = v.size();
  const std::size_t segs = closed ? n : n - 1;
  double best = std::numeric_limits<double>::infinity();
  int crossings = 0;
  for (std::size_t i = 0; i < segs; ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % n];
    const Vec2 ab = b - a;
    const double u = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (q - a - u * ab).norm());
    if ((a.y() <= q.y() && b.y() > q.y()) || (b.y() <= q.y() && a.y() > q.y())) {
      const double x = a.x() + (q.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      if (x > q.x()) ++crossings;
    }
  }
  return closed && crossings % 2 == 1 ? 0.0 : best;
}

// A gently curved, non-planar path.
Curve3 curved_path() {
  return {CurveKind::kBezier, {Vec3(0, 0, 0), Vec3(0.4, 0.1, 1), Vec3(-0.2, 0.4, 2), Vec3(0, 0, 3)}};
}

CurveSurfaceOptions surface(double radius, Kernel kernel = Kernel{KernelKind::kWyvill, 0.0}) {
  CurveSurfaceOptions o;
  o.radius = radius;
  o.kernel = kernel;
  return o;
}

// Every grid point with f > iso lies in bounds().
void check_bounds(const Field& f, const Aabb& sample, int n, const std::string& what) {
  const Aabb b = f.bounds();
  ASSERT_FALSE(b.isEmpty()) << what;
  std::vector<Vec3> pts;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      for (int k = 0; k <= n; ++k) {
        pts.push_back(sample.min() + Vec3(i, j, k).cwiseProduct(sample.diagonal()) / n);
      }
    }
  }
  std::vector<double> v(pts.size());
  f.evaluate(pts, v);
  int inside = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (v[i] > f.iso()) {
      ++inside;
      ASSERT_TRUE(b.contains(pts[i])) << what << ": " << pts[i].transpose() << " inside, bounds "
                                      << b.min().transpose() << " / " << b.max().transpose();
    }
  }
  EXPECT_GT(inside, 20) << what;
}

// bound(box) contains every sampled value of random boxes around `region`.
void check_bound(const Field& f, const Aabb& region, double scale, std::uint64_t seed, const std::string& what) {
  Rng rng(seed);
  int straddling = 0;
  for (int b = 0; b < 200; ++b) {
    const Vec3 c = random_point(rng, region);
    const Vec3 half(scale * std::exp(rng.uniform(std::log(0.01), std::log(3.0))),
                    scale * std::exp(rng.uniform(std::log(0.01), std::log(3.0))),
                    scale * std::exp(rng.uniform(std::log(0.01), std::log(3.0))));
    const Aabb box(c - half, c + half);
    const Interval iv = f.bound(box);
    ASSERT_LE(iv.lo, iv.hi) << what;
    std::vector<Vec3> pts;
    for (int k = 0; k < 8; ++k) pts.push_back(box.corner(static_cast<Aabb::CornerType>(k)));
    for (int i = 0; i < 60; ++i) pts.push_back(random_point(rng, box));
    std::vector<double> v(pts.size());
    f.evaluate(pts, v);
    bool in = false, out = false;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      ASSERT_TRUE(iv.contains(v[i])) << what << ": bound [" << iv.lo << ", " << iv.hi << "] but f("
                                     << pts[i].transpose() << ") = " << v[i];
      in |= v[i] > f.iso();
      out |= v[i] <= f.iso();
    }
    if (in && out) {
      ++straddling;
      EXPECT_TRUE(iv.straddles(f.iso())) << what;
    }
  }
  EXPECT_GT(straddling, 5) << what;
}

// Analytic gradients against central differences, where the differences are stable (two step
// sizes agree: away from kinks of d, medial ambiguities and the projection's jumps).
void check_gradients(const Field& f, const std::vector<Vec3>& pts, double rel, const std::string& what) {
  int tested = 0;
  const double wmax = 1.0;
  for (const Vec3& p : pts) {
    const double v = f.value(p);
    if (v < 0.03 * wmax || v > 0.97 * wmax) continue;
    const Vec3 fd1 = test::central_gradient(f, p, 1e-6);
    const Vec3 fd2 = test::central_gradient(f, p, 4e-6);
    if ((fd1 - fd2).norm() > 1e-4 * (1 + fd1.norm())) continue;
    ++tested;
    const Vec3 g = f.gradient(p);
    EXPECT_LT((g - fd1).norm(), rel * fd1.norm() + 1e-4)
        << what << " at " << p.transpose() << ": analytic " << g.transpose() << " fd " << fd1.transpose();
  }
  EXPECT_GT(tested, static_cast<int>(pts.size() / 10)) << what;
}

// ---------------------------------------------------------------------------------------------

TEST(Revolution, WasherFromClosedSquareProfile) {
  const double radius = 0.1;
  const FieldPtr f = make_revolution_field(square(1.5, 0.5, 0.5), surface(radius));
  EXPECT_EQ(f->iso(), 0.5);
  for (int k = 0; k < 12; ++k) {
    const double a = 2 * kPi * k / 12 + 0.05;
    auto at = [&](double r, double z) { return Vec3(r * std::cos(a), r * std::sin(a), z); };
    EXPECT_TRUE(f->is_inside(at(1.5, 0.5))) << a;
    EXPECT_FALSE(f->is_inside(at(0.5, 0.5))) << a;
    EXPECT_FALSE(f->is_inside(at(2.5, 0.5))) << a;
    EXPECT_FALSE(f->is_inside(Vec3(0, 0, 0.5)));
    // The surface is `radius` from the region: on the outer, inner, top faces and off a corner.
    EXPECT_NEAR(f->value(at(2 + radius, 0.5)), 0.5, 1e-9);
    EXPECT_NEAR(f->value(at(1 - radius, 0.3)), 0.5, 1e-9);
    EXPECT_NEAR(f->value(at(1.2, 1 + radius)), 0.5, 1e-9);
    EXPECT_NEAR(f->value(at(1.7, -radius)), 0.5, 1e-9);
    EXPECT_NEAR(f->value(at(2 + radius / std::sqrt(2.0), 1 + radius / std::sqrt(2.0))), 0.5, 1e-9);
    EXPECT_TRUE(f->is_inside(at(2 + 0.9 * radius, 0.5)));
    EXPECT_FALSE(f->is_inside(at(2 + 1.1 * radius, 0.5)));
    // Exact values against the kernel: d = 0.05 off the outer face.
    EXPECT_NEAR(f->value(at(2.05, 0.5)), reference_kernel(KernelKind::kWyvill, 0, 0.05 / 0.2), 1e-12);
  }
}

TEST(Revolution, OpenProfileIsATubeAndBezierProfileIsAVase) {
  const FieldPtr tube = make_revolution_field({CurveKind::kPolyline, {Vec2(1, 0), Vec2(1, 2)}, false}, surface(0.1));
  EXPECT_TRUE(tube->is_inside(Vec3(0, 1.05, 1)));
  EXPECT_TRUE(tube->is_inside(Vec3(-0.95, 0, 0.5)));
  EXPECT_FALSE(tube->is_inside(Vec3(0.8, 0, 1)));  // hollow: the profile is open
  EXPECT_FALSE(tube->is_inside(Vec3(0, 0, 1)));
  EXPECT_NEAR(tube->value(Vec3(0, 0.9, 1)), 0.5, 1e-9);
  // A Bezier profile: the surface is radius off the exact curve within the flattening tolerance.
  const Curve2 vase{CurveKind::kBezier, {Vec2(0.5, 0), Vec2(1.5, 0.5), Vec2(0.2, 1.2), Vec2(0.6, 2)}, false};
  CurveSurfaceOptions o = surface(0.05);
  o.tolerance = 1e-5;
  const FieldPtr f = make_revolution_field(vase, o);
  for (int i = 1; i < 20; ++i) {
    const double t = i / 20.0;
    const Vec2 c = curve_point(vase, t);
    const Vec2 d = curve_derivative(vase, t);
    const Vec2 n = Vec2(d.y(), -d.x()).normalized();
    const Vec2 q = c + 0.05 * n;
    const Vec3 p(q.x() * std::cos(1.0), q.x() * std::sin(1.0), q.y());
    if (q.x() > 0) {
      EXPECT_NEAR(f->value(p), 0.5, 3e-4) << t;  // d within 1e-5 of 0.05
    }
    const Vec3 on(c.x() * std::cos(2.0), c.x() * std::sin(2.0), c.y());
    EXPECT_NEAR(f->value(on), 1.0, 1e-6) << t;
  }
}

TEST(Revolution, GradientBoundsAndBound) {
  Rng rng(21);
  for (const Kernel k : {Kernel{KernelKind::kWyvill, 0.0}, Kernel{KernelKind::kBlinn, 0.0},
                         Kernel{KernelKind::kMetaball, 0.0}}) {
    const std::string what = kernel_name(k.kind);
    const FieldPtr f = make_revolution_field(square(1.5, 0.5, 0.5), surface(0.2, k));
    std::vector<Vec3> pts;
    for (int i = 0; i < 300; ++i) pts.push_back(random_point(rng, Aabb(Vec3(-2.5, -2.5, -0.5), Vec3(2.5, 2.5, 1.5))));
    check_gradients(*f, pts, 1e-4, what);
    check_bounds(*f, Aabb(Vec3(-4, -4, -3), Vec3(4, 4, 4)), 40, what);
    check_bound(*f, Aabb(Vec3(-2.5, -2.5, -0.5), Vec3(2.5, 2.5, 1.5)), 0.3, 22, what);
  }
}

TEST(Revolution, RejectsBadArguments) {
  EXPECT_THROW((void)make_revolution_field({CurveKind::kPolyline, {Vec2(-0.5, 0), Vec2(1, 1)}, false}), InvalidArgument);
  EXPECT_THROW((void)make_revolution_field({CurveKind::kPolyline, {Vec2(0.5, 0)}, false}), InvalidArgument);
  EXPECT_THROW((void)make_revolution_field(square(1.5, 0.5, 0.5), surface(0.0)), InvalidArgument);
  EXPECT_THROW((void)make_revolution_field(square(1.5, 0.5, 0.5), surface(-1.0)), InvalidArgument);
  CurveSurfaceOptions o;
  o.weight = 0;
  EXPECT_THROW((void)make_revolution_field(square(1.5, 0.5, 0.5), o), InvalidArgument);
  o = {};
  o.tolerance = -1;
  EXPECT_THROW((void)make_revolution_field(square(1.5, 0.5, 0.5), o), InvalidArgument);
  o = {};
  o.iso = 2;  // the Wyvill kernel never reaches 2
  EXPECT_THROW((void)make_revolution_field(square(1.5, 0.5, 0.5), o), InvalidArgument);
}

// ---------------------------------------------------------------------------------------------

TEST(Sweep, StraightPathIsACylinderWithCappedEnds) {
  const Curve3 path{CurveKind::kPolyline, {Vec3(0, 0, 0), Vec3(0, 0, 2)}};
  const FieldPtr f = make_sweep_field(path, ngon(0.3, 96), surface(0.05));
  const double apothem = 0.3 * std::cos(kPi / 96);
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * kPi * k / 16 + 0.01;
    for (const double z : {0.01, 0.5, 1.3, 1.99}) {
      EXPECT_TRUE(f->is_inside(Vec3(0.2 * std::cos(a), 0.2 * std::sin(a), z)));
      EXPECT_TRUE(f->is_inside(Vec3(0.33 * std::cos(a), 0.33 * std::sin(a), z)));
      EXPECT_FALSE(f->is_inside(Vec3(0.4 * std::cos(a), 0.4 * std::sin(a), z)));
    }
  }
  // Face of the polygon: the surface is 0.05 off the apothem.
  const double a0 = 2 * kPi * 0.5 / 96;  // middle of the first edge
  EXPECT_NEAR(f->value(Vec3((apothem + 0.05) * std::cos(a0), (apothem + 0.05) * std::sin(a0), 1)), 0.5, 1e-9);
  // Capped ends: d = sqrt(d2^2 + a^2) with a the axial distance past the end.
  EXPECT_TRUE(f->is_inside(Vec3(0.1, 0, -0.04)));
  EXPECT_FALSE(f->is_inside(Vec3(0.1, 0, -0.06)));
  EXPECT_TRUE(f->is_inside(Vec3(0, 0.1, 2.04)));
  EXPECT_FALSE(f->is_inside(Vec3(0, 0.1, 2.06)));
  EXPECT_NEAR(f->value(Vec3(0, 0, 2.05)), 0.5, 1e-9);
  EXPECT_NEAR(f->value(Vec3(apothem * std::cos(a0) + 0.03, apothem * std::sin(a0) * 1.0, -0.04)),
              reference_kernel(KernelKind::kWyvill, 0, std::hypot(0.03 * std::cos(a0), 0.04) / 0.1), 1e-6);
  // A path going up +z maps section x to world x and y to world y.
  const PathFrame fr = path_frame(path, 0.5);
  EXPECT_LT((fr.origin - Vec3(0, 0, 1)).norm(), 1e-15);
  EXPECT_LT((fr.normal - Vec3::UnitX()).norm(), 1e-15);
  EXPECT_LT((fr.binormal - Vec3::UnitY()).norm(), 1e-15);
  const FieldPtr offset = make_sweep_field(path, square(0.5, 0, 0.1), surface(0.02));
  EXPECT_TRUE(offset->is_inside(Vec3(0.5, 0, 1)));
  EXPECT_FALSE(offset->is_inside(Vec3(0, 0.5, 1)));
}

TEST(Sweep, PolylineBendIsARoundedJointWithoutNotch) {
  // Up the z axis, then along +x: the outer side of the bend is the wedge between -x and +z.
  const Curve3 path{CurveKind::kPolyline, {Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1)}};
  const FieldPtr f = make_sweep_field(path, ngon(0.2, 64), surface(0.05));
  const Vec3 v(0, 0, 1);
  std::vector<Vec3> pts;
  for (int i = 0; i <= 12; ++i) {
    const double psi = kPi / 2 * i / 12;
    const Vec3 dir = std::cos(psi) * Vec3(-1, 0, 0) + std::sin(psi) * Vec3(0, 0, 1);
    EXPECT_TRUE(f->is_inside(v + 0.2 * dir)) << psi;  // 0.2 from the path: inside the tube
    EXPECT_FALSE(f->is_inside(v + 0.3 * dir)) << psi;
    const Vec3 tilted = (dir + Vec3(0, 0.7, 0)).normalized();
    EXPECT_TRUE(f->is_inside(v + 0.2 * tilted)) << psi;
    EXPECT_FALSE(f->is_inside(v + 0.3 * tilted)) << psi;
    pts.push_back(v + 0.23 * tilted);
    pts.push_back(v + 0.24 * dir);
  }
  EXPECT_TRUE(f->is_inside(Vec3(0.1, 0.1, 0.9)));  // inner side of the bend
  check_gradients(*f, pts, 1e-4, "polyline bend");
  // Piecewise-constant rotation-minimizing frames: N = x, B = y going up; across the vertex the
  // frame turns about the bend axis y.
  const PathFrame up = path_frame(path, 0.25);
  EXPECT_LT((up.normal - Vec3::UnitX()).norm(), 1e-12);
  const PathFrame along = path_frame(path, 0.75);
  EXPECT_LT((along.tangent - Vec3::UnitX()).norm(), 1e-12);
  EXPECT_LT((along.normal - Vec3(0, 0, -1)).norm(), 1e-12);
  EXPECT_LT((along.binormal - Vec3::UnitY()).norm(), 1e-12);
  const PathFrame joint = path_frame(path, 0.5);  // the bisector plane
  EXPECT_LT((joint.tangent - Vec3(1, 0, 1).normalized()).norm(), 1e-12);
  EXPECT_LT((joint.binormal - Vec3::UnitY()).norm(), 1e-12);
}

TEST(Sweep, FramesOnAPlanarPathStayInItsPlaneAndAreOrthonormal) {
  // A planar Bezier in the x-z plane: the rotation-minimizing normal stays in the plane.
  const Curve3 path{CurveKind::kBezier, {Vec3(0, 0, 0), Vec3(2, 0, 1), Vec3(-1, 0, 2), Vec3(1, 0, 3)}};
  for (int i = 0; i <= 50; ++i) {
    const double s = i / 50.0;
    const PathFrame f = path_frame(path, s);
    EXPECT_NEAR(f.normal.y(), 0, 1e-12) << s;
    EXPECT_NEAR(std::abs(f.binormal.y()), 1, 1e-12) << s;
    EXPECT_NEAR(f.tangent.y(), 0, 1e-12) << s;
    EXPECT_NEAR(f.tangent.norm(), 1, 1e-12);
    EXPECT_NEAR(f.normal.norm(), 1, 1e-12);
    EXPECT_NEAR(f.tangent.dot(f.normal), 0, 1e-12);
    EXPECT_LT((f.binormal - f.tangent.cross(f.normal)).norm(), 1e-12);
    // The origin is on the curve and the tangent is the curve's.
    const PathProjection pr = project_on_path(path, f.origin);
    EXPECT_LT((pr.point - f.origin).norm(), 1e-9);
    EXPECT_NEAR(pr.s, s, 1e-9);
    EXPECT_LT((curve_derivative(path, pr.t).normalized() - f.tangent).norm(), 1e-9);
  }
  // Both ends as in the header: T0 = (2,0,1)/sqrt(5), N0 = x made orthogonal to T0.
  const PathFrame f0 = path_frame(path, 0);
  const Vec3 t0 = Vec3(2, 0, 1).normalized();
  EXPECT_LT((f0.tangent - t0).norm(), 1e-12);
  EXPECT_LT((f0.normal - (Vec3::UnitX() - t0.x() * t0).normalized()).norm(), 1e-12);
}

TEST(Sweep, FramesMatchAnIntegratedRotationMinimizingFrame) {
  const Curve3 path{CurveKind::kBSpline,
                    {Vec3(0, 0, 0), Vec3(1, 0.5, 0.5), Vec3(0.5, 1.5, 1), Vec3(-0.5, 1, 2), Vec3(0, 0, 2.5), Vec3(1, -0.5, 3)}};
  // Integrate dN/dt = -(N . dT/dt) T with RK4 (T = C'/|C'|), from the documented N0.
  auto tangent = [&](double t) { return curve_derivative(path, t).normalized(); };
  auto dtangent = [&](double t) {
    const Vec3 d1 = curve_derivative(path, t), d2 = curve_second_derivative(path, t);
    const Vec3 T = d1.normalized();
    return Vec3((d2 - d2.dot(T) * T) / d1.norm());
  };
  auto rhs = [&](double t, const Vec3& n) { return Vec3(-n.dot(dtangent(t)) * tangent(t)); };
  const Vec3 T0 = tangent(0);
  const Vec3 e = std::abs(T0.x()) > 0.9 ? Vec3::UnitY() : Vec3::UnitX();
  Vec3 n = (e - e.dot(T0) * T0).normalized();
  double t = 0;
  const int steps = 20000;
  const double h = 1.0 / steps;
  std::vector<double> targets;
  for (int i = 0; i <= 10; ++i) targets.push_back(project_on_path(path, path_frame(path, i / 10.0).origin).t);
  std::size_t next = 0;
  int compared = 0;
  for (int k = 0; k <= steps && next < targets.size(); ++k) {
    while (next < targets.size() && targets[next] <= t + h) {
      // Partial step to the target parameter.
      const double hh = targets[next] - t;
      const Vec3 k1 = rhs(t, n), k2 = rhs(t + hh / 2, n + hh / 2 * k1), k3 = rhs(t + hh / 2, n + hh / 2 * k2),
                 k4 = rhs(t + hh, n + hh * k3);
      const Vec3 nt = (n + hh / 6 * (k1 + 2 * k2 + 2 * k3 + k4)).normalized();
      const PathFrame f = path_frame(path, next / 10.0);
      EXPECT_LT((f.normal - nt).norm(), 1e-5) << "s " << next / 10.0 << ": " << f.normal.transpose()
                                               << " vs ode " << nt.transpose();
      EXPECT_NEAR(f.normal.dot(f.tangent), 0, 1e-12);
      ++compared;
      ++next;
    }
    if (k == steps) break;
    const Vec3 k1 = rhs(t, n), k2 = rhs(t + h / 2, n + h / 2 * k1), k3 = rhs(t + h / 2, n + h / 2 * k2),
               k4 = rhs(t + h, n + h * k3);
    n = (n + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)).normalized();
    t += h;
  }
  EXPECT_EQ(compared, 11);
}

// ---------------------------------------------------------------------------------------------

// Points p = O + x N + y B in the plane of section i: f > iso exactly where (x, y) is within
// `radius` of the section's region, outside a thin band.
void check_reproduces(const Field& f, const Curve3& path, const Curve2& section, double s, double radius,
                      const std::string& what) {
  const PathFrame fr = path_frame(path, s);
  const std::vector<Vec2> ref = section.kind == CurveKind::kPolyline ? section.points : flatten(section, 1e-6);
  double extent = 0;
  for (const auto& v : section.points) extent = std::max(extent, v.norm());
  const double band = 2e-3 * extent + 1e-9;
  int in = 0, out = 0;
  const int n = 30;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const Vec2 q(-0.6 + 1.2 * i / n, -0.6 + 1.2 * j / n);
      const double d = region_distance(q, ref, section.closed);
      if (std::abs(d - radius) < band) continue;
      const Vec3 p = fr.origin + q.x() * fr.normal + q.y() * fr.binormal;
      const bool inside = d < radius;
      EXPECT_EQ(f.is_inside(p), inside) << what << " s " << s << " q " << q.transpose() << " d " << d
                                        << " f " << f.value(p);
      (inside ? in : out) += 1;
    }
  }
  EXPECT_GT(in, 20) << what;
  EXPECT_GT(out, 20) << what;
}

TEST(Skin, ReproducesItsCrossSections) {
  const Curve3 path = curved_path();
  const Curve2 circle_spline{CurveKind::kBSpline,
                             {Vec2(0.35, 0), Vec2(0.25, 0.25), Vec2(0, 0.35), Vec2(-0.25, 0.25), Vec2(-0.35, 0),
                              Vec2(-0.25, -0.25), Vec2(0, -0.35), Vec2(0.25, -0.25)},
                             true};
  const std::vector<SkinSection> sections = {
      {square(0, 0, 0.3), 0.0}, {star(0.45, 0.18, 5), 0.4}, {circle_spline, 0.7}, {square(0.1, 0, 0.15), 1.0}};
  for (const auto interp : {SkinInterpolation::kLinear, SkinInterpolation::kQuadratic, SkinInterpolation::kCubic}) {
    SkinOptions o;
    o.surface = surface(0.05);
    o.interpolation = interp;
    const FieldPtr f = make_skin_field(path, sections, o);
    const std::string what = "interpolation " + std::to_string(static_cast<int>(interp));
    for (const auto& sec : sections) check_reproduces(*f, path, sec.curve, sec.s, 0.05, what);
  }
  // A sweep reproduces its one section everywhere along the path.
  const FieldPtr sweep = make_sweep_field(path, star(0.45, 0.18, 5), surface(0.05));
  for (const double s : {0.0, 0.15, 0.5, 0.85, 1.0}) check_reproduces(*sweep, path, star(0.45, 0.18, 5), s, 0.05, "sweep");
  // An open section is a curve, not a region.
  const Curve2 arc{CurveKind::kBezier, {Vec2(-0.4, -0.2), Vec2(0, 0.6), Vec2(0.4, -0.2)}, false};
  const FieldPtr open = make_sweep_field(path, arc, surface(0.05));
  check_reproduces(*open, path, arc, 0.3, 0.05, "open section");
}

TEST(Skin, Figure410TableFourLegsAndATop) {
  const Curve3 path{CurveKind::kPolyline, {Vec3(0, 0, 0), Vec3(0, 0, 1)}};
  const double leg = 0.08, at = 0.4, top = 0.6;
  std::vector<SkinSection> sections;
  for (const double x : {-at, at}) {
    for (const double y : {-at, at}) sections.push_back({square(x, y, leg), 0.0});
  }
  sections.push_back({square(0, 0, top), 1.0});
  for (const auto interp : {SkinInterpolation::kLinear, SkinInterpolation::kQuadratic, SkinInterpolation::kCubic}) {
    SkinOptions o;
    o.surface = surface(0.02);
    o.interpolation = interp;
    const FieldPtr f = make_skin_field(path, sections, o);
    for (const double x : {-at, at}) {
      for (const double y : {-at, at}) {
        EXPECT_TRUE(f->is_inside(Vec3(x, y, 0.05)));
        EXPECT_TRUE(f->is_inside(Vec3(x + 0.05, y - 0.05, 0.01)));
        EXPECT_FALSE(f->is_inside(Vec3(x, y, -0.05)));  // capped below the legs
      }
    }
    EXPECT_FALSE(f->is_inside(Vec3(0, 0, 0.05)));   // between the legs
    EXPECT_FALSE(f->is_inside(Vec3(0, at, 0.05)));  // between two legs on a side
    EXPECT_FALSE(f->is_inside(Vec3(0, 0, 0.5)));
    EXPECT_TRUE(f->is_inside(Vec3(0, 0, 0.99)));    // the top
    EXPECT_TRUE(f->is_inside(Vec3(0.55, -0.55, 0.995)));
    EXPECT_FALSE(f->is_inside(Vec3(0, 0, 1.05)));   // capped above
    // Linear: at height z the distance is (1 - z) d_legs + z d_top (s = z on this path).
    if (interp == SkinInterpolation::kLinear) {
      const double z = 0.3;
      const double d_legs = std::hypot(at - leg, at - leg);
      const double d = (1 - z) * d_legs;
      EXPECT_NEAR(f->value(Vec3(0, 0, z)), reference_kernel(KernelKind::kWyvill, 0, d / 0.04), 1e-12);
    }
  }
}

// Squares of half-size h_k centred on a straight path: along the x ray at height s, the in-plane
// distance is x - h(s), with h interpolated like the distances.
TEST(Skin, InterpolationSchemesMatchTheirFormulas) {
  const Curve3 path{CurveKind::kPolyline, {Vec3(0, 0, 0), Vec3(0, 0, 1)}};
  const double s0 = 0.1, s1 = 0.4, s2 = 0.9;
  const double h0 = 0.2, h1 = 0.5, h2 = 0.3;
  const std::vector<SkinSection> sections = {{square(0, 0, h1), s1}, {square(0, 0, h0), s0}, {square(0, 0, h2), s2}};
  const double radius = 0.5;  // R = 1 with the Wyvill kernel
  auto linear = [&](double s) {
    if (s <= s0) return h0;
    if (s >= s2) return h2;
    return s < s1 ? h0 + (h1 - h0) * (s - s0) / (s1 - s0) : h1 + (h2 - h1) * (s - s1) / (s2 - s1);
  };
  auto quadratic = [&](double s) {
    if (s <= s0) return h0;
    if (s >= s2) return h2;
    return h0 * (s - s1) * (s - s2) / ((s0 - s1) * (s0 - s2)) + h1 * (s - s0) * (s - s2) / ((s1 - s0) * (s1 - s2)) +
           h2 * (s - s0) * (s - s1) / ((s2 - s0) * (s2 - s1));
  };
  auto cubic = [&](double s) {
    if (s <= s0) return h0;
    if (s >= s2) return h2;
    const double d0 = (h1 - h0) / (s1 - s0), d1 = (h2 - h1) / (s2 - s1);
    const double m0 = d0, m2 = d1;
    const double m1 = ((s2 - s1) * d0 + (s1 - s0) * d1) / (s2 - s0);  // parabola's slope at s1
    double a, b, ya, yb, ma, mb;
    if (s < s1) {
      a = s0, b = s1, ya = h0, yb = h1, ma = m0, mb = m1;
    } else {
      a = s1, b = s2, ya = h1, yb = h2, ma = m1, mb = m2;
    }
    const double hh = b - a, u = (s - a) / hh;
    return (2 * u * u * u - 3 * u * u + 1) * ya + (u * u * u - 2 * u * u + u) * hh * ma +
           (-2 * u * u * u + 3 * u * u) * yb + (u * u * u - u * u) * hh * mb;
  };
  struct Case {
    SkinInterpolation kind;
    std::function<double(double)> h;
  };
  const std::vector<Case> cases = {{SkinInterpolation::kLinear, linear},
                                   {SkinInterpolation::kQuadratic, quadratic},
                                   {SkinInterpolation::kCubic, cubic}};
  for (const auto& c : cases) {
    SkinOptions o;
    o.surface = surface(radius);
    o.interpolation = c.kind;
    const FieldPtr f = make_skin_field(path, sections, o);
    for (int i = 0; i <= 40; ++i) {
      const double s = i / 40.0;
      for (const double x : {0.65, 0.8, 1.1}) {
        const double d = x - c.h(s);
        EXPECT_NEAR(f->value(Vec3(x, 0, s)), reference_kernel(KernelKind::kWyvill, 0, std::max(d, 0.0)), 1e-12)
            << static_cast<int>(c.kind) << " s " << s << " x " << x;
        // The sections sit at x = 0 in y too: the same along -y.
        EXPECT_NEAR(f->value(Vec3(0, -x, s)), reference_kernel(KernelKind::kWyvill, 0, std::max(d, 0.0)), 1e-12);
      }
    }
  }
}

TEST(Skin, NewtonProjectionSolvesEquation41) {
  const Curve3 path = curved_path();
  double extent = 0;
  {
    Aabb b;
    for (const auto& p : path.points) b.extend(p);
    extent = b.diagonal().norm();
  }
  const double tol = 1e-3 * extent;
  const auto poly = flatten(path, tol);
  // Dense samples of the exact curve for a brute-force closest distance.
  std::vector<Vec3> dense;
  for (int i = 0; i <= 20000; ++i) dense.push_back(curve_point(path, i / 20000.0));
  Rng rng(31);
  int newton = 0;
  for (int k = 0; k < 300; ++k) {
    const double t = rng.uniform(-0.05, 1.05);
    const Vec3 c = curve_point(path, std::clamp(t, 0.0, 1.0));
    const Vec3 p = c + rng.uniform(0, 0.5) * test::random_unit(rng);
    const PathProjection pr = project_on_path(path, p);
    ASSERT_GE(pr.t, 0.0);
    ASSERT_LE(pr.t, 1.0);
    EXPECT_LT((pr.point - curve_point(path, pr.t)).norm(), 1e-14);
    const double dist = (pr.point - p).norm();
    double dpoly = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
      const Vec3 ab = poly[i + 1] - poly[i];
      const double u = std::clamp((p - poly[i]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      dpoly = std::min(dpoly, (p - poly[i] - u * ab).norm());
    }
    EXPECT_LE(dist, dpoly + tol) << p.transpose();
    double brute = std::numeric_limits<double>::infinity();
    for (const auto& q : dense) brute = std::min(brute, (q - p).norm());
    EXPECT_LE(dist, brute + 1e-9) << p.transpose();
    if (pr.newton_used && pr.t > 0 && pr.t < 1) {
      ++newton;
      const Vec3 d1 = curve_derivative(path, pr.t);
      EXPECT_LT(std::abs((pr.point - p).dot(d1)) / d1.norm(), 1e-12 * extent) << p.transpose();
    }
  }
  EXPECT_GT(newton, 200);
}

TEST(Skin, GradientsMatchCentralDifferences) {
  const Curve3 path = curved_path();
  const std::vector<SkinSection> sections = {
      {ngon(0.3, 7), 0.0}, {star(0.4, 0.2, 5), 0.35}, {square(0, 0.05, 0.2), 0.6}, {ngon(0.2, 9, 0.3), 1.0}};
  Rng rng(41);
  std::vector<Vec3> pts;
  for (int i = 0; i < 400; ++i) {
    const double s = rng.uniform(-0.05, 1.05);
    const PathFrame f = path_frame(path, std::clamp(s, 0.0, 1.0));
    const double a = s < 0 ? s : (s > 1 ? s - 1 : 0.0);
    pts.push_back(f.origin + rng.uniform(-0.5, 0.5) * f.normal + rng.uniform(-0.5, 0.5) * f.binormal + 3 * a * f.tangent);
  }
  for (const auto interp : {SkinInterpolation::kLinear, SkinInterpolation::kQuadratic, SkinInterpolation::kCubic}) {
    for (const Kernel k : {Kernel{KernelKind::kWyvill, 0.0}, Kernel{KernelKind::kBlinn, 0.0}}) {
      SkinOptions o;
      o.surface = surface(0.1, k);
      o.interpolation = interp;
      const FieldPtr f = make_skin_field(path, sections, o);
      check_gradients(*f, pts, 5e-4,
                      "skin " + std::to_string(static_cast<int>(interp)) + " " + kernel_name(k.kind));
    }
  }
  const FieldPtr sweep = make_sweep_field(path, star(0.4, 0.2, 5), surface(0.1));
  check_gradients(*sweep, pts, 5e-4, "sweep");
}

TEST(Skin, BoundsAndBoundAreConservative) {
  const Curve3 path = curved_path();
  // Sections of very different sizes at close s: the quadratic and cubic schemes overshoot.
  const std::vector<SkinSection> sections = {
      {ngon(0.1, 6), 0.0}, {square(0, 0, 0.5), 0.1}, {ngon(0.05, 5), 0.2}, {star(0.3, 0.1, 4), 1.0}};
  Aabb region;
  for (const auto& p : path.points) region.extend(p);
  region = grown(region, 0.8);
  for (const auto interp : {SkinInterpolation::kLinear, SkinInterpolation::kQuadratic, SkinInterpolation::kCubic}) {
    for (const Kernel k : {Kernel{KernelKind::kWyvill, 0.0}, Kernel{KernelKind::kInversePower, 0.0}}) {
      SkinOptions o;
      o.surface = surface(0.08, k);
      o.interpolation = interp;
      const FieldPtr f = make_skin_field(path, sections, o);
      const std::string what = "skin " + std::to_string(static_cast<int>(interp)) + " " + kernel_name(k.kind);
      check_bounds(*f, grown(region, 1.0), 36, what);
      check_bound(*f, region, 0.2, 51, what);
      EXPECT_FALSE(f->describe().empty());
    }
  }
  const FieldPtr sweep = make_sweep_field(path, square(0.1, 0, 0.2), surface(0.05));
  check_bounds(*sweep, grown(region, 1.0), 36, "sweep");
  check_bound(*sweep, region, 0.2, 52, "sweep");
  // Far away the field is exactly 0 and bound() says so.
  EXPECT_EQ(sweep->value(Vec3(10, 10, 10)), 0.0);
  const Interval far = sweep->bound(Aabb(Vec3(9, 9, 9), Vec3(11, 11, 11)));
  EXPECT_EQ(far.lo, 0.0);
  EXPECT_EQ(far.hi, 0.0);
}

TEST(Skin, RejectsBadArguments) {
  const Curve3 path = curved_path();
  const std::vector<SkinSection> ok = {{square(0, 0, 0.2), 0.0}};
  EXPECT_NO_THROW((void)make_skin_field(path, ok));
  auto message = [](auto&& fn) {
    try {
      fn();
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no throw");
  };
  EXPECT_NE(message([&] { (void)make_skin_field(path, {}); }).find("no sections"), std::string::npos);
  EXPECT_NE(message([&] { (void)make_skin_field(path, {{square(0, 0, 0.2), 1.5}}); }).find("outside [0, 1]"),
            std::string::npos);
  EXPECT_NE(message([&] { (void)make_skin_field(path, {{square(0, 0, 0.2), std::nan("")}}); }).find("outside"),
            std::string::npos);
  EXPECT_NE(message([&] {
              (void)make_skin_field({CurveKind::kBezier, {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)}}, ok);
            }).find("zero length"),
            std::string::npos);
  EXPECT_NE(message([&] {
              (void)make_skin_field(path, {{Curve2{CurveKind::kPolyline, {Vec2(0, 0)}, false}, 0.5}});
            }).find("section 0"),
            std::string::npos);
  EXPECT_THROW((void)make_skin_field({CurveKind::kPolyline, {Vec3(0, 0, 0)}}, ok), InvalidArgument);
  EXPECT_THROW((void)make_skin_field({CurveKind::kPolyline, {Vec3(0, 0, 0), Vec3(0, std::nan(""), 1)}}, ok),
               InvalidArgument);
  SkinOptions o;
  o.surface.radius = 0;
  EXPECT_NE(message([&] { (void)make_skin_field(path, ok, o); }).find("radius"), std::string::npos);
  EXPECT_THROW((void)make_sweep_field(path, square(0, 0, 0.2), surface(-0.1)), InvalidArgument);
  EXPECT_THROW((void)path_frame(path, 1.5), InvalidArgument);
  EXPECT_THROW((void)path_frame({CurveKind::kPolyline, {Vec3(0, 0, 0), Vec3(0, 0, 0)}}, 0.5), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
