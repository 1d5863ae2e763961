// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The deviation measure against surfaces whose distance is known in closed form: spheres of a
// point primitive (distance and convolution surfaces), a capsule of a segment, a torus of a
// circle. Each figure is compared with the same figure computed here from the exact distance.

#include "ramiform/mesh/deviation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mesh/test_meshes.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/field/primitives.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/mesh/surface_points.h"

namespace ramiform {
namespace {

SkeletonFieldOptions distance_surface() {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kDistance;
  o.kernel = Kernel{KernelKind::kWyvill, 0.0};
  return o;
}

Vec3 random_point(Rng& rng, double half) {
  return {rng.uniform(-half, half), rng.uniform(-half, half), rng.uniform(-half, half)};
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double u = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + u * ab)).norm();
}

/// Nearest rank, as the header states.
double rank(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::max<std::size_t>(k, 1) - 1];
}

TEST(DistanceToSurface, SphereOfAPointPrimitiveIsExact) {
  const Vec3 c(0.3, -0.2, 0.5);
  const double r = 0.7;
  for (const bool convolution : {false, true}) {
    const FieldPtr f = make_point_field(c, r, convolution ? SkeletonFieldOptions{} : distance_surface());
    Rng rng(7);
    for (int i = 0; i < 300; ++i) {
      const Vec3 p = c + random_point(rng, 1.2);
      // Not the centre (every direction is a closest one there), not where the distance
      // kernel's support ends (1.54 from c: the field is flat beyond).
      if ((p - c).norm() < 0.05 || (p - c).norm() > 1.3) continue;
      const double exact = std::abs((p - c).norm() - r);
      const SurfaceDistance d = distance_to_surface(*f, p, 4.0 * r);
      ASSERT_TRUE(d.resolved) << "point " << i << " at " << (p - c).norm() << " value "
                              << f->value(p) << " iso " << f->iso() << " grad "
                              << f->gradient(p).transpose() << (convolution ? " conv" : " dist");
      EXPECT_NEAR(d.distance, exact, 1e-9) << "point " << i << (convolution ? " convolution" : "");
      EXPECT_NEAR((d.foot - c).norm(), r, 1e-9);
    }
  }
}

TEST(DistanceToSurface, CapsuleOfASegmentIsExact) {
  const Vec3 a(0, 0, 0), b(1.5, 0.5, -0.2);
  const double r = 0.4;
  const FieldPtr f = make_segment_field(a, r, b, r, distance_surface());
  Rng rng(11);
  int tested = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p = 0.5 * (a + b) + random_point(rng, 1.4);
    const double s = segment_distance(p, a, b);
    if (s < 0.05 || s > 0.8) continue;  // the axis (no unique closest point); the support's end
    ++tested;
    const SurfaceDistance d = distance_to_surface(*f, p, 10.0 * r);
    ASSERT_TRUE(d.resolved);
    EXPECT_NEAR(d.distance, std::abs(s - r), 1e-9) << "point " << i;
    EXPECT_NEAR(segment_distance(d.foot, a, b), r, 1e-9);
  }
  EXPECT_GT(tested, 300);
}

TEST(DistanceToSurface, TorusOfACircleIsExact) {
  const double R = 1.0, r = 0.3;
  const FieldPtr f = make_circle_field(Vec3::Zero(), Vec3::UnitZ(), R, r);
  auto exact = [&](const Vec3& p) {
    return std::abs(std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) - r);
  };
  Rng rng(13);
  int tested = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p = random_point(rng, 1.6);
    // Away from the core circle and the axis (where closest points are not unique).
    if (std::hypot(std::hypot(p.x(), p.y()) - R, p.z()) < 0.05 || std::hypot(p.x(), p.y()) < 0.2) {
      continue;
    }
    if (exact(p) > 0.25) continue;  // the kernel's support ends 0.36 outside the surface
    ++tested;
    const SurfaceDistance d = distance_to_surface(*f, p, 2.0);
    ASSERT_TRUE(d.resolved) << "point " << i;
    EXPECT_NEAR(d.distance, exact(p), 1e-9) << "point " << i;
  }
  EXPECT_GT(tested, 250);
}

TEST(DistanceToSurface, NoSurfaceWithinTheSearchIsUnresolved) {
  const FieldPtr f = make_point_field(Vec3::Zero(), 1.0, distance_surface());
  const SurfaceDistance d = distance_to_surface(*f, Vec3(0, 0, 0.2), 0.5);
  EXPECT_FALSE(d.resolved);
  EXPECT_EQ(d.distance, 0.5);
  EXPECT_EQ(distance_to_surface(*f, Vec3(0, 0, 0.2), 0.0).resolved, false);
  EXPECT_FALSE(distance_to_surface(*f, Vec3(NAN, 0, 0), 1.0).resolved);
}

TEST(LocalRadii, InterpolatesTheNearestEdgeAndTakesIsolatedNodes) {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 1.0}, {Vec3(10, 0, 0), 0.5}, {Vec3(0, 20, 0), 0.25}};
  s.edges = {{0, 1}};
  const std::vector<Vec3> points = {Vec3(2.5, 3, 0), Vec3(-4, 0, 0), Vec3(12, 1, 0),
                                    Vec3(0, 19, 1)};
  const std::vector<double> r = local_radii(s, points);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_DOUBLE_EQ(r[0], 1.0 - 0.25 * 0.5);  // closest point at x = 2.5 of 10
  EXPECT_DOUBLE_EQ(r[1], 1.0);               // clamped to node 0
  EXPECT_DOUBLE_EQ(r[2], 0.5);               // clamped to node 1
  EXPECT_DOUBLE_EQ(r[3], 0.25);              // the isolated node
  EXPECT_THROW((void)local_radii(Skeleton{}, points), InvalidArgument);
}

TEST(LocalRadii, FarPointsStillFindTheNearestEdge) {
  Skeleton s;
  for (int i = 0; i < 50; ++i) s.nodes.push_back({Vec3(0.01 * i, 0, 0), 0.1 + 0.01 * i});
  for (std::uint32_t i = 0; i + 1 < 50; ++i) s.edges.push_back({i, i + 1});
  const std::vector<double> r = local_radii(s, std::vector<Vec3>{Vec3(1e4, 0, 0), Vec3(-1e6, 5, 0)});
  EXPECT_DOUBLE_EQ(r[0], 0.1 + 0.49);
  EXPECT_DOUBLE_EQ(r[1], 0.1);
}

/// The figures of measure_deviation for an icosphere inscribed in the sphere of a point
/// primitive, against the exact distance r - |q - c| at the same sample points.
TEST(MeasureDeviation, IcosphereAgainstItsSphereMatchesTheExactDistance) {
  const Vec3 c(1, 2, 3);
  const double r = 0.5;
  const TriMesh mesh = test::icosphere(2, r, c);
  const FieldPtr f = make_point_field(c, r, distance_surface());
  Skeleton s;
  s.nodes = {{c, r}};
  DeviationOptions o;
  o.samples = 5000;
  o.seed = 42;
  const DeviationReport rep = measure_deviation(mesh, *f, &s, o);
  ASSERT_TRUE(rep.relative);
  // The same points, drawn independently with the documented sampler and seed.
  const MeshAreaSampler sampler(mesh);
  Rng rng(o.seed);
  std::vector<double> rel;
  for (std::size_t i = 0; i < o.samples; ++i) {
    const Vec3 q = sampler.position(sampler.draw(rng));
    rel.push_back((r - (q - c).norm()) / r);
  }
  EXPECT_EQ(rep.samples.points, o.samples);
  EXPECT_EQ(rep.samples.unresolved, 0u);
  EXPECT_NEAR(rep.samples.p50, rank(rel, 0.5), 1e-9);
  EXPECT_NEAR(rep.samples.p99, rank(rel, 0.99), 1e-9);
  EXPECT_NEAR(rep.samples.max, *std::max_element(rel.begin(), rel.end()), 1e-9);
  EXPECT_NEAR(rep.samples.abs_max, r * rep.samples.max, 1e-9);
  EXPECT_GT(rep.samples.max, 0.005);  // a level-2 icosphere's facets are that flat
  EXPECT_NEAR((rep.samples.worst - c).norm(), r * (1.0 - rep.samples.max), 1e-9);
  // Its vertices lie on the sphere.
  EXPECT_EQ(rep.vertices.points, mesh.positions.size());
  EXPECT_LT(rep.vertices.max, 1e-12);
  EXPECT_GT(rep.field_evaluations, o.samples);
}

TEST(MeasureDeviation, BatchedProjectionAgreesWithDistanceToSurfaceAtAFork) {
  // measure_deviation projects its points in lockstep with batched evaluations; each figure
  // must be the one distance_to_surface gives point by point. A sphere around the fork of a
  // convolution surface (no closed form) puts the points at many distances and directions.
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 0.1},
             {Vec3(0, 0, 0.5), 0.08},
             {Vec3(0.3, 0, 0.9), 0.05},
             {Vec3(-0.3, 0.05, 0.9), 0.05}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}};
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh mesh = test::icosphere(3, 0.2, Vec3(0, 0, 0.55));
  DeviationOptions o;
  o.samples = 2000;
  o.seed = 5;
  o.vertices = false;
  const DeviationReport rep = measure_deviation(mesh, *f, &s, o);
  const MeshAreaSampler sampler(mesh);
  Rng rng(o.seed);
  std::vector<Vec3> points;
  for (std::size_t i = 0; i < o.samples; ++i) points.push_back(sampler.position(sampler.draw(rng)));
  const std::vector<double> radius = local_radii(s, points);
  std::vector<double> rel, abs;
  std::size_t unresolved = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SurfaceDistance d = distance_to_surface(*f, points[i], o.search_radii * radius[i]);
    unresolved += d.resolved ? 0 : 1;
    abs.push_back(d.distance);
    rel.push_back(d.distance / radius[i]);
  }
  EXPECT_EQ(rep.samples.unresolved, unresolved);
  EXPECT_LT(unresolved, points.size() / 10);
  EXPECT_GT(rank(rel, 0.5), 0.1);  // far enough off for the projection to matter
  EXPECT_NEAR(rep.samples.p50, rank(rel, 0.5), 1e-9);
  EXPECT_NEAR(rep.samples.p99, rank(rel, 0.99), 1e-9);
  EXPECT_NEAR(rep.samples.max, *std::max_element(rel.begin(), rel.end()), 1e-9);
  EXPECT_NEAR(rep.samples.abs_p50, rank(abs, 0.5), 1e-10);
  EXPECT_NEAR(rep.samples.abs_max, *std::max_element(abs.begin(), abs.end()), 1e-10);
}

TEST(MeasureDeviation, TorusWithoutASkeletonGivesAbsoluteFigures) {
  const double R = 1.0, r = 0.3;
  const TriMesh mesh = test::torus(R, r, 48, 16);
  const FieldPtr f = make_circle_field(Vec3::Zero(), Vec3::UnitZ(), R, r);
  DeviationOptions o;
  o.samples = 3000;
  const DeviationReport rep = measure_deviation(mesh, *f, nullptr, o);
  EXPECT_FALSE(rep.relative);
  const MeshAreaSampler sampler(mesh);
  Rng rng(o.seed);
  std::vector<double> abs;
  for (std::size_t i = 0; i < o.samples; ++i) {
    const Vec3 q = sampler.position(sampler.draw(rng));
    abs.push_back(std::abs(std::hypot(std::hypot(q.x(), q.y()) - R, q.z()) - r));
  }
  EXPECT_NEAR(rep.samples.abs_p50, rank(abs, 0.5), 1e-9);
  EXPECT_NEAR(rep.samples.abs_p99, rank(abs, 0.99), 1e-9);
  EXPECT_NEAR(rep.samples.abs_max, *std::max_element(abs.begin(), abs.end()), 1e-9);
  EXPECT_EQ(rep.samples.p99, 0.0);
  EXPECT_LT(rep.vertices.abs_max, 1e-12);
}

TEST(MeasureDeviation, AMeshFarFromTheSurfaceIsUnresolvedAtTheSearchDistance) {
  const double r = 0.5;
  const TriMesh mesh = test::icosphere(1, r, Vec3(10, 0, 0));
  const FieldPtr f = make_point_field(Vec3::Zero(), r, distance_surface());
  Skeleton s;
  s.nodes = {{Vec3::Zero(), r}};
  DeviationOptions o;
  o.samples = 100;
  const DeviationReport rep = measure_deviation(mesh, *f, &s, o);
  EXPECT_EQ(rep.samples.unresolved, 100u);
  EXPECT_EQ(rep.vertices.unresolved, mesh.positions.size());
  EXPECT_DOUBLE_EQ(rep.samples.max, o.search_radii);
}

TEST(MeasureDeviation, SameFiguresOnAnyThreadCountAndBadOptionsAreRefused) {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 0.3}, {Vec3(0, 0, 2), 0.1}, {Vec3(0.8, 0, 2.8), 0.05}};
  s.edges = {{0, 1}, {1, 2}};
  const FieldPtr f = make_skeleton_field(s);
  const TriMesh mesh = test::icosphere(3, 1.0, Vec3(0, 0, 1));  // a poor mesh of it, on purpose
  DeviationOptions o;
  o.samples = 2000;
  Context one(1), two(2);
  const DeviationReport a = measure_deviation(mesh, *f, &s, o, &one);
  const DeviationReport b = measure_deviation(mesh, *f, &s, o, &two);
  EXPECT_EQ(a.samples.p50, b.samples.p50);
  EXPECT_EQ(a.samples.p99, b.samples.p99);
  EXPECT_EQ(a.samples.max, b.samples.max);
  EXPECT_EQ(a.vertices.max, b.vertices.max);
  EXPECT_EQ(a.samples.unresolved, b.samples.unresolved);
  o.search_radii = 0;
  EXPECT_THROW((void)measure_deviation(mesh, *f, &s, o), InvalidArgument);
  o.search_radii = 4;
  o.refine_steps = -1;
  EXPECT_THROW((void)measure_deviation(mesh, *f, &s, o), InvalidArgument);
  o.refine_steps = 8;
  const Skeleton empty;
  EXPECT_THROW((void)measure_deviation(mesh, *f, &empty, o), InvalidArgument);
  TriMesh bad = mesh;
  bad.triangles.push_back({0, 1, 99999});
  EXPECT_THROW((void)measure_deviation(bad, *f, &s, o), InputError);
}

}  // namespace
}  // namespace ramiform
