// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Curved edges in skeleton files: the JSON edge object {"nodes", "controls", "radii"}, its
// round trip, read_skeleton's straightening (SkeletonReadOptions::keep_curves), errors naming
// the edge, and PLY/OBJ output straightening the curves.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {
namespace {

using io_test::TempDir;

const char* kCurvedJson = R"({
  "nodes": [
    {"position": [0, 0, 0], "radius": 0.5},
    {"position": [4, 0, 0], "radius": 0.3},
    {"position": [4, 0, 3], "radius": 0.4}
  ],
  "edges": [
    {"nodes": [0, 1], "controls": [[1, 3, 0], [3, 3, 1]]},
    [1, 2],
    {"nodes": [2, 0], "controls": [[2, -2, 4]], "radii": [0.7]}
  ]
})";

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

void expect_same(const Skeleton& a, const Skeleton& b) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].position, b.nodes[i].position) << i;
    EXPECT_EQ(a.nodes[i].radius, b.nodes[i].radius) << i;
  }
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.node_types, b.node_types);
  EXPECT_EQ(a.open_ends, b.open_ends);
  ASSERT_EQ(a.curves.size(), b.curves.size());
  for (std::size_t e = 0; e < a.curves.size(); ++e) {
    EXPECT_EQ(a.curves[e].controls, b.curves[e].controls) << e;
    EXPECT_EQ(a.curves[e].radii, b.curves[e].radii) << e;
  }
}

TEST(SkeletonCurvesIo, ParseKeepsCurves) {
  const Skeleton s = parse_skeleton_json(kCurvedJson, "c.json");
  ASSERT_EQ(s.nodes.size(), 3u);
  ASSERT_EQ(s.edges.size(), 3u);
  EXPECT_EQ(s.edges[0], (std::array<std::uint32_t, 2>{0, 1}));
  EXPECT_EQ(s.edges[1], (std::array<std::uint32_t, 2>{1, 2}));
  EXPECT_EQ(s.edges[2], (std::array<std::uint32_t, 2>{2, 0}));
  ASSERT_EQ(s.curves.size(), 3u);
  EXPECT_EQ(s.curves[0].controls, (std::vector<Vec3>{Vec3(1, 3, 0), Vec3(3, 3, 1)}));
  EXPECT_TRUE(s.curves[0].radii.empty());
  EXPECT_TRUE(s.curves[1].controls.empty());
  EXPECT_EQ(s.curves[2].controls, (std::vector<Vec3>{Vec3(2, -2, 4)}));
  EXPECT_EQ(s.curves[2].radii, (std::vector<double>{0.7}));
  EXPECT_TRUE(s.has_curves());
  // An edge object without controls is a plain straight edge (no curves vector at all).
  const Skeleton plain = parse_skeleton_json(
      R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[1,0,0],"radius":1}],)"
      R"("edges":[{"nodes":[0,1]}]})",
      "p.json");
  EXPECT_EQ(plain.edges.size(), 1u);
  EXPECT_TRUE(plain.curves.empty());
}

TEST(SkeletonCurvesIo, JsonRoundTripIsBitExact) {
  Rng rng(77);
  Skeleton s;
  for (int i = 0; i < 6; ++i) {
    s.nodes.push_back({Vec3(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3)) * 1.1,
                       rng.uniform(0.01, 0.9) / 3});
  }
  s.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}};
  s.curves.resize(s.edges.size());
  s.curves[0].controls = {Vec3(0.1, 0.2, 0.3), Vec3(1.0 / 3, -2.0 / 7, 1e-300)};
  s.curves[0].radii = {0.1 + 0.2, 1.0 / 3};
  s.curves[2].controls = {Vec3(rng.uniform(), rng.uniform(), -0.0)};
  for (int k = 0; k < 14; ++k) {
    s.curves[4].controls.push_back(Vec3(rng.uniform(-9, 9), rng.uniform(-9, 9), rng.uniform(-9, 9)));
    s.curves[4].radii.push_back(rng.uniform(0.001, 2));
  }
  s.node_types = {1, 2, 3, 3, 4, -7};
  s.open_ends = {0, 1, 0, 0, 0, 1};
  ASSERT_NO_THROW(validate(s));
  const std::string text = skeleton_to_json(s);
  const Skeleton back = parse_skeleton_json(text, "rt.json");
  expect_same(s, back);
  EXPECT_TRUE(std::signbit(back.curves[2].controls[0].z()));
  // Twice is a fixed point.
  EXPECT_EQ(skeleton_to_json(back), text);
  // Through a file as well (keep_curves).
  TempDir dir;
  write_skeleton(s, dir.file("rt.json"));
  SkeletonReadOptions keep;
  keep.keep_curves = true;
  expect_same(s, read_skeleton(dir.file("rt.json"), keep));
}

TEST(SkeletonCurvesIo, ReadSkeletonStraightensUnlessKeepCurves) {
  TempDir dir;
  const std::string path = dir.file("c.json");
  write_text(path, kCurvedJson);
  const Skeleton parsed = parse_skeleton_json(kCurvedJson, path);
  const Skeleton straight = read_skeleton(path);
  EXPECT_TRUE(straight.curves.empty());
  EXPECT_FALSE(straight.has_curves());
  const Skeleton expected = straighten_curves(parsed, 0.01);
  expect_same(straight, expected);
  EXPECT_GT(straight.nodes.size(), 3u);
  SkeletonReadOptions keep;
  keep.keep_curves = true;
  expect_same(read_skeleton(path, keep), parsed);
  // Upper-case extension too.
  write_text(dir.file("C.JSON"), kCurvedJson);
  EXPECT_TRUE(read_skeleton(dir.file("C.JSON"), keep).has_curves());
}

// Expects parse_skeleton_json to throw InputError whose message has every needle.
void expect_error(const std::string& edges, const std::vector<std::string>& needles) {
  const std::string text =
      R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[3,0,0],"radius":1},)"
      R"({"position":[0,3,0],"radius":1}],"edges":)" +
      edges + "}";
  try {
    (void)parse_skeleton_json(text, "bad.json");
    ADD_FAILURE() << "accepted: " << edges;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& n : needles) {
      EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
    }
  }
}

TEST(SkeletonCurvesIo, ErrorsNameTheEdge) {
  expect_error(R"([[0,1],{"nodes":[1,2],"controls":5}])",
               {"bad.json", "edge 1", "\"controls\" must be an array"});
  expect_error(R"([[0,1],{"nodes":[1,2],"controls":{"a":1}}])", {"edge 1", "\"controls\""});
  expect_error(R"([{"nodes":[0,1],"controls":[[1,1,1],[1,2]]}])",
               {"edge 0", "control point 1 must be an array of 3 numbers"});
  expect_error(R"([[0,1],[1,2],{"nodes":[2,0],"controls":[[1,"x",1]]}])",
               {"edge 2", "control point 0 must be a number", "\"x\""});
  expect_error(R"([{"nodes":[0,1],"controls":[[1,null,1]]}])",
               {"edge 0", "control point 0 must be a number", "null"});
  expect_error(R"([{"nodes":[0,1],"controls":[[1,1,1e999]]}])", {"bad.json"});
  expect_error(R"([[0,1],{"nodes":[1,2],"controls":[[1,1,1]],"radius":3}])",
               {"edge 1", "unknown key \"radius\""});
  expect_error(R"([[0,1],{"controls":[[1,1,1]]}])",
               {"edge 1", "an edge object needs \"nodes\""});
  expect_error(R"([{"nodes":[0,1],"controls":[[1,1,1]],"radii":"big"}])",
               {"edge 0", "\"radii\" must be an array"});
  expect_error(R"([{"nodes":[0,1],"controls":[[1,1,1]],"radii":[true]}])",
               {"edge 0", "radius 0 must be a number"});
  // Invariants checked by validate() after parsing name the edge as well.
  expect_error(R"([[0,1],{"nodes":[1,2],"controls":[[1,1,1],[2,2,2]],"radii":[1]}])",
               {"bad.json", "edge 1", "1 radii for 2 control points"});
  expect_error(R"([{"nodes":[0,1],"controls":[[1,1,1]],"radii":[-1]}])",
               {"edge 0", "radius 0 must be finite and > 0"});
  expect_error(R"([{"nodes":[0,1],"controls":[[1,1,1]],"radii":[0.5]},{"nodes":[1,0]}])",
               {"edge 1", "duplicate edge"});
  std::string many = R"([{"nodes":[0,1],"controls":[)";
  for (int k = 0; k < 15; ++k) many += std::string(k ? "," : "") + "[1,1," + std::to_string(k) + "]";
  expect_error(many + "]}]", {"edge 0", "15 control points"});
}

TEST(SkeletonCurvesIo, NonJsonFormatsStraighten) {
  TempDir dir;
  const Skeleton s = parse_skeleton_json(kCurvedJson, "c.json");
  const Skeleton straight = straighten_curves(s);
  write_skeleton(s, dir.file("c.ply"));
  const Skeleton ply = read_skeleton(dir.file("c.ply"));
  expect_same(ply, straight);
  write_skeleton(s, dir.file("c.obj"));
  SkeletonReadOptions obj;
  obj.obj_radius = 0.25;
  const Skeleton o = read_skeleton(dir.file("c.obj"), obj);
  ASSERT_EQ(o.nodes.size(), straight.nodes.size());
  EXPECT_EQ(o.edges, straight.edges);
  for (std::size_t i = 0; i < o.nodes.size(); ++i) {
    EXPECT_EQ(o.nodes[i].position, straight.nodes[i].position);
  }
  // JSON keeps the curves.
  write_skeleton(s, dir.file("c.json"));
  SkeletonReadOptions keep;
  keep.keep_curves = true;
  expect_same(read_skeleton(dir.file("c.json"), keep), s);
}

TEST(SkeletonCurvesIo, WritingAnInvalidCurveIsRefused) {
  Skeleton s = parse_skeleton_json(kCurvedJson, "c.json");
  s.curves[0].radii = {1};  // 2 controls
  TempDir dir;
  EXPECT_THROW((void)skeleton_to_json(s), InvalidArgument);
  EXPECT_THROW(write_skeleton(s, dir.file("x.json")), InvalidArgument);
}

// write_skeleton validates before straightening for .ply/.obj: a curve with 1 radius for 2
// controls is refused, not read past its radii.
TEST(SkeletonCurvesIo, WritingAnInvalidCurveToPlyOrObjIsRefused) {
  Skeleton s = parse_skeleton_json(kCurvedJson, "c.json");
  s.curves[0].radii = {1};  // 2 controls
  TempDir dir;
  EXPECT_THROW(write_skeleton(s, dir.file("x.ply")), InvalidArgument);
  EXPECT_THROW(write_skeleton(s, dir.file("x.obj")), InvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.ply")));
}

}  // namespace
}  // namespace ramiform

namespace ramiform {
namespace {

using io_test::TempDir;

// A file whose curves would need more than 2^22 straight pieces (radius 1e-9, 1100 tight
// curves of 4096 pieces each) is refused on reading, naming the file, before anything is
// allocated; with keep_curves it reads.
TEST(SkeletonCurvesIo, HostileCurvesAreRefusedBeforeStraightening) {
  std::string json = R"({"nodes":[)";
  for (int k = 0; k < 2200; ++k) {
    json += std::string(k ? "," : "") + R"({"position":[)" + std::to_string(k) +
            R"(,0,0],"radius":1e-9})";
  }
  json += R"(],"edges":[)";
  for (int k = 0; k < 1100; ++k) {
    json += std::string(k ? "," : "") + R"({"nodes":[)" + std::to_string(2 * k) + "," +
            std::to_string(2 * k + 1) + R"(],"controls":[[)" + std::to_string(2 * k) +
            ",5,0]]}";
  }
  json += "]}";
  TempDir dir;
  const std::string path = dir.file("tight.json");
  std::ofstream(path) << json;
  try {
    (void)read_skeleton(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tight.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("straight pieces"), std::string::npos) << e.what();
  }
  SkeletonReadOptions keep;
  keep.keep_curves = true;
  EXPECT_EQ(read_skeleton(path, keep).edges.size(), 1100u);
}

}  // namespace
}  // namespace ramiform
