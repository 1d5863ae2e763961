// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Reads the real models and point clouds in ../shared/data (outside the repository); skipped
// when that directory is absent. Expected counts come from the files' headers and NOTICE.md.
#include <gtest/gtest.h>

#include <filesystem>

#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"

namespace ramiform {
namespace {

namespace fs = std::filesystem;

std::string shared_file(const std::string& relative) {
  return (fs::path(RAMIFORM_SOURCE_DIR) / ".." / "shared" / "data" / relative).string();
}

#define REQUIRE_SHARED(path)                                                                   \
  if (!fs::exists(path)) {                                                                     \
    GTEST_SKIP() << "../shared/data is not present (no " << (path) << "); skipping real-data " \
                 << "check";                                                                   \
  }

TEST(SharedData, BunnyPly) {
  const std::string path = shared_file("models/bunny.ply");
  REQUIRE_SHARED(path);
  const TriMesh m = read_mesh(path);
  EXPECT_EQ(m.vertex_count(), 1839U);    // "element vertex 1839"
  EXPECT_EQ(m.triangle_count(), 3674U);  // "element face 3674", all triangles
  EXPECT_TRUE(m.normals.empty());
  EXPECT_EQ(m.positions[0], Vec3(1.301895, 0.122622, 2.550061));  // first body line
}

TEST(SharedData, CowOff) {
  const std::string path = shared_file("models/cow.off");
  REQUIRE_SHARED(path);
  const TriMesh m = read_mesh(path);
  EXPECT_EQ(m.vertex_count(), 2904U);  // "2904 5804 0"
  EXPECT_EQ(m.triangle_count(), 5804U);
  EXPECT_EQ(m.positions[0], Vec3(0.281526, 0.266379, -1.55991e-008));
  EXPECT_EQ(m.triangles.back(), (std::array<std::uint32_t, 3>{961, 970, 966}));
}

TEST(SharedData, TreePointClouds) {
  const std::string rtwig = shared_file("trees/rtwig_cloud.txt");
  REQUIRE_SHARED(rtwig);
  const PointSet a = read_points(rtwig);
  EXPECT_EQ(a.size(), 14667U);
  EXPECT_FALSE(a.has_normals());
  EXPECT_EQ(a.positions[0], Vec3(0.73229748, -16.39104271, 253.89553833));

  // CRLF line ends, a trailing blank on every line and no newline after the last point.
  const PointSet b = read_points(shared_file("trees/adtree_tree1.xyz"));
  EXPECT_EQ(b.size(), 11855U);
  EXPECT_EQ(b.positions[0], Vec3(0.132, 18.645, 3.971));
  EXPECT_EQ(b.positions.back(), Vec3(-2.355, 17.254, 3.132));
}

TEST(SharedData, OrientedPointClouds) {
  const std::string kitten = shared_file("models/kitten.xyz");
  REQUIRE_SHARED(kitten);
  const PointSet k = read_points(kitten);
  EXPECT_EQ(k.size(), 5210U);
  EXPECT_TRUE(k.has_normals());
  const PointSet o = read_points(shared_file("models/oni.pwn"));
  EXPECT_EQ(o.size(), 1435U);
  EXPECT_TRUE(o.has_normals());
}

}  // namespace
}  // namespace ramiform
