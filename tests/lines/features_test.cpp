// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/primitives.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform {
namespace {

ParticleSystem particles_on(const Field& f, std::size_t count) {
  ParticleOptions o;
  o.count = count;
  return spread_particles(f, o);
}

struct Segment {
  Vec3 a, b;
};

double distance_to_segment(const Segment& s, const Vec3& q) {
  const Vec3 ab = s.b - s.a;
  const double t = std::clamp((q - s.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (q - (s.a + t * ab)).norm();
}

// A sharp box: the intersection of six half-spaces, moved by `pose`; its 12 edges.
struct SharpBox {
  FieldPtr field;
  std::vector<Segment> edges;
};

SharpBox sharp_box(const Vec3& half, const Affine3& pose) {
  std::vector<FieldPtr> faces;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {-1, 1}) {
      Vec3 n = Vec3::Zero();
      n[axis] = side;
      faces.push_back(make_plane_field(side * half[axis] * Vec3::Unit(axis), n, 0.5));
    }
  }
  SharpBox box;
  box.field = make_transform(make_intersection(faces), pose);
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, w = (axis + 2) % 3;
    for (int su : {-1, 1}) {
      for (int sw : {-1, 1}) {
        Vec3 a = Vec3::Zero();
        a[u] = su * half[u];
        a[w] = sw * half[w];
        Vec3 b = a;
        a[axis] = -half[axis];
        b[axis] = half[axis];
        box.edges.push_back({pose * a, pose * b});
      }
    }
  }
  return box;
}

// The index of the box edge nearest to q.
std::size_t nearest_edge(const SharpBox& box, const Vec3& q) {
  std::size_t best = 0;
  for (std::size_t e = 1; e < box.edges.size(); ++e)
    if (distance_to_segment(box.edges[e], q) < distance_to_segment(box.edges[best], q)) best = e;
  return best;
}

void check_box(const SharpBox& box, const ParticleSystem& ps, StraddleSource source) {
  SCOPED_TRACE(static_cast<int>(source));
  double dmax = 0;
  for (const SurfaceParticle& p : ps.particles) dmax = std::max(dmax, p.delta);
  LineOptions o;
  o.straddle = source;
  LineStats st;
  const std::vector<Polyline> lines = feature_lines(*box.field, ps, o, &st);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(st.straddle_pairs, st.straddle_pairs_movement + st.straddle_pairs_search);
  if (source == StraddleSource::kSearch) {
    EXPECT_EQ(st.straddle_pairs_movement, 0u);
    EXPECT_GT(st.straddle_pairs_search, 0u);
  } else {
    // The movement test finds the creases on its own: kAuto needs no search.
    EXPECT_GT(st.straddle_pairs_movement, 0u);
    EXPECT_EQ(st.straddle_pairs_search, 0u);
  }
  EXPECT_EQ(st.lines[2], lines.size());
  EXPECT_GT(st.field_evals, 0u);
  // Every point on an edge (and on the surface), steps of about δ, never turning back.
  for (const Polyline& l : lines) {
    EXPECT_EQ(l.kind, LineKind::kFeature);
    EXPECT_FALSE(l.closed);
    for (std::size_t i = 1; i < l.points.size(); ++i) {
      ASSERT_LE((l.points[i] - l.points[i - 1]).norm(), 1.5 * dmax);
      if (i > 1) {
        ASSERT_GT((l.points[i] - l.points[i - 1]).dot(l.points[i - 1] - l.points[i - 2]), 0);
      }
    }
    for (const Vec3& p : l.points) {
      double d = 1e300;
      for (const Segment& e : box.edges) d = std::min(d, distance_to_segment(e, p));
      ASSERT_LE(d, 1e-3 * dmax) << p.transpose();
      const Vec3 g = box.field->gradient(p);
      ASSERT_LE(std::abs(box.field->value(p) - box.field->iso()) / g.norm(), 1e-3 * dmax);
    }
  }
  // Chained: one line per edge, never round a corner (all of a line's points on the edge
  // nearest its middle point), and every edge drawn by exactly one line: 90 % of 200 samples
  // along it within δ of a point of that line, and the samples more than 2 δ from the corners
  // near no other line.
  ASSERT_EQ(lines.size(), box.edges.size());
  std::vector<int> line_of_edge(box.edges.size(), -1);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const std::vector<Vec3>& pts = lines[k].points;
    const std::size_t e = nearest_edge(box, pts[pts.size() / 2]);
    for (const Vec3& p : pts) ASSERT_LE(distance_to_segment(box.edges[e], p), 1e-3 * dmax);
    EXPECT_EQ(line_of_edge[e], -1) << "edge " << e << " drawn twice";
    line_of_edge[e] = static_cast<int>(k);
  }
  for (std::size_t e = 0; e < box.edges.size(); ++e) {
    const Segment& s = box.edges[e];
    ASSERT_GE(line_of_edge[e], 0) << "edge " << e << " not drawn";
    int covered = 0;
    for (int i = 0; i < 200; ++i) {
      const Vec3 q = s.a + (i + 0.5) / 200 * (s.b - s.a);
      const bool inner = (q - s.a).norm() > 2 * dmax && (q - s.b).norm() > 2 * dmax;
      for (std::size_t k = 0; k < lines.size(); ++k) {
        double d = 1e300;
        for (const Vec3& p : lines[k].points) d = std::min(d, (p - q).norm());
        if (static_cast<int>(k) == line_of_edge[e]) {
          covered += d <= dmax ? 1 : 0;
        } else if (inner) {
          EXPECT_GT(d, dmax) << "edge " << e << " also near line " << k;
        }
      }
    }
    EXPECT_GE(covered, 180) << "edge " << s.a.transpose() << " -> " << s.b.transpose();
  }
  // Total length close to the edges' total length.
  double edges_length = 0;
  for (const Segment& e : box.edges) edges_length += (e.b - e.a).norm();
  EXPECT_GE(st.length[2], 0.9 * edges_length);
  EXPECT_LE(st.length[2], 1.02 * edges_length);
}

void check_box(const SharpBox& box, std::size_t count) {
  const ParticleSystem ps = particles_on(*box.field, count);
  ASSERT_TRUE(has_seed_state(ps));
  for (StraddleSource source :
       {StraddleSource::kMovement, StraddleSource::kSearch, StraddleSource::kAuto})
    check_box(box, ps, source);
}

TEST(FeatureLines, AxisAlignedBoxEdges) {
  check_box(sharp_box(Vec3(1.0, 0.8, 0.6), Affine3::Identity()), 3000);
}

TEST(FeatureLines, RotatedBoxEdges) {
  Affine3 pose = Affine3::Identity();
  pose.translate(Vec3(0.3, -0.2, 0.1));
  pose.rotate(Eigen::AngleAxisd(0.5, Vec3(1, 2, 3).normalized()));
  check_box(sharp_box(Vec3(0.9, 0.7, 0.5), pose), 3000);
}

// Without a seeding state kAuto searches, and kMovement is refused.
TEST(FeatureLines, WithoutSeedingStateAutoSearches) {
  const SharpBox box = sharp_box(Vec3(1.0, 0.8, 0.6), Affine3::Identity());
  ParticleSystem ps = particles_on(*box.field, 2000);
  ps.seed_positions.clear();
  ps.seed_normals.clear();
  LineStats st;
  const std::vector<Polyline> lines = feature_lines(*box.field, ps, {}, &st);
  EXPECT_EQ(lines.size(), 12u);
  EXPECT_EQ(st.straddle_pairs_movement, 0u);
  EXPECT_GT(st.straddle_pairs_search, 0u);
  LineOptions o;
  o.straddle = StraddleSource::kMovement;
  EXPECT_THROW((void)feature_lines(*box.field, ps, o), InvalidArgument);
}

// Seeding states that never turned by k_a: the movement test finds nothing, kAuto falls back
// to the search and draws what kSearch draws.
TEST(FeatureLines, AutoFallsBackWhenTheMovementTestFails) {
  const SharpBox box = sharp_box(Vec3(1.0, 0.8, 0.6), Affine3::Identity());
  ParticleSystem ps = particles_on(*box.field, 2000);
  for (std::size_t i = 0; i < ps.particles.size(); ++i) {
    ps.seed_positions[i] = ps.particles[i].position;
    ps.seed_normals[i] = ps.particles[i].normal;
  }
  LineOptions o;
  o.straddle = StraddleSource::kMovement;
  LineStats sm;
  EXPECT_TRUE(feature_lines(*box.field, ps, o, &sm).empty());
  EXPECT_EQ(sm.straddle_pairs, 0u);
  LineStats sa, ss;
  const std::vector<Polyline> a = feature_lines(*box.field, ps, {}, &sa);
  o.straddle = StraddleSource::kSearch;
  const std::vector<Polyline> s = feature_lines(*box.field, ps, o, &ss);
  EXPECT_EQ(a.size(), 12u);
  ASSERT_EQ(a.size(), s.size());
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k].points, s[k].points);
  EXPECT_EQ(sa.straddle_pairs_search, ss.straddle_pairs_search);
}

TEST(FeatureLines, StraddleNames) {
  EXPECT_EQ(straddle_from_name("auto"), StraddleSource::kAuto);
  EXPECT_EQ(straddle_from_name("movement"), StraddleSource::kMovement);
  EXPECT_EQ(straddle_from_name("search"), StraddleSource::kSearch);
  try {
    (void)straddle_from_name("both");
    ADD_FAILURE() << "no throw";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("straddle"), std::string::npos) << e.what();
  }
  LineOptions o;
  EXPECT_EQ(o.straddle, StraddleSource::kAuto);
  o.straddle = static_cast<StraddleSource>(7);
  EXPECT_THROW(validate(o), InvalidArgument);
}

// A cylinder cut by two planes: the two rims are closed feature loops; the crease between a
// curved and a flat face.
TEST(FeatureLines, CylinderRimsAreClosedLoops) {
  const double R = 0.6, h = 0.7;
  const FieldPtr f = make_intersection({make_cylinder_field(Vec3(0, 0, -2), Vec3(0, 0, 2), R, 0.1),
                                        make_plane_field(Vec3(0, 0, h), Vec3::UnitZ(), 0.5),
                                        make_plane_field(Vec3(0, 0, -h), -Vec3::UnitZ(), 0.5)});
  const ParticleSystem ps = particles_on(*f, 3000);
  double dmax = 0;
  for (const SurfaceParticle& p : ps.particles) dmax = std::max(dmax, p.delta);
  LineStats st;
  const std::vector<Polyline> lines = feature_lines(*f, ps, {}, &st);
  ASSERT_EQ(lines.size(), 2u);
  double z_sum = 0;
  for (const Polyline& l : lines) {
    EXPECT_TRUE(l.closed);
    const double z = l.points[0].z();
    z_sum += z;
    for (const Vec3& p : l.points) {
      ASSERT_LE(std::hypot(std::hypot(p.x(), p.y()) - R, p.z() - z), 1e-3 * dmax) << p.transpose();
      ASSERT_NEAR(std::abs(z), h, 1e-3 * dmax);
    }
    for (std::size_t i = 0; i < l.points.size(); ++i)
      EXPECT_LE((l.points[i] - l.points[(i + 1) % l.points.size()]).norm(), 1.5 * dmax);
  }
  EXPECT_NEAR(z_sum, 0, 2e-3 * dmax);  // the rims at ±h (each within 1e-3 δ)
  EXPECT_NEAR(st.length[2], 2 * 2 * std::numbers::pi * R, 0.02 * 2 * 2 * std::numbers::pi * R);
}

TEST(FeatureLines, NoneOnSmoothSurfaces) {
  const FieldPtr sphere = make_box_field(Vec3(0.1, 0.2, 0.3), Vec3::Constant(1), 1);
  const FieldPtr torus = make_circle_field(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.35);
  const FieldPtr blend =
      make_sum({make_segment_field(Vec3(-0.8, 0, 0), 0.3, Vec3(0.4, 0, 0), 0.3),
                make_segment_field(Vec3(0, -0.7, 0.2), 0.25, Vec3(0, 0.7, -0.2), 0.25)});
  for (const FieldPtr& f : {sphere, torus, blend}) {
    const ParticleSystem ps = particles_on(*f, 2000);
    for (StraddleSource source :
         {StraddleSource::kAuto, StraddleSource::kMovement, StraddleSource::kSearch}) {
      LineOptions o;
      o.straddle = source;
      LineStats st;
      const std::vector<Polyline> lines = feature_lines(*f, ps, o, &st);
      EXPECT_TRUE(lines.empty()) << f->describe() << " (" << static_cast<int>(source)
                                 << "): " << lines.size() << " lines from " << st.straddle_pairs
                                 << " straddle pairs";
    }
  }
}

TEST(FeatureLines, SameBytesOnOneAndTwoThreads) {
  const SharpBox box =
      sharp_box(Vec3(1.0, 0.8, 0.6), Affine3(Eigen::AngleAxisd(0.3, Vec3::UnitY())));
  const ParticleSystem ps = particles_on(*box.field, 2000);
  const Context one(1), two(2);
  for (StraddleSource source : {StraddleSource::kMovement, StraddleSource::kSearch}) {
    LineOptions o;
    o.straddle = source;
    const auto a = feature_lines(*box.field, ps, o, nullptr, &one);
    const auto b = feature_lines(*box.field, ps, o, nullptr, &two);
    ASSERT_FALSE(a.empty());
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].points.size(), b[k].points.size());
      EXPECT_EQ(a[k].closed, b[k].closed);
      EXPECT_EQ(
          std::memcmp(a[k].points.data(), b[k].points.data(), a[k].points.size() * sizeof(Vec3)),
          0);
    }
  }
}

}  // namespace
}  // namespace ramiform
