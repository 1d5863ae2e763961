// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors

// The internal box BVH (src/field/bvh.h) against brute force: box queries return exactly the
// items whose boxes meet the query, and nearest() the item of least distance, ties to the
// lower id.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "field/bvh.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

std::vector<Aabb> random_boxes(Rng& rng, std::size_t n) {
  std::vector<Aabb> boxes;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
    const Vec3 h(rng.uniform(0, 1.5), rng.uniform(0, 1.5), rng.uniform(0, 1.5));
    boxes.emplace_back(c - h, c + h);
  }
  // Touching and repeated boxes: ties in the queries and in nearest().
  boxes.emplace_back(Vec3(0, 0, 0), Vec3(1, 1, 1));
  boxes.emplace_back(Vec3(1, 0, 0), Vec3(2, 1, 1));
  boxes.emplace_back(Vec3(0, 0, 0), Vec3(1, 1, 1));
  return boxes;
}

TEST(BoxBvh, QueriesReturnExactlyTheMeetingBoxes) {
  Rng rng(5);
  const std::vector<Aabb> boxes = random_boxes(rng, 700);
  const detail::BoxBvh bvh(boxes);
  std::vector<std::uint32_t> got;
  for (int q = 0; q < 300; ++q) {
    const Vec3 c(rng.uniform(-12, 12), rng.uniform(-12, 12), rng.uniform(-12, 12));
    const double h = q < 10 ? 0.0 : rng.uniform(0, 4);  // points too
    const Aabb query(c - Vec3::Constant(h), c + Vec3::Constant(h));
    got.clear();
    bvh.query(query, got);
    std::vector<std::uint32_t> want;
    for (std::uint32_t i = 0; i < boxes.size(); ++i) {
      if (boxes[i].intersects(query)) want.push_back(i);
    }
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want) << "query " << q;
  }
  got.clear();
  bvh.query(Aabb(Vec3(1, 0.5, 0.5), Vec3(1, 0.5, 0.5)), got);  // on the shared face
  for (const std::uint32_t i : {700U, 701U, 702U}) {
    EXPECT_EQ(std::count(got.begin(), got.end(), i), 1) << i;
  }
  got.clear();
  bvh.query(Aabb(), got);  // empty
  EXPECT_TRUE(got.empty());
}

TEST(BoxBvh, NearestIsTheLeastDistanceTiesToTheLowerId) {
  Rng rng(9);
  const std::vector<Aabb> boxes = random_boxes(rng, 500);
  const detail::BoxBvh bvh(boxes);
  for (int q = 0; q < 400; ++q) {
    const Vec3 p = q == 0 ? Vec3(0.5, 0.5, 0.5)
                          : Vec3(rng.uniform(-14, 14), rng.uniform(-14, 14), rng.uniform(-14, 14));
    // The distance to each box's centre, floored by the box distance as nearest() requires.
    const auto distance2 = [&](std::uint32_t i) {
      return std::max((boxes[i].center() - p).squaredNorm(), squared_distance(boxes[i], p));
    };
    std::uint32_t want = 0;
    for (std::uint32_t i = 1; i < boxes.size(); ++i) {
      if (distance2(i) < distance2(want)) want = i;
    }
    double d2 = -1;
    EXPECT_EQ(bvh.nearest(p, distance2, &d2), want) << "point " << q;
    EXPECT_EQ(d2, distance2(want));
  }
  // The box distance itself: zero in every box holding the point, many ties.
  for (const Vec3& p : {Vec3(0.5, 0.5, 0.5), Vec3(1, 0.5, 0.5), Vec3(3, -2, 1)}) {
    const auto box_d2 = [&](std::uint32_t i) { return squared_distance(boxes[i], p); };
    std::uint32_t want = 0;
    for (std::uint32_t i = 1; i < boxes.size(); ++i) {
      if (box_d2(i) < box_d2(want)) want = i;
    }
    EXPECT_EQ(bvh.nearest(p, box_d2), want);
  }
}

}  // namespace
}  // namespace ramiform
