// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform eval SKELETON --points FILE --distance [--tie first|last]`: the nearest skeleton
// element of each point, with curved edges kept exact, against hand-computed values and the
// library's skeleton_distances; the tie rule; refused option combinations and bad files.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "cli/cli_run.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/io/skeleton_io.h"

namespace ramiform {
namespace {

using test::CliRun;
using test::run_cli;
using EvalDistanceTest = test::CliDirTest;

struct Line {
  double distance = -1;
  std::string kind;
  unsigned index = 0;
  double t = -1;
};

// Parses the `distance edge|node INDEX t` lines of a run.
std::vector<Line> lines_of(const std::string& out) {
  std::vector<Line> r;
  std::istringstream in(out);
  std::string text;
  while (std::getline(in, text)) {
    std::istringstream l(text);
    Line x;
    if (l >> x.distance >> x.kind >> x.index >> x.t) r.push_back(x);
  }
  return r;
}

// The arch: a cubic from (0,0,0) through controls (0,0,4), (4,0,4) to (4,0,0); C(0.5) =
// (2, 0, 3) with C'(0.5) = (6, 0, 0). Node 2 is isolated; edge 1 is a straight edge.
const char* kArch = R"({"nodes":[{"position":[0,0,0],"radius":0.5},{"position":[4,0,0],"radius":0.5},)"
                    R"({"position":[10,0,0],"radius":0.2},{"position":[4,0,-3],"radius":0.4}],)"
                    R"("edges":[{"nodes":[0,1],"controls":[[0,0,4],[4,0,4]]},[1,3]]})";

TEST_F(EvalDistanceTest, ArchDistancesAndParameters) {
  const std::string sk = write("arch.json", kArch);
  const std::vector<Vec3> pts = {
      Vec3(2, 0, 1.5),    // the apex's centre of curvature: distance 1.5 at t = 0.5
      Vec3(2, 0, 2.5),    // below the apex: 0.5 at t = 0.5
      Vec3(2, 1, 3),      // beside the apex: 1 at t = 0.5
      Vec3(-1, 0, -1),    // beyond the first end: sqrt(2) at t = 0
      Vec3(4.5, 0, -1.5), // beside the straight edge 1 -> 3: 0.5 at t = 0.5
      Vec3(10, 0.3, 0.4), // the isolated node 2: 0.5
  };
  std::string text;
  for (const Vec3& p : pts) {
    std::ostringstream l;
    l.precision(17);
    l << p.x() << " " << p.y() << " " << p.z() << "\n";
    text += l.str();
  }
  const std::string pf = write("p.txt", text);
  const CliRun r = run_cli("eval " + sk + " --points " + pf + " --distance", 60);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::vector<Line> l = lines_of(r.out);
  ASSERT_EQ(l.size(), pts.size()) << r.out;
  // Hand-computed.
  EXPECT_NEAR(l[0].distance, 1.5, 1e-12);
  EXPECT_EQ(l[0].kind, "edge");
  EXPECT_EQ(l[0].index, 0u);
  EXPECT_NEAR(l[0].t, 0.5, 1e-3);  // a degenerate (fourth-order) minimum: t is loose
  EXPECT_NEAR(l[1].distance, 0.5, 1e-12);
  EXPECT_NEAR(l[1].t, 0.5, 1e-9);
  EXPECT_NEAR(l[2].distance, 1.0, 1e-12);
  EXPECT_NEAR(l[2].t, 0.5, 1e-9);
  EXPECT_NEAR(l[3].distance, std::sqrt(2.0), 1e-12);
  EXPECT_EQ(l[3].t, 0.0);
  EXPECT_EQ(l[3].index, 0u);
  EXPECT_NEAR(l[4].distance, 0.5, 1e-12);
  EXPECT_EQ(l[4].kind, "edge");
  EXPECT_EQ(l[4].index, 1u);
  EXPECT_NEAR(l[4].t, 0.5, 1e-12);
  EXPECT_NEAR(l[5].distance, 0.5, 1e-12);
  EXPECT_EQ(l[5].kind, "node");
  EXPECT_EQ(l[5].index, 2u);
  EXPECT_EQ(l[5].t, 0.0);
  // The library's answer, printed with %.17g: identical.
  SkeletonReadOptions keep;
  keep.keep_curves = true;
  const std::vector<SkeletonDistance> d = skeleton_distances(read_skeleton(sk, keep), pts);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    EXPECT_EQ(l[i].distance, d[i].distance) << i;
    EXPECT_EQ(l[i].t, d[i].t) << i;
    EXPECT_EQ(l[i].index, d[i].index) << i;
    EXPECT_EQ(l[i].kind, d[i].is_edge ? "edge" : "node") << i;
  }
}

TEST_F(EvalDistanceTest, RandomPointsMatchLibrary) {
  const std::string sk = write(
      "s.json",
      R"({"nodes":[{"position":[0,0,0],"radius":0.5},{"position":[3,1,0],"radius":0.4},)"
      R"({"position":[5,-1,2],"radius":0.3},{"position":[1,4,1],"radius":0.3}],)"
      R"("edges":[{"nodes":[0,1],"controls":[[1,2,1],[2,-1,0.5]],"radii":[0.6,0.2]},)"
      R"({"nodes":[1,2],"controls":[[4,3,1]]},[1,3]]})");
  std::string text;
  std::vector<Vec3> pts;
  for (int i = 0; i < 200; ++i) {
    const Vec3 p(-1 + 7 * std::fmod(i * 0.6180339887, 1.0), -2 + 7 * std::fmod(i * 0.4142135623, 1.0),
                 -1 + 4 * std::fmod(i * 0.7320508075, 1.0));
    pts.push_back(p);
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
    text += buf;
  }
  const std::string pf = write("p.txt", text);
  SkeletonReadOptions keep;
  keep.keep_curves = true;
  const Skeleton s = read_skeleton(sk, keep);
  for (const char* tie : {"first", "last"}) {
    const CliRun r = run_cli("eval " + sk + " --points " + pf + " --distance --tie " + tie, 60);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::vector<Line> l = lines_of(r.out);
    ASSERT_EQ(l.size(), pts.size());
    const auto d = skeleton_distances(s, pts, std::string(tie) == "last" ? TieRule::kLast : TieRule::kFirst);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      EXPECT_EQ(l[i].distance, d[i].distance) << i;
      EXPECT_EQ(l[i].t, d[i].t) << i;
      EXPECT_EQ(l[i].index, d[i].index) << i;
    }
  }
}

TEST_F(EvalDistanceTest, TieRule) {
  // A U-shaped cubic symmetric about x = 0 (ends at (-+2, 0, 2), bottom at (0, 0, -1)).
  const std::string sk = write(
      "u.json", R"({"nodes":[{"position":[-2,0,2],"radius":0.3},{"position":[2,0,2],"radius":0.3}],)"
                R"("edges":[{"nodes":[0,1],"controls":[[-2,0,-2],[2,0,-2]]}]})");
  // Far above on the axis: the two ends are equally near. Lower: two interior points t, 1 - t.
  const std::string pf = write("p.txt", "0 0 50\n0 0.3 1.2\n0 0 -0.5\n");
  const CliRun first = run_cli("eval " + sk + " --points " + pf + " --distance", 60);
  const CliRun first2 = run_cli("eval " + sk + " --points " + pf + " --distance --tie first", 60);
  const CliRun last = run_cli("eval " + sk + " --points " + pf + " --distance --tie last", 60);
  ASSERT_EQ(first.code, 0) << first.out;
  ASSERT_EQ(last.code, 0) << last.out;
  EXPECT_EQ(first.out, first2.out);  // first is the default
  const auto f = lines_of(first.out), l = lines_of(last.out);
  ASSERT_EQ(f.size(), 3u);
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(f[0].t, 0.0);
  EXPECT_EQ(l[0].t, 1.0);
  EXPECT_EQ(f[0].distance, l[0].distance);
  EXPECT_DOUBLE_EQ(f[0].distance, std::sqrt(4.0 + 48.0 * 48.0));
  EXPECT_GT(f[1].t, 0.0);
  EXPECT_LT(f[1].t, 0.5);
  EXPECT_NEAR(f[1].t + l[1].t, 1.0, 1e-9);
  EXPECT_NEAR(f[1].distance, l[1].distance, 1e-12);
  // No tie below the bottom's centre of curvature: both rules agree on t = 0.5.
  EXPECT_NEAR(f[2].t, 0.5, 1e-9);
  EXPECT_EQ(f[2].t, l[2].t);
  EXPECT_NEAR(f[2].distance, 0.5, 1e-12);
  // A bad tie word is refused.
  EXPECT_NE(run_cli("eval " + sk + " --points " + pf + " --distance --tie middle", 60).code, 0);
}

TEST_F(EvalDistanceTest, DistanceWithGradientIsRefused) {
  const std::string sk = write("arch.json", kArch);
  const std::string pf = write("p.txt", "1 0 1\n");
  const CliRun r = run_cli("eval " + sk + " --points " + pf + " --distance --gradient", 60);
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("--gradient"), std::string::npos) << r.out;
  EXPECT_TRUE(lines_of(r.out).empty()) << r.out;
}

TEST_F(EvalDistanceTest, BadSkeletonFileNamesTheFile) {
  const std::string pf = write("p.txt", "1 0 1\n");
  const std::string bad = write(
      "bad.json", R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[3,0,0],"radius":1}],)"
                  R"("edges":[{"nodes":[0,1],"controls":[[1,2]]}]})");
  CliRun r = run_cli("eval " + bad + " --points " + pf + " --distance", 60);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(bad), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("edge 0"), std::string::npos) << r.out;
  // A missing file.
  r = run_cli("eval " + path("none.json") + " --points " + pf + " --distance", 60);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(path("none.json")), std::string::npos) << r.out;
  // Not JSON at all.
  const std::string junk = write("junk.json", "{ nodes: ");
  r = run_cli("eval " + junk + " --points " + pf + " --distance", 60);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(junk), std::string::npos) << r.out;
}

TEST_F(EvalDistanceTest, PlainEvalStillStraightensCurves) {
  // Without --distance the curved edge is straightened and the field is defined around it:
  // the apex of the arch is inside.
  const std::string sk = write("arch.json", kArch);
  const std::string pf = write("p.txt", "2 0 3\n2 0 1.5\n");
  const CliRun r = run_cli("eval " + sk + " --points " + pf, 60);
  ASSERT_EQ(r.code, 0) << r.out;
  std::istringstream in(r.out);
  double v0 = 0, v1 = 0;
  ASSERT_TRUE(in >> v0 >> v1) << r.out;
  EXPECT_GT(v0, v1);
  EXPECT_GT(v0, 0.0);
}

}  // namespace
}  // namespace ramiform
