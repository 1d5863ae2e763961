// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/swc_io.h"

#include <gtest/gtest.h>

#include <string>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/skeleton_io.h"

namespace ramiform {
namespace {

using io_test::catch_input_error;
using io_test::TempDir;
using io_test::write_bytes;

// Samples out of order (children before parents), a comment, tabs and CRLF.
constexpr const char* kPlain =
    "# a neuron\r\n"
    "3 3 0 20 0 0.5 2\r\n"
    "1 1 0 0 0 5 -1\r\n"
    "2\t3\t0 10 0 1 1\r\n"
    "4 2 10 0 0 0.75 1\r\n";

TEST(Swc, AsInTheFileKeepsEverySampleEdgeAndType) {
  SwcReport report;
  const Skeleton s = parse_swc(kPlain, "plain.swc", {.soma_regions = false, .report = &report});
  ASSERT_EQ(s.nodes.size(), 4u);
  ASSERT_EQ(s.edges.size(), 3u);
  ASSERT_EQ(s.node_types.size(), 4u);
  EXPECT_EQ(report.samples, 4u);
  EXPECT_EQ(report.roots, 1u);
  // Every sample's node has the sample's position, radius and type, whatever the file order.
  const struct {
    double x, y, r;
    int type;
  } want[] = {{0, 20, 0.5, 3}, {0, 0, 5, 1}, {0, 10, 1, 3}, {10, 0, 0.75, 2}};
  for (std::size_t i = 0; i < 4; ++i) {
    const std::uint32_t n = report.sample_node.at(i);
    EXPECT_EQ(s.nodes[n].position, Vec3(want[i].x, want[i].y, 0)) << i;
    EXPECT_EQ(s.nodes[n].radius, want[i].r) << i;
    EXPECT_EQ(s.node_types[n], want[i].type) << i;
  }
  // Each child is joined to its parent.
  auto joined = [&](std::size_t a, std::size_t b) {
    const std::uint32_t na = report.sample_node[a];
    const std::uint32_t nb = report.sample_node[b];
    for (const auto& e : s.edges) {
      if ((e[0] == na && e[1] == nb) || (e[0] == nb && e[1] == na)) return true;
    }
    return false;
  };
  EXPECT_TRUE(joined(0, 2));
  EXPECT_TRUE(joined(2, 1));
  EXPECT_TRUE(joined(3, 1));
}

TEST(Swc, SinglePointSomaNeuritesStartOnItsSurface) {
  SwcReport report;
  const Skeleton s = parse_swc(kPlain, "plain.swc", {.report = &report});
  ASSERT_EQ(report.somata.size(), 1u);
  const SwcSoma& soma = report.somata[0];
  EXPECT_EQ(soma.kind, SwcSomaKind::kSinglePoint);
  EXPECT_EQ(soma.radius, 5.0);
  EXPECT_EQ(soma.center, Vec3(0, 0, 0));
  EXPECT_EQ(s.nodes[soma.node].radius, 5.0);
  EXPECT_EQ(s.node_types[soma.node], 1);
  // Two neurites leave the soma: each gets a node on the sphere with the neurite's radius.
  EXPECT_EQ(report.attachments, 2u);
  int on_surface = 0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (i == soma.node) continue;
    const double d = (s.nodes[i].position - soma.center).norm();
    if (std::abs(d - 5.0) < 1e-12) {
      ++on_surface;
      EXPECT_TRUE(s.nodes[i].radius == 1.0 || s.nodes[i].radius == 0.75);
    } else {
      EXPECT_GT(d, 5.0) << "no neurite node inside the soma sphere";
    }
  }
  EXPECT_EQ(on_surface, 2);
  // The soma centre is not joined to the neurites by a cone.
  for (const auto& e : s.edges) EXPECT_TRUE(e[0] != soma.node && e[1] != soma.node);
}

TEST(Swc, ThreePointSomaBecomesOneSphere) {
  const std::string text =
      "1 1 0 0 0 4 -1\n"
      "2 1 0 -4 0 4 1\n"
      "3 1 0 4 0 4 1\n"
      "4 3 10 0 0 1 1\n"
      "5 3 20 0 0 0.5 4\n";
  SwcReport report;
  const Skeleton s = parse_swc(text, "three.swc", {.report = &report});
  ASSERT_EQ(report.somata.size(), 1u);
  EXPECT_EQ(report.somata[0].kind, SwcSomaKind::kThreePoint);
  EXPECT_EQ(report.somata[0].radius, 4.0);
  EXPECT_EQ(report.somata[0].samples, 3u);
  // The two side points are gone: sphere, surface node, two dendrite samples.
  EXPECT_EQ(s.nodes.size(), 4u);
  EXPECT_EQ(report.sample_node[1], report.somata[0].node);
  EXPECT_EQ(report.sample_node[2], report.somata[0].node);
}

TEST(Swc, ReadSkeletonDispatchesAndJsonKeepsTypes) {
  const TempDir dir;
  const std::string path = dir.file("roundtrip.swc");
  write_bytes(path, kPlain);
  const Skeleton s = read_skeleton(path);
  ASSERT_FALSE(s.node_types.empty());
  const Skeleton back = parse_skeleton_json(skeleton_to_json(s), "back.json");
  EXPECT_EQ(back.node_types, s.node_types);
  EXPECT_EQ(back.edges, s.edges);
}

TEST(Swc, BadFilesNameTheLine) {
  const struct {
    const char* text;
    std::size_t line;
    const char* says;
  } cases[] = {
      {"", 0, "empty"},
      {"# only a comment\n", 0, "no samples"},
      {"1 1 0 0 0 1\n", 1, ""},                              // six fields
      {"1 1 0 0 0 1 -1\n2 3 0 x 0 1 1\n", 2, ""},            // not a number
      {"1 1 0 0 0 1 -1\n2 3 0 nan 0 1 1\n", 2, ""},          // not finite
      {"1 1 0 0 0 1 -1\n2 3 0 1 0 0 1\n", 2, "radius"},      // radius 0
      {"1 1 0 0 0 1 -1\n2 3 0 1 0 -1 1\n", 2, "radius"},     // negative radius
      {"1 1 0 0 0 1 -1\n2 3 0 1 0 1 2\n", 2, "own parent"},  // self parent
      {"1 1 0 0 0 1 -1\n2 3 0 1 0 1 7\n", 2, "7"},           // unknown parent
      {"1 1 0 0 0 1 -1\n1 3 0 1 0 1 -1\n", 2, "1"},          // duplicate index
      {"1 1 0 0 0 1 -1\n2 3 0 1 0 1 3\n3 3 0 2 0 1 2\n", 2, "cycle"},
      {"1 1 0 0 0 1 -2\n", 1, ""},        // parent below -1
      {"-1 1 0 0 0 1 -1\n", 1, "index"},  // negative index
      {"1.5 1 0 0 0 1 -1\n", 1, ""},      // index not an integer
  };
  for (const auto& c : cases) {
    const InputError e = catch_input_error([&] { (void)parse_swc(c.text, "bad.swc"); });
    EXPECT_EQ(e.file(), "bad.swc") << c.text;
    EXPECT_EQ(e.line(), c.line) << c.text << " -> " << e.what();
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos)
        << c.text << " -> " << e.what();
  }
}

}  // namespace
}  // namespace ramiform
