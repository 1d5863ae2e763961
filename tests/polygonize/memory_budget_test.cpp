// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The memory budget (core/memory.h) in the operations whose memory grows with their options:
// the tetrahedral polygonizer's levels, the marching-cubes grid and mesh, and point counts. Each
// refuses a run above Context::max_memory with ResourceLimit and its estimate, and the same run
// within the budget gives the same result as without one.

#include <gtest/gtest.h>

#include <string>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/polygonize/marching_cubes.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/sample/point_sets.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// A Context whose budget is `bytes`.
struct Budget : Context {
  explicit Budget(std::uint64_t bytes) { set_max_memory(bytes); }
};

TEST(MemoryBudgetUse, TetrahedralLevelsAboveTheBudgetAreRefused) {
  const Skeleton s = test::y_fork();
  const FieldPtr field = make_skeleton_field(s, {});
  TetrahedralOptions o;
  o.levels = 3;
  Budget tight(1000000);
  try {
    (void)polygonize_tetrahedral(*field, s, o, &tight);
    ADD_FAILURE() << "levels 3 within 1 MB";
  } catch (const ResourceLimit& e) {
    EXPECT_TRUE(contains(e.what(), "tetrahedral polygonizer: ")) << e.what();
    EXPECT_TRUE(contains(e.what(), " bounding points at --levels 3 need at least ")) << e.what();
    EXPECT_TRUE(contains(e.what(), "more than the budget of 1 MB")) << e.what();
    EXPECT_GT(e.needed(), 1e6);
  }
  // With room, the budget changes nothing.
  Budget roomy(std::uint64_t{4} << 30);
  const TriMesh a = polygonize_tetrahedral(*field, s, o, &roomy);
  const TriMesh b = polygonize_tetrahedral(*field, s, o);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
}

TEST(MemoryBudgetUse, MarchingCubesRefusesAGridAndAMeshAboveTheBudget) {
  const Skeleton s = test::y_fork();
  const FieldPtr field = make_skeleton_field(s, {});
  MarchingCubesOptions o;
  o.resolution = 200;
  const TriMesh full = marching_cubes(*field, o);
  ASSERT_GT(full.positions.size(), 10000U);
  // The grid alone does not fit in 1 kB.
  Budget tiny(1000);
  try {
    (void)marching_cubes(*field, o, &tiny);
    ADD_FAILURE() << "a 200^3 grid within 1 kB";
  } catch (const ResourceLimit& e) {
    EXPECT_TRUE(contains(e.what(), "marching_cubes: a grid of ")) << e.what();
  }
  // The grid fits in a quarter of the mesh's size; the growing mesh does not.
  const auto quarter = static_cast<std::uint64_t>(12.0 * double(full.positions.size()));
  Budget part(quarter);
  try {
    (void)marching_cubes(*field, o, &part);
    ADD_FAILURE() << "the mesh within a quarter of its size";
  } catch (const ResourceLimit& e) {
    EXPECT_TRUE(contains(e.what(), "marching_cubes: the mesh of ")) << e.what();
    EXPECT_TRUE(contains(e.what(), "vertices so far need at least")) << e.what();
  }
  Budget roomy(std::uint64_t{4} << 30);
  const TriMesh again = marching_cubes(*field, o, &roomy);
  EXPECT_EQ(again.positions, full.positions);
  EXPECT_EQ(again.triangles, full.triangles);
}

TEST(MemoryBudgetUse, PointCountsAboveTheBudgetAreRefused) {
  const FieldPtr field = make_skeleton_field(test::y_fork(), {});
  Budget tight(1000000);
  UniformOptions u;
  u.count = 1000000;
  try {
    (void)sample_uniform(*field, u, 1, &tight);
    ADD_FAILURE() << "a million points within 1 MB";
  } catch (const ResourceLimit& e) {
    EXPECT_EQ(std::string(e.what()),
              "sample_uniform: 1000000 points need at least 64 MB of memory, more than the "
              "budget of 1 MB (the max_memory set for this run); ask for fewer points");
  }
  NearSurfaceOptions n;
  n.count = 1000000;
  EXPECT_THROW((void)sample_near_surface(*field, n, 1, &tight), ResourceLimit);
  StratifiedOptions st;
  st.count = 1000000;
  EXPECT_THROW((void)sample_stratified(*field, st, 1, &tight), ResourceLimit);
  // Within the budget the points are those of an unbounded run.
  u.count = 200;
  EXPECT_EQ(sample_uniform(*field, u, 1, &tight).positions, sample_uniform(*field, u, 1).positions);
}

}  // namespace
}  // namespace ramiform
