// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform reconstruct` and `ramiform particles` as a user runs them, and the scene commands
// `mpu` and `particles`: generated clouds (sphere, torus) with exact answers, the shared models
// when ../shared/data is there, and the bad inputs a user feeds them.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli/cli_run.h"
#include "field/point_cloud_fixtures.h"
#include "ramiform/core/random.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/mesh/checks.h"
#include "support/mesh_checkers.h"

namespace ramiform {
namespace {

using test::CliRun;
using test::read_json;
using test::run_cli;

class ReconstructCliTest : public test::CliDirTest {
 protected:
  /// Writes `cloud` as "x y z [nx ny nz]" text; with `flip_every` > 0 every flip_every-th
  /// normal is reversed, with `drop_normals` they are left out.
  std::string cloud_file(const std::string& name, PointSet cloud, int flip_every = 0,
                         bool drop_normals = false) const {
    if (drop_normals) cloud.normals.clear();
    for (std::size_t i = 0; flip_every > 0 && i < cloud.normals.size(); i += flip_every) {
      cloud.normals[i] = -cloud.normals[i];
    }
    write_points(cloud, path(name));
    return path(name);
  }

  /// Reconstructs `input` with `extra` options; expects success and returns the mesh and stats.
  std::pair<TriMesh, nlohmann::json> reconstruct(const std::string& input,
                                                 const std::string& extra = "") const {
    const std::string out = path("out.ply");
    const std::string stats = path("stats.json");
    const CliRun r =
        run_cli("reconstruct " + input + " -o " + out + " --stats " + stats + " " + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    if (r.code != 0) return {};
    return {read_mesh(out), read_json(stats)};
  }
};

// Every vertex lies on the sphere (within a small fraction of its radius), the mesh is one
// closed sphere, and the surface passes through the points.
void expect_sphere_mesh(const TriMesh& mesh, const nlohmann::json& stats, double tolerance) {
  test::expect_closed_surface(mesh, 1, 2);
  double worst = 0;
  for (const Vec3& v : mesh.positions) worst = std::max(worst, std::abs(v.norm() - 1.0));
  EXPECT_LT(worst, tolerance);
  EXPECT_GT(signed_volume(mesh), 0.9 * 4.0 / 3.0 * std::numbers::pi);  // outward, whole
  EXPECT_LT(stats["interpolation"]["median"].get<double>(), 1e-3);
}

TEST_F(ReconstructCliTest, SphereWithGivenMissingFlippedAndInvertedNormals) {
  const PointSet cloud = test::sphere_cloud(3000);
  {
    const auto [mesh, stats] = reconstruct(cloud_file("given.xyz", cloud));
    expect_sphere_mesh(mesh, stats, 0.01);
    EXPECT_EQ(stats["normals"]["estimated"], 0);
    EXPECT_EQ(stats["normals"]["flipped"], 0);
    EXPECT_EQ(stats["points"], 3000);
  }
  {
    const auto [mesh, stats] = reconstruct(cloud_file("none.xyz", cloud, 0, true));
    expect_sphere_mesh(mesh, stats, 0.01);
    EXPECT_EQ(stats["normals"]["estimated"], 3000);
  }
  {
    // Every fifth normal reversed: 600 are found and turned back.
    const auto [mesh, stats] = reconstruct(cloud_file("some.xyz", cloud, 5));
    expect_sphere_mesh(mesh, stats, 0.01);
    EXPECT_EQ(stats["normals"]["flipped"], 600);
  }
  {
    // Every normal inward.
    const auto [mesh, stats] = reconstruct(cloud_file("all.xyz", cloud, 1));
    expect_sphere_mesh(mesh, stats, 0.01);
    EXPECT_EQ(stats["normals"]["flipped"], 3000);
  }
}

TEST_F(ReconstructCliTest, TorusKeepsItsHoleAndCellSizeOptionsApply) {
  const std::string in = cloud_file("torus.xyz", test::torus_cloud(4000, 3));
  const auto [mesh, stats] = reconstruct(in);
  test::expect_closed_surface(mesh, 1, 0);  // genus 1
  double worst = 0;
  for (const Vec3& v : mesh.positions) worst = std::max(worst, std::abs(test::torus_distance(v)));
  EXPECT_LT(worst, 0.02);
  // The default cell is one point spacing (sqrt(area / points) for these random points).
  const double area =
      4 * std::numbers::pi * std::numbers::pi * test::kTorusMajor * test::kTorusMinor;
  EXPECT_NEAR(stats["spacing"].get<double>(), std::sqrt(area / 4000), 0.1 * std::sqrt(area / 4000));
  EXPECT_EQ(stats["mesh"]["cell_size"].get<double>(), stats["spacing"].get<double>());
  // A coarser grid: fewer triangles, still one closed torus.
  const auto [coarse, coarse_stats] = reconstruct(in, "--cell-size 0.08");
  test::expect_closed_surface(coarse, 1, 0);
  EXPECT_LT(coarse.triangles.size(), mesh.triangles.size() / 1.4);
  EXPECT_EQ(coarse_stats["mesh"]["cell_size"].get<double>(), 0.08);
}

TEST_F(ReconstructCliTest, MeshInputIsSampledWithItsFaceNormals) {
  // A closed sphere mesh made by ramiform itself (marching cubes), as OFF.
  const std::string scene =
      write("ball.rf", "sphere ball 1\nsave_mesh ball ball.off method=mc resolution=40\n");
  const CliRun made = run_cli("run " + scene + " --out " + path(""));
  ASSERT_EQ(made.code, 0) << made.out;
  const std::string ball = path("ball.off");
  const TriMesh source = read_mesh(ball);
  const auto [mesh, stats] = reconstruct(ball, "--mesh-samples 5000 --seed 4");
  test::expect_closed_surface(mesh, 1, 2);
  EXPECT_EQ(stats["mesh_input"]["triangles"], source.triangles.size());
  EXPECT_EQ(stats["points"], 5000);
  EXPECT_EQ(stats["normals"]["flipped"], 0);
  // The same seed gives the same file.
  const std::string first = test::read_file(path("out.ply"));
  (void)reconstruct(ball, "--mesh-samples 5000 --seed 4 --threads 1");
  EXPECT_EQ(test::read_file(path("out.ply")), first);
}

TEST_F(ReconstructCliTest, BadInputsExitTwoNamingTheProblemAndWriteNothing) {
  const std::string out = path("out.ply");
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {"0 0 0 0 0 1\n1 0 0 0 0 0\n", ":2: zero normal"},
      {"0 0 0\n1 0 0\n", "points"},  // too few points to fit anything
      {"0 0 0 1 0 0\n1 0 nan 1 0 0\n", ":2:"},
      {"", "empty"},
  };
  for (const Case& c : cases) {
    const std::string in = write("bad.xyz", c.text);
    const CliRun r = run_cli("reconstruct " + in + " -o " + out);
    EXPECT_EQ(r.code, 2) << c.text << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expected), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(out));
  }
  const CliRun missing = run_cli("reconstruct " + path("nope.xyz") + " -o " + out);
  EXPECT_EQ(missing.code, 2) << missing.out;
  EXPECT_NE(missing.out.find("nope.xyz"), std::string::npos) << missing.out;
  const CliRun bad_ext = run_cli("reconstruct " + path("nope.xyz") + " -o " + path("x.stl"));
  EXPECT_EQ(bad_ext.code, 2) << bad_ext.out;
}

TEST_F(ReconstructCliTest, ParticlesOnAScriptShapeLieOnItAndRegenerateLocally) {
  const std::string scene = write("scene.rf", "sphere ball 1\n");
  const std::string state = path("p.ply");
  const std::string stats = path("s.json");
  CliRun r = run_cli("particles " + scene + ":ball -o " + state + " --count 2000 --stats " + stats);
  ASSERT_EQ(r.code, 0) << r.out;
  const ParticleSystem sys = read_particles(state);
  const nlohmann::json s = read_json(stats);
  EXPECT_EQ(s["particles"], sys.particles.size());
  EXPECT_NEAR(static_cast<double>(sys.particles.size()), 2000.0, 200.0);
  EXPECT_LT(s["spacing_cv"].get<double>(), 0.3);
  // The scene's sphere has radius 1 at iso: every particle on it, normals radial.
  for (const SurfaceParticle& p : sys.particles) {
    const double on = p.position.norm() - 1.0;
    EXPECT_LE(std::abs(on), 1e-3 * p.delta) << p.position.transpose();
    EXPECT_GT(p.normal.dot(p.position.normalized()), 0.999);
  }
  // One thread or two: the same bytes.
  const std::string one = path("one.ply");
  ASSERT_EQ(run_cli("particles " + scene + ":ball -o " + one + " --count 2000 --threads 1").code,
            0);
  EXPECT_EQ(test::read_file(one), test::read_file(state));
  // Regenerate after an "edit" confined to a box: the particles far from it stay as they were.
  const std::string regen = path("r.ply");
  r = run_cli("particles " + scene + ":ball -o " + regen + " --previous " + state +
              " --edit-box 0.5,-0.3,-0.3,1.2,0.3,0.3");
  ASSERT_EQ(r.code, 0) << r.out;
  const ParticleSystem after = read_particles(regen);
  std::size_t kept = 0;
  for (const SurfaceParticle& p : sys.particles) {
    if (p.position.x() > 0.2) continue;  // possibly re-simulated near the box
    for (const SurfaceParticle& q : after.particles) {
      if (q.position == p.position) {
        ++kept;
        break;
      }
    }
  }
  std::size_t far = 0;
  for (const SurfaceParticle& p : sys.particles) far += p.position.x() > 0.2 ? 0 : 1;
  EXPECT_EQ(kept, far);
  // Unknown shape: exit 2 naming it.
  r = run_cli("particles " + scene + ":bal -o " + path("x.ply"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("did you mean 'ball'"), std::string::npos) << r.out;
}

TEST_F(ReconstructCliTest, ParticlesOnASkeletonsSurface) {
  const std::string out = path("p.xyz");
  const std::string stats = path("s.json");
  const CliRun r =
      run_cli("particles " + y_fork() + " -o " + out + " --count 1500 --stats " + stats);
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json s = read_json(stats);
  EXPECT_EQ(s["input"], "skeleton");
  EXPECT_LE(s["residual_max"].get<double>(), 1e-4);
  const PointSet p = read_points(out);
  EXPECT_EQ(p.size(), s["particles"].get<std::size_t>());
  EXPECT_NEAR(static_cast<double>(p.size()), 1500.0, 300.0);
  // On the surface: `eval` gives the field's value there, the iso value (0 for the default
  // convolution surface, whose iso is reported by eval) up to the residual.
  const CliRun e = run_cli("eval " + y_fork() + " --points " + out);
  ASSERT_EQ(e.code, 0) << e.out;
  std::istringstream lines(e.out);
  std::string line;
  std::size_t n = 0;
  double worst = 0;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    worst = std::max(worst, std::abs(std::stod(line) - s["iso"].get<double>()));
    ++n;
  }
  EXPECT_EQ(n, p.size());
  EXPECT_LT(worst, 1e-3);
}

TEST_F(ReconstructCliTest, SceneMpuBlendsWithModelledShapesAndSpreadsParticles) {
  cloud_file("cloud.xyz", test::sphere_cloud(2000, 1.0, Vec3(0, 0, 0)));
  const std::string scene = write("scene.rf",
                                  "mpu scan cloud.xyz\n"
                                  "sphere ball 0.6 center=1.2,0,0\n"
                                  "union scan ball both\n"
                                  "save_mesh both both.ply method=mc resolution=60\n"
                                  "particles scan count=1500 name=p\n"
                                  "save_point_set p.xyz p\n");
  const CliRun r = run_cli("run " + scene + " --out " + path(""));
  ASSERT_EQ(r.code, 0) << r.out;
  const TriMesh both = read_mesh(path("both.ply"));
  test::expect_closed_surface(both, 1, 2);
  const PointSet p = read_points(path("p.xyz"));
  EXPECT_NEAR(static_cast<double>(p.size()), 1500.0, 150.0);
  for (const Vec3& q : p.positions) EXPECT_NEAR(q.norm(), 1.0, 0.01);
}

TEST_F(ReconstructCliTest, SharedModelsAreWatertightSinglePiecesThroughTheirPoints) {
  const auto dir = test::models_dir();
  if (dir.empty()) GTEST_SKIP() << "../shared/data/models absent: a clone skips the model tests";
  for (const char* model : {"kitten.xyz", "oni.pwn", "bunny.ply", "cow.off"}) {
    SCOPED_TRACE(model);
    const auto [mesh, stats] = reconstruct((dir / model).string());
    test::expect_closed_manifold(mesh);
    EXPECT_EQ(check_mesh(mesh).components, 1u);
    EXPECT_LT(stats["interpolation"]["median"].get<double>(), 1e-3);
    EXPECT_GT(signed_volume(mesh), 0.0);
  }
}

}  // namespace
}  // namespace ramiform
