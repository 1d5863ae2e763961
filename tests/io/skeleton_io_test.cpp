// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/skeleton_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using io_test::put;
using io_test::TempDir;
using io_test::write_bytes;

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Awkward doubles: no short decimal form, tiny and large magnitudes, negative zero, a
// subnormal (kept within what validate() accepts as non-zero edge lengths).
Skeleton awkward_skeleton() {
  Skeleton s;
  s.nodes.push_back({Vec3(0.1, 1.0 / 3.0, -0.0), 0.7});
  s.nodes.push_back({Vec3(1.0e9 + 0.1, -2.5e-300, 4.9406564584124654e-324), 1e-7});
  s.nodes.push_back({Vec3(M_PI, -M_E, 123456789.123456789), 2.0 / 3.0});
  s.nodes.push_back({Vec3(-7.0, 8.0, 1.0), 1.0});
  s.edges = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
  return s;
}

void expect_identical(const Skeleton& a, const Skeleton& b, bool radii = true) {
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(same_bits(a.nodes[i].position[c], b.nodes[i].position[c]))
          << "node " << i << " coordinate " << c << ": " << a.nodes[i].position[c] << " vs "
          << b.nodes[i].position[c];
    }
    if (radii) {
      EXPECT_TRUE(same_bits(a.nodes[i].radius, b.nodes[i].radius)) << "node " << i;
    }
  }
  EXPECT_EQ(a.edges, b.edges);
}

TEST(SkeletonJson, InMemoryRoundTripIsBitExact) {
  const Skeleton s = awkward_skeleton();
  expect_identical(parse_skeleton_json(skeleton_to_json(s), "mem.json"), s);
}

TEST(SkeletonIo, FileRoundTripsAreBitExactForJsonAndPly) {
  TempDir dir;
  const Skeleton s = awkward_skeleton();
  for (const char* name : {"s.json", "s.ply", "S.PLY"}) {
    const std::string path = dir.file(name);
    write_skeleton(s, path);
    expect_identical(read_skeleton(path), s);
  }
  write_skeleton_json(s, dir.file("t.json"));
  expect_identical(read_skeleton(dir.file("t.json")), s);
}

TEST(SkeletonIo, ObjRoundTripKeepsPositionsAndEdgesAndUsesTheGivenRadius) {
  TempDir dir;
  const Skeleton s = awkward_skeleton();
  write_skeleton(s, dir.file("s.obj"));
  SkeletonReadOptions options;
  options.obj_radius = 0.25;
  const Skeleton r = read_skeleton(dir.file("s.obj"), options);
  expect_identical(r, s, /*radii=*/false);
  for (const auto& n : r.nodes) EXPECT_EQ(n.radius, 0.25);
}

TEST(SkeletonIo, WritingAnInvalidSkeletonThrowsAndWritesNothing) {
  TempDir dir;
  Skeleton s = awkward_skeleton();
  s.nodes[1].radius = 0.0;
  EXPECT_THROW(write_skeleton(s, dir.file("bad.json")), InvalidArgument);
  EXPECT_THROW(write_skeleton(s, dir.file("bad.ply")), InvalidArgument);
  EXPECT_THROW(write_skeleton(awkward_skeleton(), dir.file("bad.txt")), InvalidArgument);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(SkeletonJson, EdgesMayBeAbsentOrEmpty) {
  const std::string one = R"({"nodes":[{"position":[0,0,0],"radius":1}]})";
  EXPECT_EQ(parse_skeleton_json(one, "a.json").edge_count(), 0U);
  const std::string two = R"({"nodes":[{"position":[0,0,0],"radius":1}],"edges":[]})";
  EXPECT_EQ(parse_skeleton_json(two, "b.json").node_count(), 1U);
  const Skeleton s = parse_skeleton_json(
      R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[1,2,3],"radius":0.5}],
          "edges":[[1,0]], "comment": "extra keys are ignored"})",
      "c.json");
  ASSERT_EQ(s.edges.size(), 1U);
  EXPECT_EQ(s.edges[0][0], 1U);
  EXPECT_EQ(s.nodes[1].position, Vec3(1, 2, 3));
  EXPECT_EQ(s.nodes[1].radius, 0.5);
}

TEST(SkeletonJson, SyntaxErrorNamesTheLine) {
  const std::string text = "{\n  \"nodes\": [\n    {\"position\": [0, 0, 0], \"radius\": 1,}\n]}";
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(text, "syn.json"), "syn.json", 3, "JSON syntax error");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json("{\"nodes\": [\n\n", "eof.json"), "eof.json", 3,
                        "JSON syntax error");
}

TEST(SkeletonJson, OpenEndsRoundTripAndBadValuesNameTheNode) {
  const std::string text =
      R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[0,0,5],"radius":1,"end":"open"},)"
      R"({"position":[0,5,0],"radius":1,"end":"closed"}],"edges":[[0,1],[0,2]]})";
  const Skeleton s = parse_skeleton_json(text, "o.json");
  EXPECT_EQ(s.open_ends, (std::vector<std::uint8_t>{0, 1, 0}));
  const Skeleton back = parse_skeleton_json(skeleton_to_json(s), "back.json");
  EXPECT_EQ(back.open_ends, s.open_ends);
  // No "end" anywhere: no flags at all.
  EXPECT_TRUE(parse_skeleton_json(R"({"nodes":[{"position":[0,0,0],"radius":1}]})", "n.json")
                  .open_ends.empty());
  EXPECT_INPUT_ERROR_AT(
      parse_skeleton_json(R"({"nodes":[{"position":[0,0,0],"radius":1,"end":"opened"}]})", "b.json"),
      "b.json", 0, "node 0: \"end\" must be \"open\" or \"closed\"");
  EXPECT_INPUT_ERROR_AT(
      parse_skeleton_json(R"({"nodes":[{"position":[0,0,0],"radius":1,"end":1}]})", "c.json"),
      "c.json", 0, "node 0: \"end\" must be");
}

TEST(SkeletonJson, StructuralErrorsNameTheElement) {
  const auto node = [](const std::string& second) {
    return R"({"nodes":[{"position":[0,0,0],"radius":1},)" + second + "]}";
  };
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(node(R"({"position":[1,2],"radius":1})"), "p.json"),
                        "p.json", 0, "node 1: \"position\" must be an array of 3 numbers");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(node(R"({"position":[1,2,"3"],"radius":1})"), "q.json"),
                        "q.json", 0, "node 1: \"position\" must be a number");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(node(R"({"position":[1,2,3]})"), "r.json"), "r.json", 0,
                        "node 1: missing \"radius\"");
  EXPECT_INPUT_ERROR_AT(
      parse_skeleton_json(node(R"({"position":[1,2,3],"radius":-2})"), "neg.json"), "neg.json", 0,
      "node 1: radius must be > 0");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(node("[1,2,3]"), "o.json"), "o.json", 0, "node 1:");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(R"({"edges":[]})", "n.json"), "n.json", 0,
                        "missing \"nodes\"");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json("[1]", "t.json"), "t.json", 0, "\"nodes\"");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json("  \n ", "e.json"), "e.json", 0, "empty");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(R"({"nodes":[]})", "z.json"), "z.json", 0, "no nodes");
}

TEST(SkeletonJson, EdgeErrorsNameTheEdge) {
  const auto with_edges = [](const std::string& edges) {
    return R"({"nodes":[{"position":[0,0,0],"radius":1},{"position":[1,0,0],"radius":1},
               {"position":[2,0,0],"radius":1}], "edges":)" +
           edges + "}";
  };
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(with_edges("[[0,1],[1,-2]]"), "a.json"), "a.json", 0,
                        "edge 1: negative node index -2");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(with_edges("[[0,1],[1,2],[2]]"), "b.json"), "b.json", 0,
                        "edge 2: must be an array of 2");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(with_edges("[[0,1.5]]"), "c.json"), "c.json", 0,
                        "edge 0: node indices must be integers");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(with_edges("[[0,1],[1,7]]"), "d.json"), "d.json", 0,
                        "edge 1: node index 7 out of range");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(with_edges("[[0,1],[1,2],[2,1]]"), "e.json"), "e.json",
                        0, "edge 2: duplicate edge");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(with_edges("[[1,1]]"), "f.json"), "f.json", 0,
                        "edge 0: self-loop");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(with_edges("{}"), "g.json"), "g.json", 0,
                        "\"edges\" must be an array");
}

TEST(SkeletonJson, ZeroLengthEdgeIsRejected) {
  const std::string text = R"({"nodes":[{"position":[1,1,1],"radius":1},
      {"position":[1,1,1],"radius":1}], "edges":[[0,1]]})";
  EXPECT_INPUT_ERROR_AT(parse_skeleton_json(text, "z.json"), "z.json", 0,
                        "edge 0: zero-length edge");
}

TEST(SkeletonIo, UnknownExtensionAndMissingFileNameTheFile) {
  TempDir dir;
  const std::string path = dir.file("skel.yaml");
  write_bytes(path, "nodes: []\n");
  EXPECT_INPUT_ERROR_AT(read_skeleton(path), path, 0, ".json, .ply, .obj");
  const std::string missing = dir.file("missing.json");
  EXPECT_INPUT_ERROR_AT(read_skeleton(missing), missing, 0, "cannot open");
}

TEST(SkeletonIo, FileErrorsCarryThePath) {
  TempDir dir;
  const std::string path = dir.file("broken.json");
  write_bytes(path, "{\"nodes\": [\n  {\"position\": [0, 0, nan], \"radius\": 1}\n]}\n");
  EXPECT_INPUT_ERROR_AT(read_skeleton(path), path, 2, "JSON syntax error");
}

// ---- PLY ---------------------------------------------------------------------------------

TEST(SkeletonPly, AsciiWithExtraPropertiesAndAnyOrder) {
  const std::string text =
      "ply\n"
      "format ascii 1.0\n"
      "comment a tree\n"
      "element vertex 3\n"
      "property uchar red\n"
      "property float radius\n"
      "property double z\n"
      "property list uchar int tags\n"
      "property int16 x\n"
      "property float32 y\n"
      "element edge 2\n"
      "property int vertex1\n"
      "property uint32 vertex2\n"
      "property float weight\n"
      "end_header\n"
      "255 0.5 3 2 7 8 1 2\n"
      "0 0.25 -1 0 -4 5.5\n"
      "\n"
      "12 1 0 1 9 0 0\n"
      "0 1 0.5\n"
      "1 2 nan\n";  // skipped properties are not parsed
  const Skeleton s = parse_skeleton_ply(text, "extra.ply");
  ASSERT_EQ(s.node_count(), 3U);
  EXPECT_EQ(s.nodes[0].position, Vec3(1, 2, 3));
  EXPECT_EQ(s.nodes[0].radius, 0.5);
  EXPECT_EQ(s.nodes[1].position, Vec3(-4, 5.5, -1));
  EXPECT_EQ(s.nodes[2].position, Vec3(0, 0, 0));
  EXPECT_EQ(s.nodes[2].radius, 1.0);
  ASSERT_EQ(s.edge_count(), 2U);
  EXPECT_EQ(s.edges[1], (std::array<std::uint32_t, 2>{1, 2}));
}

std::string binary_skeleton_ply(bool big_endian, std::size_t declared_vertices,
                                std::size_t written_vertices) {
  std::string b = "ply\nformat ";
  b += big_endian ? "binary_big_endian" : "binary_little_endian";
  b += " 1.0\nelement vertex " + std::to_string(declared_vertices) +
       "\nproperty float x\nproperty float y\nproperty float z\nproperty double radius\n"
       "property ushort flags\nelement edge 1\nproperty uchar vertex1\nproperty short vertex2\n"
       "end_header\n";
  for (std::size_t i = 0; i < written_vertices; ++i) {
    put<float>(b, 1.5f * static_cast<float>(i), big_endian);
    put<float>(b, -2.0f, big_endian);
    put<float>(b, 0.25f, big_endian);
    put<double>(b, 0.1 * static_cast<double>(i + 1), big_endian);
    put<std::uint16_t>(b, 0xBEEF, big_endian);
  }
  if (written_vertices == declared_vertices) {
    put<std::uint8_t>(b, 1, big_endian);
    put<std::int16_t>(b, 0, big_endian);
  }
  return b;
}

TEST(SkeletonPly, BinaryBigAndLittleEndian) {
  for (const bool big : {true, false}) {
    const Skeleton s = parse_skeleton_ply(binary_skeleton_ply(big, 2, 2), "bin.ply");
    ASSERT_EQ(s.node_count(), 2U) << big;
    EXPECT_EQ(s.nodes[1].position, Vec3(1.5, -2.0, 0.25));
    EXPECT_EQ(s.nodes[1].radius, 0.2);
    EXPECT_EQ(s.nodes[0].radius, 0.1);
    ASSERT_EQ(s.edge_count(), 1U);
    EXPECT_EQ(s.edges[0], (std::array<std::uint32_t, 2>{1, 0}));
  }
}

TEST(SkeletonPly, TruncatedBinaryNamesTheElementIndex) {
  std::string b = binary_skeleton_ply(false, 5, 3);
  b += "xy";  // a partial fourth vertex
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(b, "cut.ply"), "cut.ply", 0, "vertex 3:");
  const std::string whole = binary_skeleton_ply(true, 2, 2);
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(whole.substr(0, whole.size() - 1), "cut2.ply"),
                        "cut2.ply", 0, "edge 0:");
}

TEST(SkeletonPly, NonFiniteBinaryValueNamesTheElementIndex) {
  std::string b =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\nproperty double radius\nend_header\n";
  for (double v : {0.0, 0.0, 0.0, 1.0, 1.0, std::numeric_limits<double>::infinity(), 0.0, 1.0}) {
    put<double>(b, v, false);
  }
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(b, "inf.ply"), "inf.ply", 0,
                        "vertex 1: property 'y' is not a finite number");
}

TEST(SkeletonPly, HeaderErrorsNameTheLine) {
  const std::string good_tail =
      "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
      "property float radius\nend_header\n0 0 0 1\n";
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply("plx\nformat ascii 1.0\n" + good_tail, "m.ply"), "m.ply",
                        1, "not a PLY file");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply("ply\nformat binary 1.0\n" + good_tail, "f.ply"),
                        "f.ply", 2, "unknown PLY format");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply("ply\nformat ascii 2.0\n" + good_tail, "v.ply"), "v.ply",
                        2, "version");
  EXPECT_INPUT_ERROR_AT(
      parse_skeleton_ply("ply\nformat ascii 1.0\ncomment x\nelement vertex 1\nproperty float x\n"
                         "property float y\nproperty float z\nend_header\n0 0 0\n",
                         "r.ply"),
      "r.ply", 4, "no property 'radius'");
  EXPECT_INPUT_ERROR_AT(
      parse_skeleton_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                         "property quad y\n",
                         "t.ply"),
      "t.ply", 5, "unknown PLY type 'quad'");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply("ply\nformat ascii 1.0\nelement vertex 1\n", "e.ply"),
                        "e.ply", 3, "end_header");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply("ply\nelement vertex 0\nend_header\n", "n.ply"), "n.ply",
                        3, "no 'format' line");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply("", "empty.ply"), "empty.ply", 0, "empty");
}

TEST(SkeletonPly, AsciiBodyErrorsNameTheLine) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float radius\nend_header\n";  // body starts at line 9
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(head + "0 0 0 1\n1 1 1 nan\n2 2 2 1\n", "nan.ply"),
                        "nan.ply", 10, "not a finite number");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(head + "0 0 0 1\n1 1 1 1\n2 2 2x 1\n", "junk.ply"),
                        "junk.ply", 11, "expected a number, got '2x'");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(head + "0 0 0 1\n1 1 1 1 1\n2 2 2 1\n", "many.ply"),
                        "many.ply", 10, "expected 4 fields, got 5");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(head + "0 0 0 1\n1 1 1\n2 2 2 1\n", "few.ply"),
                        "few.ply", 10, "too few fields");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(head + "0 0 0 1\n1 1 1 1\n", "short.ply"), "short.ply",
                        0, "vertex 2:");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(head + "0 0 0 1\n1 1 1 1\n2 2 2 1\n3\n", "extra.ply"),
                        "extra.ply", 12, "extra data");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(head + "0 0 0 1\n1 1 1 0\n2 2 2 1\n", "r0.ply"),
                        "r0.ply", 0, "node 1: radius must be > 0");
}

TEST(SkeletonPly, BadEdgeIndicesNameTheEdge) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty float radius\nelement edge 2\nproperty float vertex1\n"
      "property float vertex2\nend_header\n0 0 0 1\n1 0 0 1\n0 1\n1 0.5\n";
  EXPECT_INPUT_ERROR_AT(parse_skeleton_ply(text, "edge.ply"), "edge.ply", 0,
                        "edge 1: invalid node index");
}

// ---- OBJ ---------------------------------------------------------------------------------

SkeletonReadOptions obj_options(double radius) {
  SkeletonReadOptions o;
  o.obj_radius = radius;
  return o;
}

TEST(SkeletonObj, PolylinesGiveConsecutiveEdges) {
  const std::string text =
      "# a fork\n"
      "o tree\n"
      "v 0 0 0\n"
      "v 0 0 1\n"
      "v 1 0 2  # comment after data\n"
      "vt 0.5 0.5\n"
      "l 1 2 3\n"
      "v -1 0 2\r\n"
      "l 2/1 -1\n"
      "f 1 2 3\n";
  const Skeleton s = parse_skeleton_obj(text, "fork.obj", obj_options(0.1));
  ASSERT_EQ(s.node_count(), 4U);
  EXPECT_EQ(s.nodes[3].position, Vec3(-1, 0, 2));
  EXPECT_EQ(s.nodes[3].radius, 0.1);
  ASSERT_EQ(s.edge_count(), 3U);
  EXPECT_EQ(s.edges[0], (std::array<std::uint32_t, 2>{0, 1}));
  EXPECT_EQ(s.edges[1], (std::array<std::uint32_t, 2>{1, 2}));
  EXPECT_EQ(s.edges[2], (std::array<std::uint32_t, 2>{1, 3}));
}

TEST(SkeletonObj, ErrorsNameTheLine) {
  const SkeletonReadOptions o = obj_options(1.0);
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\nv 1 1\n", "a.obj", o), "a.obj", 2,
                        "'v' needs 3 coordinates");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\n\nv 1 1 1e\n", "b.obj", o), "b.obj", 3,
                        "expected a number, got '1e'");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\nv 1 inf 1\n", "c.obj", o), "c.obj", 2,
                        "not a finite number");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\nv 1 1 1\nl 1 3\nv 2 2 2\n", "d.obj", o),
                        "d.obj", 3, "vertex index 3 out of range");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\nv 1 1 1\nl 0 1\n", "e.obj", o), "e.obj", 3,
                        "index 0 is invalid");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\nv 1 1 1\nl -3 1\n", "f.obj", o), "f.obj", 3,
                        "out of range");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\nv 1 1 1\nl 2\n", "g.obj", o), "g.obj", 3,
                        "at least 2");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("v 0 0 0\nv 1 1 1\nl 1 x\n", "h.obj", o), "h.obj", 3,
                        "expected an integer");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("", "i.obj", o), "i.obj", 0, "empty");
  EXPECT_INPUT_ERROR_AT(parse_skeleton_obj("# nothing\n", "j.obj", o), "j.obj", 0, "no vertices");
}

TEST(SkeletonObj, RadiusMustBeGiven) {
  EXPECT_THROW((void)parse_skeleton_obj("v 0 0 0\n", "r.obj", {}), InvalidArgument);
  EXPECT_THROW((void)parse_skeleton_obj("v 0 0 0\n", "r.obj", obj_options(-1.0)), InvalidArgument);
  EXPECT_THROW((void)read_skeleton("whatever.obj"), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
