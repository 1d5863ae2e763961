// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/rbf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using test::random_point;
using test::random_unit;

// n points spread evenly over the unit sphere (Fibonacci lattice).
std::vector<Vec3> fibonacci_sphere(int n) {
  std::vector<Vec3> pts;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n;
    const double r = std::sqrt(1 - z * z);
    pts.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return pts;
}

FieldPtr unit_sphere(double iso = 0.0) {
  const std::vector<Vec3> pts = fibonacci_sphere(100);
  const auto constraints = rbf_constraints_from_normals(pts, pts, 0.1, iso);
  RbfOptions o;
  o.iso = iso;
  return make_rbf_field(constraints, o);
}

TEST(Rbf, InterpolatesEveryConstraint) {
  Rng rng(1);
  std::vector<RbfConstraint> cs;
  for (int i = 0; i < 60; ++i) {
    cs.push_back({random_point(rng, Aabb(Vec3(-2, -1, 0), Vec3(3, 2, 1))), rng.uniform(-1, 1)});
  }
  RbfOptions o;
  o.iso = 0.1;
  const FieldPtr f = make_rbf_field(cs, o);
  EXPECT_EQ(f->iso(), 0.1);
  for (const auto& c : cs) EXPECT_NEAR(f->value(c.position), c.value, 1e-8);

  const std::vector<Vec3> pts = fibonacci_sphere(100);
  const auto sphere = rbf_constraints_from_normals(pts, pts, 0.1);
  const FieldPtr g = make_rbf_field(sphere);
  for (const auto& c : sphere) EXPECT_NEAR(g->value(c.position), c.value, 1e-8);
}

TEST(Rbf, ReproducesLinearFunctions) {
  // The polynomial part makes the interpolant exact for linear data (all w_j = 0).
  Rng rng(2);
  const Vec3 a(0.3, -1.2, 0.7);
  const double b = 0.25;
  std::vector<RbfConstraint> cs;
  const Aabb region(Vec3(-1, -1, -1), Vec3(2, 1, 1.5));
  for (int i = 0; i < 40; ++i) {
    const Vec3 p = random_point(rng, region);
    cs.push_back({p, a.dot(p) + b});
  }
  const FieldPtr f = make_rbf_field(cs);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 p = random_point(rng, region);
    const double lin = a.dot(p) + b;
    if (lin > f->iso()) continue;  // the clip only lowers values above iso
    ++checked;
    ASSERT_NEAR(f->value(p), lin, 1e-9);
    ASSERT_LT((f->gradient(p) - a).norm(), 1e-8);
  }
  EXPECT_GT(checked, 50);
}

TEST(Rbf, SphereFromPointsAndNormals) {
  for (const double iso : {0.0, 0.3}) {
    const FieldPtr f = unit_sphere(iso);
    EXPECT_GT(f->value(Vec3::Zero()), iso);
    Rng rng(3);
    for (int ray = 0; ray < 14; ++ray) {
      const Vec3 d = random_unit(rng);
      EXPECT_LT(f->value(1.3 * d), iso);
      // Bisection for the surface between r = 0.5 (inside) and 1.3 (outside).
      double lo = 0.5, hi = 1.3;
      ASSERT_GT(f->value(lo * d), iso);
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (f->value(mid * d) > iso ? lo : hi) = mid;
      }
      EXPECT_NEAR(lo, 1.0, 0.02) << d.transpose();
    }
  }
}

TEST(Rbf, GradientMatchesCentralDifferences) {
  const FieldPtr f = unit_sphere();
  Rng rng(4);
  int checked = 0;
  for (int i = 0; i < 400 && checked < 60; ++i) {
    const Vec3 p = random_point(rng, Aabb(Vec3::Constant(-1.2), Vec3::Constant(1.2)));
    if (p.norm() > 1.2 || std::abs(f->value(p) - f->iso()) > 0.5) continue;  // near the surface
    const Vec3 g = f->gradient(p);
    const Vec3 fd = test::central_gradient(*f, p, 1e-6);
    ASSERT_LT((g - fd).norm(), 1e-5 * (1 + g.norm())) << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 30);
}

TEST(Rbf, ClippedOutsideItsBox) {
  const FieldPtr f = unit_sphere();
  const Aabb b = f->bounds();
  ASSERT_FALSE(b.isEmpty());
  // The clip box: the constraints' box padded by 0.25 of its diagonal.
  EXPECT_GT(b.max().x(), 1.5);
  EXPECT_LT(b.max().x(), 2.0);
  Rng rng(5);
  int inside = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p = random_point(rng, Aabb(Vec3::Constant(-6), Vec3::Constant(6)));
    if (f->is_inside(p)) {
      ++inside;
      ASSERT_TRUE(b.contains(p)) << p.transpose();
    }
    if (!b.contains(p)) {
      ASSERT_LT(f->value(p), f->iso());
    }
  }
  EXPECT_GT(inside, 5);
}

TEST(Rbf, BoundIsConservative) {
  const FieldPtr f = unit_sphere();
  Rng rng(6);
  int straddling = 0;
  for (int k = 0; k < 120; ++k) {
    const Vec3 c = random_point(rng, Aabb(Vec3::Constant(-2.5), Vec3::Constant(2.5)));
    Vec3 half;
    for (int a = 0; a < 3; ++a) half[a] = std::exp(rng.uniform(std::log(0.01), std::log(2.0)));
    const Aabb box(c - half, c + half);
    const Interval iv = f->bound(box);
    ASSERT_LE(iv.lo, iv.hi);
    std::vector<Vec3> pts;
    for (int i = 0; i < 8; ++i) pts.push_back(box.corner(static_cast<Aabb::CornerType>(i)));
    for (int i = 0; i < 60; ++i) pts.push_back(random_point(rng, box));
    std::vector<double> v(pts.size());
    f->evaluate(pts, v);
    bool in = false, out = false;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      ASSERT_TRUE(iv.contains(v[i])) << "[" << iv.lo << ", " << iv.hi << "] f = " << v[i];
      in |= v[i] > f->iso();
      out |= v[i] <= f->iso();
    }
    if (in && out) {
      ++straddling;
      EXPECT_TRUE(iv.straddles(f->iso()));
    }
  }
  EXPECT_GT(straddling, 5);
  const double inf = std::numeric_limits<double>::infinity();
  const Interval all = f->bound(Aabb(Vec3::Constant(-inf), Vec3::Constant(inf)));
  EXPECT_TRUE(all.contains(f->value(Vec3::Zero())));
}

TEST(Rbf, ConstraintsFromNormals) {
  const std::vector<Vec3> pts = {Vec3(1, 0, 0), Vec3(0, 2, 0)};
  const std::vector<Vec3> normals = {Vec3(3, 0, 0), Vec3(0, 0.5, 0)};
  const auto cs = rbf_constraints_from_normals(pts, normals, 0.2, 0.5);
  ASSERT_EQ(cs.size(), 4u);
  EXPECT_EQ(cs[0].position, pts[0]);
  EXPECT_EQ(cs[0].value, 0.5);
  EXPECT_TRUE((cs[1].position - Vec3(0.8, 0, 0)).norm() < 1e-15);
  EXPECT_EQ(cs[1].value, 1.5);
  EXPECT_TRUE((cs[3].position - Vec3(0, 1.8, 0)).norm() < 1e-15);
}

TEST(Rbf, BadInputsThrow) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<RbfConstraint> three = {
      {Vec3(0, 0, 0), 1}, {Vec3(1, 0, 0), 0}, {Vec3(0, 1, 0), 0}};
  EXPECT_THROW((void)make_rbf_field(three), InvalidArgument);
  std::vector<RbfConstraint> ok = three;
  ok.push_back({Vec3(0, 0, 1), 0});
  EXPECT_NO_THROW((void)make_rbf_field(ok));
  auto dup = ok;
  dup.push_back({Vec3(1, 0, 0), 0.5});
  try {
    (void)make_rbf_field(dup);
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("1 and 4"), std::string::npos) << e.what();
  }
  std::vector<RbfConstraint> flat;
  for (int i = 0; i < 10; ++i) flat.push_back({Vec3(i % 3, i / 3, 0), 0.1 * i});
  EXPECT_THROW((void)make_rbf_field(flat), InvalidArgument);
  auto bad = ok;
  bad[2].position.y() = nan;
  EXPECT_THROW((void)make_rbf_field(bad), InvalidArgument);
  bad = ok;
  bad[1].value = nan;
  EXPECT_THROW((void)make_rbf_field(bad), InvalidArgument);
  RbfOptions o;
  o.margin = 0;
  EXPECT_THROW((void)make_rbf_field(ok, o), InvalidArgument);
  o = RbfOptions{};
  o.iso = nan;
  EXPECT_THROW((void)make_rbf_field(ok, o), InvalidArgument);
  const std::vector<Vec3> pts = {Vec3(1, 0, 0), Vec3(0, 1, 0)};
  EXPECT_THROW((void)rbf_constraints_from_normals(pts, std::vector<Vec3>{Vec3(1, 0, 0)}, 0.1),
               InvalidArgument);
  EXPECT_THROW(
      (void)rbf_constraints_from_normals(pts, std::vector<Vec3>{Vec3(1, 0, 0), Vec3::Zero()}, 0.1),
      InvalidArgument);
  EXPECT_THROW((void)rbf_constraints_from_normals(pts, pts, 0), InvalidArgument);
  EXPECT_THROW((void)rbf_constraints_from_normals(pts, pts, nan), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
