// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/curve_io.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// Runs fn, expects InputError at `line` whose problem contains `needle`.
template <class Fn>
void expect_input_error(Fn fn, std::size_t line, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(CurveReadPoints, GoodFiles) {
  io_test::TempDir dir;
  const std::string f2 = dir.file("profile.txt");
  write_file(f2, "# a profile\n\n1 0\n  1.5\t0.25  # comment\r\n2e0 1\n\n");
  const auto p2 = read_points2(f2);
  ASSERT_EQ(p2.size(), 3U);
  EXPECT_EQ(p2[1], Vec2(1.5, 0.25));
  EXPECT_EQ(p2[2], Vec2(2, 1));
  const std::string f3 = dir.file("path.txt");
  write_file(f3, "0 0 0\n# mid\n0 0.5 1\n-1 2 3.25");
  const auto p3 = read_points3(f3);
  ASSERT_EQ(p3.size(), 3U);
  EXPECT_EQ(p3[2], Vec3(-1, 2, 3.25));
  // Single commas separate fields as in point files.
  write_file(f3, "0, 0, 0\n1,2 , 3\n");
  const auto pc = read_points3(f3);
  ASSERT_EQ(pc.size(), 2U);
  EXPECT_EQ(pc[1], Vec3(1, 2, 3));
}

TEST(CurveReadPoints, BadLinesNameTheLine) {
  io_test::TempDir dir;
  const std::string f = dir.file("bad.txt");
  write_file(f, "1 2\n# c\n3 4 5\n");
  expect_input_error([&] { (void)read_points2(f); }, 3, "expected 2 numbers");
  write_file(f, "1 2 3\n\n4 5\n");
  expect_input_error([&] { (void)read_points3(f); }, 3, "expected 3 numbers");
  write_file(f, "1 2\n1 abc\n");
  expect_input_error([&] { (void)read_points2(f); }, 2, "expected a number");
  write_file(f, "1 2\n3 4\n\n1 nan\n");
  expect_input_error([&] { (void)read_points2(f); }, 4, "not a finite number");
  write_file(f, "inf 0 0\n");
  expect_input_error([&] { (void)read_points3(f); }, 1, "not a finite number");
  write_file(f, "1,2\n3,,4\n");
  expect_input_error([&] { (void)read_points2(f); }, 2, "empty field between commas");
  write_file(f, "# nothing\n\n");
  expect_input_error([&] { (void)read_points2(f); }, 0, "no points");
  EXPECT_THROW((void)read_points2(dir.file("missing.txt")), InputError);
}

}  // namespace
}  // namespace ramiform
