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

#include "mesh/test_meshes.h"
#include "ramiform/core/errors.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/cleanup.h"
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

}  // namespace
}  // namespace ramiform
