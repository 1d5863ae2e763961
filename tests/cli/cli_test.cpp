// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// End-to-end tests of the `ramiform` binary: exit codes, messages, no partial outputs, stats,
// agreement with the library, and identical outputs for any thread count.

#include <gtest/gtest.h>

#include <array>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli/cli_run.h"
#include "support/glb_reader.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"

namespace ramiform {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::run_cli;

class CliTest : public test::CliDirTest {};

TEST_F(CliTest, MeshIsWatertightAndStatsHaveTheDocumentedKeys) {
  const std::string skel = y_fork();
  const CliRun r = run_cli("mesh " + skel + " -o " + path("fork.ply") + " --method mc --resolution 64 --stats " +
                    path("s.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  const TriMesh mesh = read_mesh(path("fork.ply"));
  const MeshReport rep = check_mesh(mesh);
  EXPECT_TRUE(rep.watertight);
  EXPECT_TRUE(rep.oriented);
  EXPECT_TRUE(rep.manifold);
  EXPECT_EQ(rep.components, 1U);
  EXPECT_EQ(rep.euler, 2);
  std::ifstream in(path("s.json"));
  const auto stats = nlohmann::json::parse(in);
  EXPECT_EQ(stats["vertices"].get<std::size_t>(), mesh.vertex_count());
  EXPECT_EQ(stats["triangles"].get<std::size_t>(), mesh.triangle_count());
  EXPECT_GT(stats["field_evals"].get<std::uint64_t>(), 0U);
  EXPECT_TRUE(stats["seconds"].contains("total"));
  EXPECT_TRUE(stats["watertight"].get<bool>());
}

TEST_F(CliTest, CheckJsonHasExactlyTheDocumentedKeys) {
  const std::string skel = y_fork();
  ASSERT_EQ(run_cli("mesh " + skel + " -o " + path("fork.ply") + " --levels 2").code, 0);
  const CliRun r = run_cli("check " + path("fork.ply") + " --skeleton " + skel + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  std::set<std::string> keys;
  for (auto it = j.begin(); it != j.end(); ++it) keys.insert(it.key());
  const std::set<std::string> expected = {"vertices", "triangles", "watertight", "oriented",
                                          "manifold", "components", "euler", "min_angle_deg",
                                          "median_angle_deg", "triangles_below_10_deg",
                                          "triangles_below_1_deg", "boundary_edges",
                                          "nonmanifold_edges", "misoriented_edges",
                                          "nonmanifold_vertices", "degenerate_triangles",
                                          "skeleton_nodes", "skeleton_nodes_inside_count",
                                          "skeleton_nodes_inside"};
  EXPECT_EQ(keys, expected);
  EXPECT_DOUBLE_EQ(j["skeleton_nodes_inside"].get<double>(), 1.0);
  EXPECT_EQ(j["skeleton_nodes_inside_count"].get<std::size_t>(), j["skeleton_nodes"].get<std::size_t>());
  EXPECT_EQ(j["boundary_edges"].get<std::size_t>(), 0U);
  EXPECT_EQ(j["euler"].get<int>(), 2);
}

// check --deviation: the documented keys, a mesh at the default tolerance meets it by the
// independent measure, and the deviation options need --deviation.
TEST_F(CliTest, CheckDeviationReportsTheMeasureOfTheMesh) {
  const std::string skel = y_fork();
  ASSERT_EQ(run_cli("mesh " + skel + " -o " + path("fork.ply") + " --stats " + path("s.json")).code,
            0);
  const CliRun r = run_cli("check " + path("fork.ply") + " --deviation " + skel +
                           " --samples 5000 --seed 3 --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* prefix : {"deviation_", "vertex_deviation_"}) {
    for (const char* key :
         {"points", "unresolved", "p50", "p99", "max", "abs_p50", "abs_p99", "abs_max", "worst"}) {
      EXPECT_TRUE(j.contains(std::string(prefix) + key)) << prefix << key;
    }
  }
  EXPECT_EQ(j["deviation_points"].get<std::size_t>(), 5000U);
  EXPECT_EQ(j["deviation_unresolved"].get<std::size_t>(), 0U);
  EXPECT_LE(j["deviation_p99"].get<double>(), 0.05);
  EXPECT_LE(j["deviation_p50"].get<double>(), j["deviation_p99"].get<double>());
  EXPECT_LT(j["vertex_deviation_p99"].get<double>(), 1e-3);  // vertices lie on the surface
  std::ifstream in(path("s.json"));
  const auto stats = nlohmann::json::parse(in);
  EXPECT_LE(stats["deviation_p99"].get<double>(), 0.05);
  EXPECT_TRUE(stats["tolerance_reached"].get<bool>());
  EXPECT_EQ(run_cli("check " + path("fork.ply") + " --samples 10").code, 1);
  const CliRun huge = run_cli("check " + path("fork.ply") + " --deviation " + skel +
                              " --samples 100000000000000");
  EXPECT_EQ(huge.code, 2) << huge.out;
  EXPECT_NE(huge.out.find("sample points"), std::string::npos) << huge.out;
  EXPECT_EQ(run_cli("check " + path("fork.ply") + " --fit-radii").code, 1);
}

TEST_F(CliTest, CheckReportsAnOpenMeshWithExitZero) {
  const std::string obj = write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n");
  const CliRun r = run_cli("check " + obj + " --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j["watertight"].get<bool>());
  EXPECT_EQ(j["triangles"].get<int>(), 2);
}

TEST_F(CliTest, EvalPrintsTheLibraryValues) {
  const std::string skel = y_fork();
  const std::string pts = write("p.txt", "0 0 1\n0.3 0.2 2.5\n5 5 5\n-1.5 0 5.3\n");
  const CliRun r = run_cli("eval " + skel + " --points " + pts + " --gradient");
  ASSERT_EQ(r.code, 0) << r.out;
  const Skeleton s = read_skeleton(skel);
  const FieldPtr f = make_skeleton_field(s);
  std::istringstream lines(r.out);
  const Vec3 points[] = {{0, 0, 1}, {0.3, 0.2, 2.5}, {5, 5, 5}, {-1.5, 0, 5.3}};
  for (const Vec3& p : points) {
    double v = 0, gx = 0, gy = 0, gz = 0;
    ASSERT_TRUE(lines >> v >> gx >> gy >> gz);
    EXPECT_EQ(v, f->value(p));  // %.17g round-trips exactly
    const Vec3 g = f->gradient(p);
    EXPECT_EQ(gx, g.x());
    EXPECT_EQ(gy, g.y());
    EXPECT_EQ(gz, g.z());
  }
  EXPECT_GT(f->value(points[0]), f->iso());  // on the trunk axis: inside
  EXPECT_LE(f->value(points[2]), f->iso());  // far away: outside
}

TEST_F(CliTest, OutputIsByteIdenticalForOneAndTwoThreads) {
  const std::string skel = y_fork();
  for (const std::string method : {"--method mc --resolution 80", "--levels 2"}) {
    ASSERT_EQ(run_cli("mesh " + skel + " -o " + path("t1.ply") + " " + method + " --threads 1").code, 0);
    ASSERT_EQ(run_cli("mesh " + skel + " -o " + path("t2.ply") + " " + method + " --threads 2").code, 0);
    std::ifstream a(path("t1.ply"), std::ios::binary), b(path("t2.ply"), std::ios::binary);
    const std::string sa((std::istreambuf_iterator<char>(a)), {}), sb((std::istreambuf_iterator<char>(b)), {});
    EXPECT_GT(sa.size(), 1000U) << method;
    EXPECT_EQ(sa, sb) << method;
  }
}

struct BadInput {
  const char* name;
  const char* text;
  const char* expect;  // substring of the message
};

TEST_F(CliTest, BadSkeletonsExitTwoWithLocatedMessageAndNoOutput) {
  const BadInput cases[] = {
      {"empty.json", "", "empty.json"},
      {"syntax.json", "{\"nodes\": [\n{\"position\": [0,0,0], \"radius\": 1},\n]}", ":3"},
      {"radius.json", R"({"nodes":[{"position":[0,0,0],"radius":0}],"edges":[]})", "node 0"},
      {"negative.json", R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[0,0,1],"radius":-2}],"edges":[[0,1]]})", "node 1"},
      {"range.json", R"({"nodes":[{"position":[0,0,0],"radius":1}],"edges":[[0,7]]})", "edge 0"},
      {"loop.json", R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[0,0,1],"radius":1}],"edges":[[0,1],[1,1]]})", "edge 1"},
      {"dup.json", R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[0,0,1],"radius":1}],"edges":[[0,1],[1,0]]})", "edge 1"},
      {"zero.json", R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[0,0,0],"radius":1}],"edges":[[0,1]]})", "edge 0"},
      {"header.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n", "header.ply"},
      {"nan.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nproperty float radius\nend_header\n0 nan 0 1\n", "nan.ply"},
  };
  for (const auto& c : cases) {
    const std::string in = write(c.name, c.text);
    const std::string out = path(std::string(c.name) + ".out.ply");
    const std::size_t before = files_in_dir();
    const CliRun r = run_cli("mesh " + in + " -o " + out + " --levels 1");
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.out;
    EXPECT_NE(r.out.find(c.name), std::string::npos) << c.name << ": " << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.name << " should mention '" << c.expect << "': " << r.out;
    EXPECT_FALSE(fs::exists(out)) << c.name;
    EXPECT_EQ(files_in_dir(), before) << c.name << ": a file was left behind";
  }
}

TEST_F(CliTest, UsageErrorsExitOne) {
  EXPECT_EQ(run_cli("").code, 1);
  EXPECT_EQ(run_cli("mesh").code, 1);
  EXPECT_EQ(run_cli("mesh x.json --method nope").code, 1);
  EXPECT_EQ(run_cli("mesh x.json --cell 0.1 --resolution 20").code, 1);
  EXPECT_EQ(run_cli("mesh x.json --cell 0.1").code, 1);            // mc option, tets method
  EXPECT_EQ(run_cli("mesh x.json --method mc --levels 2").code, 1);  // tets option, mc method
  EXPECT_EQ(run_cli("frobnicate").code, 1);
}

TEST_F(CliTest, BadOptionValuesAndMissingFilesExitTwo) {
  const std::string skel = y_fork();
  const CliRun k = run_cli("mesh " + skel + " --kernel nonsense -o " + path("k.ply"));
  EXPECT_EQ(k.code, 2) << k.out;
  EXPECT_NE(k.out.find("unknown kernel"), std::string::npos) << k.out;
  const CliRun m = run_cli("mesh " + path("missing.json") + " -o " + path("m.ply"));
  EXPECT_EQ(m.code, 2) << m.out;
  EXPECT_NE(m.out.find("missing.json"), std::string::npos) << m.out;
  const CliRun obj = run_cli("mesh " + write("line.obj", "v 0 0 0\nv 0 0 1\nl 1 2\n") + " -o " + path("o.ply"));
  EXPECT_EQ(obj.code, 2) << obj.out;  // OBJ needs --obj-radius
  EXPECT_FALSE(fs::exists(path("o.ply")));
}

TEST_F(CliTest, EveryCommandHasHelp) {
  for (const char* c : {"mesh", "check", "eval", "demo"}) {
    const CliRun r = run_cli(std::string(c) + " --help");
    EXPECT_EQ(r.code, 0) << c;
    EXPECT_NE(r.out.find("--threads"), std::string::npos) << c;
    EXPECT_NE(r.out.find("--stats"), std::string::npos) << c;
  }
}

TEST_F(CliTest, DemoRunsTheWholePipelineIdenticallyOnAnyThreadCount) {
  const CliRun r = run_cli("demo --out " + path("demo") + " --levels 1 --points 600 --threads 2");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"crown.ply", "points.txt", "skeleton.json", "tree.ply", "tree.glb", "tree.svg",
                        "stats.json"}) {
    EXPECT_TRUE(fs::exists(dir_ / "demo" / f)) << f;
    EXPECT_NE(r.out.find(f), std::string::npos) << "summary should name " << f;
  }
  for (const char* f : {"crown.ply", "tree.ply"}) {
    const MeshReport rep = check_mesh(read_mesh((dir_ / "demo" / f).string()));
    EXPECT_TRUE(rep.watertight && rep.oriented && rep.manifold) << f;
    EXPECT_EQ(rep.components, 1U) << f;
  }
  // The demo's .glb stands upright in a glTF viewer (+Y up) and carries normals and bark UVs.
  const test::Glb glb = test::read_glb((dir_ / "demo" / "tree.glb").string());
  const auto& box = glb.json["accessors"][glb.attribute(0, "POSITION")];
  std::array<double, 3> extent{};
  for (std::size_t k = 0; k < 3; ++k) {
    extent[k] = box["max"][k].get<double>() - box["min"][k].get<double>();
  }
  EXPECT_GT(extent[1], extent[0]);
  EXPECT_GT(extent[1], extent[2]);
  for (const char* a : {"NORMAL", "TEXCOORD_0", "TANGENT"}) EXPECT_GE(glb.attribute(0, a), 0) << a;
  const Skeleton s = read_skeleton((dir_ / "demo" / "skeleton.json").string());
  EXPECT_EQ(connected_components(s).count, 1U);
  EXPECT_EQ(s.edge_count() + 1, s.node_count());
  EXPECT_GT(s.edge_count(), 100U);
  // The demo cleans its tree's branches and says what that changed (examples/demo.rf).
  const auto stats = nlohmann::json::parse(test::read_file((dir_ / "demo" / "stats.json").string()));
  ASSERT_TRUE(stats.contains("grow_cleanup")) << stats.dump();
  const auto& c = stats["grow_cleanup"];
  EXPECT_GT(c["nodes_moved"].get<std::size_t>(), 0U);
  EXPECT_GT(c["nodes_removed"].get<std::size_t>(), 0U);
  EXPECT_GT(c["stubs_pruned"].get<std::size_t>(), 0U);
  EXPECT_LE(c["after"]["turn_p90_deg"].get<double>(), 30.0);
  EXPECT_LE(c["after"]["turn_max_deg"].get<double>(), 90.0);
  EXPECT_LE(c["after"]["short_tip_percent"].get<double>(), 10.0);
  const auto deg = degrees(s);
  std::size_t tips = 0;
  for (std::size_t i = 1; i < s.node_count(); ++i) tips += deg[i] == 1 ? 1 : 0;
  EXPECT_EQ(c["after"]["tip_branches"].get<std::size_t>(), tips);
  EXPECT_EQ(c["before"]["tip_branches"].get<std::size_t>() - c["stubs_pruned"].get<std::size_t>(),
            tips);
  // Same seed, one thread: byte-identical outputs.
  const CliRun one = run_cli("demo --out " + path("demo1") + " --levels 1 --points 600 --threads 1");
  ASSERT_EQ(one.code, 0) << one.out;
  for (const char* f : {"crown.ply", "points.txt", "skeleton.json", "tree.ply", "tree.glb", "tree.svg"}) {
    EXPECT_EQ(test::read_file((dir_ / "demo" / f).string()), test::read_file((dir_ / "demo1" / f).string())) << f;
  }
  const CliRun other = run_cli("demo --out " + path("demo2") + " --levels 0 --points 600 --seed 2");
  ASSERT_EQ(other.code, 0) << other.out;
  EXPECT_NE(test::read_file((dir_ / "demo" / "points.txt").string()), test::read_file((dir_ / "demo2" / "points.txt").string()));
}

}  // namespace
}  // namespace ramiform
