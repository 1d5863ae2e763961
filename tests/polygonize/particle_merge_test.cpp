// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Joining branches whose tubes merge without an edge between them (polygonize/particle_merge.h):
// the joined skeleton computed by hand for a twig whose tip lies inside a thicker branch, the
// repair's forced and forbidden joins, a tip beside a thicker branch joined at the neck of the
// field between them, and no join for a child that leaves its parent's tube at their fork.

#include "polygonize/particle_merge.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "ramiform/field/equipotential.h"

namespace ramiform {
namespace {

std::vector<double> mean_radii(const Skeleton& s) {
  std::vector<double> r;
  for (const auto& e : s.edges) r.push_back(0.5 * (s.nodes[e[0]].radius + s.nodes[e[1]].radius));
  return r;
}

// A trunk (radius 0.5 to 0.4) with a twig (0.1) from node 1 that goes out to (2, 0, 4) and
// comes back into the trunk, its tip 0.2 from the trunk's axis.
TEST(JoinMergingBranches, TwigTipInsideAThickerBranchIsJoinedToItsAxis) {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, -3), 0.5},
             {Vec3(0, 0, 2), 0.5},
             {Vec3(0, 0, 10), 0.4},
             {Vec3(2, 0, 4), 0.1},
             {Vec3(0.2, 0, 7), 0.1}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}};
  const std::vector<double> radius = mean_radii(s);  // 0.5, 0.45, 0.3, 0.1
  const std::vector<double> spacing = {0.25, 0.2, 0.05, 0.05};
  const detail::MergedSkeleton m = detail::join_merging_branches(s, radius, spacing, {});
  EXPECT_EQ(m.joins, 1U);
  // The trunk's edge 1 is split at (0, 0, 7), its axis point nearest the tip (t = 5/8), with
  // the radius interpolated there; the tip becomes that node.
  ASSERT_EQ(m.skeleton.nodes.size(), 5U);
  for (int v = 0; v < 4; ++v) {
    EXPECT_EQ(m.skeleton.nodes[v].position, s.nodes[v].position) << v;
  }
  EXPECT_EQ(m.skeleton.nodes[4].position, Vec3(0, 0, 7));
  EXPECT_DOUBLE_EQ(m.skeleton.nodes[4].radius, 0.5 - 0.625 * 0.1);
  const std::vector<std::array<std::uint32_t, 2>> edges = {{0, 1}, {1, 4}, {4, 2}, {1, 3}, {3, 4}};
  EXPECT_EQ(m.skeleton.edges, edges);
  // The trunk's pieces keep its R and spacing; the twig's piece into the join starts from the
  // trunk, R the mean of the two.
  EXPECT_EQ(m.edge_radius, (std::vector<double>{0.5, 0.45, 0.45, 0.3, 0.5 * (0.1 + 0.45)}));
  EXPECT_EQ(m.edge_spacing, (std::vector<double>{0.25, 0.2, 0.2, 0.05, 0.05}));
  EXPECT_TRUE(m.open_end.empty());
}

// The particle mesher's repair: a tip outside the trunk's tube (1.0 from its axis, R 0.45) is
// not joined as found, is joined like the tip inside it when marked kJoinNearby (within 3 R),
// and a tip inside it is left alone when marked kJoinNever.
TEST(JoinMergingBranches, RepairJoinsANodeNearbyOrLeavesItInPlace) {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, -3), 0.5},
             {Vec3(0, 0, 2), 0.5},
             {Vec3(0, 0, 10), 0.4},
             {Vec3(2, 0, 4), 0.1},
             {Vec3(1.0, 0, 7), 0.1}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}};
  const std::vector<double> radius = mean_radii(s);
  const std::vector<double> spacing = {0.25, 0.2, 0.05, 0.05};
  const detail::MergedSkeleton as_found = detail::join_merging_branches(s, radius, spacing, {});
  EXPECT_EQ(as_found.joins, 0U);
  EXPECT_EQ(as_found.skeleton.edges, s.edges);
  EXPECT_TRUE(as_found.moved.empty());

  std::vector<std::uint8_t> force(s.nodes.size(), detail::kJoinAsFound);
  force[4] = detail::kJoinNearby;
  const detail::MergedSkeleton nearby =
      detail::join_merging_branches(s, radius, spacing, {}, force);
  EXPECT_EQ(nearby.joins, 1U);
  ASSERT_EQ(nearby.skeleton.nodes.size(), 5U);
  EXPECT_EQ(nearby.skeleton.nodes[4].position, Vec3(0, 0, 7));  // t = 5/8 on the trunk's edge 1
  const std::vector<std::array<std::uint32_t, 2>> edges = {{0, 1}, {1, 4}, {4, 2}, {1, 3}, {3, 4}};
  EXPECT_EQ(nearby.skeleton.edges, edges);
  EXPECT_EQ(nearby.moved, (std::vector<std::uint8_t>{0, 0, 0, 0, 1}));

  Skeleton inside = s;
  inside.nodes[4].position = Vec3(0.2, 0, 7);
  force[4] = detail::kJoinNever;
  const detail::MergedSkeleton never =
      detail::join_merging_branches(inside, radius, spacing, {}, force);
  EXPECT_EQ(never.joins, 0U);
  EXPECT_EQ(never.skeleton.edges, inside.edges);
  EXPECT_EQ(never.skeleton.nodes[4].position, Vec3(0.2, 0, 7));
}

// With the surface's field: a twig (radius 0.25) whose tip lies beside the trunk (R 0.45), 0.5
// from its axis, outside its tube but within R_g + R_own = 0.7 of it, where the equipotential
// surfaces of the two merge broadly (the field stays above twice lambda all the way between
// the axes: 2.7 lambda at least). The tip is joined to the trunk's edge at its nearest axis
// point (0, 0, 7), and the joined node goes to the neck: of the 8 points evenly inside the
// segment from the tip to that axis point, the one of least field value. A thinner twig (0.1)
// at the same place, its tube still overlapping the trunk's, is not joined: the field between
// them falls to 1.5 lambda. Nor is the tip without the field. (Meshed, the twig of 0.25 folds
// 26 triangles unjoined, 1 joined.)
TEST(JoinMergingBranches, TipBesideAThickerBranchWhereTheSurfacesMergeIsJoinedAtTheNeck) {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, -3), 0.5},
             {Vec3(0, 0, 2), 0.5},
             {Vec3(0, 0, 10), 0.4},
             {Vec3(2, 0, 4), 0.25},
             {Vec3(0.5, 0, 7), 0.25}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}};
  const std::vector<double> radius = mean_radii(s);  // 0.5, 0.45, 0.375, 0.25
  const std::vector<double> spacing = {0.25, 0.2, 0.12, 0.12};
  const Equipotential eq = make_equipotential(s);
  const Field& field = *eq.field;
  Context ctx(2);
  const detail::MergedSkeleton m =
      detail::join_merging_branches(s, radius, spacing, {}, {}, &field, &ctx);
  EXPECT_EQ(m.joins, 1U);
  ASSERT_EQ(m.skeleton.nodes.size(), 5U);
  for (int v = 0; v < 4; ++v) {
    EXPECT_EQ(m.skeleton.nodes[v].position, s.nodes[v].position) << v;
  }
  const std::vector<std::array<std::uint32_t, 2>> edges = {{0, 1}, {1, 4}, {4, 2}, {1, 3}, {3, 4}};
  EXPECT_EQ(m.skeleton.edges, edges);
  EXPECT_EQ(m.moved, (std::vector<std::uint8_t>{0, 0, 0, 0, 1}));
  // The neck, computed here from the field's values on the segment.
  const Vec3 tip = s.nodes[4].position;
  const Vec3 axis(0, 0, 7);
  std::vector<Vec3> points;
  for (int k = 1; k <= 8; ++k) points.push_back(tip + (k / 9.0) * (axis - tip));
  std::vector<double> f(points.size());
  field.evaluate(points, f);
  const auto least = std::min_element(f.begin(), f.end());
  EXPECT_GT(*least, 2 * field.iso());
  EXPECT_EQ(m.skeleton.nodes[4].position, points[static_cast<std::size_t>(least - f.begin())]);
  EXPECT_GT(m.skeleton.nodes[4].position.x(), 0.0);  // off the trunk's axis, toward the tip
  EXPECT_LT(m.skeleton.nodes[4].position.x(), 0.5);

  const detail::MergedSkeleton without = detail::join_merging_branches(s, radius, spacing, {});
  EXPECT_EQ(without.joins, 0U);
  EXPECT_EQ(without.skeleton.edges, s.edges);

  Skeleton thin = s;
  thin.nodes[3].radius = thin.nodes[4].radius = 0.1;
  const std::vector<double> thin_radius = mean_radii(thin);
  const Equipotential thin_eq = make_equipotential(thin);
  const detail::MergedSkeleton apart =
      detail::join_merging_branches(thin, thin_radius, spacing, {}, {}, thin_eq.field.get(), &ctx);
  EXPECT_EQ(apart.joins, 0U);
  EXPECT_EQ(apart.skeleton.edges, thin.edges);
}

// A child from the trunk's node that runs inside the trunk's tube before it leaves it: reached
// from the trunk through nodes inside its tube, so it is the trunk's own child and not joined.
TEST(JoinMergingBranches, ChildInsideItsParentsTubeAtTheForkKeepsItsEdges) {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, -3), 1.0},
             {Vec3(0, 0, 0), 1.0},
             {Vec3(0, 0, 10), 1.0},
             {Vec3(0.5, 0, 6), 0.3},
             {Vec3(3, 0, 9), 0.3}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}};
  const std::vector<double> radius = mean_radii(s);
  const std::vector<double> spacing(4, 0.15);
  const std::vector<std::uint8_t> open = {1, 0, 0, 0, 0};
  const detail::MergedSkeleton m = detail::join_merging_branches(s, radius, spacing, open);
  EXPECT_EQ(m.joins, 0U);
  ASSERT_EQ(m.skeleton.nodes.size(), s.nodes.size());
  EXPECT_EQ(m.skeleton.edges, s.edges);
  EXPECT_EQ(m.edge_radius, radius);
  EXPECT_EQ(m.open_end, open);
}

}  // namespace
}  // namespace ramiform
