// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/winding.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh/test_meshes.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using test::icosphere;
using test::merged;
using test::tetrahedron;
using test::torus;

std::vector<Vec3> random_points(std::size_t n, double extent, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<Vec3> p(n);
  for (auto& q : p) q = Vec3(u(rng), u(rng), u(rng));
  return p;
}

TEST(WindingNumber, ExactIsOneInsideAndZeroOutsideATetrahedron) {
  const TriMesh m = tetrahedron();
  EXPECT_NEAR(winding_number(m, Vec3(0.1, 0.1, 0.1)), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(m, Vec3(0.2, 0.3, 0.1)), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(m, Vec3(1, 1, 1)), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(m, Vec3(-0.1, 0.1, 0.1)), 0.0, 1e-12);
  EXPECT_NEAR(winding_number(m, Vec3(50, -20, 3)), 0.0, 1e-12);
}

TEST(WindingNumber, ReversedMeshGivesMinusOne) {
  TriMesh m = tetrahedron();
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  EXPECT_NEAR(winding_number(m, Vec3(0.1, 0.1, 0.1)), -1.0, 1e-12);
}

TEST(WindingNumber, OpenHalfOfACubeGivesAFraction) {
  // A single face of the unit cube seen from the cube's centre subtends 1/6 of the sphere.
  TriMesh m;
  m.positions = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  EXPECT_NEAR(winding_number(m, Vec3(0.5, 0.5, 0.5)), 1.0 / 6.0, 1e-12);
}

void expect_fast_matches_exact(const TriMesh& m, const std::vector<Vec3>& points) {
  const WindingNumber fast(m);
  const std::vector<double> w = fast.evaluate(points);
  ASSERT_EQ(w.size(), points.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double exact = winding_number(m, points[i]);
    worst = std::max(worst, std::abs(w[i] - exact));
    EXPECT_NEAR(w[i], exact, 0.01) << "point " << points[i].transpose();
    EXPECT_EQ(fast(points[i]), w[i]);
  }
  ::testing::Test::RecordProperty("worst_error", std::to_string(worst));
}

TEST(WindingNumber, FastMatchesExactOnASphere) {
  const TriMesh m = icosphere(4, 1.0, Vec3(0.1, -0.2, 0.3));  // 5120 triangles
  expect_fast_matches_exact(m, random_points(400, 2.0, 1));
}

TEST(WindingNumber, FastMatchesExactOnATorusAndTwoComponents) {
  const TriMesh m = merged(torus(1.5, 0.5, 96, 32), icosphere(3, 0.7, Vec3(0, 0, 1.6)));
  expect_fast_matches_exact(m, random_points(400, 2.5, 2));
}

TEST(WindingNumber, FastMatchesExactNearTheSurface) {
  const TriMesh m = icosphere(4, 1.0);
  std::vector<Vec3> points = random_points(300, 1.0, 3);
  for (auto& p : points) {
    if (p.norm() == 0.0) continue;
    p = p.normalized() * (p.norm() > 0.5 ? 1.02 : 0.98);  // just outside / just inside
  }
  expect_fast_matches_exact(m, points);
}

TEST(WindingNumber, PointsInsideClassifiesASphereAndATorus) {
  const double R = 1.5;
  const double r = 0.5;
  const TriMesh m = merged(icosphere(4, 1.0, Vec3(0, 0, 3)), torus(R, r, 128, 48));
  const std::vector<Vec3> points = random_points(4000, 3.0, 4);
  const std::vector<char> inside = points_inside(m, points);
  ASSERT_EQ(inside.size(), points.size());
  int checked = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    // Signed distances to the true shapes; skip points within the meshes' chord error.
    const double ds = (p - Vec3(0, 0, 3)).norm() - 1.0;
    const double dt = std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) - r;
    if (std::abs(ds) < 0.01 || std::abs(dt) < 0.01) continue;
    ++checked;
    EXPECT_EQ(inside[i] != 0, ds < 0 || dt < 0) << "point " << p.transpose();
  }
  EXPECT_GT(checked, 3500);
}

TEST(WindingNumber, PointsInsideDoesNotDependOnThreads) {
  const TriMesh m = torus(1.5, 0.5, 64, 24);
  const std::vector<Vec3> points = random_points(2000, 2.5, 5);
  Context one(1);
  Context two(2);
  const WindingNumber wn(m);
  EXPECT_EQ(wn.evaluate(points, &one), wn.evaluate(points, &two));
  EXPECT_EQ(points_inside(m, points, &one), points_inside(m, points, &two));
}

TEST(WindingNumber, HigherBetaIsCloserToExact) {
  const TriMesh m = torus(1.5, 0.5, 64, 24);
  const std::vector<Vec3> points = random_points(200, 2.5, 6);
  WindingOptions precise;
  precise.beta = 6.0;
  const WindingNumber wn(m, precise);
  for (const Vec3& p : points) EXPECT_NEAR(wn(p), winding_number(m, p), 1e-4);
}

TEST(WindingNumber, EmptyMeshAndBadOptions) {
  const WindingNumber empty{TriMesh{}};
  EXPECT_EQ(empty(Vec3(0, 0, 0)), 0.0);
  WindingOptions bad;
  bad.beta = 1.0;
  EXPECT_THROW(WindingNumber(tetrahedron(), bad), InvalidArgument);
  bad = {};
  bad.leaf_size = 0;
  EXPECT_THROW(WindingNumber(tetrahedron(), bad), InvalidArgument);
  TriMesh broken = tetrahedron();
  broken.triangles[0][0] = 7;
  EXPECT_THROW((void)winding_number(broken, Vec3::Zero()), InvalidArgument);
  EXPECT_THROW(WindingNumber{broken}, InvalidArgument);
}

}  // namespace
}  // namespace ramiform
