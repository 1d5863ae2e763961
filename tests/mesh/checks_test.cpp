// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh/test_meshes.h"
#include "ramiform/core/errors.h"
#include "support/mesh_checkers.h"

namespace ramiform {
namespace {

using test::icosphere;
using test::merged;
using test::tetrahedron;
using test::torus;
using test::unit_cube;

TEST(CheckMesh, TetrahedronIsAClosedOrientedManifoldSphere) {
  const MeshReport r = check_mesh(tetrahedron());
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.triangles, 4u);
  EXPECT_EQ(r.edges, 6u);
  EXPECT_TRUE(r.watertight);
  EXPECT_TRUE(r.oriented);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(r.boundary_edges, 0u);
  // Three right isosceles faces (45, 45, 90) and one equilateral (60, 60, 60).
  EXPECT_NEAR(r.min_angle_deg, 45.0, 1e-12);
  EXPECT_NEAR(r.median_angle_deg, 52.5, 1e-12);
  EXPECT_NEAR(signed_volume(tetrahedron()), 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(surface_area(tetrahedron()), 1.5 + std::sqrt(3.0) / 2.0, 1e-14);
}

TEST(CheckMesh, CubeIsClosedAndOneFlippedTriangleBreaksOrientationOnly) {
  TriMesh cube = unit_cube();
  test::expect_closed_surface(cube, 1, 2);
  EXPECT_NEAR(signed_volume(cube), 1.0, 1e-15);
  std::swap(cube.triangles[5][1], cube.triangles[5][2]);
  const MeshReport r = check_mesh(cube);
  EXPECT_TRUE(r.watertight);
  EXPECT_FALSE(r.oriented);
  EXPECT_EQ(r.misoriented_edges, 3u);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.euler, 2);
}

TEST(CheckMesh, ReversedMeshHasNegativeVolumeButIsStillOriented) {
  TriMesh m = tetrahedron();
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  EXPECT_TRUE(check_mesh(m).oriented);
  EXPECT_NEAR(signed_volume(m), -1.0 / 6.0, 1e-15);
}

TEST(CheckMesh, TwoTetrahedraSharingAVertexAreNotVertexManifold) {
  // The second tetrahedron is the first mirrored through its vertex 0 (the origin).
  const TriMesh a = tetrahedron();
  TriMesh m = a;
  m.positions.push_back(Vec3(-1, 0, 0));
  m.positions.push_back(Vec3(0, -1, 0));
  m.positions.push_back(Vec3(0, 0, -1));
  // Mirrored through the origin: mirroring flips orientation, so reverse each triangle.
  for (const auto& t : a.triangles) {
    std::array<std::uint32_t, 3> u{};
    for (int k = 0; k < 3; ++k) u[k] = t[k] == 0 ? 0 : t[k] + 3;
    m.triangles.push_back({u[0], u[2], u[1]});
  }
  const MeshReport r = check_mesh(m);
  EXPECT_TRUE(r.watertight);
  EXPECT_TRUE(r.oriented);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.nonmanifold_vertices, 1u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler, 7 - 12 + 8);
  EXPECT_NEAR(signed_volume(m), 2.0 / 6.0, 1e-15);
}

TEST(CheckMesh, OpenSquareIsNotWatertight) {
  TriMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const MeshReport r = check_mesh(m);
  EXPECT_FALSE(r.watertight);
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_TRUE(r.oriented);
  EXPECT_TRUE(r.manifold);  // a disk: the fans at the boundary are open
  EXPECT_EQ(r.euler, 1);
  EXPECT_EQ(r.components, 1u);
}

TEST(CheckMesh, EdgeInThreeTrianglesIsNotManifold) {
  TriMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshReport r = check_mesh(m);
  EXPECT_FALSE(r.manifold);
  EXPECT_FALSE(r.watertight);
  EXPECT_EQ(r.nonmanifold_edges, 1u);
  EXPECT_FALSE(r.oriented);  // 0->1 is used twice
}

TEST(CheckMesh, TwoDisjointSpheresAreTwoComponents) {
  const TriMesh m = merged(icosphere(2, 1.0), icosphere(2, 0.5, Vec3(3, 0, 0)));
  const MeshReport r = check_mesh(m);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.euler, 4);
  EXPECT_TRUE(r.watertight);
  EXPECT_TRUE(r.oriented);
  EXPECT_TRUE(r.manifold);
  const TriangleComponents c = triangle_components(m);
  ASSERT_EQ(c.count, 2u);
  const std::size_t half = m.triangles.size() / 2;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) EXPECT_EQ(c.label[t], t < half ? 0u : 1u);
}

TEST(CheckMesh, TorusHasEulerZero) { test::expect_closed_surface(torus(2.0, 0.5, 24, 12), 1, 0); }

TEST(CheckMesh, IcosphereVolumeApproachesTheBall) {
  const TriMesh m = icosphere(4, 2.0);
  test::expect_closed_surface(m, 1, 2);
  const double ball = 4.0 / 3.0 * std::numbers::pi * 8.0;
  EXPECT_LT(signed_volume(m), ball);
  EXPECT_NEAR(signed_volume(m) / ball, 1.0, 0.01);
}

TEST(CheckMesh, RightIsoscelesTriangleAngles) {
  TriMesh m;
  m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  m.triangles = {{0, 1, 2}};
  const MeshReport r = check_mesh(m);
  EXPECT_NEAR(r.min_angle_deg, 45.0, 1e-12);
  EXPECT_NEAR(r.median_angle_deg, 45.0, 1e-12);
  EXPECT_EQ(r.zero_area_triangles, 0u);
  EXPECT_TRUE(r.manifold);
  EXPECT_EQ(r.euler, 1);
}

TEST(CheckMesh, ZeroAreaTrianglesCountZeroDegrees) {
  TriMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 1, 3}};  // collinear, then right isosceles
  MeshReport r = check_mesh(m);
  EXPECT_EQ(r.zero_area_triangles, 1u);
  EXPECT_EQ(r.min_angle_deg, 0.0);
  EXPECT_NEAR(r.median_angle_deg, 22.5, 1e-12);  // 0 0 0 45 45 90
  EXPECT_TRUE(r.manifold);                       // distinct indices: topology is fine

  m.triangles = {{0, 0, 3}};  // repeated index
  r = check_mesh(m);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.degenerate_triangles, 1u);
  EXPECT_EQ(r.zero_area_triangles, 1u);
  EXPECT_EQ(r.edges, 1u);
}

TEST(CheckMesh, UnusedVerticesAreIgnored) {
  TriMesh m = tetrahedron();
  m.positions.emplace_back(5, 5, 5);
  const MeshReport r = check_mesh(m);
  EXPECT_EQ(r.vertices, 5u);
  EXPECT_EQ(r.euler, 2);
  EXPECT_EQ(r.components, 1u);
  EXPECT_TRUE(r.manifold);
}

TEST(CheckMesh, EmptyMeshIsNotWatertight) {
  const MeshReport r = check_mesh(TriMesh{});
  EXPECT_FALSE(r.watertight);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.components, 0u);
  EXPECT_EQ(r.euler, 0);
  EXPECT_EQ(r.min_angle_deg, 0.0);
}

TEST(CheckMesh, IndexOutOfRangeThrowsNamingTheTriangle) {
  TriMesh m = tetrahedron();
  m.triangles[2][1] = 9;
  try {
    (void)check_mesh(m);
    FAIL() << "expected InvalidArgument";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)signed_volume(m), InvalidArgument);
  EXPECT_THROW((void)triangle_components(m), InvalidArgument);
}

TEST(CheckMesh, ResultDoesNotDependOnThreads) {
  const TriMesh m = merged(icosphere(5, 1.0), torus(3.0, 0.5, 200, 40));
  Context one(1);
  Context two(2);
  const MeshReport a = check_mesh(m, &one);
  const MeshReport b = check_mesh(m, &two);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.euler, b.euler);
  EXPECT_EQ(a.euler, 2);
  EXPECT_EQ(a.components, 2u);
  EXPECT_EQ(a.min_angle_deg, b.min_angle_deg);
  EXPECT_EQ(a.median_angle_deg, b.median_angle_deg);
}

TEST(MeshCheckers, ReportFailures) {
  TriMesh open;
  open.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  open.triangles = {{0, 1, 2}};
  EXPECT_FALSE(test::is_watertight(open));
  EXPECT_TRUE(test::is_oriented(open));
  EXPECT_TRUE(test::is_manifold(open));
  EXPECT_TRUE(test::has_components(open, 1));
  EXPECT_FALSE(test::has_components(open, 2));
}

}  // namespace
}  // namespace ramiform
