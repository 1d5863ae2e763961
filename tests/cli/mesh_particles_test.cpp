// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform mesh --method particles` (Gruber & Wallner 2014, docs/equipotential.md) as a user
// runs it, on the skeletons the issue names: generated trees of 10 to 5,000 segments, the
// L-system examples and the paper's Figures 6 and 7, the two real cylinder models of
// ../shared/data/trees (skipped without it), a 20-degree fork and near-parallel branches. On
// every one, checked here and not taken from the stats: every particle converged, the mesh is a
// closed, consistently oriented 2-manifold with one component per connected skeleton, every
// skeleton node lies inside it (generalized winding number), and its vertices lie on the
// equipotential surface (`ramiform check --deviation --surface equipotential`). The same field
// meshed by the tetrahedral polygonizer agrees with the particle mesh to within both meshes'
// distance to the surface. Where the surfaces of branches not joined in the skeleton merge (the
// generated trees' crowded crowns, the scanned trees) the mesh folds: the folds are counted
// (`inverted_triangles`, recounted here), and on the 5,000-segment tree two nodes in such a
// fold fall outside the mesh (docs/equipotential.md, "What is weak"). Chains of short edges,
// sharp bends and short leaves (the scanned trees' other folds) must not fold, nor leave their
// nodes outside.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "cli/cli_run.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/skeleton/skeleton.h"
#include "support/mesh_checkers.h"

// Under AddressSanitizer (`make sanitize`, CI) the binary runs several times slower: the large
// skeletons (1,000 segments and up, the scanned trees, 300 k-triangle L-systems) run in the
// Release suite (`make test`) only; the small ones cover the same code under the sanitizers.
#ifdef RAMIFORM_TEST_SANITIZED  // support/fixtures.h
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif

namespace ramiform {
namespace {

using test::CliRun;
using test::read_json;
using test::run_cli;

std::string examples_dir() { return std::string(RAMIFORM_SOURCE_DIR) + "/examples/data/"; }

/// What one particle mesh of a skeleton file gave.
struct ParticleRun {
  nlohmann::json stats;  // the --stats file
  nlohmann::json check;  // ramiform check --deviation ... --json
  TriMesh mesh;
};

class MeshParticlesTest : public test::CliDirTest {
 protected:
  /// Writes `generate SKEL --segments N --seed S` and returns its path.
  std::string generated(std::size_t segments, int seed = 1, const std::string& extra = "") const {
    const std::string out = path("tree" + std::to_string(segments) + ".json");
    const CliRun r = run_cli("generate " + out + " --segments " + std::to_string(segments) +
                             " --seed " + std::to_string(seed) + " " + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    return out;
  }

  /// Writes the skeleton of an L-system (a built-in example or a file) and returns its path.
  std::string lsystem(const std::string& source, int iterations, const std::string& name) const {
    const std::string out = path(name + ".json");
    const CliRun r =
        run_cli("lsystem " + source + " --iterations " + std::to_string(iterations) + " -o " + out);
    EXPECT_EQ(r.code, 0) << r.out;
    return out;
  }

  /// `mesh SKEL --method particles EXTRA`, then every property of the issue checked on the file
  /// written: the mesh is read back, checked and holds the skeleton's nodes; its deviation from
  /// the equipotential surface (the field options in `field_args`, which EXTRA must repeat) is
  /// measured by `ramiform check`.
  /// `deviation`: also run `ramiform check --deviation`, which projects every vertex onto the
  /// surface (minutes for a million particles: small skeletons only).
  ParticleRun mesh_and_check(const std::string& skeleton, const std::string& extra = "",
                             const std::string& field_args = "", std::size_t max_nodes_outside = 0,
                             bool deviation = true) const {
    ParticleRun run;
    const std::string out = path("particles.ply");
    const std::string stats = path("particles.json");
    const CliRun r = run_cli("mesh " + skeleton + " -o " + out + " --method particles --stats " +
                             stats + " " + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    if (r.code != 0) return run;
    run.stats = read_json(stats);
    const std::size_t particles = run.stats.at("particles").get<std::size_t>();
    EXPECT_EQ(run.stats.at("converged").get<std::size_t>(), particles);
    EXPECT_TRUE(run.stats.at("unconverged").empty());
    EXPECT_GT(run.stats.at("charges").get<std::size_t>(), 0U);
    EXPECT_GT(run.stats.at("lambda").get<double>(), 0.0);
    EXPECT_TRUE(run.stats.contains("radius_error_median"));

    run.mesh = read_mesh(out);
    EXPECT_EQ(run.mesh.positions.size(), particles);
    const Skeleton s = read_skeleton(skeleton);
    const MeshReport rep = check_mesh(run.mesh);
    EXPECT_TRUE(rep.watertight) << test::describe(rep);
    EXPECT_TRUE(rep.oriented) << test::describe(rep);
    EXPECT_TRUE(rep.manifold) << test::describe(rep);
    EXPECT_EQ(rep.degenerate_triangles, 0U) << test::describe(rep);
    EXPECT_EQ(rep.components, connected_components(s).count) << test::describe(rep);
    EXPECT_GT(signed_volume(run.mesh), 0.0);
    EXPECT_LE(test::nodes_outside(run.mesh, s), max_nodes_outside)
        << "of " << s.nodes.size() << " nodes";

    if (!deviation) return run;
    const CliRun c = run_cli("check " + out + " --deviation " + skeleton + " " + field_args +
                             " --surface equipotential --samples 4000 --json");
    EXPECT_EQ(c.code, 0) << c.out;
    if (c.code == 0) run.check = nlohmann::json::parse(c.out);
    if (!run.check.is_null()) {
      // The particles are on the surface: |f - lambda| <= 1e-3 lambda, a distance of about
      // 1e-3 |f / grad f|, far below a percent of the radius.
      EXPECT_LE(run.check.at("vertex_deviation_p99").get<double>(), 0.005);
      EXPECT_EQ(run.check.at("vertex_deviation_unresolved").get<std::size_t>(), 0U);
      EXPECT_EQ(run.check.at("deviation_unresolved").get<std::size_t>(), 0U);
    }
    return run;
  }
};

// Triangles whose normal points along the summed field gradient of their corners, counted
// here with the library's equipotential field of the same skeleton (default options).
std::size_t count_inverted(const TriMesh& mesh, const Skeleton& s) {
  return test::triangles_facing_inwards(mesh, *make_equipotential(s).field);
}

TEST_F(MeshParticlesTest, GeneratedTreesFrom10To1000Segments) {
  for (const std::size_t n : {10U, 100U, 1000U}) {
    SCOPED_TRACE(n);
    if (kSanitized && n >= 1000) continue;
    const std::string skel = generated(n);
    const ParticleRun run = mesh_and_check(skel, "", "", 0, n < 1000);
    if (run.stats.is_null()) continue;
    if (!run.check.is_null()) {
      // Between the particles the flat triangles cut the round tubes: a chord of a ring of 12
      // lies 1 - cos(15 deg) = 3.4 % of the radius inside; the blends at forks add a little.
      EXPECT_LE(run.check.at("deviation_p50").get<double>(), 0.03);
      EXPECT_LE(run.check.at("deviation_p99").get<double>(), 0.10);
    }
    // The surface follows the radii without a fit (charges from the radii).
    EXPECT_LE(run.stats.at("radius_error_median").get<double>(), 0.05);
    const std::size_t inverted = run.stats.at("inverted_triangles").get<std::size_t>();
    EXPECT_EQ(inverted, count_inverted(run.mesh, read_skeleton(skel)));
    // Folds only where crowded twigs merge: 303 of 830 k triangles on the 1,000-segment tree.
    EXPECT_LE(static_cast<double>(inverted), 1e-3 * static_cast<double>(run.mesh.triangles.size()));
  }
}

// The 5,000-segment tree (1.1 M particles, about a minute): every node inside. Two nodes of its
// crown, a thin twig's fork and leaf beside a thicker branch they are not joined to, used to
// fall outside when relaxation slid a folded sheet over them; those moves are now undone.
// Joining the branches that run into thicker ones took its folds from 0.40 % of the triangles
// (9,360) to 0.24 % (5,558); not relaxing across nodes to 5,335.
TEST_F(MeshParticlesTest, GeneratedTreeOf5000Segments) {
  if (kSanitized) GTEST_SKIP() << "a minute in Release; run by make test, not under sanitizers";
  const ParticleRun run = mesh_and_check(generated(5000), "", "", 0, false);
  if (run.stats.is_null()) return;
  EXPECT_EQ(run.stats.at("nodes_outside").get<std::size_t>(), 0U);
  EXPECT_LE(run.stats.at("radius_error_median").get<double>(), 0.10);
  EXPECT_GT(run.stats.at("joined_branches").get<std::size_t>(), 0U);
  EXPECT_LE(run.stats.at("inverted_triangles").get<double>(),
            0.003 * static_cast<double>(run.mesh.triangles.size()));
}

TEST_F(MeshParticlesTest, FitRadiiMeetsTheRadiusTargets) {
  for (const std::size_t n : {100U, 1000U}) {
    SCOPED_TRACE(n);
    if (kSanitized && n >= 1000) continue;
    const ParticleRun run =
        mesh_and_check(generated(n, 3), "--fit-radii", "--fit-radii", 0, n < 1000 && !kSanitized);
    if (run.stats.is_null()) continue;
    // The issue's median target holds. Its max target (10 %) does not, for any blending surface
    // under this measure: the worst rays start on a twig's first station at a fork and meet the
    // parent's surface (docs/equipotential.md); 90 % of the rays are within 10 %.
    EXPECT_LE(run.stats.at("radius_error_median").get<double>(), 0.02);
    EXPECT_LE(run.stats.at("radius_error_p90").get<double>(), 0.10);
  }
}

TEST_F(MeshParticlesTest, LsystemSkeletons) {
  // The built-in examples: forks of every angle, monopodial chains of degree-two nodes.
  for (const char* name : {"binary", "monopodial", "bush-3d"}) {
    SCOPED_TRACE(name);
    if (kSanitized && std::string(name) != "binary") continue;
    const ParticleRun run = mesh_and_check(lsystem(name, 4, name));
    if (!run.stats.is_null()) {
      // bush-3d's twigs cross: 4 of 294 k triangles fold where their surfaces merge.
      EXPECT_LE(run.stats.at("inverted_triangles").get<double>(),
                1e-3 * run.stats.at("triangles").get<double>());
    }
  }
}

TEST_F(MeshParticlesTest, PaperFiguresSixAndSeven) {
  // Gruber & Wallner 2014: Figure 6 has 4068 particles and 8132 triangles, Figure 7 24369 and
  // 48700. The L-systems of examples/data are shaped like them; the counts come within 5 %.
  struct Figure {
    const char* file;
    double particles, triangles;
  };
  for (const Figure f : {Figure{"equipotential_fig6.lsys", 4068, 8132},
                         Figure{"equipotential_fig7.lsys", 24369, 48700}}) {
    SCOPED_TRACE(f.file);
    const ParticleRun run =
        mesh_and_check(lsystem(examples_dir() + f.file, 5, std::string(f.file).substr(0, 17)));
    if (run.stats.is_null()) continue;
    const double p = run.stats.at("particles").get<double>();
    const double t = run.stats.at("triangles").get<double>();
    EXPECT_NEAR(p / f.particles, 1.0, 0.05) << p;
    EXPECT_NEAR(t / f.triangles, 1.0, 0.05) << t;
    // A closed genus-0 surface: 2 V - 4 triangles.
    EXPECT_EQ(t, 2 * p - 4);
    EXPECT_EQ(run.stats.at("inverted_triangles").get<int>(), 0);
  }
}

TEST_F(MeshParticlesTest, AcuteForkAndNearParallelBranches) {
  // A 20-degree fork.
  const std::string acute = write(
      "acute.json",
      R"({"nodes":[{"position":[0,0,-4],"radius":0.5},{"position":[0,0,0],"radius":0.5},)"
      R"({"position":[0.868,0,4.924],"radius":0.35},{"position":[-0.868,0,4.924],"radius":0.35}],)"
      R"("edges":[[0,1],[1,2],[1,3]]})");
  const ParticleRun a = mesh_and_check(acute);
  if (!a.stats.is_null()) {
    EXPECT_EQ(a.stats.at("inverted_triangles").get<int>(), 0);
  }
  // Branches of radius 0.3 running side by side, their tubes two radii apart: separate
  // surfaces, no fold. One radius apart their surfaces merge (alpha 4): the mesh stays a closed
  // oriented manifold with every node inside. Without the twig, their bends at nodes 2 and 3
  // are chains and nothing folds; with a twig at node 2 it is a junction, whose sphere's
  // particles land on the merged surface over the other branch's: the folds are reported, with
  // a warning.
  for (const bool twig : {false, true}) {
    for (const double gap : {0.6, 0.3}) {
      SCOPED_TRACE(gap);
      SCOPED_TRACE(twig);
      const std::string x = std::to_string(0.3 + 0.5 * gap);
      const std::string parallel = write(
          "parallel.json",
          R"({"nodes":[{"position":[0,0,-3],"radius":0.5},{"position":[0,0,0],"radius":0.4},)"
          R"({"position":[-)" +
              x + R"(,0,1.5],"radius":0.3},{"position":[)" + x +
              R"(,0,1.5],"radius":0.3},{"position":[-)" + x +
              R"(,0,7],"radius":0.3},)"
              R"({"position":[)" +
              x + R"(,0,7],"radius":0.3})" +
              (twig ? R"(,{"position":[-)" + x + R"(,0.3,1.5],"radius":0.3})" : std::string()) +
              R"(],"edges":[[0,1],[1,2],[1,3],[2,4],[3,5])" + (twig ? ",[2,6]" : "") + "]}");
      const ParticleRun p = mesh_and_check(parallel);
      if (p.stats.is_null()) continue;
      const auto folded = p.stats.at("inverted_triangles").get<std::size_t>();
      if (gap > 0.5 || !twig) {
        EXPECT_EQ(folded, 0U);
      } else {
        EXPECT_GT(folded, 0U);
        const CliRun r =
            run_cli("mesh " + parallel + " -o " + path("p.ply") + " --method particles");
        EXPECT_EQ(r.code, 0) << r.out;
        EXPECT_NE(r.out.find("face into the surface"), std::string::npos) << r.out;
      }
    }
  }
}

// The shapes that folded the scanned trees' meshes: a trunk of cylinders 1.5 long (radius 0.5)
// joined by connectors 0.2 long at 76 degrees to them (a zig-zag of edges shorter than the
// radius, as TreeQSM's connectors make), a fork right after it, a short leaf at the fork whose
// edge and cap lie inside the fork's sphere, and a half circle of 41 edges bent at a radius of
// 1.6 tube radii. The chains' rings follow the smoothed course, the short leaf is absorbed by the
// fork: no fold, every node inside.
TEST_F(MeshParticlesTest, ZigzagChainsBendsAndShortLeavesDoNotFold) {
  std::string nodes;
  std::string edges;
  int count = 0;
  const auto node = [&](double x, double y, double z, double r) {
    nodes += std::string(count == 0 ? "" : ",") + "{\"position\":[" + std::to_string(x) + "," +
             std::to_string(y) + "," + std::to_string(z) + "],\"radius\":" + std::to_string(r) +
             "}";
    return count++;
  };
  const auto edge = [&](int a, int b) {
    edges += std::string(edges.empty() ? "" : ",") + "[" + std::to_string(a) + "," +
             std::to_string(b) + "]";
  };
  int previous = node(0, 0, 0, 0.5);
  double x = 0;
  double z = 0;
  for (int i = 0; i < 5; ++i) {
    z += 1.5;
    const int a = node(x, 0, z, 0.5);
    edge(previous, a);
    x = x == 0 ? 0.2 : 0;
    z += 0.05;
    previous = node(x, 0, z, 0.5);
    edge(a, previous);
  }
  edge(previous, node(x + 1.5, 0, z + 3, 0.35));
  edge(previous, node(x - 1.5, 0, z + 3, 0.35));
  edge(previous, node(x, 0.3, z + 0.1, 0.3));  // the short leaf
  const std::string zigzag =
      write("zigzag.json", "{\"nodes\":[" + nodes + "],\"edges\":[" + edges + "]}");
  nodes.clear();
  edges.clear();
  count = 0;
  previous = node(-0.8, 0, -3, 0.5);
  for (int i = 0; i <= 40; ++i) {
    const double t = std::numbers::pi * i / 40;
    const int p = node(-0.8 * std::cos(t), 0, 0.8 * std::sin(t), 0.5);
    edge(previous, p);
    previous = p;
  }
  edge(previous, node(0.8, 0, -3, 0.5));
  const std::string arc =
      write("arc.json", "{\"nodes\":[" + nodes + "],\"edges\":[" + edges + "]}");
  for (const std::string& skel : {zigzag, arc}) {
    SCOPED_TRACE(skel);
    // --fit-radii: eq. 2's test points around a connector lie on the trunk's axis, which puts
    // lambda far above the tubes' potential without the fit.
    const ParticleRun run = mesh_and_check(skel, "--fit-radii", "--fit-radii");
    if (run.stats.is_null()) continue;
    EXPECT_EQ(run.stats.at("inverted_triangles").get<int>(), 0);
  }
}

// The corner that put archi_Tree_1's nodes outside the mesh: a twig turns 90 degrees into a
// connector one radius long and leaves it heading back down (130 degrees from its first edge).
// Its nodes stay inside and nothing folds (before: 2 of 6 nodes outside, 11 folded triangles).
TEST_F(MeshParticlesTest, ShortConnectorAtARightAngleKeepsItsNodesInside) {
  const double a = 130.0 * std::numbers::pi / 180.0;
  const std::string skel = write(
      "turn.json",
      R"({"nodes":[{"position":[0,0,-3],"radius":0.5},{"position":[0,0,0],"radius":0.5},)"
      R"({"position":[-2,0,2],"radius":0.4},{"position":[0,0,3],"radius":0.5},)"
      R"({"position":[0.5,0,3],"radius":0.5},{"position":[)" +
          std::to_string(0.5 + 3 * std::sin(a)) + ",0," + std::to_string(3 + 3 * std::cos(a)) +
          R"(],"radius":0.5}],"edges":[[0,1],[1,2],[1,3],[3,4],[4,5]]})");
  const ParticleRun run = mesh_and_check(skel, "--fit-radii", "--fit-radii");
  if (run.stats.is_null()) return;
  EXPECT_EQ(run.stats.at("inverted_triangles").get<int>(), 0);
}

TEST_F(MeshParticlesTest, TetsAndParticlesAgreeOnTheSameField) {
  const std::string skel = generated(kSanitized ? 30 : 100, 2);
  const ParticleRun particles = mesh_and_check(skel);
  const std::string tets = path("tets.ply");
  const CliRun r = run_cli("mesh " + skel + " -o " + tets + " --surface equipotential");
  ASSERT_EQ(r.code, 0) << r.out;
  const CliRun c = run_cli("check " + tets + " --deviation " + skel +
                           " --surface equipotential --samples 4000 --json");
  ASSERT_EQ(c.code, 0) << c.out;
  const nlohmann::json t = nlohmann::json::parse(c.out);
  ASSERT_FALSE(particles.check.is_null());
  // Both lie within a few percent of the radius of one surface, so within the sum of that of
  // each other: the tets mesh at its default tolerance (p99 <= 5 %), the particles' chords.
  EXPECT_LE(t.at("deviation_p99").get<double>(), 0.05);
  EXPECT_LE(particles.check.at("deviation_p99").get<double>(), 0.10);
  // Their enclosed volumes agree (the chords of the particle mesh cut a little off).
  const double vp = signed_volume(particles.mesh);
  const double vt = signed_volume(read_mesh(tets));
  EXPECT_NEAR(vp / vt, 1.0, 0.05) << vp << " vs " << vt;
}

TEST_F(MeshParticlesTest, LambdaScaleWithFitRadiiIsAUsageError) {
  const CliRun r = run_cli("mesh " + y_fork() + " -o " + path("m.ply") +
                           " --method particles --fit-radii --lambda-scale 0.5");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("--lambda-scale"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(path("m.ply")));
}

TEST_F(MeshParticlesTest, RealCylinderModels) {
  if (kSanitized) GTEST_SKIP() << "half a minute each in Release; run by make test only";
  const std::filesystem::path trees = test::shared_data_dir() / "trees";
  if (!std::filesystem::is_directory(trees)) {
    GTEST_SKIP() << "no shared tree data at " << trees.string();
  }
  for (const char* file : {"archi_Tree_1_TreeQSM.txt", "rtwig_QSM.csv"}) {
    SCOPED_TRACE(file);
    const std::string skel = (trees / file).string();
    // Every node inside: the chains' rings at nodes stay, and the 15 nodes of archi_Tree_1
    // at 78-90 degree bends next to short connectors that they still cannot enclose are
    // junctions (docs/equipotential.md, "Chains").
    const ParticleRun run = mesh_and_check(skel, "--fit-radii", "--fit-radii", 0, false);
    if (run.stats.is_null()) continue;
    EXPECT_LE(run.stats.at("radius_error_median").get<double>(), 0.02);
    EXPECT_LE(run.stats.at("radius_error_p90").get<double>(), 0.10);
    // Chains of short cylinders and short leaves no longer fold (archi_Tree_1: 3.3 % of the
    // triangles before, 0.39 % now; rtwig 0.5 %, now 0.03 %): what is left is at junctions
    // closer together than their spheres and where separate branches merge.
    EXPECT_LE(run.stats.at("inverted_triangles").get<double>(),
              0.005 * static_cast<double>(run.mesh.triangles.size()));
  }
}

}  // namespace
}  // namespace ramiform
