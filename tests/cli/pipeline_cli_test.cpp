// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform sample`, `ramiform grow` and `ramiform lsystem`: outputs, stats and bad input.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/cli_run.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

using PipelineCli = CliDirTest;

TEST_F(PipelineCli, SampleThenGrowGivesAPipeModelTree) {
  const std::string script = write("crown.rf", "param r 2\nsphere crown $r center=0,0,4\n");
  const std::string props = write("p.props", "# poisson\ncount = 400\nmin_distance = 0.2\n");
  const CliRun s = run_cli("sample " + script + " crown --dist poisson --props " + props + " -o " +
                           path("pts.txt") + " --seed 3");
  ASSERT_EQ(s.code, 0) << s.out;
  const PointSet pts = read_points(path("pts.txt"));
  ASSERT_EQ(pts.size(), 400u);
  for (const Vec3& p : pts.positions) EXPECT_LT((p - Vec3(0, 0, 4)).norm(), 2.0);
  const CliRun g = run_cli("grow --points " + path("pts.txt") +
                           " --step 0.25 --influence 1.5 --kill 0.5 --root 0,0,0 --tip-radius 0.03 "
                           "--pipe-exponent 2 -o " +
                           path("tree.json") + " --stats " + path("stats.json"));
  ASSERT_EQ(g.code, 0) << g.out;
  const Skeleton tree = read_skeleton(path("tree.json"));
  EXPECT_EQ(tree.edge_count() + 1, tree.node_count());
  EXPECT_EQ(connected_components(tree).count, 1u);
  // Exponent 2: the cross-section area is conserved, so the root's r^2 is the sum over tips.
  const auto deg = degrees(tree);
  double tips = 0;
  for (std::size_t i = 1; i < tree.node_count(); ++i) {
    if (deg[i] == 1) tips += 0.03 * 0.03;
  }
  EXPECT_NEAR(tree.nodes[0].radius * tree.nodes[0].radius, tips, 1e-9 * tips);
  const auto stats = nlohmann::json::parse(read_file(path("stats.json")));
  for (const char* key : {"nodes", "iterations", "points_reached", "stalled", "seconds"}) {
    EXPECT_TRUE(stats.contains(key)) << key;
  }
  EXPECT_EQ(stats["nodes"].get<std::size_t>(), tree.node_count());
  // Same inputs: byte-identical skeleton, on one thread too.
  ASSERT_EQ(
      run_cli("grow --points " + path("pts.txt") +
              " --step 0.25 --influence 1.5 --kill 0.5 --tip-radius 0.03 --pipe-exponent 2 -o " +
              path("tree1.json") + " --threads 1")
          .code,
      0);
  EXPECT_EQ(read_file(path("tree.json")), read_file(path("tree1.json")));
}

TEST_F(PipelineCli, GrowCleansBranchesWithTheCleanupFlags) {
  // Uniform points in a ball (a fixed linear congruential sequence: no library randomness).
  std::string text;
  std::uint64_t state = 7;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0 * 2 - 1;
  };
  for (int n = 0; n < 1500;) {
    const double x = next(), y = next(), z = next();
    if (x * x + y * y + z * z > 1) continue;
    text += std::to_string(2.5 * x) + " " + std::to_string(2.5 * y) + " " +
            std::to_string(4 + 2.5 * z) + "\n";
    ++n;
  }
  const std::string pts = write("ball.txt", text);
  const std::string flags = " --step 0.2 --influence 1.2 --kill 0.4";
  ASSERT_EQ(run_cli("grow --points " + pts + flags + " -o " + path("raw.json")).code, 0);
  const CliRun g = run_cli("grow --points " + pts + flags + " --smooth 8 --prune 2 -o " +
                           path("tree.json") + " --stats " + path("stats.json"));
  ASSERT_EQ(g.code, 0) << g.out;
  EXPECT_NE(g.out.find("cleanup: "), std::string::npos) << g.out;
  const Skeleton raw = read_skeleton(path("raw.json"));
  const Skeleton tree = read_skeleton(path("tree.json"));
  const auto stats = nlohmann::json::parse(read_file(path("stats.json")));
  const auto& c = stats["cleanup"];
  EXPECT_EQ(stats["nodes"].get<std::size_t>(), tree.node_count());
  EXPECT_EQ(c["nodes_removed"].get<std::size_t>(), raw.node_count() - tree.node_count());
  EXPECT_GT(c["stubs_pruned"].get<std::size_t>(), 0u);
  EXPECT_GT(c["nodes_moved"].get<std::size_t>(), 0u);
  EXPECT_GT(c["before"]["turn_p90_deg"].get<double>(), 30.0);
  EXPECT_LE(c["after"]["turn_p90_deg"].get<double>(), 30.0);
  EXPECT_LE(c["after"]["turn_max_deg"].get<double>(), 90.0);
  EXPECT_LE(c["after"]["short_tip_share"].get<double>(), 0.1);
  EXPECT_EQ(c["short_steps"].get<double>(), 2.0);
  // Bad values: exit 2, a message naming the option, no output.
  for (const char* bad :
       {"--smooth -1", "--smooth 1001", "--prune -1", "--max-turn 0", "--max-turn 181"}) {
    const CliRun r =
        run_cli("grow --points " + pts + flags + " " + bad + " -o " + path("bad.json"));
    EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
    const std::string option = std::string(bad).substr(2, std::string(bad).find(' ') - 2);
    const std::string key = option == "smooth"  ? "smooth_iterations"
                            : option == "prune" ? "prune_steps"
                                                : "max_turn_deg";
    EXPECT_NE(r.out.find(key), std::string::npos) << bad << ": " << r.out;
    EXPECT_FALSE(fs::exists(path("bad.json"))) << bad;
  }
}

TEST_F(PipelineCli, BadInputsExitTwoWithAMessageAndNoOutput) {
  const std::string pts = write("pts.txt", "0 0 1\n0 0 2\n");
  // Points out of reach: growth stops early, and that is a result (reported), not an error.
  const CliRun far = run_cli("grow --points " + write("far.txt", "100 0 0\n") +
                             " --step 1 --influence 2 --kill 1 "
                             "-o " +
                             path("far.json") + " --stats " + path("far_stats.json"));
  EXPECT_EQ(far.code, 0) << far.out;
  EXPECT_NE(far.out.find("stopped early"), std::string::npos) << far.out;
  const auto far_stats = nlohmann::json::parse(read_file(path("far_stats.json")));
  EXPECT_TRUE(far_stats["stalled"].get<bool>());
  EXPECT_EQ(far_stats["points_reached"].get<int>(), 0);
  const CliRun bad =
      run_cli("grow --points " + write("bad.txt", "0 0 1\n0 x 2\n") + " -o " + path("t.json"));
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("bad.txt:2"), std::string::npos) << bad.out;
  const CliRun exponent =
      run_cli("grow --points " + pts + " --pipe-exponent 4 -o " + path("t.json"));
  EXPECT_EQ(exponent.code, 2) << exponent.out;
  EXPECT_NE(exponent.out.find("exponent"), std::string::npos) << exponent.out;
  const CliRun root = run_cli("grow --points " + pts + " --root 0,0 -o " + path("t.json"));
  EXPECT_EQ(root.code, 2) << root.out;
  EXPECT_FALSE(fs::exists(path("t.json")));
  const std::string script = write("s.rf", "sphere s\n");
  const CliRun dist = run_cli("sample " + script + " s --dist poison -o " + path("p.txt"));
  EXPECT_EQ(dist.code, 2) << dist.out;
  EXPECT_NE(dist.out.find("did you mean 'poisson'"), std::string::npos) << dist.out;
  const CliRun key =
      run_cli("sample " + script + " s --dist poisson --props " +
              write("k.props", "count = 10\nmin_dist = 1\n") + " -o " + path("p.txt"));
  EXPECT_EQ(key.code, 2) << key.out;
  EXPECT_NE(key.out.find("k.props:2"), std::string::npos) << key.out;
  const CliRun shape = run_cli("sample " + script + " t --dist uniform -o " + path("p.txt"));
  EXPECT_EQ(shape.code, 2) << shape.out;
  EXPECT_FALSE(fs::exists(path("p.txt")));
  const CliRun ls =
      run_cli("lsystem " + write("l.txt", "axiom: A\nA -> F[+A(]\n") + " -o " + path("l.json"));
  EXPECT_EQ(ls.code, 2) << ls.out;
  EXPECT_NE(ls.out.find("l.txt:2:"), std::string::npos) << ls.out;
  EXPECT_FALSE(fs::exists(path("l.json")));
}

// Every command that writes refuses an output it cannot write before doing any work: the
// inputs below are missing or broken too, and the message is about the output, so no input was
// read (grow and sample can run for minutes before writing).
TEST_F(PipelineCli, OutputPathsAreCheckedBeforeTheWork) {
  const std::string missing = path("no/such/dir/out.json");
  const std::string broken = path("absent-input");
  const struct {
    std::string args;
    const char* expected;
  } cases[] = {
      {"generate " + missing, "does not exist"},
      {"generate " + path("t.stl"), "unknown format '.stl' (supported: .json, .ply, .obj)"},
      {"convert " + broken + ".json " + missing, "does not exist"},
      {"convert " + broken + ".json " + path("t.txt"), "unknown format '.txt'"},
      {"grow --points " + broken + ".txt -o " + missing, "does not exist"},
      {"grow --points " + broken + ".txt -o " + path("t.off"), "unknown format '.off'"},
      {"sample " + broken + ".rf s --dist uniform -o " + path("no/such/p.txt"), "does not exist"},
      {"lsystem bush-2d -o " + missing, "does not exist"},
      {"generate " + path("t.json") + " --stats " + missing, "does not exist"},
      {"run " + broken + ".rf --stats " + missing, "does not exist"},
      {"check " + broken + ".ply --stats " + missing, "does not exist"},
  };
  for (const auto& c : cases) {
    const CliRun r = run_cli(c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.out;
    EXPECT_NE(r.out.find(c.expected), std::string::npos) << c.args << ": " << r.out;
    EXPECT_EQ(r.out.find("absent-input"), std::string::npos) << c.args << ": " << r.out;
  }
  EXPECT_FALSE(fs::exists(path("t.json")));
  EXPECT_FALSE(fs::exists(path("t.stl")));
}

TEST_F(PipelineCli, LSystemExamplesBecomeSkeletons) {
  const CliRun list = run_cli("lsystem --list");
  ASSERT_EQ(list.code, 0) << list.out;
  EXPECT_NE(list.out.find("monopodial"), std::string::npos) << list.out;
  const CliRun r = run_cli("lsystem bush-2d --iterations 2 -o " + path("b.json"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Skeleton s = read_skeleton(path("b.json"));
  EXPECT_EQ(connected_components(s).count, 1u);
  EXPECT_EQ(s.edge_count() + 1, s.node_count());
}

}  // namespace
}  // namespace ramiform::test
