// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/points_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using io_test::put;
using io_test::TempDir;
using io_test::write_bytes;

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), 24) == 0; }

PointSet awkward_points(bool normals) {
  PointSet p;
  // 1e150: as large as a coordinate can be here while the set's span stays readable (see
  // PointsIo.ExtremeCoordinatesRoundTripWhileTheSpanFits for larger ones).
  p.positions = {Vec3(0.1, -0.0, 1e-320), Vec3(1.0 / 3.0, 1e150, -2.0), Vec3(M_PI, 1, 2)};
  if (normals) p.normals = {Vec3(1, 0, 0), Vec3(0.6, -0.8, 0), Vec3(1, 1, 1).normalized()};
  return p;
}

void expect_identical(const PointSet& a, const PointSet& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.normals.size(), b.normals.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(same_bits(a.positions[i], b.positions[i])) << "point " << i;
    if (a.has_normals()) {
      EXPECT_TRUE(same_bits(a.normals[i], b.normals[i])) << "normal " << i;
    }
  }
}

TEST(PointsIo, RoundTripsAreBitExact) {
  TempDir dir;
  for (const bool normals : {false, true}) {
    for (const char* name : {"p.xyz", "p.txt", "p.ply", "P.PLY", "p"}) {
      SCOPED_TRACE(std::string(name) + (normals ? " with normals" : ""));
      const PointSet p = awkward_points(normals);
      write_points(p, dir.file(name));
      expect_identical(read_points(dir.file(name)), p);
    }
  }
}

TEST(PointsIo, ExtremeCoordinatesRoundTripWhileTheSpanFits) {
  // Huge coordinates are fine; only a span whose length overflows is refused (see below).
  TempDir dir;
  PointSet p;
  p.positions = {Vec3(-std::numeric_limits<double>::max(), 1e300, 5e-324),
                 Vec3(-std::numeric_limits<double>::max(), 1e300, 1.0)};
  for (const char* name : {"x.xyz", "x.ply"}) {
    SCOPED_TRACE(name);
    write_points(p, dir.file(name));
    expect_identical(read_points(dir.file(name)), p);
  }
}

TEST(PointsIo, WriteRejectsBadPointSetsWithoutOutput) {
  TempDir dir;
  PointSet p = awkward_points(true);
  p.normals.pop_back();
  EXPECT_THROW(write_points(p, dir.file("a.xyz")), InvalidArgument);
  PointSet q = awkward_points(false);
  q.positions[1].x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(write_points(q, dir.file("b.ply")), InvalidArgument);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(PointsText, SeparatorsCommentsAndLineEndings) {
  const std::string text =
      "# x y z nx ny nz\r\n"
      "1 2 3 0 0 1\r\n"
      "\t4\t5\t6\t1\t0\t0  \r\n"
      "\r\n"
      "7,8,9,0,1,0\n"
      "+1.5e1 , -2 ,3.25, 0 ,0, -1   # trailing comment\n"
      "1e-400 0 0 0 0 1";  // no final newline; underflow reads as zero
  const PointSet p = parse_points_text(text, "mixed.txt");
  ASSERT_EQ(p.size(), 5U);
  ASSERT_TRUE(p.has_normals());
  EXPECT_EQ(p.positions[1], Vec3(4, 5, 6));
  EXPECT_EQ(p.positions[3], Vec3(15, -2, 3.25));
  EXPECT_EQ(p.normals[3], Vec3(0, 0, -1));
  EXPECT_EQ(p.positions[4], Vec3(0, 0, 0));
}

TEST(PointsText, ErrorsNameTheLine) {
  EXPECT_INPUT_ERROR_AT(parse_points_text("1 2 3\n4 5 6\n\n7 8 9 0 0 1\n", "mix.xyz"), "mix.xyz", 4,
                        "expected 3 numbers like line 1, got 6");
  EXPECT_INPUT_ERROR_AT(parse_points_text("# header\n1 2 3 4\n", "four.xyz"), "four.xyz", 2,
                        "got 4 fields");
  EXPECT_INPUT_ERROR_AT(parse_points_text("1 2 3\n4 nan 6\n", "nan.xyz"), "nan.xyz", 2,
                        "y: 'nan' is not a finite number");
  EXPECT_INPUT_ERROR_AT(parse_points_text("1 2 3\n4 5 6\n7 8 -inf\n", "inf.xyz"), "inf.xyz", 3,
                        "not a finite number");
  EXPECT_INPUT_ERROR_AT(parse_points_text("1 2 3\n4 5 6;\n", "junk.xyz"), "junk.xyz", 2,
                        "expected a number, got '6;'");
  EXPECT_INPUT_ERROR_AT(parse_points_text("1,2,3\n4,,6\n", "comma.csv"), "comma.csv", 2,
                        "empty field");
  EXPECT_INPUT_ERROR_AT(parse_points_text("1,2,3,\n", "tail.csv"), "tail.csv", 1, "empty field");
  EXPECT_INPUT_ERROR_AT(parse_points_text("1 2 0x10\n", "hex.xyz"), "hex.xyz", 1,
                        "expected a number");
  EXPECT_INPUT_ERROR_AT(parse_points_text("", "empty.xyz"), "empty.xyz", 0, "empty");
  EXPECT_INPUT_ERROR_AT(parse_points_text("# only a comment\n", "none.xyz"), "none.xyz", 0,
                        "no points");
}

TEST(PointsText, SpansThatOverflowAreRefusedAtTheFirstOffendingLine) {
  // max - min of +-1e308 is inf: fields then compute inf and NaN (eval printed -nan). The rule is
  // the skeleton reader's: the bounding box's diagonal length must be finite.
  EXPECT_INPUT_ERROR_AT(parse_points_text("0 0 0\n1 2 3\n-1e308 0 0\n1e308 5 5\n", "wide.xyz"),
                        "wide.xyz", 3,
                        "span more than double precision can hold (from -1e+308 to 3)");
  EXPECT_INPUT_ERROR_AT(parse_points_text("# a\n1 1 -1e308 0 0 1\n\n1 1 1e308 0 0 1\n", "n.pwn"),
                        "n.pwn", 4, "(from -1e+308 to 1e+308)");
  // Each coordinate is small enough, the diagonal's length is not.
  EXPECT_INPUT_ERROR_AT(parse_points_text("1e200,0,0\n0,1e200,0\n", "diag.csv"), "diag.csv", 2,
                        "span more than double precision");
  // Just inside the rule.
  EXPECT_EQ(parse_points_text("1e150 0 0\n-1e150 0 0\n", "ok.xyz").size(), 2U);
}

TEST(PointsPly, NoVerticesIsNoPoints) {
  // Refused as the text reader refuses a file without point lines, at the 'element' line.
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    SCOPED_TRACE(format);
    const std::string ply = std::string("ply\nformat ") + format +
                            " 1.0\ncomment nothing\nelement vertex 0\nproperty float x\n"
                            "property float y\nproperty float z\nend_header\n";
    EXPECT_INPUT_ERROR_AT(parse_points_ply(ply, "none.ply"), "none.ply", 4, "no points");
  }
  // With another element that has data: still no points.
  const std::string with_other =
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\nproperty double y\n"
      "property double z\nproperty double nx\nproperty double ny\nproperty double nz\n"
      "element note 1\nproperty int id\nend_header\n7\n";
  EXPECT_INPUT_ERROR_AT(parse_points_ply(with_other, "faces.ply"), "faces.ply", 3, "no points");
  TempDir dir;
  const std::string path = dir.file("EMPTY.PLY");
  write_bytes(path,
              "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
              "property float y\nproperty float z\nend_header\n");
  EXPECT_INPUT_ERROR_AT(read_points(path), path, 3, "no points");
}

TEST(PointsPly, SpansThatOverflowAreRefusedAtTheFirstOffendingVertex) {
  std::string le =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n";
  for (const double z : {0.0, 1.0, -1e308}) {
    put<double>(le, 1.0, false);
    put<double>(le, 2.0, false);
    put<double>(le, z, false);
  }
  EXPECT_INPUT_ERROR_AT(
      parse_points_ply(le, "wide.ply"), "wide.ply", 0,
      "vertex 2: with this point the coordinates span more than double precision");
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property double z\nend_header\n0 0 -1.7e308\n0 0 1.7e308\n";
  EXPECT_INPUT_ERROR_AT(parse_points_ply(ascii, "wide_ascii.ply"), "wide_ascii.ply", 0,
                        "vertex 1: with this point");
}

TEST(PointsPly, AsciiAndBigEndianWithExtraProperties) {
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty double nx\nproperty float x\n"
      "property float y\nproperty float z\nproperty float ny\nproperty float nz\n"
      "property float intensity\nelement face 0\nproperty list uchar int vertex_indices\n"
      "end_header\n1 0.5 1.5 2.5 0 0 17\n0 -1 -2 -3 1 0 3\n";
  const PointSet a = parse_points_ply(ascii, "pts.ply");
  ASSERT_EQ(a.size(), 2U);
  EXPECT_EQ(a.positions[1], Vec3(-1, -2, -3));
  EXPECT_EQ(a.normals[0], Vec3(1, 0, 0));
  EXPECT_EQ(a.normals[1], Vec3(0, 1, 0));

  std::string be =
      "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty int x\nproperty short y\n"
      "property double z\nproperty uchar confidence\nend_header\n";
  for (int i = 0; i < 2; ++i) {
    put<std::int32_t>(be, -100000 * (i + 1), true);
    put<std::int16_t>(be, static_cast<std::int16_t>(7 * i), true);
    put<double>(be, 0.1 * i, true);
    put<std::uint8_t>(be, 9, true);
  }
  const PointSet b = parse_points_ply(be, "be.ply");
  ASSERT_EQ(b.size(), 2U);
  EXPECT_FALSE(b.has_normals());
  EXPECT_EQ(b.positions[1], Vec3(-200000, 7, 0.1));
  EXPECT_INPUT_ERROR_AT(parse_points_ply(be.substr(0, be.size() - 3), "cut.ply"), "cut.ply", 0,
                        "vertex 1:");
}

TEST(PointsIo, ReadErrorsCarryThePath) {
  TempDir dir;
  const std::string path = dir.file("cloud.txt");
  write_bytes(path, "1 2 3\n4 5 6\n7 8\n");
  EXPECT_INPUT_ERROR_AT(read_points(path), path, 3, "got 2 fields");
}

}  // namespace
}  // namespace ramiform
