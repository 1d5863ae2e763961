// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Hostile point sets given to `ramiform eval` and `ramiform grow` (issue 15): each is bad input
// (exit 2) with a message naming the file and the line or element, and leaves no output behind.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "cli/cli_run.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

// run_cli under `timeout`: before the fixes `grow` on points at +-1e308 never returned, and a
// regression must fail the test rather than hang the suite.
CliRun run_bounded(const std::string& args) { return run_cli(args, 30); }

std::string ply_header(const char* format, std::size_t vertices, const char* type) {
  return std::string("ply\nformat ") + format + " 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty " + type + " x\nproperty " + type + " y\nproperty " + type +
         " z\nend_header\n";
}

std::string le_doubles(const std::vector<double>& values) {
  std::string out;
  for (const double v : values) {
    char b[8];
    std::memcpy(b, &v, 8);
    out.append(b, 8);  // the test machines are little-endian (x86-64, aarch64)
  }
  return out;
}

struct Hostile {
  const char* name;      // file name in the test's directory
  std::string content;   // its bytes
  std::string location;  // expected after the path: ":LINE: " or ": vertex K: "
  const char* problem;   // expected in the message
};

std::vector<Hostile> hostile_point_sets() {
  return {
      // `element vertex 0` was an empty point set: eval printed nothing and exited 0.
      {"none.ply", ply_header("ascii", 0, "float"), ":3: ", "no points"},
      {"none_binary.ply", ply_header("binary_little_endian", 0, "double"), ":3: ", "no points"},
      // A span that overflows (max - min = inf): eval printed -nan, grow never returned.
      {"wide.xyz", "0 0 5\n# far away\n0 0 1e308\n1 1 -1e308\n",
       ":3: ", "span more than double precision can hold"},
      {"wide_normals.txt", "1 1 1 0 0 1\n-1.7e308,0,0,1,0,0\n1.7e308,0,0,1,0,0\n",
       ":2: ", "span more than double precision can hold"},
      {"wide.ply",
       ply_header("binary_little_endian", 3, "double") +
           le_doubles({0, 0, 5, 0, 0, 6, 1, 1, -1e308}),
       ": vertex 2: ", "span more than double precision can hold"},
      {"wide_ascii.ply", ply_header("ascii", 2, "double") + "0 0 -1e308\n0 0 1e308\n",
       ": vertex 1: ", "span more than double precision can hold"},
  };
}

class HostileInputs : public CliDirTest {
 protected:
  // Exit 2, one error line naming the file at the expected place, and the directory holding the
  // input files alone (no output, no stats, no staged file).
  void expect_refused(const std::string& args, const Hostile& h, std::size_t inputs) {
    const CliRun r = run_bounded(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    const std::string where = path(h.name) + h.location;
    EXPECT_NE(r.out.find(where), std::string::npos) << "expected '" << where << "' in\n" << r.out;
    EXPECT_NE(r.out.find(h.problem), std::string::npos) << r.out;
    EXPECT_EQ(r.out.rfind("ramiform: error: ", 0), 0U) << r.out;  // nothing printed before it
    EXPECT_EQ(r.out.find('\n'), r.out.size() - 1) << "one line expected:\n" << r.out;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    EXPECT_EQ(files_in_dir(), inputs) << args;
  }
};

TEST_F(HostileInputs, EvalRefusesThemWithNoOutput) {
  const std::string skel = y_fork();
  for (const Hostile& h : hostile_point_sets()) {
    SCOPED_TRACE(h.name);
    const std::string pts = write(h.name, h.content);
    expect_refused("eval " + skel + " --points " + pts + " --stats " + path("stats.json"), h, 2);
    fs::remove(pts);
  }
}

TEST_F(HostileInputs, GrowRefusesThemWithNoOutput) {
  for (const Hostile& h : hostile_point_sets()) {
    SCOPED_TRACE(h.name);
    const std::string pts = write(h.name, h.content);
    expect_refused(
        "grow --points " + pts + " -o " + path("tree.json") + " --stats " + path("stats.json"), h,
        1);
    fs::remove(pts);
  }
}

TEST_F(HostileInputs, GrowRefusesARootTooFarFromThePoints) {
  // The points are readable; the root 1e200 away from them is not usable (its distance to the
  // points' box is inf): the library's InvalidArgument, exit 2, no output.
  const std::string pts = write("crown.xyz", "0 0 5\n1 0 5\n0 1 6\n");
  const CliRun r = run_bounded("grow --points " + pts + " --root 1e200,0,0 -o " +
                               path("tree.json") + " --stats " + path("stats.json"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("root 0 is too far from the attraction points"), std::string::npos) << r.out;
  EXPECT_EQ(files_in_dir(), 1U);
}

TEST_F(HostileInputs, CurvedEdgeWhoseControlsOverflowTheSpanIsRefused) {
  // Finite controls that, with the nodes, span more than a double: once named "<input>: node 2"
  // (a node of the straightened curve) instead of the file and the edge.
  const std::string skel = write("wide_curve.json",
                                 R"({"nodes": [{"position": [0, 0, 0], "radius": 0.1},
                          {"position": [1, 0, 0], "radius": 0.1}],
                "edges": [{"nodes": [0, 1], "controls": [[0.5, 1e308, 0]]}]})");
  const CliRun r =
      run_bounded("mesh " + skel + " -o " + path("m.ply") + " --stats " + path("stats.json"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(skel + ": edge 0: control point 0: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("span more than double precision can hold"), std::string::npos) << r.out;
  EXPECT_EQ(files_in_dir(), 1U);
}

TEST_F(HostileInputs, AnEmptyMeshIsAFailureWithTheRemedy) {
  // One edge a billionth of its radius long: its convolution surface does not form, and the
  // empty mesh used to be written with exit 0.
  const std::string skel = write("speck.json",
                                 R"({"nodes": [{"position": [0, 0, 0], "radius": 1},
                                               {"position": [1e-9, 0, 0], "radius": 1}],
                                     "edges": [[0, 1]]})");
  const CliRun r = run_bounded("mesh " + skel + " -o " + path("m.ply"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("ramiform: failure: " + path("m.ply") + ": the mesh is empty"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("--surface distance"), std::string::npos) << r.out;
  // The remedy works: the distance surface skins the edge at its radius.
  const CliRun d = run_bounded("mesh " + skel + " -o " + path("m.ply") + " --surface distance");
  EXPECT_EQ(d.code, 0) << d.out;
  EXPECT_EQ(d.out.find("failure"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find(", watertight"), std::string::npos) << d.out;
}

TEST_F(HostileInputs, TheSameFilesWithinTheLimitsAreAccepted) {
  // Control: large coordinates whose span fits, and one vertex, are read and evaluated.
  const std::string skel = y_fork();
  const std::string big = write("big.xyz", "0 0 5\n0 0 1e150\n1 1 -1e150\n");
  const CliRun a = run_bounded("eval " + skel + " --points " + big);
  ASSERT_EQ(a.code, 0) << a.out;
  EXPECT_EQ(std::count(a.out.begin(), a.out.end(), '\n'), 3) << a.out;
  EXPECT_EQ(a.out.find("nan"), std::string::npos) << a.out;
  const std::string one = write("one.ply", ply_header("ascii", 1, "float") + "0 0 1\n");
  const CliRun b = run_bounded("eval " + skel + " --points " + one);
  ASSERT_EQ(b.code, 0) << b.out;
  EXPECT_EQ(std::count(b.out.begin(), b.out.end(), '\n'), 1) << b.out;
}

TEST_F(HostileInputs, RunsAboveTheMemoryBudgetAreRefusedBeforeTheyStart) {
  // --max-memory: the estimate is checked before the work; exit 2, the estimate and the budget
  // in the message, nothing written.
  const std::string skel = y_fork();
  const std::string out = path("fork.ply");
  const std::string stats = " --stats " + path("stats.json");
  for (const std::string& job :
       {std::string("mesh ") + skel + " -o " + out + " --levels 3",
        std::string("mesh ") + skel + " -o " + out + " --method mc --resolution 400"}) {
    SCOPED_TRACE(job);
    const CliRun r = run_bounded(job + " --max-memory 100k" + stats);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(r.out.rfind("ramiform: error: ", 0), 0U) << r.out;
    EXPECT_NE(r.out.find("need at least "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("more than the budget of 100 kB (the max_memory set for this run)"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(files_in_dir(), 1U);
    // Within a budget of a gigabyte the same run succeeds.
    const CliRun ok = run_bounded(job + " --max-memory 1GiB");
    EXPECT_EQ(ok.code, 0) << ok.out;
    EXPECT_TRUE(fs::exists(out));
    fs::remove(out);
  }
  // A line drawing's particles: 20,000 need at least 2.24 MB.
  const std::string svg = path("fork.svg");
  const CliRun d = run_bounded("draw " + skel + " -o " + svg + " --count 20000 --max-memory 1M");
  EXPECT_EQ(d.code, 2) << d.out;
  EXPECT_NE(d.out.find("20000 surface particles need at least 2.24 MB of memory, more than the "
                       "budget of 1 MB"),
            std::string::npos)
      << d.out;
  EXPECT_FALSE(fs::exists(svg));
  const std::string script =
      write("many.rf", "sphere s 1\npoint_set_gen s uniform count=100000\nsave_point_set p.txt\n");
  const CliRun r = run_bounded("run " + script + " --out " + dir_.string() + " --max-memory 1M");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("100000 points need at least 6.4 MB"), std::string::npos) << r.out;
  EXPECT_EQ(files_in_dir(), 2U);  // the fork and the script
  // A size that is not one is a usage error naming the option.
  const CliRun bad = run_bounded("mesh " + skel + " -o " + out + " --max-memory 12X");
  EXPECT_NE(bad.code, 0) << bad.out;
  EXPECT_NE(bad.out.find("--max-memory"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find("expected a size such as 512M"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(HostileInputs, HugeResolutionsAndLevelsAreRefusedBeforeTheWork) {
  // A resolution of 100000 and levels 6 on a 1,500-segment tree, from the command line and from
  // a script: refused at once (exit 2, the reason in the message), nothing written. The kill
  // timeout fails the test if any of them starts the work instead.
  const std::string tree = path("tree.json");
  ASSERT_EQ(run_bounded("generate " + tree + " --segments 1500 --seed 2").code, 0);
  const std::string script = write("huge.rf", "skeleton t " + tree +
                                                  " surface=convolution\n"
                                                  "save_mesh t mc.ply resolution=100000\n");
  const std::string script6 =
      write("levels.rf", "skeleton t " + tree + "\nsave_mesh t tets.ply method=tets levels=6\n");
  const std::string out = " --stats " + path("stats.json");
  const std::vector<std::pair<std::string, std::string>> jobs = {
      {"mesh " + tree + " -o " + path("mc.ply") + " --method mc --resolution 100000" + out,
       "the grid needs more than MarchingCubesOptions.max_cells"},
      {"mesh " + tree + " -o " + path("tets.ply") + " --levels 6" + out,
       "bounding points at --levels 6 need at least "},
      {"run " + script + " --out " + dir_.string() + out,
       "huge.rf:2:1: save_mesh: marching_cubes: the grid needs more than"},
      {"run " + script6 + " --out " + dir_.string() + out,
       "levels.rf:2:1: save_mesh: tetrahedral polygonizer: "},
  };
  for (const auto& [job, expected] : jobs) {
    SCOPED_TRACE(job);
    const CliRun r = run_bounded(job);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(r.out.rfind("ramiform: error: ", 0), 0U) << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << r.out;
    EXPECT_EQ(files_in_dir(), 3U);  // the tree and the two scripts
  }
}

}  // namespace
}  // namespace ramiform::test
