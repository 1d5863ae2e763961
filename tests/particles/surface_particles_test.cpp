// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/particles/surface_particles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/primitives.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

// A sphere of radius r: the distance surface of a point (a box shrunk to its centre).
FieldPtr sphere(const Vec3& c, double r) { return make_box_field(c, Vec3::Constant(r), r); }

double sphere_distance(const Vec3& p, const Vec3& c, double r) {
  return std::abs((p - c).norm() - r);
}

// Torus around the z axis through the origin.
double torus_distance(const Vec3& p, double R, double r) {
  const double q = std::hypot(p.x(), p.y()) - R;
  return std::abs(std::hypot(q, p.z()) - r);
}

bool same_bytes(const std::vector<SurfaceParticle>& a, const std::vector<SurfaceParticle>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(a[i].position.data(), b[i].position.data(), sizeof(double) * 3) != 0 ||
        std::memcmp(a[i].normal.data(), b[i].normal.data(), sizeof(double) * 3) != 0 ||
        std::memcmp(&a[i].delta, &b[i].delta, sizeof(double)) != 0 || a[i].cell != b[i].cell) {
      return false;
    }
  }
  return true;
}

TEST(SurfaceParticles, SphereParticlesOnTheSurfaceAndEvenlySpread) {
  const Vec3 c(0.3, -0.2, 0.1);
  const double r = 1.0;
  const FieldPtr f = sphere(c, r);
  ParticleOptions o;
  ParticleStats st;
  const ParticleSystem ps = spread_particles(*f, o, {}, {}, &st);
  ASSERT_GT(ps.particles.size(), 500u);
  EXPECT_EQ(st.particles, ps.particles.size());
  EXPECT_EQ(st.dropped, 0u);
  for (const SurfaceParticle& p : ps.particles) {
    ASSERT_LE(sphere_distance(p.position, c, r), 1e-4 * p.delta);
    EXPECT_NEAR(p.normal.dot((p.position - c).normalized()), 1.0, 1e-9);
    ASSERT_LT(p.cell, ps.cells.size());
  }
  EXPECT_LE(st.residual_max, 1e-4);
  // Measured 0.07-0.08 (see docs); a random placement gives about 0.5.
  EXPECT_LE(st.spacing_cv, 0.15) << "spacing CV " << st.spacing_cv;
  // The particle count follows per_cell: k per cell on average.
  EXPECT_NEAR(static_cast<double>(ps.particles.size()) / static_cast<double>(ps.cells.size()), 4.0,
              0.5);
}

TEST(SurfaceParticles, TorusParticlesOnTheSurfaceAndEvenlySpread) {
  const double R = 1.0, r = 0.35;
  const FieldPtr f = make_circle_field(Vec3::Zero(), Vec3::UnitZ(), R, r);
  ParticleStats st;
  const ParticleSystem ps = spread_particles(*f, {}, {}, {}, &st);
  ASSERT_GT(ps.particles.size(), 500u);
  for (const SurfaceParticle& p : ps.particles)
    ASSERT_LE(torus_distance(p.position, R, r), 1e-4 * p.delta);
  EXPECT_LE(st.spacing_cv, 0.2) << "spacing CV " << st.spacing_cv;
}

TEST(SurfaceParticles, CountIsHonoured) {
  const FieldPtr f = sphere(Vec3::Zero(), 2.0);
  ParticleOptions o;
  o.count = 3000;
  const ParticleSystem ps = spread_particles(*f, o);
  EXPECT_NEAR(static_cast<double>(ps.particles.size()), 3000.0, 30.0);
}

TEST(SurfaceParticles, CountsAboveTheMemoryBudgetAreRefusedBeforeSpreading) {
  // Each particle keeps at least its state and its seed state (112 bytes): 100,000 particles
  // need 11.2 MB, more than a 1 MB budget; 3,000 (336 kB) fit.
  const FieldPtr f = sphere(Vec3::Zero(), 2.0);
  ParticleOptions o;
  o.count = 100000;
  Context ctx;
  ctx.set_max_memory(1'000'000);
  try {
    (void)spread_particles(*f, o, {}, {}, nullptr, &ctx);
    ADD_FAILURE() << "no ResourceLimit";
  } catch (const ResourceLimit& e) {
    EXPECT_NE(
        std::string(e.what()).find("100000 surface particles need at least 11.2 MB of memory"),
        std::string::npos)
        << e.what();
  }
  o.count = 3000;
  EXPECT_NEAR(static_cast<double>(spread_particles(*f, o, {}, {}, nullptr, &ctx).particles.size()),
              3000.0, 30.0);
}

TEST(SurfaceParticles, AdaptiveCellsConcentrateParticlesWhereCurvatureIsHigh) {
  // A thin torus (high curvature) next to a big sphere (low curvature): cells are deeper and
  // particles denser on the torus.
  const FieldPtr torus = make_circle_field(Vec3(3, 0, 0), Vec3::UnitZ(), 0.8, 0.1);
  const FieldPtr ball = sphere(Vec3(-1, 0, 0), 1.5);
  const FieldPtr f = make_union({torus, ball});
  ParticleOptions o;
  o.per_cell = 1;  // the density ratio does not depend on k
  ParticleStats st;
  const ParticleSystem ps = spread_particles(*f, o, {}, {}, &st);
  std::size_t on_torus = 0, on_ball = 0;
  double delta_torus = 0, delta_ball = 0;
  for (const SurfaceParticle& p : ps.particles) {
    if (p.position.x() > 1.5) {
      ++on_torus;
      delta_torus = std::max(delta_torus, p.delta);
    } else {
      ++on_ball;
      delta_ball = std::max(delta_ball, p.delta);
    }
  }
  const double area_torus = 4 * M_PI * M_PI * 0.8 * 0.1;
  const double area_ball = 4 * M_PI * 1.5 * 1.5;
  const double density_ratio = (on_torus / area_torus) / (on_ball / area_ball);
  EXPECT_GT(density_ratio, 4.0) << on_torus << " on the torus, " << on_ball << " on the ball";
  EXPECT_LT(delta_torus, 0.5 * delta_ball);
  for (const SurfaceParticle& p : ps.particles)
    ASSERT_LE(std::abs(f->value(p.position) - f->iso()) / f->gradient(p.position).norm(),
              1e-4 * p.delta);
}

TEST(SurfaceParticles, IdenticalOnOneAndTwoThreads) {
  const FieldPtr f = make_circle_field(Vec3::Zero(), Vec3(0.2, 0.1, 1), 1.0, 0.3);
  ParticleOptions o;
  o.count = 2000;
  const Context one(1), two(2);
  const ParticleSystem a = spread_particles(*f, o, {}, {}, nullptr, &one);
  const ParticleSystem b = spread_particles(*f, o, {}, {}, nullptr, &two);
  EXPECT_TRUE(same_bytes(a.particles, b.particles));
  ASSERT_EQ(a.cells.size(), b.cells.size());
  ASSERT_TRUE(has_seed_state(a));
  ASSERT_TRUE(has_seed_state(b));
  EXPECT_EQ(std::memcmp(a.seed_positions.data(), b.seed_positions.data(),
                        a.seed_positions.size() * sizeof(Vec3)),
            0);
  EXPECT_EQ(std::memcmp(a.seed_normals.data(), b.seed_normals.data(),
                        a.seed_normals.size() * sizeof(Vec3)),
            0);
}

// The seeding state: where each particle started (on the surface, before the simulation) and
// the normal there, −∇f/|∇f| at that point; the simulation then moved the particles.
TEST(SurfaceParticles, KeepTheirSeedingState) {
  const Vec3 c(0.3, -0.2, 0.1);
  const double r = 1.0;
  const FieldPtr f = sphere(c, r);
  ParticleOptions o;
  o.count = 1500;
  const ParticleSystem ps = spread_particles(*f, o);
  ASSERT_TRUE(has_seed_state(ps));
  double moved = 0;
  for (std::size_t i = 0; i < ps.particles.size(); ++i) {
    const Vec3& s = ps.seed_positions[i];
    const Vec3& n = ps.seed_normals[i];
    ASSERT_LE(sphere_distance(s, c, r), 1e-3 * ps.particles[i].delta) << i;
    ASSERT_NEAR(n.norm(), 1.0, 1e-12);
    const Vec3 expected = -f->gradient(s).normalized();
    ASSERT_LE((n - expected).norm(), 1e-12) << i;
    // On a sphere the normal is the radial direction.
    ASSERT_LE((n - (s - c).normalized()).norm(), 1e-3) << i;
    moved = std::max(moved, (ps.particles[i].position - s).norm() / ps.particles[i].delta);
  }
  EXPECT_GT(moved, 0.01);  // the simulation moved them
  // Without steps the seeds are only projected: position within the projection, same normal.
  o.iterations = 0;
  const ParticleSystem still = spread_particles(*f, o);
  ASSERT_TRUE(has_seed_state(still));
  for (std::size_t i = 0; i < still.particles.size(); ++i) {
    ASSERT_EQ(still.seed_normals[i], still.particles[i].normal);
    ASSERT_LE((still.seed_positions[i] - still.particles[i].position).norm(),
              1e-3 * still.particles[i].delta);
  }
}

TEST(SurfaceParticles, SeedsAreUsedAndCallerCellsKept) {
  const FieldPtr f = sphere(Vec3::Zero(), 1.0);
  const std::vector<ParticleCell> cells = adaptive_cells(*f);
  ASSERT_FALSE(cells.empty());
  std::vector<Vec3> seeds;
  for (int i = 0; i < 2000; ++i) {
    const double z = -1 + 2 * (i + 0.5) / 2000, t = i * 2.399963;
    const double s = std::sqrt(1 - z * z);
    seeds.emplace_back(1.001 * s * std::cos(t), 1.001 * s * std::sin(t), 1.001 * z);
  }
  ParticleOptions o;
  o.iterations = 0;  // the seeds as they are, projected onto the surface
  const ParticleSystem ps = spread_particles(*f, o, cells, seeds);
  ASSERT_EQ(ps.cells.size(), cells.size());
  ASSERT_GT(ps.particles.size(), cells.size());
  for (const SurfaceParticle& p : ps.particles) {
    ASSERT_LE(sphere_distance(p.position, Vec3::Zero(), 1.0), 1e-4 * p.delta);
    const Aabb& b = ps.cells[p.cell].box;
    ASSERT_LE(std::sqrt(squared_distance(b, p.position)), 0.25 * b.sizes().maxCoeff());
    // Every cell holds about 7 seeds and wants about 4 particles: each particle is a seed
    // moved along the gradient (radially, on a sphere).
    double best = -1;
    for (const Vec3& s : seeds) best = std::max(best, s.normalized().dot(p.position.normalized()));
    ASSERT_GT(best, 1 - 1e-12);
  }
}

TEST(SurfaceParticles, BadOptionsAreRefused) {
  const FieldPtr f = sphere(Vec3::Zero(), 1.0);
  ParticleOptions o;
  o.per_cell = 0;
  EXPECT_THROW((void)spread_particles(*f, o), InvalidArgument);
  o = {};
  o.flatness_deg = 0;
  EXPECT_THROW((void)adaptive_cells(*f, o), InvalidArgument);
  o = {};
  o.max_depth = 40;
  EXPECT_THROW((void)adaptive_cells(*f, o), InvalidArgument);
  const std::vector<ParticleCell> bad{{Aabb(Vec3::Zero(), Vec3::Zero()), 1}};
  EXPECT_THROW((void)spread_particles(*f, {}, bad), InvalidArgument);
}

TEST(SurfaceParticles, CancelledThroughTheContext) {
  const FieldPtr f = sphere(Vec3::Zero(), 1.0);
  Context ctx(1);
  ctx.cancel();
  EXPECT_THROW((void)spread_particles(*f, {}, {}, {}, nullptr, &ctx), Cancelled);
}

TEST(SurfaceParticles, ReportsProgressAndHandlesEmptyAndUnboundedFields) {
  const FieldPtr f = sphere(Vec3::Zero(), 1.0);
  Context ctx(2);
  double last_simulate = -1;
  int reports = 0;
  ctx.set_progress([&](const std::string& stage, double fraction) {
    ++reports;
    if (stage == "particles: simulate") last_simulate = fraction;
  });
  (void)spread_particles(*f, {}, {}, {}, nullptr, &ctx);
  EXPECT_GT(reports, 20);
  EXPECT_EQ(last_simulate, 1.0);
  // Nothing inside: no cells, no particles.
  const FieldPtr empty = make_difference(sphere(Vec3::Zero(), 1.0), sphere(Vec3::Zero(), 2.0));
  ParticleStats st;
  const ParticleSystem none = spread_particles(*empty, {}, {}, {}, &st);
  EXPECT_TRUE(none.particles.empty());
  EXPECT_EQ(st.particles, 0u);
  // A half-space has no finite bounds: the cells must be passed.
  const FieldPtr plane = make_plane_field(Vec3::Zero(), Vec3::UnitZ(), 1.0);
  EXPECT_THROW((void)adaptive_cells(*plane), InvalidArgument);
  const std::vector<ParticleCell> cells{{Aabb(Vec3(-1, -1, -0.5), Vec3(1, 1, 0.5)), 0}};
  const ParticleSystem flat = spread_particles(*plane, {}, cells);
  ASSERT_EQ(flat.particles.size(), 4u);
  for (const SurfaceParticle& p : flat.particles) {
    EXPECT_LE(std::abs(p.position.z()), 1e-4 * p.delta);
    EXPECT_NEAR(p.normal.z(), 1.0, 1e-12);
  }
}

TEST(SurfaceParticles, TenThousandParticles) {
#ifdef RAMIFORM_TEST_SANITIZED
  const std::size_t n = 2000;
#else
  const std::size_t n = 10000;
#endif
  const FieldPtr f = sphere(Vec3::Zero(), 1.0);
  ParticleOptions o;
  o.count = n;
  ParticleStats st;
  const ParticleSystem ps = spread_particles(*f, o, {}, {}, &st);
  EXPECT_NEAR(static_cast<double>(ps.particles.size()), static_cast<double>(n), 0.01 * n);
  EXPECT_EQ(st.iterations, 20);
  EXPECT_LE(st.spacing_cv, 0.15);
}

}  // namespace
}  // namespace ramiform
