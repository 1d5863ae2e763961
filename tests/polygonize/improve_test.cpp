// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Triangle improvement: on a generated tree meshed to a tolerance, no triangle below 1 degree
// and at least 99 % at 10 degrees or more, with the mesh closed, oriented, manifold, in one
// piece, every node inside, no more triangles turned against the surface, and the deviation
// (measured independently) still under the tolerance; identical on any thread count; a
// generated tree whose pinched necks kept a needle below 1 degree before the nudge has none; the
// needles held-out trees kept before the small move, in patches cut from their meshes, are
// mended by it within half the tolerance; a hand-built needle and cap on a sphere are fixed; bad
// options are refused by name.

#include "ramiform/polygonize/improve.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>
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

/// The deviation of `m`, measured with a seed and a count the mesher did not use, and at every
/// vertex.
DeviationReport measured(const TriMesh& m, const Field& f, const Skeleton& s) {
  DeviationOptions o;
  o.samples = 40000;
  o.seed = 987;
  return measure_deviation(m, f, &s, o);
}

/// Triangles whose normal points against the surface's outward normal (-grad f) at their
/// centroid: folds.
std::size_t inverted(const TriMesh& m, const Field& f) {
  std::vector<Vec3> c;
  for (const auto& t : m.triangles) {
    c.push_back((m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0);
  }
  std::vector<double> v(c.size());
  std::vector<Vec3> g(c.size());
  f.evaluate(c, v, g);
  std::size_t n = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto& t = m.triangles[i];
    const Vec3 normal =
        (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    n += normal.dot(-g[i]) < 0 ? 1 : 0;
  }
  return n;
}

double largest_surface_distance(const TriMesh& m, const Field& f) {
  double worst = 0;
  for (const Vec3& p : m.positions) {
    worst = std::max(worst, std::abs(f.value(p) - f.iso()) / f.gradient(p).norm());
  }
  return worst;
}

// A tree's mesh after the improvement: closed, oriented and 2-manifold, in one piece, every
// skeleton node inside, no triangle below 1 degree and fewer than 1 % below 10. Returns its report.
MeshReport expect_whole_with_good_angles(const TriMesh& m, const Skeleton& s) {
  const MeshReport r = test::expect_closed_manifold(m);
  test::expect_components(m, 1);
  EXPECT_EQ(test::nodes_outside(m, s), 0u);
  EXPECT_EQ(r.triangles_below_1_deg, 0u) << test::describe(r);
  EXPECT_LT(r.triangles_below_10_deg, r.triangles / 100);
  return r;
}

TEST(ImproveTriangles, TreeMeshedToAToleranceMeetsTheAngleTargets) {
  const Skeleton s = test::twig_tree(150);  // 280 k triangles
  const FieldPtr f = make_skeleton_field(s);
  ToleranceOptions off;
  off.improve.max_rounds = 0;
  ToleranceStats st_off;
  const TriMesh before = polygonize_to_tolerance(*f, s, off, nullptr, &st_off);
  const MeshReport r0 = check_mesh(before);
  ToleranceOptions on;
  ToleranceStats st;
  const TriMesh m = polygonize_to_tolerance(*f, s, on, nullptr, &st);
  // The base mesh and its refinement have bad triangles; the pass leaves none below 1 degree
  // and fewer than 1 % below 10.
  ASSERT_GT(r0.triangles_below_10_deg, 100u);
  const MeshReport r = expect_whole_with_good_angles(m, s);
  EXPECT_LT(r.triangles_below_10_deg, r0.triangles_below_10_deg / 5);
  EXPECT_GT(r.min_angle_deg, 1.0);
  // The stats say so, and what was done.
  EXPECT_EQ(st.improve.below_10_deg_after, r.triangles_below_10_deg);
  EXPECT_EQ(st.improve.below_1_deg_after, r.triangles_below_1_deg);
  EXPECT_EQ(st.improve.triangles_after, m.triangles.size());
  EXPECT_GT(st.improve.flips, 0u);
  EXPECT_GT(st.improve.collapses, 0u);
  EXPECT_EQ(st_off.improve.flips + st_off.improve.collapses + st_off.improve.relaxed, 0u);
  // No new folds, the vertices on the surface, the deviation under the tolerance and not
  // worse than without the pass (the largest over the vertices, each measured, and 40,000
  // points: the points' maximum alone varies by a quarter from one sample to the next).
  EXPECT_LE(inverted(m, *f), inverted(before, *f));
  EXPECT_LE(largest_surface_distance(m, *f), largest_surface_distance(before, *f));
  const DeviationReport d = measured(m, *f, s), d0 = measured(before, *f, s);
  EXPECT_EQ(d.samples.unresolved, 0u);
  EXPECT_LE(d.samples.p99, on.tolerance);
  // p99 within 3 % of it (on this tree 0.0408 against 0.0400: 40,000 points resolve p99 to
  // about that).
  EXPECT_LE(d.samples.p99, 1.03 * d0.samples.p99);
  EXPECT_LE(std::max(d.samples.max, d.vertices.max), std::max(d0.samples.max, d0.vertices.max));
  EXPECT_LE(st.deviation.samples.p99, on.tolerance);
  EXPECT_TRUE(st.reached);
}

TEST(ImproveTriangles, SameMeshOnAnyThreadCount) {
  const Skeleton s = test::twig_tree(60);
  const FieldPtr f = make_skeleton_field(s);
  ToleranceOptions off;
  off.improve.max_rounds = 0;
  const TriMesh base = polygonize_to_tolerance(*f, s, off);
  TriMesh a = base, b = base;
  Context one(1), two(2);
  ImproveStats sa, sb;
  improve_triangles(a, *f, s, {}, &one, &sa);
  improve_triangles(b, *f, s, {}, &two, &sb);
  ASSERT_GT(sa.flips + sa.collapses + sa.relaxed, 0u);
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    ASSERT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;
  }
  EXPECT_EQ(sa.flips, sb.flips);
  EXPECT_EQ(sa.collapses, sb.collapses);
  EXPECT_EQ(sa.relaxed, sb.relaxed);
}

TEST(ImproveTriangles, NoNeedleStaysOnAPinchedNeck) {
  // The tree of `ramiform generate --segments 200 --tip-radius 0.004 --trunk-length 1 --seed
  // 5` (347 k triangles, 25 needles below 1 degree before the improvement). Seed 4 was the
  // fixture of the nudge: one needle of 0.77 degrees whose short edge lay on a cycle of three
  // edges that is no triangle (no collapse keeps the mesh 2-manifold there) and every larger
  // move of its corners turned a triangle against the gradient; since the crotch points its
  // base mesh has no needle below 1 degree at all.
  BranchingTreeOptions g;
  g.segments = 200;
  g.tip_radius = 0.004;
  g.trunk_length = 1;
  g.seed = 5;
  const Skeleton s = branching_tree(g);
  const FieldPtr f = make_skeleton_field(s);
  ToleranceOptions o;
  ToleranceStats st;
  const TriMesh m = polygonize_to_tolerance(*f, s, o, nullptr, &st);
  ASSERT_GT(st.improve.below_1_deg_before, 0u);
  const MeshReport r = expect_whole_with_good_angles(m, s);
  EXPECT_GT(r.min_angle_deg, 1.0);
  EXPECT_EQ(st.improve.below_1_deg_after, 0u);
  const DeviationReport d = measured(m, *f, s);
  EXPECT_EQ(d.samples.unresolved, 0u);
  EXPECT_LE(d.samples.p99, o.tolerance);
}

/// A patch of a held-out tree's mesh at the default tolerance (`ramiform generate --segments
/// `segments` --seed `seed``): a needle below 1 degree that no flip, relaxation, collapse or nudge
/// mended (`needles` of them), with the two rings of triangles around its corners (all that those
/// moves read). The small move mends it: afterwards no triangle is below 1 degree, the patch keeps
/// its boundary and stays oriented and manifold, no triangle turns against the surface that did not
/// before, and every vertex lies where one was, or within half the tolerance (in local radii) of
/// one that is gone; the same on one and two threads.
void expect_small_move_mends(std::size_t segments, std::uint64_t seed, const TriMesh& patch,
                             std::size_t needles) {
  BranchingTreeOptions g;
  g.segments = segments;
  g.seed = seed;
  const Skeleton s = branching_tree(g);
  const FieldPtr f = make_skeleton_field(s);
  const MeshReport r0 = check_mesh(patch);
  ASSERT_EQ(r0.triangles_below_1_deg, needles) << test::describe(r0);
  ASSERT_TRUE(r0.oriented && r0.manifold);
  TriMesh m = patch, m2 = patch;
  Context one(1), two(2);
  ImproveOptions o;
  ImproveStats st;
  improve_triangles(m, *f, s, o, &one, &st);
  improve_triangles(m2, *f, s, o, &two);
  EXPECT_EQ(m.triangles, m2.triangles);
  EXPECT_EQ(m.positions, m2.positions);
  const MeshReport r = check_mesh(m);
  EXPECT_EQ(r.triangles_below_1_deg, 0u) << test::describe(r);
  EXPECT_GT(r.min_angle_deg, 1.0);
  EXPECT_EQ(st.below_1_deg_before, needles);
  EXPECT_EQ(st.below_1_deg_after, 0u);
  EXPECT_TRUE(r.oriented && r.manifold);
  EXPECT_EQ(r.boundary_edges, r0.boundary_edges);
  EXPECT_LE(inverted(m, *f), inverted(patch, *f));
  // The boundary, by positions.
  auto boundary = [](const TriMesh& t) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& f3 : t.triangles) {
      for (int k = 0; k < 3; ++k) ++directed[{f3[k], f3[(k + 1) % 3]}];
    }
    std::vector<std::array<double, 6>> out;
    for (const auto& [e, n] : directed) {
      if (directed.count({e.second, e.first}) != 0) continue;
      const Vec3 &a = t.positions[e.first], &b = t.positions[e.second];
      out.push_back({a.x(), a.y(), a.z(), b.x(), b.y(), b.z()});
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(boundary(m), boundary(patch));
  // Vertices: kept, or new within half the tolerance of a vertex that is gone (and each vertex
  // that is gone within it of a new one).
  const std::vector<double> radii = local_radii(s, patch.positions);
  auto nearest = [&](const Vec3& p, const std::vector<Vec3>& among) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& q : among) best = std::min(best, (q - p).norm());
    return best;
  };
  std::vector<Vec3> fresh, gone;
  for (const Vec3& p : m.positions) {
    if (std::find(patch.positions.begin(), patch.positions.end(), p) == patch.positions.end()) {
      fresh.push_back(p);
    }
  }
  for (std::size_t i = 0; i < patch.positions.size(); ++i) {
    const Vec3& p = patch.positions[i];
    if (std::find(m.positions.begin(), m.positions.end(), p) != m.positions.end()) continue;
    gone.push_back(p);
    EXPECT_LE(nearest(p, fresh.empty() ? m.positions : fresh),
              0.5 * o.tolerance * radii[i] * (1 + 1e-9))
        << "vertex " << i;
  }
  ASSERT_FALSE(gone.empty());
  for (const Vec3& p : fresh) {
    const std::vector<double> rp = local_radii(s, std::vector<Vec3>{p});
    EXPECT_LE(nearest(p, gone), 0.5 * o.tolerance * rp[0] * (1 + 1e-9));
  }
}

TEST(ImproveTriangles, SmallMoveMendsANeedleOnAHandle) {
  // Its short edge (4.5e-4 against 0.04) lies on a cycle of three edges that is no triangle (a
  // handle of the mesh: no collapse keeps it 2-manifold), and its far corner was left by
  // refinement 0.32 radii off the surface: every nudge put an edge a hundredth of a radius
  // farther from the surface than the edges it replaced (first-order distances 0.763 against
  // 0.755). The small move takes a corner of the short edge aside by a fortieth of a radius.
  TriMesh patch;
  patch.positions = {
      {0x1.9018956f3e408p-1, -0x1.df28b94371f54p+2, 0x1.303401afbba38p+2},
      {0x1.8e8785c45bb49p-1, -0x1.e0d3d5bc1b7b2p+2, 0x1.2e43b1a13f58ap+2},
      {0x1.8c66cb60bbd15p-1, -0x1.df67beae6d051p+2, 0x1.2eb9079800065p+2},
      {0x1.87d7e8f471c0fp-1, -0x1.defd093d2227fp+2, 0x1.30497bb0a7c34p+2},
      {0x1.90d970ddbbcc7p-1, -0x1.e0bf5fce07abep+2, 0x1.2d7b9a43fa684p+2},
      {0x1.8c81256b7cd3dp-1, -0x1.dd9fdbd31dfb1p+2, 0x1.2dc714594395cp+2},
      {0x1.a3f28bc174117p-1, -0x1.de263a3707e55p+2, 0x1.3209480280885p+2},
      {0x1.9c1c68a1e8d89p-1, -0x1.df1446429366cp+2, 0x1.32a3c35490901p+2},
      {0x1.9deeaf6b23c5p-1, -0x1.de6c586546d66p+2, 0x1.31f075f89b96fp+2},
      {0x1.b02780a8322fep-1, -0x1.df221e2c56942p+2, 0x1.334f626bef824p+2},
      {0x1.92b6f86afacfap-1, -0x1.debf281374d48p+2, 0x1.31e8decc727a5p+2},
      {0x1.925981b982f7dp-1, -0x1.de8f7408ee803p+2, 0x1.31315b356d2d8p+2},
      {0x1.8c679a7262651p-1, -0x1.de9abd7b69895p+2, 0x1.31286bbdd0517p+2},
      {0x1.9265704792deap-1, -0x1.deacf1a058244p+2, 0x1.31c39be2b61dep+2},
      {0x1.8ad5c6acbda4ap-1, -0x1.df98be2850aeap+2, 0x1.303a05a28a23dp+2},
      {0x1.89ebe90c57fc1p-1, -0x1.e13f4381d1eb6p+2, 0x1.2f0e0938891ffp+2},
      {0x1.8b4aecef168ap-1, -0x1.defc62fb3fc43p+2, 0x1.30afba5709686p+2},
      {0x1.879064f128078p-1, -0x1.dfddd5498244dp+2, 0x1.2fa78e82c6468p+2},
      {0x1.8a42afd8ea1fbp-1, -0x1.e1500aa17933dp+2, 0x1.2f0187967dd94p+2},
      {0x1.88abbb6b21151p-1, -0x1.e1575adf468c3p+2, 0x1.2f30650047b01p+2},
      {0x1.87c03cc479e51p-1, -0x1.e00fae3e0253fp+2, 0x1.2f8f3ef4cd0cfp+2},
      {0x1.89d977f8dc6f9p-1, -0x1.e138fd2f3e972p+2, 0x1.2f10fca40cfdp+2},
      {0x1.8e41218cbac85p-1, -0x1.df6dc63457328p+2, 0x1.30c45d4d693fp+2},
      {0x1.87e2a4a6dcc97p-1, -0x1.df06a61a0ffdp+2, 0x1.303681bfa696dp+2},
      {0x1.9024496dec9cdp-1, -0x1.e18366675d25p+2, 0x1.2e0534b351576p+2},
      {0x1.922b3c9f4b8a7p-1, -0x1.e1119574dba87p+2, 0x1.2d10b0a0481bap+2},
      {0x1.964ec36c38452p-1, -0x1.e283006ea04ebp+2, 0x1.2bb4668b6f8e4p+2},
      {0x1.96b62309060abp-1, -0x1.e5fb5e496c53ep+2, 0x1.2d892427a89c8p+2},
      {0x1.98ea5f4e7575dp-1, -0x1.e42d2c4c95f4fp+2, 0x1.2cbe506a16219p+2},
      {0x1.a0b36ca1b07bap-1, -0x1.e01b38ae1301bp+2, 0x1.3477b4818bb8cp+2},
      {0x1.94e74f8aefa43p-1, -0x1.df775a375d361p+2, 0x1.33a18614cfa74p+2},
      {0x1.8b509cb8acb51p-1, -0x1.df1d7daf207f8p+2, 0x1.33d83fe73b175p+2},
      {0x1.8c778d7709a7dp-1, -0x1.df88804c63236p+2, 0x1.311eef3bcd445p+2},
      {0x1.81327764a4c9bp-1, -0x1.e13eed4b6a3bep+2, 0x1.2fcf8a2be7809p+2},
      {0x1.8029495c88474p-1, -0x1.e0ad35a9b18cbp+2, 0x1.300db7b495c93p+2},
      {0x1.8ae05b79792aep-1, -0x1.df96ebe3293aap+2, 0x1.304bc693dc29p+2},
      {0x1.789363a39b626p-1, -0x1.e221d0be3a9dap+2, 0x1.2f4a521632f5ap+2},
      {0x1.7992a598ada63p-1, -0x1.e2de3b68f4bb2p+2, 0x1.2f84cb0a5280ep+2},
      {0x1.be2d94b857d7cp-1, -0x1.e09cab4fef76ap+2, 0x1.34f76f35492c6p+2},
      {0x1.8380fc690b159p-1, -0x1.e2ca93baffca7p+2, 0x1.2f50b68aad819p+2},
      {0x1.8ab95167e32bp-1, -0x1.e51c5879462bep+2, 0x1.2e8ab11cfbdf2p+2},
  };
  patch.triangles = {
      {0, 1, 2},    {3, 1, 0},    {4, 5, 1},    {2, 1, 5},    {6, 7, 8},    {9, 7, 6},
      {8, 10, 11},  {10, 12, 11}, {13, 14, 7},  {14, 15, 7},  {14, 13, 16}, {14, 17, 18},
      {17, 14, 16}, {18, 19, 14}, {3, 20, 1},   {20, 21, 1},  {21, 15, 1},  {22, 21, 23},
      {10, 7, 22},  {10, 22, 23}, {21, 22, 15}, {22, 7, 15},  {7, 10, 8},   {1, 24, 4},
      {24, 25, 4},  {25, 24, 26}, {27, 28, 24}, {28, 26, 24}, {1, 15, 24},  {15, 19, 24},
      {7, 29, 30},  {12, 10, 31}, {18, 17, 32}, {7, 30, 32},  {13, 7, 32},  {20, 33, 19},
      {34, 20, 3},  {20, 34, 33}, {35, 18, 32}, {30, 10, 32}, {10, 35, 32}, {35, 10, 23},
      {21, 18, 35}, {21, 35, 23}, {10, 30, 31}, {33, 36, 19}, {21, 20, 19}, {19, 36, 37},
      {21, 19, 18}, {7, 9, 38},   {38, 29, 7},  {39, 19, 37}, {19, 15, 14}, {19, 27, 24},
      {27, 19, 40}, {19, 39, 40},
  };
  expect_small_move_mends(1500, 2, patch, 1);
}

TEST(ImproveTriangles, SmallMoveMendsANeedleFarFromTheSurface) {
  // Two needles (0.55 and 0.60 degrees) on one short edge (3.5e-4) that joins two vertices 5.8
  // radii off the surface by the first-order measure, where the gradient nearly vanishes (|grad
  // f| 2.9 against 20-50 around): each collapse turned a triangle against the gradient or put an
  // edge 0.013 radii farther than the edges it replaced. The small move collapses the short edge
  // into one end.
  TriMesh patch;
  patch.positions = {
      {0x1.b495b1ceb1831p-1, -0x1.d18105f00e5dap+2, 0x1.09c0925f0a7fbp+3},
      {0x1.aeb3fe1e4837ap-1, -0x1.d286290bc5243p+2, 0x1.093048bbc55eap+3},
      {0x1.ac511b69eaf24p-1, -0x1.d1f244c3f4ffap+2, 0x1.08e1d772936a5p+3},
      {0x1.a5266cca357cap-1, -0x1.d369f3a104a56p+2, 0x1.08ca8a201eabap+3},
      {0x1.a337e79fdee8bp-1, -0x1.d1ff5c03c0ad7p+2, 0x1.0869d63e07c18p+3},
      {0x1.943942f51eap-1, -0x1.d528c610322d5p+2, 0x1.08cd5d7d7f85ap+3},
      {0x1.96de416ac49f4p-1, -0x1.d291073c64773p+2, 0x1.083f0dd4e82f8p+3},
      {0x1.bd9b448e5f8f2p-1, -0x1.d0dc6d76b9cdap+2, 0x1.080c99c58a9a2p+3},
      {0x1.ac28a360a4d76p-1, -0x1.d0b56c82e58b9p+2, 0x1.089ee9c46dbffp+3},
      {0x1.bdf53ff2a22p-1, -0x1.d1d6d64188612p+2, 0x1.08295b72686c8p+3},
      {0x1.cfefa932a2d1bp-1, -0x1.d2fa053632265p+2, 0x1.07b77988ea15p+3},
      {0x1.ced5f4b871b8ep-1, -0x1.d1f881eddfddcp+2, 0x1.07ab932179336p+3},
      {0x1.ad89acc80c3bep-1, -0x1.d0e9658c4bcd6p+2, 0x1.08c476ec612b9p+3},
      {0x1.b18688f0f9ec2p-1, -0x1.d04497db7f3d2p+2, 0x1.090aad8b02291p+3},
      {0x1.ad5fb0eb65fbcp-1, -0x1.d07e161b15925p+2, 0x1.08abe2e74d3cbp+3},
      {0x1.abc98c6e94ef5p-1, -0x1.d0ab6f490e151p+2, 0x1.089613f9d482bp+3},
      {0x1.b6f803de2a9dap-1, -0x1.d0fcc43bab776p+2, 0x1.07cf929fb4dd7p+3},
      {0x1.cf3bb26a1daffp-1, -0x1.d10533a094ff5p+2, 0x1.077df62f2e702p+3},
      {0x1.c1f53109b3cdp-1, -0x1.d145e12a7852bp+2, 0x1.0703e7e382f6dp+3},
      {0x1.a51413cd22b35p-1, -0x1.ce60247a0f4f1p+2, 0x1.07bf08c85f041p+3},
      {0x1.ab131e8a7d9d9p-1, -0x1.cfdfb94844e56p+2, 0x1.08612149b5971p+3},
      {0x1.a7e68560c20d5p-1, -0x1.d031e881f3668p+2, 0x1.08402f0dde40ap+3},
      {0x1.c5043b3776a5p-1, -0x1.d0e07cfce2523p+2, 0x1.06f2f39d0153p+3},
      {0x1.c178fab5ccaf9p-1, -0x1.d0e41f3494641p+2, 0x1.06ca3b125f1f9p+3},
      {0x1.b5d1a9e2974d6p-1, -0x1.d1ca450c26b6bp+2, 0x1.07c8d2a6c9718p+3},
      {0x1.c0edfe8243d57p-1, -0x1.d212a6a4c6c26p+2, 0x1.06ff3b54b27c8p+3},
      {0x1.b5f0d156baa62p-1, -0x1.d1c989b5f9e7p+2, 0x1.07cae610e4632p+3},
      {0x1.abbc87ca5abcep-1, -0x1.d0b51df9383b5p+2, 0x1.08971687b0e0cp+3},
      {0x1.bfe6cbfad3ddep-1, -0x1.d2df6c1f15321p+2, 0x1.06fa8ec5e2024p+3},
      {0x1.c37d7166acadap-1, -0x1.d35c273b8d57dp+2, 0x1.06f59fb4b9cf8p+3},
      {0x1.c08b2ffc809a7p-1, -0x1.d35a7f74098cfp+2, 0x1.06cf6da9fd20fp+3},
      {0x1.cb8dff0195ba7p-1, -0x1.d3697855fecddp+2, 0x1.0753b14ca446fp+3},
      {0x1.be86ee0fd842bp-1, -0x1.d101475d0cadap+2, 0x1.06b794e07b804p+3},
      {0x1.bfcbe381b502p-1, -0x1.d38af7bd8d5ep+2, 0x1.06a45865ebffap+3},
      {0x1.bcdb1c78b4c2ap-1, -0x1.d38136aa1c1b9p+2, 0x1.0683a0b1d8efbp+3},
      {0x1.bcb9bc84f49b4p-1, -0x1.d0e0323e66048p+2, 0x1.068b6984e521bp+3},
      {0x1.b9cb50380940cp-1, -0x1.d1ed168744157p+2, 0x1.06bfddc8649abp+3},
      {0x1.b9e8840f4014dp-1, -0x1.d28a18479ce44p+2, 0x1.06bc7e0310062p+3},
      {0x1.9ce2debcb10adp-1, -0x1.d0e5e2cffff07p+2, 0x1.07fc80a4f8d78p+3},
      {0x1.8ce4ff89000f2p-1, -0x1.d1f671f2077d9p+2, 0x1.081192958a3f3p+3},
      {0x1.b88f060c77a2bp-1, -0x1.d15993d549d36p+2, 0x1.06910f440d3f7p+3},
      {0x1.b55febc09f36ep-1, -0x1.d1ec4bf95b0bep+2, 0x1.0683e6d81fb14p+3},
  };
  patch.triangles = {
      {0, 1, 2},    {1, 3, 2},    {3, 4, 2},    {5, 4, 3},    {6, 4, 5},    {7, 8, 9},
      {9, 10, 11},  {7, 9, 11},   {0, 12, 13},  {12, 8, 14},  {15, 8, 16},  {16, 8, 7},
      {17, 18, 7},  {18, 16, 7},  {19, 20, 21}, {13, 12, 14}, {15, 21, 20}, {14, 8, 15},
      {22, 18, 17}, {18, 22, 23}, {24, 25, 26}, {8, 27, 26},  {27, 24, 26}, {9, 8, 26},
      {28, 10, 9},  {28, 9, 26},  {0, 2, 12},   {2, 4, 27},   {2, 27, 12},  {12, 27, 8},
      {29, 28, 30}, {10, 28, 31}, {28, 29, 31}, {18, 25, 16}, {25, 28, 26}, {24, 27, 16},
      {25, 24, 16}, {27, 21, 16}, {21, 15, 16}, {27, 4, 21},  {23, 32, 18}, {33, 28, 34},
      {30, 28, 33}, {35, 36, 32}, {34, 28, 37}, {28, 25, 36}, {25, 18, 36}, {37, 28, 36},
      {18, 32, 36}, {19, 21, 38}, {4, 39, 38},  {4, 6, 39},   {38, 21, 4},  {35, 40, 36},
      {40, 41, 36}, {41, 37, 36},
  };
  expect_small_move_mends(3000, 3, patch, 2);
}

/// An icosphere (the icosahedron split 1:4 `levels` times) on the surface of `f` around the
/// origin.
TriMesh icosphere(const Field& f, double radius, int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  TriMesh m;
  m.positions = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.positions.push_back(0.5 * (m.positions[a] + m.positions[b]));
      return mid[key] = static_cast<std::uint32_t>(m.positions.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& t : m.triangles) {
      const std::uint32_t ab = middle(t[0], t[1]), bc = middle(t[1], t[2]), ca = middle(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  for (Vec3& p : m.positions) p = distance_to_surface(f, radius * p.normalized(), radius).foot;
  return m;
}

TEST(ImproveTriangles, FixesAHandBuiltNeedleAndCap) {
  constexpr double kRadius = 1.0;
  const FieldPtr f = make_point_field(Vec3::Zero(), kRadius);
  Skeleton s;
  s.nodes.push_back({Vec3::Zero(), kRadius});
  const TriMesh sphere = icosphere(*f, kRadius, 2);
  const MeshReport clean = check_mesh(sphere);
  ASSERT_GT(clean.min_angle_deg, 40.0);
  // A needle: the first edge a -> b of triangle 0 split a thousandth of its length from a (on
  // the surface). Its two triangles on a are needles.
  TriMesh m = sphere;
  auto surface_point = [&](const Vec3& p) { return distance_to_surface(*f, p, kRadius).foot; };
  auto find = [&](std::uint32_t a, std::uint32_t b) {  // the triangle with the edge a -> b
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        if (m.triangles[t][k] == a && m.triangles[t][(k + 1) % 3] == b) return t;
      }
    }
    ADD_FAILURE() << "no edge " << a << " -> " << b;
    return std::size_t{0};
  };
  {
    const std::uint32_t a = m.triangles[0][0], b = m.triangles[0][1];
    const auto p = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(surface_point(m.positions[a] + 1e-3 * (m.positions[b] - m.positions[a])));
    const std::size_t t1 = find(a, b), t2 = find(b, a);
    auto third = [&](std::size_t t) {
      for (const std::uint32_t w : m.triangles[t]) {
        if (w != a && w != b) return w;
      }
      return a;
    };
    const std::uint32_t c = third(t1), d = third(t2);
    m.triangles[t1] = {a, p, c};
    m.triangles[t2] = {p, a, d};
    m.triangles.push_back({p, b, c});
    m.triangles.push_back({b, p, d});
  }
  // A cap: a triangle (a, b, c) far from the needle split 1:3 at the surface point above the
  // middle of its edge a - b pulled 2 % towards c; the triangle (a, b, q) has an angle near 180.
  {
    const std::size_t t = m.triangles.size() / 2;
    const auto [a, b, c] = m.triangles[t];
    const Vec3 mid = 0.5 * (m.positions[a] + m.positions[b]);
    const auto q = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back(surface_point(mid + 0.02 * (m.positions[c] - mid)));
    m.triangles[t] = {a, b, q};
    m.triangles.push_back({b, c, q});
    m.triangles.push_back({c, a, q});
  }
  const MeshReport bad = check_mesh(m);
  ASSERT_TRUE(bad.watertight && bad.oriented && bad.manifold);
  ASSERT_EQ(bad.triangles_below_10_deg, 3u);  // two needles and the cap
  ASSERT_EQ(bad.triangles_below_1_deg, 2u);   // the needles
  ImproveOptions o;
  ImproveStats st;
  improve_triangles(m, *f, s, o, nullptr, &st);
  const MeshReport r = test::expect_closed_manifold(m);
  test::expect_closed_surface(m, 1, 2);
  EXPECT_EQ(r.triangles_below_10_deg, 0u) << test::describe(r);
  EXPECT_GT(r.min_angle_deg, 20.0);
  EXPECT_EQ(st.below_10_deg_before, 3u);
  EXPECT_EQ(st.below_1_deg_before, 2u);
  EXPECT_EQ(st.below_10_deg_after, 0u);
  EXPECT_GE(st.flips, 1u);                   // the cap's long edge
  EXPECT_GE(st.collapses + st.relaxed, 1u);  // the needles' short edge
  EXPECT_EQ(st.triangles_before, sphere.triangles.size() + 4);
  EXPECT_EQ(st.triangles_after, m.triangles.size());
  EXPECT_EQ(test::nodes_outside(m, s), 0u);
  EXPECT_LT(largest_surface_distance(m, *f), 1e-6 * kRadius);
  // Every triangle faces outwards.
  EXPECT_EQ(inverted(m, *f), 0u);
  // A mesh without bad triangles is left exactly as it is.
  TriMesh same = sphere;
  improve_triangles(same, *f, s, o, nullptr, &st);
  EXPECT_EQ(same.triangles, sphere.triangles);
  EXPECT_EQ(same.positions, sphere.positions);
  EXPECT_EQ(st.flips + st.collapses + st.relaxed, 0u);
  EXPECT_EQ(st.rounds, 0);
}

TEST(ImproveTriangles, CollapsesRootsThatLandedOnOnePoint) {
  // A vertex of the sphere replaced by three within 1e-4 radii of it, joined by a tiny triangle
  // and sharing its fan (the needle cluster of several roots on one lattice point).
  constexpr double kRadius = 1.0;
  const FieldPtr f = make_point_field(Vec3::Zero(), kRadius);
  Skeleton s;
  s.nodes.push_back({Vec3::Zero(), kRadius});
  const TriMesh sphere = icosphere(*f, kRadius, 2);
  TriMesh m = sphere;
  const std::uint32_t v = m.triangles[7][0];
  // v's ring, counter-clockwise: each triangle (v, a, b) gives the edge a -> b.
  std::map<std::uint32_t, std::uint32_t> next;
  std::vector<std::array<std::uint32_t, 3>> kept;
  for (const auto& t : m.triangles) {
    int k = -1;
    for (int i = 0; i < 3; ++i) {
      if (t[i] == v) k = i;
    }
    if (k < 0) {
      kept.push_back(t);
    } else {
      next[t[(k + 1) % 3]] = t[(k + 2) % 3];
    }
  }
  std::vector<std::uint32_t> ring{next.begin()->first};
  while (ring.size() < next.size()) ring.push_back(next[ring.back()]);
  const std::size_t n = ring.size(), k1 = n / 3, k2 = 2 * n / 3;
  std::array<std::uint32_t, 3> c{};
  const std::array<std::size_t, 3> at{0, k1, k2};
  for (int i = 0; i < 3; ++i) {
    c[i] = i == 0 ? v : static_cast<std::uint32_t>(m.positions.size());
    const Vec3 p = m.positions[v] + 1e-4 * (m.positions[ring[at[i]]] - m.positions[v]).normalized();
    const Vec3 q = distance_to_surface(*f, p, kRadius).foot;
    if (i == 0) {
      m.positions[v] = q;
    } else {
      m.positions.push_back(q);
    }
  }
  for (std::size_t j = 0; j < n; ++j) {
    const int owner = j < k1 ? 0 : (j < k2 ? 1 : 2);
    kept.push_back({c[owner], ring[j], ring[(j + 1) % n]});
  }
  kept.push_back({c[0], ring[k1], c[1]});
  kept.push_back({c[1], ring[k2], c[2]});
  kept.push_back({c[2], ring[0], c[0]});
  kept.push_back({c[0], c[1], c[2]});
  m.triangles = kept;
  const MeshReport bad = check_mesh(m);
  ASSERT_TRUE(bad.watertight && bad.oriented && bad.manifold) << test::describe(bad);
  ASSERT_EQ(bad.triangles_below_1_deg, 3u);  // the triangles joining the three
  ImproveStats st;
  improve_triangles(m, *f, s, {}, nullptr, &st);
  const MeshReport r = test::expect_closed_manifold(m);
  test::expect_closed_surface(m, 1, 2);
  EXPECT_EQ(r.triangles_below_10_deg, 0u) << test::describe(r);
  EXPECT_GE(st.collapses, 1u);
  EXPECT_LT(m.triangles.size(), sphere.triangles.size() + 4);  // some of the cluster went
  EXPECT_EQ(test::nodes_outside(m, s), 0u);
  EXPECT_EQ(inverted(m, *f), 0u);
  EXPECT_LT(largest_surface_distance(m, *f), 1e-6 * kRadius);
}

TEST(ImproveTriangles, BadOptionsAreRefusedByName) {
  const FieldPtr f = make_point_field(Vec3::Zero(), 1.0);
  Skeleton s;
  s.nodes.push_back({Vec3::Zero(), 1.0});
  TriMesh m = icosphere(*f, 1.0, 0);
  auto refused = [&](const ImproveOptions& o, const std::string& name) {
    try {
      improve_triangles(m, *f, s, o);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  ImproveOptions o;
  o.tolerance = 0;
  refused(o, "tolerance");
  o = {};
  o.tolerance = std::numeric_limits<double>::infinity();
  refused(o, "tolerance");
  o = {};
  o.min_angle_deg = 60;
  refused(o, "min_angle_deg");
  o = {};
  o.min_angle_deg = 0;
  refused(o, "min_angle_deg");
  o = {};
  o.max_turn_deg = 0;
  refused(o, "max_turn_deg");
  o = {};
  o.max_turn_deg = 91;
  refused(o, "max_turn_deg");
  o = {};
  o.max_rounds = -1;
  refused(o, "max_rounds");
  EXPECT_THROW(improve_triangles(m, *f, Skeleton{}), InvalidArgument);
  TriMesh broken = m;
  broken.triangles[3][1] = 99;
  EXPECT_THROW(improve_triangles(broken, *f, s), InvalidArgument);
  // Through polygonize_to_tolerance, before any meshing.
  ToleranceOptions t;
  t.improve.min_angle_deg = -1;
  EXPECT_THROW((void)polygonize_to_tolerance(*f, s, t), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
