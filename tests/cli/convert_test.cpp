// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform convert`: cylinder models and skeleton files to skeleton JSON, exit codes, no
// partial output, stats.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli/cli_run.h"
#include "ramiform/io/qsm_io.h"
#include "ramiform/io/skeleton_io.h"

namespace ramiform {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::run_cli;

using ConvertTest = test::CliDirTest;

// A trunk with a branch starting on its surface half-way up, and a continuation.
const char* const kTreeQsm =
    "0.2 2 0 0 0 0 0 1 0 2 0 0.2 1 0 1\n"
    "0.15 1 0 0 2 0 0 1 1 0 0 0.15 1 0 2\n"
    "0.05 1 0.2 0 1 1 0 0 1 0 0 0.05 2 1 1\n";

TEST_F(ConvertTest, TreeQsmToJsonReadsBackWithStats) {
  const std::string in = write("tree.txt", kTreeQsm);
  const CliRun r = run_cli("convert " + in + " " + path("tree.json") + " --stats " +
                           path("stats.json") + " --threads 1");
  ASSERT_EQ(r.code, 0) << r.out;
  const Skeleton s = read_skeleton(path("tree.json"));
  QsmImportReport report;
  const Skeleton direct = read_treeqsm(in, &report);
  EXPECT_EQ(s.edges, direct.edges);
  ASSERT_EQ(s.node_count(), direct.node_count());
  for (std::size_t i = 0; i < s.node_count(); ++i) {
    EXPECT_EQ(s.nodes[i].position, direct.nodes[i].position);
    EXPECT_EQ(s.nodes[i].radius, direct.nodes[i].radius);
  }
  EXPECT_EQ(connected_components(s).count, 1U);
  EXPECT_NE(r.out.find("6 nodes, 5 edges, 1 component"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 parent splits, 1 connectors"), std::string::npos) << r.out;
  std::ifstream stats_in(path("stats.json"));
  const auto stats = nlohmann::json::parse(stats_in);
  EXPECT_EQ(stats["nodes"].get<std::size_t>(), 6U);
  EXPECT_EQ(stats["edges"].get<std::size_t>(), 5U);
  EXPECT_EQ(stats["components"].get<std::size_t>(), 1U);
  EXPECT_EQ(stats["cylinders"].get<std::size_t>(), 3U);
  EXPECT_EQ(stats["split_parents"].get<std::size_t>(), report.split_parents);
  EXPECT_EQ(stats["connectors"].get<std::size_t>(), report.connectors);
  EXPECT_TRUE(stats["seconds"].contains("total"));
}

TEST_F(ConvertTest, SimpleForestAndObjConvert) {
  const std::string csv = write("tree.csv",
                                "ID,parentID,startX,startY,startZ,endX,endY,endZ,radius\n"
                                "0,-1,0,0,0,0,0,1,0.1\n"
                                "1,0,0,0,1,0,0,2,0.05\n");
  const CliRun a = run_cli("convert " + csv + " " + path("a.json"));
  ASSERT_EQ(a.code, 0) << a.out;
  EXPECT_EQ(read_skeleton(path("a.json")).node_count(), 3U);

  const std::string obj = write("s.obj", "v 0 0 0\nv 0 0 1\nl 1 2\n");
  const CliRun b = run_cli("convert " + obj + " " + path("b.json") + " --obj-radius 0.25");
  ASSERT_EQ(b.code, 0) << b.out;
  const Skeleton s = read_skeleton(path("b.json"));
  ASSERT_EQ(s.node_count(), 2U);
  EXPECT_EQ(s.nodes[1].radius, 0.25);
  EXPECT_EQ(b.out.find("cylinders"), std::string::npos) << b.out;  // no import report
}

TEST_F(ConvertTest, BadInputExitsTwoWithTheLineAndLeavesNoOutput) {
  const std::string in = write("bad.txt", std::string(kTreeQsm) + "0.1 1 0 0 1 0 0 1 nan\n");
  const std::string out = path("out.json");
  const std::size_t before = files_in_dir();
  const CliRun r = run_cli("convert " + in + " " + out);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("bad.txt:4: parent: 'nan' is not a finite number"), std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(files_in_dir(), before);

  // An existing output is kept when the input is bad.
  write("keep.json", "old");
  EXPECT_EQ(run_cli("convert " + in + " " + path("keep.json")).code, 2);
  std::ifstream keep(path("keep.json"));
  std::string content((std::istreambuf_iterator<char>(keep)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "old");

  EXPECT_EQ(run_cli("convert " + path("missing.txt") + " " + out).code, 2);
  EXPECT_EQ(run_cli("convert " + write("s.obj", "v 0 0 0\n") + " " + out).code, 2);  // no radius
  EXPECT_EQ(run_cli("convert " + in).code, 1);  // usage: OUT missing
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace ramiform
