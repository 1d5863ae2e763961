// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The scene language's equipotential surfaces (Gruber & Wallner 2014): surface=equipotential on
// skeleton, grow and lsystem, and save_mesh method=particles. The shapes are checked against the
// library's field built independently, and the meshes for the properties the particle mesher
// promises: closed where the ends are closed, one boundary loop per open end, every vertex on
// the surface, every node inside.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>
#include <regex>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/winding.h"
#include "ramiform/polygonize/particles.h"
#include "ramiform/script/script.h"
#include "script/script_fixture.h"
#include "support/fixtures.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Boundary loops of a mesh: the connected parts of the graph of its boundary edges (edges whose
// opposite half-edge no triangle has).
std::size_t boundary_loops(const TriMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> half;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++half[{t[k], t[(k + 1) % 3]}];
  }
  std::vector<std::uint32_t> parent(mesh.positions.size());
  std::iota(parent.begin(), parent.end(), 0U);
  const auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<char> on_boundary(mesh.positions.size(), 0);
  for (const auto& [e, n] : half) {
    if (half.count({e.second, e.first}) != 0) continue;
    on_boundary[e.first] = on_boundary[e.second] = 1;
    parent[find(e.first)] = find(e.second);
  }
  std::size_t loops = 0;
  for (std::uint32_t v = 0; v < parent.size(); ++v) loops += on_boundary[v] != 0 && find(v) == v;
  return loops;
}

class EquipotentialScriptTest : public ScriptDirTest {
 protected:
  // A small Y: trunk 3 long, two branches; leaves 0, 2 and 3.
  void SetUp() override {
    ScriptDirTest::SetUp();
    y_ = y_fork(0.3);
    write_skeleton(y_, (dir_ / "y.json").string());
  }

  static double value(ScriptSession& s, const std::string& name, const Vec3& p) {
    const CommandResult r = s.execute_line("eval " + name + " " + exact(p.x()) + " " +
                                           exact(p.y()) + " " + exact(p.z()));
    return std::stod(r.message.substr(r.message.find("= ") + 2));
  }

  // The points where the meshes are checked against the field: on each edge's axis at its
  // middle, and about each middle at the node radii, plus points far away.
  std::vector<Vec3> probes() const {
    std::vector<Vec3> p;
    for (const auto& e : y_.edges) {
      const Vec3 a = y_.nodes[e[0]].position;
      const Vec3 b = y_.nodes[e[1]].position;
      const Vec3 m = 0.5 * (a + b);
      p.push_back(m);
      p.push_back(m + Vec3(0, 0.3, 0));
      p.push_back(m + Vec3(0, 0.9, 0.1));
    }
    p.emplace_back(7, 1, -2);
    p.emplace_back(0, 0, 40);
    return p;
  }

  TriMesh committed_mesh(ScriptSession& s, const std::string& file) {
    s.commit();
    return read_mesh((dir_ / file).string());
  }

  Skeleton y_;
};

TEST_F(EquipotentialScriptTest, SkeletonShapeIsTheLibrarysEquipotentialField) {
  ScriptSession s(options_);
  const auto results = s.run_text(
      "skeleton y y.json surface=equipotential alpha=3 charge_spacing=0.1 lambda_scale=0.5\n"
      "skeleton q y.json surface=equipotential charge=0.25 lambda=2\n",
      "t.rf");
  EquipotentialOptions o;
  o.alpha = 3;
  o.charge_spacing = 0.1;
  o.lambda_scale = 0.5;
  const Equipotential eq = make_equipotential(y_, o);
  EquipotentialOptions oq;
  oq.charge = 0.25;
  oq.lambda = 2;
  const Equipotential q = make_equipotential(y_, oq);
  for (const Vec3& p : probes()) {
    const double want = eq.field->value(p);
    EXPECT_NEAR(value(s, "y", p), want, 1e-13 * std::abs(want)) << p.transpose();
    const double want_q = q.field->value(p);
    EXPECT_NEAR(value(s, "q", p), want_q, 1e-13 * std::abs(want_q)) << p.transpose();
  }
  // The iso value is lambda (estimated, times lambda_scale; or the given one), and the summary
  // says what was built.
  const CommandResult info = s.execute_line("info y");
  EXPECT_NE(info.message.find("iso " + format_number(eq.lambda)), std::string::npos)
      << info.message;
  EXPECT_NE(s.execute_line("info q").message.find("iso 2"), std::string::npos);
  EXPECT_NE(results[0].message.find("equipotential surface (alpha 3, " +
                                    std::to_string(eq.charges.positions.size()) + " charges"),
            std::string::npos)
      << results[0].message;
  // Inside near the skeleton, outside far from it.
  EXPECT_GT(value(s, "y", y_.nodes[1].position), eq.lambda);
  EXPECT_LT(value(s, "y", Vec3(7, 1, -2)), eq.lambda);
}

TEST_F(EquipotentialScriptTest, EquipotentialOptionsOnAnotherSurfaceFailAtTheirToken) {
  const std::string line = "skeleton y y.json surface=convolution alpha=3";
  const InputError e = error_of(line + "\n");
  EXPECT_EQ(e.line(), 1u);
  EXPECT_EQ(e.column(), line.find("alpha=") + 1 + 6) << e.what();  // the value's column
  EXPECT_NE(std::string(e.what()).find("alpha= applies to surface=equipotential, not to "
                                       "surface=convolution"),
            std::string::npos)
      << e.what();
  // The default surface of skeleton is distance, of lsystem and grow convolution.
  EXPECT_NE(std::string(error_of("skeleton y y.json open_ends=yes\n").what())
                .find("open_ends= applies to surface=equipotential, not to surface=distance"),
            std::string::npos);
  EXPECT_NE(std::string(error_of("lsystem p binary iterations=2 fit_radii=yes\n").what())
                .find("fit_radii= applies to surface=equipotential"),
            std::string::npos);
  EXPECT_NE(std::string(error_of("sphere c 3 center=0,0,5\npoint_set_gen c uniform count=50\n"
                                 "grow t from c lambda_scale=0.5\n")
                            .what())
                .find("t.rf:3:"),
            std::string::npos);
  // Bad values fail at their token too.
  EXPECT_NE(std::string(error_of("skeleton y y.json surface=equipotential alpha=1.5\n").what())
                .find("alpha must be in [2, 16], got 1.5"),
            std::string::npos);
  EXPECT_NE(std::string(error_of("skeleton y y.json surface=equipotential kernel=wyvill\n").what())
                .find("kernel= applies to surface=distance"),
            std::string::npos);
  EXPECT_NE(std::string(error_of("skeleton y y.json surface=equipotential fit_radii=yes "
                                 "lambda_scale=0.5\n")
                            .what())
                .find("lambda_scale= does not change the surface with fit_radii=yes"),
            std::string::npos);
}

TEST_F(EquipotentialScriptTest, ParticleOptionsBelongToMethodParticles) {
  const std::string base = "skeleton y y.json surface=equipotential\n";
  EXPECT_NE(std::string(error_of(base + "save_mesh y y.ply n_circ=8\n").what())
                .find("n_circ= applies to method=particles"),
            std::string::npos);
  EXPECT_NE(std::string(error_of(base + "save_mesh y y.ply method=tets relax=0\n").what())
                .find("relax= applies to method=particles"),
            std::string::npos);
  EXPECT_NE(
      std::string(error_of(base + "save_mesh y y.ply method=particles resolution=40\n").what())
          .find("resolution= applies to method=mc"),
      std::string::npos);
  EXPECT_NE(
      std::string(error_of(base + "save_mesh y y.ply method=particles tolerance=0.1\n").what())
          .find("tolerance= applies to method=tets"),
      std::string::npos);
  EXPECT_NE(std::string(error_of(base + "save_mesh y y.ply method=particles n_circ=2\n").what())
                .find("n_circ must be an integer in [3, 4096], got 2"),
            std::string::npos);
  EXPECT_NE(std::string(error_of(base + "save_mesh y y.ply method=particles delta=1\n").what())
                .find("delta must be in (0, 1)"),
            std::string::npos);
  // A shape without a skeleton, and one whose skeleton a transform dropped.
  EXPECT_NE(std::string(error_of("sphere s\nsave_mesh s s.ply method=particles\n").what())
                .find("method=particles needs a shape made by skeleton, grow or lsystem"),
            std::string::npos);
  EXPECT_NE(
      std::string(error_of(base + "translate y 1 0 0\nsave_mesh y y.ply method=particles\n").what())
          .find("t.rf:3:"),
      std::string::npos);
  EXPECT_EQ(files(), 1u);  // y.json only: no failed script left a file
}

TEST_F(EquipotentialScriptTest, ParticleMeshIsClosedOnTheSurfaceAndHoldsTheNodes) {
  ScriptSession s(options_);
  const auto results = s.run_text(
      "skeleton y y.json surface=equipotential alpha=4 charge=0.25\n"
      "copy y y2\n"
      "save_mesh y2 y.ply method=particles n_circ=10 delta=0.0005\n",
      "t.rf");
  const std::string& message = results.back().message;
  const TriMesh mesh = committed_mesh(s, "y.ply");
  const MeshReport r = check_mesh(mesh);
  EXPECT_TRUE(r.watertight && r.oriented && r.manifold) << r.boundary_edges;
  EXPECT_EQ(r.components, 1u);
  EXPECT_GT(signed_volume(mesh), 0.0);
  // The message: every particle (= vertex) converged, and the mesh is closed.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      message, m, std::regex(R"(\(particles: ([0-9,]+) particles, ([0-9,]+) converged, )")))
      << message;
  const auto count = [](std::string t) {
    std::erase(t, ',');
    return std::stoul(t);
  };
  EXPECT_EQ(count(m[1].str()), mesh.vertex_count());
  EXPECT_EQ(count(m[2].str()), mesh.vertex_count());
  EXPECT_NE(message.find("watertight, 1 component(s)"), std::string::npos) << message;
  // Every vertex on the surface of the library's field to within delta lambda.
  EquipotentialOptions o;
  o.charge = 0.25;
  const Equipotential eq = make_equipotential(y_, o);
  std::vector<double> f(mesh.vertex_count());
  eq.field->evaluate(mesh.positions, f);
  double worst = 0;
  for (const double v : f) worst = std::max(worst, std::abs(v - eq.lambda));
  EXPECT_LE(worst, 0.0005 * eq.lambda * (1 + 1e-9));
  // Every skeleton node inside the mesh.
  std::vector<Vec3> nodes;
  for (const auto& node : y_.nodes) nodes.push_back(node.position);
  const auto inside = points_inside(mesh, nodes);
  for (std::size_t i = 0; i < nodes.size(); ++i) EXPECT_EQ(inside[i], 1) << "node " << i;
}

TEST_F(EquipotentialScriptTest, OpenEndsGiveOneBoundaryLoopPerOpenLeaf) {
  // Every leaf open: three loops.
  {
    ScriptSession s(options_);
    const auto results = s.run_text(
        "skeleton y y.json surface=equipotential open_ends=yes\n"
        "save_mesh y all_open.ply method=particles\n",
        "t.rf");
    EXPECT_NE(results[0].message.find("3 open end(s)"), std::string::npos) << results[0].message;
    const TriMesh mesh = committed_mesh(s, "all_open.ply");
    const MeshReport r = check_mesh(mesh);
    EXPECT_FALSE(r.watertight);
    EXPECT_TRUE(r.manifold && r.oriented);
    EXPECT_EQ(r.components, 1u);
    EXPECT_EQ(boundary_loops(mesh), 3u);
    EXPECT_NE(results[1].message.find("open at 3 end(s) as asked"), std::string::npos)
        << results[1].message;
  }
  // One leaf flagged open in the file ("end": "open"), the others closed.
  Skeleton flagged = y_;
  flagged.open_ends = {0, 0, 1, 0};
  write_skeleton(flagged, (dir_ / "flagged.json").string());
  ScriptSession s(options_);
  s.run_text(
      "skeleton y flagged.json surface=equipotential\n"
      "save_mesh y one_open.ply method=particles\n",
      "t.rf");
  const TriMesh mesh = committed_mesh(s, "one_open.ply");
  EXPECT_EQ(boundary_loops(mesh), 1u);
  EXPECT_TRUE(check_mesh(mesh).manifold);
  // The loop is at the flagged leaf: its vertices lie nearer node 2 than any other node.
  std::size_t near_leaf = 0, boundary = 0;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> half;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) ++half[{t[k], t[(k + 1) % 3]}];
  }
  for (const auto& [e, count] : half) {
    if (half.count({e.second, e.first}) != 0) continue;
    ++boundary;
    const Vec3& p = mesh.positions[e.first];
    std::size_t best = 0;
    for (std::size_t i = 1; i < y_.nodes.size(); ++i) {
      if ((p - y_.nodes[i].position).norm() < (p - y_.nodes[best].position).norm()) best = i;
    }
    near_leaf += best == 2;
  }
  EXPECT_GT(boundary, 0u);
  EXPECT_EQ(near_leaf, boundary);
}

TEST_F(EquipotentialScriptTest, OtherSurfacesAreMeshedByParticlesToo) {
  ScriptSession s(options_);
  s.run_text(
      "skeleton y y.json surface=convolution\n"
      "save_mesh y conv.ply method=particles\n",
      "t.rf");
  const TriMesh mesh = committed_mesh(s, "conv.ply");
  const MeshReport r = check_mesh(mesh);
  EXPECT_TRUE(r.watertight && r.oriented && r.manifold);
  EXPECT_EQ(r.components, 1u);
  SkeletonFieldOptions o;  // the convolution surface of `skeleton ... surface=convolution`
  o.surface = SurfaceKind::kConvolution;
  o.kernel = Kernel{KernelKind::kCauchy, 0.0};
  const FieldPtr field = make_skeleton_field(y_, o);
  std::vector<double> f(mesh.vertex_count());
  field->evaluate(mesh.positions, f);
  const double iso = field->iso();
  for (const double v : f)
    ASSERT_LE(std::abs(v - iso), ParticleMeshOptions{}.delta * std::abs(iso) * 1.0001);
}

TEST_F(EquipotentialScriptTest, UnconvergedParticlesFailTheCommandAndWriteNothing) {
  const InputError e = error_of(
      "skeleton y y.json surface=equipotential lambda_scale=0.2\n"
      "save_mesh y y.ply method=particles max_iterations=1 relax=0\n");
  EXPECT_EQ(e.line(), 2u);
  EXPECT_NE(std::string(e.what()).find("particles did not reach the surface within delta 0.001 "
                                       "after 1 iterations"),
            std::string::npos)
      << e.what();
  EXPECT_NE(std::string(e.what()).find("raise max_iterations= (now 1)"), std::string::npos);
  EXPECT_EQ(files(), 1u);  // y.json only
}

TEST_F(EquipotentialScriptTest, LsystemAndGrowTakeTheEquipotentialSurface) {
  ScriptSession s(options_);
  const auto results = s.run_text(
      "lsystem plant binary iterations=2 surface=equipotential alpha=5\n"
      "save_mesh plant plant.ply method=particles n_circ=8\n"
      "sphere crown 2 center=0,0,4\n"
      "point_set_gen crown uniform count=60\n"
      "grow tree from crown step=0.5 influence=2 kill=0.8 surface=equipotential\n",
      "t.rf");
  EXPECT_NE(results[0].message.find("equipotential surface (alpha 5, "), std::string::npos)
      << results[0].message;
  EXPECT_NE(results[4].message.find("equipotential surface (alpha 4, "), std::string::npos)
      << results[4].message;
  const TriMesh mesh = committed_mesh(s, "plant.ply");
  const MeshReport r = check_mesh(mesh);
  EXPECT_TRUE(r.watertight && r.oriented && r.manifold);
  EXPECT_EQ(r.components, 1u);
  // The tree's root (grow starts at the origin) is inside its equipotential surface.
  const CommandResult root = s.execute_line("eval tree 0 0 0");
  EXPECT_NE(root.message.find("(inside"), std::string::npos) << root.message;
}

TEST_F(EquipotentialScriptTest, FitRadiiPutsTheSurfaceAtTheRadii) {
  ScriptSession s(options_);
  s.run_text(
      "skeleton fitted y.json surface=equipotential fit_radii=yes\n"
      "skeleton plain y.json surface=equipotential charge=0.5\n",
      "t.rf");
  // The surface's distance from the axis at the middle of each edge, by bisection on the field
  // along a ray perpendicular to the edge, against the radius interpolated there.
  const auto radius_error = [&](const std::string& name) {
    double worst = 0;
    const std::string info = s.execute_line("info " + name).message;
    const double iso = std::stod(info.substr(info.find("iso ") + 4));
    for (const auto& e : y_.edges) {
      const Vec3 a = y_.nodes[e[0]].position;
      const Vec3 b = y_.nodes[e[1]].position;
      const Vec3 m = 0.5 * (a + b);
      const double want = 0.5 * (y_.nodes[e[0]].radius + y_.nodes[e[1]].radius);
      const Vec3 dir = Vec3(0, 1, 0);  // every edge lies in the xz plane
      double lo = 0.01 * want, hi = 5 * want;
      for (int k = 0; k < 50; ++k) {
        const double mid = 0.5 * (lo + hi);
        (value(s, name, m + mid * dir) > iso ? lo : hi) = mid;
      }
      worst = std::max(worst, std::abs(lo / want - 1));
    }
    return worst;
  };
  EXPECT_LT(radius_error("fitted"), 0.05);
  EXPECT_GT(radius_error("plain"), 0.2);  // one charge for all: the radii do not matter
}

TEST(EquipotentialHelp, HelpStatesTheOptionsAndTheirDefaults) {
  const std::string skeleton = ScriptSession::command_help("skeleton");
  for (const char* key : {"`alpha` (default 4, 2\u201316)", "`lambda_scale` (default 1)",
                          "`charge`", "`charge_spacing`", "`open_ends`", "`fit_radii`"}) {
    EXPECT_NE(skeleton.find(key), std::string::npos) << key;
  }
  const std::string save_mesh = ScriptSession::command_help("save_mesh");
  for (const char* key : {"method=particles", "`n_circ` (default 12, 3\u20134096)",
                          "`max_iterations` (default 200, 1\u2013100000)", "`delta`"}) {
    EXPECT_NE(save_mesh.find(key), std::string::npos) << key;
  }
  for (const char* command : {"grow", "lsystem"}) {
    EXPECT_NE(ScriptSession::command_help(command).find("`surface`=equipotential"),
              std::string::npos)
        << command;
  }
}

}  // namespace
}  // namespace ramiform::test
