// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Curved skeleton edges (Skeleton::curves, Rigaudière et al. §3.3): validation, the control
// polygon of an edge, and straighten_curves against de Casteljau and dense sampling.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Independent de Casteljau on points or radii.
template <class T>
T casteljau(std::vector<T> w, double t) {
  for (std::size_t level = w.size() - 1; level > 0; --level) {
    for (std::size_t i = 0; i < level; ++i) w[i] = (1 - t) * w[i] + t * w[i + 1];
  }
  return w[0];
}

// 0 -(curved)- 1 -(straight)- 2 -(curved, with radii)- 3, and node 4 joined straight to 0.
Skeleton curved() {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 0.5},
             {Vec3(4, 0, 0), 0.3},
             {Vec3(4, 0, 3), 0.4},
             {Vec3(8, 2, 3), 0.2},
             {Vec3(-2, 0, -1), 0.6}};
  s.edges = {{0, 1}, {1, 2}, {2, 3}, {4, 0}};
  s.curves.resize(4);
  s.curves[0].controls = {Vec3(1, 3, 0), Vec3(3, 3, 1)};
  s.curves[2].controls = {Vec3(5, 3, 4), Vec3(6, -2, 2), Vec3(7, 2, 5)};
  s.curves[2].radii = {0.6, 0.25, 0.35};
  return s;
}

void expect_rejected(const Skeleton& s, const std::vector<std::string>& needles) {
  try {
    validate(s, "sk.json");
    ADD_FAILURE() << "accepted; expected " << needles.front();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& n : needles) {
      EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
    }
  }
}

TEST(CurvedEdges, ValidSkeletonPasses) {
  const Skeleton s = curved();
  EXPECT_NO_THROW(validate(s));
  EXPECT_TRUE(s.has_curves());
  Skeleton straight = s;
  for (auto& c : straight.curves) c = {};
  EXPECT_NO_THROW(validate(straight));
  EXPECT_FALSE(straight.has_curves());
}

TEST(CurvedEdges, ValidateNamesTheEdge) {
  {
    Skeleton s = curved();
    s.curves[2].radii = {0.1, 0.2};  // 3 controls
    expect_rejected(s, {"sk.json", "edge 2", "2 radii for 3 control points"});
  }
  {
    Skeleton s = curved();
    s.curves[0].controls[1] = Vec3(1, kNaN, 0);
    expect_rejected(s, {"edge 0", "control point 1 is not finite"});
    s.curves[0].controls[1] = Vec3(kInf, 0, 0);
    expect_rejected(s, {"edge 0", "control point 1 is not finite"});
    // Finite, but with the nodes the span overflows: the straightened nodes would.
    s.curves[0].controls[1] = Vec3(0, -1e308, 0);
    expect_rejected(
        s, {"sk.json", "edge 0", "control point 1", "span more than double precision can hold"});
  }
  {
    Skeleton s = curved();
    s.curves[2].radii[1] = -0.5;
    expect_rejected(s, {"edge 2", "radius 1 must be finite and > 0", "-0.5"});
    s.curves[2].radii[1] = 0;
    expect_rejected(s, {"edge 2", "radius 1"});
    s.curves[2].radii[1] = kNaN;
    expect_rejected(s, {"edge 2", "radius 1"});
  }
  {
    Skeleton s = curved();
    s.curves.resize(3);
    expect_rejected(s, {"3 edge curves for 4 edges"});
    s.curves.resize(5);
    expect_rejected(s, {"5 edge curves for 4 edges"});
  }
  {
    Skeleton s = curved();
    s.curves[3].controls.assign(15, Vec3(-1, 1, 0));
    expect_rejected(s, {"edge 3", "15 control points", "at most 14"});
    s.curves[3].controls.assign(14, Vec3(-1, 1, 0));  // degree 15: the most allowed
    EXPECT_NO_THROW(validate(s));
  }
  {
    // Radii without controls are radii for 0 control points.
    Skeleton s = curved();
    s.curves[1].radii = {0.3};
    expect_rejected(s, {"edge 1", "1 radii for 0 control points"});
  }
}

TEST(CurvedEdges, EdgeControls) {
  const Skeleton s = curved();
  std::vector<Vec3> p;
  std::vector<double> r;
  // Straight edge: the two nodes.
  edge_controls(s, 1, p, r);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0], s.nodes[1].position);
  EXPECT_EQ(p[1], s.nodes[2].position);
  EXPECT_EQ(r, (std::vector<double>{0.3, 0.4}));
  // Curved edge without radii: the radius runs linearly in the control index.
  edge_controls(s, 0, p, r);
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p[0], s.nodes[0].position);
  EXPECT_EQ(p[1], s.curves[0].controls[0]);
  EXPECT_EQ(p[2], s.curves[0].controls[1]);
  EXPECT_EQ(p[3], s.nodes[1].position);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0], 0.5);
  EXPECT_NEAR(r[1], 0.5 + (0.3 - 0.5) / 3, 1e-15);
  EXPECT_NEAR(r[2], 0.5 + 2 * (0.3 - 0.5) / 3, 1e-15);
  EXPECT_EQ(r[3], 0.3);
  // ... which makes the Bernstein radius linear in t.
  for (double t : {0.1, 0.4, 0.77}) EXPECT_NEAR(casteljau(r, t), 0.5 + t * (0.3 - 0.5), 1e-15);
  // Curved edge with radii.
  edge_controls(s, 2, p, r);
  ASSERT_EQ(p.size(), 5u);
  EXPECT_EQ(p[4], s.nodes[3].position);
  EXPECT_EQ(r, (std::vector<double>{0.4, 0.6, 0.25, 0.35, 0.2}));
  // Edge index out of range.
  EXPECT_THROW(edge_controls(s, 4, p, r), std::out_of_range);
  // Without a curves vector every edge is straight.
  Skeleton plain = s;
  plain.curves.clear();
  edge_controls(plain, 2, p, r);
  EXPECT_EQ(p.size(), 2u);
}

// Distance from p to segment [a, b].
double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// Checks straighten_curves(s, tol) against the curves of s.
void check_straightened(const Skeleton& s, double tol) {
  const Skeleton out = straighten_curves(s, tol);
  ASSERT_NO_THROW(validate(out));
  EXPECT_TRUE(out.curves.empty());
  EXPECT_FALSE(out.has_curves());
  ASSERT_GE(out.nodes.size(), s.nodes.size());
  // Original nodes keep their indices (and everything else).
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    EXPECT_EQ(out.nodes[i].position, s.nodes[i].position);
    EXPECT_EQ(out.nodes[i].radius, s.nodes[i].radius);
  }
  if (!s.node_types.empty()) {
    ASSERT_EQ(out.node_types.size(), out.nodes.size());
    for (std::size_t i = 0; i < s.nodes.size(); ++i) EXPECT_EQ(out.node_types[i], s.node_types[i]);
  }
  if (!s.open_ends.empty()) {
    ASSERT_EQ(out.open_ends.size(), out.nodes.size());
    for (std::size_t i = 0; i < s.nodes.size(); ++i) EXPECT_EQ(out.open_ends[i], s.open_ends[i]);
    for (std::size_t i = s.nodes.size(); i < out.nodes.size(); ++i) EXPECT_EQ(out.open_ends[i], 0);
  }
  // Walk the output edges in order: each input edge becomes one edge (straight) or a chain.
  std::size_t k = 0;
  std::size_t next_new = s.nodes.size();
  std::vector<Vec3> controls;
  std::vector<double> radii;
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    const auto [a, b] = s.edges[e];
    ASSERT_LT(k, out.edges.size());
    if (s.curves.empty() || s.curves[e].controls.empty()) {
      EXPECT_EQ(out.edges[k], s.edges[e]) << "straight edge " << e;
      ++k;
      continue;
    }
    edge_controls(s, e, controls, radii);
    const double r_min = *std::min_element(radii.begin(), radii.end());
    // The chain a -> new nodes (consecutive indices) -> b.
    std::vector<std::uint32_t> chain = {a};
    while (true) {
      ASSERT_LT(k, out.edges.size());
      ASSERT_EQ(out.edges[k][0], chain.back()) << "edge " << e << " chain broken";
      const std::uint32_t to = out.edges[k][1];
      ++k;
      chain.push_back(to);
      if (to == b) break;
      ASSERT_EQ(to, next_new) << "new nodes follow the originals in order";
      ++next_new;
    }
    const std::size_t pieces = chain.size() - 1;
    ASSERT_GE(pieces, 1u);
    ASSERT_LE(pieces, 4096u);
    // New node j lies at t = j / pieces on the curve, with the curve's radius there.
    for (std::size_t j = 1; j < pieces; ++j) {
      const double t = static_cast<double>(j) / static_cast<double>(pieces);
      const SkeletonNode& n = out.nodes[chain[j]];
      EXPECT_LE((n.position - casteljau(controls, t)).norm(), 1e-12 * (1 + n.position.norm()))
          << "edge " << e << " node " << j;
      EXPECT_NEAR(n.radius, casteljau(radii, t), 1e-12) << "edge " << e << " node " << j;
      if (!s.node_types.empty()) {
        EXPECT_EQ(out.node_types[chain[j]], s.node_types[a]);
      }
    }
    // Chord error by dense sampling: every curve point near its piece.
    double worst = 0, worst_radius = 0;
    for (std::size_t j = 0; j < pieces; ++j) {
      const Vec3 pa = out.nodes[chain[j]].position, pb = out.nodes[chain[j + 1]].position;
      const double ra = out.nodes[chain[j]].radius, rb = out.nodes[chain[j + 1]].radius;
      for (int i = 0; i <= 50; ++i) {
        const double f = i / 50.0;
        const double t = (static_cast<double>(j) + f) / static_cast<double>(pieces);
        worst = std::max(worst, segment_distance(casteljau(controls, t), pa, pb));
        worst_radius = std::max(worst_radius, std::abs(casteljau(radii, t) - ((1 - f) * ra + f * rb)));
      }
    }
    EXPECT_LE(worst, tol * r_min * (1 + 1e-9)) << "edge " << e << ", " << pieces << " pieces";
    EXPECT_LE(worst_radius, tol * r_min * (1 + 1e-9)) << "edge " << e;
    // Not absurdly over-refined either: the error bound is within a factor of 30 of the truth.
    if (pieces > 4) {
      EXPECT_GT(std::max(worst, worst_radius), tol * r_min / 30) << "edge " << e;
    }
  }
  EXPECT_EQ(k, out.edges.size());
  EXPECT_EQ(next_new, out.nodes.size());
}

TEST(CurvedEdges, StraightenCurves) {
  const Skeleton s = curved();
  for (double tol : {1.0, 0.1, 0.01, 0.001}) {
    SCOPED_TRACE(tol);
    check_straightened(s, tol);
  }
  // Finer tolerance, more nodes.
  EXPECT_LT(straighten_curves(s, 0.1).nodes.size(), straighten_curves(s, 0.001).nodes.size());
  // Default tolerance is 1 %.
  const Skeleton d = straighten_curves(s);
  const Skeleton p = straighten_curves(s, 0.01);
  EXPECT_EQ(d.nodes.size(), p.nodes.size());
  EXPECT_EQ(d.edges, p.edges);
}

TEST(CurvedEdges, StraightenKeepsTypesAndOpenEnds) {
  Skeleton s = curved();
  s.node_types = {1, 3, 3, 4, 2};
  s.open_ends = {0, 0, 0, 1, 1};
  check_straightened(s, 0.01);
}

TEST(CurvedEdges, StraightenRandomCurves) {
  Rng rng(31);
  for (int trial = 0; trial < 10; ++trial) {
    Skeleton s;
    for (int i = 0; i < 6; ++i) {
      s.nodes.push_back({Vec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5)),
                         rng.uniform(0.05, 0.6)});
    }
    s.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {1, 5}};
    s.curves.resize(s.edges.size());
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
      const int inner = static_cast<int>(rng.below(6));  // 0 (straight) to 5
      for (int k = 0; k < inner; ++k) {
        s.curves[e].controls.push_back(
            Vec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5)));
        if (trial % 2 == 0) s.curves[e].radii.push_back(rng.uniform(0.05, 0.8));
      }
      if (trial % 2 == 0 && inner == 0) s.curves[e].radii.clear();
    }
    ASSERT_NO_THROW(validate(s));
    SCOPED_TRACE(trial);
    check_straightened(s, 0.02);
  }
}

TEST(CurvedEdges, CollinearControlsNeedOnePiece) {
  // Evenly spaced collinear controls: the curve is its chord, one piece (no new node).
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 0.5}, {Vec3(3, 0, 0), 0.5}};
  s.edges = {{0, 1}};
  s.curves = {EdgeCurve{{Vec3(1, 0, 0), Vec3(2, 0, 0)}, {}}};
  const Skeleton out = straighten_curves(s);
  EXPECT_EQ(out.nodes.size(), 2u);
  ASSERT_EQ(out.edges.size(), 1u);
  EXPECT_EQ(out.edges[0], (std::array<std::uint32_t, 2>{0, 1}));
}

TEST(CurvedEdges, WithoutCurvesReturnedEqual) {
  Skeleton s = curved();
  s.curves.clear();
  s.node_types = {1, 2, 3, 4, 5};
  Skeleton out = straighten_curves(s);
  EXPECT_EQ(out.edges, s.edges);
  EXPECT_EQ(out.node_types, s.node_types);
  ASSERT_EQ(out.nodes.size(), s.nodes.size());
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    EXPECT_EQ(out.nodes[i].position, s.nodes[i].position);
    EXPECT_EQ(out.nodes[i].radius, s.nodes[i].radius);
  }
  // A curves vector of straight entries only: same, and the result has no curves.
  s.curves.resize(s.edges.size());
  out = straighten_curves(s);
  EXPECT_EQ(out.edges, s.edges);
  EXPECT_TRUE(out.curves.empty());
}

TEST(CurvedEdges, StraightenRefusesBadTolerance) {
  const Skeleton s = curved();
  for (double tol : {0.0, -0.1, 1.5, kNaN, kInf}) {
    EXPECT_THROW((void)straighten_curves(s, tol), InvalidArgument) << tol;
  }
  EXPECT_NO_THROW((void)straighten_curves(s, 1.0));
}

}  // namespace
}  // namespace ramiform
