// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/coarsen.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/mesh/winding.h"
#include "ramiform/polygonize/refine.h"
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

// Vertices farther than 1e-3 local radii from the surface, to first order.
std::size_t off_surface(const TriMesh& m, const Field& f, const Skeleton& s) {
  std::vector<double> v(m.positions.size());
  std::vector<Vec3> g(m.positions.size());
  f.evaluate(m.positions, v, g);
  const std::vector<double> r = local_radii(s, m.positions);
  std::size_t n = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    n += std::abs(v[i] - f.iso()) > 1e-3 * r[i] * g[i].norm() ? 1 : 0;
  return n;
}

struct Case {
  const char* name;
  Skeleton skeleton;
};

std::vector<Case> cases() {
  return {{"branching tree", tree(30, 7)}, {"subdivided tree", test::subdivided(tree(30, 7), 6)}};
}

TEST(CoarsenToBudget, HalfAndQuarterStayClosedWholeOnTheSurfaceWithTheSkeletonInside) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const FieldPtr f = make_skeleton_field(c.skeleton);
    const TriMesh base = polygonize_to_tolerance(*f, c.skeleton);
    ASSERT_EQ(test::nodes_outside(base, c.skeleton), 0u);
    const DeviationReport d0 = measure_deviation(base, *f, &c.skeleton);
    for (const std::size_t share : {2u, 4u}) {
      SCOPED_TRACE("1/" + std::to_string(share));
      TriMesh m = base;
      CoarsenOptions o;
      o.max_triangles = base.triangle_count() / share;
      CoarsenStats st;
      coarsen_to_budget(m, *f, c.skeleton, o, nullptr, &st);
      EXPECT_TRUE(st.reached);
      EXPECT_LE(m.triangle_count(), o.max_triangles);
      EXPECT_EQ(st.triangles_before, base.triangle_count());
      EXPECT_EQ(st.triangles_after, m.triangle_count());
      EXPECT_EQ(st.triangles_before - st.triangles_after, 2 * st.collapsed);
      test::expect_closed_surface(m, 1, 2);  // genus 0, one piece, as the base mesh
      EXPECT_EQ(test::nodes_outside(m, c.skeleton), 0u);
      const DeviationReport d = measure_deviation(m, *f, &c.skeleton);
      EXPECT_EQ(d.samples.unresolved, 0u);
      // The bound is first order at centroids and midpoints (0.5 radii); least quadric error
      // first keeps the measure far below it (shortest edge first: p99 0.26, max 0.46 at a
      // quarter of the branching tree).
      EXPECT_LE(d.samples.p99, share == 2 ? 0.05 : 0.07) << "base p99 " << d0.samples.p99;
      EXPECT_LE(d.samples.max, 0.35) << "base max " << d0.samples.max;
      // Vertices lie on the surface: those a collapse makes or keeps are taken onto it, so no
      // more are off it than in the base mesh (the polygonizer leaves a few).
      EXPECT_LE(off_surface(m, *f, c.skeleton), off_surface(base, *f, c.skeleton));
      EXPECT_LE(d.vertices.max, d0.vertices.max + 1e-6);
    }
  }
}

TEST(CoarsenToBudget, SameResultOnOneAndTwoThreads) {
  const Skeleton s = test::subdivided(tree(20, 3), 4);
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh base = polygonize_to_tolerance(*f, s);
  CoarsenOptions o;
  o.max_triangles = base.triangle_count() / 3;
  Context one, two;
  one.set_threads(1);
  two.set_threads(2);
  TriMesh a = base, b = base;
  coarsen_to_budget(a, *f, s, o, &one);
  coarsen_to_budget(b, *f, s, o, &two);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.positions, b.positions);
}

TEST(CoarsenToBudget, StopsWithoutThrowingWhenNoCollapseIsAllowed) {
  const Skeleton s = tree(15, 2);
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh base = polygonize_to_tolerance(*f, s);
  // A budget no closed tree mesh can meet: it stops short, whole.
  TriMesh m = base;
  CoarsenOptions o;
  o.max_triangles = 8;
  CoarsenStats st;
  EXPECT_NO_THROW(coarsen_to_budget(m, *f, s, o, nullptr, &st));
  EXPECT_FALSE(st.reached);
  EXPECT_GT(m.triangle_count(), 8u);
  EXPECT_GT(st.collapsed, 0u);
  test::expect_closed_surface(m, 1, 2);
  EXPECT_EQ(test::nodes_outside(m, s), 0u);
  // A deviation bound nothing meets: nothing changes.
  TriMesh n = base;
  o.max_triangles = base.triangle_count() / 2;
  o.max_deviation = 1e-9;
  coarsen_to_budget(n, *f, s, o, nullptr, &st);
  EXPECT_EQ(st.collapsed, 0u);
  EXPECT_FALSE(st.reached);
  EXPECT_EQ(n.triangles, base.triangles);
  EXPECT_EQ(n.positions, base.positions);
  // A mesh within the budget is left alone.
  TriMesh w = base;
  o.max_triangles = base.triangle_count();
  o.max_deviation = 0.5;
  coarsen_to_budget(w, *f, s, o, nullptr, &st);
  EXPECT_TRUE(st.reached);
  EXPECT_EQ(st.collapsed, 0u);
  EXPECT_EQ(w.triangles, base.triangles);
}

TEST(CoarsenToBudget, RejectsBadOptions) {
  const Skeleton s = tree(5, 1);
  const FieldPtr f = make_skeleton_field(s);
  TriMesh m = polygonize_to_tolerance(*f, s);
  const auto bad = [&](auto edit) {
    CoarsenOptions o;
    o.max_triangles = 10;
    edit(o);
    EXPECT_THROW(coarsen_to_budget(m, *f, s, o), InvalidArgument);
  };
  bad([](CoarsenOptions& o) { o.max_triangles = 0; });
  bad([](CoarsenOptions& o) { o.min_angle_deg = 60; });
  bad([](CoarsenOptions& o) { o.max_turn_deg = 0; });
  bad([](CoarsenOptions& o) { o.max_deviation = 0; });
  CoarsenOptions o;
  o.max_triangles = 10;
  EXPECT_THROW(coarsen_to_budget(m, *f, Skeleton{}, o), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
