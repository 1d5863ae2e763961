// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "ramiform/core/errors.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/primitives.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform {
namespace {

FieldPtr sphere(const Vec3& c, double r) { return make_box_field(c, Vec3::Constant(r), r); }

bool same_particle(const SurfaceParticle& a, const SurfaceParticle& b) {
  return std::memcmp(a.position.data(), b.position.data(), sizeof(double) * 3) == 0 &&
         std::memcmp(a.normal.data(), b.normal.data(), sizeof(double) * 3) == 0 &&
         std::memcmp(&a.delta, &b.delta, sizeof(double)) == 0;
}

// A unit sphere, then the same sphere with a bump (a small sphere, blended by union) at its
// north pole, all of the change inside the edit box.
TEST(RegenerateParticles, KeepsParticlesAwayFromTheEditAndSpreadsNewOnes) {
  const FieldPtr before = sphere(Vec3::Zero(), 1.0);
  const FieldPtr bump = sphere(Vec3(0, 0, 1.1), 0.3);
  const FieldPtr after = make_union({before, bump});
  const Aabb edit_box(Vec3(-0.45, -0.45, 0.6), Vec3(0.45, 0.45, 1.45));
  ParticleOptions o;
  const ParticleSystem prev = spread_particles(*before, o);
  ParticleStats st;
  const ParticleSystem next = regenerate_particles(*after, prev, edit_box, o, &st);
  ASSERT_GT(st.kept, 0u);
  ASSERT_GT(st.particles, 0u);
  EXPECT_EQ(next.particles.size(), st.kept + st.particles);
  EXPECT_LT(st.kept, prev.particles.size());
  double delta_max = 0;
  for (const SurfaceParticle& p : prev.particles) delta_max = std::max(delta_max, p.delta);
  // Every previous particle outside the box grown by δ is kept exactly.
  const Aabb grown(edit_box.min() - Vec3::Constant(delta_max),
                   edit_box.max() + Vec3::Constant(delta_max));
  std::size_t outside = 0, matched = 0;
  for (const SurfaceParticle& p : prev.particles) {
    if (grown.contains(p.position)) continue;
    ++outside;
    for (std::size_t i = 0; i < st.kept; ++i) {
      if (same_particle(p, next.particles[i])) {
        ++matched;
        break;
      }
    }
  }
  EXPECT_EQ(matched, outside);
  // The kept ones come first, unchanged and in order.
  std::size_t k = 0;
  for (const SurfaceParticle& p : prev.particles) {
    if (k < st.kept && same_particle(p, next.particles[k])) ++k;
  }
  EXPECT_EQ(k, st.kept);
  // The new ones lie on the edited surface, some on the bump, and are well spread.
  std::size_t on_bump = 0;
  for (std::size_t i = st.kept; i < next.particles.size(); ++i) {
    const SurfaceParticle& p = next.particles[i];
    // Distance to the union of the two spheres: |min of the signed distances| (exact outside
    // both, where the surface is).
    const double d =
        std::abs(std::min(p.position.norm() - 1.0, (p.position - Vec3(0, 0, 1.1)).norm() - 0.3));
    ASSERT_LE(d, 1e-4 * p.delta);
    ASSERT_LT(p.cell, next.cells.size());
    on_bump += (p.position - Vec3(0, 0, 1.1)).norm() < 0.31;
  }
  EXPECT_GT(on_bump, 10u);
  EXPECT_LE(st.spacing_cv, 0.25) << st.spacing_cv;
  // Regenerating with an unchanged field keeps the count about the same.
  ParticleStats same;
  const ParticleSystem again = regenerate_particles(*before, prev, edit_box, o, &same);
  EXPECT_NEAR(static_cast<double>(again.particles.size()),
              static_cast<double>(prev.particles.size()),
              0.05 * static_cast<double>(prev.particles.size()));
}

// Kept particles keep their seeding state; new ones get theirs; a previous system without one
// gives a result without one.
TEST(RegenerateParticles, SeedingStateFollowsTheParticles) {
  const FieldPtr before = sphere(Vec3::Zero(), 1.0);
  const FieldPtr after = make_union({before, sphere(Vec3(0, 0, 1.1), 0.3)});
  const Aabb edit_box(Vec3(-0.45, -0.45, 0.6), Vec3(0.45, 0.45, 1.45));
  const ParticleSystem prev = spread_particles(*before);
  ASSERT_TRUE(has_seed_state(prev));
  ParticleStats st;
  const ParticleSystem next = regenerate_particles(*after, prev, edit_box, {}, &st);
  ASSERT_TRUE(has_seed_state(next));
  ASSERT_GT(st.kept, 0u);
  ASSERT_GT(st.particles, 0u);
  // Kept: the previous particle's seeding state, byte for byte (matched in order).
  std::size_t k = 0;
  for (std::size_t i = 0; i < prev.particles.size() && k < st.kept; ++i) {
    if (!same_particle(prev.particles[i], next.particles[k])) continue;
    ASSERT_EQ(std::memcmp(prev.seed_positions[i].data(), next.seed_positions[k].data(), 24), 0);
    ASSERT_EQ(std::memcmp(prev.seed_normals[i].data(), next.seed_normals[k].data(), 24), 0);
    ++k;
  }
  EXPECT_EQ(k, st.kept);
  // New: seeded on the edited surface, the normal −∇f/|∇f| there.
  for (std::size_t i = st.kept; i < next.particles.size(); ++i) {
    const Vec3& s = next.seed_positions[i];
    ASSERT_LE(std::abs(after->value(s) - after->iso()) / after->gradient(s).norm(),
              1e-3 * next.particles[i].delta);
    ASSERT_LE((next.seed_normals[i] + after->gradient(s).normalized()).norm(), 1e-12);
  }
  ParticleSystem bare = prev;
  bare.seed_positions.clear();
  bare.seed_normals.clear();
  const ParticleSystem none = regenerate_particles(*after, bare, edit_box);
  EXPECT_FALSE(has_seed_state(none));
  EXPECT_TRUE(none.seed_positions.empty());
  EXPECT_TRUE(none.seed_normals.empty());
  EXPECT_EQ(none.particles.size(), next.particles.size());
}

TEST(RegenerateParticles, IdenticalOnOneAndTwoThreads) {
  const FieldPtr before = make_circle_field(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.3);
  const FieldPtr after = make_union({before, sphere(Vec3(1, 0, 0.3), 0.15)});
  const Aabb edit_box(Vec3(0.7, -0.3, 0.0), Vec3(1.3, 0.3, 0.6));
  const Context one(1), two(2);
  ParticleOptions o;
  o.per_cell = 2;
  const ParticleSystem prev = spread_particles(*before, o, {}, {}, nullptr, &one);
  const ParticleSystem a = regenerate_particles(*after, prev, edit_box, o, nullptr, &one);
  const ParticleSystem b = regenerate_particles(*after, prev, edit_box, o, nullptr, &two);
  ASSERT_GT(a.particles.size(), prev.particles.size() / 2);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    ASSERT_TRUE(same_particle(a.particles[i], b.particles[i])) << i;
    ASSERT_EQ(a.particles[i].cell, b.particles[i].cell);
  }
}

TEST(RegenerateParticles, RemovingAPartRemovesItsParticlesOnly) {
  const FieldPtr a = sphere(Vec3(-2, 0, 0), 1.0);
  const FieldPtr both = make_union({a, sphere(Vec3(2, 0, 0), 0.5)});
  const ParticleSystem prev = spread_particles(*both);
  const Aabb edit_box(Vec3(1.2, -0.8, -0.8), Vec3(2.8, 0.8, 0.8));
  ParticleStats st;
  const ParticleSystem next = regenerate_particles(*a, prev, edit_box, {}, &st);
  std::size_t on_a = 0;
  for (const SurfaceParticle& p : prev.particles) on_a += p.position.x() < 0 ? 1 : 0;
  ASSERT_GT(on_a, 0u);
  EXPECT_EQ(st.particles, 0u);
  ASSERT_EQ(next.particles.size(), on_a);
  std::size_t k = 0;
  for (const SurfaceParticle& p : prev.particles) {
    if (p.position.x() >= 0) continue;
    ASSERT_TRUE(same_particle(p, next.particles[k]));
    ASSERT_LT(next.particles[k].cell, next.cells.size());
    EXPECT_TRUE(next.cells[next.particles[k].cell].box.isApprox(prev.cells[p.cell].box));
    ++k;
  }
  for (const ParticleCell& c : next.cells) EXPECT_LT(c.box.min().x(), 0.0);
}

TEST(RegenerateParticles, RefusesAnotherIsoAndEmptyBox) {
  const FieldPtr f = sphere(Vec3::Zero(), 1.0);
  const ParticleSystem prev = spread_particles(*f);
  EXPECT_THROW((void)regenerate_particles(*f, prev, Aabb()), InvalidArgument);
  ParticleSystem other = prev;
  other.iso += 0.1;
  EXPECT_THROW((void)regenerate_particles(*f, other, Aabb(Vec3::Zero(), Vec3::Ones())),
               InvalidArgument);
}

}  // namespace
}  // namespace ramiform
