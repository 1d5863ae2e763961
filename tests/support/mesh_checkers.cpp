// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "support/mesh_checkers.h"

#include "ramiform/mesh/winding.h"

#include <sstream>
#include <string>
#include <vector>

namespace ramiform::test {

std::string describe(const MeshReport& r) {
  std::ostringstream s;
  s << r.vertices << " vertices, " << r.triangles << " triangles, " << r.edges << " edges ("
    << r.boundary_edges << " boundary, " << r.nonmanifold_edges << " non-manifold, "
    << r.misoriented_edges << " misoriented), " << r.nonmanifold_vertices
    << " non-manifold vertices, " << r.degenerate_triangles << " degenerate triangles, "
    << r.components << " components, euler " << r.euler;
  return s.str();
}

::testing::AssertionResult is_watertight(const TriMesh& mesh) {
  const MeshReport r = check_mesh(mesh);
  if (r.watertight) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "mesh is not watertight: " << describe(r);
}

::testing::AssertionResult is_oriented(const TriMesh& mesh) {
  const MeshReport r = check_mesh(mesh);
  if (r.oriented) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "mesh is not consistently oriented: " << describe(r);
}

::testing::AssertionResult is_manifold(const TriMesh& mesh) {
  const MeshReport r = check_mesh(mesh);
  if (r.manifold) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "mesh is not manifold: " << describe(r);
}

::testing::AssertionResult has_components(const TriMesh& mesh, std::size_t n) {
  const MeshReport r = check_mesh(mesh);
  if (r.components == n) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "expected " << n << " components: " << describe(r);
}

void expect_watertight(const TriMesh& mesh) { EXPECT_TRUE(is_watertight(mesh)); }
void expect_oriented(const TriMesh& mesh) { EXPECT_TRUE(is_oriented(mesh)); }
void expect_manifold(const TriMesh& mesh) { EXPECT_TRUE(is_manifold(mesh)); }
void expect_components(const TriMesh& mesh, std::size_t n) { EXPECT_TRUE(has_components(mesh, n)); }

MeshReport expect_closed_manifold(const TriMesh& mesh) {
  const MeshReport r = check_mesh(mesh);
  EXPECT_TRUE(r.watertight) << describe(r);
  EXPECT_TRUE(r.oriented) << describe(r);
  EXPECT_TRUE(r.manifold) << describe(r);
  EXPECT_EQ(r.euler % 2, 0) << describe(r);
  return r;
}

void expect_closed_surface(const TriMesh& mesh, std::size_t components, long long euler) {
  const MeshReport r = expect_closed_manifold(mesh);
  EXPECT_EQ(r.components, components) << describe(r);
  EXPECT_EQ(r.euler, euler) << describe(r);
}

std::size_t nodes_outside(const TriMesh& mesh, const Skeleton& skeleton,
                          Vec3 (*transform)(const Vec3&)) {
  std::vector<Vec3> nodes;
  for (const auto& n : skeleton.nodes) {
    nodes.push_back(transform != nullptr ? transform(n.position) : n.position);
  }
  std::size_t outside = 0;
  for (const char f : points_inside(mesh, nodes)) outside += f == 0 ? 1 : 0;
  return outside;
}

std::size_t triangles_facing_inwards(const TriMesh& mesh, const Field& field) {
  std::vector<double> values(mesh.positions.size());
  std::vector<Vec3> gradients(mesh.positions.size());
  field.evaluate(mesh.positions, values, gradients);
  std::size_t inwards = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.positions[t[0]];
    const Vec3 normal = (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
    if (normal.dot(gradients[t[0]] + gradients[t[1]] + gradients[t[2]]) > 0) ++inwards;
  }
  return inwards;
}

}  // namespace ramiform::test
