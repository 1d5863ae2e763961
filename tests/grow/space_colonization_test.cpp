// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/grow/space_colonization.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/field/skeleton_field.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

// Expects `stmt` to throw InvalidArgument whose message contains `text`.
#define EXPECT_THAT_THROWS_WITH(stmt, text)                                       \
  do {                                                                            \
    try {                                                                         \
      (void)(stmt);                                                               \
      ADD_FAILURE() << #stmt " did not throw";                                    \
    } catch (const InvalidArgument& e) {                                          \
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what(); \
    }                                                                             \
  } while (0)

// Uniform points in a ball (rejection sampling from the cube).
std::vector<Vec3> ball_points(std::uint64_t seed, std::size_t n, const Vec3& center, double radius) {
  Rng rng(seed);
  std::vector<Vec3> out;
  while (out.size() < n) {
    const Vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (p.squaredNorm() <= 1) out.push_back(center + radius * p);
  }
  return out;
}

// A forest with one tree per root: validate() passes, edges = nodes - roots, one component
// per root with the roots in distinct components (so no cycles), every edge of length `step`.
void expect_forest(const Skeleton& s, std::size_t roots, double step) {
  ASSERT_NO_THROW(validate(s));
  ASSERT_EQ(s.edge_count() + roots, s.node_count());
  const auto comp = connected_components(s);
  ASSERT_EQ(comp.count, roots);
  for (std::uint32_t r = 0; r < roots; ++r) EXPECT_EQ(comp.label[r], r);
  for (const auto& e : s.edges) {
    EXPECT_LT(e[0], e[1]);  // parents come before children
    EXPECT_NEAR((s.nodes[e[0]].position - s.nodes[e[1]].position).norm(), step, 1e-12 * step);
  }
}

bool same_skeleton(const Skeleton& a, const Skeleton& b) {
  if (a.node_count() != b.node_count() || a.edges != b.edges) return false;
  for (std::size_t i = 0; i < a.node_count(); ++i)
    if (std::memcmp(a.nodes[i].position.data(), b.nodes[i].position.data(), 3 * sizeof(double)) != 0 ||
        a.nodes[i].radius != b.nodes[i].radius)
      return false;
  return true;
}

TEST(Colonization, OnePointStraightAheadIsReached) {
  const std::vector<Vec3> pts{Vec3(0, 0, 5)};
  ColonizationOptions o;
  o.step = 1;
  o.influence = 10;
  o.kill = 1;
  const auto r = grow_space_colonization(pts, o);
  EXPECT_EQ(r.status, ColonizationStatus::kCompleted);
  EXPECT_FALSE(r.stalled);
  EXPECT_TRUE(r.stall_reason.empty());
  EXPECT_EQ(r.points_reached, 1u);
  EXPECT_EQ(r.points_total, 1u);
  // Nodes at z = 0..4; the one at z = 4 is within d_k = 1 of the point.
  ASSERT_EQ(r.skeleton.node_count(), 5u);
  EXPECT_EQ(r.iterations, 4u);
  for (std::size_t k = 0; k < 5; ++k)
    EXPECT_EQ(r.skeleton.nodes[k].position, Vec3(0, 0, static_cast<double>(k)));
  expect_forest(r.skeleton, 1, 1.0);
}

TEST(Colonization, SymmetricPullsUseClosestPointFallback) {
  // The unit vectors from the root cancel exactly; the fallback grows toward the closest point
  // (tie: the smaller index, point 0 at +x), then the other point pulls the root to -x.
  const std::vector<Vec3> pts{Vec3(3, 0, 0), Vec3(-3, 0, 0)};
  ColonizationOptions o;
  o.step = 1;
  o.influence = 5;
  o.kill = 1;
  const auto r = grow_space_colonization(pts, o);
  EXPECT_EQ(r.status, ColonizationStatus::kCompleted) << r.stall_reason;
  ASSERT_GE(r.skeleton.node_count(), 2u);
  EXPECT_EQ(r.skeleton.nodes[1].position, Vec3(1, 0, 0));
  for (const auto& n : r.skeleton.nodes) EXPECT_TRUE(is_finite(n.position));
  expect_forest(r.skeleton, 1, 1.0);
  // Both points reached: nodes exist near both.
  EXPECT_EQ(r.points_reached, 2u);
}

TEST(Colonization, DuplicateChildIsNotCreatedAndGrowthStalls) {
  // Both points are exactly as far from the child at (0,0,1) as from the root, so they stay
  // with the root, which would re-grow the same child: blocked, then stalled (finite).
  const std::vector<Vec3> pts{Vec3(3, 0, 0.5), Vec3(-3, 0, 0.5)};
  ColonizationOptions o;
  o.step = 1;
  o.influence = 5;
  o.kill = 0.5;
  const auto r = grow_space_colonization(pts, o);
  EXPECT_EQ(r.status, ColonizationStatus::kStalled);
  EXPECT_TRUE(r.stalled);
  EXPECT_NE(r.stall_reason.find("duplicate"), std::string::npos) << r.stall_reason;
  ASSERT_EQ(r.skeleton.node_count(), 2u);
  EXPECT_EQ(r.skeleton.nodes[1].position, Vec3(0, 0, 1));
  EXPECT_EQ(r.iterations, 2u);
}

TEST(Colonization, PointsOutOfReachStallWithReason) {
  // Crown off to the side: the trunk moves away from it and stops.
  {
    const std::vector<Vec3> pts{Vec3(100, 0, 0), Vec3(101, 0, 0)};
    ColonizationOptions o;
    const auto r = grow_space_colonization(pts, o);
    EXPECT_TRUE(r.stalled);
    EXPECT_EQ(r.status, ColonizationStatus::kStalled);
    EXPECT_NE(r.stall_reason.find("trunk"), std::string::npos) << r.stall_reason;
    EXPECT_LE(r.iterations, 2u);
  }
  // d_i below the point spacing: the root reaches its neighbourhood, nothing else.
  {
    std::vector<Vec3> pts;
    for (int i = -3; i <= 3; ++i)
      for (int j = -3; j <= 3; ++j) pts.emplace_back(5.0 * i, 5.0 * j, 0.5);
    ColonizationOptions o;
    o.step = 0.5;
    o.influence = 2;
    o.kill = 0.5;
    const auto r = grow_space_colonization(pts, o);
    EXPECT_TRUE(r.stalled);
    EXPECT_NE(r.stall_reason.find("influence distance"), std::string::npos) << r.stall_reason;
    EXPECT_LT(r.iterations, 100u);
    EXPECT_EQ(r.points_reached, 1u);
  }
}

TEST(Colonization, TrunkGrowsStraightUntilInfluenced) {
  const auto pts = ball_points(3, 500, Vec3(0, 0, 30), 8);
  ColonizationOptions o;
  o.step = 1;
  o.influence = 4;
  o.kill = 1.5;
  o.tropism = Vec3(0.3, 0, 0);  // the trunk ignores tropism
  SpaceColonization sc(pts, o);
  while (!sc.done()) sc.step();
  const Skeleton s = sc.skeleton();
  // The crown's lowest point is at z >= 22; the trunk is straight up to z = 22 - 4 at least.
  for (int k = 0; k <= 17; ++k) EXPECT_EQ(s.nodes[static_cast<std::size_t>(k)].position, Vec3(0, 0, k));
  expect_forest(s, 1, 1.0);
}

TEST(Colonization, RandomCrownIsAForestAndKillDistanceHolds) {
  const auto pts = ball_points(7, 3000, Vec3(0, 0, 12), 10);
  ColonizationOptions o;
  o.step = 0.6;
  o.influence = 4;
  o.kill = 1.2;
  o.tip_radius = 0.01;
  SpaceColonization sc(pts, o);
  std::size_t nodes = sc.node_count();
  while (!sc.done()) {
    const auto rep = sc.step();
    EXPECT_EQ(sc.node_count(), nodes + rep.nodes_added);
    nodes = sc.node_count();
  }
  const Skeleton s = sc.skeleton();
  expect_forest(s, 1, o.step);
  EXPECT_GT(s.node_count(), 200u);
  // No live point within d_k of any node; every dead point within d_k of some node.
  const auto alive = sc.alive();
  std::size_t live = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    double best = 1e300;
    for (const auto& n : s.nodes) best = std::min(best, (n.position - pts[p]).norm());
    if (alive[p]) {
      ++live;
      EXPECT_GT(best, o.kill);
    } else {
      EXPECT_LE(best, o.kill);
    }
  }
  EXPECT_EQ(live, sc.points_alive());
  if (sc.status() != ColonizationStatus::kCompleted) {
    EXPECT_FALSE(sc.stall_reason().empty());
  }
  // Most of the crown is reached.
  EXPECT_LT(live, pts.size() / 20);
}

TEST(Colonization, SeveralRoots) {
  const auto pts = ball_points(11, 1500, Vec3(0, 0, 10), 8);
  ColonizationOptions o;
  o.step = 0.8;
  o.influence = 5;
  o.kill = 1.6;
  o.roots = {Vec3(-3, 0, 0), Vec3(3, 0, 0)};
  const auto r = grow_space_colonization(pts, o);
  EXPECT_EQ(r.skeleton.nodes[0].position, o.roots[0]);
  EXPECT_EQ(r.skeleton.nodes[1].position, o.roots[1]);
  expect_forest(r.skeleton, 2, o.step);
  EXPECT_GT(r.skeleton.node_count(), 50u);
}

TEST(Colonization, NodesNeverEnterTheObstacle) {
  SkeletonFieldOptions fo;
  fo.surface = SurfaceKind::kDistance;
  fo.kernel = Kernel{KernelKind::kWyvill, 0.0};
  const Vec3 c(0, 0, 10);
  const double radius = 5;
  const FieldPtr sphere = make_point_field(c, radius, fo);
  ASSERT_TRUE(sphere->is_inside(c));
  ASSERT_FALSE(sphere->is_inside(c + Vec3(0, 0, 1.01 * radius)));
  // Points in a shell just outside the sphere, including around its top.
  Rng rng(5);
  std::vector<Vec3> pts;
  while (pts.size() < 1500) {
    const Vec3 d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (d.squaredNorm() > 1 || d.squaredNorm() < 1e-6) continue;
    pts.push_back(c + d.normalized() * rng.uniform(radius * 1.1, radius * 1.5));
  }
  ColonizationOptions o;
  o.step = 0.4;
  o.influence = 2;
  o.kill = 0.8;
  o.obstacle = sphere.get();
  const auto r = grow_space_colonization(pts, o);
  expect_forest(r.skeleton, 1, o.step);
  EXPECT_GT(r.skeleton.node_count(), 100u);
  for (const auto& n : r.skeleton.nodes) EXPECT_FALSE(sphere->is_inside(n.position));
  // Growth wraps around: some nodes are above the sphere's equator.
  double top = 0;
  for (const auto& n : r.skeleton.nodes) top = std::max(top, n.position.z());
  EXPECT_GT(top, c.z());
  // A root inside the obstacle is rejected.
  o.roots = {c};
  EXPECT_THROW((void)grow_space_colonization(pts, o), InvalidArgument);
}

TEST(Colonization, DeterministicAcrossRunsAndThreadCounts) {
  const auto pts = ball_points(21, 4000, Vec3(0, 0, 12), 9);
  ColonizationOptions o;
  o.step = 0.5;
  o.influence = 3;
  o.kill = 1;
  o.tropism = Vec3(0, 0, -0.2);
  o.roots = {Vec3(0, 0, 0), Vec3(2, 1, 0)};
  Context one(1), two(2);
  const auto a = grow_space_colonization(pts, o, &one);
  const auto b = grow_space_colonization(pts, o, &two);
  const auto c = grow_space_colonization(pts, o, nullptr);
  const auto d = grow_space_colonization(pts, o, &two);
  EXPECT_TRUE(same_skeleton(a.skeleton, b.skeleton));
  EXPECT_TRUE(same_skeleton(a.skeleton, c.skeleton));
  EXPECT_TRUE(same_skeleton(b.skeleton, d.skeleton));
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.points_reached, b.points_reached);
}

TEST(Colonization, MaxIterationsStops) {
  const auto pts = ball_points(2, 800, Vec3(0, 0, 10), 8);
  ColonizationOptions o;
  o.max_iterations = 3;
  o.influence = 4;
  o.kill = 1;
  const auto r = grow_space_colonization(pts, o);
  EXPECT_EQ(r.status, ColonizationStatus::kMaxIterations);
  EXPECT_TRUE(r.stalled);
  EXPECT_EQ(r.iterations, 3u);
  EXPECT_NE(r.stall_reason.find("max_iterations"), std::string::npos);
  expect_forest(r.skeleton, 1, o.step);
}

TEST(Colonization, StepApiMatchesOneCall) {
  const auto pts = ball_points(9, 1000, Vec3(0, 0, 8), 6);
  ColonizationOptions o;
  o.influence = 3;
  o.kill = 1.5;
  SpaceColonization sc(pts, o);
  std::size_t steps = 0;
  while (!sc.done()) {
    const auto rep = sc.step();
    ++steps;
    EXPECT_EQ(rep.iteration, steps);
    EXPECT_EQ(rep.points_alive, sc.points_alive());
  }
  const auto again = sc.step();  // a finished growth does nothing
  EXPECT_EQ(again.nodes_added, 0u);
  EXPECT_TRUE(same_skeleton(sc.skeleton(), grow_space_colonization(pts, o).skeleton));
  EXPECT_EQ(sc.parents()[0], UINT32_MAX);
}

TEST(Colonization, EmptyPointsAndBadInput) {
  ColonizationOptions o;
  const auto r = grow_space_colonization({}, o);
  EXPECT_TRUE(r.stalled);
  EXPECT_EQ(r.skeleton.node_count(), 1u);
  std::vector<Vec3> bad{Vec3(0, 0, std::nan(""))};
  EXPECT_THROW((void)grow_space_colonization(bad, o), InvalidArgument);
}

// Points within the kill distance of the root are reached before the first iteration: growth
// completes (not stalled, no reason) with the root alone; no_branch_reason explains it.
TEST(Colonization, PointsWithinKillOfTheRootCompleteWithoutABranch) {
  ColonizationOptions o;  // kill 2, root at the origin
  for (const std::vector<Vec3>& pts :
       {std::vector<Vec3>{Vec3(0, 0, 0), Vec3(1, 1, 1)}, std::vector<Vec3>{Vec3::Zero()}}) {
    const auto r = grow_space_colonization(pts, o);
    EXPECT_EQ(r.status, ColonizationStatus::kCompleted);
    EXPECT_FALSE(r.stalled);
    EXPECT_TRUE(r.stall_reason.empty());
    EXPECT_EQ(r.iterations, 0u);
    EXPECT_EQ(r.points_reached, pts.size());
    EXPECT_EQ(r.skeleton.node_count(), 1u);
    EXPECT_EQ(r.skeleton.edge_count(), 0u);
  }
}

// no_branch_reason explains the case with numbers; a stalled growth gives its stall reason, and
// a growth with an edge needs no explanation.
TEST(Colonization, NoBranchReasonExplainsPointsWithinKillOfTheRoot) {
  ColonizationOptions o;  // kill 2, root at the origin
  const std::vector<Vec3> two{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  EXPECT_EQ(no_branch_reason(grow_space_colonization(two, o), two, o),
            "all 2 attraction points lie within the kill distance d_k = 2 of the root (0,0,0) (the "
            "farthest at distance 1.73205), so they were reached before any branch grew");
  const std::vector<Vec3> one{Vec3(0.5, 0, 0)};
  o.roots = {Vec3(0, 0, 0.25)};
  EXPECT_EQ(no_branch_reason(grow_space_colonization(one, o), one, o),
            "the one attraction point lies within the kill distance d_k = 2 of the root "
            "(0,0,0.25) (at distance 0.559017), so it was reached before any branch grew");
  o.roots = {Vec3(0, 0, 0), Vec3(10, 0, 0)};
  const std::vector<Vec3> near_each{Vec3(1, 0, 0), Vec3(10, 0, 1.5)};
  EXPECT_EQ(no_branch_reason(grow_space_colonization(near_each, o), near_each, o),
            "all 2 attraction points lie within the kill distance d_k = 2 of a root (the farthest "
            "at distance 1.5), so they were reached before any branch grew");

  ColonizationOptions d;
  const auto empty = grow_space_colonization({}, d);
  EXPECT_EQ(no_branch_reason(empty, {}, d), empty.stall_reason);
  EXPECT_FALSE(empty.stall_reason.empty());
  const std::vector<Vec3> ahead{Vec3(0, 0, 5)};
  const auto grown = grow_space_colonization(ahead, d);
  ASSERT_GT(grown.skeleton.edge_count(), 0u);
  EXPECT_EQ(no_branch_reason(grown, ahead, d), "");
}

TEST(Colonization, OverflowingExtentIsRefusedNotHung) {
  // Points at +-1e308: max - min is inf, the grid's cell count was NaN and the loop enlarging
  // its cells never ended. Run in a child process with an alarm so that a hang fails the test.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto refused = [](bool step_api) {
    alarm(20);
    const std::vector<Vec3> pts{Vec3(0, 0, 5), Vec3(0, 0, 1e308), Vec3(1, 1, -1e308)};
    try {
      if (step_api) {
        SpaceColonization sc(pts, ColonizationOptions{});
      } else {
        (void)grow_space_colonization(pts, ColonizationOptions{});
      }
    } catch (const InvalidArgument& e) {
      std::fprintf(stderr, "%s\n", e.what());
      std::_Exit(0);
    }
    std::_Exit(1);
  };
  for (const bool step_api : {false, true}) {
    EXPECT_EXIT(refused(step_api), ::testing::ExitedWithCode(0),
                "coordinates span more than double precision can hold \\(with point 1 ");
  }
}

TEST(Colonization, PointsAreCheckedBeforeTheGrid) {
  const ColonizationOptions o;
  const std::vector<Vec3> nan{Vec3(0, 0, 1), Vec3(0, 0, 2), Vec3(0, std::nan(""), 3)};
  EXPECT_THAT_THROWS_WITH(grow_space_colonization(nan, o), "attraction point 2 is not finite");
  // Each coordinate fits, the diagonal's length does not (the rule of skeleton validate()).
  const std::vector<Vec3> diag{Vec3(1e200, 0, 0), Vec3(0, 1e200, 0)};
  EXPECT_THAT_THROWS_WITH(grow_space_colonization(diag, o), "span more than double precision");
  // The points fit together but the root is too far from them: the trunk's distance to their
  // box was inf, so it never stopped and grew max_iterations nodes toward nothing.
  const std::vector<Vec3> far{Vec3(1e200, 0, 0), Vec3(1e200, 0, 1)};
  EXPECT_THAT_THROWS_WITH(grow_space_colonization(far, o), "root 0 is too far");
}

TEST(Colonization, CancelledContextStopsConstruction) {
  // Checked from the first round of the grid sizing on (and by the association that follows).
  Context ctx;
  ctx.cancel();
  EXPECT_THROW(SpaceColonization(ball_points(1, 50, Vec3(0, 0, 5), 2), ColonizationOptions{}, &ctx),
               Cancelled);
}

TEST(Colonization, HugeFiniteExtentsGrowNormally) {
  // A span of 1e150 with d_i = 10: the grid must be sized in a few rounds (and stay >= d_i).
  const std::vector<Vec3> pts{Vec3(0, 0, 5), Vec3(1e150, 0, 0), Vec3(0, -1e150, 1e150)};
  ColonizationOptions o;
  o.kill = 1;
  const auto r = grow_space_colonization(pts, o);
  EXPECT_EQ(r.points_reached, 1u);
  EXPECT_EQ(r.status, ColonizationStatus::kStalled);
  expect_forest(r.skeleton, 1, o.step);
  // A tiny d_i makes the cell count overflow (5e249 per axis): one big cell, still correct.
  o.step = 1e-100;
  o.kill = 1e-100;
  o.influence = 2e-100;
  o.max_iterations = 3;
  const auto t = grow_space_colonization(pts, o);
  EXPECT_EQ(t.points_reached, 0u);
  EXPECT_EQ(t.skeleton.node_count(), 4u) << t.stall_reason;  // the trunk's 3 steps
}

TEST(Colonization, NodesPastTheDoubleRangeAreNotCreated) {
  // A trunk one step from the end of the double range: its next node would be at +inf.
  ColonizationOptions o;
  o.roots = {Vec3(1.7e308, 0, 0)};
  o.direction = Vec3::UnitX();
  o.step = 1e308;
  o.influence = 10;
  o.kill = 1;
  const std::vector<Vec3> pts{Vec3(1.7e308, 0, 1e150)};
  const auto r = grow_space_colonization(pts, o);
  EXPECT_EQ(r.status, ColonizationStatus::kStalled);
  EXPECT_EQ(r.skeleton.node_count(), 1u);
  for (const auto& n : r.skeleton.nodes) EXPECT_TRUE(is_finite(n.position));
  EXPECT_NE(r.stall_reason.find("would not be finite"), std::string::npos) << r.stall_reason;
}

TEST(Colonization, OptionsValidate) {
  auto bad = [](auto edit) {
    ColonizationOptions o;
    edit(o);
    EXPECT_THROW(o.validate(), InvalidArgument);
  };
  bad([](ColonizationOptions& o) { o.step = 0; });
  bad([](ColonizationOptions& o) { o.kill = -1; });
  bad([](ColonizationOptions& o) { o.influence = o.kill; });
  bad([](ColonizationOptions& o) { o.roots.clear(); });
  bad([](ColonizationOptions& o) { o.roots = {Vec3::Zero(), Vec3::Zero()}; });
  bad([](ColonizationOptions& o) { o.direction = Vec3::Zero(); });
  bad([](ColonizationOptions& o) { o.max_iterations = -1; });
  bad([](ColonizationOptions& o) { o.tip_radius = 0; });
  bad([](ColonizationOptions& o) { o.pipe_exponent = 1.9; });
  bad([](ColonizationOptions& o) { o.pipe_exponent = 3.1; });
  EXPECT_NO_THROW(ColonizationOptions{}.validate());
}

// Pipe-model equation at every node with children; tips have the tip radius.
void expect_pipe(const Skeleton& s, std::uint32_t root, double tip, double n) {
  const auto deg = degrees(s);
  std::vector<std::vector<std::uint32_t>> adj(s.node_count());
  for (const auto& e : s.edges) {
    adj[e[0]].push_back(e[1]);
    adj[e[1]].push_back(e[0]);
  }
  // Orient from the root.
  std::vector<std::uint32_t> parent(s.node_count(), UINT32_MAX), order{root};
  std::vector<bool> seen(s.node_count(), false);
  seen[root] = true;
  for (std::size_t h = 0; h < order.size(); ++h)
    for (auto w : adj[order[h]])
      if (!seen[w]) {
        seen[w] = true;
        parent[w] = order[h];
        order.push_back(w);
      }
  std::vector<double> sum(s.node_count(), 0);
  std::vector<int> kids(s.node_count(), 0);
  for (std::size_t v = 0; v < s.node_count(); ++v)
    if (parent[v] != UINT32_MAX) {
      sum[parent[v]] += std::pow(s.nodes[v].radius, n);
      ++kids[parent[v]];
    }
  for (std::size_t v = 0; v < s.node_count(); ++v) {
    if (kids[v] == 0) {
      EXPECT_EQ(s.nodes[v].radius, tip);
    } else {
      const double rn = std::pow(s.nodes[v].radius, n);
      EXPECT_NEAR(rn, sum[v], 1e-12 * sum[v]) << "node " << v;
    }
  }
  (void)deg;
}

TEST(PipeModel, EquationHoldsAtEveryFork) {
  for (double n : {2.0, 2.5, 3.0}) {
    Skeleton s = test::random_tree(4, 300);
    assign_pipe_radii(s, std::vector<std::uint32_t>{0}, 0.05, n);
    expect_pipe(s, 0, 0.05, n);
  }
  Skeleton y = test::y_fork();
  assign_pipe_radii(y, std::vector<std::uint32_t>{0}, 0.5, 2.0);
  EXPECT_EQ(y.nodes[2].radius, 0.5);
  EXPECT_NEAR(y.nodes[1].radius, std::sqrt(0.5), 1e-15);
  EXPECT_EQ(y.nodes[0].radius, y.nodes[1].radius);
  // Rooted at a tip instead, the orientation changes and so do the radii.
  assign_pipe_radii(y, std::vector<std::uint32_t>{2}, 0.5, 2.0);
  expect_pipe(y, 2, 0.5, 2.0);
}

TEST(PipeModel, GrownTreesFollowIt) {
  const auto pts = ball_points(13, 1500, Vec3(0, 0, 10), 7);
  ColonizationOptions o;
  o.influence = 4;
  o.kill = 1.5;
  o.tip_radius = 0.03;
  o.pipe_exponent = 2.2;
  const auto r = grow_space_colonization(pts, o);
  expect_pipe(r.skeleton, 0, 0.03, 2.2);
  EXPECT_GT(r.skeleton.nodes[0].radius, 0.15);  // many tips behind the root
}

TEST(PipeModel, RejectsBadInput) {
  Skeleton y = test::y_fork();
  const std::vector<std::uint32_t> root{0};
  EXPECT_THROW(assign_pipe_radii(y, root, 0.1, 1.99), InvalidArgument);
  EXPECT_THROW(assign_pipe_radii(y, root, 0.1, 3.01), InvalidArgument);
  EXPECT_THROW(assign_pipe_radii(y, root, 0.0, 2.5), InvalidArgument);
  EXPECT_THROW(assign_pipe_radii(y, std::vector<std::uint32_t>{7}, 0.1, 2.5), InvalidArgument);
  EXPECT_THROW(assign_pipe_radii(y, std::vector<std::uint32_t>{0, 2}, 0.1, 2.5), InvalidArgument);
  EXPECT_THROW(assign_pipe_radii(y, std::vector<std::uint32_t>{}, 0.1, 2.5), InvalidArgument);
  Skeleton cyc = y;
  cyc.edges.push_back({2, 3});
  EXPECT_THROW(assign_pipe_radii(cyc, root, 0.1, 2.5), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
