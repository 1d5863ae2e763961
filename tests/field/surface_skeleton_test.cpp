// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/surface_skeleton.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

// An orthonormal frame tilted away from the axes, for planes and rotations.
Mat3 tilted_frame() {
  return Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
}

// Plane patch O + u X + v Y with X = 2 e1, Y = 1.5 e2 (evenly spaced controls: linear precision).
BicubicPatch planar_patch(const Vec3& origin, const Mat3& frame) {
  BicubicPatch p;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      p.controls[4 * i + j] = origin + (2.0 * i / 3) * frame.col(0) + (1.5 * j / 3) * frame.col(1);
    }
  }
  return p;
}

// A saddle-and-bump patch over [0,3]^2 with heights of order 1.
BicubicPatch curved_patch() {
  const double z[4][4] = {
      {0, 1, -0.5, 0.3}, {0.8, -1.2, 1.5, 0}, {-0.4, 1.6, -1, 0.9}, {0.5, 0, 1.2, -0.7}};
  BicubicPatch p;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) p.controls[4 * i + j] = Vec3(i, j, z[i][j]);
  }
  return p;
}

Vec3 random_in(Rng& rng, const Aabb& box, double scale) {
  const Vec3 c = box.center();
  const Vec3 h = 0.5 * scale * box.diagonal();
  return c +
         Vec3(rng.uniform(-1, 1) * h.x(), rng.uniform(-1, 1) * h.y(), rng.uniform(-1, 1) * h.z());
}

// Distance to the true surface: the best points of a 129 x 129 grid, each refined by a
// shrinking 8-direction pattern search in (u, v) (clamped to the square; the diagonal moves
// follow the narrow valleys of a strongly non-uniform parametrization).
double brute_force_distance(const ParametricSurface& s, const Vec3& p) {
  constexpr int kGrid = 128;
  constexpr int kStarts = 6;
  std::vector<std::pair<double, Vec2>> grid;
  grid.reserve((kGrid + 1) * (kGrid + 1));
  for (int i = 0; i <= kGrid; ++i) {
    for (int j = 0; j <= kGrid; ++j) {
      const Vec2 uv(static_cast<double>(i) / kGrid, static_cast<double>(j) / kGrid);
      grid.emplace_back((s.point(uv.x(), uv.y()) - p).norm(), uv);
    }
  }
  std::partial_sort(grid.begin(), grid.begin() + kStarts, grid.end(),
                    [](const auto& a, const auto& b) { return a.first < b.first; });
  double overall = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kStarts; ++k) {
    double best = grid[k].first;
    Vec2 at = grid[k].second;
    for (double step = 1.0 / kGrid; step > 1e-12; step *= 0.5) {
      for (bool improved = true; improved;) {
        improved = false;
        for (int du = -1; du <= 1; ++du) {
          for (int dv = -1; dv <= 1; ++dv) {
            const Vec2 uv(std::clamp(at.x() + du * step, 0.0, 1.0),
                          std::clamp(at.y() + dv * step, 0.0, 1.0));
            const double d = (s.point(uv.x(), uv.y()) - p).norm();
            if (d < best) {
              best = d;
              at = uv;
              improved = true;
            }
          }
        }
      }
    }
    overall = std::min(overall, best);
  }
  return overall;
}

// Barycentric coordinates of q (on the triangle's plane) in triangle t.
Vec3 barycentric(const SkeletonTriangle& t, const Vec3& q) {
  const Vec3 ab = t.vertices[1] - t.vertices[0];
  const Vec3 ac = t.vertices[2] - t.vertices[0];
  const Vec3 aq = q - t.vertices[0];
  const double g11 = ab.dot(ab), g12 = ab.dot(ac), g22 = ac.dot(ac);
  const double det = g11 * g22 - g12 * g12;
  const double v = (g22 * ab.dot(aq) - g12 * ac.dot(aq)) / det;
  const double w = (g11 * ac.dot(aq) - g12 * ab.dot(aq)) / det;
  return Vec3(1 - v - w, v, w);
}

template <class F>
void expect_invalid(F&& f, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "expected InvalidArgument mentioning '" << fragment << "'";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(SurfaceSkeleton, PlanarPatchIsFlatAtDepthZeroAndExact) {
  const Mat3 frame = tilted_frame();
  const Vec3 origin(0.3, -0.2, 1.1);
  const SurfaceSkeleton sk(make_patch_surface(planar_patch(origin, frame)));
  EXPECT_EQ(sk.depth_reached(), 0);
  EXPECT_EQ(sk.patch_count(), 1U);
  EXPECT_EQ(sk.triangle_count(), 2U);
  EXPECT_FALSE(sk.error_is_estimate());
  EXPECT_LE(sk.error_bound(), 1e-14);
  Rng rng(11);
  for (int k = 0; k < 500; ++k) {
    const Vec3 p =
        origin + frame * Vec3(rng.uniform(-1, 3), rng.uniform(-1, 2.5), rng.uniform(-1.5, 1.5));
    const Vec3 local = frame.transpose() * (p - origin);
    const double u = std::clamp(local.x() / 2.0, 0.0, 1.0);
    const double v = std::clamp(local.y() / 1.5, 0.0, 1.0);
    const Vec3 q = origin + 2.0 * u * frame.col(0) + 1.5 * v * frame.col(1);
    const SurfaceProjection r = sk.project(p);
    EXPECT_NEAR(r.distance, (p - q).norm(), 1e-12);
    EXPECT_NEAR(r.u, u, 1e-12);
    EXPECT_NEAR(r.v, v, 1e-12);
    EXPECT_LE((r.point - q).norm(), 1e-12);
    if (local.x() > 0 && local.x() < 2 && local.y() > 0 && local.y() < 1.5) {
      // Foot inside: the plane distance, and u, v move along e1 / 2 and e2 / 1.5.
      EXPECT_NEAR(r.distance, std::abs(local.z()), 1e-12);
      EXPECT_LE((r.grad_u - frame.col(0) / 2.0).norm(), 1e-12);
      EXPECT_LE((r.grad_v - frame.col(1) / 1.5).norm(), 1e-12);
    }
  }
}

TEST(SurfaceSkeleton, UvGradientOnEdgesAndVertices) {
  BicubicPatch p;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) p.controls[4 * i + j] = Vec3(i, j, 0);  // [0,3]^2 in z = 0
  }
  const SurfaceSkeleton sk(make_patch_surface(p));
  // Beyond the u = 1 side: foot on that edge, u = 1, v moves along it.
  const SurfaceProjection e = sk.project(Vec3(4, 1.2, 0.5));
  EXPECT_NEAR(e.u, 1, 1e-15);
  EXPECT_NEAR(e.v, 0.4, 1e-15);
  EXPECT_LE(e.grad_u.norm(), 1e-15);
  EXPECT_LE((e.grad_v - Vec3(0, 1.0 / 3, 0)).norm(), 1e-15);
  EXPECT_LE((e.gradient - Vec3(1, 0, 0.5).normalized()).norm(), 1e-15);
  // Beyond the corner (1, 0): a vertex, u and v constant.
  const SurfaceProjection c = sk.project(Vec3(4, -1, 0.5));
  EXPECT_EQ(c.u, 1);
  EXPECT_EQ(c.v, 0);
  EXPECT_EQ(c.grad_u, Vec3::Zero());
  EXPECT_EQ(c.grad_v, Vec3::Zero());
  // On the surface: distance 0 and a zero gradient.
  const SurfaceProjection on = sk.project(Vec3(1, 2, 0));
  EXPECT_EQ(on.distance, 0);
  EXPECT_EQ(on.gradient, Vec3::Zero());
}

TEST(SurfaceSkeleton, CurvedPatchWithinErrorBoundOfTrueDistance) {
  const auto surface = make_patch_surface(curved_patch());
  for (int depth : {3, 5}) {
    SubdivisionOptions o;
    o.max_depth = depth;
    const SurfaceSkeleton sk(surface, o);
    EXPECT_GT(sk.depth_reached(), 0);
    EXPECT_LE(sk.depth_reached(), depth);
    EXPECT_LE(sk.patch_count(), std::size_t{1} << (2 * depth));
    EXPECT_EQ(sk.triangle_count(), 2 * sk.patch_count());
    EXPECT_FALSE(sk.error_is_estimate());
    EXPECT_GT(sk.error_bound(), 0);
    Rng rng(23 + depth);
    double worst = 0;
    for (int k = 0; k < 150; ++k) {
      const Vec3 p = random_in(rng, sk.box(), 1.5);
      const double diff = std::abs(sk.project(p).distance - brute_force_distance(*surface, p));
      worst = std::max(worst, diff);
      EXPECT_LE(diff, sk.error_bound() + 1e-9) << "depth " << depth;
    }
    EXPECT_GT(worst, 0.0);
  }
}

TEST(SurfaceSkeleton, ProjectionAgreesWithBruteForceOverTriangles) {
  SubdivisionOptions o;
  o.max_depth = 4;
  const SurfaceSkeleton sk(make_patch_surface(curved_patch()), o);
  Rng rng(5);
  for (int k = 0; k < 300; ++k) {
    const Vec3 p = random_in(rng, sk.box(), 1.5);
    const SurfaceProjection r = sk.project(p);
    // The nearest triangle by brute force (distance via a fine barycentric sampling is too
    // coarse; instead check that no triangle vertex or edge sample is nearer than r).
    for (std::size_t t = 0; t < sk.triangle_count(); ++t) {
      const SkeletonTriangle tri = sk.triangle(t);
      for (int a = 0; a <= 4; ++a) {
        for (int b = 0; a + b <= 4; ++b) {
          const Vec3 q = tri.vertices[0] + (a / 4.0) * (tri.vertices[1] - tri.vertices[0]) +
                         (b / 4.0) * (tri.vertices[2] - tri.vertices[0]);
          ASSERT_GE((q - p).norm(), r.distance - 1e-12);
        }
      }
    }
    EXPECT_NEAR((r.point - p).norm(), r.distance, 1e-12);
  }
}

TEST(SurfaceSkeleton, GradientsMatchCentralDifferences) {
  SubdivisionOptions o;
  o.max_depth = 3;
  const SurfaceSkeleton sk(make_patch_surface(curved_patch()), o);
  Rng rng(9);
  constexpr double h = 1e-6;
  int checked = 0;
  for (int k = 0; k < 400 && checked < 100; ++k) {
    const Vec3 p = random_in(rng, sk.box(), 1.2);
    const SurfaceProjection r = sk.project(p);
    if (r.distance < 1e-3) continue;
    const Vec3 bary = barycentric(sk.triangle(r.triangle), r.point);
    if (bary.minCoeff() < 0.02) continue;  // foot near an edge or vertex
    bool same = true;
    Vec3 fd_d, fd_u, fd_v;
    for (int a = 0; a < 3 && same; ++a) {
      const Vec3 e = h * Vec3::Unit(a);
      const SurfaceProjection plus = sk.project(p + e);
      const SurfaceProjection minus = sk.project(p - e);
      same = plus.triangle == r.triangle && minus.triangle == r.triangle;
      fd_d[a] = (plus.distance - minus.distance) / (2 * h);
      fd_u[a] = (plus.u - minus.u) / (2 * h);
      fd_v[a] = (plus.v - minus.v) / (2 * h);
    }
    if (!same) continue;  // near the medial axis
    ++checked;
    EXPECT_NEAR(r.gradient.norm(), 1.0, 1e-12);
    EXPECT_LE((fd_d - r.gradient).norm(), 1e-6);
    EXPECT_LE((fd_u - r.grad_u).norm(), 1e-6 * std::max(1.0, r.grad_u.norm()));
    EXPECT_LE((fd_v - r.grad_v).norm(), 1e-6 * std::max(1.0, r.grad_v.norm()));
  }
  EXPECT_GE(checked, 40);
}

TEST(SurfaceSkeleton, DistanceRangeBracketsDistances) {
  Superquadric q;
  q.radii = Vec3(1.5, 1, 0.7);
  q.e1 = q.e2 = 0.5;
  SubdivisionOptions o;
  o.max_depth = 4;
  for (const auto& surface : {make_patch_surface(curved_patch()), make_superquadric_surface(q)}) {
    const SurfaceSkeleton sk(surface, o);
    Rng rng(17);
    for (int k = 0; k < 100; ++k) {
      const Vec3 c = random_in(rng, sk.box(), 2.0);
      const double size = rng.uniform(0.01, 1.5);
      const Aabb box(c - size * Vec3(rng.uniform(), rng.uniform(), rng.uniform()),
                     c + size * Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
      const auto [lo, hi] = sk.distance_range(box);
      ASSERT_LE(lo, hi);
      for (int m = 0; m < 20; ++m) {
        const Vec3 p = random_in(rng, box, 1.0);
        const double d = sk.project(p).distance;
        EXPECT_LE(lo, d + 1e-12);
        EXPECT_GE(hi, d - 1e-12);
      }
    }
  }
}

TEST(SurfaceSkeleton, SuperquadricSphereWithinErrorBound) {
  Superquadric q;
  q.center = Vec3(0.5, -1, 2);
  q.radii = Vec3::Constant(2);
  q.rotation = tilted_frame();
  const auto surface = make_superquadric_surface(q);
  // On the surface: S(u, v) at radius 2.
  for (double u : {0.0, 0.13, 0.5, 1.0}) {
    for (double v : {0.0, 0.31, 0.5, 1.0}) {
      EXPECT_NEAR((surface->point(u, v) - q.center).norm(), 2, 1e-14);
    }
  }
  double previous = std::numeric_limits<double>::infinity();
  for (int depth : {4, 6}) {
    SubdivisionOptions o;
    o.max_depth = depth;
    const SurfaceSkeleton sk(surface, o);
    EXPECT_TRUE(sk.error_is_estimate());
    EXPECT_EQ(sk.depth_reached(), depth);
    EXPECT_LT(sk.error_bound(), previous);
    previous = sk.error_bound();
    Rng rng(31);
    for (int k = 0; k < 500; ++k) {
      const Vec3 p = random_in(rng, sk.box(), 1.5);
      const double exact = std::abs((p - q.center).norm() - 2);
      EXPECT_LE(std::abs(sk.project(p).distance - exact), sk.error_bound() + 1e-12);
    }
  }
  // A coarser epsilon stops earlier: fewer patches, a larger error.
  SubdivisionOptions fine;
  fine.epsilon_degrees = 5;
  SubdivisionOptions coarse;
  coarse.epsilon_degrees = 30;
  const SurfaceSkeleton a(surface, fine);
  const SurfaceSkeleton b(surface, coarse);
  EXPECT_LT(b.patch_count(), a.patch_count());
  EXPECT_LT(a.error_bound(), b.error_bound());
}

TEST(SurfaceSkeleton, RoundedBoxSuperquadricWithinEstimatedBound) {
  // e1 = e2 = 0.5 (a rounded box): the estimate against brute-force distances to the surface.
  Superquadric q;
  q.radii = Vec3(1.5, 1, 0.8);
  q.e1 = q.e2 = 0.5;
  const auto surface = make_superquadric_surface(q);
  for (int depth : {4, 6}) {
    SubdivisionOptions o;
    o.max_depth = depth;
    const SurfaceSkeleton sk(surface, o);
    Rng rng(41);
    double worst = 0;
    for (int k = 0; k < 150; ++k) {
      const Vec3 p = random_in(rng, sk.box(), 1.5);
      worst = std::max(worst, std::abs(sk.project(p).distance - brute_force_distance(*surface, p)));
    }
    EXPECT_LE(worst, sk.error_bound() + 1e-9) << "depth " << depth;
    RecordProperty("worst_depth_" + std::to_string(depth), std::to_string(worst));
  }
}

TEST(SurfaceSkeleton, SuperquadricIsSubdividedToDepthTwoAtLeast) {
  SubdivisionOptions o;
  o.max_depth = 0;
  const SurfaceSkeleton sk(make_superquadric_surface(Superquadric{}), o);
  EXPECT_EQ(sk.depth_reached(), 2);
  EXPECT_EQ(sk.patch_count(), 16U);
  // The coarse approximation of the unit sphere is closed around the centre.
  const double d = sk.project(Vec3::Zero()).distance;
  EXPECT_GT(d, 0.5);
  EXPECT_LT(d, 1.0);
}

TEST(SurfaceSkeleton, BoxyAndPinchedSuperquadricsAreFinite) {
  for (double e : {0.2, 2.5}) {
    Superquadric q;
    q.radii = Vec3(1, 2, 0.5);
    q.e1 = q.e2 = e;
    const auto surface = make_superquadric_surface(q);
    for (double u = 0; u <= 1; u += 0.125) {
      for (double v = 0; v <= 1; v += 0.125) {
        Vec3 su, sv;
        surface->derivatives(u, v, su, sv);
        ASSERT_TRUE(surface->point(u, v).allFinite());
        ASSERT_TRUE(su.allFinite() && sv.allFinite()) << "e " << e << " u " << u << " v " << v;
      }
    }
    const SurfaceSkeleton sk(surface);
    EXPECT_TRUE(std::isfinite(sk.error_bound()));
    EXPECT_GT(sk.patch_count(), 16U);
    EXPECT_TRUE(sk.box().min().allFinite() && sk.box().max().allFinite());
    EXPECT_LE((sk.box().max() - Vec3(1, 2, 0.5)).cwiseAbs().maxCoeff(), 1e-12);
    Rng rng(3);
    for (int k = 0; k < 200; ++k) {
      const SurfaceProjection r = sk.project(random_in(rng, sk.box(), 1.5));
      ASSERT_TRUE(std::isfinite(r.distance) && std::isfinite(r.u) && std::isfinite(r.v));
      ASSERT_TRUE(r.gradient.allFinite() && r.grad_u.allFinite() && r.grad_v.allFinite());
    }
  }
}

TEST(SurfaceSkeleton, ValidationNamesTheProblem) {
  BicubicPatch p = curved_patch();
  p.controls[6].y() = std::numeric_limits<double>::quiet_NaN();
  expect_invalid([&] { (void)make_patch_surface(p); }, "control point 6");
  Superquadric q;
  q.radii = Vec3(1, -1, 1);
  expect_invalid([&] { (void)make_superquadric_surface(q); }, "radii");
  q = Superquadric{};
  q.e1 = 0;
  expect_invalid([&] { (void)make_superquadric_surface(q); }, "e1");
  q.e1 = 1;
  q.e2 = 10.5;
  expect_invalid([&] { (void)make_superquadric_surface(q); }, "e2");
  q.e2 = std::numeric_limits<double>::infinity();
  expect_invalid([&] { (void)make_superquadric_surface(q); }, "e2");
  q = Superquadric{};
  q.rotation(0, 1) = 0.5;
  expect_invalid([&] { (void)make_superquadric_surface(q); }, "rotation");
  const auto surface = make_superquadric_surface(Superquadric{});
  SubdivisionOptions o;
  o.epsilon_degrees = 0;
  expect_invalid([&] { SurfaceSkeleton s(surface, o); }, "epsilon_degrees");
  o.epsilon_degrees = 91;
  expect_invalid([&] { SurfaceSkeleton s(surface, o); }, "epsilon_degrees");
  o = SubdivisionOptions{};
  o.max_depth = 11;
  expect_invalid([&] { SurfaceSkeleton s(surface, o); }, "max_depth");
  o.max_depth = -1;
  expect_invalid([&] { SurfaceSkeleton s(surface, o); }, "max_depth");
  expect_invalid([&] { SurfaceSkeleton s(nullptr); }, "null");
  const SurfaceSkeleton sk(surface);
  expect_invalid([&] { (void)sk.triangle(sk.triangle_count()); }, "triangle");
  expect_invalid([&] { (void)sk.distance_range(Aabb()); }, "box");
}

TEST(SurfaceSkeleton, SpansAndPointsBeyondDoublePrecisionAreRefusedNotCrashed) {
  // Both used to end in a segmentation fault (every distance NaN, no nearest triangle).
  Superquadric q;
  q.radii = Vec3::Constant(1e200);
  const auto huge = make_superquadric_surface(q);
  expect_invalid([&] { SurfaceSkeleton s(huge); }, "spans more than double precision can hold");
  BicubicPatch p = curved_patch();
  p.controls[3].x() = 1e308;
  p.controls[15].x() = -1e308;
  const auto wide = make_patch_surface(p);
  expect_invalid([&] { SurfaceSkeleton s(wide); }, "spans more than double precision can hold");
  q.radii = Vec3::Constant(1e150);  // large, but its distances fit
  EXPECT_NO_THROW(SurfaceSkeleton s(make_superquadric_surface(q)));
  const SurfaceSkeleton unit(make_superquadric_surface(Superquadric{}));
  // Far points: a distance that overflows is +inf, never NaN or a missing triangle.
  EXPECT_GT(unit.project(Vec3(1e300, -1e300, 1e300)).distance, 1e299);
  EXPECT_NEAR(unit.project(Vec3(0, 0, 1e100)).distance, 1e100, 1e90);
}

}  // namespace
}  // namespace ramiform
