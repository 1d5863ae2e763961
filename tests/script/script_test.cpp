// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The scene language: the thesis's listings, values against independent formulas, errors with
// file/line/column and hints, parameters, staged (all-or-nothing) outputs.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <regex>

#include "ramiform/core/errors.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/script/script.h"
#include "script/script_fixture.h"
#include "support/fixtures.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

// Wyvill's kernel written out (thesis §3.2), and R = r / (1/2) for a surface radius r.
double wyvill(double x) {
  if (x >= 1) return 0;
  const double x2 = x * x;
  return 1 - 22.0 / 9 * x2 + 17.0 / 9 * x2 * x2 - 4.0 / 9 * x2 * x2 * x2;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

class ScriptTest : public ScriptDirTest {
 protected:
  double value(ScriptSession& s, const std::string& name, const Vec3& p) {
    const CommandResult r = s.execute_line("eval " + name + " " + std::to_string(p.x()) + " " +
                                           std::to_string(p.y()) + " " + std::to_string(p.z()));
    const std::size_t eq = r.message.find("= ");
    return std::stod(r.message.substr(eq + 2));
  }
};

TEST_F(ScriptTest, ThesisDifferenceListingRunsVerbatimAndMatchesTheFormula) {
  ScriptSession s(options_);
  s.run_text("sphere s1\nline s2\ndiff s1 s2 s3\n", "thesis.rf");
  // s1: unit sphere (R = 2), s2: segment (0,0,-1.5)-(0,0,1.5) radius 0.3 (R = 0.6);
  // diff = min(f1, 2 iso - f2) with iso 0.5.
  for (const Vec3& p : {Vec3(0.7, 0, 0), Vec3(0, 0, 0), Vec3(0.2, 0.1, 0.5), Vec3(0, 0.5, 0.9),
                        Vec3(1.2, 0, 0), Vec3(0.31, 0, 0)}) {
    const double f1 = wyvill(p.norm() / 2);
    const double f2 = wyvill(segment_distance(p, Vec3(0, 0, -1.5), Vec3(0, 0, 1.5)) / 0.6);
    EXPECT_NEAR(value(s, "s3", p), std::min(f1, 1.0 - f2), 1e-12) << p.transpose();
  }
  EXPECT_GT(value(s, "s3", Vec3(0.7, 0, 0)), 0.5);  // in the sphere's body
  EXPECT_LT(value(s, "s3", Vec3(0, 0, 0)), 0.5);    // in the drilled hole
  EXPECT_LT(value(s, "s3", Vec3(1.2, 0, 0)), 0.5);  // outside the sphere
}

TEST_F(ScriptTest, DrilledSphereMeshIsWatertightWithTheNapkinRingVolume) {
  ScriptSession s(options_);
  s.run_text("sphere s1\nline s2\ndiff s1 s2 s3\nsave_mesh s3 s3.ply resolution=128\n", "t.rf");
  EXPECT_LE(files(), 1u);  // staged (unnamed where Linux allows), not yet committed
  EXPECT_FALSE(fs::exists(dir_ / "s3.ply"));
  s.commit();
  const TriMesh mesh = read_mesh((dir_ / "s3.ply").string());
  const MeshReport r = check_mesh(mesh);
  EXPECT_TRUE(r.watertight && r.oriented && r.manifold);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler, 0);  // a torus: the hole goes through
  // Sphere of radius 1 minus a cylinder of radius a = 0.3 through it: 4/3 pi (1 - a^2)^(3/2).
  const double expected = 4.0 / 3 * std::numbers::pi * std::pow(1 - 0.09, 1.5);
  EXPECT_NEAR(signed_volume(mesh), expected, 0.01 * expected);
}

TEST_F(ScriptTest, ThesisCrownListingRunsVerbatim) {
  std::ofstream(dir_ / "poisson.props")
      << "# thesis-style properties\ncount = 300\nmin_distance = 7\n";
  ScriptSession s(options_);
  s.run_text(
      "sphere s\nscale s 50 80 50\npoint_set_gen s poisson poisson.props\nsave_point_set "
      "points.txt\n",
      "crown.rf");
  EXPECT_GT(value(s, "s", Vec3(0, 79, 0)), 0.5);
  EXPECT_LT(value(s, "s", Vec3(0, 81, 0)), 0.5);
  s.commit();
  const PointSet p = read_points((dir_ / "points.txt").string());
  ASSERT_EQ(p.size(), 300u);
  double closest = 1e300;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3& q = p.positions[i];
    // Inside the ellipsoid of semi-axes 50, 80, 50 (the scaled unit sphere).
    EXPECT_LT(std::pow(q.x() / 50, 2) + std::pow(q.y() / 80, 2) + std::pow(q.z() / 50, 2), 1.0)
        << i;
    for (std::size_t j = 0; j < i; ++j) closest = std::min(closest, (q - p.positions[j]).norm());
  }
  EXPECT_GE(closest, 7.0);
}

TEST_F(ScriptTest, ThinningGrowthAndSkeletonsThroughTheLanguage) {
  ScriptSession s(options_);
  const auto results = s.run_text(
      "sphere crown 2 center=0,0,4\nsphere secondary 1 center=1,0,4\n"
      "point_set_gen crown uniform count=800\npoint_set_thin crown secondary 100\n"
      "save_point_set thinned.txt\n"
      "grow tree from crown step=0.25 influence=1.5 kill=0.5 root=0,0,0\nsave_skeleton tree "
      "tree.json\n"
      "lsystem plant bush-2d iterations=2\nsave_skeleton plant plant.json\n",
      "t.rf");
  s.commit();
  // Every point inside `secondary` was removed, none outside it.
  const PointSet thinned = read_points((dir_ / "thinned.txt").string());
  EXPECT_LT(thinned.size(), 800u);
  for (const Vec3& q : thinned.positions) EXPECT_GT((q - Vec3(1, 0, 4)).norm(), 0.999);
  const Skeleton tree = read_skeleton((dir_ / "tree.json").string());
  EXPECT_EQ(connected_components(tree).count, 1u);
  EXPECT_EQ(tree.edge_count() + 1, tree.node_count());
  EXPECT_EQ(tree.nodes[0].position, Vec3(0, 0, 0));
  // Every node lies inside the crown (a sphere of radius 2 about (0,0,4)) except the trunk that
  // leads to it from the root: a chain without forks.
  std::vector<std::vector<std::uint32_t>> adjacent(tree.node_count());
  for (const auto& e : tree.edges) {
    adjacent[e[0]].push_back(e[1]);
    adjacent[e[1]].push_back(e[0]);
  }
  auto inside = [&](std::uint32_t v) {
    return (tree.nodes[v].position - Vec3(0, 0, 4)).norm() < 2.0;
  };
  std::vector<char> trunk(tree.node_count(), 0);
  for (std::uint32_t v = 0, previous = UINT32_MAX; !inside(v);) {
    trunk[v] = 1;
    std::vector<std::uint32_t> next;
    for (std::uint32_t w : adjacent[v]) {
      if (w != previous) next.push_back(w);
    }
    ASSERT_EQ(next.size(), 1u) << "the tree forks outside the crown at node " << v;
    previous = v;
    v = next[0];
  }
  std::size_t outside = 0;
  for (std::uint32_t v = 0; v < tree.node_count(); ++v) {
    if (!trunk[v]) {
      EXPECT_TRUE(inside(v)) << "node " << v << " at " << tree.nodes[v].position.transpose();
    }
    outside += trunk[v];
  }
  EXPECT_LT(outside, 20u);
  const Skeleton plant = read_skeleton((dir_ / "plant.json").string());
  EXPECT_EQ(connected_components(plant).count, 1u);
  EXPECT_EQ(plant.edge_count() + 1, plant.node_count());
  // Errors of the pipeline commands name the line and the problem.
  EXPECT_NE(std::string(error_of("sphere s\npoint_set_gen s poison\n").what())
                .find("(did you mean 'poisson'?)"),
            std::string::npos);
  EXPECT_NE(std::string(error_of("sphere s\ngrow t from s\n").what()).find("no point set 's'"),
            std::string::npos);
  EXPECT_NE(std::string(error_of("lsystem p bush2d\n").what()).find("did you mean 'bush-2d'"),
            std::string::npos);
  const InputError bad = error_of("sphere s\npoint_set_gen s uniform count=10\ngrow t of s\n");
  EXPECT_EQ(bad.line(), 3u);
  EXPECT_EQ(bad.column(), 8u);
}

TEST_F(ScriptTest, GrowSmoothsAndPrunesWhenAsked) {
  const std::string base =
      "sphere crown 2.5 center=0,0,4\npoint_set_gen crown uniform count=1500\n";
  ScriptSession s(options_);
  const auto results =
      s.run_text(base +
                     "grow raw from crown step=0.2 influence=1.2 kill=0.4\n"
                     "grow tree from crown step=0.2 influence=1.2 kill=0.4 smooth=8 prune=2\n"
                     "save_skeleton raw raw.json\nsave_skeleton tree tree.json\n",
                 "t.rf");
  s.commit();
  std::vector<std::string> grown;
  for (const CommandResult& r : results)
    if (r.command == "grow") grown.push_back(r.message);
  ASSERT_EQ(grown.size(), 2u);
  // Off by default: nothing changes, the figures are still reported.
  EXPECT_NE(grown[0].find("cleanup: 0 nodes moved, 0 removed (0 kinks, 0 stubs pruned)"),
            std::string::npos)
      << grown[0];
  EXPECT_NE(grown[0].find("tip branches shorter than 2 steps"), std::string::npos) << grown[0];
  EXPECT_EQ(grown[1].find(" 0 stubs pruned"), std::string::npos) << grown[1];
  const Skeleton raw = read_skeleton((dir_ / "raw.json").string());
  const Skeleton tree = read_skeleton((dir_ / "tree.json").string());
  EXPECT_LT(tree.node_count(), raw.node_count());
  const std::string removed = std::to_string(raw.node_count() - tree.node_count()) + " removed";
  EXPECT_NE(grown[1].find(removed), std::string::npos) << grown[1];
  EXPECT_EQ(tree.nodes[0].position, raw.nodes[0].position);
  // Bad values name the option.
  EXPECT_NE(std::string(error_of(base + "grow t from crown prune=-1\n").what())
                .find("prune must be a number of growth steps >= 0, got -1"),
            std::string::npos);
  EXPECT_NE(std::string(error_of(base + "grow t from crown smooth=1001\n").what()).find("smooth"),
            std::string::npos);
  EXPECT_NE(std::string(error_of(base + "grow t from crown smooth=1.5\n").what()).find("smooth"),
            std::string::npos);
  EXPECT_NE(std::string(error_of(base + "grow t from crown max_turn=0\n").what())
                .find("max_turn must be an angle in (0, 180] degrees, got 0"),
            std::string::npos);
}

TEST_F(ScriptTest, PointSetsDependOnlyOnTheSeed) {
  auto run = [&](std::uint64_t seed) {
    options_.seed = seed;
    ScriptSession s(options_);
    s.run_text("sphere s\npoint_set_gen s poisson count=200\nsave_point_set p.txt\n", "t.rf");
    s.commit();
    std::ifstream in(dir_ / "p.txt");
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string a = run(5);
  EXPECT_EQ(a, run(5));
  EXPECT_NE(a, run(6));
}

TEST_F(ScriptTest, TransformsRebindTheNameAndCopiesKeepTheOldShape) {
  ScriptSession s(options_);
  s.run_text("sphere a 1\ncopy a b\ntranslate a 3 0 0\nrotate b z 90 center=0,2,0\n", "t.rf");
  EXPECT_NEAR(value(s, "a", Vec3(3, 0, 0)), 1.0, 1e-12);
  // b: the unit sphere at the origin turned 90 degrees about (0,2,0): centre (2,2,0).
  EXPECT_NEAR(value(s, "b", Vec3(2, 2, 0)), 1.0, 1e-12);
  EXPECT_NEAR(value(s, "b", Vec3(2.5, 2, 0)), wyvill(0.25), 1e-12);
}

TEST_F(ScriptTest, ParametersTakeDefaultsAndOverrides) {
  {
    ScriptSession s(options_);
    s.run_text("param r 2\nsphere s $r\n", "t.rf");
    EXPECT_NEAR(value(s, "s", Vec3(1.9, 0, 0)), wyvill(1.9 / 4), 1e-12);
  }
  options_.params["r"] = "0.5";
  {
    ScriptSession s(options_);
    s.run_text("param r 2\nsphere s ${r}\n", "t.rf");
    EXPECT_NEAR(value(s, "s", Vec3(0.4, 0, 0)), wyvill(0.4), 1e-12);
  }
  options_.params["radius"] = "1";
  const InputError e = error_of("param r 2\nsphere s $r\n");
  EXPECT_NE(std::string(e.what()).find("no parameter 'radius'"), std::string::npos) << e.what();
}

struct BadLine {
  const char* script;
  std::size_t line;
  std::size_t column;
  const char* words;
};

TEST_F(ScriptTest, ErrorsNameLineColumnCommandAndExpectation) {
  const BadLine cases[] = {
      {"sphre s\n", 1, 1, "unknown command 'sphre' (did you mean 'sphere'?)"},
      {"sphere s1\nline s2\ndiff s1 s4 s3\n", 3, 9,
       "diff: unknown shape 's4' (did you mean 's1'?)"},
      {"sphere s x\n", 1, 10, "sphere: expected a number for radius, got 'x'"},
      {"sphere s -1\n", 1, 10, "radius must be > 0"},
      {"sphere s 1 centre=0,0,0\n", 1, 12, "unknown option 'centre' (did you mean 'center'?)"},
      {"sphere s 1 center=0,0\n", 1, 19, "expected X,Y,Z"},
      {"sphere s\nsave_mesh s ../up.ply\n", 2, 13, "outside the output directory"},
      {"sphere s\nsave_mesh s s.stl\n", 2, 13, "mesh files end in .ply, .obj, .off or .glb"},
      {"sphere s\ndiff s s\n", 2, 1, "expected A B OUT"},
      {"curve c polyline 0 0 1 1\nsweep w c c\n", 2, 11, "'c' is a 2-D curve, expected a 3-D path"},
      {"curve c polyline 0 0 1\n", 1, 22, "X Y pairs"},
      {"curve c polygon 0 0 1 1\n", 1, 9, "(did you mean 'polyline'?)"},
      {"sphere 1s\n", 1, 8, "not a valid object name"},
      {"sphere s \"unterminated\n", 1, 10, "unterminated quote"},
      {"sphere s $radius\n", 1, 10, "unknown parameter '$radius'"},
      {"skeleton t missing.json\n", 1, 12, "no such file"},
      {"plane p\nsave_mesh p p.ply\n", 2, 11, "unbounded"},
      {"sphere a\nsphere b 1 kernel=cauchy\n", 2, 19, "Cauchy kernel"},
  };
  for (const BadLine& c : cases) {
    const InputError e = error_of(c.script);
    EXPECT_EQ(e.file(), "t.rf");
    EXPECT_EQ(e.line(), c.line) << c.script;
    EXPECT_EQ(e.column(), c.column) << c.script << " -> " << e.what();
    EXPECT_NE(std::string(e.what()).find(c.words), std::string::npos)
        << c.script << " -> " << e.what();
    const std::string prefix =
        "t.rf:" + std::to_string(c.line) + ":" + std::to_string(c.column) + ": ";
    EXPECT_EQ(std::string(e.what()).rfind(prefix, 0), 0u) << e.what();
  }
}

TEST_F(ScriptTest, ErrorsInInputFilesNameTheScriptLineAndTheFileLine) {
  std::ofstream(dir_ / "bad.json") << "{\"nodes\": [}";
  const InputError e = error_of("sphere s\nskeleton t bad.json\n");
  EXPECT_EQ(e.line(), 2u);
  EXPECT_EQ(std::string(e.what()).rfind("t.rf:2:1: skeleton: ", 0), 0u) << e.what();
  EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  std::ofstream(dir_ / "pts.txt") << "0 0\n1 x\n";
  const InputError c = error_of("curve c polyline file=pts.txt\n");
  EXPECT_EQ(std::string(c.what()).rfind("t.rf:1:1: curve: ", 0), 0u) << c.what();
  EXPECT_NE(std::string(c.what()).find("pts.txt:2"), std::string::npos) << c.what();
}

TEST_F(ScriptTest, AFailedScriptLeavesNoOutput) {
  const std::string script = (dir_ / "bad.rf").string();
  std::ofstream(script)
      << "sphere s\nsave_mesh s a.ply resolution=16\nsave_mesh s b.obj resolution=16\n"
         "diff s nothing x\n";
  EXPECT_THROW(run_script(script, options_), InputError);
  EXPECT_EQ(files(), 1u);  // only bad.rf
  std::ofstream(script)
      << "sphere s\nsave_mesh s a.ply resolution=16\nsave_mesh s b.obj resolution=16\n";
  const auto results = run_script(script, options_);
  EXPECT_EQ(results.size(), 3u);
  EXPECT_TRUE(fs::exists(dir_ / "a.ply"));
  EXPECT_TRUE(fs::exists(dir_ / "b.obj"));
  EXPECT_EQ(files(), 3u);
}

TEST_F(ScriptTest, OutputsMayLeaveTheOutputDirectoryOnlyWhenAllowed) {
  fs::create_directories(dir_ / "out");
  options_.out_dir = (dir_ / "out").string();
  EXPECT_NE(std::string(error_of("sphere s\nsave_mesh s ../x.ply resolution=8\n").what())
                .find("--allow-any-path"),
            std::string::npos);
  options_.allow_any_path = true;
  ScriptSession s(options_);
  s.run_text("sphere s\nsave_mesh s ../x.ply resolution=8\n", "t.rf");
  s.commit();
  EXPECT_TRUE(fs::exists(dir_ / "x.ply"));
}

// The figures of a `deviation` message: {samples p50, p99, max, vertices p50, p99, max}.
std::array<double, 6> deviation_figures(const std::string& message) {
  const std::regex re(
      "deviation p50 ([^,]+), p99 ([^,]+), max ([^ ]+) .* vertices p50 ([^,]+), p99 ([^,]+), "
      "max ([^ ]+) ");
  std::smatch m;
  std::array<double, 6> out{};
  if (!std::regex_search(message, m, re)) {
    ADD_FAILURE() << "no deviation figures in: " << message;
    return out;
  }
  for (std::size_t k = 0; k < 6; ++k) out[k] = std::stod(m[k + 1].str());
  return out;
}

TEST_F(ScriptTest, DeviationMeasuresASavedMeshAgainstItsShape) {
  // A unit sphere meshed by marching cubes: each vertex lies ||v| - 1| from the surface, and
  // every point of a triangle within its largest vertex error plus its chord sag.
  ScriptSession s(options_);
  s.run_text("sphere s\nsave_mesh s s.ply resolution=20\n", "t.rf");
  const CommandResult r = s.execute_line("deviation s s.ply samples=4000");
  EXPECT_NE(r.message.find("model units over 4,000 points"), std::string::npos) << r.message;
  s.commit();
  const TriMesh mesh = read_mesh((dir_ / "s.ply").string());
  double vertex_max = 0, edge_max = 0;
  for (const Vec3& v : mesh.positions) vertex_max = std::max(vertex_max, std::abs(v.norm() - 1));
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      edge_max = std::max(edge_max, (mesh.positions[t[k]] - mesh.positions[t[(k + 1) % 3]]).norm());
    }
  }
  const auto f = deviation_figures(r.message);
  EXPECT_NEAR(f[5], vertex_max, 1e-5 * vertex_max);  // the message's 6 digits
  EXPECT_GT(f[2], 0.0);
  EXPECT_LE(f[1], f[2]);
  // A point of a triangle of the sphere's mesh is inside the sphere at most by the chord sag
  // (1 - cos of the half angle the longest edge spans) and outside by the vertex error.
  EXPECT_LE(f[2], vertex_max + edge_max * edge_max / 8 * 1.01);
  // The same file read from the input directory in a new run gives the same figures.
  ScriptSession again(options_);
  const CommandResult r2 = again.execute_line("sphere s");
  (void)r2;
  EXPECT_EQ(deviation_figures(again.execute_line("deviation s s.ply samples=4000").message), f);
}

TEST_F(ScriptTest, DeviationOfATetsMeshIsRelativeToTheLocalRadius) {
  {
    std::ofstream out(dir_ / "fork.json");
    out << R"({"nodes": [{"id": 0, "position": [0, 0, 0], "radius": 0.1},
      {"id": 1, "position": [0, 0, 1], "radius": 0.07},
      {"id": 2, "position": [0.4, 0, 1.5], "radius": 0.04},
      {"id": 3, "position": [-0.3, 0.1, 1.6], "radius": 0.05}],
      "edges": [[0, 1], [1, 2], [1, 3]]})";
  }
  ScriptSession s(options_);
  s.run_text(
      "skeleton fork fork.json surface=convolution\n"
      "save_mesh fork fork.ply method=tets tolerance=0.1\n",
      "t.rf");
  const CommandResult r = s.execute_line("deviation fork fork.ply");
  EXPECT_NE(r.message.find("of the local radius over 20,000 points"), std::string::npos)
      << r.message;
  const auto f = deviation_figures(r.message);
  EXPECT_LE(f[1], 0.1);   // the tolerance it was meshed to
  EXPECT_LT(f[5], 1e-3);  // vertices lie on the surface
  // Bad input: a missing file, a bad option.
  EXPECT_THROW((void)s.execute_line("deviation fork nothing.ply"), InputError);
  EXPECT_THROW((void)s.execute_line("deviation fork fork.ply samples=-1"), InputError);
  EXPECT_THROW((void)s.execute_line("deviation nobody fork.ply"), InputError);
}

TEST_F(ScriptTest, HelpListsEveryCommandAndDescribesOne) {
  const auto names = ScriptSession::command_names();
  for (const char* want : {"sphere",         "line",           "circle",         "box",
                           "cylinder",       "cone",           "plane",          "skeleton",
                           "blend",          "union",          "intersect",      "diff",
                           "translate",      "rotate",         "scale",          "bend",
                           "taper",          "twist",          "curve",          "path",
                           "revolve",        "sweep",          "skin",           "rbf",
                           "save_mesh",      "eval",           "eval_points",    "param",
                           "help",           "point_set_gen",  "save_point_set", "point_set_thin",
                           "load_point_set", "point_set_mesh", "grow",           "lsystem",
                           "save_skeleton",  "deviation"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  }
  EXPECT_NE(ScriptSession::command_help("skin").find("SECTION@S"), std::string::npos);
  EXPECT_THROW((void)ScriptSession::command_help("skn"), InvalidArgument);
  ScriptSession s(options_);
  EXPECT_NE(s.execute_line("help").message.find("save_mesh NAME FILE"), std::string::npos);
}

TEST_F(ScriptTest, TokenizerKeepsQuotedPathsAndStripsComments) {
  fs::create_directories(dir_ / "with space");
  ScriptSession s(options_);
  s.run_text(
      "# a comment line\n\n  sphere s   # trailing comment\nsave_mesh s \"with space/s.off\" "
      "resolution=8\n",
      "t.rf");
  s.commit();
  EXPECT_TRUE(fs::exists(dir_ / "with space" / "s.off"));
}

// ScriptOptions::on_mesh sees each save_mesh's mesh as polygonized, before normals and bark UVs:
// the geometry its files hold (a .ply without UVs has exactly its vertices and triangles; the
// textured .glb only adds seam copies).
TEST_F(ScriptTest, OnMeshSeesEachMeshAsPolygonized) {
  std::vector<std::pair<std::string, TriMesh>> seen;
  ScriptOptions o = options_;
  o.on_mesh = [&](const std::string& shape, const TriMesh& mesh) {
    EXPECT_TRUE(mesh.normals.empty() && mesh.uvs.empty());
    seen.emplace_back(shape, mesh);
  };
  ScriptSession s(o);
  s.run_text(
      "lsystem t binary iterations=3\nsave_mesh t t.ply t.glb method=tets levels=0\n"
      "sphere b 1\nsave_mesh b b.ply resolution=20\n",
      "t.rf");
  s.commit();
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].first, "t");
  EXPECT_EQ(seen[1].first, "b");
  for (const auto& [shape, mesh] : seen) {
    const TriMesh saved = read_mesh((dir_ / (shape + ".ply")).string());
    EXPECT_EQ(mesh.positions, saved.positions) << shape;
    EXPECT_EQ(mesh.triangles, saved.triangles) << shape;
  }
}

// A draft run (ScriptOptions::draft, the studio's slider previews): save_mesh meshes tets at the
// base lattice exactly as levels=0 does and mc at resolution kDraftResolution at most; draw
// writes nothing; the shapes and skeletons are those of the full run.
TEST_F(ScriptTest, DraftRunsMeshCoarselyAndDrawNothing) {
  const std::string tree = "lsystem t binary iterations=3\n";
  const auto mesh_of = [&](const std::string& text, bool draft, const std::string& file) {
    ScriptOptions o = options_;
    o.draft = draft;
    ScriptSession s(o);
    s.run_text(text, "t.rf");
    s.commit();
    return read_mesh((dir_ / file).string());
  };
  const TriMesh full =
      mesh_of(tree + "save_mesh t full.ply method=tets tolerance=0.05\n", false, "full.ply");
  const TriMesh base =
      mesh_of(tree + "save_mesh t base.ply method=tets levels=0\n", false, "base.ply");
  const TriMesh draft =
      mesh_of(tree + "save_mesh t draft.ply method=tets tolerance=0.05\n", true, "draft.ply");
  EXPECT_EQ(draft.positions, base.positions);
  EXPECT_EQ(draft.triangles, base.triangles);
  EXPECT_LT(draft.triangle_count(), full.triangle_count());
  const MeshReport r = check_mesh(draft);
  EXPECT_TRUE(r.watertight && r.oriented && r.manifold);
  EXPECT_EQ(r.components, 1u);

  // Marching cubes: resolution 200 asked, 48 made (the same mesh as resolution=48).
  const TriMesh mc_draft = mesh_of("sphere b 1\nsave_mesh b d.ply resolution=200\n", true, "d.ply");
  const TriMesh mc48 = mesh_of("sphere b 1\nsave_mesh b m.ply resolution=48\n", false, "m.ply");
  EXPECT_EQ(mc_draft.triangles, mc48.triangles);
  // cell= finer than the draft allows is coarsened to the box over 48.
  const TriMesh cell_draft = mesh_of("sphere b 1\nsave_mesh b c.ply cell=0.001\n", true, "c.ply");
  EXPECT_LE(cell_draft.triangle_count(), mc48.triangle_count() * 11 / 10);

  // draw: nothing written, and the report says why.
  ScriptOptions o = options_;
  o.draft = true;
  ScriptSession s(o);
  const auto results = s.run_text("sphere b 1\ndraw b b.svg count=500\n", "t.rf");
  s.commit();
  EXPECT_FALSE(fs::exists(dir_ / "b.svg"));
  EXPECT_NE(results.back().message.find("draft"), std::string::npos);
}

}  // namespace
}  // namespace ramiform::test
