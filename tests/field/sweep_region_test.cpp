// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The 2-D distance of the curve-based surfaces (src/field/sweep_region.h), against brute force:
// the distance to every segment, and inside-ness from the winding number (an angle sum, not the
// crossing count the implementation uses).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "field/sweep_region.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

using detail::sweep::Region2;
constexpr double kPi = std::numbers::pi;

double segment_distance(const Vec2& q, const Vec2& a, const Vec2& b) {
  // The nearest of the two end points and the clamped orthogonal projection.
  const Vec2 ab = b - a;
  const double l2 = ab.squaredNorm();
  if (l2 == 0) return (q - a).norm();
  const double u = std::min(1.0, std::max(0.0, (q - a).dot(ab) / l2));
  return std::min({(q - a).norm(), (q - b).norm(), (a + u * ab - q).norm()});
}

double brute_distance(const Vec2& q, const std::vector<Vec2>& v, bool closed) {
  const std::size_t n = v.size();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + (closed ? 0 : 1) < n; ++i) {
    best = std::min(best, segment_distance(q, v[i], v[(i + 1) % n]));
  }
  return best;
}

// The winding number of the closed polygon around q, from the sum of the signed angles its
// edges subtend.
int winding_number(const Vec2& q, const std::vector<Vec2>& v) {
  double total = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i] - q, b = v[(i + 1) % v.size()] - q;
    total += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  return static_cast<int>(std::lround(total / (2 * kPi)));
}

std::vector<Vec2> star(double outer, double inner, int tips) {
  std::vector<Vec2> v;
  for (int i = 0; i < 2 * tips; ++i) {
    const double a = kPi * i / tips + 0.1;
    const double r = i % 2 == 0 ? outer : inner;
    v.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return v;
}

// Checks d at random points against brute force, with inside-ness by the winding number's
// parity (the even-odd rule) for closed polygons.
void expect_matches_brute_force(const std::vector<Vec2>& v, bool closed, std::uint64_t seed) {
  const Region2 region(v, closed);
  Rng rng(seed);
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec2 q(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
    const bool in = closed && winding_number(q, v) % 2 != 0;
    inside += in ? 1 : 0;
    const double expected = in ? 0.0 : brute_distance(q, v, closed);
    EXPECT_NEAR(region.distance(q, nullptr), expected, 1e-12) << q.transpose();
  }
  if (closed) {
    EXPECT_GT(inside, 100);  // the sample reaches the inside
  }
}

TEST(SweepRegion, StarPolygonMatchesBruteForce) {
  expect_matches_brute_force(star(1.0, 0.4, 7), true, 1);
}

TEST(SweepRegion, ManySegmentsAcrossPruningBlocksMatchBruteForce) {
  // 203 vertices: many blocks of 8 segments, the last one partial.
  std::vector<Vec2> v;
  for (int i = 0; i < 203; ++i) {
    const double a = 2 * kPi * i / 203;
    const double r = 0.8 + 0.15 * std::sin(9 * a);
    v.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  expect_matches_brute_force(v, true, 2);
  expect_matches_brute_force(v, false, 3);
}

TEST(SweepRegion, SelfOverlappingPolygonFollowsTheEvenOddRule) {
  // The pentagram {5/2}: its central pentagon has winding number 2, so it is outside.
  std::vector<Vec2> v;
  for (int i = 0; i < 5; ++i) {
    const double a = kPi / 2 + 2 * kPi * (2 * i) / 5;
    v.emplace_back(std::cos(a), std::sin(a));
  }
  ASSERT_EQ(winding_number(Vec2(0, 0), v), 2);
  const Region2 region(v, true);
  EXPECT_GT(region.distance(Vec2(0, 0), nullptr), 0.3);
  expect_matches_brute_force(v, true, 4);
}

TEST(SweepRegion, OpenCurveHasNoInside) {
  // A U shape: the point between its arms is not inside, however enclosed it looks.
  const std::vector<Vec2> u{{-1, 1}, {-1, -1}, {1, -1}, {1, 1}};
  const Region2 region(u, false);
  EXPECT_DOUBLE_EQ(region.distance(Vec2(0, 0), nullptr), 1.0);
  EXPECT_DOUBLE_EQ(region.distance(Vec2(0, 2), nullptr), std::sqrt(2.0));
  const Region2 filled(u, true);
  EXPECT_EQ(filled.distance(Vec2(0, 0), nullptr), 0.0);
  expect_matches_brute_force(u, false, 5);
}

TEST(SweepRegion, GradientPointsAwayFromTheNearestPoint) {
  const std::vector<Vec2> v = star(1.0, 0.5, 5);
  const Region2 region(v, true);
  Rng rng(6);
  for (int i = 0; i < 500; ++i) {
    const Vec2 q(rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
    Vec2 g;
    const double d = region.distance(q, &g);
    if (d == 0) {
      EXPECT_EQ(g, Vec2::Zero());
      continue;
    }
    EXPECT_NEAR(g.norm(), 1.0, 1e-12);
    // Stepping back along the gradient towards the nearest point lowers d at unit rate (d is
    // 1-Lipschitz and the nearest point comes closer by exactly the step).
    const double t = 0.5 * d;
    EXPECT_NEAR(region.distance(q - t * g, nullptr), d - t, 1e-12);
  }
}

TEST(SweepRegion, BoxAndExtent) {
  const std::vector<Vec2> v{{0.5, -2}, {3, 1}, {-1, 0.25}};
  const Region2 region(v, true);
  EXPECT_EQ(region.box().min(), Vec2(-1, -2));
  EXPECT_EQ(region.box().max(), Vec2(3, 1));
  EXPECT_DOUBLE_EQ(region.extent(), std::sqrt(10.0));
  EXPECT_TRUE(region.closed());
  EXPECT_EQ(region.vertices().size(), 3U);
}

}  // namespace
}  // namespace ramiform
