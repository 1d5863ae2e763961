// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The voxel grid helpers and the min-distance point grid, checked against brute force.
#include "sample/point_grid.h"

#include <gtest/gtest.h>

#include <set>
#include <tuple>
#include <vector>

#include "ramiform/core/random.h"
#include "sample/voxel_grid.h"

namespace ramiform::sample_detail {
namespace {

bool brute_has_near(const std::vector<Vec3>& pts, const Vec3& p, double r) {
  for (const auto& q : pts) {
    if ((q - p).squaredNorm() < r * r) return true;
  }
  return false;
}

Vec3 uniform_in(const Aabb& box, Rng& rng) {
  const Vec3 t(rng.uniform(), rng.uniform(), rng.uniform());
  return box.min() + box.sizes().cwiseProduct(t);
}

/// Inserts points into a grid as dart throwing does (only those with no near neighbour, plus
/// every tenth regardless) and compares every query with brute force. Queries and points range
/// beyond the grid's box, so points filed in the boundary cells are covered too.
void expect_matches_brute_force(const Aabb& box, double r, std::uint64_t seed, bool dense) {
  PointGrid grid(box, r);
  ASSERT_TRUE(grid.is_active());
  EXPECT_EQ(grid.is_dense(), dense);
  Aabb wide = box;
  wide.min() -= 0.3 * box.sizes();
  wide.max() += 0.3 * box.sizes();
  Rng rng(seed);
  std::vector<Vec3> pts;
  std::size_t near_count = 0;
  for (int k = 0; k < 6000; ++k) {
    // Every other query lies within 1.5 r of a stored point, so both answers occur.
    const Vec3 jitter(rng.uniform(-1.5 * r, 1.5 * r), rng.uniform(-1.5 * r, 1.5 * r),
                      rng.uniform(-1.5 * r, 1.5 * r));
    const Vec3 p = k % 2 == 1 && !pts.empty() ? Vec3(pts[rng.below(pts.size())] + jitter)
                                              : uniform_in(wide, rng);
    const bool expected = brute_has_near(pts, p, r);
    ASSERT_EQ(grid.has_near(p), expected) << "query " << k;
    near_count += expected ? 1 : 0;
    if (!expected || k % 10 == 0) {
      grid.add(p);
      pts.push_back(p);
    }
  }
  // Both answers were exercised.
  EXPECT_GT(near_count, 500U);
  EXPECT_LT(near_count, 5500U);
}

TEST(SamplePointGrid, DenseGridMatchesBruteForce) {
  expect_matches_brute_force(Aabb(Vec3(-1, -2, 0), Vec3(2, 1, 0.5)), 0.15, 1, true);
}

TEST(SamplePointGrid, SparseGridMatchesBruteForce) {
  // 2000^3 cells of edge 0.0005: past 2^24, so the cells are hashed.
  expect_matches_brute_force(Aabb(Vec3(0, 0, 0), Vec3(1, 1, 1)), 0.0005, 2, false);
}

TEST(SamplePointGrid, DistanceExactlyTheRadiusIsNotNear) {
  PointGrid grid(Aabb(Vec3(0, 0, 0), Vec3(4, 4, 4)), 0.5);
  grid.add(Vec3(1, 1, 1));
  EXPECT_FALSE(grid.has_near(Vec3(1.5, 1, 1)));
  EXPECT_TRUE(grid.has_near(Vec3(1.4999, 1, 1)));
  EXPECT_TRUE(grid.has_near(Vec3(1, 1, 1)));
}

TEST(SamplePointGrid, ZeroRadiusOrEmptyBoxIsInactive) {
  PointGrid none(Aabb(Vec3(0, 0, 0), Vec3(1, 1, 1)), 0.0);
  EXPECT_FALSE(none.is_active());
  none.add(Vec3(0.5, 0.5, 0.5));
  EXPECT_FALSE(none.has_near(Vec3(0.5, 0.5, 0.5)));
  PointGrid empty(Aabb(), 0.1);
  EXPECT_FALSE(empty.is_active());
}

TEST(SampleVoxelGrid, CoversTheBoxWithTheFewestCells) {
  const Aabb box(Vec3(0, 0, 0), Vec3(1, 0.25, 0.3));
  const VoxelGrid grid(box, 0.1);
  EXPECT_EQ(grid.n[0], 10);  // an exact multiple gains no cell
  EXPECT_EQ(grid.n[1], 3);
  EXPECT_EQ(grid.n[2], 3);
  EXPECT_EQ(grid.size(), 90U);
  EXPECT_EQ(grid.coord(-5.0, 0), 0);  // clamped
  EXPECT_EQ(grid.coord(5.0, 0), 9);
  EXPECT_EQ(grid.coord(0.55, 0), 5);
  EXPECT_EQ(grid.index(1, 2, 1), 1U + 10U * (2U + 3U * 1U));
}

TEST(SampleVoxelGrid, OctantsPartitionTheBox) {
  Rng rng(4);
  for (int k = 0; k < 200; ++k) {
    IndexBox b{};
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = static_cast<std::int64_t>(rng.below(5));
      b.hi[a] = b.lo[a] + 1 + static_cast<std::int64_t>(rng.below(6));
    }
    std::set<std::tuple<std::int64_t, std::int64_t, std::int64_t>> seen;
    std::size_t cells = 0;
    const auto children = octants(b);
    ASSERT_LE(children.size(), 8U);
    for (const auto& c : children) {
      for_each_voxel(c, [&](std::int64_t i, std::int64_t j, std::int64_t kk) {
        ASSERT_TRUE(i >= b.lo[0] && i < b.hi[0] && j >= b.lo[1] && j < b.hi[1] && kk >= b.lo[2] &&
                    kk < b.hi[2]);
        seen.emplace(i, j, kk);
        ++cells;
      });
    }
    const auto volume =
        static_cast<std::size_t>((b.hi[0] - b.lo[0]) * (b.hi[1] - b.lo[1]) * (b.hi[2] - b.lo[2]));
    EXPECT_EQ(cells, volume);        // no voxel twice
    EXPECT_EQ(seen.size(), volume);  // every voxel once
  }
}

TEST(SampleVoxelGrid, NeighbourhoodIsCutToTheGrid) {
  const VoxelGrid grid(Aabb(Vec3(0, 0, 0), Vec3(1, 1, 1)), 0.25);  // 4 x 4 x 4
  const IndexBox corner = neighbourhood(grid, 0, 0, 3, 1);
  EXPECT_EQ(corner.lo, (std::array<std::int64_t, 3>{0, 0, 2}));
  EXPECT_EQ(corner.hi, (std::array<std::int64_t, 3>{2, 2, 4}));
  const IndexBox wide = neighbourhood(grid, 1, 2, 1, 10);
  EXPECT_EQ(wide.lo, (std::array<std::int64_t, 3>{0, 0, 0}));
  EXPECT_EQ(wide.hi, (std::array<std::int64_t, 3>{4, 4, 4}));
}

}  // namespace
}  // namespace ramiform::sample_detail
