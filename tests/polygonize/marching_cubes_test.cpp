// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/marching_cubes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "polygonize/analytic_fields.h"
#include "ramiform/core/errors.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/winding.h"
#include "support/mesh_checkers.h"

namespace ramiform {
namespace {

using test::BlobField;
using test::MaxField;
using test::QuadraticSphereField;
using test::SphereField;
using test::TorusField;

constexpr double kPi = std::numbers::pi;

void expect_same_mesh(const TriMesh& a, const TriMesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    ASSERT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;  // bitwise equal doubles
  }
  for (std::size_t i = 0; i < a.triangles.size(); ++i) {
    ASSERT_EQ(a.triangles[i], b.triangles[i]) << "triangle " << i;
  }
}

FieldPtr random_blobs(std::uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-2.0, 2.0);
  std::uniform_real_distribution<double> size(0.3, 0.9);
  std::vector<BlobField::Blob> blobs;
  for (int i = 0; i < count; ++i) blobs.push_back({Vec3(pos(rng), pos(rng), pos(rng)), size(rng)});
  return std::make_shared<BlobField>(std::move(blobs));
}

TEST(MarchingCubes, SphereIsClosedAndVerticesLieOnIt) {
  const Vec3 c(0.1, 0.2, -0.05);
  const double r = 1.0;
  const auto field = std::make_shared<SphereField>(c, r);
  MarchingCubesOptions o;
  o.resolution = 40;
  MarchingCubesStats stats;
  const TriMesh m = marching_cubes(*field, o, nullptr, &stats);
  ASSERT_GT(m.triangles.size(), 1000u);
  test::expect_closed_surface(m, 1, 2);
  for (const Vec3& p : m.positions) ASSERT_LT(std::abs((p - c).norm() - r), 1e-6 * r);
  // The mesh is inscribed: slightly smaller than the ball, by O(h^2).
  const double ball = 4.0 / 3.0 * kPi * r * r * r;
  const double v = signed_volume(m);
  EXPECT_LT(v, ball);
  EXPECT_GT(v, ball * (1.0 - 0.01));
  EXPECT_EQ(stats.crossing_edges, static_cast<std::int64_t>(m.positions.size()));
  EXPECT_EQ(stats.cells_total, stats.grid_cells[0] * stats.grid_cells[1] * stats.grid_cells[2]);
  EXPECT_EQ(stats.cells_total, stats.cells_visited + stats.cells_skipped);
  EXPECT_EQ(stats.sign_overrides, 0);
  EXPECT_EQ(stats.bound_conflicts, 0);
  // 40 cells over the sphere's diameter, plus one padding cell on each side.
  EXPECT_EQ(stats.grid_cells[0], 42);
  EXPECT_NEAR(stats.cell_size, 2.0 * r / 40.0, 1e-15);
}

TEST(MarchingCubes, RootFindingPlacesVerticesOnANonlinearField) {
  const Vec3 c(-0.3, 0.1, 0.25);
  const auto field = std::make_shared<QuadraticSphereField>(c, 2.0);
  MarchingCubesOptions o;
  o.resolution = 24;
  const TriMesh m = marching_cubes(*field, o);
  test::expect_closed_surface(m, 1, 2);
  for (const Vec3& p : m.positions) ASSERT_LT(std::abs((p - c).norm() - 2.0), 1e-6 * 2.0);

  // Linear interpolation alone is visibly off on this field.
  o.root_steps = 0;
  const TriMesh lin = marching_cubes(*field, o);
  EXPECT_EQ(lin.triangles, m.triangles);  // same topology
  double worst = 0.0;
  for (const Vec3& p : lin.positions) worst = std::max(worst, std::abs((p - c).norm() - 2.0));
  EXPECT_GT(worst, 1e-4);
}

TEST(MarchingCubes, UsesTheFieldsIsoValue) {
  // Surface radius r - iso = 0.7.
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.0, 0.3);
  MarchingCubesOptions o;
  o.resolution = 30;
  const TriMesh m = marching_cubes(*field, o);
  test::expect_closed_surface(m, 1, 2);
  for (const Vec3& p : m.positions) ASSERT_NEAR(p.norm(), 0.7, 1e-6);
  EXPECT_GT(signed_volume(m), 0.0);  // f > iso is inside: normals point outward
}

TEST(MarchingCubes, TorusHasEulerZero) {
  const auto field = std::make_shared<TorusField>(Vec3(0.05, -0.1, 0.0), 1.5, 0.5);
  MarchingCubesOptions o;
  o.resolution = 48;
  const TriMesh m = marching_cubes(*field, o);
  test::expect_closed_surface(m, 1, 0);
  const double torus_volume = 2.0 * kPi * kPi * 1.5 * 0.25;
  EXPECT_NEAR(signed_volume(m) / torus_volume, 1.0, 0.02);
}

TEST(MarchingCubes, TwoSpheresAreTwoComponents) {
  const auto field = std::make_shared<MaxField>(
      std::vector<FieldPtr>{std::make_shared<SphereField>(Vec3(-1.5, 0, 0), 1.0),
                            std::make_shared<SphereField>(Vec3(1.6, 0.2, 0), 0.8)});
  MarchingCubesOptions o;
  o.cell_size = 0.08;
  const TriMesh m = marching_cubes(*field, o);
  test::expect_closed_surface(m, 2, 4);
}

TEST(MarchingCubes, SurfaceThroughGridPointsStaysClosed) {
  // Grid points hit the sphere exactly (e.g. (0.75, 1, 0) on radius 1.25, all exact in binary),
  // where f == iso counts as outside; two crossing edges then end at the same point.
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.25);
  MarchingCubesOptions o;
  o.cell_size = 0.25;
  o.box = Aabb(Vec3::Constant(-1.5), Vec3::Constant(1.5));
  const TriMesh m = marching_cubes(*field, o);
  test::expect_closed_surface(m, 1, 2);
  const MeshReport r = check_mesh(m);
  EXPECT_GT(r.zero_area_triangles, 0u);  // kept on purpose: dropping them would open the mesh
}

TEST(MarchingCubes, BlobsAreClosedManifoldsForManySeeds) {
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const FieldPtr field = random_blobs(seed, 8);
    MarchingCubesOptions o;
    o.resolution = 40;
    o.block_cells = 4 + static_cast<int>(seed % 5);  // many block boundaries, odd sizes
    MarchingCubesStats stats;
    const TriMesh m = marching_cubes(*field, o, nullptr, &stats);
    test::expect_closed_manifold(m);
    EXPECT_GT(signed_volume(m), 0.0);
    EXPECT_EQ(stats.sign_overrides, 0);
    // Every component is a closed surface, and the mesh's inside agrees with the field's.
    const WindingNumber wn(m);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    int agree = 0;
    int total = 0;
    for (int i = 0; i < 300; ++i) {
      const Vec3 p(u(rng), u(rng), u(rng));
      const double f = field->value(p);
      if (std::abs(f - field->iso()) < 0.05) continue;  // too close to the surface
      ++total;
      agree += (wn(p) > 0.5) == (f > field->iso()) ? 1 : 0;
    }
    EXPECT_EQ(agree, total);
  }
}

TEST(MarchingCubes, OutputDoesNotDependOnThreadCount) {
  const FieldPtr field = random_blobs(7, 10);
  MarchingCubesOptions o;
  o.resolution = 64;
  o.block_cells = 8;
  Context one(1);
  Context two(2);
  Context all(0);
  const TriMesh a = marching_cubes(*field, o, &one);
  const TriMesh b = marching_cubes(*field, o, &two);
  const TriMesh c = marching_cubes(*field, o, &all);
  ASSERT_GT(a.triangles.size(), 1000u);
  expect_same_mesh(a, b);
  expect_same_mesh(a, c);
}

TEST(MarchingCubes, BlockSizeDoesNotChangeTheSurface) {
  // Vertex order follows the blocks, but the vertex set and the topology do not depend on them.
  const auto field = std::make_shared<TorusField>(Vec3(0.02, 0.01, -0.03), 1.2, 0.45);
  std::vector<Vec3> reference;
  std::size_t reference_triangles = 0;
  for (const int block : {2, 3, 5, 16, 64}) {
    SCOPED_TRACE("block_cells " + std::to_string(block));
    MarchingCubesOptions o;
    o.resolution = 36;
    o.block_cells = block;
    MarchingCubesStats stats;
    const TriMesh m = marching_cubes(*field, o, nullptr, &stats);
    test::expect_closed_surface(m, 1, 0);
    std::vector<Vec3> sorted = m.positions;
    std::sort(sorted.begin(), sorted.end(), [](const Vec3& a, const Vec3& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    if (reference.empty()) {
      reference = sorted;
      reference_triangles = m.triangles.size();
    } else {
      EXPECT_EQ(sorted, reference);
      EXPECT_EQ(m.triangles.size(), reference_triangles);
    }
  }
}

TEST(MarchingCubes, BoundSkippingSkipsAndGivesTheSameMesh) {
  const auto field = std::make_shared<MaxField>(
      std::vector<FieldPtr>{std::make_shared<SphereField>(Vec3(-2, 0, 0), 0.5),
                            std::make_shared<SphereField>(Vec3(2, 1, 0.5), 0.7)});
  MarchingCubesOptions o;
  o.resolution = 96;
  o.block_cells = 8;
  MarchingCubesStats pruned;
  field->reset_evaluations();
  const TriMesh a = marching_cubes(*field, o, nullptr, &pruned);
  const std::uint64_t pruned_evals = field->evaluations();

  o.use_bounds = false;
  MarchingCubesStats full;
  field->reset_evaluations();
  const TriMesh b = marching_cubes(*field, o, nullptr, &full);
  const std::uint64_t full_evals = field->evaluations();

  expect_same_mesh(a, b);
  test::expect_closed_surface(a, 2, 4);
  EXPECT_GT(pruned.blocks_skipped, pruned.blocks_total / 2);
  EXPECT_GT(pruned.cells_skipped, pruned.cells_total / 2);
  EXPECT_EQ(full.blocks_skipped, 0);
  EXPECT_EQ(full.cells_skipped, 0);
  EXPECT_EQ(full.cells_visited, full.cells_total);
  EXPECT_LT(pruned.corner_evaluations, full.corner_evaluations / 2);
  EXPECT_EQ(pruned_evals,
            static_cast<std::uint64_t>(pruned.corner_evaluations + pruned.root_evaluations));
  EXPECT_EQ(full_evals,
            static_cast<std::uint64_t>(full.corner_evaluations + full.root_evaluations));
  // Every grid corner is evaluated exactly once without pruning.
  EXPECT_EQ(full.corner_evaluations,
            (full.grid_cells[0] + 1) * (full.grid_cells[1] + 1) * (full.grid_cells[2] + 1));
}

TEST(MarchingCubes, AWrongBoundStillGivesAClosedMesh) {
  // The bound claims "outside" for every block beyond a plane x = cut: the sphere is clipped at a
  // block boundary, but the mesh stays watertight (signs are forced to agree with the skipped
  // blocks, and skipped blocks that contradict each other are evaluated after all).
  const Vec3 c(0.01, 0.02, 0.03);
  const auto sphere = std::make_shared<SphereField>(c, 1.0);
  std::int64_t conflicts = 0;
  for (const double cut : {0.2, -0.3, -0.6}) {
    SCOPED_TRACE("cut " + std::to_string(cut));
    const auto field = std::make_shared<test::LyingBoundField>(
        sphere, Aabb(Vec3::Constant(-10.0), Vec3(cut, 10.0, 10.0)));
    MarchingCubesOptions o;
    o.resolution = 32;
    o.block_cells = 4;
    MarchingCubesStats stats;
    const TriMesh m = marching_cubes(*field, o, nullptr, &stats);
    EXPECT_GT(stats.sign_overrides, 0);
    conflicts += stats.bound_conflicts;
    test::expect_closed_surface(m, 1, 2);
    EXPECT_LT(signed_volume(m), 0.95 * 4.0 / 3.0 * kPi);  // clipped
  }
  EXPECT_GT(conflicts, 0);
}

TEST(MarchingCubes, ExplicitCellSizeAndBox) {
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.0);
  MarchingCubesOptions o;
  o.cell_size = 0.1;
  o.box = Aabb(Vec3(-1.25, -1.25, -1.25), Vec3(1.25, 1.25, 1.3));
  MarchingCubesStats stats;
  const TriMesh m = marching_cubes(*field, o, nullptr, &stats);
  EXPECT_EQ(stats.grid_cells[0], 25);
  EXPECT_EQ(stats.grid_cells[1], 25);
  EXPECT_EQ(stats.grid_cells[2], 26);  // 25.5 cells round up
  EXPECT_EQ(stats.cell_size, 0.1);
  test::expect_closed_surface(m, 1, 2);
}

TEST(MarchingCubes, BoxCuttingTheSurfaceGivesAnOpenMesh) {
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.0);
  MarchingCubesOptions o;
  o.resolution = 20;
  o.box = Aabb(Vec3(-1.5, -1.5, -1.5), Vec3(1.5, 1.5, 0.0));
  const TriMesh m = marching_cubes(*field, o);
  const MeshReport r = check_mesh(m);
  EXPECT_FALSE(r.watertight);
  EXPECT_GT(r.boundary_edges, 0u);
  EXPECT_TRUE(r.oriented);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.euler, 1);  // a disk
}

TEST(MarchingCubes, EmptyFieldGivesAnEmptyMesh) {
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.0, 2.0);  // radius -1
  const TriMesh m = marching_cubes(*field, MarchingCubesOptions{});
  EXPECT_TRUE(m.positions.empty());
  EXPECT_TRUE(m.triangles.empty());
  // With an explicit box the grid is evaluated and finds nothing.
  MarchingCubesOptions o;
  o.box = Aabb(Vec3::Constant(-1), Vec3::Constant(1));
  o.resolution = 8;
  EXPECT_TRUE(marching_cubes(*field, o).triangles.empty());
}

void expect_invalid(const MarchingCubesOptions& o, const std::string& name) {
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.0);
  try {
    (void)marching_cubes(*field, o);
    ADD_FAILURE() << "expected InvalidArgument for " << name;
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(MarchingCubes, RejectsBadOptionsByName) {
  MarchingCubesOptions o;
  o.cell_size = -1.0;
  expect_invalid(o, "cell_size");
  o = {};
  o.cell_size = std::nan("");
  expect_invalid(o, "cell_size");
  o = {};
  o.resolution = 0;
  expect_invalid(o, "resolution");
  o = {};
  o.root_steps = -1;
  expect_invalid(o, "root_steps");
  o = {};
  o.block_cells = 1;
  expect_invalid(o, "block_cells");
  o = {};
  o.box = Aabb(Vec3(0, 0, 0), Vec3(std::numeric_limits<double>::infinity(), 1, 1));
  expect_invalid(o, "box");
  o = {};
  o.cell_size = 1e-6;  // 2e6 cells per side
  expect_invalid(o, "max_cells");
  o = {};
  o.max_cells = 0;
  expect_invalid(o, "max_cells");
}

TEST(MarchingCubes, CancelThrows) {
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.0);
  Context ctx;
  ctx.cancel();
  EXPECT_THROW((void)marching_cubes(*field, MarchingCubesOptions{}, &ctx), Cancelled);
}

TEST(MarchingCubes, ReportsProgress) {
  const auto field = std::make_shared<SphereField>(Vec3::Zero(), 1.0);
  Context ctx(1);
  std::vector<double> fractions;
  ctx.set_progress([&](const std::string& stage, double f) {
    EXPECT_EQ(stage, "marching cubes");
    fractions.push_back(f);
  });
  (void)marching_cubes(*field, MarchingCubesOptions{}, &ctx);
  ASSERT_GE(fractions.size(), 2u);
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
}

}  // namespace
}  // namespace ramiform
