// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The scene commands of Rigaudière et al.'s skeletons: deform, bezier, patch, superquadric and
// `line ... def=D`. Each shape is inside on its skeleton and outside far away and equals the
// library's field built directly; errors point at the offending token; meshes are watertight.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/script/script.h"
#include "ramiform/skeleton/from_points.h"
#include "script/script_fixture.h"

namespace ramiform::test {
namespace {

using SkeletalCommandsTest = ScriptDirTest;

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

double value(ScriptSession& s, const std::string& name, const Vec3& p) {
  const CommandResult r = s.execute_line("eval " + name + " " + exact(p.x()) + " " +
                                         exact(p.y()) + " " + exact(p.z()));
  return std::stod(r.message.substr(r.message.find("= ") + 2));
}

TEST_F(SkeletalCommandsTest, EachCommandDefinesAShape) {
  ScriptSession s(options_);
  s.run_text(
      "deform spindle squared-cosine 0.2\n"
      "deform ramp linear 1 2 1.5\n"
      "bezier b 0,0,0 1,0,1 2,0,0 3,0,0.5 radius=0.2 def=spindle\n"
      "bezier b2 0,0,0 1,1,0 2,0,0 radii=0.2,0.4,0.1 def=wave:0.3,2 tie=last\n"
      "line l 0 0 0 0 0 3 radius=0.3 def=ramp\n"
      "superquadric q 1 0.8 0.6 e1=0.5 e2=0.7 center=5,0,0 radius=0.1 def_u=ramp\n"
      "superquadric q1 2\n"
      // z_ij = [i in {1,2}] + 0.5 [j in {1,2}]: curved sides, so the curvature test subdivides
      // (a patch whose sides are all straight stays one flat piece, paper §4.1).
      "patch p 0,0,0 0,1,0.5 0,2,0.5 0,3,0 1,0,1 1,1,1.5 1,2,1.5 1,3,1 2,0,1 2,1,1.5 2,2,1.5 "
      "2,3,1 3,0,0 3,1,0.5 3,2,0.5 3,3,0 radius=0.1 def_v=spindle epsilon=5 depth=4\n",
      "t.rf");
  struct Probe {
    std::string name;
    Vec3 on;
  };
  const std::vector<Probe> probes = {
      {"b", Vec3(1.5, 0, 0.4375)},     // C(0.5) of the cubic
      {"b2", Vec3(1, 0.5, 0)},         // C(0.5) of the quadratic
      {"l", Vec3(0, 0, 1.5)},
      {"q", Vec3(6, 0, 0)},            // on the superquadric (u = 0.5, v = 0.5 -> +x)
      {"q1", Vec3(0, 0, 2)},           // the pole of a sphere of radius 2
      {"p", Vec3(1.5, 1.5, 1.125)},    // S(0.5, 0.5) of the patch
  };
  for (const Probe& pr : probes) {
    EXPECT_GT(value(s, pr.name, pr.on), 0.5) << pr.name;
    EXPECT_EQ(value(s, pr.name, pr.on + Vec3(50, 50, 50)), 0.0) << pr.name;
  }
  // The script's shapes are the library's fields.
  const Deformation spindle = parse_deformation("squared-cosine:0.2");
  const FieldPtr b = make_bezier_field(
      BezierCurve{{Vec3(0, 0, 0), Vec3(1, 0, 1), Vec3(2, 0, 0), Vec3(3, 0, 0.5)}, {}}, 0.2, spindle);
  const FieldPtr b2 = make_bezier_field(
      BezierCurve{{Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)}, {0.2, 0.4, 0.1}}, 1,
      parse_deformation("wave:0.3,2"), TieRule::kLast);
  const FieldPtr l = make_anisotropic_segment_field(Vec3(0, 0, 0), Vec3(0, 0, 3), 0.3,
                                                    parse_deformation("linear:1,2,1.5"));
  for (const Vec3& p : {Vec3(0.5, 0.1, 0.3), Vec3(1.5, 0, 0.2), Vec3(2.9, 0.1, 0.4),
                        Vec3(1, 0.3, 0.1), Vec3(0.1, 0.05, 1), Vec3(0, 0.2, 2.5)}) {
    EXPECT_EQ(value(s, "b", p), b->value(p)) << p.transpose();
    EXPECT_EQ(value(s, "b2", p), b2->value(p)) << p.transpose();
    EXPECT_EQ(value(s, "l", p), l->value(p)) << p.transpose();
  }
  // The line's def thins it where def is large: the ramp is 2 at the middle.
  EXPECT_GT(value(s, "l", Vec3(0.2, 0, 0.05)), 0.5);
  EXPECT_LE(value(s, "l", Vec3(0.2, 0, 1.5)), 0.5);
  // Shapes blend with other commands.
  s.execute_line("blend b l mix");
  EXPECT_NEAR(value(s, "mix", Vec3(0.1, 0, 0.1)),
              b->value(Vec3(0.1, 0, 0.1)) + l->value(Vec3(0.1, 0, 0.1)), 1e-15);
}

TEST_F(SkeletalCommandsTest, DeformObjectsAreUsedByName) {
  ScriptSession s(options_);
  s.run_text(
      "deform thin linear 2 2\n"
      "bezier a 0,0,0 1,1,0 2,0,0 radius=0.3 def=thin\n"
      "bezier b 0,0,0 1,1,0 2,0,0 radius=0.3 def=linear:2,2\n"
      "bezier c 0,0,0 1,1,0 2,0,0 radius=0.15\n"
      "line la 0 0 0 0 0 1 def=thin\n"
      "superquadric qa 1 def_u=thin def_v=thin\n"
      "superquadric qb 1 def_u=linear:2,2 def_v=linear:2,2\n",
      "t.rf");
  for (const Vec3& p : {Vec3(1, 0.4, 0.1), Vec3(0.2, 0.1, 0), Vec3(1.9, 0.05, 0.1)}) {
    EXPECT_EQ(value(s, "a", p), value(s, "b", p));
    // def = 2 everywhere halves the thickness: same as radius 0.15.
    EXPECT_NEAR(value(s, "a", p), value(s, "c", p), 1e-15);
  }
  for (const Vec3& p : {Vec3(1.05, 0, 0), Vec3(0, 0.3, 0.96)}) {
    EXPECT_EQ(value(s, "qa", p), value(s, "qb", p));
  }
  // A deformation is not a shape.
  EXPECT_THROW(s.execute_line("eval thin 0 0 0"), InputError);
  // A shape name is not a deformation.
  EXPECT_THROW(s.execute_line("bezier d 0,0,0 1,1,0 def=c"), InputError);
}

// `deform` keeps the values exactly as typed (no rounding on the way through its text form).
TEST_F(SkeletalCommandsTest, DeformKeepsFullPrecision) {
  ScriptSession s(options_);
  s.run_text(
      "deform d squared-cosine 0.123456789\n"
      "line a 0 0 0 0 0 3 def=d\n"
      "line b 0 0 0 0 0 3 def=squared-cosine:0.123456789\n",
      "t.rf");
  const Vec3 p(0.01, 0.02, 0.05);
  EXPECT_EQ(value(s, "a", p), value(s, "b", p));
}

// 1-based column of the value of option `key` in `line`.
std::size_t value_column(const std::string& line, const std::string& key) {
  return line.find(key + "=") + key.size() + 2;
}

// Expects the script to fail with an InputError at `line`:`column` whose message has `needle`.
void expect_error_at(ScriptDirTest& t, const InputError& e, std::size_t line, std::size_t column,
                     const std::string& needle) {
  (void)t;
  const std::string msg = e.what();
  EXPECT_EQ(e.line(), line) << msg;
  EXPECT_EQ(e.column(), column) << msg;
  EXPECT_NE(msg.find("t.rf:" + std::to_string(line) + ":" + std::to_string(column) + ":"),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find(needle), std::string::npos) << "'" << needle << "' not in: " << msg;
}

TEST_F(SkeletalCommandsTest, ErrorsPointAtTheToken) {
  const std::string p16 =
      " 0,0,0 0,1,0 0,2,0 0,3,0 1,0,0 1,1,1 1,2,1 1,3,0 2,0,0 2,1,1 2,2,1 2,3,0 3,0,0 3,1,0 "
      "3,2,0 3,3,0";
  // bezier with a single point
  expect_error_at(*this, error_of("bezier b 0,0,0\n"), 1, 1, "bezier");
  // radius= and radii= together: at radius=
  {
    const std::string line = "bezier b 0,0,0 1,0,0 radii=0.1,0.2 radius=0.3";
    expect_error_at(*this, error_of("sphere s\n" + line + "\n"), 2, value_column(line, "radius"),
                    "not both");
  }
  // unknown def kind: at the def option, naming the kind
  {
    const std::string line = "bezier b 0,0,0 1,0,0 def=bogus:1";
    expect_error_at(*this, error_of(line + "\n"), 1, value_column(line, "def"), "unknown kind 'bogus'");
    const std::string dl = "deform d bogus 1";
    expect_error_at(*this, error_of(dl + "\n"), 1, dl.find("bogus") + 1, "unknown kind 'bogus'");
    const std::string ll = "line l 0 0 0 0 0 1 def=wave:1";
    expect_error_at(*this, error_of(ll + "\n"), 1, value_column(ll, "def"), "amplitude");
    const std::string sl = "superquadric q def_v=linear:1";
    expect_error_at(*this, error_of(sl + "\n"), 1, value_column(sl, "def_v"), "linear");
  }
  // patch with 5 points
  expect_error_at(*this, error_of("patch p 0,0,0 1,0,0 2,0,0 3,0,0 4,0,0\n"), 1, 15,
                  "unexpected argument '1,0,0'");
  // superquadric e1=0, depth=11, epsilon=100
  {
    const std::string l1 = "superquadric q e1=0";
    expect_error_at(*this, error_of(l1 + "\n"), 1, value_column(l1, "e1"), "e1");
    const std::string l2 = "superquadric q depth=11";
    expect_error_at(*this, error_of(l2 + "\n"), 1, value_column(l2, "depth"), "depth");
    const std::string l3 = "superquadric q epsilon=100";
    expect_error_at(*this, error_of(l3 + "\n"), 1, value_column(l3, "epsilon"), "epsilon");
    const std::string l4 = "patch p" + p16 + " depth=11";
    expect_error_at(*this, error_of(l4 + "\n"), 1, value_column(l4, "depth"), "depth");
  }
  // a bad control point names its index
  {
    const std::string line = "bezier b 0,0,0 1,x,0";
    expect_error_at(*this, error_of(line + "\n"), 1, line.find("x") + 1, "control point 1");
  }
  // radii count mismatch comes from the library, labelled at the command's line
  {
    const InputError e = error_of("sphere s\nbezier b 0,0,0 1,0,0 2,0,0 radii=0.1,0.2\n");
    EXPECT_EQ(e.line(), 2u) << e.what();
    EXPECT_NE(std::string(e.what()).find("radii"), std::string::npos) << e.what();
  }
  // line: radius_end with def
  {
    const std::string line = "line l 0 0 0 0 0 1 radius_end=0.5 def=flat";
    expect_error_at(*this, error_of(line + "\n"), 1, value_column(line, "radius_end"),
                    "radius_end does not apply");
  }
  // an unknown option is refused
  EXPECT_NE(std::string(error_of("bezier b 0,0,0 1,0,0 radus=0.3\n").what()).find("radus"),
            std::string::npos);
}

TEST_F(SkeletalCommandsTest, MeshesAreWatertight) {
  ScriptSession s(options_);
  s.run_text(
      "bezier b 0,0,0 1,0,1 2,0,0 3,0,0.5 radius=0.25 def=squared-cosine:0.4\n"
      "superquadric q 1 0.8 0.6 e1=0.6 e2=0.8 radius=0.12 def_u=wave:0.3,2 "
      "def_v=squared-cosine:0.5 depth=4\n"
      "save_mesh b b.ply resolution=48\n"
      "save_mesh q q.ply resolution=48\n",
      "t.rf");
  s.commit();
  for (const char* name : {"b.ply", "q.ply"}) {
    const std::string path = (dir_ / name).string();
    ASSERT_TRUE(std::filesystem::exists(path)) << name;
    const TriMesh mesh = read_mesh(path);
    const MeshReport r = check_mesh(mesh);
    EXPECT_GT(r.triangles, 200u) << name;
    EXPECT_TRUE(r.watertight) << name;
    EXPECT_TRUE(r.oriented) << name;
    EXPECT_TRUE(r.manifold) << name;
  }
  // The superquadric shell is a closed shell around a hollow: two components (outer and inner).
  const MeshReport q = check_mesh(read_mesh((dir_ / "q.ply").string()));
  EXPECT_EQ(q.components, 2u);
  const MeshReport b = check_mesh(read_mesh((dir_ / "b.ply").string()));
  EXPECT_EQ(b.components, 1u);
  EXPECT_EQ(b.euler, 2);
}

}  // namespace
}  // namespace ramiform::test

namespace ramiform::test {
namespace {

// tree_from_points: the scene's skeleton is the library's for the same cloud and options, it is
// a shape (inside on the trunk's axis, outside beside it) and saves and meshes like a skeleton.
TEST_F(ScriptDirTest, TreeFromPointsIsTheLibrarysSkeletonAsAShape) {
  const std::filesystem::path cloud =
      std::filesystem::path(RAMIFORM_SOURCE_DIR) / "examples" / "data" / "tree_cloud.xyz";
  std::filesystem::copy_file(cloud, dir_ / "tree.xyz");
  ScriptSession s(options_);
  s.run_text(
      "tree_from_points t tree.xyz bin=0.08 up=z surface=convolution\n"
      "save_skeleton t t.json\n",
      "t.rf");
  (void)s.commit();
  TreeFromPointsOptions o;
  o.bin_width = 0.08;
  const Skeleton expected =
      tree_from_points(read_points((dir_ / "tree.xyz").string()).positions, o);
  const Skeleton saved = read_skeleton((dir_ / "t.json").string());
  ASSERT_EQ(saved.nodes.size(), expected.nodes.size());
  EXPECT_EQ(saved.edges, expected.edges);
  for (std::size_t i = 0; i < saved.nodes.size(); ++i) {
    EXPECT_NEAR((saved.nodes[i].position - expected.nodes[i].position).norm(), 0.0, 1e-12);
    EXPECT_NEAR(saved.nodes[i].radius, expected.nodes[i].radius, 1e-12);
  }
  // The example tree has three tips (two limbs and a side branch).
  std::size_t tips = 0;
  const auto deg = degrees(saved);
  for (std::size_t i = 1; i < deg.size(); ++i) tips += deg[i] == 1 ? 1 : 0;
  EXPECT_EQ(tips, 3u);
  EXPECT_THROW(s.run_text("tree_from_points u tree.xyz up=x\n", "u.rf"), InputError);
  EXPECT_THROW(s.run_text("tree_from_points u tree.xyz bin=-1\n", "u.rf"), InputError);
}

}  // namespace
}  // namespace ramiform::test
