// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "field/point_cloud_fixtures.h"
#include "lines/visibility_reference.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/mpu.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/primitives.h"
#include "ramiform/lines/lines.h"

namespace ramiform {
namespace {

// A sphere of radius r: the distance surface of a point (a box shrunk to its centre).
FieldPtr sphere(const Vec3& c, double r) { return make_box_field(c, Vec3::Constant(r), r); }

struct Ball {
  Vec3 c;
  double r;
};

// Does the segment a → b pass through the open ball? Also the signed margin: distance from the
// centre to the segment minus the radius (negative: through it).
double segment_margin(const Vec3& a, const Vec3& b, const Ball& ball) {
  const Vec3 d = b - a;
  const double t = std::clamp((ball.c - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (a + t * d - ball.c).norm() - ball.r;
}

// The contour generator of `ball` seen from `eye`: the circle where the view rays touch it.
Polyline contour_circle(const Ball& ball, const Vec3& eye, int n) {
  const Vec3 to_eye = eye - ball.c;
  const double dist = to_eye.norm();
  const Vec3 u = to_eye / dist;
  const Vec3 centre = ball.c + (ball.r * ball.r / dist) * u;
  const double rho = ball.r * std::sqrt(1 - ball.r * ball.r / (dist * dist));
  const Vec3 e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  Polyline line;
  line.kind = LineKind::kSilhouette;
  line.closed = true;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    line.points.push_back(centre + rho * (std::cos(a) * e1 + std::sin(a) * e2));
  }
  return line;
}

// A circle of latitude on the ball facing `eye`: polar angle `theta` from the direction to the
// eye (front-facing for theta below the contour's).
Polyline latitude(const Ball& ball, const Vec3& eye, double theta, int n) {
  const Vec3 u = (eye - ball.c).normalized();
  const Vec3 e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  Polyline line;
  line.kind = LineKind::kFeature;
  line.closed = true;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    const Vec3 dir = std::cos(theta) * u + std::sin(theta) * (std::cos(a) * e1 + std::sin(a) * e2);
    line.points.push_back(ball.c + ball.r * dir);
  }
  return line;
}

// Two spheres apart in space, the front one hiding part of the back one from the eye.
struct TwoSpheres {
  Ball back{Vec3(0, 0, -1.5), 1.0};
  Ball front{Vec3(0.8, 0.1, 0.6), 0.6};
  Camera camera;
  FieldPtr field;
  ParticleSystem particles;

  TwoSpheres() {
    camera.eye = Vec3(0, 0, 6);
    camera.target = Vec3(0, 0, -0.5);
    camera.fov_deg = 40;
    field = make_union({sphere(back.c, back.r), sphere(front.c, front.r)});
    ParticleOptions o;
    o.count = 4000;
    particles = spread_particles(*field, o);
  }
};

const TwoSpheres& scene() {
  static const TwoSpheres s;
  return s;
}

struct Comparison {
  std::size_t points = 0, decided = 0, wrong = 0;  // wrong among the decided ones
  std::vector<std::uint8_t> flags;
  double seconds = 0;
  LineStats stats;
};

// Classifies the lines with `method` and compares with the analytic truth (hidden when the
// segment from the eye passes through the front ball), leaving out points whose segment passes
// within `margin` of the front ball's boundary (the tolerance band, where both answers hold).
Comparison classify(std::vector<Polyline> lines, Visibility method, double margin,
                    const Context* ctx = nullptr) {
  const TwoSpheres& s = scene();
  LineOptions o;
  o.visibility = method;
  Comparison c;
  const auto t0 = std::chrono::steady_clock::now();
  classify_visibility(*s.field, s.particles, s.camera, lines, o, &c.stats, ctx);
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (const Polyline& line : lines) {
    EXPECT_EQ(line.visible.size(), line.points.size());
    for (std::size_t i = 0; i < line.points.size(); ++i) {
      const double m = segment_margin(s.camera.eye, line.points[i], s.front);
      c.flags.push_back(line.visible[i]);
      ++c.points;
      if (std::abs(m) <= margin) continue;
      ++c.decided;
      const bool hidden = m < 0;
      if (hidden == (line.visible[i] != 0)) ++c.wrong;
    }
  }
  return c;
}

std::vector<Polyline> test_lines() {
  const TwoSpheres& s = scene();
  return {contour_circle(s.back, s.camera.eye, 2000), latitude(s.back, s.camera.eye, 0.6, 1500)};
}

double mean_delta() {
  double sum = 0;
  for (const SurfaceParticle& p : scene().particles.particles) sum += p.delta;
  return sum / static_cast<double>(scene().particles.particles.size());
}

TEST(LineVisibility, RaysMatchTheAnalyticOcclusion) {
  ASSERT_GT(scene().particles.particles.size(), 2000u);
  const double delta = mean_delta();
  const Comparison c = classify(test_lines(), Visibility::kRays, 0.5 * delta);
  ASSERT_GT(c.decided, 3000u);
  // The test sees part of each line hidden, part visible.
  std::size_t hidden = 0;
  for (std::uint8_t f : c.flags) hidden += f == 0 ? 1 : 0;
  EXPECT_GT(hidden, 300u);
  EXPECT_LT(hidden, c.points - 300);
  EXPECT_EQ(c.wrong, 0u) << "of " << c.decided;
  EXPECT_GT(c.stats.field_evals, c.points);
  std::printf(
      "[ kRays    ] %zu points, %zu outside the band, %zu wrong; %.2f ms, %.1f evaluations"
      " per point\n",
      c.points, c.decided, c.wrong, 1e3 * c.seconds,
      static_cast<double>(c.stats.field_evals) / static_cast<double>(c.points));
}

TEST(LineVisibility, SurfelsMatchTheAnalyticOcclusionAwayFromOutlines) {
  const double delta = mean_delta();
  // Surfels err near the front ball's outline (disks are sampled at pixel centres and the
  // disks of the outline stand edge-on): compare outside a band of 2 δ, and count all.
  const Comparison c = classify(test_lines(), Visibility::kSurfels, 2 * delta);
  const Comparison all = classify(test_lines(), Visibility::kSurfels, 0.0);
  const Comparison rays = classify(test_lines(), Visibility::kRays, 0.0);
  ASSERT_GT(c.decided, 2500u);
  EXPECT_EQ(c.wrong, 0u) << "of " << c.decided;
  std::size_t differ = 0;
  for (std::size_t i = 0; i < all.flags.size(); ++i) differ += all.flags[i] != rays.flags[i];
  const double fraction = static_cast<double>(differ) / static_cast<double>(all.points);
  EXPECT_LT(fraction, 0.02);
  std::printf(
      "[ kSurfels ] %zu points, %zu outside the 2 δ band, %zu wrong; %zu of all wrong "
      "(rays: %zu); differ from kRays on %.3f %% of the points; %.2f ms\n",
      c.points, c.decided, c.wrong, all.wrong, rays.wrong, 100 * fraction, 1e3 * all.seconds);
}

TEST(LineVisibility, HiddenFractionIsTheHiddenLength) {
  const TwoSpheres& s = scene();
  std::vector<Polyline> lines = test_lines();
  // The analytic hidden share of the two (evenly sampled) circles, weighted by their lengths.
  double length = 0, hidden = 0;
  for (const Polyline& line : lines) {
    const double step = (line.points[1] - line.points[0]).norm();
    for (const Vec3& p : line.points) {
      length += step;
      if (segment_margin(s.camera.eye, p, s.front) < 0) hidden += step;
    }
  }
  LineStats st;
  for (Visibility method : {Visibility::kRays, Visibility::kSurfels}) {
    LineOptions o;
    o.visibility = method;
    st = {};
    classify_visibility(*s.field, s.particles, s.camera, lines, o, &st);
    EXPECT_NEAR(st.hidden_fraction, hidden / length, 0.01) << static_cast<int>(method);
    EXPECT_GT(st.seconds_visibility, 0);
  }
  // kNone: everything visible.
  LineOptions none;
  none.visibility = Visibility::kNone;
  classify_visibility(*s.field, s.particles, s.camera, lines, none, &st);
  EXPECT_EQ(st.hidden_fraction, 0);
  for (const Polyline& line : lines) {
    EXPECT_EQ(line.visible, std::vector<std::uint8_t>(line.points.size(), 1));
  }
}

TEST(LineVisibility, FarSideOfASphereIsHiddenNearSideVisible) {
  const Vec3 c(0.2, -0.1, 0.3);
  const double r = 1.0;
  const FieldPtr f = sphere(c, r);
  ParticleOptions po;
  po.count = 1500;
  const ParticleSystem ps = spread_particles(*f, po);
  Camera cam;
  cam.eye = Vec3(1, 2, 6);
  cam.target = c;
  // Points on the sphere every few degrees, away from the contour (|n·v| > 0.2).
  Polyline line;
  line.kind = LineKind::kFeature;
  std::vector<bool> facing;
  for (int i = 0; i < 36; ++i) {
    for (int j = 1; j < 18; ++j) {
      const double a = 2 * std::numbers::pi * i / 36, b = std::numbers::pi * j / 18;
      const Vec3 n(std::sin(b) * std::cos(a), std::sin(b) * std::sin(a), std::cos(b));
      const Vec3 p = c + r * n;
      const double nv = n.dot(view_vector(cam, p));
      if (std::abs(nv) < 0.2) continue;
      line.points.push_back(p);
      facing.push_back(nv < 0);
    }
  }
  ASSERT_GT(line.points.size(), 300u);
  for (Visibility method : {Visibility::kRays, Visibility::kSurfels}) {
    LineOptions o;
    o.visibility = method;
    std::vector<Polyline> lines{line};
    classify_visibility(*f, ps, cam, lines, o);
    for (std::size_t i = 0; i < facing.size(); ++i) {
      ASSERT_EQ(lines[0].visible[i] != 0, facing[i])
          << "method " << static_cast<int>(method) << " point " << i;
    }
  }
}

TEST(LineVisibility, SameFlagsOnOneAndTwoThreads) {
  for (Visibility method : {Visibility::kRays, Visibility::kSurfels}) {
    const Context one(1), two(2);
    const Comparison a = classify(test_lines(), method, 0.0, &one);
    const Comparison b = classify(test_lines(), method, 0.0, &two);
    EXPECT_EQ(a.flags, b.flags);
    EXPECT_EQ(a.stats.field_evals, b.stats.field_evals);
    EXPECT_EQ(a.stats.hidden_fraction, b.stats.hidden_fraction);
  }
}

TEST(LineVisibility, ToleranceKeepsContourPointsOfTheirOwnSurface) {
  // The contour of a lone sphere grazes its own surface: visible with either method, and the
  // ray from behind the tolerance would see the surface the point sits on.
  const Ball b{Vec3::Zero(), 1.0};
  const FieldPtr f = sphere(b.c, b.r);
  ParticleOptions po;
  po.count = 1500;
  const ParticleSystem ps = spread_particles(*f, po);
  Camera cam;
  cam.eye = Vec3(0.5, 0.3, 4);
  for (Visibility method : {Visibility::kRays, Visibility::kSurfels}) {
    LineOptions o;
    o.visibility = method;
    std::vector<Polyline> lines{contour_circle(b, cam.eye, 500)};
    LineStats st;
    classify_visibility(*f, ps, cam, lines, o, &st);
    EXPECT_EQ(st.hidden_fraction, 0) << static_cast<int>(method);
  }
}

TEST(LineVisibility, EyeInsideHidesEverything) {
  const TwoSpheres& s = scene();
  Camera cam = s.camera;
  cam.eye = s.front.c + Vec3(0.1, 0, 0.1);  // inside the front ball
  std::vector<Polyline> lines = test_lines();
  LineOptions o;
  o.visibility = Visibility::kRays;
  LineStats st;
  classify_visibility(*s.field, s.particles, cam, lines, o, &st);
  EXPECT_EQ(st.hidden_fraction, 1);
}

// kRays's bounds only skip samples: the flags equal those of evaluating every sample of every
// segment (detail::rays_visibility_exhaustive), on an MPU surface (its walk through the cells)
// and on a CSG one (field.bound of boxes).
void expect_exhaustive_flags(const Field& field, const ParticleSystem& particles,
                             const Camera& camera, std::vector<Polyline> lines, std::size_t& hidden,
                             std::size_t& visible) {
  const Context two(2);
  const std::vector<std::uint8_t> reference = detail::rays_visibility_exhaustive(
      field, particles, camera, lines, LineOptions{}.occlusion_tolerance, &two);
  LineOptions o;
  o.visibility = Visibility::kRays;
  LineStats st;
  classify_visibility(field, particles, camera, lines, o, &st, &two);
  std::size_t k = 0, differ = 0;
  for (const Polyline& line : lines) {
    for (const std::uint8_t v : line.visible) {
      ASSERT_LT(k, reference.size());
      differ += v != reference[k] ? 1 : 0;
      (v != 0 ? visible : hidden) += 1;
      ++k;
    }
  }
  EXPECT_EQ(k, reference.size());
  EXPECT_EQ(differ, 0u) << "of " << k << " points";
}

std::vector<Polyline> particles_as_points(const ParticleSystem& particles) {
  Polyline all;
  all.kind = LineKind::kFeature;
  for (const SurfaceParticle& p : particles.particles) all.points.push_back(p.position);
  return {all};
}

TEST(LineVisibility, RaysEqualEverySampleEvaluatedOnAnMpuSurface) {
  // A torus and a ball partly in front of it, fitted together by the MPU.
  PointSet cloud = test::torus_cloud(4000, 7);
  const PointSet ball = test::sphere_cloud(1500, 0.4, Vec3(0.3, -0.9, 0.7));
  cloud.positions.insert(cloud.positions.end(), ball.positions.begin(), ball.positions.end());
  cloud.normals.insert(cloud.normals.end(), ball.normals.begin(), ball.normals.end());
  const Context two(2);
  const FieldPtr field = make_mpu_field(cloud, {}, nullptr, &two);
  ParticleOptions po;
  po.count = 2000;
  const ParticleSystem particles = spread_particles(*field, po, {}, {}, nullptr, &two);
  Aabb box;
  for (const SurfaceParticle& p : particles.particles) box.extend(p.position);
  std::size_t hidden = 0, visible = 0;
  for (int v = 0; v < 3; ++v) {
    const Camera camera = frame_box(box, 20.0 + 120.0 * v, 25.0 + 10.0 * v);
    LineOptions none;
    none.visibility = Visibility::kNone;
    const LineDrawing drawing = draw_lines(*field, particles, camera, none, nullptr, nullptr, &two);
    expect_exhaustive_flags(*field, particles, camera, drawing.lines, hidden, visible);
    expect_exhaustive_flags(*field, particles, camera, particles_as_points(particles), hidden,
                            visible);
  }
  // Both answers are common (the back of the torus, the torus behind the ball).
  EXPECT_GT(hidden, 1000u);
  EXPECT_GT(visible, 500u);
}

TEST(LineVisibility, RaysEqualEverySampleEvaluatedOnACsgSurface) {
  const TwoSpheres& s = scene();
  std::size_t hidden = 0, visible = 0;
  expect_exhaustive_flags(*s.field, s.particles, s.camera, test_lines(), hidden, visible);
  expect_exhaustive_flags(*s.field, s.particles, s.camera, particles_as_points(s.particles), hidden,
                          visible);
  EXPECT_GT(hidden, 1000u);
  EXPECT_GT(visible, 1000u);
}

TEST(LineVisibility, RejectsBadInput) {
  const TwoSpheres& s = scene();
  std::vector<Polyline> lines = test_lines();
  LineOptions bad;
  bad.occlusion_tolerance = -1;
  EXPECT_THROW(classify_visibility(*s.field, s.particles, s.camera, lines, bad), InvalidArgument);
  Camera cam = s.camera;
  cam.target = cam.eye;
  EXPECT_THROW(classify_visibility(*s.field, s.particles, cam, lines), InvalidArgument);
  EXPECT_THROW(classify_visibility(*s.field, ParticleSystem{}, s.camera, lines), InvalidArgument);
  std::vector<Polyline> nan = test_lines();
  nan[1].points[7].y() = std::nan("");
  EXPECT_THROW(classify_visibility(*s.field, s.particles, s.camera, nan), InvalidArgument);
  // No lines, no particles: nothing to do.
  std::vector<Polyline> none;
  classify_visibility(*s.field, ParticleSystem{}, s.camera, none);
}

}  // namespace
}  // namespace ramiform
