// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/skeleton/skeleton.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "ramiform/core/errors.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A valid 4-node chain 0-1-2-3 to break in one place per test.
Skeleton chain() {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 1.0}, {Vec3(0, 0, 5), 0.9}, {Vec3(1, 0, 9), 0.8}, {Vec3(2, 1, 12), 0.5}};
  s.edges = {{0, 1}, {1, 2}, {2, 3}};
  return s;
}

// Expects validate() to throw InputError whose message contains every piece of `needles`.
void expect_rejected(const Skeleton& s, const std::vector<std::string>& needles) {
  try {
    validate(s, "tree.swc");
    ADD_FAILURE() << "validate() accepted a bad skeleton (expected " << needles.front() << ")";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.file(), "tree.swc");
    EXPECT_EQ(what.rfind("tree.swc", 0), 0U) << what;
    for (const auto& n : needles) EXPECT_NE(what.find(n), std::string::npos) << what << " lacks " << n;
  }
}

TEST(SkeletonValidate, AcceptsValidSkeletons) {
  EXPECT_NO_THROW(validate(chain()));
  EXPECT_NO_THROW(validate(test::y_fork()));
  EXPECT_NO_THROW(validate(test::helix(40, 0.5)));
  EXPECT_NO_THROW(validate(test::single_segment()));
  // A single isolated node is a valid skeleton.
  Skeleton lone;
  lone.nodes = {{Vec3(1, 2, 3), 0.1}};
  EXPECT_NO_THROW(validate(lone));
}

TEST(SkeletonValidate, RejectsEmpty) {
  Skeleton s;
  EXPECT_THROW(validate(s), InputError);
  expect_rejected(s, {"no nodes"});
}

TEST(SkeletonValidate, RejectsNonFinitePosition) {
  for (double bad : {kNaN, kInf, -kInf}) {
    for (int axis = 0; axis < 3; ++axis) {
      Skeleton s = chain();
      s.nodes[2].position[axis] = bad;
      expect_rejected(s, {"node 2"});
    }
  }
}

TEST(SkeletonValidate, RejectsCoordinatesWhoseSpanOverflows) {
  // Each coordinate is finite, but their differences are not: reported as such, not as the
  // "zero-length edge" that an infinite scale used to make of it.
  Skeleton s = chain();
  s.nodes[0].position = Vec3(0, 0, -1e308);
  s.nodes[1].position = Vec3(0, 0, 1e308);
  expect_rejected(s, {"span more than double precision"});
  // The message names the first node that makes the span overflow, and the range so far.
  s = chain();
  s.nodes[2].position = Vec3(1e308, 0, 9);
  try {
    validate(s, "tree.json");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "tree.json");
    EXPECT_STREQ(e.what(),
                 "tree.json: node 2: with this node the coordinates span more than double "
                 "precision can hold (from 0 to 1e+308)");
  }
  // A span just below the limit (a diagonal of about 1.5e151) is fine.
  s = chain();
  for (auto& n : s.nodes) n.position *= 1e150;
  EXPECT_NO_THROW(validate(s));
}

TEST(SkeletonValidate, RejectsBadRadius) {
  for (double bad : {0.0, -0.0, -1.0, -1e-300, kNaN, kInf, -kInf}) {
    SCOPED_TRACE(bad);
    Skeleton s = chain();
    s.nodes[3].radius = bad;
    expect_rejected(s, {"node 3", "radius"});
  }
  // Tiny positive radii are fine.
  Skeleton s = chain();
  s.nodes[3].radius = 1e-300;
  EXPECT_NO_THROW(validate(s));
}

TEST(SkeletonValidate, RejectsIndexOutOfRange) {
  Skeleton s = chain();
  s.edges[1] = {1, 4};
  expect_rejected(s, {"edge 1", "4"});
  s = chain();
  s.edges[2] = {UINT32_MAX, 0};
  expect_rejected(s, {"edge 2"});
}

TEST(SkeletonValidate, RejectsSelfLoop) {
  Skeleton s = chain();
  s.edges.push_back({2, 2});
  expect_rejected(s, {"edge 3"});
}

TEST(SkeletonValidate, RejectsDuplicateEdgeEitherOrientation) {
  Skeleton s = chain();
  s.edges.push_back({1, 2});
  expect_rejected(s, {"edge 3"});
  s = chain();
  s.edges.push_back({2, 1});
  expect_rejected(s, {"edge 3"});
  s = chain();
  s.edges.insert(s.edges.begin() + 1, {3, 2});  // duplicate of the later {2, 3}
  expect_rejected(s, {"edge 3"});
}

TEST(SkeletonValidate, RejectsZeroLengthEdge) {
  Skeleton s = chain();
  s.nodes[2].position = s.nodes[1].position;
  expect_rejected(s, {"edge 1"});
  // A relative tolerance: coincident up to 1e-13 of the extent is still zero length...
  s = chain();
  s.nodes[2].position = s.nodes[1].position + Vec3(1e-13, 0, 0);
  expect_rejected(s, {"edge 1"});
  // ...but a short edge well above kCoincident times the extent is fine.
  s = chain();
  s.nodes[2].position = s.nodes[1].position + Vec3(1e-6, 0, 0);
  EXPECT_NO_THROW(validate(s));
  // Nodes that coincide without an edge between them are allowed.
  s = chain();
  s.nodes.push_back({s.nodes[0].position, 1.0});
  EXPECT_NO_THROW(validate(s));
}

TEST(SkeletonValidate, ReportsFirstOffendingElement) {
  Skeleton s = chain();
  s.edges.push_back({0, 0});  // edge 3
  s.edges.push_back({0, 9});  // edge 4
  expect_rejected(s, {"edge 3"});
}

TEST(SkeletonComponents, LabelsInOrderOfSmallestNode) {
  // Components: {0, 3, 5}, {1, 2}, {4}, {6, 7}
  Skeleton s;
  for (int i = 0; i < 8; ++i) s.nodes.push_back({Vec3(i, 0, 0), 1.0});
  s.edges = {{5, 3}, {2, 1}, {3, 0}, {7, 6}};
  const auto c = connected_components(s);
  EXPECT_EQ(c.count, 4U);
  EXPECT_EQ(c.label, (std::vector<std::uint32_t>{0, 1, 1, 0, 2, 0, 3, 3}));
  // A tree is one component.
  const auto t = connected_components(test::random_tree(3, 100));
  EXPECT_EQ(t.count, 1U);
  for (auto l : t.label) EXPECT_EQ(l, 0U);
  // No edges: every node alone.
  Skeleton lone;
  for (int i = 0; i < 3; ++i) lone.nodes.push_back({Vec3(i, 0, 0), 1.0});
  const auto l = connected_components(lone);
  EXPECT_EQ(l.count, 3U);
  EXPECT_EQ(l.label, (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(connected_components(Skeleton{}).count, 0U);
}

TEST(SkeletonComponents, MatchBreadthFirstSearch) {
  // Two random trees side by side plus an extra disconnected node, with the edge list shuffled.
  Skeleton a = test::random_tree(5, 30);
  const Skeleton b = test::random_tree(6, 20);
  const auto offset = static_cast<std::uint32_t>(a.nodes.size());
  for (const auto& n : b.nodes) a.nodes.push_back({n.position + Vec3(100, 0, 0), n.radius});
  for (const auto& e : b.edges) a.edges.push_back({e[0] + offset, e[1] + offset});
  a.nodes.push_back({Vec3(-50, 0, 0), 1.0});
  const auto c = connected_components(a);
  EXPECT_EQ(c.count, 3U);
  for (std::uint32_t i = 0; i < 30; ++i) EXPECT_EQ(c.label[i], 0U);
  for (std::uint32_t i = 30; i < 50; ++i) EXPECT_EQ(c.label[i], 1U);
  EXPECT_EQ(c.label[50], 2U);
}

TEST(Skeleton, BoundingBoxOfNodeSpheres) {
  const Skeleton s = test::y_fork(2.0);
  const Aabb b = bounding_box(s);
  // Nodes (0,0,0) r2, (0,0,20) r1.6, (-12,0,36) r1, (12,0,36) r1.
  EXPECT_EQ(b.min(), Vec3(-13, -2, -2));
  EXPECT_EQ(b.max(), Vec3(13, 2, 37));
  EXPECT_TRUE(bounding_box(Skeleton{}).isEmpty());
}

TEST(Skeleton, Degrees) {
  EXPECT_EQ(degrees(test::y_fork()), (std::vector<std::uint32_t>{1, 3, 1, 1}));
  const Skeleton t = test::random_tree(9, 50);
  const auto d = degrees(t);
  std::uint64_t total = 0;
  for (auto x : d) total += x;
  EXPECT_EQ(total, 2 * t.edges.size());
  EXPECT_EQ(t.node_count(), 50U);
  EXPECT_EQ(t.edge_count(), 49U);
}

}  // namespace
}  // namespace ramiform
