// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/lod.h"

#include <gtest/gtest.h>

#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/winding.h"
#include "ramiform/skeleton/generate.h"
#include "support/fixtures.h"
#include "support/mesh_checkers.h"

namespace ramiform {
namespace {

Skeleton tree(std::size_t segments, std::uint64_t seed) {
  BranchingTreeOptions o;
  o.segments = segments;
  o.seed = seed;
  o.tip_radius = 0.02;
  return branching_tree(o);
}

void expect_whole(const std::vector<TriMesh>& levels, const Skeleton& s) {
  for (std::size_t k = 0; k < levels.size(); ++k) {
    SCOPED_TRACE("level " + std::to_string(k));
    test::expect_closed_manifold(levels[k]);
    test::expect_components(levels[k], 1);
    EXPECT_EQ(test::nodes_outside(levels[k], s), 0u);
    if (k > 0) {
      EXPECT_LT(levels[k].triangle_count(), levels[k - 1].triangle_count());
    }
  }
}

TEST(PolygonizeLods, ToleranceLevelsAreWholeMeshesWithFallingCountsAndTheirDeviation) {
  const Skeleton s = tree(40, 5);
  const FieldPtr f = make_skeleton_field(s);
  const std::vector<LodLevel> levels = {{0.05, 0}, {0.15, 0}, {0.4, 0}};
  std::vector<LodStats> st;
  const std::vector<TriMesh> m = polygonize_lods(*f, s, {}, levels, nullptr, &st);
  ASSERT_EQ(m.size(), 3u);
  ASSERT_EQ(st.size(), 3u);
  expect_whole(m, s);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(st[k].triangles, m[k].triangle_count());
    EXPECT_EQ(st[k].tolerance, levels[k].tolerance);
    EXPECT_EQ(st[k].attempts, 1);
    EXPECT_TRUE(st[k].mesher.reached) << "level " << k;
    EXPECT_LE(st[k].mesher.deviation.samples.p99, levels[k].tolerance) << "level " << k;
  }
}

TEST(PolygonizeLods, BudgetLevelsStayWithinTheirBudgetsEvenBelowTheCoarsestBaseMesh) {
  const Skeleton s = test::subdivided(tree(30, 7), 6);
  const FieldPtr f = make_skeleton_field(s);
  ToleranceOptions coarsest;
  coarsest.tets.levels = 0;
  coarsest.tets.crotch_points = true;  // as the tolerance mesher's base mesh has them
  const std::size_t base0 = polygonize_tetrahedral(*f, s, coarsest.tets).triangle_count();
  const std::size_t fine = polygonize_to_tolerance(*f, s).triangle_count();
  const std::vector<LodLevel> levels = {
      {0, fine * 8 / 10}, {0, fine * 4 / 10}, {0, base0 * 7 / 10}};
  std::vector<LodStats> st;
  const std::vector<TriMesh> m = polygonize_lods(*f, s, {}, levels, nullptr, &st);
  ASSERT_EQ(m.size(), 3u);
  expect_whole(m, s);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_LE(m[k].triangle_count(), levels[k].max_triangles) << "level " << k;
    EXPECT_GE(st[k].attempts, 1);
  }
  // The last budget is below what the polygonizer gives at 0 levels: the previous level's mesh
  // (closer to the surface than that one) was coarsened by edge collapses, and stays close to
  // the surface.
  EXPECT_EQ(st[2].levels, st[1].levels);
  EXPECT_EQ(st[2].coarsened_from, st[1].triangles);
  EXPECT_EQ(st[2].collapsed, (st[1].triangles - m[2].triangle_count()) / 2);
  EXPECT_LE(st[2].mesher.deviation.samples.p99, 0.15);  // 0.11 (from the 0-level mesh: 0.34)
  EXPECT_EQ(st[0].collapsed, 0u);                       // the first level has no finer one
  // Alone, such a budget coarsens the mesh at 0 levels.
  const std::vector<LodLevel> below = {{0, base0 * 7 / 10}};
  const std::vector<TriMesh> b = polygonize_lods(*f, s, {}, below, nullptr, &st);
  expect_whole(b, s);
  EXPECT_LE(b[0].triangle_count(), below[0].max_triangles);
  EXPECT_EQ(st[0].levels, 0);
  EXPECT_EQ(st[0].coarsened_from, base0);
  EXPECT_GT(st[0].collapsed, 0u);
  EXPECT_LE(st[0].mesher.deviation.samples.p99, 0.4);  // the 0-level mesh's own: 0.33
  // A budget far below anything the skeleton allows is refused, naming the budget.
  const std::vector<LodLevel> tiny = {{0, 10}};
  try {
    (void)polygonize_lods(*f, s, {}, tiny);
    ADD_FAILURE() << "a 10-triangle budget was accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("budget of 10 triangles"), std::string::npos) << e.what();
  }
}

TEST(PolygonizeLods, SameResultOnOneAndTwoThreads) {
  const Skeleton s = tree(25, 2);
  const FieldPtr f = make_skeleton_field(s);
  const std::vector<LodLevel> levels = {{0.08, 0}, {0.3, 0}};
  Context one, two;
  one.set_threads(1);
  two.set_threads(2);
  const auto a = polygonize_lods(*f, s, {}, levels, &one);
  const auto b = polygonize_lods(*f, s, {}, levels, &two);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].triangles, b[k].triangles);
    EXPECT_EQ(a[k].positions, b[k].positions);
  }
  // Budgets, the last below the mesh at 0 levels (coarsened).
  const std::size_t n = a[1].triangle_count();
  const std::vector<LodLevel> budgets = {{0, n}, {0, n / 3}};
  std::vector<LodStats> st;
  const auto c = polygonize_lods(*f, s, {}, budgets, &one, &st);
  const auto d = polygonize_lods(*f, s, {}, budgets, &two);
  EXPECT_GT(st[1].collapsed, 0u);
  ASSERT_EQ(c.size(), d.size());
  for (std::size_t k = 0; k < c.size(); ++k) {
    EXPECT_EQ(c[k].triangles, d[k].triangles);
    EXPECT_EQ(c[k].positions, d[k].positions);
  }
}

TEST(PolygonizeLods, RejectsLevelsThatAreEmptyMixedOutOfRangeOrNotCoarsening) {
  const Skeleton s = tree(10, 1);
  const FieldPtr f = make_skeleton_field(s);
  const std::vector<std::vector<LodLevel>> bad = {
      {},
      {{0.05, 0}, {0, 1000}},
      {{0.05, 100}},
      {{0.0001, 0}},
      {{0.2, 0}, {0.1, 0}},
      {{0, 1000}, {0, 1000}},
  };
  for (const auto& levels : bad) {
    EXPECT_THROW((void)polygonize_lods(*f, s, {}, levels), InvalidArgument) << levels.size();
  }
}

TEST(SimplifyChains, DropsStraightChainNodesAndKeepsRootsForksTipsAndShape) {
  const Skeleton t = tree(20, 4);
  const Skeleton s = test::subdivided(t, 5);
  const Skeleton c = simplify_chains(s, 0.25);
  EXPECT_NO_THROW(validate(c));
  // The subdivision nodes lie on straight, linearly tapered edges: all of them go, and the
  // result has the tree's own edges (its chains may lose their straight interior nodes too).
  EXPECT_LE(c.edge_count(), t.edge_count());
  const auto deg_s = degrees(s);
  std::size_t special = 0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) special += deg_s[i] != 2 ? 1 : 0;
  std::size_t special_c = 0;
  const auto deg_c = degrees(c);
  for (std::size_t i = 0; i < c.nodes.size(); ++i) special_c += deg_c[i] != 2 ? 1 : 0;
  EXPECT_EQ(special_c, special);  // every root, fork and tip stays
  EXPECT_EQ(connected_components(c).count, 1u);
  // A bent chain keeps its bend.
  Skeleton bent;
  for (int i = 0; i <= 10; ++i) {
    const double x = i * 0.1;
    bent.nodes.push_back({Vec3(x, i <= 5 ? 0.0 : (x - 0.5), 0), 0.05});
    if (i > 0)
      bent.edges.push_back({static_cast<std::uint32_t>(i - 1), static_cast<std::uint32_t>(i)});
  }
  const Skeleton b = simplify_chains(bent, 0.25);
  ASSERT_EQ(b.node_count(), 3u);
  EXPECT_EQ(b.nodes[1].position, Vec3(0.5, 0, 0));  // the corner, numbered as its chain is walked
  EXPECT_THROW((void)simplify_chains(bent, 0.0), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
