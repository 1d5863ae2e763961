// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Root finding along lattice edges (polygonize/edge_roots.h), shared by both polygonizers.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "polygonize/edge_roots.h"
#include "ramiform/field/skeleton_field.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

double value_at(const Field& field, const Vec3& p) {
  double f = 0;
  field.evaluate(std::span<const Vec3>(&p, 1), std::span<double>(&f, 1));
  return f;
}

// Edges from a segment's axis to far away, where the Cauchy field is all but zero (below 1e-9
// of the iso value from 100 radii on): the root lies within the first thousandth of such an
// edge. Interpolating towards the vanished end put the vertex on the inside end (a node of
// archi_Tree_1 at level 0 was left outside the mesh that way); the root finder must still land
// on the surface.
TEST(EdgeRoots, LongEdgesIntoTheVoidLandOnTheSurface) {
  const Skeleton s = test::single_segment(Vec3(0, 0, 0), Vec3(1, 0, 0), 0.01, 0.01);
  const FieldPtr field = make_skeleton_field(s);
  const double iso = field->iso();
  std::vector<Vec3> a, b;
  std::vector<double> fa, fb;
  for (const double reach : {0.05, 1.0, 10.0, 100.0, 4400.0}) {
    for (const Vec3& dir : {Vec3(0, 1, 0), Vec3(0, 0.6, -0.8)}) {
      a.emplace_back(0.5, 0, 0);
      b.push_back(a.back() + reach * dir);
      fa.push_back(value_at(*field, a.back()));
      fb.push_back(value_at(*field, b.back()));
      ASSERT_GT(fa.back(), 2 * iso);
      ASSERT_LT(fb.back(), iso);
    }
  }
  std::uint64_t evaluations = 0;
  const std::vector<Vec3> roots = detail::find_edge_roots(*field, a, b, fa, fb, 16, evaluations);
  ASSERT_EQ(roots.size(), a.size());
  for (std::size_t e = 0; e < roots.size(); ++e) {
    EXPECT_NEAR(value_at(*field, roots[e]), iso, 1e-6 * iso) << "edge " << e;
    // On the surface of a 1 cm tube: about 1 cm from the axis.
    EXPECT_NEAR((roots[e] - a[e]).norm(), 0.01, 0.002) << "edge " << e << " value " << value_at(*field, roots[e]) << " at " << roots[e].transpose();
  }
  EXPECT_LE(evaluations, 16 * a.size());
}

}  // namespace
}  // namespace ramiform
