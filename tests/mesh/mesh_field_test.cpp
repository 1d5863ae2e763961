// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// A closed mesh as a shape: inside/outside, orientation repair, bounds, gradient, bad meshes.

#include "ramiform/mesh/mesh_field.h"

#include <gtest/gtest.h>

#include "mesh/test_meshes.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

TEST(MeshField, InsideIsInsideTheSphereEvenWhenTheMeshIsInsideOut) {
  TriMesh sphere = test::icosphere(3, 1.0, Vec3(0, 0, 2));
  TriMesh flipped = sphere;
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  for (const TriMesh& m : {sphere, flipped}) {
    const FieldPtr f = make_mesh_field(m);
    EXPECT_EQ(f->iso(), 0.5);
    EXPECT_TRUE(f->is_inside(Vec3(0, 0, 2)));
    EXPECT_TRUE(f->is_inside(Vec3(0.5, 0.3, 2.2)));
    EXPECT_FALSE(f->is_inside(Vec3(0, 0, 3.2)));
    EXPECT_FALSE(f->is_inside(Vec3(2, 0, 2)));
    EXPECT_TRUE(f->bounds().contains(Vec3(0.9, 0, 2)));
  }
}

TEST(MeshField, BoundHoldsOnRandomBoxesAndTheGradientPointsInward) {
  const TriMesh sphere = test::icosphere(3, 1.0);
  const FieldPtr f = make_mesh_field(sphere);
  Rng rng(4);
  for (int b = 0; b < 40; ++b) {
    const Vec3 c(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    const Aabb box(c, c + Vec3::Constant(rng.uniform(0.05, 1.0)));
    const Interval iv = f->bound(box);
    for (int k = 0; k < 20; ++k) {
      const Vec3 p = box.min() + (box.max() - box.min())
                                     .cwiseProduct(Vec3(rng.uniform(0, 1), rng.uniform(0, 1),
                                                        rng.uniform(0, 1)));
      EXPECT_TRUE(iv.contains(f->value(p))) << p.transpose();
    }
  }
  // On the surface the winding number steps from 1 to 0 outward: the gradient points inward.
  const Vec3 v = sphere.positions[0];
  EXPECT_LT(f->gradient(0.9995 * v).dot(v), 0.0);
}

TEST(MeshField, OpenOrEmptyMeshesAreRefused) {
  TriMesh open = test::icosphere(1);
  open.triangles.pop_back();
  EXPECT_THROW((void)make_mesh_field(open), InvalidArgument);
  EXPECT_THROW((void)make_mesh_field(TriMesh{}), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
