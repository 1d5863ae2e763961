// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/warps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/primitives.h"
#include "ramiform/field/skeleton_field.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

using test::random_point;
constexpr double kPi = std::numbers::pi;

// A field that forwards to a child but records the box of the last bound() call and reports a
// chosen bounds() box, to check the boxes a warp passes down and up.
class Recording final : public Field {
 public:
  Recording(FieldPtr child, const Aabb& fake_bounds)
      : Field(child->iso()), child_(std::move(child)), fake_bounds_(fake_bounds) {}
  Interval bound(const Aabb& box) const override {
    last_box_ = box;
    return child_->bound(box);
  }
  Aabb bounds() const override { return fake_bounds_; }
  std::string describe() const override { return "recording"; }
  mutable Aabb last_box_;

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    child_->evaluate(points, values, gradients, ctx);
  }

 private:
  FieldPtr child_;
  Aabb fake_bounds_;
};

// One warp under test: its field maker and maps, and whether a preimage q is in the region
// where the inverse is exact.
struct Warp {
  std::string name;
  std::function<FieldPtr(FieldPtr)> make;
  std::function<Vec3(const Vec3&)> forward, inverse;
  std::function<bool(const Vec3&)> valid = [](const Vec3&) { return true; };
  std::function<bool(const Vec3&)> smooth = [](const Vec3&) { return true; };
};

Warp taper(const TaperOptions& o) {
  Warp w{"taper", [o](FieldPtr c) { return make_taper(std::move(c), o); },
         [o](const Vec3& p) { return taper_forward(p, o); },
         [o](const Vec3& p) { return taper_inverse(p, o); }};
  // r(t) has kinks at start and end.
  w.smooth = [o](const Vec3& q) {
    return std::abs(q[o.axis] - o.start) > 1e-3 && std::abs(q[o.axis] - o.end) > 1e-3;
  };
  return w;
}

Warp twist(const TwistOptions& o) {
  return {"twist", [o](FieldPtr c) { return make_twist(std::move(c), o); },
          [o](const Vec3& p) { return twist_forward(p, o); },
          [o](const Vec3& p) { return twist_inverse(p, o); }};
}

Warp bend(const BendOptions& o) {
  Warp w{"bend", [o](FieldPtr c) { return make_bend(std::move(c), o); },
         [o](const Vec3& p) { return bend_forward(p, o); },
         [o](const Vec3& p) { return bend_inverse(p, o); }};
  // Barr's inverse is exact on the axis side of the centre of curvature.
  w.valid = [o](const Vec3& q) { return 1 - o.rate * q.z() > 0.05; };
  // The bend is C0 only across the ends of the bent region (the stretch jumps there).
  w.smooth = [o](const Vec3& q) {
    return 1 - o.rate * q.z() > 0.1 && std::abs(q.y() - o.min) > 1e-3 &&
           std::abs(q.y() - o.max) > 1e-3;
  };
  return w;
}

std::vector<Warp> warps() {
  return {taper({2, -1, 1.5, 1.2, 0.4}), taper({0, 0, 2, 0.5, 2}), twist({2, 1.3, 0.2}),
          twist({1, -0.7, -1}),          twist({0, 3.0, 0}),       bend({0.5, 0, -1, 1}),
          bend({-0.8, 0.5, 0, 2}),       bend({0.3, -1, -1, 3})};
}

// Also maps whose inverse is not exact everywhere (bend angle above pi, many twist turns): their
// boxes must still be conservative for the inverse as computed.
std::vector<Warp> box_warps() {
  std::vector<Warp> w = warps();
  w.push_back(bend({2.0, 0, -1, 1}));
  w.push_back(bend({-1.2, 1, -2, 2.5}));
  w.push_back(twist({2, 10, 0}));
  return w;
}

// A smooth child: a convolution-surface segment.
FieldPtr smooth_child() {
  return make_segment_field(Vec3(0.2, -1.5, 0.1), 0.8, Vec3(-0.3, 1.8, 0.4), 0.5);
}

bool near(const Vec3& a, const Vec3& b, double tol) {
  return (a - b).norm() <= tol * (1 + b.norm());
}

TEST(Warp, ForwardAndInverseAreInverse) {
  Rng rng(1);
  const Aabb region(Vec3::Constant(-3), Vec3::Constant(3));
  for (const auto& w : warps()) {
    int valid = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 q = random_point(rng, region);
      if (w.valid(q)) {
        ++valid;
        ASSERT_TRUE(near(w.inverse(w.forward(q)), q, 1e-10)) << w.name << " " << q.transpose();
      }
      const Vec3 p = random_point(rng, region);
      const Vec3 pre = w.inverse(p);
      ASSERT_TRUE(pre.allFinite()) << w.name;
      if (w.valid(pre)) {
        ASSERT_TRUE(near(w.forward(pre), p, 1e-10)) << w.name << " " << p.transpose();
      }
    }
    EXPECT_GT(valid, 1000) << w.name;
  }
}

TEST(Warp, KnownPoints) {
  const TaperOptions t{2, 0, 1, 1, 0.5};
  EXPECT_TRUE(near(taper_forward(Vec3(1, 2, 0.5), t), Vec3(0.75, 1.5, 0.5), 1e-15));
  EXPECT_TRUE(near(taper_forward(Vec3(1, 2, 2), t), Vec3(0.5, 1, 2), 1e-15));
  EXPECT_TRUE(near(taper_forward(Vec3(1, 2, -1), t), Vec3(1, 2, -1), 1e-15));
  const TwistOptions tw{2, kPi / 2, 0};
  EXPECT_TRUE(near(twist_forward(Vec3(1, 0, 1), tw), Vec3(0, 1, 1), 1e-15));
  EXPECT_TRUE(near(twist_forward(Vec3(1, 0, 2), tw), Vec3(-1, 0, 2), 1e-15));
  EXPECT_TRUE(near(twist_forward(Vec3(0, 1, -1), tw), Vec3(1, 0, -1), 1e-15));
  // Barr's bend: the y axis becomes a circle of radius 1/k around (y0, 1/k) in the bent region
  // and continues along the tangent beyond it.
  const BendOptions b{0.5, 0, -1, 1};
  const Vec3 end = bend_forward(Vec3(0.3, 1, 0), b);
  EXPECT_TRUE(near(end, Vec3(0.3, std::sin(0.5) / 0.5, (1 - std::cos(0.5)) / 0.5), 1e-15));
  EXPECT_TRUE(near(bend_forward(Vec3(0.3, 2.5, 0), b),
                   end + 1.5 * Vec3(0, std::cos(0.5), std::sin(0.5)), 1e-15));
  EXPECT_TRUE(near(bend_forward(Vec3(0, 0, 0.7), b), Vec3(0, 0, 0.7), 1e-15));
  Rng rng(4);
  for (int i = 0; i < 100; ++i) {
    const double y = rng.uniform(-1, 1), z = rng.uniform(-1, 1.5);
    const Vec3 p = bend_forward(Vec3(0, y, z), b);
    EXPECT_NEAR((Eigen::Vector2d(p.y(), p.z()) - Eigen::Vector2d(0, 2)).norm(), 2 - z, 1e-13);
  }
}

TEST(Warp, FieldIsChildAtInverse) {
  Rng rng(2);
  const FieldPtr child = make_box_field(Vec3(0.1, 0.2, 0.3), Vec3(1, 0.5, 1.5), 0.2);
  const Aabb region(Vec3::Constant(-3), Vec3::Constant(3));
  for (const auto& w : warps()) {
    const FieldPtr f = w.make(child);
    EXPECT_EQ(f->iso(), child->iso());
    std::vector<Vec3> pts;
    for (int i = 0; i < 300; ++i) pts.push_back(random_point(rng, region));
    std::vector<double> v(pts.size());
    f->evaluate(pts, v);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      ASSERT_NEAR(v[i], child->value(w.inverse(pts[i])), 1e-14) << w.name;
    }
    // The child's surface points map to the warped surface: the box's face centres.
    for (int axis = 0; axis < 3; ++axis) {
      for (const double side : {-1.0, 1.0}) {
        Vec3 face(0.1, 0.2, 0.3);
        face[axis] += side * Vec3(1, 0.5, 1.5)[axis];
        if (!w.valid(face)) continue;
        EXPECT_NEAR(f->value(w.forward(face)), child->iso(), 1e-12) << w.name << " face " << axis;
      }
    }
  }
}

TEST(Warp, TwistedBoxCorners) {
  // A box twisted a quarter turn per unit: its (rounded) corner near the top maps onto the
  // rotated corner, and the untwisted corner position is no longer inside.
  const Vec3 half(1, 0.5, 1);
  const FieldPtr box = make_box_field(Vec3::Zero(), half, 0.05);
  const FieldPtr f = make_twist(box, {2, kPi / 2, 0});
  const Vec3 corner =
      half - Vec3::Constant(0.1);  // just inside the rounded corner; z = 0.9: rotated by 0.9 pi/2
  ASSERT_TRUE(box->is_inside(corner));
  const double a = kPi / 2 * corner.z();
  const Vec3 rotated(std::cos(a) * corner.x() - std::sin(a) * corner.y(),
                     std::sin(a) * corner.x() + std::cos(a) * corner.y(), corner.z());
  EXPECT_TRUE(f->is_inside(rotated));
  EXPECT_NEAR(f->value(rotated), box->value(corner), 1e-14);
  EXPECT_FALSE(f->is_inside(corner));
}

TEST(Warp, GradientsMatchCentralDifferences) {
  Rng rng(3);
  const FieldPtr child = smooth_child();
  const Aabb region(Vec3(-2, -3, -2), Vec3(2, 3, 2));
  for (const auto& w : warps()) {
    const FieldPtr f = w.make(child);
    int checked = 0;
    for (int i = 0; i < 400 && checked < 60; ++i) {
      const Vec3 p = random_point(rng, region);
      const Vec3 q = w.inverse(p);
      if (!w.smooth(q) || child->value(q) < 0.05) continue;
      const Vec3 g = f->gradient(p);
      const Vec3 fd = test::central_gradient(*f, p, 1e-6);
      ASSERT_LT((g - fd).norm(), 1e-5 * (1 + g.norm()))
          << w.name << " at " << p.transpose() << ": " << g.transpose() << " vs " << fd.transpose();
      ++checked;
    }
    EXPECT_GT(checked, 20) << w.name;
  }
}

TEST(Warp, IdentityParametersReproduceTheChild) {
  const FieldPtr child = smooth_child();
  const std::vector<FieldPtr> identities = {make_taper(child, {2, -1, 1, 1, 1}),
                                            make_twist(child, {2, 0, 0}),
                                            make_bend(child, {0, 0, -1, 1})};
  Rng rng(5);
  for (const auto& f : identities) {
    for (int i = 0; i < 200; ++i) {
      const Vec3 p = random_point(rng, Aabb(Vec3::Constant(-3), Vec3::Constant(3)));
      ASSERT_EQ(f->value(p), child->value(p)) << f->describe();
      ASSERT_EQ(f->gradient(p), child->gradient(p)) << f->describe();
    }
  }
}

TEST(Warp, BoundPassesAConservativeInverseBox) {
  Rng rng(6);
  const FieldPtr child = smooth_child();
  for (const auto& w : box_warps()) {
    const auto rec =
        std::make_shared<Recording>(child, Aabb(Vec3::Constant(-1), Vec3::Constant(1)));
    const FieldPtr f = w.make(rec);
    for (int b = 0; b < 150; ++b) {
      const Vec3 c = random_point(rng, Aabb(Vec3::Constant(-4), Vec3::Constant(4)));
      Vec3 half;
      for (int a = 0; a < 3; ++a) half[a] = std::exp(rng.uniform(std::log(0.01), std::log(4.0)));
      const Aabb box(c - half, c + half);
      (void)f->bound(box);
      const Aabb down = rec->last_box_;
      for (int i = 0; i < 108; ++i) {
        const Vec3 p =
            i < 8 ? box.corner(static_cast<Aabb::CornerType>(i)) : random_point(rng, box);
        const Vec3 q = w.inverse(p);
        ASSERT_TRUE(down.contains(q))
            << w.name << ": box " << box.min().transpose() << " / " << box.max().transpose()
            << " passes " << down.min().transpose() << " / " << down.max().transpose()
            << " but W^-1(" << p.transpose() << ") = " << q.transpose();
      }
    }
    // bound() of the warp is the child's bound of that box: conservative for the warp's values.
    const Aabb box(Vec3(-0.5, -1, -0.5), Vec3(0.7, 1.2, 0.6));
    const Interval iv = f->bound(box);
    for (int i = 0; i < 200; ++i)
      ASSERT_TRUE(iv.contains(f->value(random_point(rng, box)))) << w.name;
  }
}

TEST(Warp, BoundsContainTheForwardImage) {
  Rng rng(7);
  const FieldPtr child = smooth_child();
  for (const auto& w : box_warps()) {
    for (int b = 0; b < 100; ++b) {
      const Vec3 c = random_point(rng, Aabb(Vec3::Constant(-3), Vec3::Constant(3)));
      Vec3 half;
      for (int a = 0; a < 3; ++a) half[a] = std::exp(rng.uniform(std::log(0.01), std::log(3.0)));
      const Aabb child_box(c - half, c + half);
      const FieldPtr f = w.make(std::make_shared<Recording>(child, child_box));
      const Aabb up = f->bounds();
      for (int i = 0; i < 108; ++i) {
        const Vec3 q = i < 8 ? child_box.corner(static_cast<Aabb::CornerType>(i))
                             : random_point(rng, child_box);
        ASSERT_TRUE(up.contains(w.forward(q)))
            << w.name << ": W(" << q.transpose() << ") = " << w.forward(q).transpose()
            << " outside " << up.min().transpose() << " / " << up.max().transpose();
      }
    }
    // And with a real child: every inside point of the warped field lies in bounds().
    const FieldPtr f = w.make(make_box_field(Vec3(0.1, 0.2, 0.3), Vec3(1, 1.5, 0.8), 0.2));
    const Aabb up = f->bounds();
    int inside = 0;
    for (int i = 0; i < 4000; ++i) {
      const Vec3 p = random_point(rng, Aabb(Vec3::Constant(-4), Vec3::Constant(4)));
      if (f->is_inside(p)) {
        ++inside;
        ASSERT_TRUE(up.contains(p)) << w.name;
      }
    }
    EXPECT_GT(inside, 20) << w.name;
  }
}

TEST(Warp, RestrictKeepsValuesInTheBox) {
  const FieldPtr child = make_skeleton_field(test::y_fork());
  const Aabb box(Vec3(-2, -2, 8), Vec3(2, 2, 12));
  Rng rng(8);
  for (const auto& w : {twist({2, 0.1, 10}), taper({2, 0, 20, 1, 0.5}), bend({0.05, 0, -5, 5})}) {
    const FieldPtr f = w.make(child);
    const FieldPtr r = f->restrict(box);
    for (int i = 0; i < 100; ++i) {
      const Vec3 p = random_point(rng, box);
      ASSERT_NEAR(r->value(p), f->value(p), 1e-12 * (1 + std::abs(f->value(p)))) << w.name;
    }
  }
}

TEST(Warp, BendIsFiniteEverywhere) {
  const BendOptions b{0.5, 0, -1, 1};
  const FieldPtr f = make_bend(smooth_child(), b);
  std::vector<Vec3> pts = {Vec3(0, 0, 2), Vec3(0, 0, 4), Vec3(0, 3, 2), Vec3(0, -10, 2.0000001)};
  Rng rng(9);
  for (int i = 0; i < 500; ++i)
    pts.push_back(random_point(rng, Aabb(Vec3::Constant(-10), Vec3::Constant(10))));
  for (const Vec3& p : pts) {
    ASSERT_TRUE(bend_inverse(p, b).allFinite()) << p.transpose();
    ASSERT_TRUE(bend_forward(p, b).allFinite()) << p.transpose();
    ASSERT_TRUE(std::isfinite(f->value(p)));
    ASSERT_TRUE(f->gradient(p).allFinite()) << p.transpose();
  }
}

TEST(Warp, BadArgumentsThrow) {
  const FieldPtr child = smooth_child();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)make_taper(nullptr, {}), InvalidArgument);
  EXPECT_THROW((void)make_taper(child, {3, 0, 1, 1, 0.5}), InvalidArgument);
  EXPECT_THROW((void)make_taper(child, {2, 1, 1, 1, 0.5}), InvalidArgument);
  EXPECT_THROW((void)make_taper(child, {2, 0, 1, 0, 0.5}), InvalidArgument);
  EXPECT_THROW((void)make_taper(child, {2, 0, 1, 1, -0.5}), InvalidArgument);
  EXPECT_THROW((void)make_taper(child, {2, nan, 1, 1, 0.5}), InvalidArgument);
  EXPECT_THROW((void)make_twist(nullptr, {}), InvalidArgument);
  EXPECT_THROW((void)make_twist(child, {-1, 1, 0}), InvalidArgument);
  EXPECT_THROW((void)make_twist(child, {2, nan, 0}), InvalidArgument);
  EXPECT_THROW((void)make_bend(nullptr, {}), InvalidArgument);
  EXPECT_THROW((void)make_bend(child, {nan, 0, -1, 1}), InvalidArgument);
  EXPECT_THROW((void)make_bend(child, {0.5, 2, -1, 1}), InvalidArgument);
  EXPECT_THROW((void)make_bend(child, {0.5, 0, 1, -1}), InvalidArgument);
  try {
    (void)make_taper(child, {2, 0, 1, 1, -0.5});
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("scale_end"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ramiform
