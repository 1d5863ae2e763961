// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Field evaluation honours the caller's Context (threads, cancellation) through every operator,
// and its values never depend on the thread count.

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/skeleton_field.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

std::vector<Vec3> cloud(std::size_t n, const Aabb& box) {
  Rng rng(11);
  std::vector<Vec3> p(n);
  for (auto& q : p) {
    for (int k = 0; k < 3; ++k) q[k] = box.min()[k] + rng.uniform() * (box.max()[k] - box.min()[k]);
  }
  return p;
}

FieldPtr blended_trees() {
  auto a = make_skeleton_field(test::random_tree(5, 60));
  auto b = make_transform(make_skeleton_field(test::random_tree(6, 60)),
                          Affine3(Eigen::Translation3d(0.5, 0, 0)));
  return make_sum({a, b});
}

TEST(FieldContext, ValuesAndGradientsIdenticalForAnyThreadCount) {
  const FieldPtr f = blended_trees();
  const std::vector<Vec3> p = cloud(60000, f->bounds());
  std::vector<std::vector<double>> values;
  std::vector<std::vector<Vec3>> gradients;
  for (int threads : {1, 2, 0}) {
    const Context ctx(threads);
    std::vector<double> v(p.size());
    std::vector<Vec3> g(p.size());
    f->evaluate(p, v, g, &ctx);
    values.push_back(v);
    gradients.push_back(g);
  }
  for (std::size_t r = 1; r < values.size(); ++r) {
    EXPECT_EQ(std::memcmp(values[0].data(), values[r].data(), values[0].size() * sizeof(double)),
              0);
    EXPECT_EQ(
        std::memcmp(gradients[0].data(), gradients[r].data(), gradients[0].size() * sizeof(Vec3)),
        0);
  }
}

// Bezier curve fields (batched projection, SIMD across points) under a sum: the same bits on 1
// and 2 threads.
TEST(FieldContext, BezierCurveFieldIdenticalForAnyThreadCount) {
  BezierCurve c;
  c.controls = {Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(2, -1, 1), Vec3(3, 0, 0)};
  BezierCurve q;
  q.controls = {Vec3(0, 1, 0),  Vec3(1, 0, 2), Vec3(2, 2, 1),
                Vec3(3, 1, -1), Vec3(2, 0, 0), Vec3(4, 1, 0)};
  const FieldPtr f = make_sum(
      {make_bezier_field(c, 0.4, Deformation{}), make_bezier_field(q, 0.3, Deformation{})});
  const std::vector<Vec3> p = cloud(20000, f->bounds());
  std::vector<double> v1(p.size()), v2(p.size());
  std::vector<Vec3> g1(p.size()), g2(p.size());
  const Context one(1), two(2);
  f->evaluate(p, v1, g1, &one);
  f->evaluate(p, v2, g2, &two);
  EXPECT_EQ(std::memcmp(v1.data(), v2.data(), v1.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(g1.data(), g2.data(), g1.size() * sizeof(Vec3)), 0);
  // And the same as one point at a time.
  for (std::size_t k = 0; k < p.size(); k += 97) {
    const double v = f->value(p[k]);
    EXPECT_EQ(std::memcmp(&v, &v1[k], sizeof(double)), 0) << k;
  }
}

// The Context reaches the skeleton fields under the sum and the transform: a cancelled one stops
// the evaluation of a large batch with `Cancelled`, as every long operation does.
TEST(FieldContext, CancellationReachesChildrenOfOperators) {
  const FieldPtr f = blended_trees();
  const std::vector<Vec3> p = cloud(60000, f->bounds());
  std::vector<double> v(p.size());
  Context ctx(1);
  ctx.cancel();
  EXPECT_THROW(f->evaluate(p, v, {}, &ctx), Cancelled);
  const Context fine(1);
  EXPECT_NO_THROW(f->evaluate(p, v, {}, &fine));
}

}  // namespace
}  // namespace ramiform
