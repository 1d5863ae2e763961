// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The scene language's particle commands: local regeneration through previous= (Proença et al.
// 2008 §3) and its refusals.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "ramiform/io/particles_io.h"
#include "script_fixture.h"

namespace ramiform::test {
namespace {

using PointsCommandsTest = ScriptDirTest;

TEST_F(PointsCommandsTest, PreviousKeepsTheParticlesAwayFromTheEditBoxExactly) {
  ScriptSession s(options_);
  s.run_text(
      "sphere ball 1\n"
      "particles ball count=800 state=before.ply seed=3\n"
      "sphere bump 0.3 center=1,0,0\n"
      "diff ball bump edited\n"
      "particles edited previous=before.ply edit_min=0.6,-0.5,-0.5 edit_max=1.4,0.5,0.5 "
      "state=after.ply name=after\n",
      "t.rf");
  s.commit();
  const ParticleSystem before = read_particles((dir_ / "before.ply").string());
  const ParticleSystem after = read_particles((dir_ / "after.ply").string());
  const Aabb box(Vec3(0.6, -0.5, -0.5), Vec3(1.4, 0.5, 0.5));
  // Particles farther from the box than a replaced cell reaches (cells meeting the box grown
  // by δ are re-seeded: at 800 particles the cells are about 0.26 wide) keep their exact state.
  std::size_t far = 0, kept = 0;
  for (const SurfaceParticle& p : before.particles) {
    if (box.exteriorDistance(p.position) <= 0.35) continue;
    ++far;
    for (const SurfaceParticle& q : after.particles) {
      if (q.position == p.position && q.normal == p.normal && q.delta == p.delta) {
        ++kept;
        break;
      }
    }
  }
  EXPECT_GT(far, 500u);
  EXPECT_EQ(kept, far);
  // The dent: no particle inside the bump's sphere, and particles on its wall.
  const Vec3 c(1, 0, 0);
  std::size_t on_wall = 0;
  for (const SurfaceParticle& q : after.particles) {
    EXPECT_GT((q.position - c).norm(), 0.3 - 1e-3) << q.position.transpose();
    on_wall += std::abs((q.position - c).norm() - 0.3) < 1e-3 ? 1 : 0;
  }
  EXPECT_GT(on_wall, 5u);
}

TEST_F(PointsCommandsTest, PreviousNeedsTheBoxAndTheBoxNeedsPrevious) {
  ScriptSession s(options_);
  s.run_text("sphere ball 1\nparticles ball count=200 state=before.ply\n", "t.rf");
  s.commit();
  EXPECT_NE(std::string(error_of("sphere ball 1\nparticles ball previous=before.ply\n").what())
                .find("needs edit_min=X,Y,Z and edit_max=X,Y,Z"),
            std::string::npos);
  EXPECT_NE(
      std::string(error_of("sphere ball 1\nparticles ball edit_min=0,0,0 edit_max=1,1,1\n").what())
          .find("need previous=STATE.ply"),
      std::string::npos);
  EXPECT_NE(std::string(error_of("sphere ball 1\nparticles ball previous=before.ply "
                                 "edit_min=1,1,1 edit_max=0,0,0\n")
                            .what())
                .find("edit_max is below edit_min"),
            std::string::npos);
  // An MPU shape of other iso than the sphere's: the saved particles do not belong to it.
  {
    std::ofstream points(dir_ / "ball.xyz");
    for (int i = 0; i < 400; ++i) {
      const double z = 1 - (2 * i + 1) / 400.0, r = std::sqrt(1 - z * z), a = 2.39996 * i;
      points << r * std::cos(a) << ' ' << r * std::sin(a) << ' ' << z << ' ' << r * std::cos(a)
             << ' ' << r * std::sin(a) << ' ' << z << '\n';
    }
  }
  EXPECT_NE(std::string(error_of("mpu m ball.xyz iso=0.123\nparticles m previous=before.ply "
                                 "edit_min=0,0,0 edit_max=1,1,1\n")
                            .what())
                .find("lie on iso"),
            std::string::npos);
}

}  // namespace
}  // namespace ramiform::test
