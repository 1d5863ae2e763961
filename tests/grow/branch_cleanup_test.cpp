// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/grow/branch_cleanup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/grow/space_colonization.h"

namespace ramiform {
namespace {

// Expects `stmt` to throw InvalidArgument whose message contains `text`.
#define EXPECT_THROWS_WITH(stmt, text)                                            \
  do {                                                                            \
    try {                                                                         \
      (void)(stmt);                                                               \
      ADD_FAILURE() << #stmt " did not throw";                                    \
    } catch (const InvalidArgument& e) {                                          \
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what(); \
    }                                                                             \
  } while (0)

// The demo's cleanup (examples/demo.rf).
constexpr int kDemoSmooth = 8;
constexpr double kDemoPrune = 2.0;

// Uniform points in an axis-aligned ellipsoid (rejection sampling from the cube).
std::vector<Vec3> crown_points(std::uint64_t seed, std::size_t n, const Vec3& center,
                               const Vec3& radii) {
  Rng rng(seed);
  std::vector<Vec3> out;
  while (out.size() < n) {
    const Vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (p.squaredNorm() <= 1) out.push_back(center + radii.cwiseProduct(p));
  }
  return out;
}

struct TreeCase {
  std::uint64_t seed;
  std::size_t points;
  Vec3 center, radii;
  double step, influence, kill;
};

// Different crowns, densities and growth parameters (none of them the demo's).
std::vector<TreeCase> tree_cases() {
  return {
      {11, 2000, {0, 0, 5.5}, {3.0, 3.0, 2.2}, 0.22, 1.4, 0.45},
      {12, 1500, {0.5, 0, 6}, {2.0, 3.5, 2.5}, 0.25, 1.2, 0.5},
      {13, 3000, {0, 0, 4}, {2.5, 2.5, 2.5}, 0.15, 1.0, 0.3},
      {14, 1200, {0, 1, 7}, {4.0, 2.0, 1.5}, 0.3, 2.0, 0.6},
  };
}

ColonizationOptions grow_options(const TreeCase& t) {
  ColonizationOptions o;
  o.step = t.step;
  o.influence = t.influence;
  o.kill = t.kill;
  o.tip_radius = 0.02;
  o.pipe_exponent = 2.5;
  return o;
}

ColonizationResult grow_case(const TreeCase& t, int smooth, double prune, Context* ctx = nullptr) {
  ColonizationOptions o = grow_options(t);
  o.smooth_iterations = smooth;
  o.prune_steps = prune;
  return grow_space_colonization(crown_points(t.seed, t.points, t.center, t.radii), o, ctx);
}

std::vector<std::uint32_t> degree_of(const Skeleton& s) { return degrees(s); }

// r_parent^n = sum r_child^n at every node with children, relative 1e-9; children by BFS from 0.
void expect_pipe_model(const Skeleton& s, double exponent) {
  const std::size_t n = s.node_count();
  std::vector<std::vector<std::uint32_t>> adj(n);
  for (const auto& e : s.edges) {
    adj[e[0]].push_back(e[1]);
    adj[e[1]].push_back(e[0]);
  }
  std::vector<std::uint32_t> parent(n, UINT32_MAX), queue = {0};
  std::vector<std::uint8_t> seen(n, 0);
  seen[0] = 1;
  for (std::size_t h = 0; h < queue.size(); ++h)
    for (const std::uint32_t w : adj[queue[h]])
      if (!seen[w]) {
        seen[w] = 1;
        parent[w] = queue[h];
        queue.push_back(w);
      }
  ASSERT_EQ(queue.size(), n);
  std::vector<double> sum(n, 0.0);
  std::vector<int> kids(n, 0);
  for (std::uint32_t v = 0; v < n; ++v)
    if (parent[v] != UINT32_MAX) {
      sum[parent[v]] += std::pow(s.nodes[v].radius, exponent);
      ++kids[parent[v]];
    }
  for (std::uint32_t v = 0; v < n; ++v) {
    if (kids[v] == 0) continue;
    const double lhs = std::pow(s.nodes[v].radius, exponent);
    EXPECT_NEAR(lhs, sum[v], 1e-9 * lhs) << "node " << v;
  }
}

// Every node lies inside the tree's convolution surface (the field the demo meshes).
void expect_nodes_inside(const Skeleton& s) {
  const FieldPtr f = make_skeleton_field(s, SkeletonFieldOptions{});
  std::vector<Vec3> where;
  for (const SkeletonNode& node : s.nodes) where.push_back(node.position);
  std::vector<double> values(where.size());
  f->evaluate(where, values);
  for (std::size_t i = 0; i < values.size(); ++i) EXPECT_GT(values[i], f->iso()) << "node " << i;
}

TEST(BranchCleanup, GrownTreesMeetTheTurnAndStubFigures) {
  for (const TreeCase& t : tree_cases()) {
    SCOPED_TRACE("seed " + std::to_string(t.seed));
    const ColonizationResult raw = grow_case(t, 0, 0);
    const ColonizationResult r = grow_case(t, kDemoSmooth, kDemoPrune);
    // The raw trees have the problem (kinks and stubs) ...
    EXPECT_GT(raw.cleanup.after.turn_p90_deg, 30.0);
    EXPECT_GT(raw.cleanup.after.short_share(), 0.2);
    EXPECT_EQ(raw.cleanup.nodes_moved + raw.cleanup.nodes_removed, 0u);
    // ... the cleaned ones do not.
    const BranchShape& after = r.cleanup.after;
    EXPECT_LE(after.turn_p90_deg, 30.0);
    EXPECT_LE(after.turn_max_deg, 90.0);
    EXPECT_LE(after.short_share(), 0.10);
    // The report's "before" is the raw tree, "after" the returned one.
    EXPECT_EQ(r.cleanup.before.chain_nodes, raw.cleanup.after.chain_nodes);
    EXPECT_EQ(r.cleanup.before.tip_branches, raw.cleanup.after.tip_branches);
    EXPECT_DOUBLE_EQ(r.cleanup.before.turn_p90_deg, raw.cleanup.after.turn_p90_deg);
    const BranchShape measured =
        measure_branches(r.skeleton, std::vector<std::uint32_t>{0}, kShortTipSteps * t.step);
    EXPECT_EQ(measured.short_tip_branches, after.short_tip_branches);
    EXPECT_DOUBLE_EQ(measured.turn_max_deg, after.turn_max_deg);
    // Counts: removed nodes and pruned stubs (each pruned stub takes one tip).
    EXPECT_EQ(r.skeleton.node_count() + r.cleanup.nodes_removed, raw.skeleton.node_count());
    EXPECT_EQ(after.tip_branches + r.cleanup.stubs_pruned, r.cleanup.before.tip_branches);
    EXPECT_GT(r.cleanup.stubs_pruned, 0u);
    EXPECT_GT(r.cleanup.nodes_moved, 0u);
    // Still one valid tree with exact pipe-model radii, its nodes inside its surface.
    ASSERT_NO_THROW(validate(r.skeleton));
    EXPECT_EQ(r.skeleton.edge_count() + 1, r.skeleton.node_count());
    for (const auto& e : r.skeleton.edges) EXPECT_LT(e[0], e[1]);
    expect_pipe_model(r.skeleton, 2.5);
    expect_nodes_inside(r.skeleton);
  }
}

TEST(BranchCleanup, SmoothingKeepsForksRootAndTipsAndTheTopology) {
  const TreeCase t = tree_cases()[1];
  const ColonizationResult raw = grow_case(t, 0, 0);
  Skeleton s = raw.skeleton;
  BranchCleanupOptions o;
  o.smooth_iterations = 8;
  o.max_turn_deg = 180;  // no kink removal: smoothing only
  const BranchCleanupReport rep = clean_branches(s, std::vector<std::uint32_t>{0}, o);
  ASSERT_EQ(rep.nodes_removed, 0u);
  EXPECT_EQ(rep.rounds, 1u);
  ASSERT_EQ(s.node_count(), raw.skeleton.node_count());
  EXPECT_EQ(s.edges, raw.skeleton.edges);
  const auto deg = degree_of(s);
  std::size_t moved = 0;
  for (std::size_t v = 0; v < s.node_count(); ++v) {
    EXPECT_EQ(s.nodes[v].radius, raw.skeleton.nodes[v].radius);
    const bool fixed = v == 0 || deg[v] != 2;
    if (fixed) {
      EXPECT_EQ(s.nodes[v].position, raw.skeleton.nodes[v].position) << v;
    }
    if (s.nodes[v].position != raw.skeleton.nodes[v].position) ++moved;
  }
  EXPECT_EQ(moved, rep.nodes_moved);
  EXPECT_GT(moved, s.node_count() / 2);
  expect_pipe_model(s, 2.5);
  EXPECT_LT(rep.after.turn_p90_deg, rep.before.turn_p90_deg);
}

// x <- x/2 + (parent + child)/4 is a descent step of the sum of squared edge lengths: more
// passes never increase it, and many passes straighten every chain between its fixed ends.
TEST(BranchCleanup, SmoothingConvergesMonotonically) {
  const Skeleton raw = grow_case(tree_cases()[0], 0, 0).skeleton;
  auto energy = [](const Skeleton& s) {
    double e = 0;
    for (const auto& [a, b] : s.edges)
      e += (s.nodes[a].position - s.nodes[b].position).squaredNorm();
    return e;
  };
  double previous = energy(raw);
  for (const int passes : {1, 2, 4, 8, 16, 64}) {
    Skeleton s = raw;
    BranchCleanupOptions o;
    o.smooth_iterations = passes;
    o.max_turn_deg = 180;
    clean_branches(s, std::vector<std::uint32_t>{0}, o);
    const double e = energy(s);
    EXPECT_LE(e, previous * (1 + 1e-12)) << passes;
    previous = e;
  }
  Skeleton s = raw;
  BranchCleanupOptions o;
  o.smooth_iterations = BranchCleanupOptions::kMaxSmoothIterations;
  o.max_turn_deg = 180;
  const BranchCleanupReport rep = clean_branches(s, std::vector<std::uint32_t>{0}, o);
  EXPECT_LT(rep.after.turn_p90_deg, 5.0);
}

// A zig-zag chain between two fixed ends: one pass removes the alternating part exactly, so a
// pure zig-zag about a straight line becomes straight.
TEST(BranchCleanup, OnePassRemovesAZigZag) {
  Skeleton s;
  const int n = 9;
  for (int i = 0; i < n; ++i) s.nodes.push_back({Vec3(i, 0, 0), 0.1});
  // Interior nodes 1..7 alternate +0.25, -0.25 about the axis; the ends lie on it.
  for (int i = 1; i < n - 1; ++i) s.nodes[i].position.y() = (i % 2 == 1 ? 0.25 : -0.25);
  for (int i = 0; i + 1 < n; ++i)
    s.edges.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1)});
  BranchCleanupOptions o;
  o.smooth_iterations = 1;
  o.max_turn_deg = 180;
  clean_branches(s, std::vector<std::uint32_t>{0}, o);
  // Interior nodes next to the ends keep a quarter of the neighbour's offset; the rest vanish.
  for (int i = 2; i < n - 2; ++i) EXPECT_EQ(s.nodes[i].position.y(), 0.0) << i;
  EXPECT_EQ(s.nodes[0].position, Vec3(0, 0, 0));
  EXPECT_EQ(s.nodes[n - 1].position, Vec3(n - 1, 0, 0));
}

TEST(BranchCleanup, PruningIsIdempotentAndKeepsOneChildPerFork) {
  for (const TreeCase& t : tree_cases()) {
    SCOPED_TRACE("seed " + std::to_string(t.seed));
    Skeleton s = grow_case(t, 0, 0).skeleton;
    BranchCleanupOptions o;
    o.prune_length = 2.0 * t.step;
    const BranchCleanupReport first = clean_branches(s, std::vector<std::uint32_t>{0}, o);
    EXPECT_GT(first.stubs_pruned, 0u);
    EXPECT_EQ(first.kinks_removed, 0u);  // no smoothing, no kink removal
    EXPECT_EQ(first.nodes_moved, 0u);
    // No removable stub is left, and a second pass changes nothing.
    const Skeleton once = s;
    const BranchCleanupReport second = clean_branches(s, std::vector<std::uint32_t>{0}, o);
    EXPECT_EQ(second.nodes_removed, 0u);
    EXPECT_EQ(second.stubs_pruned, 0u);
    EXPECT_EQ(s.edges, once.edges);
    for (std::size_t v = 0; v < s.node_count(); ++v)
      EXPECT_EQ(s.nodes[v].position, once.nodes[v].position);
    expect_pipe_model(s, o.pipe_exponent);
  }
}

// Hand-made trees: a trunk 0-1-2 forking at 2 into a long branch and stubs.
Skeleton fork_with_stubs() {
  Skeleton s;
  auto add = [&](double x, double y, double z, int parent) {
    s.nodes.push_back({Vec3(x, y, z), 1.0});
    if (parent >= 0)
      s.edges.push_back(
          {static_cast<std::uint32_t>(parent), static_cast<std::uint32_t>(s.nodes.size() - 1)});
  };
  add(0, 0, 0, -1);      // 0 root
  add(0, 0, 1, 0);       // 1
  add(0, 0, 2, 1);       // 2 fork
  add(1, 0, 3, 2);       // 3 long branch
  add(2, 0, 4, 3);       // 4
  add(3, 0, 5, 4);       // 5 tip
  add(-0.5, 0, 2.5, 2);  // 6 stub tip (length ~0.71)
  add(0, 0.8, 2.2, 2);   // 7 second stub tip (length ~0.82)
  return s;
}

TEST(BranchCleanup, StubsArePrunedAndTheRadiiFollowThePipeModel) {
  Skeleton s = fork_with_stubs();
  BranchCleanupOptions o;
  o.prune_length = 1.0;
  o.tip_radius = 0.1;
  o.pipe_exponent = 2.0;
  const BranchCleanupReport rep = clean_branches(s, std::vector<std::uint32_t>{0}, o);
  EXPECT_EQ(rep.stubs_pruned, 2u);
  EXPECT_EQ(rep.nodes_removed, 2u);
  ASSERT_EQ(s.node_count(), 6u);
  for (std::size_t v = 0; v < 6; ++v)
    EXPECT_EQ(s.nodes[v].position, fork_with_stubs().nodes[v].position);
  for (const SkeletonNode& node : s.nodes) EXPECT_DOUBLE_EQ(node.radius, 0.1);  // one chain now
  EXPECT_EQ(rep.before.tip_branches, 3u);
  EXPECT_EQ(rep.before.short_tip_branches, 2u);
  EXPECT_EQ(rep.after.tip_branches, 1u);
  EXPECT_EQ(rep.after.short_tip_branches, 0u);
}

TEST(BranchCleanup, AForkWhoseChildrenAreAllStubsKeepsTheLongest) {
  Skeleton s = fork_with_stubs();
  BranchCleanupOptions o;
  o.prune_length = 100;  // every tip branch is a stub; the root chain never is
  const BranchCleanupReport rep = clean_branches(s, std::vector<std::uint32_t>{0}, o);
  EXPECT_EQ(rep.stubs_pruned, 2u);
  ASSERT_EQ(s.node_count(), 6u);  // the long branch stays, the whole tree is one chain
  EXPECT_EQ(s.nodes.back().position, Vec3(3, 0, 5));
  // A second pass finds nothing: a chain from the root is never a stub.
  EXPECT_EQ(clean_branches(s, std::vector<std::uint32_t>{0}, o).nodes_removed, 0u);
}

TEST(BranchCleanup, AChainThatDoublesBackLosesItsKink) {
  // 0 -> 1 -> 2 -> 3 -> 4 where 3 turns almost straight back toward 2.
  Skeleton s;
  const std::vector<Vec3> p = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {0.05, 0, 2.2}};
  for (const Vec3& q : p) s.nodes.push_back({q, 0.1});
  for (std::uint32_t i = 0; i + 1 < p.size(); ++i) s.edges.push_back({i, i + 1});
  BranchCleanupOptions o;
  o.smooth_iterations = 2;
  const BranchCleanupReport rep = clean_branches(s, std::vector<std::uint32_t>{0}, o);
  EXPECT_GT(rep.before.turn_max_deg, 170.0);
  EXPECT_GE(rep.kinks_removed, 1u);
  EXPECT_EQ(rep.nodes_removed, rep.kinks_removed);
  EXPECT_LE(rep.after.turn_max_deg, o.max_turn_deg);
  EXPECT_EQ(s.nodes.front().position, p.front());
  EXPECT_EQ(s.nodes.back().position, p.back());
  ASSERT_NO_THROW(validate(s));
}

TEST(BranchCleanup, SeveralRootsStaySeparateTrees) {
  const TreeCase t = tree_cases()[0];
  ColonizationOptions o = grow_options(t);
  o.roots = {Vec3(-1.5, 0, 0), Vec3(1.5, 0, 0)};
  o.smooth_iterations = kDemoSmooth;
  o.prune_steps = kDemoPrune;
  const ColonizationResult r =
      grow_space_colonization(crown_points(t.seed, t.points, t.center, t.radii), o);
  ASSERT_NO_THROW(validate(r.skeleton));
  EXPECT_EQ(connected_components(r.skeleton).count, 2u);
  EXPECT_EQ(r.skeleton.nodes[0].position, o.roots[0]);
  EXPECT_EQ(r.skeleton.nodes[1].position, o.roots[1]);
  EXPECT_EQ(r.skeleton.edge_count() + 2, r.skeleton.node_count());
  EXPECT_GT(r.cleanup.stubs_pruned, 0u);
  EXPECT_LE(r.cleanup.after.turn_p90_deg, 30.0);
  EXPECT_LE(r.cleanup.after.turn_max_deg, 90.0);
  EXPECT_LE(r.cleanup.after.short_share(), 0.10);
}

TEST(BranchCleanup, SameResultOnAnyThreadCount) {
  const TreeCase t = tree_cases()[2];
  Context one(1), two(2);
  const ColonizationResult a = grow_case(t, kDemoSmooth, kDemoPrune, &one);
  const ColonizationResult b = grow_case(t, kDemoSmooth, kDemoPrune, &two);
  ASSERT_EQ(a.skeleton.node_count(), b.skeleton.node_count());
  EXPECT_EQ(a.skeleton.edges, b.skeleton.edges);
  for (std::size_t v = 0; v < a.skeleton.node_count(); ++v) {
    EXPECT_EQ(a.skeleton.nodes[v].position, b.skeleton.nodes[v].position);
    EXPECT_EQ(a.skeleton.nodes[v].radius, b.skeleton.nodes[v].radius);
  }
  EXPECT_EQ(cleanup_summary(a.cleanup, "2 steps"), cleanup_summary(b.cleanup, "2 steps"));
}

TEST(BranchCleanup, OffChangesNothing) {
  const Skeleton raw = grow_case(tree_cases()[3], 0, 0).skeleton;
  Skeleton s = raw;
  const BranchCleanupReport rep = clean_branches(s, std::vector<std::uint32_t>{0}, {});
  EXPECT_EQ(rep.nodes_moved + rep.nodes_removed + rep.stubs_pruned + rep.kinks_removed, 0u);
  EXPECT_EQ(s.edges, raw.edges);
  for (std::size_t v = 0; v < s.node_count(); ++v) {
    EXPECT_EQ(s.nodes[v].position, raw.nodes[v].position);
    EXPECT_EQ(s.nodes[v].radius, raw.nodes[v].radius);
  }
}

TEST(BranchCleanup, BadOptionsAndSkeletonsAreRejected) {
  Skeleton s = fork_with_stubs();
  const std::vector<std::uint32_t> root = {0};
  auto with = [&](auto change) {
    BranchCleanupOptions o;
    change(o);
    return clean_branches(s, root, o);
  };
  EXPECT_THROWS_WITH(with([](auto& o) { o.smooth_iterations = -1; }),
                     "smooth_iterations must be in [0, 1000] (got -1)");
  EXPECT_THROWS_WITH(with([](auto& o) { o.smooth_iterations = 1001; }), "(got 1001)");
  EXPECT_THROWS_WITH(with([](auto& o) { o.max_turn_deg = 0; }), "max_turn_deg must be in (0, 180]");
  EXPECT_THROWS_WITH(with([](auto& o) { o.max_turn_deg = 181; }), "(got 181)");
  EXPECT_THROWS_WITH(with([](auto& o) { o.prune_length = -1; }),
                     "prune_length must be finite and >= 0");
  EXPECT_THROWS_WITH(with([](auto& o) { o.prune_length = std::nan(""); }), "prune_length");
  EXPECT_THROWS_WITH(with([](auto& o) { o.tip_radius = 0; }), "tip_radius");
  EXPECT_THROWS_WITH(with([](auto& o) { o.pipe_exponent = 4; }), "pipe_exponent must be in [2, 3]");
  EXPECT_THROWS_WITH(clean_branches(s, std::vector<std::uint32_t>{99}, {}),
                     "root 99 is out of range");
  Skeleton cycle = s;
  cycle.edges.push_back({5, 6});
  EXPECT_THROWS_WITH(clean_branches(cycle, root, {}), "cycle");

  ColonizationOptions c;
  c.smooth_iterations = -2;
  EXPECT_THROWS_WITH(c.validate(), "smooth_iterations must be in [0, 1000] (got -2)");
  c = {};
  c.prune_steps = -0.5;
  EXPECT_THROWS_WITH(c.validate(), "prune_steps must be finite and >= 0 (got -0.5)");
  c = {};
  c.max_turn_deg = 200;
  EXPECT_THROWS_WITH(c.validate(), "max_turn_deg must be in (0, 180] (got 200)");
}

}  // namespace
}  // namespace ramiform
