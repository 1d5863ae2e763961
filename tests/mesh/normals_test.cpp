// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/normals.h"

#include <gtest/gtest.h>

#include "ramiform/core/errors.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/skeleton/generate.h"

namespace ramiform {
namespace {

// The outward normal against an independent central-difference gradient, and against the
// geometry: it points away from the skeleton's nearest node of a single capsule.
TEST(FieldNormals, AreTheUnitOutwardFieldGradientToOneInAMillion) {
  BranchingTreeOptions o;
  o.segments = 30;
  o.seed = 9;
  o.tip_radius = 0.02;
  const Skeleton s = branching_tree(o);
  const FieldPtr f = make_skeleton_field(s);
  TriMesh m = polygonize_to_tolerance(*f, s);
  EXPECT_EQ(set_normals_from_field(m, *f), 0u);
  ASSERT_EQ(m.normals.size(), m.positions.size());
  double worst = 0;
  for (std::size_t i = 0; i < m.positions.size(); i += 7) {
    const Vec3 g = numeric_gradient(*f, m.positions[i], 1e-6);
    worst = std::max(worst, (m.normals[i] - (-g.normalized())).norm());
    EXPECT_NEAR(m.normals[i].norm(), 1.0, 1e-12);
  }
  EXPECT_LT(worst, 1e-6);
  // Outward: along the face normals (CCW from outside) nearly everywhere.
  TriMesh faces = m;
  set_normals_from_faces(faces);
  std::size_t agree = 0;
  for (std::size_t i = 0; i < m.normals.size(); ++i) agree += m.normals[i].dot(faces.normals[i]) > 0.5;
  EXPECT_GT(static_cast<double>(agree), 0.999 * static_cast<double>(m.normals.size()));
}

TEST(FaceNormals, AreAreaWeightedOutwardAndSharedBySeamCopies) {
  TriMesh m;  // a tetrahedron with vertex 4 a seam copy of vertex 0
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0, 0, 0),
                 Vec3(5, 5, 5)};  // vertex 5 is in no triangle
  m.triangles = {{0, 2, 1}, {4, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  m.welded = {0, 1, 2, 3, 0, 5};
  set_normals_from_faces(m);
  // Vertex 0's triangles: -z, -y, -x faces of area 1/2 each.
  EXPECT_TRUE(m.normals[0].isApprox(Vec3(-1, -1, -1).normalized(), 1e-15));
  EXPECT_EQ(m.normals[4], m.normals[0]);
  EXPECT_EQ(m.normals[5], Vec3(0, 0, 1));
  // Vertex 3: the -y and -x faces (area 1/2) and the slanted face (area sqrt(3)/2).
  const Vec3 expect3 = (Vec3(0, -0.5, 0) + Vec3(-0.5, 0, 0) + Vec3(0.5, 0.5, 0.5)).normalized();
  EXPECT_TRUE(m.normals[3].isApprox(expect3, 1e-15));
  TriMesh bad = m;
  bad.triangles[0][1] = 9;
  EXPECT_THROW(set_normals_from_faces(bad), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
