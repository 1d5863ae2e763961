// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// What `mesh` writes for viewers, game engines and Blender (issue 20): .glb +Y up with field
// normals, bark UVs and tangents; --up, --no-normals, --uv/--no-uv; levels of detail (--lod,
// --lod-budget) as files or glTF nodes; the scene language's save_mesh options; bad values.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/cli_run.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/winding.h"
#include "support/glb_reader.h"
#include "support/mesh_checkers.h"

namespace ramiform {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::run_cli;

Vec3 y_up(const Vec3& v) { return {v.x(), v.z(), -v.y()}; }

// The mesh of mesh `index` of a .glb, positions as floats widened, welded by position.
TriMesh glb_mesh(const test::Glb& g, int index) {
  TriMesh m;
  const std::vector<float> p = g.floats(g.attribute(index, "POSITION"));
  for (std::size_t i = 0; i + 2 < p.size(); i += 3) m.positions.emplace_back(p[i], p[i + 1], p[i + 2]);
  const int ia = g.json["meshes"][index]["primitives"][0]["indices"].get<int>();
  const std::vector<std::uint32_t> idx = g.uints(ia);
  for (std::size_t t = 0; t + 2 < idx.size(); t += 3) m.triangles.push_back({idx[t], idx[t + 1], idx[t + 2]});
  return m;
}

class MeshOutputTest : public test::CliDirTest {
 protected:
  std::string tree() const {
    const std::string out = path("tree.json");
    const CliRun r = run_cli("generate " + out + " --segments 30 --seed 3 --branch-angle 20");
    EXPECT_EQ(r.code, 0) << r.out;
    return out;
  }
};

TEST_F(MeshOutputTest, GlbStandsUpWithTheFieldsNormalsAndBarkUvsOverAClosedSurface) {
  const std::string t = tree();
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("t.glb") + " --stats " + path("g.json")).code, 0);
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("t.ply")).code, 0);
  const TriMesh ply = read_mesh(path("t.ply"));  // the same polygonization, doubles, +Z up
  ASSERT_EQ(ply.normals.size(), ply.positions.size());
  EXPECT_TRUE(ply.uvs.empty());  // PLY gets UVs only with --uv
  const test::Glb g = test::read_glb(path("t.glb"));
  const auto& pos = g.json["accessors"][g.attribute(0, "POSITION")];
  const double dx = pos["max"][0].get<double>() - pos["min"][0].get<double>();
  const double dy = pos["max"][1].get<double>() - pos["min"][1].get<double>();
  const double dz = pos["max"][2].get<double>() - pos["min"][2].get<double>();
  EXPECT_GT(dy, dx);  // tallest along +Y: upright in every glTF viewer
  EXPECT_GT(dy, dz);
  // The seam copies come after the surface's own vertices, which are the PLY's, rotated; the
  // normals are the PLY's (the field's) to float precision.
  const std::vector<float> p = g.floats(g.attribute(0, "POSITION"));
  const std::vector<float> n = g.floats(g.attribute(0, "NORMAL"));
  const std::vector<float> tan = g.floats(g.attribute(0, "TANGENT"));
  const std::vector<float> uv = g.floats(g.attribute(0, "TEXCOORD_0"));
  const std::size_t nv = p.size() / 3;
  ASSERT_GT(nv, ply.positions.size());
  ASSERT_EQ(n.size(), p.size());
  ASSERT_EQ(tan.size(), nv * 4);
  ASSERT_EQ(uv.size(), nv * 2);
  double worst = 0, worst_tan = 0;
  for (std::size_t i = 0; i < nv; ++i) {
    const Vec3 ni(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
    const Vec3 ti(tan[4 * i], tan[4 * i + 1], tan[4 * i + 2]);
    if (i < ply.positions.size()) {
      EXPECT_EQ(Vec3(p[3 * i], p[3 * i + 1], p[3 * i + 2]), y_up(ply.positions[i]).cast<float>().cast<double>());
      worst = std::max(worst, (ni - y_up(ply.normals[i])).norm());
    }
    worst_tan = std::max({worst_tan, std::abs(ti.norm() - 1), std::abs(ti.dot(ni))});
    EXPECT_EQ(std::abs(tan[4 * i + 3]), 1.0f);
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_LT(worst_tan, 1e-5);
  // Welded through its seam copies (identical positions), the .glb's mesh is the closed,
  // one-piece surface, with every node inside.
  TriMesh w = glb_mesh(g, 0);
  weld_coincident(w);
  test::expect_closed_manifold(w);
  test::expect_components(w, 1);
  EXPECT_EQ(test::nodes_outside(welded_topology(w), read_skeleton(t), y_up), 0u);
  const auto stats = nlohmann::json::parse(test::read_file(path("g.json")));
  ASSERT_TRUE(stats.contains("uv")) << stats.dump();
  EXPECT_GT(stats["uv"]["branches"].get<std::size_t>(), 5u);
  EXPECT_EQ(stats["vertices"].get<std::size_t>(), nv);
}

TEST_F(MeshOutputTest, UpNormalsAndUvFlagsChangeWhatPlyAndObjCarry) {
  const std::string t = tree();
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("z.ply")).code, 0);
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("y.obj") + " --up y --no-normals").code, 0);
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("u.ply") + " --uv").code, 0);
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("n.obj") + " --no-uv").code, 0);
  const TriMesh z = read_mesh(path("z.ply"));
  const TriMesh y = read_mesh(path("y.obj"));
  EXPECT_TRUE(y.normals.empty());
  ASSERT_EQ(y.positions.size(), z.positions.size());  // OBJ writes seam copies once
  for (std::size_t i = 0; i < z.positions.size(); ++i) EXPECT_EQ(y.positions[i], y_up(z.positions[i]));
  EXPECT_EQ(y.triangles, z.triangles);
  const std::string obj = test::read_file(path("y.obj"));
  EXPECT_NE(obj.find("\nvt "), std::string::npos);
  EXPECT_EQ(test::read_file(path("n.obj")).find("\nvt "), std::string::npos);
  // A textured PLY has seam copies; reading it welds them back, and it is closed.
  const TriMesh u = read_mesh(path("u.ply"));
  EXPECT_GT(u.positions.size(), z.positions.size());
  EXPECT_EQ(u.uvs.size(), u.positions.size());
  const MeshReport r = check_mesh(u);
  EXPECT_TRUE(r.watertight && r.oriented && r.manifold);
  const CliRun chk = run_cli("check " + path("u.ply"));
  EXPECT_EQ(chk.code, 0) << chk.out;
}

TEST_F(MeshOutputTest, LodsAreWholeMeshesWithFallingCountsAsFilesOrGltfNodes) {
  const std::string t = tree();
  const Skeleton s = read_skeleton(t);
  const CliRun r = run_cli("mesh " + t + " -o " + path("t.ply") + " --lod 0.05,0.15,0.4 --stats " + path("s.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("3 levels of detail"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("t.ply")));
  const auto stats = nlohmann::json::parse(test::read_file(path("s.json")));
  ASSERT_EQ(stats["lods"].size(), 3u);
  std::size_t previous = SIZE_MAX;
  for (int k = 0; k < 3; ++k) {
    const TriMesh m = read_mesh(path("t.lod" + std::to_string(k) + ".ply"));
    test::expect_closed_manifold(m);
    test::expect_components(m, 1);
    EXPECT_EQ(test::nodes_outside(m, s), 0u) << k;
    EXPECT_LT(m.triangle_count(), previous);
    previous = m.triangle_count();
    EXPECT_EQ(stats["lods"][k]["triangles"].get<std::size_t>(), m.triangle_count());
    EXPECT_TRUE(stats["lods"][k]["watertight"].get<bool>());
    EXPECT_LE(stats["lods"][k]["deviation_p99"].get<double>(), stats["lods"][k]["tolerance"].get<double>());
  }
  // One .glb with one node per level, LOD0 finest; the same meshes, rotated.
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("t.glb") + " --lod 0.05,0.15,0.4").code, 0);
  const test::Glb g = test::read_glb(path("t.glb"));
  ASSERT_EQ(g.json["meshes"].size(), 3u);
  EXPECT_EQ(g.json["nodes"][0]["extensions"]["MSFT_lod"]["ids"], nlohmann::json::array({1, 2}));
  for (int k = 0; k < 3; ++k) {
    TriMesh m = glb_mesh(g, k);
    EXPECT_EQ(m.triangle_count(), stats["lods"][k]["triangles"].get<std::size_t>());
    weld_coincident(m);
    test::expect_closed_manifold(m);
  }
  // Budgets: each level within its own.
  ASSERT_EQ(run_cli("mesh " + t + " -o " + path("b.ply") + " --lod 30000,12000 --lod-budget").code, 0);
  EXPECT_LE(read_mesh(path("b.lod0.ply")).triangle_count(), 30000u);
  EXPECT_LE(read_mesh(path("b.lod1.ply")).triangle_count(), 12000u);
}

// Bad option values are usage errors (exit 1, as every flag's); nothing is written.
TEST_F(MeshOutputTest, BadOutputOptionsAreUsageErrorsWithAMessageAndNoOutput) {
  const std::string t = tree();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--lod 0.2,0.1", "not coarser"},
      {"--lod-budget", "needs --lod"},
      {"--lod 0.05 --method mc", "tolerance mesher"},
      {"--lod 0.05 --levels 2", "tolerance mesher"},
      {"--lod 1000.5 --lod-budget", "not a triangle count"},
      {"--lod 0.05,abc", "--lod"},
      {"--up x", "--up"},
      {"--uv-facing 1,2", "--uv-facing"},
  };
  for (const auto& [flags, message] : cases) {
    const CliRun r = run_cli("mesh " + t + " -o " + path("bad.ply") + " " + flags);
    EXPECT_EQ(r.code, 1) << flags << ": " << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << flags << ": " << r.out;
    for (const char* f : {"bad.ply", "bad.lod0.ply", "bad.lod1.ply"}) {
      EXPECT_FALSE(fs::exists(path(f))) << flags << " left " << f;
    }
  }
}

TEST_F(MeshOutputTest, SaveMeshInTheSceneLanguageTakesTheSameOptions) {
  (void)tree();
  const std::string scene = write("s.rf",
                                  "skeleton t tree.json\n"
                                  "save_mesh t t.glb t.ply lod=0.05,0.3 up=y\n"
                                  "save_mesh t plain.obj normals=no uv=no\n");
  fs::create_directories(path("out"));
  fs::create_directories(path("bad"));
  const CliRun r = run_cli("run " + scene + " --out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const test::Glb g = test::read_glb(path("out/t.glb"));
  EXPECT_EQ(g.json["meshes"].size(), 2u);
  EXPECT_GE(g.attribute(0, "TEXCOORD_0"), 0);  // uv=auto: .glb gets UVs
  const TriMesh l0 = read_mesh(path("out/t.lod0.ply"));
  const TriMesh l1 = read_mesh(path("out/t.lod1.ply"));
  EXPECT_GT(l0.triangle_count(), l1.triangle_count());
  EXPECT_TRUE(l0.uvs.empty());
  EXPECT_EQ(l0.normals.size(), l0.positions.size());
  // up=y: the PLY's height is along y, as the glb's.
  double ymax = -1e300, zmax = -1e300;
  for (const Vec3& p : l0.positions) {
    ymax = std::max(ymax, p.y());
    zmax = std::max(zmax, p.z());
  }
  EXPECT_GT(ymax, zmax);
  const std::string obj = test::read_file(path("out/plain.obj"));
  EXPECT_EQ(obj.find("\nvn "), std::string::npos);
  EXPECT_EQ(obj.find("\nvt "), std::string::npos);
  for (const auto& [line, message] : std::vector<std::pair<std::string, std::string>>{
           {"save_mesh t x.ply lod=0.3,0.1", "not coarser"},
           {"save_mesh t x.ply lod=0.1 lod_budget=1000", "not both"},
           {"save_mesh t x.ply lod_budget=10.5", "triangle counts"},
           {"save_mesh t x.ply up=q", "up"},
           {"save_mesh t x.ply method=mc lod=0.1", "applies to method=tets"}}) {
    const std::string bad = write("b.rf", "skeleton t tree.json\n" + line + "\n");
    const CliRun b = run_cli("run " + bad + " --out " + path("bad"));
    EXPECT_EQ(b.code, 2) << line << ": " << b.out;
    EXPECT_NE(b.out.find(message), std::string::npos) << line << ": " << b.out;
    EXPECT_NE(b.out.find("b.rf:2"), std::string::npos) << line << ": " << b.out;
  }
}

}  // namespace
}  // namespace ramiform
