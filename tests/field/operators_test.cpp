// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/operators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/field/warps.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

using test::check_bound_conservative;
using test::check_bounds_contain_inside;
using test::grown;
using test::point_near;
using test::random_point;
using test::random_unit;

SkeletonFieldOptions wyvill() {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kDistance;
  o.kernel = Kernel{KernelKind::kWyvill, 0.0};
  return o;
}

SkeletonFieldOptions power() {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kDistance;
  o.kernel = Kernel{KernelKind::kInversePower, 0.0};
  return o;
}

// Two overlapping skeletons (a Y-fork and a segment crossing it) and their fields, for the
// generic property tests; `both` is one skeleton holding both for sampling near them.
struct Scene {
  Skeleton fork = test::y_fork();
  Skeleton bar = test::single_segment(Vec3(-6, -1, 8), Vec3(6, 1, 12), 1.2, 0.6);
  Skeleton both;
  Scene() {
    both = fork;
    const auto off = static_cast<std::uint32_t>(both.nodes.size());
    for (const auto& n : bar.nodes) both.nodes.push_back(n);
    for (const auto& e : bar.edges) both.edges.push_back({e[0] + off, e[1] + off});
  }
};

TEST(Operators, SumIsExactSum) {
  const Scene sc;
  for (const auto& o : {wyvill(), SkeletonFieldOptions{}}) {
    const FieldPtr a = make_skeleton_field(sc.fork, o);
    const FieldPtr b = make_skeleton_field(sc.bar, o);
    const FieldPtr s = make_sum({a, b});
    EXPECT_EQ(s->iso(), a->iso());
    const FieldPtr twice = make_sum({a, a});  // a DAG: one child used twice
    Rng rng(1);
    for (int i = 0; i < 500; ++i) {
      const Vec3 p = point_near(sc.both, rng, 3.0);
      EXPECT_EQ(s->value(p), a->value(p) + b->value(p));
      const Vec3 g = s->gradient(p);
      EXPECT_TRUE(g == a->gradient(p) + b->gradient(p)) << g.transpose();
      EXPECT_EQ(twice->value(p), 2 * a->value(p));
    }
    // One child: the child itself.
    const FieldPtr one = make_sum({a});
    EXPECT_EQ(one->value(Vec3(0.2, 0.1, 3)), a->value(Vec3(0.2, 0.1, 3)));
  }
}

TEST(Operators, SumOfThree) {
  const Scene sc;
  const FieldPtr a = make_skeleton_field(sc.fork, wyvill());
  const FieldPtr b = make_skeleton_field(sc.bar, wyvill());
  const FieldPtr c = make_point_field(Vec3(0, 0, 9), 2.0, wyvill());
  const FieldPtr s = make_sum({a, b, c});
  Rng rng(2);
  for (int i = 0; i < 300; ++i) {
    const Vec3 p = point_near(sc.both, rng, 3.0);
    const double e = a->value(p) + b->value(p) + c->value(p);
    EXPECT_NEAR(s->value(p), e, 4e-16 * std::max(1.0, e));
  }
}

TEST(Operators, SumNeedsEqualIsoAndChildren) {
  const FieldPtr a = make_point_field(Vec3::Zero(), 1.0, wyvill());  // iso 0.5
  const FieldPtr b = make_point_field(Vec3::Zero(), 1.0, power());   // iso 1
  EXPECT_THROW((void)make_sum({a, b}), InvalidArgument);
  EXPECT_THROW((void)make_sum({}), InvalidArgument);
  EXPECT_THROW((void)make_union({}), InvalidArgument);
  EXPECT_THROW((void)make_intersection({}), InvalidArgument);
}

TEST(Operators, UnionIsMaxIntersectionIsMin) {
  const Scene sc;
  const FieldPtr a = make_skeleton_field(sc.fork, wyvill());
  const FieldPtr b = make_skeleton_field(sc.bar, wyvill());
  const FieldPtr u = make_union({a, b});
  const FieldPtr n = make_intersection({a, b});
  EXPECT_EQ(u->iso(), 0.5);
  EXPECT_EQ(n->iso(), 0.5);
  Rng rng(3);
  int both_inside = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p = point_near(sc.both, rng, 3.0);
    const double va = a->value(p), vb = b->value(p);
    EXPECT_EQ(u->value(p), std::max(va, vb));
    EXPECT_EQ(n->value(p), std::min(va, vb));
    EXPECT_EQ(u->is_inside(p), a->is_inside(p) || b->is_inside(p));
    EXPECT_EQ(n->is_inside(p), a->is_inside(p) && b->is_inside(p));
    both_inside += n->is_inside(p);
    if (va != vb) {
      const Vec3 gu = u->gradient(p), gn = n->gradient(p);
      EXPECT_TRUE(gu == (va > vb ? a : b)->gradient(p));
      EXPECT_TRUE(gn == (va < vb ? a : b)->gradient(p));
    }
  }
  EXPECT_GT(both_inside, 10);
}

TEST(Operators, DifferenceOnKnownPoints) {
  // a: sphere of radius 2 at the origin; b: sphere of radius 1 at (1.5, 0, 0).
  const FieldPtr a = make_point_field(Vec3::Zero(), 2.0, wyvill());
  const FieldPtr b = make_point_field(Vec3(1.5, 0, 0), 1.0, wyvill());
  const FieldPtr d = make_difference(a, b);
  EXPECT_EQ(d->iso(), 0.5);
  EXPECT_TRUE(d->is_inside(Vec3(-1, 0, 0)));      // in a, far from b
  EXPECT_TRUE(d->is_inside(Vec3(0, 1.5, 0)));     // in a, outside b
  EXPECT_FALSE(d->is_inside(Vec3(1.5, 0, 0)));    // centre of b
  EXPECT_FALSE(d->is_inside(Vec3(1.9, 0.1, 0)));  // in both
  EXPECT_FALSE(d->is_inside(Vec3(2.3, 0, 0)));    // in b only
  EXPECT_FALSE(d->is_inside(Vec3(5, 0, 0)));      // in neither
  // The new surface lies on b's sphere: along the x axis it is at x = 0.5.
  EXPECT_NEAR(d->value(Vec3(0.5, 0, 0)), 0.5, 1e-12);
  Rng rng(4);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 p = random_point(rng, Aabb(Vec3(-3, -3, -3), Vec3(3, 3, 3)));
    const double va = a->value(p), vb = b->value(p);
    EXPECT_EQ(d->value(p), std::min(va, 2 * 0.5 - vb));
    EXPECT_EQ(d->is_inside(p), a->is_inside(p) && vb < 0.5);
  }
}

TEST(Operators, CsgShiftsChildrenOfDifferentIso) {
  // a has iso 0.5 (Wyvill), b iso 1 (inverse power): b's values are shifted by 0.5 - 1.
  const FieldPtr a = make_point_field(Vec3::Zero(), 2.0, wyvill());
  const FieldPtr b = make_segment_field(Vec3(1, -3, 0), 0.8, Vec3(1, 3, 0), 0.8, power());
  ASSERT_EQ(a->iso(), 0.5);
  ASSERT_EQ(b->iso(), 1.0);
  const FieldPtr u = make_union({a, b});
  const FieldPtr n = make_intersection({a, b});
  const FieldPtr d = make_difference(a, b);
  const FieldPtr d2 = make_difference(b, a);
  EXPECT_EQ(u->iso(), 0.5);
  EXPECT_EQ(n->iso(), 0.5);
  EXPECT_EQ(d->iso(), 0.5);
  EXPECT_EQ(d2->iso(), 1.0);
  Rng rng(5);
  int counts[4] = {0, 0, 0, 0};
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p = random_point(rng, Aabb(Vec3(-3, -4, -3), Vec3(3, 4, 3)));
    const double va = a->value(p), vb = b->value(p);
    // Skip points within 1e-9 of either surface (rounding of the shift).
    if (std::abs(va - 0.5) < 1e-9 || std::abs(vb - 1.0) < 1e-9) continue;
    const bool ia = va > 0.5, ib = vb > 1.0;
    ++counts[ia * 2 + ib];
    EXPECT_NEAR(u->value(p), std::max(va, vb - 0.5), 1e-14 * std::max(1.0, vb));
    EXPECT_NEAR(n->value(p), std::min(va, vb - 0.5), 1e-14 * std::max(1.0, vb));
    EXPECT_NEAR(d->value(p), std::min(va, 2 * 0.5 - (vb - 0.5)), 1e-14 * std::max(1.0, vb));
    EXPECT_NEAR(d2->value(p), std::min(vb, 2 * 1.0 - (va + 0.5)), 1e-14 * std::max(1.0, vb));
    EXPECT_EQ(u->is_inside(p), ia || ib);
    EXPECT_EQ(n->is_inside(p), ia && ib);
    EXPECT_EQ(d->is_inside(p), ia && !ib);
    EXPECT_EQ(d2->is_inside(p), ib && !ia);
  }
  for (int c : counts) EXPECT_GT(c, 20);
}

Affine3 test_transform() {
  Affine3 t = Affine3::Identity();
  t.translate(Vec3(1, -2, 3));
  t.rotate(Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()));
  t.scale(Vec3(2.0, 0.5, 1.5));
  return t;
}

TEST(Operators, TransformMovesTheShape) {
  const Scene sc;
  const Affine3 T = test_transform();
  const Mat3 inv_t = T.linear().inverse().transpose();
  for (const auto& o : {wyvill(), SkeletonFieldOptions{}}) {
    const FieldPtr f = make_skeleton_field(sc.fork, o);
    const FieldPtr ft = make_transform(f, T);
    EXPECT_EQ(ft->iso(), f->iso());
    Rng rng(6);
    for (int i = 0; i < 500; ++i) {
      const Vec3 p = point_near(sc.fork, rng, 3.0);
      const Vec3 q = T * p;
      EXPECT_NEAR(ft->value(q), f->value(p), 1e-12);
      // grad f_T(q) = T^-T grad f(T^-1 q).
      const Vec3 g = ft->gradient(q);
      const Vec3 expected = inv_t * f->gradient(T.inverse() * q);
      EXPECT_LE((g - expected).norm(), 1e-12 * std::max(1.0, expected.norm())) << g.transpose();
      // Central differences on the smooth (convolution) field; the distance field has kinks
      // at segment ends that make finite differences unreliable at arbitrary points.
      if (o.surface == SurfaceKind::kConvolution) {
        const Vec3 fd = test::central_gradient(*ft, q, 1e-6);
        EXPECT_LE((g - fd).norm(), 1e-5 * g.norm() + 1e-7) << g.transpose() << " fd " << fd.transpose();
      }
    }
  }
}

TEST(Operators, TransformRejectsSingularMaps) {
  const FieldPtr f = make_point_field(Vec3::Zero(), 1.0, wyvill());
  Affine3 flat = Affine3::Identity();
  flat.scale(Vec3(1, 0, 1));
  EXPECT_THROW((void)make_transform(f, flat), InvalidArgument);
  Affine3 nan = Affine3::Identity();
  nan.translate(Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0));
  EXPECT_THROW((void)make_transform(f, nan), InvalidArgument);
  Affine3 inf = Affine3::Identity();
  inf.linear()(0, 1) = std::numeric_limits<double>::infinity();
  EXPECT_THROW((void)make_transform(f, inf), InvalidArgument);
}

// All operators over the scene, with a skeleton to sample near (transformed for transforms).
struct OpCase {
  std::string name;
  FieldPtr field;
  Skeleton near;
};

std::vector<OpCase> operator_cases() {
  const Scene sc;
  std::vector<OpCase> out;
  for (const auto& o : {wyvill(), SkeletonFieldOptions{}}) {
    const std::string k = o.surface == SurfaceKind::kDistance ? "wyvill" : "cauchy";
    const FieldPtr a = make_skeleton_field(sc.fork, o);
    const FieldPtr b = make_skeleton_field(sc.bar, o);
    out.push_back({"sum/" + k, make_sum({a, b}), sc.both});
    out.push_back({"union/" + k, make_union({a, b}), sc.both});
    out.push_back({"intersection/" + k, make_intersection({a, b}), sc.both});
    out.push_back({"difference/" + k, make_difference(a, b), sc.both});
    Skeleton moved = sc.both;
    const Affine3 T = test_transform();
    for (auto& n : moved.nodes) {
      n.position = T * n.position;
      n.radius *= 2.0;
    }
    const FieldPtr blend = make_sum({a, b});
    out.push_back({"transform(sum)/" + k, make_transform(blend, T), moved});
    out.push_back({"union(transform, b)/" + k,
                   make_union({make_transform(a, T), make_transform(b, T)}), moved});
    out.push_back({"difference(sum, transform)/" + k,
                   make_difference(blend, make_transform(make_skeleton_field(sc.bar, o), Affine3(Eigen::Translation3d(0.5, 0.5, 0.5)))),
                   sc.both});
  }
  // Mixed iso values.
  const FieldPtr p = make_skeleton_field(sc.bar, power());
  const FieldPtr w = make_skeleton_field(sc.fork, wyvill());
  out.push_back({"union(mixed iso)", make_union({w, p}), sc.both});
  out.push_back({"difference(mixed iso)", make_difference(p, w), sc.both});
  return out;
}

TEST(Operators, BoundIsConservative) {
  std::uint64_t seed = 10;
  for (const auto& c : operator_cases()) check_bound_conservative(*c.field, c.near, seed++, c.name);
}

TEST(Operators, BoundsContainEveryInsidePoint) {
  std::uint64_t seed = 50;
  for (const auto& c : operator_cases()) check_bounds_contain_inside(*c.field, c.near, seed++, c.name);
}

TEST(Operators, RestrictIsExactInsideTheBox) {
  Rng rng(7);
  for (const auto& c : operator_cases()) {
    for (int b = 0; b < 10; ++b) {
      const Vec3 center = point_near(c.near, rng, 2.0);
      const Vec3 half = Vec3::Constant(rng.uniform(0.2, 5.0));
      const Aabb box(center - half, center + half);
      const FieldPtr r = c.field->restrict(box);
      EXPECT_EQ(r->iso(), c.field->iso());
      c.field->reset_evaluations();
      for (int i = 0; i < 100; ++i) {
        const Vec3 p = random_point(rng, box);
        ASSERT_EQ(r->value(p), c.field->value(p)) << c.name << " " << p.transpose();
        ASSERT_TRUE(r->gradient(p) == c.field->gradient(p)) << c.name;
      }
      EXPECT_EQ(c.field->evaluations(), 400U) << c.name;
    }
  }
}

TEST(Operators, DeepTreeStillPrunes) {
  // A sum of many far-apart points, unioned and transformed: the bound of an empty box far
  // from all of them must still exclude the surface.
  std::vector<FieldPtr> pts;
  for (int i = 0; i < 50; ++i) pts.push_back(make_point_field(Vec3(10.0 * i, 0, 0), 1.0, wyvill()));
  const FieldPtr sum = make_sum(pts);
  const FieldPtr tree =
      make_union({make_transform(sum, Affine3(Eigen::Translation3d(0, 0, 5))), make_intersection({sum, sum})});
  const Interval far = tree->bound(Aabb(Vec3(200, 50, 50), Vec3(210, 60, 60)));
  EXPECT_FALSE(far.straddles(tree->iso()));
  // Between two points, a box that touches neither sphere's support.
  const Interval gap = tree->bound(Aabb(Vec3(104, -1, -1), Vec3(106, 1, 1)));
  EXPECT_FALSE(gap.straddles(tree->iso()));
  // A box around one sphere's surface does straddle.
  const Interval on = tree->bound(Aabb(Vec3(100.5, -0.5, -0.5), Vec3(101.5, 0.5, 0.5)));
  EXPECT_TRUE(on.straddles(tree->iso()));
}

// ---- nesting depth -------------------------------------------------------------------------

// (A transform of a transform merges into one: TransformChainsAreOneLevel.)
const std::vector<std::string> kNestingKinds = {"union", "blend", "intersection", "difference",
                                                "taper", "twist", "bend"};

// `f` one level deeper under the operator or warp `kind` (a second child, where there is one, is
// the shared point field `other`).
FieldPtr nest(const std::string& kind, const FieldPtr& f, const FieldPtr& other) {
  if (kind == "union") return make_union({f, other});
  if (kind == "blend") return make_sum({f, other});
  if (kind == "intersection") return make_intersection({f, other});
  if (kind == "difference") return make_difference(f, other);
  if (kind == "taper") {
    TaperOptions o;
    o.scale_end = 0.9999;
    return make_taper(f, o);
  }
  if (kind == "twist") {
    TwistOptions o;
    o.rate = 1e-4;
    return make_twist(f, o);
  }
  BendOptions o;
  o.rate = 1e-4;
  return make_bend(f, o);
}

// A chain `depth` deep (the point field at its bottom has depth 1).
FieldPtr chain(const std::string& kind, std::size_t depth, const FieldPtr& other) {
  FieldPtr f = make_point_field(Vec3::Zero(), 1.0, wyvill());
  for (std::size_t d = 1; d < depth; ++d) f = nest(kind, f, other);
  return f;
}

TEST(Operators, NestingBeyondTheMaximumDepthIsRefused) {
  const FieldPtr other = make_point_field(Vec3(0.2, 0, 0), 1.0, wyvill());
  EXPECT_EQ(field_depth(*other), 1U);
  EXPECT_EQ(field_depth(*make_union({other, other})), 2U);
  for (const std::string& kind : kNestingKinds) {
    const FieldPtr deepest = chain(kind, kMaxFieldDepth, other);
    EXPECT_EQ(field_depth(*deepest), kMaxFieldDepth) << kind;
    try {
      (void)nest(kind, deepest, other);
      ADD_FAILURE() << kind << " nested " << kMaxFieldDepth + 1 << " deep was accepted";
    } catch (const InvalidArgument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(std::to_string(kMaxFieldDepth + 1) + " deep"), std::string::npos) << what;
      EXPECT_NE(what.find("maximum depth " + std::to_string(kMaxFieldDepth)), std::string::npos)
          << what;
    }
    // A shallow field under the deep one's parent is no deeper than the deep one.
    EXPECT_EQ(field_depth(*make_union({other, chain(kind, 3, other)})), 4U) << kind;
  }
}

TEST(Operators, TransformChainsAreOneLevel) {
  // 5,000 moves of 1e-4 along x, 10 times the depth limit, are one transform by 0.5: depth 2,
  // and the values and gradients of the point field moved by 0.5 (up to rounding).
  const FieldPtr point = make_point_field(Vec3(0.2, 0, 0), 1.0, wyvill());
  FieldPtr f = point;
  for (int k = 0; k < 5000; ++k) f = make_transform(f, Affine3(Eigen::Translation3d(1e-4, 0, 0)));
  EXPECT_EQ(field_depth(*f), 2U);
  const FieldPtr once = make_transform(point, Affine3(Eigen::Translation3d(0.5, 0, 0)));
  const std::vector<Vec3> points = {Vec3(0.7, 0.1, 0), Vec3(0.2, 0.3, 0.1), Vec3(1.1, 0, -0.2)};
  std::vector<double> a(points.size()), b(points.size());
  std::vector<Vec3> ga(points.size()), gb(points.size());
  f->evaluate(points, a, ga);
  once->evaluate(points, b, gb);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR(a[i], b[i], 1e-12) << i;
    EXPECT_LT((ga[i] - gb[i]).norm(), 1e-11) << i;
  }
  // Rotations and scales compose too: a quarter turn four times is the identity.
  FieldPtr r = point;
  const Affine3 quarter(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()));
  for (int k = 0; k < 4; ++k) r = make_transform(r, quarter);
  EXPECT_EQ(field_depth(*r), 2U);
  std::vector<double> c(points.size());
  r->evaluate(points, c);
  std::vector<double> d(points.size());
  point->evaluate(points, d);
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(c[i], d[i], 1e-12) << i;
}

TEST(Operators, EveryRecursiveCallSurvivesTheMaximumDepth) {
  // evaluate, bound, bounds, restrict, describe and the destruction all recurse; at the maximum
  // depth each must run, on the calling thread and on the worker threads that polygonizers use.
  const FieldPtr other = make_point_field(Vec3(0.2, 0, 0), 1.0, wyvill());
  const Aabb box(Vec3(-1, -1, -1), Vec3(1, 1, 1));
  const std::vector<Vec3> points = {Vec3(0.1, 0.2, 0), Vec3(0.5, 0, 0.3), Vec3(3, 0, 0)};
  for (const std::string& kind : kNestingKinds) {
    FieldPtr f = chain(kind, kMaxFieldDepth, other);
    auto calls = [&](bool with_bounds) {
      std::vector<double> v(points.size());
      std::vector<Vec3> g(points.size());
      f->evaluate(points, v, g);
      for (double x : v) EXPECT_TRUE(std::isfinite(x)) << kind;
      EXPECT_TRUE(f->bound(box).lo <= f->bound(box).hi) << kind;
      if (with_bounds) (void)f->bounds();
      const FieldPtr r = f->restrict(box);
      r->evaluate(points, v);
      // A chain of transforms or warps cuts its children's descriptions short.
      EXPECT_LT(f->describe().size(), 1000U) << kind;
    };
    calls(true);
    // A sum chain's bounds() is quadratic in its depth (every level bounds its subtree to grow
    // the box): once is enough.
    Context two(2);
    parallel::for_chunks(
        2, 1, [&](std::size_t, std::size_t) { calls(kind != "blend"); }, &two);
    f.reset();  // the last reference: the whole chain is destroyed here
  }
}

// ---- shared children -----------------------------------------------------------------------

TEST(Operators, SharedChildrenAreEvaluatedOncePerBatch) {
  // Ten levels of `union x x x x x x x x y` (each level's result used 8 times by the next): one
  // evaluation per distinct child, not 8^10 through every path. The values are those of
  // union(x0, y), since max(v, v) = v.
  const std::vector<Vec3> points = {Vec3(0.1, 0.2, 0), Vec3(0.4, 0, 0.3), Vec3(-0.6, 0.1, 0),
                                    Vec3(0.9, 0.9, 0.9), Vec3(2, 0, 0)};
  const std::size_t n = points.size();
  using Make = std::function<FieldPtr(std::vector<FieldPtr>)>;
  for (const auto& [name, make] :
       {std::pair<std::string, Make>{"union", make_union},
        std::pair<std::string, Make>{"intersection", make_intersection}}) {
    const FieldPtr x0 = make_point_field(Vec3::Zero(), 1.0, wyvill());
    const FieldPtr y = make_point_field(Vec3(0.3, 0, 0), 1.0, wyvill());
    FieldPtr x = x0;
    for (int level = 0; level < 10; ++level) {
      std::vector<FieldPtr> kids(9, x);
      kids.back() = y;
      x = make(kids);
    }
    const FieldPtr plain = make({x0, y});
    std::vector<double> v(n), pv(n);
    std::vector<Vec3> g(n), pg(n);
    x0->reset_evaluations();
    y->reset_evaluations();
    x->evaluate(points, v, g);
    EXPECT_EQ(x0->evaluations(), n) << name;
    EXPECT_EQ(y->evaluations(), 10 * n) << name;
    plain->evaluate(points, pv, pg);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(v[i], pv[i]) << name << " " << i;
      EXPECT_TRUE(g[i] == pg[i]) << name << " " << i;
    }
    // bound, bounds and restrict visit each distinct child once too (8^10 calls otherwise).
    const Aabb box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
    EXPECT_EQ(x->bound(box).lo, plain->bound(box).lo) << name;
    EXPECT_EQ(x->bound(box).hi, plain->bound(box).hi) << name;
    EXPECT_TRUE(x->bounds().min() == plain->bounds().min()) << name;
    EXPECT_TRUE(x->bounds().max() == plain->bounds().max()) << name;
    const FieldPtr r = x->restrict(box);
    x0->reset_evaluations();
    r->evaluate(std::span<const Vec3>(points).first(2), std::span<double>(v).first(2));
    EXPECT_EQ(x0->evaluations(), 2U) << name << ": the restricted copies stay shared";
    EXPECT_EQ(v[0], pv[0]) << name;
    EXPECT_EQ(v[1], pv[1]) << name;
  }
}

// Three levels: a blend of 4 x, then a union of 4 and a difference x minus x; `shared` uses one
// node per level, otherwise every occurrence is a separate copy (4^3 leaves).
FieldPtr sharing_tree(int level, bool shared) {
  if (level == 0) return make_point_field(Vec3(0.1, 0, 0), 1.0, power());
  auto child = [&] { return sharing_tree(level - 1, shared); };
  const FieldPtr one = child();
  std::vector<FieldPtr> kids = {one};
  for (int k = 1; k < 4; ++k) kids.push_back(shared ? one : child());
  kids.push_back(make_segment_field(Vec3(0, 0, -1), 0.3, Vec3(0, 0, 1), 0.3, power()));
  if (level == 1) return make_sum(kids);
  if (level == 2) return make_union(kids);
  return make_difference(make_intersection(kids), shared ? one : child());
}

TEST(Operators, SharedChildrenGiveTheValuesOfTheUnsharedTree) {
  const FieldPtr shared = sharing_tree(3, true);
  const FieldPtr copies = sharing_tree(3, false);
  Rng rng(11);
  const Aabb sample(Vec3(-2, -2, -2), Vec3(2, 2, 2));
  std::vector<Vec3> points;
  for (int i = 0; i < 200; ++i) points.push_back(random_point(rng, sample));
  std::vector<double> v(points.size()), cv(points.size());
  std::vector<Vec3> g(points.size()), cg(points.size());
  shared->evaluate(points, v, g);
  copies->evaluate(points, cv, cg);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(v[i], cv[i]) << i;  // bit for bit: the same additions and comparisons, in order
    ASSERT_TRUE(g[i] == cg[i]) << i;
  }
  for (int b = 0; b < 20; ++b) {
    const Vec3 c = random_point(rng, sample);
    const Aabb box(c - Vec3::Constant(0.3), c + Vec3::Constant(0.3));
    EXPECT_EQ(shared->bound(box).lo, copies->bound(box).lo);
    EXPECT_EQ(shared->bound(box).hi, copies->bound(box).hi);
    const FieldPtr r = shared->restrict(box);
    for (int i = 0; i < 5; ++i) {
      const Vec3 p = random_point(rng, box);
      ASSERT_EQ(r->value(p), copies->value(p));
    }
  }
  EXPECT_TRUE(shared->bounds().min() == copies->bounds().min());
  EXPECT_TRUE(shared->bounds().max() == copies->bounds().max());
}

TEST(Operators, EvaluationChecksCancellationPerChild) {
  const FieldPtr a = make_point_field(Vec3::Zero(), 1.0, wyvill());
  const FieldPtr b = make_point_field(Vec3(0.5, 0, 0), 1.0, wyvill());
  Context ctx;
  ctx.cancel();
  const std::vector<Vec3> points(3, Vec3::Zero());
  std::vector<double> v(points.size());
  for (const FieldPtr& f : {make_union({a, b}), make_sum({a, b}), make_difference(a, b)}) {
    a->reset_evaluations();
    EXPECT_THROW(f->evaluate(points, v, {}, &ctx), Cancelled) << f->describe();
    EXPECT_EQ(a->evaluations(), 0U) << f->describe();
  }
}

}  // namespace
}  // namespace ramiform
