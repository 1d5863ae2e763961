// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The ten-line library example of README.md, verbatim in the test body.

#include <gtest/gtest.h>

#include <ramiform/field/skeleton_field.h>
#include <ramiform/mesh/checks.h>
#include <ramiform/polygonize/tetrahedral.h>

TEST(ReadmeExample, YForkMeshIsWatertight) {
  ramiform::Skeleton s;                                   // a Y: trunk and two branches
  s.nodes = {{{0, 0, 0}, 0.5}, {{0, 0, 3}, 0.4}, {{-1, 0, 5}, 0.3}, {{1, 0, 5}, 0.3}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}};
  auto field = ramiform::make_skeleton_field(s);          // Cauchy convolution surface
  ramiform::TetrahedralOptions tets;  tets.levels = 2;
  ramiform::TriMesh mesh = ramiform::polygonize_tetrahedral(*field, s, tets);
  bool ok = ramiform::check_mesh(mesh).watertight;        // true
  EXPECT_TRUE(ok);
  const ramiform::MeshReport r = ramiform::check_mesh(mesh);
  EXPECT_EQ(r.components, 1U);
  EXPECT_TRUE(r.oriented);
  EXPECT_TRUE(r.manifold);
}
