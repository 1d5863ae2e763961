// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// tree_from_points on a synthetic scanned tree with a known skeleton (tips, node positions,
// radii), its invariants (a rooted tree, deterministic, bridges), and bad input.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/skeleton/from_points.h"
#include "skeleton/tree_cloud_fixture.h"

namespace ramiform {
namespace {

using test::synthetic_tree;

std::vector<std::size_t> tips_of(const Skeleton& sk) {
  const std::vector<std::uint32_t> deg = degrees(sk);
  std::vector<std::size_t> tips;
  for (std::size_t i = 1; i < sk.nodes.size(); ++i) {
    if (deg[i] == 1) tips.push_back(i);
  }
  return tips;
}

TEST(TreeFromPoints, SyntheticTreeTipsPositionsAndRadii) {
  const test::SyntheticTree tree = synthetic_tree();
  ASSERT_GT(tree.points.size(), 5000u);
  TreeFromPointsReport rep;
  const Skeleton sk = tree_from_points(tree.points, {}, &rep);
  const double w = rep.bin_width;
  EXPECT_GT(w, 0.0);
  EXPECT_EQ(rep.nodes, sk.nodes.size());
  EXPECT_EQ(connected_components(sk).count, 1u);
  EXPECT_EQ(sk.edges.size(), sk.nodes.size() - 1);  // a tree
  // The root is at the base.
  EXPECT_LT(sk.nodes[0].position.z(), w);
  EXPECT_LT(sk.nodes[0].position.head<2>().norm(), 0.15);

  // Every true tip has a skeleton tip within 3 bin widths; at most one spurious tip.
  const std::vector<std::size_t> tips = tips_of(sk);
  EXPECT_EQ(rep.tips, tips.size());
  std::size_t matched = 0;
  for (const Vec3& t : tree.tips) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i : tips) best = std::min(best, (sk.nodes[i].position - t).norm());
    EXPECT_LT(best, 3 * w) << "true tip " << t.transpose();
    matched += best < 3 * w ? 1 : 0;
  }
  EXPECT_EQ(matched, tree.tips.size());
  EXPECT_LE(tips.size(), tree.tips.size() + 1);

  // Every node lies inside the true branches (within the radius plus a tolerance).
  for (std::size_t i = 0; i < sk.nodes.size(); ++i) {
    const auto near = tree.nearest(sk.nodes[i].position);
    EXPECT_LE(near.distance, near.radius + 0.3 * w) << "node " << i;
  }
  // Radii within 30 % on the trunk and the limbs, away from the forks and ends. A fork node
  // stands for the section where its branches are still joined in the neighbour graph (where
  // they diverge at a narrow angle, above the true fork): it carries the parent's radius.
  // Every level-set node (no chain thinning) is checked.
  TreeFromPointsOptions all_nodes;
  all_nodes.straight_tolerance = 0.0;
  const Skeleton sk0 = tree_from_points(tree.points, all_nodes);
  std::vector<int> children(sk0.nodes.size(), 0);
  for (const auto& e : sk0.edges) ++children[e[0]];
  std::size_t checked = 0;
  for (std::size_t i = 0; i < sk0.nodes.size(); ++i) {
    if (children[i] >= 2) continue;
    const Vec3& p = sk0.nodes[i].position;
    const auto near = tree.nearest(p);
    if (near.segment > 2) continue;
    const test::TrueSegment& g = tree.segments[near.segment];
    const double len = (g.b - g.a).norm();
    if (near.t * len < 2 * w || (1 - near.t) * len < 2 * w) continue;
    bool near_fork = false;
    for (const auto& s : tree.segments) near_fork |= (p - s.a).norm() < 2 * w && s.a != g.a;
    if (near_fork) continue;
    EXPECT_NEAR(sk0.nodes[i].radius, near.radius, 0.3 * near.radius)
        << "node " << i << " at " << p.transpose() << " segment " << near.segment << " t " << near.t
        << " w " << w;
    ++checked;
  }
  EXPECT_GE(checked, 20u);
  // Radii never grow from parent to child (edges are (parent, child)).
  for (const auto& e : sk.edges) {
    EXPECT_LT(e[0], e[1]);
    EXPECT_LE(sk.nodes[e[1]].radius, sk.nodes[e[0]].radius * (1 + 1e-12));
  }
}

TEST(TreeFromPoints, PipeModelBoundsTheChildrenAtForks) {
  const test::SyntheticTree tree = synthetic_tree();
  TreeFromPointsOptions o;
  o.straight_tolerance = 0.0;
  const Skeleton sk = tree_from_points(tree.points, o);
  std::vector<double> sum(sk.nodes.size(), 0.0);
  std::vector<int> kids(sk.nodes.size(), 0);
  for (const auto& e : sk.edges) {
    sum[e[0]] += std::pow(sk.nodes[e[1]].radius, o.pipe_exponent);
    ++kids[e[0]];
  }
  int forks = 0;
  for (std::size_t i = 0; i < sk.nodes.size(); ++i) {
    if (kids[i] < 2) continue;
    ++forks;
    EXPECT_LE(sum[i], std::pow(sk.nodes[i].radius, o.pipe_exponent) * (1 + 1e-9)) << i;
  }
  EXPECT_GE(forks, 3);
}

TEST(TreeFromPoints, UpAxisYGivesTheSameTreeRotated) {
  const test::SyntheticTree tree = synthetic_tree();
  std::vector<Vec3> rotated;  // (x, y, z) -> (x, z, -y): z up becomes y up
  for (const Vec3& p : tree.points) rotated.emplace_back(p.x(), p.z(), -p.y());
  TreeFromPointsOptions o;
  const Skeleton a = tree_from_points(tree.points, o);
  o.up_axis = 1;
  const Skeleton b = tree_from_points(rotated, o);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  ASSERT_EQ(a.edges, b.edges);
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    const Vec3& p = a.nodes[i].position;
    EXPECT_NEAR((b.nodes[i].position - Vec3(p.x(), p.z(), -p.y())).norm(), 0.0, 1e-9);
    EXPECT_NEAR(a.nodes[i].radius, b.nodes[i].radius, 1e-9);
  }
}

TEST(TreeFromPoints, DisconnectedPartsAreBridgedToTheNearestPart) {
  // Two vertical sticks of points with a gap of 10 spacings: one bridge.
  std::vector<Vec3> pts;
  for (int i = 0; i < 200; ++i) {
    const double z = i < 100 ? 0.01 * i : 0.01 * i + 0.1;
    const double phi = 0.7 * i;
    pts.emplace_back(0.02 * std::cos(phi), 0.02 * std::sin(phi), z);
  }
  TreeFromPointsOptions o;
  o.bin_width = 0.05;
  TreeFromPointsReport rep;
  const Skeleton sk = tree_from_points(pts, o, &rep);
  EXPECT_EQ(rep.graph_parts, 2u);
  EXPECT_EQ(rep.bridges, 1u);
  EXPECT_EQ(connected_components(sk).count, 1u);
  // A straight stick thins to a single edge (tolerance 0.25 radii).
  EXPECT_EQ(rep.tips, 1u);
  EXPECT_NEAR(sk.nodes.back().position.z(), 2.0, 0.1);
}

TEST(TreeFromPoints, DeterministicAndOrderOfEqualInputs) {
  const test::SyntheticTree tree = synthetic_tree(2500.0, 0.03, 11);
  const Skeleton a = tree_from_points(tree.points);
  const Skeleton b = tree_from_points(tree.points);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  EXPECT_EQ(a.edges, b.edges);
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].position, b.nodes[i].position);
    EXPECT_EQ(a.nodes[i].radius, b.nodes[i].radius);
  }
}

TEST(TreeFromPoints, BadInputIsRefusedWithAClearMessage) {
  std::vector<Vec3> few(9, Vec3::Zero());
  EXPECT_THROW((void)tree_from_points(few), InvalidArgument);
  std::vector<Vec3> pts;
  for (int i = 0; i < 50; ++i) pts.emplace_back(0.01 * i, 0, 0.1 * i);
  pts[17].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    (void)tree_from_points(pts);
    ADD_FAILURE() << "a NaN point was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("point 17"), std::string::npos) << e.what();
  }
  pts[17].y() = 0;
  std::vector<Vec3> same(20, Vec3(1, 2, 3));
  EXPECT_THROW((void)tree_from_points(same), InvalidArgument);
  TreeFromPointsOptions o;
  o.up_axis = 0;
  EXPECT_THROW((void)tree_from_points(pts, o), InvalidArgument);
  o = {};
  o.bin_width = -1;
  EXPECT_THROW((void)tree_from_points(pts, o), InvalidArgument);
  o = {};
  o.pipe_exponent = 0.5;
  EXPECT_THROW((void)tree_from_points(pts, o), InvalidArgument);
  o = {};
  o.neighbours = 0;
  EXPECT_THROW((void)tree_from_points(pts, o), InvalidArgument);
  o = {};
  o.min_radius = std::numeric_limits<double>::infinity();
  EXPECT_THROW((void)tree_from_points(pts, o), InvalidArgument);
  EXPECT_NO_THROW((void)tree_from_points(pts));
}

}  // namespace
}  // namespace ramiform
