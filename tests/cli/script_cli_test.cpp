// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform run` and `ramiform shell`: outputs, reports, exit codes and messages.

#include <gtest/gtest.h>

#include <filesystem>

#include "cli/cli_run.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/mesh/checks.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

using ScriptCli = CliDirTest;

TEST_F(ScriptCli, RunWritesOutputsIntoOutAndReportsThem) {
  fs::create_directories(path("out"));
  const std::string script = write("scene.rf",
                                   "param r 1\nsphere s1 $r\nline s2\ndiff s1 s2 s3\n"
                                   "save_mesh s3 drilled.ply resolution=48\neval s3 0.7 0 0\n");
  const CliRun r =
      run_cli("run " + script + " --out " + path("out") + " --stats " + path("out/stats.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("drilled.ply: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("watertight"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(inside, iso 0.5)"), std::string::npos) << r.out;
  const MeshReport m = check_mesh(read_mesh(path("out/drilled.ply")));
  EXPECT_TRUE(m.watertight && m.oriented && m.manifold);
  EXPECT_TRUE(fs::exists(path("out/stats.json")));
}

// The tetrahedral polygonizer from the scene language, with its options; a skeleton file
// relative to the script.
TEST_F(ScriptCli, SaveMeshRunsTheTetrahedralPolygonizerWithItsOptions) {
  fs::create_directories(path("out"));
  (void)y_fork();  // writes fork.json beside the script
  const std::string script = write(
      "tree.rf",
      "skeleton t fork.json\nsave_mesh t square.ply method=tets levels=1\n"
      "save_mesh t round.ply method=tets levels=1 section_scale=2.6\n");
  const CliRun r = run_cli("run " + script + " --out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("(tets, 1 levels)"), std::string::npos) << r.out;
  const TriMesh square = read_mesh(path("out/square.ply"));
  const TriMesh round = read_mesh(path("out/round.ply"));
  for (const TriMesh* m : {&square, &round}) {
    const MeshReport rep = check_mesh(*m);
    EXPECT_TRUE(rep.watertight && rep.oriented && rep.manifold);
    EXPECT_EQ(rep.components, 1U);
  }
  EXPECT_GT(round.triangle_count(), square.triangle_count());
  const std::string bad = write("bad.rf",
                                "skeleton t fork.json\n"
                                "save_mesh t b.ply method=tets section_scale=1.5\n");
  const CliRun b = run_cli("run " + bad + " --out " + path("out"));
  EXPECT_EQ(b.code, 2) << b.out;
  EXPECT_NE(b.out.find("bad.rf:2:45: save_mesh: section_scale= must be in [2, 1000]"),
            std::string::npos)
      << b.out;
  const std::string cubes = write("mc.rf", "sphere s\nsave_mesh s c.ply section_scale=2.6\n");
  const CliRun c = run_cli("run " + cubes + " --out " + path("out"));
  EXPECT_EQ(c.code, 2) << c.out;
  EXPECT_NE(c.out.find("section_scale= applies to method=tets"), std::string::npos) << c.out;
  EXPECT_FALSE(fs::exists(path("out/b.ply")));
  EXPECT_FALSE(fs::exists(path("out/c.ply")));
}

TEST_F(ScriptCli, SetOverridesAParameter) {
  const std::string script = write("scene.rf", "param r 1\nsphere s $r\neval s 1.5 0 0\n");
  const CliRun small = run_cli("run " + script + " --out " + dir_.string());
  const CliRun big = run_cli("run " + script + " --out " + dir_.string() + " --set r=2");
  ASSERT_EQ(small.code, 0) << small.out;
  ASSERT_EQ(big.code, 0) << big.out;
  EXPECT_NE(small.out.find("outside"), std::string::npos) << small.out;
  EXPECT_NE(big.out.find("inside"), std::string::npos) << big.out;
  const CliRun bad = run_cli("run " + script + " --out " + dir_.string() + " --set radius=2");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("declares no parameter 'radius'; it declares: r"), std::string::npos)
      << bad.out;
}

TEST_F(ScriptCli, BadScriptExitsTwoWithLocationAndWritesNothing) {
  const std::string script =
      write("scene.rf", "sphere s1\nsave_mesh s1 a.ply resolution=16\ndiff s1 s4 s3\n");
  const std::size_t before = files_in_dir();
  const CliRun r = run_cli("run " + script + " --out " + dir_.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("scene.rf:3:9: diff: unknown shape 's4' (did you mean 's1'?)"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(files_in_dir(), before);
  EXPECT_EQ(run_cli("run " + path("missing.rf")).code, 2);
  EXPECT_EQ(run_cli("run " + script + " --out " + path("no/such/dir")).code, 2);
  EXPECT_EQ(run_cli("run").code, 1);
}

TEST_F(ScriptCli, ShellReportsEachResultAndGoesOnAfterErrors) {
  const std::string input =
      write("in.txt", "sphere s\nsphre t\neval s 0 0 0\nhelp diff\nquit\nsphere never\n");
  const CliRun r = run_cli("shell --out " + dir_.string() + " < " + input);
  EXPECT_EQ(r.code, 2) << r.out;  // one command failed, reading from a pipe
  EXPECT_NE(r.out.find("s: sphere, radius 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("error: <shell>:2:1: unknown command 'sphre' (did you mean 'sphere'?)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("f(0,0,0) = 1 (inside"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("diff A B OUT"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("never"), std::string::npos) << r.out;  // stopped at quit
  const std::string ok = write("ok.txt", "sphere s\nsave_mesh s s.ply resolution=16\n");
  const CliRun good = run_cli("shell --out " + dir_.string() + " < " + ok);
  EXPECT_EQ(good.code, 0) << good.out;
  EXPECT_TRUE(fs::exists(path("s.ply")));
}

}  // namespace
}  // namespace ramiform::test
