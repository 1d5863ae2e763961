// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Checks the shared fixtures themselves, since every stage relies on them.
#include "support/fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "ramiform/skeleton/skeleton.h"

namespace ramiform {
namespace {

TEST(Fixtures, YForkShape) {
  const Skeleton s = test::y_fork(1.5);
  ASSERT_EQ(s.node_count(), 4U);
  ASSERT_EQ(s.edge_count(), 3U);
  EXPECT_NO_THROW(validate(s));
  EXPECT_EQ(s.nodes[0].radius, 1.5);
  EXPECT_LT(s.nodes[1].radius, s.nodes[0].radius);
  EXPECT_LT(s.nodes[2].radius, s.nodes[1].radius);
  EXPECT_EQ(s.nodes[2].radius, s.nodes[3].radius);
  EXPECT_EQ(degrees(s)[1], 3U);
}

TEST(Fixtures, HelixTubesDoNotTouch) {
  const double r = 0.5;
  const Skeleton s = test::helix(36, r);
  ASSERT_EQ(s.edge_count(), 36U);
  ASSERT_EQ(s.node_count(), 37U);
  EXPECT_NO_THROW(validate(s));
  for (const auto& n : s.nodes) {
    EXPECT_NEAR(std::hypot(n.position.x(), n.position.y()), 5 * r, 1e-12);
    EXPECT_EQ(n.radius, r);
  }
  // Nodes 12 apart are one turn above each other.
  EXPECT_NEAR((s.nodes[12].position - s.nodes[0].position).norm(), 8 * r, 1e-12);
  EXPECT_EQ(connected_components(s).count, 1U);
}

TEST(Fixtures, RandomTreeIsValidDeterministicAndGrowsUp) {
  for (std::uint64_t seed : {1ULL, 2ULL, 12345ULL}) {
    const Skeleton t = test::random_tree(seed, 200);
    ASSERT_EQ(t.node_count(), 200U);
    ASSERT_EQ(t.edge_count(), 199U);
    EXPECT_NO_THROW(validate(t));
    EXPECT_EQ(connected_components(t).count, 1U);
    EXPECT_EQ(t.nodes[0].position, Vec3::Zero());
    for (std::size_t e = 0; e < t.edges.size(); ++e) {
      const auto [p, c] = t.edges[e];
      EXPECT_EQ(c, e + 1);
      EXPECT_LT(p, c);
      const Vec3 d = t.nodes[c].position - t.nodes[p].position;
      EXPECT_GT(d.z(), 0.0);                                  // grows upward
      EXPECT_LE(t.nodes[c].radius, t.nodes[p].radius);        // tapers
      EXPECT_GE(d.norm(), 3 * t.nodes[p].radius * (1 - 1e-12));  // several radii long
      EXPECT_LE(d.norm(), 6 * t.nodes[p].radius * (1 + 1e-12));
    }
    const Skeleton again = test::random_tree(seed, 200);
    for (std::size_t i = 0; i < t.nodes.size(); ++i) {
      EXPECT_EQ(again.nodes[i].position, t.nodes[i].position);
      EXPECT_EQ(again.nodes[i].radius, t.nodes[i].radius);
    }
    EXPECT_EQ(again.edges, t.edges);
  }
  EXPECT_NE(test::random_tree(1, 10).nodes[5].position, test::random_tree(2, 10).nodes[5].position);
  EXPECT_EQ(test::random_tree(7, 1).node_count(), 1U);
}

TEST(Fixtures, SingleSegment) {
  const Skeleton s = test::single_segment(Vec3(1, 2, 3), Vec3(4, 5, 6), 0.5, 0.25);
  ASSERT_EQ(s.node_count(), 2U);
  ASSERT_EQ(s.edge_count(), 1U);
  EXPECT_EQ(s.nodes[1].position, Vec3(4, 5, 6));
  EXPECT_EQ(s.nodes[1].radius, 0.25);
  EXPECT_NO_THROW(validate(s));
}

TEST(Fixtures, TempDirIsUniqueAndEmpty) {
  const auto a = test::temp_dir("fixture");
  const auto b = test::temp_dir("fixture");
  EXPECT_NE(a, b);
  EXPECT_TRUE(std::filesystem::is_directory(a));
  EXPECT_TRUE(std::filesystem::is_empty(a));
  std::filesystem::remove_all(a);
  std::filesystem::remove_all(b);
}

TEST(Fixtures, SharedDataDir) {
  EXPECT_EQ(test::shared_data_dir().filename(), "data");
  if (!test::shared_data_available()) GTEST_SKIP() << "no shared data at " << test::shared_data_dir();
  EXPECT_TRUE(std::filesystem::is_directory(test::shared_data_dir() / "trees"));
}

}  // namespace
}  // namespace ramiform
