// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/mesh_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>

#include "io/io_test_util.h"
#include "ramiform/mesh/checks.h"
#include "support/glb_reader.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using io_test::put;
using io_test::read_bytes;
using io_test::TempDir;
using io_test::write_bytes;
using Tri = std::array<std::uint32_t, 3>;

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 24) == 0; }

// A tetrahedron with awkward coordinates and a degenerate triangle (allowed).
TriMesh awkward_mesh(bool normals) {
  TriMesh m;
  m.positions = {Vec3(0.1, 0.2, 0.3), Vec3(1.0 / 3.0, -0.0, 1e-310), Vec3(-1e300, 7.0, 2.5),
                 Vec3(M_PI, M_E, -M_SQRT2)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}, {3, 3, 1}};
  if (normals) {
    m.normals = {Vec3(0.6, 0.8, 0.0), Vec3(-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0), Vec3(0, 0, -1),
                 Vec3(0.1, 0.2, 0.3).normalized()};
  }
  return m;
}

void expect_identical(const TriMesh& a, const TriMesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    EXPECT_TRUE(same_bits(a.positions[i], b.positions[i])) << "vertex " << i;
  }
  ASSERT_EQ(a.normals.size(), b.normals.size());
  for (std::size_t i = 0; i < a.normals.size(); ++i) {
    EXPECT_TRUE(same_bits(a.normals[i], b.normals[i])) << "normal " << i;
  }
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(MeshIo, RoundTripsAreBitExact) {
  TempDir dir;
  for (const bool normals : {false, true}) {
    const TriMesh m = awkward_mesh(normals);
    for (const char* name : {"m.ply", "m.obj", "M.Obj"}) {
      const std::string path = dir.file(name);
      write_mesh(m, path);
      SCOPED_TRACE(std::string(name) + (normals ? " with normals" : ""));
      expect_identical(read_mesh(path), m);
    }
  }
  const TriMesh m = awkward_mesh(false);
  write_mesh(m, dir.file("m.off"));
  expect_identical(read_mesh(dir.file("m.off")), m);
}

TEST(MeshIo, PlyWriterWritesBinaryLittleEndianDoubles) {
  TempDir dir;
  write_mesh(awkward_mesh(true), dir.file("h.ply"));
  const std::string bytes = read_bytes(dir.file("h.ply"));
  const std::string header = bytes.substr(0, bytes.find("end_header\n") + 11);
  EXPECT_NE(header.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(header.find("element vertex 4\nproperty double x\nproperty double y\n"
                        "property double z\nproperty double nx\nproperty double ny\n"
                        "property double nz\nelement face 5\n"
                        "property list uchar uint vertex_indices\n"),
            std::string::npos)
      << header;
  EXPECT_EQ(bytes.size(), header.size() + 4 * 6 * 8 + 5 * (1 + 3 * 4));
}

TEST(MeshIo, EmptyMeshRoundTripsInPly) {
  TempDir dir;
  write_mesh(TriMesh{}, dir.file("e.ply"));
  const TriMesh r = read_mesh(dir.file("e.ply"));
  EXPECT_EQ(r.vertex_count(), 0U);
  EXPECT_EQ(r.triangle_count(), 0U);
}

TEST(MeshIo, WriteRejectsBadMeshesAndUnknownExtensionsWithoutOutput) {
  TempDir dir;
  TriMesh bad = awkward_mesh(false);
  bad.triangles.push_back({0, 1, 4});
  EXPECT_THROW(write_mesh(bad, dir.file("a.ply")), InvalidArgument);
  TriMesh normals = awkward_mesh(true);
  normals.normals.pop_back();
  EXPECT_THROW(write_mesh(normals, dir.file("b.obj")), InvalidArgument);
  TriMesh nan = awkward_mesh(false);
  nan.positions[2].y() = std::nan("");
  EXPECT_THROW(write_mesh(nan, dir.file("c.off")), InvalidArgument);
  EXPECT_THROW(write_mesh(awkward_mesh(false), dir.file("d.stl")), InvalidArgument);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(MeshObj, CornerFormsAndQuadsAreTriangulated) {
  const std::string text =
      "# two triangles and a quad\n"
      "mtllib x.mtl\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1 1.0\nv 1 0 1 0.5 0.5 0.5\n"
      "vt 0 0\nvt 1 0\nvt 1 1\n"
      "vn 0 0 1\nvn 0 0 -1\n"
      "g part\nusemtl m\ns off\n"
      "f 1/1/1 2/2/1 3/3/1\n"
      "f 1//2 3//2 4//2\n"
      "f 1/1 2/2 6/3 5/1\n";
  const TriMesh m = parse_mesh_obj(text, "q.obj");
  ASSERT_EQ(m.vertex_count(), 6U);
  EXPECT_EQ(m.positions[4], Vec3(0, 0, 1));
  EXPECT_EQ(m.positions[5], Vec3(1, 0, 1));
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {0, 1, 5}, {0, 5, 4}}));
  EXPECT_TRUE(m.normals.empty());  // 2 normals for 6 vertices are not per-vertex normals
}

TEST(MeshObj, NegativeIndicesAreRelative) {
  const TriMesh m =
      parse_mesh_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n", "neg.obj");
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{0, 1, 2}, {1, 3, 2}}));
}

TEST(MeshObj, ErrorsNameTheLine) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj(v3 + "f 1 2 4\n", "a.obj"), "a.obj", 4,
                        "vertex index 4 out of range");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj(v3 + "\nf 1 2\n", "b.obj"), "b.obj", 5,
                        "at least 3 vertices");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj(v3 + "f 1/1 2/1 3/1\n", "c.obj"), "c.obj", 4,
                        "texture coordinate index 1 out of range");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj(v3 + "vn 0 0 1\nf 1//1 2//2 3//1\n", "d.obj"), "d.obj", 5,
                        "normal index 2 out of range");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj("v 0 0 0\nv 1 0 x\n", "e.obj"), "e.obj", 2,
                        "expected a number, got 'x'");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj("v 0 0 0\nvn 1 0\n", "f.obj"), "f.obj", 2,
                        "'vn' needs 3 numbers");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj(v3 + "f 1 2 3/1/1/1\n", "g.obj"), "g.obj", 4,
                        "malformed OBJ corner");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj("v 0 0 0\nv 1e999 0 0\n", "h.obj"), "h.obj", 2,
                        "out of range");
  EXPECT_INPUT_ERROR_AT(parse_mesh_obj("\n\n", "i.obj"), "i.obj", 0, "empty");
}

TEST(MeshPly, SwcTypeLabelsRoundTripBesideNormalsAndUvs) {
  TempDir dir;
  TriMesh m = awkward_mesh(true);
  m.vertex_labels = {1, 3, -7, 2147483647};
  write_mesh(m, dir.file("l.ply"));
  const TriMesh back = read_mesh(dir.file("l.ply"));
  expect_identical(back, m);
  EXPECT_EQ(back.vertex_labels, m.vertex_labels);
  // with texture coordinates the label column follows u and v
  m.uvs = {Vec2(0, 0), Vec2(0.25, 1), Vec2(0.5, 0.5), Vec2(1, 0.125)};
  write_mesh(m, dir.file("uv.ply"));
  const TriMesh uv = read_mesh(dir.file("uv.ply"));
  EXPECT_EQ(uv.vertex_labels, m.vertex_labels);
  ASSERT_EQ(uv.uvs.size(), 4u);
  EXPECT_EQ(uv.uvs[3], Vec2(1, 0.125));
  // a label that is not a whole 32-bit number names the vertex
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float swc_type\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n"
      "0 0 0 1\n1 0 0 3\n0 1 0 2.5\n3 0 1 2\n";
  write_bytes(dir.file("bad.ply"), text);
  try {
    (void)read_mesh(dir.file("bad.ply"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("swc_type 2.5"), std::string::npos) << e.what();
  }
}

TEST(MeshPly, AsciiWithPolygonsExtraPropertiesAndNormals) {
  const std::string text =
      "ply\n"
      "format ascii 1.0\n"
      "element vertex 5\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "element face 2\n"
      "property uchar flags\n"
      "property list uchar int vertex_index\n"
      "property list int uint extra\n"
      "element material 1\n"
      "property float shininess\n"
      "end_header\n"
      "0 0 0 255 0 0 0 0 1\n"
      "1 0 0 255 0 0 0 0 1\n"
      "1 1 0 255 0 0 0 0 1\n"
      "0 1 0 255 0 0 0 0 1\n"
      "0.5 0.5 -1 255 0 0 0 0 -1\n"
      "7 4 0 1 2 3 2 9 9\n"
      "0 3 4 1 0 0\n"
      "0.5\n";
  const TriMesh m = parse_mesh_ply(text, "poly.ply");
  ASSERT_EQ(m.vertex_count(), 5U);
  EXPECT_EQ(m.positions[4], Vec3(0.5, 0.5, -1));
  ASSERT_EQ(m.normals.size(), 5U);
  EXPECT_EQ(m.normals[4], Vec3(0, 0, -1));
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {4, 1, 0}}));
}

std::string big_endian_mesh(bool truncate) {
  std::string b =
      "ply\nformat binary_big_endian 1.0\ncomment mixed types\n"
      "element vertex 4\nproperty float32 x\nproperty float64 y\nproperty int16 z\n"
      "property uint8 alpha\n"
      "element face 2\nproperty list uint16 int32 vertex_indices\nend_header\n";
  const float xs[] = {0.0f, 2.5f, 2.5f, 0.0f};
  const double ys[] = {0.0, 0.0, 1.0 / 3.0, 1.0 / 3.0};
  for (int i = 0; i < 4; ++i) {
    put<float>(b, xs[i], true);
    put<double>(b, ys[i], true);
    put<std::int16_t>(b, static_cast<std::int16_t>(-300 + i), true);
    put<std::uint8_t>(b, 200, true);
  }
  put<std::uint16_t>(b, 4, true);
  for (std::int32_t v : {3, 2, 1, 0}) put<std::int32_t>(b, v, true);
  put<std::uint16_t>(b, 3, true);
  put<std::int32_t>(b, 0, true);
  put<std::int32_t>(b, 1, true);
  if (!truncate) put<std::int32_t>(b, 3, true);
  return b;
}

TEST(MeshPly, BinaryBigEndianWithMixedTypes) {
  const TriMesh m = parse_mesh_ply(big_endian_mesh(false), "be.ply");
  ASSERT_EQ(m.vertex_count(), 4U);
  EXPECT_EQ(m.positions[2], Vec3(2.5, 1.0 / 3.0, -298));
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.triangles, (std::vector<Tri>{{3, 2, 1}, {3, 1, 0}, {0, 1, 3}}));
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply(big_endian_mesh(true), "cut.ply"), "cut.ply", 0, "face 1:");
}

TEST(MeshPly, FaceErrorsNameTheFace) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";  // faces at lines 13 and 14
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply(head + "3 0 1 2\n3 0 1 3\n", "range.ply"), "range.ply", 0,
                        "face 1: vertex index 3 out of range");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply(head + "3 0 1 2\n3 0 -1 2\n", "neg.ply"), "neg.ply", 0,
                        "face 1: vertex index -1");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply(head + "2 0 1\n3 0 1 2\n", "two.ply"), "two.ply", 0,
                        "face 0: has 2 vertices");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply(head + "3 0 1 2\n4 0 1 2\n", "count.ply"), "count.ply", 14,
                        "too few fields");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply(head + "3 0 1 2\n3 0 1 2.5\n", "float.ply"), "float.ply", 14,
                        "expected an integer");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply(head + "3 0 1 2\n300 0 1 2\n", "big.ply"), "big.ply", 14,
                        "does not fit type uchar");
}

TEST(MeshPly, HeaderErrors) {
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 0\n"
                                       "property list uchar float vertex_indices\nend_header\n",
                                       "ft.ply"),
                        "ft.ply", 7, "integer item type");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                       "property float y\nproperty float z\nelement face 0\n"
                                       "property list uchar int corners\nend_header\n",
                                       "nf.ply"),
                        "nf.ply", 7, "no 'vertex_indices'");
  EXPECT_INPUT_ERROR_AT(
      parse_mesh_ply("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                     "property float y\nproperty float z\nproperty float nx\nend_header\n",
                     "pn.ply"),
      "pn.ply", 3, "only some of the normal properties");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                       "property float z\nend_header\n",
                                       "ny.ply"),
                        "ny.ply", 3, "no property 'y'");
  EXPECT_INPUT_ERROR_AT(
      parse_mesh_ply("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int "
                     "vertex_indices\nend_header\n",
                     "nv.ply"),
      "nv.ply", 5, "no 'vertex' element");
  EXPECT_INPUT_ERROR_AT(parse_mesh_ply("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                                       "property float x\nend_header\n",
                                       "dup.ply"),
                        "dup.ply", 5, "duplicate property 'x'");
  EXPECT_INPUT_ERROR_AT(
      parse_mesh_ply("ply\nformat ascii 1.0\nproperty float x\nend_header\n", "early.ply"),
      "early.ply", 3, "before any 'element'");
  EXPECT_INPUT_ERROR_AT(
      parse_mesh_ply("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", "negc.ply"),
      "negc.ply", 3, "negative element count");
}

TEST(MeshOff, CountsOnTheHeaderLineOrTheNextAndComments) {
  const std::string next_line =
      "OFF\n# a square and a triangle\n5 2 0\n\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
      "2 2 2 # apex\n4 0 1 2 3\n3 4 0 1 255 0 0\n";
  const TriMesh a = parse_mesh_off(next_line, "a.off");
  ASSERT_EQ(a.vertex_count(), 5U);
  EXPECT_EQ(a.positions[4], Vec3(2, 2, 2));
  EXPECT_EQ(a.triangles, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {4, 0, 1}}));
  const TriMesh b = parse_mesh_off("OFF 3 1 3\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n", "b.off");
  EXPECT_EQ(b.triangles, (std::vector<Tri>{{0, 1, 2}}));
}

TEST(MeshOff, ErrorsNameTheLine) {
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("COFF\n3 1 0\n", "a.off"), "a.off", 1, "expected 'OFF'");
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("OFF\n3 x 0\n", "b.off"), "b.off", 2, "face count");
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("OFF\n3 1 0 0\n", "c.off"), "c.off", 2,
                        "vertex_count face_count");
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "d.off"),
                        "d.off", 4, "a vertex needs 3 numbers");
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "e.off"),
                        "e.off", 6, "vertex index 3 out of range");
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "f.off"),
                        "f.off", 6, "ends after 1 of 2 faces");
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "g.off"),
                        "g.off", 6, "needs 3 indices");
  EXPECT_INPUT_ERROR_AT(
      parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n\n3 0 1 2\n", "h.off"), "h.off", 8,
      "extra data");
  EXPECT_INPUT_ERROR_AT(parse_mesh_off("OFF\n3 1 0\n0 0 0\n1 0 NaN\n", "i.off"), "i.off", 4,
                        "not a finite number");
}

TEST(MeshIo, ReadErrorsCarryThePath) {
  TempDir dir;
  const std::string stl = dir.file("m.stl");
  write_bytes(stl, "solid x\n");
  EXPECT_INPUT_ERROR_AT(read_mesh(stl), stl, 0, ".ply, .obj, .off");
  const std::string obj = dir.file("bad.obj");
  write_bytes(obj, "v 0 0 0\nv 0 0 0\nf 1 2 3\n");
  EXPECT_INPUT_ERROR_AT(read_mesh(obj), obj, 3, "vertex index 3 out of range");
}

}  // namespace
}  // namespace ramiform

namespace ramiform {
namespace {

using io_test::TempDir;
using io_test::write_bytes;

Vec3 y_up(const Vec3& v) { return {v.x(), v.z(), -v.y()}; }

// A closed tetrahedron textured with one seam copy: vertex 4 is a copy of vertex 0.
TriMesh textured_tetrahedron() {
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 0, 0)};
  m.triangles = {{0, 2, 1}, {4, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  m.normals = {Vec3(-1, -1, -1).normalized(), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
               Vec3(-1, -1, -1).normalized()};
  m.uvs = {Vec2(0.1, 0.2), Vec2(0.3, 0.25), Vec2(0.7, 1.5), Vec2(0.9, -0.5), Vec2(1.1, 0.2)};
  for (std::size_t i = 0; i < 5; ++i) {
    const Vec3 t = m.normals[i].unitOrthogonal();
    m.tangents.emplace_back(t.x(), t.y(), t.z(), i % 2 == 0 ? 1.0 : -1.0);
  }
  m.welded = {0, 1, 2, 3, 0};
  return m;
}

// Decodes a .glb independently (tests/support/glb_reader.h) and compares with the mesh rotated
// to +Y up and rounded to float.
TEST(MeshGlb, ChunksAccessorsAndDataFollowTheGltfSpecification) {
  const TempDir dir;
  TriMesh huge = awkward_mesh(false);
  EXPECT_THROW(write_mesh(huge, dir.file("huge.glb")), InvalidArgument);  // -1e300 is no float
  EXPECT_FALSE(std::filesystem::exists(dir.file("huge.glb")));
  for (bool normals : {false, true}) {
    TriMesh m = awkward_mesh(normals);
    m.positions[2].x() = -1e30;
    write_mesh(m, dir.file("m.glb"));
    const test::Glb g = test::read_glb(dir.file("m.glb"));
    EXPECT_EQ(g.json["asset"]["version"], "2.0");
    EXPECT_FALSE(g.json.contains("extensionsUsed"));
    ASSERT_EQ(g.json["meshes"].size(), 1u);
    const auto& prim = g.json["meshes"][0]["primitives"][0];
    EXPECT_EQ(prim["mode"], 4);
    const int pa = g.attribute(0, "POSITION");
    const std::vector<float> pos = g.floats(pa);
    ASSERT_EQ(pos.size(), m.positions.size() * 3);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      const Vec3 up = y_up(m.positions[i]);
      for (int k = 0; k < 3; ++k) {
        const float f = pos[i * 3 + static_cast<std::size_t>(k)];
        EXPECT_EQ(f, static_cast<float>(up[k])) << "vertex " << i << " axis " << k;
        EXPECT_LE(g.json["accessors"][pa]["min"][k].get<float>(), f);
        EXPECT_GE(g.json["accessors"][pa]["max"][k].get<float>(), f);
      }
    }
    EXPECT_EQ(g.attribute(0, "NORMAL") >= 0, normals);
    if (normals) {
      const std::vector<float> nor = g.floats(g.attribute(0, "NORMAL"));
      for (std::size_t i = 0; i < m.normals.size(); ++i) {
        const Vec3 up = y_up(m.normals[i].normalized());
        for (int k = 0; k < 3; ++k) {
          EXPECT_EQ(nor[i * 3 + static_cast<std::size_t>(k)], static_cast<float>(up[k]));
        }
      }
    }
    EXPECT_EQ(g.attribute(0, "TEXCOORD_0"), -1);
    const std::vector<std::uint32_t> idx = g.uints(prim["indices"].get<int>());
    ASSERT_EQ(idx.size(), m.triangles.size() * 3);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(idx[t * 3 + c], m.triangles[t][c]);
    }
  }
}

// The +Z-up library tree stands along +Y in the file: its height is the file's y extent.
TEST(MeshGlb, TheLibrarysUpIsTheFilesPlusY) {
  const TempDir dir;
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.3, 10)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  write_mesh(m, dir.file("t.glb"));
  const test::Glb g = test::read_glb(dir.file("t.glb"));
  const auto& a = g.json["accessors"][g.attribute(0, "POSITION")];
  EXPECT_EQ(a["max"][1].get<float>(), 10.0f);
  EXPECT_EQ(a["min"][1].get<float>(), 0.0f);
  EXPECT_EQ(a["min"][2].get<float>(), -1.0f);  // library +y becomes -z
  EXPECT_EQ(a["max"][2].get<float>(), 0.0f);
}

TEST(MeshGlb, TexcoordsFlipVAndTangentsRotateWithTheirHandedness) {
  const TempDir dir;
  const TriMesh m = textured_tetrahedron();
  write_mesh(m, dir.file("t.glb"));
  const test::Glb g = test::read_glb(dir.file("t.glb"));
  const std::vector<float> uv = g.floats(g.attribute(0, "TEXCOORD_0"));
  const std::vector<float> tan = g.floats(g.attribute(0, "TANGENT"));
  ASSERT_EQ(uv.size(), 10u);
  ASSERT_EQ(tan.size(), 20u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(uv[2 * i], static_cast<float>(m.uvs[i].x()));
    EXPECT_EQ(uv[2 * i + 1], static_cast<float>(1.0 - m.uvs[i].y()));  // top-left origin
    const Vec3 t = y_up(m.tangents[i].head<3>());
    for (int k = 0; k < 3; ++k) EXPECT_EQ(tan[4 * i + static_cast<std::size_t>(k)], static_cast<float>(t[k]));
    EXPECT_EQ(tan[4 * i + 3], static_cast<float>(m.tangents[i].w()));
  }
  // The seam copy is its own vertex in glTF (one texture coordinate per vertex).
  EXPECT_EQ(g.json["accessors"][g.attribute(0, "POSITION")]["count"], 5);
  // Without normals there is no TANGENT (glTF requires NORMAL with it); without uvs neither.
  TriMesh bare = m;
  bare.normals.clear();
  bare.tangents.clear();
  write_mesh(bare, dir.file("b.glb"));
  const test::Glb b = test::read_glb(dir.file("b.glb"));
  EXPECT_GE(b.attribute(0, "TEXCOORD_0"), 0);
  EXPECT_EQ(b.attribute(0, "TANGENT"), -1);
  MeshWriteOptions no_uv;
  no_uv.uvs = false;
  write_mesh(m, dir.file("n.glb"), no_uv);
  const test::Glb n = test::read_glb(dir.file("n.glb"));
  EXPECT_EQ(n.attribute(0, "TEXCOORD_0"), -1);
  EXPECT_EQ(n.attribute(0, "TANGENT"), -1);
  EXPECT_GE(n.attribute(0, "NORMAL"), 0);
}

TEST(MeshGlb, LevelsOfDetailAreNodesOfOneFileInTheMsftLodConvention) {
  const TempDir dir;
  std::vector<TriMesh> levels = {textured_tetrahedron(), awkward_mesh(true), TriMesh{}};
  levels[1].positions[2].x() = 5;
  const std::vector<std::string> written = write_mesh_lods(levels, dir.file("l.glb"));
  EXPECT_EQ(written, std::vector<std::string>{dir.file("l.glb")});
  const test::Glb g = test::read_glb(dir.file("l.glb"));
  EXPECT_EQ(g.json["extensionsUsed"], nlohmann::json::array({"MSFT_lod"}));
  ASSERT_EQ(g.json["nodes"].size(), 3u);
  EXPECT_EQ(g.json["scenes"][0]["nodes"], nlohmann::json::array({0}));
  EXPECT_EQ(g.json["nodes"][0]["name"], "LOD0");
  EXPECT_EQ(g.json["nodes"][2]["name"], "LOD2");
  EXPECT_EQ(g.json["nodes"][0]["extensions"]["MSFT_lod"]["ids"], nlohmann::json::array({1, 2}));
  EXPECT_EQ(g.json["nodes"][0]["extras"]["MSFT_screencoverage"].size(), 3u);
  ASSERT_EQ(g.json["meshes"].size(), 2u);  // the empty level has a node but no mesh
  EXPECT_EQ(g.json["nodes"][1]["mesh"], 1);
  EXPECT_FALSE(g.json["nodes"][2].contains("mesh"));
  EXPECT_EQ(g.floats(g.attribute(1, "POSITION")).size(), levels[1].positions.size() * 3);
  EXPECT_THROW(write_mesh_lods({}, dir.file("e.glb")), InvalidArgument);
}

TEST(MeshIo, LevelsOfDetailInOtherFormatsAreOneFilePerLevel) {
  const TempDir dir;
  EXPECT_EQ(lod_paths("a/tree.ply", 1), std::vector<std::string>{"a/tree.ply"});
  EXPECT_EQ(lod_paths("a/tree.PLY", 2),
            (std::vector<std::string>{"a/tree.lod0.PLY", "a/tree.lod1.PLY"}));
  EXPECT_EQ(lod_paths("tree.glb", 3), std::vector<std::string>{"tree.glb"});
  const std::vector<TriMesh> levels = {awkward_mesh(true), awkward_mesh(false)};
  const auto written = write_mesh_lods(levels, dir.file("m.obj"));
  ASSERT_EQ(written.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) expect_identical(read_mesh(written[k]), levels[k]);
  // A bad level is found before anything is written.
  std::vector<TriMesh> bad = levels;
  bad[1].positions[0].x() = std::nan("");
  EXPECT_THROW(write_mesh_lods(bad, dir.file("b.ply")), InvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(dir.file("b.lod0.ply")));
}

TEST(MeshIo, UpAxisYRotatesPositionsAndNormalsOfPlyObjOff) {
  const TempDir dir;
  MeshWriteOptions o;
  o.up = UpAxis::kY;
  for (const char* name : {"m.ply", "m.obj", "m.off"}) {
    const TriMesh m = awkward_mesh(true);
    write_mesh(m, dir.file(name), o);
    const TriMesh r = read_mesh(dir.file(name));
    ASSERT_EQ(r.positions.size(), m.positions.size()) << name;
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      EXPECT_TRUE(same_bits(r.positions[i], y_up(m.positions[i]))) << name << " vertex " << i;
    }
    if (std::string(name) != "m.off") {
      ASSERT_EQ(r.normals.size(), m.normals.size()) << name;
      for (std::size_t i = 0; i < m.normals.size(); ++i) {
        EXPECT_TRUE(same_bits(r.normals[i], y_up(m.normals[i]))) << name << " normal " << i;
      }
    }
    EXPECT_EQ(r.triangles, m.triangles) << name;
  }
  MeshWriteOptions no_normals;
  no_normals.normals = false;
  write_mesh(awkward_mesh(true), dir.file("n.ply"), no_normals);
  EXPECT_TRUE(read_mesh(dir.file("n.ply")).normals.empty());
}

// OBJ writes each surface point once and the seam copies as `vt`s, so a closed textured mesh
// stays closed by its vertex indices; OFF writes the surface points only.
TEST(MeshIo, TexturedObjAndOffKeepTheSurfaceClosed) {
  const TempDir dir;
  const TriMesh m = textured_tetrahedron();
  EXPECT_TRUE(check_mesh(m).watertight);  // checked through the seam copy
  write_mesh(m, dir.file("t.obj"));
  std::ifstream in(dir.file("t.obj"));
  std::string line;
  int v = 0, vt = 0, vn = 0;
  std::vector<std::string> faces;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("vt ", 0) == 0) ++vt;
    if (line.rfind("vn ", 0) == 0) ++vn;
    if (line.rfind("f ", 0) == 0) faces.push_back(line);
  }
  EXPECT_EQ(v, 4);
  EXPECT_EQ(vn, 4);
  EXPECT_EQ(vt, 5);
  ASSERT_EQ(faces.size(), 4u);
  EXPECT_EQ(faces[1], "f 1/5/1 2/2/2 4/4/4");  // the copy: point 1, its own texture coordinate
  for (const char* name : {"t.obj", "t.off"}) {
    write_mesh(m, dir.file(name));
    const TriMesh r = read_mesh(dir.file(name));
    EXPECT_EQ(r.positions.size(), 4u) << name;
    EXPECT_TRUE(check_mesh(r).watertight) << name;
  }
}

TEST(MeshIo, TexturedPlyKeepsItsUvsAndWeldsItsSeamCopiesBack) {
  const TempDir dir;
  const TriMesh m = textured_tetrahedron();
  write_mesh(m, dir.file("t.ply"));
  const TriMesh r = read_mesh(dir.file("t.ply"));
  ASSERT_EQ(r.uvs.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(r.uvs[i], m.uvs[i]);
  EXPECT_EQ(r.welded, m.welded);
  const MeshReport rep = check_mesh(r);
  EXPECT_TRUE(rep.watertight && rep.oriented && rep.manifold);
  EXPECT_EQ(rep.components, 1u);
  // Without the seam information the copy is a hole: the check sees it.
  TriMesh open = r;
  open.welded.clear();
  EXPECT_FALSE(check_mesh(open).watertight);
  // s/t and texture_u/texture_v name texture coordinates too; half a pair is an error.
  const std::string st = dir.file("st.ply");
  write_bytes(st,
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nproperty float s\nproperty float t\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n"
              "0 1 0 0.5 1\n3 0 1 2\n");
  EXPECT_EQ(read_mesh(st).uvs.at(2), Vec2(0.5, 1));
  const std::string half = dir.file("half.ply");
  write_bytes(half,
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
              "property float z\nproperty float u\nend_header\n0 0 0 0\n");
  EXPECT_INPUT_ERROR_AT(read_mesh(half), half, 3, "'u' without 'v'");
}

TEST(MeshIo, WriteRejectsInconsistentAttributes) {
  const TempDir dir;
  TriMesh a = textured_tetrahedron();
  a.uvs.pop_back();
  EXPECT_THROW(write_mesh(a, dir.file("a.glb")), InvalidArgument);
  TriMesh b = textured_tetrahedron();
  b.uvs.clear();
  EXPECT_THROW(write_mesh(b, dir.file("b.ply")), InvalidArgument);  // tangents without uvs
  TriMesh c = textured_tetrahedron();
  c.welded[1] = 4;  // a copy of a later vertex
  EXPECT_THROW(write_mesh(c, dir.file("c.obj")), InvalidArgument);
  EXPECT_THROW((void)check_mesh(c), InvalidArgument);
  TriMesh d = textured_tetrahedron();
  d.tangents[0].w() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(write_mesh(d, dir.file("d.glb")), InvalidArgument);
  for (const char* f : {"a.glb", "b.ply", "c.obj", "d.glb"}) {
    EXPECT_FALSE(std::filesystem::exists(dir.file(f))) << f;
  }
}

}  // namespace
}  // namespace ramiform
