// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// clean_needles: needles made on purpose (every triangle split 1:3 at a point very close to one
// corner) must go, while the mesh stays a closed, oriented 2-manifold of the same genus and no
// vertex moves.

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>
#include <vector>

#include "mesh/test_meshes.h"
#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/cleanup.h"
#include "ramiform/mesh/winding.h"
#include "support/mesh_checkers.h"

namespace ramiform {
namespace {

// Splits every `stride`-th triangle 1:3 at a point `eps` (barycentric) away from its first
// corner: each split makes two needles with angles of order eps.
TriMesh with_needles(TriMesh m, double eps, std::size_t stride) {
  const std::size_t n = m.triangles.size();
  for (std::size_t t = 0; t < n; t += stride) {
    const auto [a, b, c] = m.triangles[t];
    const Vec3 p = (1 - 2 * eps) * m.positions[a] + eps * m.positions[b] + eps * m.positions[c];
    const auto v = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(p);
    m.triangles[t] = {a, b, v};
    m.triangles.push_back({b, c, v});
    m.triangles.push_back({c, a, v});
  }
  return m;
}

// Numbers the vertices by first use, as the polygonizers do: consecutive vertex indices are
// then a compact piece of surface, which is what clean_needles() splits into parallel blocks.
TriMesh renumbered_by_first_use(const TriMesh& m) {
  std::vector<std::uint32_t> remap(m.positions.size(), UINT32_MAX);
  TriMesh out;
  for (auto t : m.triangles) {
    for (auto& v : t) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<std::uint32_t>(out.positions.size());
        out.positions.push_back(m.positions[v]);
      }
      v = remap[v];
    }
    out.triangles.push_back(t);
  }
  return out;
}

std::set<std::tuple<double, double, double>> position_set(const TriMesh& m) {
  std::set<std::tuple<double, double, double>> s;
  for (const auto& p : m.positions) s.insert({p.x(), p.y(), p.z()});
  return s;
}

TEST(NeedleCleanup, RemovesNeedlesKeepsTopologyAndDoesNotMoveVertices) {
  for (const auto& [base, euler] : {std::pair{test::icosphere(3), 2LL}, std::pair{test::torus(2.0, 0.6, 40, 16), 0LL}}) {
    const TriMesh needles = with_needles(base, 1e-4, 2);
    test::expect_closed_surface(needles, 1, euler);
    const AngleSummary before = angle_summary(needles);
    ASSERT_LT(before.min_deg, 0.1);
    TriMesh cleaned = needles;
    NeedleCleanupStats st;
    clean_needles(cleaned, {}, &st);
    test::expect_closed_surface(cleaned, 1, euler);
    EXPECT_GT(st.collapsed_edges, 0U);
    EXPECT_LT(cleaned.triangle_count(), needles.triangle_count());
    EXPECT_EQ(st.min_angle_before, before.min_deg);
    const AngleSummary after = angle_summary(cleaned);
    EXPECT_EQ(st.min_angle_after, after.min_deg);
    EXPECT_GT(after.min_deg, 10.0) << "every planted needle is removable";
    // Kept vertices stay where they were: the output positions are a subset of the input's.
    const auto in = position_set(needles);
    for (const auto& p : cleaned.positions) EXPECT_TRUE(in.count({p.x(), p.y(), p.z()}) == 1);
  }
}

TEST(NeedleCleanup, IsDeterministicAndLeavesGoodMeshesAlone) {
  const TriMesh needles = with_needles(test::icosphere(3), 1e-3, 3);
  TriMesh a = needles, b = needles;
  clean_needles(a);
  clean_needles(b);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  // An icosphere has no triangle below 15 degrees: nothing changes.
  TriMesh sphere = test::icosphere(2);
  const TriMesh original = sphere;
  NeedleCleanupStats st;
  clean_needles(sphere, {}, &st);
  EXPECT_EQ(st.collapsed_edges, 0U);
  EXPECT_EQ(sphere.positions, original.positions);
  EXPECT_EQ(sphere.triangles, original.triangles);
  // A tetrahedron cannot lose an edge and stay closed: the valence rule refuses.
  TriMesh tet = with_needles(test::tetrahedron(), 1e-3, 4);
  clean_needles(tet);
  test::expect_closed_surface(tet, 1, 2);
}

TEST(NeedleCleanup, SameResultOnAnyThreadCount) {
  // Some 60k vertices: several blocks of the parallel pass, with needles inside blocks and on
  // their borders (left to the serial pass). Both a sphere and a torus, in one mesh.
  const TriMesh needles =
      renumbered_by_first_use(test::merged(with_needles(test::icosphere(6), 1e-4, 2),
                                           with_needles(test::torus(4.0, 1.0, 120, 40), 1e-3, 3)));
  ASSERT_GT(needles.vertex_count(), 50000U);
  test::expect_closed_surface(needles, 2, 2);
  TriMesh reference = needles;
  NeedleCleanupStats ref_st;
  const Context serial(1);
  clean_needles(reference, {}, &ref_st, &serial);
  test::expect_closed_surface(reference, 2, 2);
  EXPECT_GT(ref_st.collapsed_edges, 0U);
  EXPECT_LT(ref_st.min_angle_before, 0.1);
  EXPECT_GT(ref_st.min_angle_after, 10.0) << "every planted needle is removable";
  for (const int threads : {2, 3, 8, 0}) {
    SCOPED_TRACE(testing::Message() << "threads " << threads);
    TriMesh m = needles;
    NeedleCleanupStats st;
    const Context ctx(threads);
    clean_needles(m, {}, &st, &ctx);
    EXPECT_EQ(m.positions, reference.positions);
    EXPECT_EQ(m.triangles, reference.triangles);
    EXPECT_EQ(st.collapsed_edges, ref_st.collapsed_edges);
    EXPECT_EQ(st.flipped_edges, ref_st.flipped_edges);
    EXPECT_EQ(st.removed_triangles, ref_st.removed_triangles);
    EXPECT_EQ(st.min_angle_after, ref_st.min_angle_after);
    EXPECT_EQ(st.median_angle_after, ref_st.median_angle_after);
  }
}

TEST(NeedleCleanup, AngleSummaryMatchesCheckMesh) {
  // Odd and even corner counts (the median of an even count is the mean of the middle two),
  // needles, and a regular mesh with many equal angles.
  for (const TriMesh& m : {with_needles(test::icosphere(4), 1e-5, 3), test::torus(2.0, 0.6, 41, 17),
                           test::torus(2.0, 0.6, 40, 16), test::unit_cube()}) {
    const MeshReport r = check_mesh(m);
    const AngleSummary s = angle_summary(m);
    const Context serial(1);
    const AngleSummary one = angle_summary(m, &serial);
    EXPECT_NEAR(s.min_deg, r.min_angle_deg, 1e-12 * std::max(1.0, r.min_angle_deg));
    EXPECT_NEAR(s.median_deg, r.median_angle_deg, 1e-12 * r.median_angle_deg);
    EXPECT_EQ(one.min_deg, s.min_deg);
    EXPECT_EQ(one.median_deg, s.median_deg);
  }
  EXPECT_EQ(angle_summary(TriMesh{}).median_deg, 0.0);
}

TEST(NeedleCleanup, NormalsFollowTheirVertices) {
  TriMesh m = with_needles(test::icosphere(3), 1e-4, 2);
  for (const Vec3& p : m.positions) m.normals.push_back(p.normalized());
  clean_needles(m);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    EXPECT_EQ(m.normals[v], m.positions[v].normalized()) << "vertex " << v;
  }
}

TEST(NeedleCleanup, CancelledContextThrowsBeforeChanging) {
  const TriMesh needles = with_needles(test::icosphere(2), 1e-4, 2);
  TriMesh m = needles;
  Context ctx;
  ctx.cancel();
  EXPECT_THROW(clean_needles(m, {}, nullptr, &ctx), Cancelled);
  EXPECT_EQ(m.positions, needles.positions);
  EXPECT_EQ(m.triangles, needles.triangles);
}

TEST(NeedleCleanup, BadOptionsThrow) {
  TriMesh m = test::icosphere(1);
  for (const auto& set : {+[](NeedleCleanupOptions& o) { o.min_angle_deg = 0; },
                          +[](NeedleCleanupOptions& o) { o.min_angle_deg = 60; },
                          +[](NeedleCleanupOptions& o) { o.max_normal_turn_deg = 0; },
                          +[](NeedleCleanupOptions& o) { o.max_edge_ratio = 1; },
                          +[](NeedleCleanupOptions& o) { o.passes = 0; }}) {
    NeedleCleanupOptions o;
    set(o);
    EXPECT_THROW(clean_needles(m, o), InvalidArgument);
  }
}

// Needles on small bumps: every 4th triangle of a sphere gets a split point near its first
// corner lifted outward by h, so the split is a flat tent and collapsing the needle's short edge
// removes it. A point inside each tent is inside the mesh before the cleanup; as keep_sides it
// must still be inside after, and without keep_sides most of them fall out (the test can fail).
TEST(NeedleCleanup, KeepSidesPointsStayInside) {
  TriMesh m = test::icosphere(3);
  std::vector<Vec3> inside_tents;
  const std::size_t n = m.triangles.size();
  const double eps = 1e-3;
  for (std::size_t t = 0; t < n; t += 4) {
    const auto [a, b, c] = m.triangles[t];
    const Vec3 pa = m.positions[a], pb = m.positions[b], pc = m.positions[c];
    const Vec3 normal = (pb - pa).cross(pc - pa).normalized();
    const Vec3 base = (1 - 2 * eps) * pa + eps * pb + eps * pc;
    const Vec3 tip = base + 1e-3 * (pb - pa).norm() * normal;
    const auto v = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(tip);
    m.triangles[t] = {a, b, v};
    m.triangles.push_back({b, c, v});
    m.triangles.push_back({c, a, v});
    inside_tents.push_back(0.5 * (base + tip));
  }
  test::expect_closed_surface(m, 1, 2);
  for (const char in : points_inside(m, inside_tents)) ASSERT_EQ(in, 1);

  TriMesh guarded = m;
  NeedleCleanupOptions o;
  o.keep_sides = inside_tents;
  NeedleCleanupStats st;
  clean_needles(guarded, o, &st);
  test::expect_closed_surface(guarded, 1, 2);
  const std::vector<char> kept = points_inside(guarded, inside_tents);
  EXPECT_EQ(std::count(kept.begin(), kept.end(), 1), static_cast<long>(inside_tents.size()));

  TriMesh free = m;
  clean_needles(free);
  test::expect_closed_surface(free, 1, 2);
  const std::vector<char> lost = points_inside(free, inside_tents);
  EXPECT_GT(std::count(lost.begin(), lost.end(), 0), static_cast<long>(inside_tents.size() / 2));
}

}  // namespace
}  // namespace ramiform
