// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Refinement towards a deviation tolerance: the mesh stays closed, oriented, manifold and in
// one piece with every node inside; its deviation, measured independently (another seed, more
// points, the exact projection of mesh/deviation.h), stays under the tolerance and follows it.

#include "ramiform/polygonize/refine.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "polygonize/cheapest_first.h"
#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/mesh/winding.h"
#include "ramiform/skeleton/generate.h"
#include "support/mesh_checkers.h"

namespace ramiform {
namespace {

Skeleton tree(std::size_t segments) {
  BranchingTreeOptions o;
  o.segments = segments;
  o.seed = 3;
  o.tip_radius = 0.01;
  return branching_tree(o);
}

/// The paper's uniform mesh at level 1 of the field of `s`.
TriMesh level_one(const Field& f, const Skeleton& s) {
  TetrahedralOptions base;
  base.levels = 1;
  return polygonize_tetrahedral(f, s, base);
}

/// The deviation p99 of `m`, measured with a seed and a count the polygonizer did not use.
DeviationSummary measured(const TriMesh& m, const Field& f, const Skeleton& s) {
  DeviationOptions o;
  o.samples = 40000;
  o.seed = 987;
  o.vertices = false;
  return measure_deviation(m, f, &s, o).samples;
}

TEST(PolygonizeToTolerance, MeetsTheToleranceAndKeepsTheMeshWhole) {
  const Skeleton s = tree(60);
  const FieldPtr f = make_skeleton_field(s);
  ToleranceOptions o;
  ToleranceStats st;
  const TriMesh m = polygonize_to_tolerance(*f, s, o, nullptr, &st);
  test::expect_closed_manifold(m);
  test::expect_components(m, 1);
  EXPECT_EQ(test::nodes_outside(m, s), 0u);
  EXPECT_TRUE(st.reached);
  EXPECT_LE(st.deviation.samples.p99, o.tolerance);
  EXPECT_GT(st.refine.split_edges, 0u);
  EXPECT_GT(m.triangles.size(), st.refine.triangles_before);
  // The base mesh's vertices stop at |f - iso| <= 1e-4 iso (TetrahedralOptions::root_value):
  // 2.2 root evaluations per crossing edge here, 3.2 to the default 1e-8.
  EXPECT_LT(static_cast<double>(st.tets.root_evaluations),
            2.6 * static_cast<double>(st.tets.crossing_edges));
  const DeviationSummary d = measured(m, *f, s);
  EXPECT_EQ(d.unresolved, 0u);
  EXPECT_LE(d.p99, o.tolerance) << "max " << d.max;
  EXPECT_LE(d.max, 5 * o.tolerance);
  // The unrefined base mesh is much farther off: refinement did the work.
  TetrahedralOptions base = o.tets;
  const TriMesh coarse = polygonize_tetrahedral(*f, s, base);
  EXPECT_GT(measured(coarse, *f, s).p99, 2 * o.tolerance);
}

/// polygonize_to_tolerance() of the convolution surface of `s` at the default tolerance, checked
/// closed and 2-manifold with `pieces` components and every node inside; returns its deviation
/// over `samples` points (seed `seed`).
DeviationReport tolerance_mesh_deviation(const Skeleton& s, std::size_t pieces, std::size_t samples,
                                         std::uint64_t seed, ToleranceStats* st = nullptr) {
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh m = polygonize_to_tolerance(*f, s, {}, nullptr, st);
  test::expect_closed_manifold(m);
  test::expect_components(m, pieces);
  EXPECT_EQ(test::nodes_outside(m, s), 0u);
  DeviationOptions o;
  o.samples = samples;
  o.seed = seed;
  return measure_deviation(m, *f, &s, o);
}

/// Two Y forks, nodes 0-3 (base, fork, two ends) and 4-7 alike: two skeleton components.
Skeleton two_forks(std::vector<SkeletonNode> nodes) {
  Skeleton s;
  s.nodes = std::move(nodes);
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {4, 5}, {5, 6}, {5, 7}};
  return s;
}

TEST(PolygonizeToTolerance, CrotchOfANarrowForkIsMeshedOnTheSurface) {
  // A fork cut from a generated tree: two 0.113 branches leaving a 0.16 node 67° apart. Without
  // the crotch points the lattice crossed the V between them with edges a radius long, the
  // refinement's splits there folded and stayed off the surface (vertices 0.18 radii out,
  // points of the mesh 0.23-0.26), the largest deviations of generated trees.
  Skeleton s;
  s.nodes = {{Vec3(1.7073, 0.4406, -0.7598), 0.24},
             {Vec3(0, 0, 0), 0.16},
             {Vec3(-1.1065, 0.1353, 1.0567), 0.1131},
             {Vec3(-1.2997, -0.811, -0.1112), 0.1131}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}};
  ToleranceStats st;
  const DeviationReport d = tolerance_mesh_deviation(s, 1, 40000, 987, &st);
  EXPECT_EQ(st.tets.crotch_points, 3u);  // the two branches' pair only (the others are wide)
  EXPECT_LT(d.vertices.max, 0.01);
  EXPECT_LT(d.samples.max, 0.125);
}

TEST(PolygonizeToTolerance, TwigPassingAForkOfAnotherBranchStaysApart) {
  // Cut from `generate --segments 1000 --seed 51 --tip-radius 0.004 --trunk-length 1`: a 0.0048
  // twig passing 0.0105 (1.5 twig radii) from the fork of another branch, two skeleton
  // components. The gap search's crosses for the fork's two outgoing edges lay 1.2 twig radii
  // from the narrowest spot and, within 1.5 radii, left out the cross across it; the lattice
  // then joined the two into one piece by a handle whose vertices stood 0.32 radii off the
  // surface (the tree's largest deviation, 0.34).
  Skeleton s;
  s.nodes = {{Vec3(-0.2689542, 1.9814674, 2.5050914), 0.008},
             {Vec3(-0.1855464, 2.1318343, 2.5344277), 0.0056569},
             {Vec3(-0.2362302, 2.1270317, 2.5818225), 0.0056569},
             {Vec3(-0.3001288, 2.1431975, 2.6033926), 0.004},
             {Vec3(-0.283746, 2.2384262, 2.6396837), 0.004},
             {Vec3(-0.1548132, 2.2198142, 2.6345205), 0.004}};
  s.edges = {{0, 2}, {1, 3}, {2, 4}, {2, 5}};
  const FieldPtr f = make_skeleton_field(s);
  // The surfaces stay apart: half way between the twig's axis and the fork the field is 0.91
  // of iso.
  ASSERT_LT(f->value(Vec3(-0.23977136, 2.13310647, 2.57467362)), 0.95 * f->iso());
  const DeviationReport d = tolerance_mesh_deviation(s, 2, 40000, 7);
  EXPECT_LT(d.vertices.max, 0.05);
  EXPECT_LT(d.samples.max, 0.15);
}

TEST(PolygonizeToTolerance, GapCrossGoesWhereTheSwollenTubesLeaveTheirGap) {
  // Cut from `generate --segments 1700 --seed 34`: a 0.02 twig fork passing 0.17 (axis to
  // axis) from a 0.10 branch, two skeleton components. By the radii the gap between the tubes
  // is 0.047 wide and its cross went to its middle, but the blend swells both tubes: the field
  // there is just inside (1.003 of iso), and below iso only further on (0.99 at 0.64 of the
  // gap). The lattice joined the two by handles (Euler characteristic -2) with vertices a twig
  // radius off the surface.
  const Skeleton s = two_forks({{Vec3(-2.3793064, -0.5867075, 9.3008973), 0.16},
                                {Vec3(-2.8703306, -0.9719789, 10.0603898), 0.1131371},
                                {Vec3(-3.140931, -1.6513392, 10.3497345), 0.08},
                                {Vec3(-3.1910024, -0.8261133, 10.763503), 0.08},
                                {Vec3(-2.3343263, -0.8210634, 9.9996099), 0.04},
                                {Vec3(-2.6718141, -0.8892519, 10.2083727), 0.0282843},
                                {Vec3(-2.8577314, -1.0830593, 10.386239), 0.02},
                                {Vec3(-2.9428429, -0.7457798, 10.3069733), 0.02}});
  const FieldPtr f = make_skeleton_field(s);
  ASSERT_GT(f->value(Vec3(-2.90425726, -0.81752446, 10.28225701)), f->iso());
  ASSERT_LT(f->value(Vec3(-2.90748426, -0.82303598, 10.28192866)), f->iso());
  const DeviationReport d = tolerance_mesh_deviation(s, 2, 40000, 7);
  EXPECT_LT(d.vertices.max, 0.05);
  EXPECT_LT(d.samples.max, 0.2);
}

TEST(PolygonizeToTolerance, FanOfAVertexBroughtOntoTheSurfaceLateIsRefined) {
  // Cut from `generate --segments 3000 --seed 56 --tip-radius 0.004 --trunk-length 1`: a twig
  // fork (0.004-0.008) beside a 0.032-0.045 branch. A split in the crotch between them was left
  // half way to the surface and only brought onto it after the rounds; none of its edges had
  // been split while it was off, so its fan stayed coarse and sagged 0.4-0.7 twig radii
  // between corners on the surface.
  const Skeleton s = two_forks({{Vec3(-0.9924003, -0.1466398, 2.5940301), 0.0452548},
                                {Vec3(-1.316539, -0.0322917, 2.8168098), 0.032},
                                {Vec3(-1.5541065, -0.0926174, 3.0342878), 0.0226274},
                                {Vec3(-1.524208, 0.2068707, 2.9007688), 0.0226274},
                                {Vec3(-1.1103074, -0.0402849, 2.8735419), 0.008},
                                {Vec3(-1.200009, 0.0016618, 2.832029), 0.0056569},
                                {Vec3(-1.2611301, -0.0012332, 2.771742), 0.004},
                                {Vec3(-1.2603591, 0.0626007, 2.8368259), 0.004}});
  ToleranceStats st;
  const DeviationReport d = tolerance_mesh_deviation(s, 1, 100000, 1, &st);
  EXPECT_GT(st.refine.reprojected, 0u);
  EXPECT_LT(d.vertices.max, 0.1);
  EXPECT_LT(d.samples.max, 0.2);
}

TEST(PolygonizeToTolerance, HalvingTheToleranceRoughlyHalvesTheDeviation) {
  const Skeleton s = tree(40);
  const FieldPtr f = make_skeleton_field(s);
  std::vector<double> p99;
  std::vector<std::size_t> triangles;
  for (const double t : {0.1, 0.05, 0.025}) {
    ToleranceOptions o;
    o.tolerance = t;
    const TriMesh m = polygonize_to_tolerance(*f, s, o);
    const DeviationSummary d = measured(m, *f, s);
    EXPECT_LE(d.p99, t);
    p99.push_back(d.p99);
    triangles.push_back(m.triangles.size());
    EXPECT_EQ(test::nodes_outside(m, s), 0u) << "tolerance " << t;
  }
  for (std::size_t i = 1; i < p99.size(); ++i) {
    const double ratio = p99[i] / p99[i - 1];
    EXPECT_GT(ratio, 0.3) << "step " << i;
    EXPECT_LT(ratio, 0.8) << "step " << i;
    EXPECT_GT(triangles[i], triangles[i - 1]);
  }
}

TEST(PolygonizeToTolerance, SameMeshOnAnyThreadCount) {
  const Skeleton s = tree(30);
  const FieldPtr f = make_skeleton_field(s);
  Context one(1), two(2);
  const TriMesh a = polygonize_to_tolerance(*f, s, {}, &one);
  const TriMesh b = polygonize_to_tolerance(*f, s, {}, &two);
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    ASSERT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;
  }
}

// on_pass sees each pass's mesh before it is measured (the studio shows it meanwhile): once per
// pass, the last one the result itself.
TEST(PolygonizeToTolerance, OnPassSeesEachPassBeforeItsMeasure) {
  const Skeleton s = tree(30);
  const FieldPtr f = make_skeleton_field(s);
  ToleranceOptions o;
  std::vector<TriMesh> seen;
  o.on_pass = [&](const TriMesh& m) { seen.push_back(m); };
  ToleranceStats st;
  const TriMesh m = polygonize_to_tolerance(*f, s, o, nullptr, &st);
  ASSERT_EQ(seen.size(), static_cast<std::size_t>(st.passes));
  EXPECT_EQ(seen.back().triangles, m.triangles);
  EXPECT_EQ(seen.back().positions, m.positions);
}

TEST(RefineToSurface, SplitsOnlyWhereTheMeshIsFarAndRespectsTheBudget) {
  const Skeleton s = tree(20);
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh coarse = level_one(*f, s);
  // A tolerance the coarse mesh already meets everywhere: nothing changes.
  TriMesh same = coarse;
  RefineOptions loose;
  loose.edge_tolerance = 10.0;
  RefineStats st;
  refine_to_surface(same, *f, s, loose, nullptr, &st);
  EXPECT_EQ(st.rounds, 0);
  EXPECT_EQ(same.triangles, coarse.triangles);
  // A budget below the first round's size stops before it.
  TriMesh capped = coarse;
  RefineOptions tight;
  tight.max_triangles = coarse.triangles.size() + 10;
  refine_to_surface(capped, *f, s, tight, nullptr, &st);
  EXPECT_TRUE(st.budget_reached);
  EXPECT_EQ(capped.triangles.size(), coarse.triangles.size());
  // One round: every split adds one triangle per side, and the new vertices lie on the surface
  // unless left flat.
  TriMesh one = coarse;
  RefineOptions r;
  r.max_rounds = 1;
  r.settle_rounds = 0;
  refine_to_surface(one, *f, s, r, nullptr, &st);
  EXPECT_EQ(st.rounds, 1);
  EXPECT_EQ(one.triangles.size(), coarse.triangles.size() + 2 * st.split_edges);
  EXPECT_EQ(one.positions.size(), coarse.positions.size() + st.split_edges);
  test::expect_closed_manifold(one);
  // On the surface: within 1e-4 local radii (the projection stops once its Newton step is below
  // 3e-3 radii, which leaves about 1e-5).
  std::size_t on_surface = 0;
  const std::vector<double> radii = local_radii(s, one.positions);
  for (std::size_t v = coarse.positions.size(); v < one.positions.size(); ++v) {
    const double g = f->value(one.positions[v]) - f->iso();
    on_surface += std::abs(g) / f->gradient(one.positions[v]).norm() < 1e-4 * radii[v] ? 1 : 0;
  }
  EXPECT_EQ(on_surface, st.split_edges - st.flat_splits - st.halfway + st.reprojected);
  EXPECT_EQ(st.flat_splits, st.unprojected + st.reverted);
}

/// Per vertex, its first-order distance from the surface in local radii.
std::vector<double> vertex_distances(const TriMesh& m, const Field& f, const Skeleton& s) {
  const std::vector<double> radii = local_radii(s, m.positions);
  std::vector<double> d(m.positions.size());
  for (std::size_t v = 0; v < d.size(); ++v) {
    d[v] =
        std::abs(f.value(m.positions[v]) - f.iso()) / f.gradient(m.positions[v]).norm() / radii[v];
  }
  return d;
}

TEST(RefineToSurface, VerticesLeftOffTheSurfaceGoOntoItOnceTheirFanIsRefined) {
  // A tree whose forks leave vertices half way to the surface (17 here), spikes over it once
  // the rounds have refined their neighbours onto it.
  BranchingTreeOptions to;
  to.segments = 60;
  to.seed = 3;
  const Skeleton s = branching_tree(to);
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh coarse = level_one(*f, s);
  RefineOptions without, once;
  without.reproject = false;
  once.settle_rounds = 0;  // one reprojection, no rounds after it: only vertices move
  RefineStats st_without, st;
  TriMesh left = coarse, taken = coarse;
  refine_to_surface(left, *f, s, without, nullptr, &st_without);
  refine_to_surface(taken, *f, s, once, nullptr, &st);
  ASSERT_GT(st.halfway + st.flat_splits, 0U);
  EXPECT_EQ(st_without.reprojected, 0U);
  EXPECT_GT(st.reprojected, 0U);
  // Only vertices move: the same triangles, the same counts.
  EXPECT_EQ(taken.triangles, left.triangles);
  EXPECT_EQ(st.split_edges, st_without.split_edges);
  test::expect_closed_manifold(taken);
  for (const auto& node : s.nodes) EXPECT_GT(winding_number(taken, node.position), 0.5);
  // The vertices that moved: `reprojected` of them onto the surface, the others half way.
  const std::vector<double> d_left = vertex_distances(left, *f, s);
  const std::vector<double> d_taken = vertex_distances(taken, *f, s);
  std::size_t moved = 0, onto = 0;
  for (std::size_t v = 0; v < d_left.size(); ++v) {
    if (taken.positions[v] == left.positions[v]) continue;
    ++moved;
    onto += d_taken[v] < 1e-4 ? 1 : 0;
    EXPECT_LT(d_taken[v], d_left[v]) << "vertex " << v;
  }
  EXPECT_EQ(onto, st.reprojected);
  EXPECT_GE(moved, onto);
  // Vertices beyond a tenth of a radius: 9 before, 1 after; the largest distance 0.18 -> 0.11.
  auto far = [](const std::vector<double>& d) {
    return std::count_if(d.begin(), d.end(), [](double x) { return x > 0.1; });
  };
  EXPECT_LE(3 * far(d_taken), far(d_left));
  EXPECT_LT(*std::max_element(d_taken.begin(), d_taken.end()),
            0.75 * *std::max_element(d_left.begin(), d_left.end()));
  // The default then refines the fans of the vertices it brought onto the surface: more splits
  // (each at a reprojected vertex's edge at first), the mesh still closed with every node
  // inside, and no vertex farther off than after the one reprojection.
  RefineStats st_settled;
  TriMesh settled = coarse;
  refine_to_surface(settled, *f, s, RefineOptions{}, nullptr, &st_settled);
  EXPECT_GT(st_settled.split_edges, st.split_edges);
  EXPECT_GE(st_settled.reprojected, st.reprojected);
  test::expect_closed_manifold(settled);
  EXPECT_EQ(test::nodes_outside(settled, s), 0u);
  const std::vector<double> d_settled = vertex_distances(settled, *f, s);
  EXPECT_LE(*std::max_element(d_settled.begin(), d_settled.end()),
            *std::max_element(d_taken.begin(), d_taken.end()) + 1e-9);
}

TEST(RefineToSurface, SpareAreaLeavesEdgesUnsplitWithinItsShare) {
  const Skeleton s = tree(20);
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh coarse = level_one(*f, s);
  // One round with and without a spare area: the same edges are beyond the tolerance, and each
  // is either split or spared.
  RefineOptions all, spare;
  all.max_rounds = spare.max_rounds = 1;
  all.settle_rounds = spare.settle_rounds = 0;
  spare.spare_area = 0.01;
  TriMesh a = coarse, b = coarse;
  RefineStats sa, sb;
  refine_to_surface(a, *f, s, all, nullptr, &sa);
  refine_to_surface(b, *f, s, spare, nullptr, &sb);
  EXPECT_EQ(sa.spared, 0u);
  EXPECT_GT(sb.spared, 0u);
  EXPECT_LT(sb.spared, sa.split_edges / 4);
  EXPECT_EQ(sb.split_edges + sb.spared, sa.split_edges);
  EXPECT_EQ(b.triangles.size(), coarse.triangles.size() + 2 * sb.split_edges);
  test::expect_closed_manifold(b);
  EXPECT_EQ(test::nodes_outside(b, s), 0u);
  // Refined to the end with the share polygonize_to_tolerance() spares (a twentieth of the 1 %
  // a p99 leaves): fewer triangles, and p99 (measured independently) still within the
  // tolerance.
  all.max_rounds = spare.max_rounds = 6;
  spare.spare_area = 5e-4;
  a = coarse;
  b = coarse;
  refine_to_surface(a, *f, s, all);
  refine_to_surface(b, *f, s, spare, nullptr, &sb);
  EXPECT_GT(sb.spared, 0u);
  EXPECT_LT(b.triangles.size(), a.triangles.size());
  test::expect_closed_manifold(b);
  const DeviationSummary da = measured(a, *f, s), db = measured(b, *f, s);
  EXPECT_LE(db.p99, all.edge_tolerance) << "without spare " << da.p99;
}

// The spared edges are taken cheapest first while they fit in the spare area: the partly sorted
// list gives the walk the same items, in the same order, as a full sort, ties (equal costs)
// broken by edge, for budgets that stop it early, late or never.
TEST(RefineToSurface, SpareOrderIsTheFullSortAsFarAsTheWalkReaches) {
  using Cost = std::vector<std::pair<double, std::uint32_t>>;
  auto walk = [](const Cost& cost, double budget) {
    std::vector<std::uint32_t> taken;
    for (const auto& [c, e] : cost) {
      if (c > budget) break;
      budget -= c;
      taken.push_back(e);
    }
    return std::make_pair(taken, budget);
  };
  Rng rng(5);
  for (const std::size_t n : {0, 10, 64, 65, 1000, 20000}) {
    Cost cost(n);
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double c = i % 11 == 0 ? 0.0 : (i % 7 == 0 ? 0.25 : rng.uniform());
      cost[i] = {c, static_cast<std::uint32_t>(n - i)};
      total += c;
    }
    Cost full = cost;
    std::sort(full.begin(), full.end());
    for (const double share : {0.0, 1e-3, 0.05, 0.3, 1.0, 2.0}) {
      Cost head = cost;
      detail::cheapest_first(head, share * total);
      ASSERT_LE(head.size(), full.size());
      EXPECT_TRUE(std::equal(head.begin(), head.end(), full.begin())) << n << " " << share;
      const auto [taken, left] = walk(head, share * total);
      EXPECT_EQ(std::make_pair(taken, left), walk(full, share * total)) << n << " " << share;
      // A shortened list holds the item the walk stops at.
      if (head.size() < full.size()) {
        EXPECT_LT(taken.size(), head.size());
      }
    }
  }
}

TEST(RefineToSurface, BadOptionsAreRefused) {
  const Skeleton s = tree(5);
  const FieldPtr f = make_skeleton_field(s);
  TriMesh m = polygonize_tetrahedral(*f, s, TetrahedralOptions{});
  RefineOptions o;
  o.edge_tolerance = 0;
  EXPECT_THROW(refine_to_surface(m, *f, s, o), InvalidArgument);
  o = {};
  o.max_turn_deg = 180;
  EXPECT_THROW(refine_to_surface(m, *f, s, o), InvalidArgument);
  o = {};
  o.max_normal_deg = 90;
  EXPECT_THROW(refine_to_surface(m, *f, s, o), InvalidArgument);
  o = {};
  o.spare_area = 0.02;
  EXPECT_THROW(refine_to_surface(m, *f, s, o), InvalidArgument);
  o.spare_area = -0.001;
  EXPECT_THROW(refine_to_surface(m, *f, s, o), InvalidArgument);
  o = {};
  o.max_rounds = -1;
  EXPECT_THROW(refine_to_surface(m, *f, s, o), InvalidArgument);
  o = {};
  o.settle_rounds = -1;
  EXPECT_THROW(refine_to_surface(m, *f, s, o), InvalidArgument);
  EXPECT_THROW(refine_to_surface(m, *f, Skeleton{}, RefineOptions{}), InvalidArgument);
  ToleranceOptions t;
  t.tolerance = 0;
  EXPECT_THROW((void)polygonize_to_tolerance(*f, s, t), InvalidArgument);
  t = {};
  t.samples = 10;
  EXPECT_THROW((void)polygonize_to_tolerance(*f, s, t), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
