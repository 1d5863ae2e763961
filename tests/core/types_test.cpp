// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/types.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "ramiform/core/random.h"

namespace ramiform {
namespace {

TEST(Types, IntervalContainsAndStraddles) {
  const Interval i{-1.0, 2.0};
  EXPECT_TRUE(i.contains(-1.0));
  EXPECT_TRUE(i.contains(2.0));
  EXPECT_FALSE(i.contains(2.0000001));
  // lo <= iso < hi: a box whose maximum equals iso has no inside point.
  EXPECT_TRUE(i.straddles(-1.0));
  EXPECT_TRUE(i.straddles(1.0));
  EXPECT_FALSE(i.straddles(2.0));
  EXPECT_FALSE(i.straddles(-1.5));
}

TEST(Types, DefaultAabbIsEmpty) {
  Aabb b;
  EXPECT_TRUE(b.isEmpty());
  b.extend(Vec3(1, 2, 3));
  EXPECT_FALSE(b.isEmpty());
}

TEST(Types, BoxPointDistancesMatchBruteForce) {
  Rng rng(4);
  for (int t = 0; t < 200; ++t) {
    const Vec3 lo(rng.uniform(-2, 0), rng.uniform(-2, 0), rng.uniform(-2, 0));
    const Vec3 hi = lo + Vec3(rng.uniform(0, 3), rng.uniform(0, 3), rng.uniform(0, 3));
    const Aabb box(lo, hi);
    const Vec3 p(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-4, 4));
    // Nearest point: clamp; farthest: a corner.
    const Vec3 nearest = p.cwiseMax(lo).cwiseMin(hi);
    EXPECT_NEAR(squared_distance(box, p), (p - nearest).squaredNorm(), 1e-12);
    double far = 0;
    for (int c = 0; c < 8; ++c) far = std::max(far, (box.corner(static_cast<Aabb::CornerType>(c)) - p).norm());
    EXPECT_NEAR(max_distance(box, p), far, 1e-12);
  }
  const Aabb unit(Vec3(0, 0, 0), Vec3(1, 1, 1));
  EXPECT_EQ(squared_distance(unit, Vec3(0.5, 0.5, 0.5)), 0.0);
  EXPECT_EQ(squared_distance(unit, Vec3(3, 0.5, 0.5)), 4.0);
}

TEST(Types, BoxBoxDistance) {
  const Aabb a(Vec3(0, 0, 0), Vec3(1, 1, 1));
  EXPECT_EQ(squared_distance(a, Aabb(Vec3(0.5, 0.5, 0.5), Vec3(2, 2, 2))), 0.0);
  EXPECT_EQ(squared_distance(a, Aabb(Vec3(3, 0, 0), Vec3(4, 1, 1))), 4.0);
  EXPECT_EQ(squared_distance(a, Aabb(Vec3(2, 3, 0), Vec3(4, 4, 1))), 1.0 + 4.0);
  EXPECT_EQ(squared_distance(Aabb(Vec3(2, 3, 0), Vec3(4, 4, 1)), a), 5.0);
}

TEST(Types, IsFinite) {
  EXPECT_TRUE(is_finite(Vec3(1, 2, 3)));
  EXPECT_FALSE(is_finite(Vec3(1, std::numeric_limits<double>::quiet_NaN(), 3)));
  EXPECT_FALSE(is_finite(Vec3(std::numeric_limits<double>::infinity(), 0, 0)));
}

}  // namespace
}  // namespace ramiform
