// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/primitives.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using test::grown;
using test::random_point;
using test::random_unit;
using Vec2 = Eigen::Vector2d;

constexpr double kPi = std::numbers::pi;

// The C1 fade of infinite kernels as documented in tolerances.h: 1 up to 80 % of the cut-off
// distance, a smoothstep to 0 at the cut-off.
double reference_fade(double x, double cut) {
  const double v = (x / cut) * (x / cut);
  if (v <= 0.64) return 1;
  if (v >= 1) return 0;
  const double s = (v - 0.64) / 0.36;
  return 1 - s * s * (3 - 2 * s);
}

// weight k(d / R) from the kernel's formula, with the documented fade for infinite kernels.
double expected_value(const Kernel& k, double iso, double weight, double R, double d) {
  const double x = d / R;
  double v = test::reference_kernel(k.kind, k.parameter, x);
  if (test::is_infinite_kernel(k.kind)) v *= reference_fade(x, k.support(iso / weight));
  return weight * v;
}

// Two unit vectors completing n to an orthonormal frame.
void frame(const Vec3& n, Vec3& e1, Vec3& e2) {
  e1 = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  e2 = n.cross(e1);
}

// Distance to a circle by dense sampling of the angle, then golden-section refinement of the
// squared distance in long double.
double brute_circle_distance(const Vec3& p, const Vec3& c, const Vec3& normal, double rc) {
  Vec3 e1, e2;
  const Vec3 n = normal.normalized();
  frame(n, e1, e2);
  auto d2 = [&](long double phi) {
    long double s = 0;
    for (int k = 0; k < 3; ++k) {
      const long double q = c[k] + rc * (std::cos(phi) * e1[k] + std::sin(phi) * e2[k]);
      s += (p[k] - q) * (p[k] - q);
    }
    return s;
  };
  constexpr int kSamples = 720;
  long double best = 0, best_d = d2(0);
  for (int i = 1; i < kSamples; ++i) {
    const long double phi = 2 * kPi * i / kSamples;
    if (d2(phi) < best_d) {
      best_d = d2(phi);
      best = phi;
    }
  }
  long double lo = best - 2 * kPi / kSamples, hi = best + 2 * kPi / kSamples;
  const long double g = (std::sqrt(5.0L) - 1) / 2;
  for (int it = 0; it < 120; ++it) {
    const long double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    (d2(m1) < d2(m2) ? hi : lo) = d2(m1) < d2(m2) ? m2 : m1;
  }
  return static_cast<double>(std::sqrt(d2((lo + hi) / 2)));
}

// Distance to a solid box by clamping the point into it.
double clamp_box_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
}

// A 2D half-plane n·x <= b.
struct HalfPlane {
  Vec2 n;
  double b;
};

// Vertices of the convex polygon given by half-planes: every pairwise intersection of their
// lines that satisfies all of them, in angular order.
std::vector<Vec2> polygon_of(const std::vector<HalfPlane>& hs, double tol) {
  std::vector<Vec2> v;
  for (std::size_t i = 0; i < hs.size(); ++i) {
    for (std::size_t j = i + 1; j < hs.size(); ++j) {
      Eigen::Matrix2d A;
      A << hs[i].n.transpose(), hs[j].n.transpose();
      if (std::abs(A.determinant()) < 1e-14) continue;
      const Vec2 x = A.inverse() * Vec2(hs[i].b, hs[j].b);
      bool ok = true;
      for (const auto& h : hs) ok = ok && h.n.dot(x) <= h.b + tol;
      bool dup = false;
      for (const auto& w : v) dup = dup || (w - x).norm() < tol;
      if (ok && !dup) v.push_back(x);
    }
  }
  Vec2 c = Vec2::Zero();
  for (const auto& x : v) c += x;
  c /= static_cast<double>(v.size());
  std::sort(v.begin(), v.end(), [&](const Vec2& a, const Vec2& b) {
    return std::atan2(a.y() - c.y(), a.x() - c.x()) < std::atan2(b.y() - c.y(), b.x() - c.x());
  });
  return v;
}

// Distance from a 2D point to a convex polygon (0 inside), edges by brute force.
double polygon_distance(const Vec2& x, const std::vector<Vec2>& poly,
                        const std::vector<HalfPlane>& hs) {
  bool inside = true;
  for (const auto& h : hs) inside = inside && h.n.dot(x) <= h.b;
  if (inside) return 0;
  const Vec3 p(x.x(), x.y(), 0);
  if (poly.size() == 1) return (x - poly[0]).norm();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& a = poly[i];
    const Vec2& b = poly[(i + 1) % poly.size()];
    best = std::min(best, test::brute_distance(p, Vec3(a.x(), a.y(), 0), Vec3(b.x(), b.y(), 0)));
  }
  return best;
}

// The inner element of a rounded cone, independently: the meridian section (t along a -> b,
// s across, both signs) of the cone is the trapezoid (0, ±ra), (L, ±rb); its inward offset by
// `rounding` is the intersection of the four edge half-planes moved inward.
struct ConeReference {
  Vec3 a, u;
  std::vector<HalfPlane> hs;
  std::vector<Vec2> poly;
  ConeReference(const Vec3& a_, double ra, const Vec3& b, double rb, double rounding) : a(a_) {
    const double L = (b - a).norm();
    u = (b - a) / L;
    const double slant = std::hypot(L, rb - ra);
    hs.push_back({Vec2(-1, 0), -rounding});
    hs.push_back({Vec2(1, 0), L - rounding});
    hs.push_back({Vec2(-(rb - ra), L) / slant, L * ra / slant - rounding});
    hs.push_back({Vec2(-(rb - ra), -L) / slant, L * ra / slant - rounding});
    poly = polygon_of(hs, 1e-12 * (L + ra + rb));
  }
  double distance(const Vec3& p) const {
    const double t = (p - a).dot(u);
    const double rho = (p - a - t * u).norm();
    return polygon_distance(Vec2(t, rho), poly, hs);
  }
};

// One primitive geometry: how to build it for given options, its reference distance, its
// surface radius (R = radius / x_iso) and a box to sample around it.
struct Geometry {
  std::string name;
  std::function<FieldPtr(const DistancePrimitiveOptions&)> make;
  std::function<double(const Vec3&)> distance;
  double radius;
  Aabb sample;
};

std::vector<Geometry> geometries() {
  std::vector<Geometry> g;
  {
    const Vec3 c(0.3, -0.2, 0.5), n(0.3, 0.4, 1);
    g.push_back(
        {"torus",
         [=](const DistancePrimitiveOptions& o) { return make_circle_field(c, n, 2.0, 0.6, o); },
         [=](const Vec3& p) { return brute_circle_distance(p, c, n, 2.0); }, 0.6,
         Aabb(c - Vec3::Constant(3.5), c + Vec3::Constant(3.5))});
  }
  {
    const Vec3 c(1, 2, -1), h(1.5, 0.8, 1.1);
    const double r = 0.3;
    g.push_back(
        {"box", [=](const DistancePrimitiveOptions& o) { return make_box_field(c, h, r, o); },
         [=](const Vec3& p) {
           return clamp_box_distance(p, c - h + Vec3::Constant(r), c + h - Vec3::Constant(r));
         },
         r, Aabb(c - h - Vec3::Constant(1.5), c + h + Vec3::Constant(1.5))});
  }
  {
    const Vec3 a(0, 0, 0), b(1, 2, 3);
    const ConeReference ref(a, 0.9, b, 0.9, 0.25);
    g.push_back(
        {"cylinder",
         [=](const DistancePrimitiveOptions& o) { return make_cylinder_field(a, b, 0.9, 0.25, o); },
         [=](const Vec3& p) { return ref.distance(p); }, 0.25,
         grown(Aabb(a.cwiseMin(b), a.cwiseMax(b)), 2.0)});
  }
  {
    const Vec3 a(0.5, 0, -1), b(0, 1, 2);
    const ConeReference ref(a, 1.2, b, 0.4, 0.2);
    g.push_back(
        {"cone",
         [=](const DistancePrimitiveOptions& o) { return make_cone_field(a, 1.2, b, 0.4, 0.2, o); },
         [=](const Vec3& p) { return ref.distance(p); }, 0.2,
         grown(Aabb(a.cwiseMin(b), a.cwiseMax(b)), 2.0)});
  }
  {
    const Vec3 a(0, 0, 0), b(0.2, -0.1, 2);
    const ConeReference ref(a, 1.0, b, 0.0, 0.15);
    g.push_back({"pointed cone",
                 [=](const DistancePrimitiveOptions& o) {
                   return make_cone_field(a, 1.0, b, 0.0, 0.15, o);
                 },
                 [=](const Vec3& p) { return ref.distance(p); }, 0.15,
                 grown(Aabb(a.cwiseMin(b), a.cwiseMax(b)), 1.5)});
  }
  {
    const Vec3 q(0.2, 0.1, -0.3), n(1, 2, -0.5);
    const double falloff = 0.4;
    g.push_back(
        {"plane",
         [=](const DistancePrimitiveOptions& o) { return make_plane_field(q, n, falloff, o); },
         [=](const Vec3& p) { return std::max(0.0, n.normalized().dot(p - q) + falloff); }, falloff,
         Aabb(q - Vec3::Constant(2), q + Vec3::Constant(2))});
  }
  return g;
}

DistancePrimitiveOptions options_for(const Kernel& k, double weight = 1.0) {
  DistancePrimitiveOptions o;
  o.kernel = k;
  o.weight = weight;
  return o;
}

TEST(Primitive, ValuesAreKernelOfIndependentDistance) {
  Rng rng(11);
  for (const auto& geo : geometries()) {
    // Points near the element and their reference distances, shared by all kernels.
    std::vector<Vec3> pts;
    std::vector<double> dist;
    for (int i = 0; i < 150; ++i) {
      pts.push_back(random_point(rng, geo.sample));
      dist.push_back(geo.distance(pts.back()));
    }
    for (const auto& k : test::distance_kernels()) {
      for (const double weight : {1.0, 1.7}) {
        const FieldPtr f = geo.make(options_for(k, weight));
        const double iso = test::reference_iso(k.kind);
        ASSERT_EQ(f->iso(), iso);
        const double R = geo.radius / k.x_at(iso);
        std::vector<double> v(pts.size());
        f->evaluate(pts, v);
        int compared = 0;
        for (std::size_t i = 0; i < pts.size(); ++i) {
          // The inverse power kernel is held constant below x = 1e-6 (singular at 0).
          if (k.kind == KernelKind::kInversePower && dist[i] < 1e-3 * R) continue;
          const double e = expected_value(k, iso, weight, R, dist[i]);
          ASSERT_NEAR(v[i], e, 1e-9 * (1 + std::abs(e)))
              << geo.name << " " << kernel_name(k.kind) << " w " << weight << " at "
              << pts[i].transpose() << " d " << dist[i];
          ++compared;
        }
        EXPECT_GT(compared, 60) << geo.name;
      }
    }
  }
}

TEST(Primitive, DefaultsAreWyvillAtHalf) {
  const FieldPtr f = make_box_field(Vec3::Zero(), Vec3(1, 1, 1), 0.5);
  EXPECT_EQ(f->iso(), 0.5);
  EXPECT_DOUBLE_EQ(f->value(Vec3::Zero()), 1.0);  // inside the element: k(0) = 1
  // Surface exactly at the face; the Wyvill R is 2 * rounding = 1: f at d = 0.75 is k(0.75).
  EXPECT_NEAR(f->value(Vec3(1, 0, 0)), 0.5, 1e-15);
  EXPECT_NEAR(f->value(Vec3(1.25, 0, 0)), test::reference_kernel(KernelKind::kWyvill, 0, 0.75),
              1e-15);
  EXPECT_EQ(f->value(Vec3(1.5, 0, 0)), 0.0);
}

// Surface points (f == iso within 1e-12), with points 1e-6 outward outside and inward inside.
void expect_surface(const Field& f, const Vec3& p, const Vec3& outward, const std::string& what) {
  const Vec3 n = outward.normalized();
  EXPECT_NEAR(f.value(p), f.iso(), 1e-12) << what << " at " << p.transpose();
  EXPECT_FALSE(f.is_inside(p + 1e-6 * n)) << what << " at " << p.transpose();
  EXPECT_TRUE(f.is_inside(p - 1e-6 * n)) << what << " at " << p.transpose();
}

TEST(Primitive, TorusSurfaceIsRadiusFromCircle) {
  const Vec3 c(0.3, -0.2, 0.5), n(0.3, 0.4, 1);
  Vec3 e1, e2;
  frame(n.normalized(), e1, e2);
  for (const auto& k :
       {Kernel{KernelKind::kWyvill, 0.0}, Kernel{KernelKind::kBlinn, 0.0},
        Kernel{KernelKind::kMetaball, 0.0}, Kernel{KernelKind::kInversePower, 0.0}}) {
    const FieldPtr f = make_circle_field(c, n, 2.0, 0.6, options_for(k));
    Rng rng(3);
    for (int i = 0; i < 50; ++i) {
      const double phi = rng.uniform(0, 2 * kPi), psi = rng.uniform(0, 2 * kPi);
      const Vec3 radial = std::cos(phi) * e1 + std::sin(phi) * e2;
      const Vec3 offset = std::cos(psi) * radial + std::sin(psi) * n.normalized();
      expect_surface(*f, c + 2.0 * radial + 0.6 * offset, offset, "torus " + kernel_name(k.kind));
    }
    EXPECT_FALSE(f->is_inside(c)) << "the hole of the torus";
  }
}

TEST(Primitive, BoxTouchesItsFaces) {
  const Vec3 c(1, 2, -1), h(1.5, 0.8, 1.1);
  const double r = 0.3;
  for (const auto& k : {Kernel{KernelKind::kWyvill, 0.0}, Kernel{KernelKind::kBlinn, 0.0},
                        Kernel{KernelKind::kInversePower, 4.0}}) {
    const FieldPtr f = make_box_field(c, h, r, options_for(k));
    EXPECT_TRUE(f->is_inside(c));
    Rng rng(5);
    for (int axis = 0; axis < 3; ++axis) {
      for (const double side : {-1.0, 1.0}) {
        const Vec3 normal = side * Vec3::Unit(axis);
        const Vec3 face = c + side * h[axis] * Vec3::Unit(axis);
        expect_surface(*f, face, normal, "box face centre");
        for (int i = 0; i < 10; ++i) {
          Vec3 p = face;
          for (int o = 0; o < 3; ++o) {
            if (o != axis) p[o] += rng.uniform(-1, 1) * (h[o] - r);
          }
          expect_surface(*f, p, normal, "box face");
        }
      }
    }
    // The requested box's corners are rounded off.
    EXPECT_FALSE(f->is_inside(c + h * 0.999));
    EXPECT_TRUE(
        f->is_inside(c + (h - Vec3::Constant(r)) + Vec3::Constant(r / std::sqrt(3.0) * 0.99)));
  }
}

TEST(Primitive, CylinderAndConeTouchCapsAndSide) {
  struct ConeCase {
    Vec3 a, b;
    double ra, rb, rounding;
  };
  for (const auto& cc : {ConeCase{Vec3(0, 0, 0), Vec3(1, 2, 3), 0.9, 0.9, 0.25},
                         ConeCase{Vec3(0.5, 0, -1), Vec3(0, 1, 2), 1.2, 0.4, 0.2},
                         ConeCase{Vec3(0, 0, 0), Vec3(0.2, -0.1, 2), 1.0, 0.0, 0.15},
                         ConeCase{Vec3(0, 0, 0), Vec3(0, 0, 1), 0.0, 2.0, 0.1}}) {
    const bool cylinder = cc.ra == cc.rb;
    const FieldPtr f = cylinder ? make_cylinder_field(cc.a, cc.b, cc.ra, cc.rounding)
                                : make_cone_field(cc.a, cc.ra, cc.b, cc.rb, cc.rounding);
    const double L = (cc.b - cc.a).norm();
    const Vec3 u = (cc.b - cc.a) / L;
    Vec3 e1, e2;
    frame(u, e1, e2);
    Rng rng(8);
    for (int i = 0; i < 40; ++i) {
      const double phi = rng.uniform(0, 2 * kPi);
      const Vec3 radial = std::cos(phi) * e1 + std::sin(phi) * e2;
      // Flat caps, away from the rim: the offset side line meets the offset cap at radius
      // r -+ rounding (slant -+ (rb - ra)) / L (2D geometry of the meridian section).
      const double slant = std::hypot(L, cc.rb - cc.ra);
      const double cap_a = cc.ra - cc.rounding * (slant - (cc.rb - cc.ra)) / L;
      const double cap_b = cc.rb - cc.rounding * (slant + (cc.rb - cc.ra)) / L;
      if (cap_a > 0) expect_surface(*f, cc.a + rng.uniform(0, 0.95 * cap_a) * radial, -u, "cap a");
      if (cap_b > 0) expect_surface(*f, cc.b + rng.uniform(0, 0.95 * cap_b) * radial, u, "cap b");
      // The side, away from both rims: outward normal (L radial - (rb - ra) u) / slant.
      const double t = rng.uniform(0.3, 0.7);
      const Vec3 p = cc.a + t * (cc.b - cc.a) + ((1 - t) * cc.ra + t * cc.rb) * radial;
      expect_surface(*f, p, L * radial - (cc.rb - cc.ra) * u, "side");
    }
    // A zero radius end is a rounded apex: the apex itself is outside.
    if (cc.rb == 0) {
      EXPECT_FALSE(f->is_inside(cc.b));
    }
    if (cc.ra == 0) {
      EXPECT_FALSE(f->is_inside(cc.a));
    }
    EXPECT_TRUE(f->is_inside(cc.a + 0.5 * (cc.b - cc.a)));
  }
}

TEST(Primitive, PlaneSurfaceIsThePlane) {
  const Vec3 q(0.2, 0.1, -0.3), n(1, 2, -0.5);
  for (const auto& k : {Kernel{KernelKind::kWyvill, 0.0}, Kernel{KernelKind::kBlinn, 0.0},
                        Kernel{KernelKind::kInversePower, 0.0}}) {
    const FieldPtr f = make_plane_field(q, n, 0.4, options_for(k));
    Vec3 e1, e2;
    frame(n.normalized(), e1, e2);
    Rng rng(2);
    for (int i = 0; i < 30; ++i) {
      const Vec3 p = q + rng.uniform(-5, 5) * e1 + rng.uniform(-5, 5) * e2;
      expect_surface(*f, p, n, "plane");
      EXPECT_TRUE(f->is_inside(p - 3 * n));
      EXPECT_FALSE(f->is_inside(p + 3 * n));
    }
  }
}

TEST(Primitive, GradientsMatchCentralDifferences) {
  Rng rng(21);
  for (const auto& geo : geometries()) {
    for (const auto& k : test::distance_kernels()) {
      const FieldPtr f = geo.make(options_for(k, 1.3));
      const double R = geo.radius / k.x_at(test::reference_iso(k.kind));
      int checked = 0;
      for (int i = 0; i < 60; ++i) {
        const Vec3 p = random_point(rng, geo.sample);
        // Kinks: the inverse power kernel's constant core, the element's boundary for the
        // non-smooth-at-0 kernels, and the torus axis.
        const double d = geo.distance(p);
        if (d < 1e-3 * R) continue;
        const Vec3 g = f->gradient(p);
        const Vec3 fd = test::central_gradient(*f, p, 1e-6 * R);
        ASSERT_LT((g - fd).norm(), 1e-5 * (1 + g.norm()))
            << geo.name << " " << kernel_name(k.kind) << " at " << p.transpose() << ": "
            << g.transpose() << " vs " << fd.transpose();
        ++checked;
      }
      EXPECT_GT(checked, 30) << geo.name;
    }
  }
}

TEST(Primitive, BoundContainsSampledValues) {
  Rng rng(31);
  for (const auto& geo : geometries()) {
    for (const auto& k :
         {Kernel{KernelKind::kWyvill, 0.0}, Kernel{KernelKind::kBlinn, 0.0},
          Kernel{KernelKind::kMetaball, 0.0}, Kernel{KernelKind::kInversePower, 0.0}}) {
      const FieldPtr f = geo.make(options_for(k, 1.2));
      int straddling = 0;
      for (int b = 0; b < 80; ++b) {
        const Vec3 c = random_point(rng, geo.sample);
        Vec3 half;
        for (int a = 0; a < 3; ++a) half[a] = std::exp(rng.uniform(std::log(0.01), std::log(3.0)));
        const Aabb box(c - half, c + half);
        const Interval iv = f->bound(box);
        ASSERT_LE(iv.lo, iv.hi);
        std::vector<Vec3> pts;
        for (int k2 = 0; k2 < 8; ++k2) pts.push_back(box.corner(static_cast<Aabb::CornerType>(k2)));
        pts.push_back(c);
        for (int i = 0; i < 60; ++i) pts.push_back(random_point(rng, box));
        std::vector<double> v(pts.size());
        f->evaluate(pts, v);
        bool in = false, out = false;
        for (std::size_t i = 0; i < pts.size(); ++i) {
          ASSERT_TRUE(iv.contains(v[i])) << geo.name << " " << kernel_name(k.kind) << " bound ["
                                         << iv.lo << ", " << iv.hi << "] but f = " << v[i];
          in |= v[i] > f->iso();
          out |= v[i] <= f->iso();
        }
        if (in && out) {
          ++straddling;
          EXPECT_TRUE(iv.straddles(f->iso()));
        }
      }
      EXPECT_GT(straddling, 5) << geo.name;
      // Far away: exactly 0 for the compact kernels.
      if (!test::is_infinite_kernel(k.kind)) {
        const Aabb far(geo.sample.max() + Vec3::Constant(5), geo.sample.max() + Vec3::Constant(6));
        if (geo.name != "plane") {
          EXPECT_EQ(f->bound(far).hi, 0.0) << geo.name;
        }
      }
    }
  }
}

TEST(Primitive, BoundsContainEveryInsidePoint) {
  Rng rng(41);
  for (const auto& geo : geometries()) {
    for (const auto& k : test::distance_kernels()) {
      for (const double weight : {1.0, 1.6}) {
        const FieldPtr f = geo.make(options_for(k, weight));
        const Aabb b = f->bounds();
        ASSERT_FALSE(b.isEmpty());
        const Aabb sample = grown(geo.sample, 1.0);
        int inside = 0;
        for (int i = 0; i < 1500; ++i) {
          const Vec3 p = random_point(rng, sample);
          if (f->is_inside(p)) {
            ++inside;
            ASSERT_TRUE(b.contains(p))
                << geo.name << " " << kernel_name(k.kind) << " " << p.transpose()
                << " outside bounds " << b.min().transpose() << " / " << b.max().transpose();
          }
        }
        EXPECT_GT(inside, 5) << geo.name;
      }
    }
  }
  // With weight 1 the surface is exactly `radius` from the element: the rounded box's bounds are
  // the requested box.
  const FieldPtr box = make_box_field(Vec3(1, 2, -1), Vec3(1.5, 0.8, 1.1), 0.3);
  EXPECT_LT((box->bounds().min() - Vec3(-0.5, 1.2, -2.1)).norm(), 1e-8);
  EXPECT_LT((box->bounds().max() - Vec3(2.5, 2.8, 0.1)).norm(), 1e-8);
  // A weight that never reaches the iso value: nothing is inside.
  EXPECT_TRUE(make_box_field(Vec3::Zero(), Vec3::Ones(), 0.5, options_for(Kernel{}, 0.4))
                  ->bounds()
                  .isEmpty());
}

TEST(Primitive, PlaneBoundsAreUnbounded) {
  const double inf = std::numeric_limits<double>::infinity();
  const FieldPtr oblique = make_plane_field(Vec3(0, 0, 1), Vec3(1, 1, 0), 0.5);
  EXPECT_EQ(oblique->bounds().min(), Vec3::Constant(-inf));
  EXPECT_EQ(oblique->bounds().max(), Vec3::Constant(inf));
  EXPECT_NE(oblique->describe().find("unbounded"), std::string::npos);
  const FieldPtr up = make_plane_field(Vec3(0, 0, 1), Vec3(0, 0, 3), 0.5);
  const Aabb b = up->bounds();
  EXPECT_EQ(b.min(), Vec3::Constant(-inf));
  EXPECT_EQ(b.max().x(), inf);
  EXPECT_EQ(b.max().y(), inf);
  EXPECT_NEAR(b.max().z(), 1.0, 1e-8);
  EXPECT_GE(b.max().z(), 1.0);
  const FieldPtr down = make_plane_field(Vec3(0, 0, 1), Vec3(0, 0, -1), 0.5);
  EXPECT_NEAR(down->bounds().min().z(), 1.0, 1e-8);
  EXPECT_EQ(down->bounds().max().z(), inf);
  // bound() of an infinite box stays valid.
  const Interval iv = up->bound(Aabb(Vec3::Constant(-inf), Vec3::Constant(inf)));
  EXPECT_LE(iv.lo, 0.0);
  EXPECT_GE(iv.hi, 1.0);
}

TEST(Primitive, DescribeNamesTheShape) {
  EXPECT_NE(make_circle_field(Vec3::Zero(), Vec3::UnitZ(), 1, 0.2)->describe().find("torus"),
            std::string::npos);
  EXPECT_NE(make_box_field(Vec3::Zero(), Vec3::Ones(), 0.2)->describe().find("box"),
            std::string::npos);
  EXPECT_NE(make_cylinder_field(Vec3::Zero(), Vec3::UnitZ(), 1, 0.2)->describe().find("cylinder"),
            std::string::npos);
  EXPECT_NE(make_cone_field(Vec3::Zero(), 1, Vec3::UnitZ(), 0, 0.2)->describe().find("cone"),
            std::string::npos);
}

TEST(Primitive, BadArgumentsThrow) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 o = Vec3::Zero(), z = Vec3::UnitZ();
  // Torus.
  EXPECT_THROW((void)make_circle_field(Vec3(nan, 0, 0), z, 1, 0.2), InvalidArgument);
  EXPECT_THROW((void)make_circle_field(o, Vec3::Zero(), 1, 0.2), InvalidArgument);
  EXPECT_THROW((void)make_circle_field(o, z, 0, 0.2), InvalidArgument);
  EXPECT_THROW((void)make_circle_field(o, z, 1, -0.2), InvalidArgument);
  EXPECT_THROW((void)make_circle_field(o, z, inf, 0.2), InvalidArgument);
  // Box.
  EXPECT_THROW((void)make_box_field(o, Vec3(1, 0, 1), 0.1), InvalidArgument);
  EXPECT_THROW((void)make_box_field(o, Vec3(1, 1, 1), 0), InvalidArgument);
  EXPECT_THROW((void)make_box_field(o, Vec3(1, 0.5, 1), 0.6), InvalidArgument);
  EXPECT_NO_THROW((void)make_box_field(o, Vec3(1, 0.5, 1), 0.5));
  // Cylinder.
  EXPECT_THROW((void)make_cylinder_field(o, o, 1, 0.1), InvalidArgument);
  EXPECT_THROW((void)make_cylinder_field(o, z, 1, 0.6), InvalidArgument);        // > length / 2
  EXPECT_THROW((void)make_cylinder_field(o, 3 * z, 0.5, 0.6), InvalidArgument);  // > radius
  EXPECT_THROW((void)make_cylinder_field(o, z, nan, 0.1), InvalidArgument);
  EXPECT_NO_THROW((void)make_cylinder_field(o, z, 0.5, 0.5));
  // Cone.
  EXPECT_THROW((void)make_cone_field(o, 0, z, 0, 0.1), InvalidArgument);
  EXPECT_THROW((void)make_cone_field(o, -1, z, 1, 0.1), InvalidArgument);
  EXPECT_THROW((void)make_cone_field(o, 1, o, 1, 0.1), InvalidArgument);
  EXPECT_THROW((void)make_cone_field(o, 1, 10 * z, 0, 0.95), InvalidArgument);  // inradius 0.905
  EXPECT_NO_THROW((void)make_cone_field(o, 1, 10 * z, 0, 0.9));
  EXPECT_THROW((void)make_cone_field(o, 1, z, 0.5, 0), InvalidArgument);
  // Plane.
  EXPECT_THROW((void)make_plane_field(o, Vec3::Zero(), 1), InvalidArgument);
  EXPECT_THROW((void)make_plane_field(o, z, 0), InvalidArgument);
  EXPECT_THROW((void)make_plane_field(Vec3(0, inf, 0), z, 1), InvalidArgument);
  // Options.
  DistancePrimitiveOptions cauchy;
  cauchy.kernel = Kernel{KernelKind::kCauchy, 0.0};
  EXPECT_THROW((void)make_box_field(o, Vec3::Ones(), 0.2, cauchy), InvalidArgument);
  for (const double w : {0.0, -1.0, nan, inf}) {
    EXPECT_THROW((void)make_box_field(o, Vec3::Ones(), 0.2, options_for(Kernel{}, w)),
                 InvalidArgument);
  }
  DistancePrimitiveOptions bad_iso;
  bad_iso.iso = 1.5;  // the Wyvill kernel never reaches it
  EXPECT_THROW((void)make_plane_field(o, z, 1, bad_iso), InvalidArgument);
  bad_iso.iso = -1;
  EXPECT_THROW((void)make_plane_field(o, z, 1, bad_iso), InvalidArgument);
  try {
    (void)make_box_field(o, Vec3(1, 0.5, 1), 0.75);
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("rounding"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0.75"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ramiform
