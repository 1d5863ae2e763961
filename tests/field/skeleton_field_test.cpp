// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/skeleton_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

using test::check_bound_conservative;
using test::check_bounds_contain_inside;
using test::grown;
using test::point_near;
using test::random_point;
using test::random_unit;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// tolerances.h: the fade-out changes a primitive's value by "at most about 2.5x" kKernelCutoff
// times iso; "about" taken as 10 %.
constexpr double kFadeChange = 4.0 * tol::kKernelCutoff;  // tolerances.h: at most 4x

SkeletonFieldOptions distance(const Kernel& k, double iso = 0.0) {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kDistance;
  o.kernel = k;
  o.iso = iso;
  return o;
}

SkeletonFieldOptions convolution(double c = 0.0, double iso = 0.0) {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kConvolution;
  o.kernel = Kernel{KernelKind::kCauchy, c};
  o.iso = iso;
  return o;
}

std::string name(const SkeletonFieldOptions& o) {
  return (o.surface == SurfaceKind::kDistance ? "distance/" : "convolution/") +
         kernel_name(o.kernel.kind) + ":" + std::to_string(o.kernel.parameter) +
         " iso " + std::to_string(o.iso);
}

// Every field configuration the generic property tests run over.
std::vector<SkeletonFieldOptions> all_options() {
  std::vector<SkeletonFieldOptions> out;
  for (const Kernel& k : test::distance_kernels()) out.push_back(distance(k));
  out.push_back(distance(Kernel{KernelKind::kWyvill, 0.0}, 0.3));
  out.push_back(convolution());
  out.push_back(convolution(2.0, 0.5));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Independent reference for distance surfaces: f = sum_i w_i k(d_i / R_i), d_i by brute force,
// R_i = r_i(t) / x_iso at the closest point, infinite kernels cut off at support(iso) with a
// fade from 0.8 support (the reference marks points in that band instead of guessing the fade).
struct Reference {
  double value = 0;
  bool in_fade = false;     ///< some primitive is in its fade band: the value is approximate
  bool near_break = false;  ///< near a kink of some primitive (gradient check unsafe)
};

Reference reference_distance(const Skeleton& s, const SkeletonFieldOptions& o,
                             std::span<const double> weights, const Vec3& p) {
  const double iso = o.iso != 0 ? o.iso : test::reference_iso(o.kernel.kind);
  const double x_iso = o.kernel.x_at(iso);
  const bool infinite = test::is_infinite_kernel(o.kernel.kind);
  const double support = o.kernel.support(iso);
  Reference ref;
  // `t_raw`: the unclamped projection parameter (the gradient has a kink where it crosses 0 or
  // 1 when the radii differ); only primitives that contribute can make a kink.
  auto add = [&](double w, double d, double r, double t_raw, bool segment) {
    const double x = d * x_iso / r;
    const bool contributes = infinite ? x <= support * (1 + 1e-3) : x < 1 + 1e-3;
    if (contributes) {
      if (d < 1e-3 * r) ref.near_break = true;
      if (segment && (std::abs(t_raw) < 1e-3 || std::abs(t_raw - 1) < 1e-3)) ref.near_break = true;
      for (double b : {1.0 / 3, 1.0, 0.8 * support, support}) {
        if (std::abs(x - b) < 1e-3 * std::max(1.0, b)) ref.near_break = true;
      }
    }
    if (infinite && x > support) return;
    if (infinite && x >= 0.8 * support) ref.in_fade = true;
    ref.value += w * test::reference_kernel(o.kernel.kind, o.kernel.parameter, x);
  };
  std::vector<int> degree(s.nodes.size(), 0);
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    const auto& na = s.nodes[s.edges[e][0]];
    const auto& nb = s.nodes[s.edges[e][1]];
    ++degree[s.edges[e][0]];
    ++degree[s.edges[e][1]];
    long double t = 0;
    const double d = test::brute_distance(p, na.position, nb.position, &t);
    const double r = static_cast<double>((1 - t) * na.radius + t * nb.radius);
    const Vec3 ab = nb.position - na.position;
    const double t_raw = (p - na.position).dot(ab) / ab.squaredNorm();
    add(weights.empty() ? 1.0 : weights[e], d, r, t_raw, true);
  }
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (degree[i] == 0) add(1.0, (p - s.nodes[i].position).norm(), s.nodes[i].radius, 0.5, false);
  }
  return ref;
}

// lambda of the convolution surface for a segment of mean radius r (skeleton_field.h).
double lambda(double c, double iso, double r) {
  return 2 * c * iso * std::pow(1 + c * c, 1.5) / (std::numbers::pi * r);
}

// ---------------------------------------------------------------------------------------------
TEST(SkeletonFieldOptions, ResolvedFillsDefaults) {
  const SkeletonFieldOptions def = SkeletonFieldOptions{}.resolved();
  EXPECT_EQ(def.surface, SurfaceKind::kConvolution);
  EXPECT_EQ(def.kernel.kind, KernelKind::kCauchy);
  EXPECT_EQ(def.iso, 1.0);
  const SkeletonFieldOptions w = distance(Kernel{KernelKind::kWyvill, 0.0}).resolved();
  EXPECT_EQ(w.iso, 0.5);
  EXPECT_EQ(distance(Kernel{KernelKind::kInversePower, 0.0}).resolved().iso, 1.0);
  EXPECT_EQ(distance(Kernel{KernelKind::kBlinn, 0.0}, 0.25).resolved().iso, 0.25);
}

TEST(SkeletonFieldOptions, BadOptionsThrow) {
  // A convolution surface needs the Cauchy kernel.
  for (KernelKind k : {KernelKind::kWyvill, KernelKind::kBlinn, KernelKind::kMetaball,
                       KernelKind::kInversePower}) {
    SkeletonFieldOptions o = convolution();
    o.kernel = Kernel{k, 0.0};
    EXPECT_THROW((void)o.resolved(), InvalidArgument) << kernel_name(k);
    EXPECT_THROW((void)make_point_field(Vec3::Zero(), 1.0, o), InvalidArgument);
  }
  EXPECT_THROW((void)distance(Kernel{KernelKind::kBlinn, -1.0}).resolved(), InvalidArgument);
  EXPECT_THROW((void)convolution(-1.0).resolved(), InvalidArgument);
  EXPECT_THROW((void)distance(Kernel{KernelKind::kInversePower, 1.5}).resolved(), InvalidArgument);
  for (double iso : {kNaN, kInf, -1.0}) {
    EXPECT_THROW((void)distance(Kernel{KernelKind::kWyvill, 0.0}, iso).resolved(), InvalidArgument)
        << iso;
    EXPECT_THROW((void)convolution(0.0, iso).resolved(), InvalidArgument) << iso;
  }
  // An iso a bounded kernel can never reach.
  EXPECT_THROW((void)make_point_field(Vec3::Zero(), 1.0, distance(Kernel{KernelKind::kWyvill, 0.0}, 1.0)),
               InvalidArgument);
}

// Bad geometric arguments are rejected with InvalidArgument (or InputError when the primitive is
// validated as a one-element skeleton): either is acceptable, anything else is not.
#define EXPECT_REJECTED(...)                                                               \
  do {                                                                                     \
    bool rejected = false;                                                                 \
    try {                                                                                  \
      __VA_ARGS__;                                                                         \
    } catch (const InvalidArgument&) {                                                     \
      rejected = true;                                                                     \
    } catch (const InputError&) {                                                          \
      rejected = true;                                                                     \
    }                                                                                      \
    EXPECT_TRUE(rejected) << #__VA_ARGS__ " was not rejected with InvalidArgument or InputError"; \
  } while (false)

TEST(SkeletonField, BadArgumentsThrow) {
  const auto opts = distance(Kernel{KernelKind::kWyvill, 0.0});
  for (double r : {0.0, -1.0, kNaN, kInf}) {
    SCOPED_TRACE(r);
    EXPECT_REJECTED((void)make_point_field(Vec3::Zero(), r, opts));
    EXPECT_REJECTED((void)make_point_field(Vec3::Zero(), r));
    EXPECT_REJECTED((void)make_segment_field(Vec3::Zero(), r, Vec3(1, 0, 0), 1.0));
    EXPECT_REJECTED((void)make_segment_field(Vec3::Zero(), 1.0, Vec3(1, 0, 0), r, opts));
  }
  EXPECT_REJECTED((void)make_point_field(Vec3(kNaN, 0, 0), 1.0, opts));
  // A zero-length segment is either rejected or acts as the point primitive.
  for (const auto& o : {opts, convolution()}) {
    try {
      const FieldPtr deg = make_segment_field(Vec3::Zero(), 1.0, Vec3::Zero(), 1.0, o);
      const FieldPtr pt = make_point_field(Vec3::Zero(), 1.0, o);
      for (double x : {0.0, 0.5, 1.0, 1.5}) {
        EXPECT_NEAR(deg->value(Vec3(x, 0, 0)), pt->value(Vec3(x, 0, 0)), 1e-14) << name(o);
        EXPECT_TRUE(is_finite(deg->gradient(Vec3(x, 0, 0))));
      }
    } catch (const InvalidArgument&) {
    } catch (const InputError&) {
    }
  }

  const Skeleton fork = test::y_fork();
  for (const auto& o : {opts, convolution()}) {
    const std::vector<double> negative = {1.0, -0.5, 1.0};
    const std::vector<double> nan = {1.0, kNaN, 1.0};
    const std::vector<double> inf = {1.0, 1.0, kInf};
    const std::vector<double> too_few = {1.0, 1.0};
    const std::vector<double> too_many = {1.0, 1.0, 1.0, 1.0};
    for (const auto* w : {&negative, &nan, &inf, &too_few, &too_many}) {
      SCOPED_TRACE(name(o));
      EXPECT_REJECTED((void)make_skeleton_field(fork, o, *w));
    }
    const std::vector<double> ok = {1.0, 0.0, 2.0};
    EXPECT_NO_THROW((void)make_skeleton_field(fork, o, ok));
  }
  // An invalid skeleton is an InputError.
  Skeleton bad = fork;
  bad.nodes[2].radius = -1;
  EXPECT_THROW((void)make_skeleton_field(bad, opts), InputError);
  EXPECT_THROW((void)make_skeleton_field(Skeleton{}, opts), InputError);
}

TEST(SkeletonField, EvaluateSizeMismatchThrows) {
  const FieldPtr f = make_skeleton_field(test::y_fork());
  std::vector<Vec3> pts(5, Vec3::Zero());
  std::vector<double> vals(4);
  std::vector<Vec3> grads(3);
  EXPECT_THROW(f->evaluate(pts, vals), InvalidArgument);
  vals.resize(5);
  EXPECT_THROW(f->evaluate(pts, vals, grads), InvalidArgument);
  grads.resize(6);
  EXPECT_THROW(f->evaluate(pts, vals, grads), InvalidArgument);
  grads.resize(5);
  EXPECT_NO_THROW(f->evaluate(pts, vals, grads));
  EXPECT_NO_THROW(f->evaluate({}, {}));
}

// ---------------------------------------------------------------------------------------------
TEST(DistanceSurface, LonePointHasExactRadius) {
  Rng rng(1);
  for (const Kernel& k : test::distance_kernels()) {
    for (double iso_opt : {0.0, 0.3}) {
      const auto o = distance(k, iso_opt);
      const double iso = o.resolved().iso;
      for (double r : {0.01, 1.0, 7.5}) {
        const Vec3 c(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-10, 10));
        const FieldPtr f = make_point_field(c, r, o);
        EXPECT_EQ(f->iso(), iso);
        for (int i = 0; i < 20; ++i) {
          const Vec3 dir = random_unit(rng);
          EXPECT_NEAR(f->value(c + r * dir), iso, 1e-12 * iso)
              << kernel_name(k.kind) << " iso " << iso << " r " << r;
          EXPECT_TRUE(f->is_inside(c + 0.99 * r * dir)) << kernel_name(k.kind);
          EXPECT_FALSE(f->is_inside(c + 1.01 * r * dir)) << kernel_name(k.kind);
        }
      }
    }
  }
}

TEST(DistanceSurface, LoneSegmentSurfaceFollowsInterpolatedRadius) {
  const Vec3 a(1, -2, 0.5), b(4, 3, 2);
  const double ra = 1.0, rb = 0.4;
  Rng rng(2);
  for (const Kernel& k : test::distance_kernels()) {
    const auto o = distance(k);
    const FieldPtr f = make_segment_field(a, ra, b, rb, o);
    const double iso = f->iso();
    for (int i = 0; i < 50; ++i) {
      const double t = rng.uniform(0.01, 0.99);
      const Vec3 perp = (b - a).unitOrthogonal();
      const Vec3 n = Eigen::AngleAxisd(rng.uniform(0, 6.3), (b - a).normalized()) * perp;
      const double r = (1 - t) * ra + t * rb;
      const Vec3 q = a + t * (b - a);
      EXPECT_NEAR(f->value(q + r * n), iso, 1e-12 * iso) << kernel_name(k.kind) << " t " << t;
      EXPECT_TRUE(f->is_inside(q + 0.99 * r * n));
      EXPECT_FALSE(f->is_inside(q + 1.01 * r * n));
    }
    // Beyond the ends: the end caps are spheres of the end radii.
    const Vec3 dir = (b - a).normalized();
    EXPECT_NEAR(f->value(b + rb * dir), iso, 1e-12 * iso);
    EXPECT_NEAR(f->value(a - ra * dir), iso, 1e-12 * iso);
  }
}

TEST(DistanceSurface, MatchesBruteForceReference) {
  const std::vector<Skeleton> skeletons = {test::y_fork(0.7), test::helix(24, 0.5),
                                           test::random_tree(5, 30),
                                           test::single_segment(Vec3(0, 0, 0), Vec3(3, 1, 2), 1.2, 0.3)};
  Rng rng(3);
  for (const Kernel& k : test::distance_kernels()) {
    const auto o = distance(k);
    const double iso = o.resolved().iso;
    for (const Skeleton& s : skeletons) {
      const FieldPtr f = make_skeleton_field(s, o);
      const Aabb box = grown(bounding_box(s), 2.0);
      int compared = 0;
      for (int i = 0; i < 300; ++i) {
        const Vec3 p = i % 2 == 0 ? point_near(s, rng, 3.0) : random_point(rng, box);
        const Reference ref = reference_distance(s, o, {}, p);
        const double v = f->value(p);
        if (ref.in_fade) {
          // The fade changes a value by at most about 2.5 kKernelCutoff * iso per primitive.
          EXPECT_NEAR(v, ref.value, 2 * kFadeChange * iso * s.edges.size());
          continue;
        }
        ++compared;
        EXPECT_NEAR(v, ref.value, 1e-10 * std::max(std::abs(ref.value), iso))
            << kernel_name(k.kind) << " p " << p.transpose();
      }
      EXPECT_GT(compared, 50) << kernel_name(k.kind);
    }
  }
}

TEST(DistanceSurface, InfiniteKernelsVanishBeyondSupport) {
  for (const Kernel& k : test::distance_kernels()) {
    if (!test::is_infinite_kernel(k.kind)) continue;
    const auto o = distance(k);
    const double iso = o.resolved().iso;
    const double r = 0.8;
    const FieldPtr f = make_point_field(Vec3(1, 2, 3), r, o);
    const double big_r = r / k.x_at(iso);
    const double cut = k.support(iso) * big_r;
    EXPECT_EQ(f->value(Vec3(1, 2, 3) + Vec3(cut * 1.001, 0, 0)), 0.0) << kernel_name(k.kind);
    EXPECT_EQ(f->value(Vec3(1, 2, 3) + Vec3(0, 0, -cut * 3)), 0.0) << kernel_name(k.kind);
    // Unchanged well inside the fade start.
    const double d = 0.79 * cut;
    EXPECT_NEAR(f->value(Vec3(1, 2, 3) + Vec3(0, d, 0)),
                test::reference_kernel(k.kind, k.parameter, d / big_r), 1e-14);
    // In the band the change is small and the value decreases monotonically.
    double prev = f->value(Vec3(1, 2, 3) + Vec3(0.8 * cut, 0, 0));
    for (double fr = 0.805; fr <= 1.0; fr += 0.005) {
      const double v = f->value(Vec3(1, 2, 3) + Vec3(fr * cut, 0, 0));
      EXPECT_LE(v, prev) << kernel_name(k.kind) << " " << fr;
      EXPECT_GE(v, 0.0);
      EXPECT_NEAR(v, test::reference_kernel(k.kind, k.parameter, fr * cut / big_r), kFadeChange * iso)
          << kernel_name(k.kind) << ":" << k.parameter << " at " << fr << " of the cutoff";
      prev = v;
    }
  }
}

TEST(DistanceSurface, ExactIsoIsNotInside) {
  // Inverse power (alpha 3), r = 1: R = 1 / x_at(1) = 1, so at distance 1, x = 1 and k = 1 = iso
  // with no rounding anywhere.
  const FieldPtr f = make_point_field(Vec3::Zero(), 1.0, distance(Kernel{KernelKind::kInversePower, 0.0}));
  const Vec3 p(1, 0, 0);
  const double v = f->value(p);
  EXPECT_EQ(v, f->iso());
  EXPECT_FALSE(f->is_inside(p));
  EXPECT_TRUE(f->is_inside(Vec3(0.999, 0, 0)));
  // is_inside is exactly value > iso.
  Rng rng(4);
  const FieldPtr g = make_skeleton_field(test::y_fork());
  for (int i = 0; i < 500; ++i) {
    const Vec3 q = random_point(rng, grown(bounding_box(test::y_fork()), 1.0));
    EXPECT_EQ(g->is_inside(q), g->value(q) > g->iso());
  }
}

TEST(DistanceSurface, SkeletonWithIsolatedNodeAddsPointPrimitive) {
  Skeleton s = test::single_segment(Vec3(0, 0, 0), Vec3(0, 0, 5), 1.0, 1.0);
  s.nodes.push_back({Vec3(10, 0, 0), 0.7});
  for (const auto& o : {distance(Kernel{KernelKind::kWyvill, 0.0}), distance(Kernel{KernelKind::kBlinn, 0.0}),
                        convolution()}) {
    const FieldPtr f = make_skeleton_field(s, o);
    const FieldPtr seg = make_segment_field(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 5), 1.0, o);
    const FieldPtr pt = make_point_field(Vec3(10, 0, 0), 0.7, o);
    Rng rng(5);
    for (int i = 0; i < 200; ++i) {
      const Vec3 p = random_point(rng, Aabb(Vec3(-3, -3, -3), Vec3(13, 3, 8)));
      EXPECT_NEAR(f->value(p), seg->value(p) + pt->value(p), 1e-13 * f->iso()) << name(o);
    }
    // The isolated node has its surface at its radius (the segment is too far to matter much
    // for compact kernels: check exactly only for those).
    if (o.surface == SurfaceKind::kDistance && o.kernel.kind == KernelKind::kWyvill) {
      EXPECT_NEAR(f->value(Vec3(10.7, 0, 0)), f->iso(), 1e-12);
    }
  }
}

TEST(DistanceSurface, GradientsMatchCentralDifferences) {
  const std::vector<Skeleton> skeletons = {test::y_fork(0.7), test::random_tree(8, 25),
                                           test::single_segment(Vec3(0, 0, 0), Vec3(3, 1, 2), 1.2, 0.3)};
  Rng rng(6);
  for (const Kernel& k : test::distance_kernels()) {
    const auto o = distance(k);
    const double iso = o.resolved().iso;
    for (const Skeleton& s : skeletons) {
      const FieldPtr f = make_skeleton_field(s, o);
      int checked = 0;
      for (int i = 0; i < 400 && checked < 150; ++i) {
        const Vec3 p = point_near(s, rng, 4.0);
        const Reference ref = reference_distance(s, o, {}, p);
        if (ref.near_break) continue;
        ++checked;
        const double r = 0.3;  // smallest radius in these skeletons (length scale)
        const Vec3 g = f->gradient(p);
        const Vec3 fd = test::central_gradient(*f, p, 1e-6 * r);
        EXPECT_LE((g - fd).norm(), 1e-5 * g.norm() + 1e-6 * iso / r)
            << kernel_name(k.kind) << ":" << k.parameter << " p " << p.transpose() << " g "
            << g.transpose() << " fd " << fd.transpose();
      }
      EXPECT_GT(checked, 100) << kernel_name(k.kind);
    }
  }
}

// ---------------------------------------------------------------------------------------------
TEST(ConvolutionSurface, LongSegmentIsCylinderOfRadius) {
  for (double r : {0.05, 1.0, 3.0}) {
    for (double c : {0.0, 0.5, 2.0}) {
      for (double iso : {0.0, 0.2}) {
        const auto o = convolution(c, iso);
        const FieldPtr f = make_segment_field(Vec3(-50 * r, 0, 0), r, Vec3(50 * r, 0, 0), r, o);
        const double fiso = f->iso();
        for (const Vec3& n : {Vec3(0, 1, 0), Vec3(0, 0, -1), Vec3(0, 0.6, 0.8)}) {
          double lo = 0.5 * r, hi = 2 * r;
          ASSERT_GT(f->value(lo * n), fiso);
          ASSERT_LE(f->value(hi * n), fiso);
          for (int it = 0; it < 100; ++it) {
            const double m = (lo + hi) / 2;
            (f->value(m * n) > fiso ? lo : hi) = m;
          }
          EXPECT_NEAR(lo / r, 1.0, 1e-3) << "r " << r << " c " << c << " iso " << iso;
        }
      }
    }
  }
}

TEST(ConvolutionSurface, ValueIsWeightLambdaIntegral) {
  Rng rng(7);
  const Vec3 a(0.5, -1, 2), b(6, 2, -1);
  for (double c : {0.0, 0.7, 3.0}) {
    const double cc = c == 0 ? 1.0 : c;
    for (double iso : {0.0, 0.35}) {
      const auto o = convolution(c, iso);
      const double fiso = o.resolved().iso;
      const double ra = 0.9, rb = 0.3;
      const FieldPtr f = make_segment_field(a, ra, b, rb, o);
      const double rm = (ra + rb) / 2;
      const double lam = lambda(cc, fiso, rm);
      for (int i = 0; i < 200; ++i) {
        const double t = rng.uniform(0.0, 1.0);
        const Vec3 p = a + t * (b - a) + rng.uniform(0, 2 * rm) * random_unit(rng);
        const double expected = lam * cauchy_segment_integral(p, a, b, cc / rm);
        EXPECT_NEAR(f->value(p), expected, 1e-12 * std::max(expected, fiso))
            << "c " << c << " iso " << fiso << " p " << p.transpose();
      }
    }
  }
}

TEST(ConvolutionSurface, WeightedSkeletonValueIsWeightLambdaIntegral) {
  // A two-edge skeleton with weights: f = sum_i w_i lambda_i F_i, each with its own mean radius.
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 1.0}, {Vec3(0, 0, 6), 0.6}, {Vec3(3, 0, 10), 0.4}};
  s.edges = {{0, 1}, {1, 2}};
  const std::vector<double> w = {2.5, 0.75};
  for (double c : {0.0, 1.7}) {
    const double cc = c == 0 ? 1.0 : c;
    const auto o = convolution(c, 0.0);
    const FieldPtr f = make_skeleton_field(s, o, w);
    Rng rng(21);
    for (int i = 0; i < 200; ++i) {
      const Vec3 p = point_near(s, rng, 1.5);
      double expected = 0;
      bool faint = false;  // a primitive near its cutoff: the fade may apply
      for (std::size_t e = 0; e < 2; ++e) {
        const auto& na = s.nodes[s.edges[e][0]];
        const auto& nb = s.nodes[s.edges[e][1]];
        const double rm = (na.radius + nb.radius) / 2;
        const double part = lambda(cc, 1.0, rm) * cauchy_segment_integral(p, na.position, nb.position, cc / rm);
        faint |= part < 1e-3;
        expected += w[e] * part;
      }
      EXPECT_NEAR(f->value(p), expected, 1e-12 * std::max(expected, 1.0) + (faint ? 3 * kFadeChange : 0.0))
          << "c " << c << " " << p.transpose();
    }
  }
}

TEST(ConvolutionSurface, EdgeWeightsScaleLinearly) {
  const Skeleton s = test::y_fork();
  const auto o = convolution();
  const std::vector<double> w = {2.0, 0.5, 0.0};
  const FieldPtr f = make_skeleton_field(s, o, w);
  const FieldPtr f1 = make_skeleton_field(s, o);
  const std::vector<double> three = {3.0, 3.0, 3.0};
  const FieldPtr f3 = make_skeleton_field(s, o, three);
  std::vector<FieldPtr> seg;
  for (const auto& e : s.edges) {
    seg.push_back(make_segment_field(s.nodes[e[0]].position, s.nodes[e[0]].radius,
                                     s.nodes[e[1]].position, s.nodes[e[1]].radius, o));
  }
  Rng rng(8);
  for (int i = 0; i < 300; ++i) {
    const Vec3 p = point_near(s, rng, 2.0);
    // Where a primitive is faint (near its cutoff) a weight may move the cutoff: allow the
    // documented fade change there.
    bool faint = false;
    for (const auto& g : seg) faint |= g->value(p) > 0 && g->value(p) < 1e-3;
    const double slack = faint ? 3 * 3 * tol::kKernelCutoff : 0.0;
    const double expected = 2.0 * seg[0]->value(p) + 0.5 * seg[1]->value(p);
    EXPECT_NEAR(f->value(p), expected, 1e-12 * std::max(expected, 1.0) + slack) << p.transpose();
    EXPECT_NEAR(f3->value(p), 3 * f1->value(p), 1e-12 * std::max(f1->value(p), 1.0) + slack);
    if (faint) continue;
    const Vec3 g = f->gradient(p);
    const Vec3 ge = 2.0 * seg[0]->gradient(p) + 0.5 * seg[1]->gradient(p);
    EXPECT_LE((g - ge).norm(), 1e-12 * std::max(ge.norm(), 1.0));
  }
  // The same for a distance surface.
  const auto od = distance(Kernel{KernelKind::kWyvill, 0.0});
  const FieldPtr fd = make_skeleton_field(s, od, w);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p = point_near(s, rng, 2.0);
    const Reference ref = reference_distance(s, od, w, p);
    EXPECT_NEAR(fd->value(p), ref.value, 1e-10);
  }
}

TEST(ConvolutionSurface, GradientsMatchCentralDifferences) {
  const std::vector<Skeleton> skeletons = {test::y_fork(0.7), test::random_tree(9, 40), test::helix(30, 0.4)};
  Rng rng(9);
  for (const auto& o : {convolution(), convolution(2.5, 0.3)}) {
    const double iso = o.resolved().iso;
    for (const Skeleton& s : skeletons) {
      const FieldPtr f = make_skeleton_field(s, o);
      double rmin = kInf;
      for (const auto& n : s.nodes) rmin = std::min(rmin, n.radius);
      for (int i = 0; i < 200; ++i) {
        const Vec3 p = point_near(s, rng, 4.0);
        const Vec3 g = f->gradient(p);
        const Vec3 fd = test::central_gradient(*f, p, 1e-6 * rmin);
        EXPECT_LE((g - fd).norm(), 1e-5 * g.norm() + 1e-6 * iso / rmin)
            << name(o) << " p " << p.transpose() << " g " << g.transpose() << " fd "
            << fd.transpose();
      }
    }
  }
}

TEST(ConvolutionSurface, LonePointHasExactRadius) {
  // make_point_field promises a primitive "of surface radius `radius`" for any options.
  for (const auto& o : {convolution(), convolution(2.0, 0.5)}) {
    const FieldPtr f = make_point_field(Vec3(1, 1, 1), 0.6, o);
    for (const Vec3& d : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0.8, 0.6)}) {
      EXPECT_NEAR(f->value(Vec3(1, 1, 1) + 0.6 * d), f->iso(), 1e-12 * f->iso()) << name(o);
    }
  }
}

TEST(ConvolutionSurface, CauchyDistanceSurfaceLonePointHasExactRadius) {
  // skeleton_field.h allows a distance surface with the Cauchy kernel (point convolution
  // 1/(1 + s^2 d^2)^2, s = c / r); a lone point should still have its surface at `radius`.
  const auto o = distance(Kernel{KernelKind::kCauchy, 0.0});
  const FieldPtr f = make_point_field(Vec3(0, 0, 0), 2.0, o);
  EXPECT_NEAR(f->value(Vec3(2, 0, 0)), f->iso(), 1e-12 * f->iso());
  EXPECT_TRUE(f->is_inside(Vec3(1.9, 0, 0)));
  EXPECT_FALSE(f->is_inside(Vec3(2.1, 0, 0)));
}

// ---------------------------------------------------------------------------------------------
// Batch evaluation (SIMD over points) must give exactly the doubles of single evaluations.

// Evaluates `pts` in one batch, with and without gradients, and asserts every value and gradient
// equal (bit for bit) to the point's own single evaluation; `nonzero` receives how many values
// are not 0. Call through ASSERT_NO_FATAL_FAILURE.
void expect_batch_matches_single(const Field& f, const std::vector<Vec3>& pts,
                                 const std::string& label, int& nonzero) {
  std::vector<double> vals(pts.size()), vals_g(pts.size());
  std::vector<Vec3> grads(pts.size());
  f.evaluate(pts, vals);
  f.evaluate(pts, vals_g, grads);
  nonzero = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double v = f.value(pts[i]);
    const Vec3 g = f.gradient(pts[i]);
    nonzero += v != 0;
    ASSERT_EQ(std::memcmp(&v, &vals[i], sizeof v), 0)
        << label << " i " << i << ": " << v << " vs " << vals[i];
    ASSERT_TRUE(g == grads[i]) << label << " i " << i << ": " << g.transpose() << " vs "
                               << grads[i].transpose();
  }
}

TEST(SkeletonField, BatchIsBitIdenticalToSingle) {
  const Skeleton tree = test::random_tree(42, 201);  // 200 segments
  ASSERT_EQ(tree.edge_count(), 200U);
  Rng rng(10);
  const Aabb box = grown(bounding_box(tree), 2.0);
  for (const auto& o : all_options()) {
    const FieldPtr f = make_skeleton_field(tree, o);
    for (std::size_t n : {1UL, 7UL, 64UL, 1000UL}) {
      std::vector<Vec3> pts(n);
      for (std::size_t i = 0; i < n; ++i) pts[i] = i % 3 == 0 ? random_point(rng, box) : point_near(tree, rng, 3.0);
      int nonzero = 0;
      ASSERT_NO_FATAL_FAILURE(
          expect_batch_matches_single(*f, pts, name(o) + " batch " + std::to_string(n), nonzero));
      if (n >= 64) {
        EXPECT_GT(nonzero, static_cast<int>(n / 2)) << name(o);
      }
    }
    // A point gives the same value in every lane position of a batch.
    const Vec3 q = point_near(tree, rng, 1.0);
    std::vector<Vec3> pts(13);
    for (auto& p : pts) p = random_point(rng, box);
    for (std::size_t pos = 0; pos < pts.size(); ++pos) {
      auto copy = pts;
      copy[pos] = q;
      std::vector<double> v(copy.size());
      f->evaluate(copy, v);
      EXPECT_EQ(v[pos], f->value(q)) << name(o) << " lane " << pos;
    }
  }
}

// A large batch packed near the skeleton: its Morton-sorted chunks are full and close, so they
// share their candidates in groups (skeleton_field.cpp, do_evaluate), and most lanes of a
// primitive's vectors lie beyond its support and are skipped (skeleton_field_simd.cpp). Neither
// may change a value or a gradient, against one point at a time.
TEST(SkeletonField, DenseBatchIsBitIdenticalToSingle) {
  const Skeleton tree = test::random_tree(44, 301);
  Rng rng(12);
  for (const auto& o : all_options()) {
    const FieldPtr f = make_skeleton_field(tree, o);
    std::vector<Vec3> pts(3000);
    for (auto& p : pts) p = point_near(tree, rng, 1.5);
    int nonzero = 0;
    ASSERT_NO_FATAL_FAILURE(expect_batch_matches_single(*f, pts, name(o), nonzero));
    EXPECT_GT(nonzero, 2000) << name(o);
  }
}

// f is one function: asking for gradients must not change the values.
TEST(SkeletonField, ValuesDoNotDependOnGradientRequest) {
  const Skeleton tree = test::random_tree(42, 201);
  Rng rng(13);
  for (const auto& o : all_options()) {
    const FieldPtr f = make_skeleton_field(tree, o);
    std::vector<Vec3> pts(500);
    for (auto& p : pts) p = point_near(tree, rng, 3.0);
    std::vector<double> vals(pts.size()), vals_g(pts.size());
    std::vector<Vec3> grads(pts.size());
    f->evaluate(pts, vals);
    f->evaluate(pts, vals_g, grads);
    int differ = 0;
    double worst = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      differ += vals[i] != vals_g[i];
      worst = std::max(worst, std::abs(vals[i] - vals_g[i]) / std::max(std::abs(vals[i]), 1e-300));
    }
    EXPECT_EQ(differ, 0) << name(o) << ": " << differ << " of " << pts.size()
                         << " values change when gradients are requested (worst relative "
                         << worst << ")";
  }
}

TEST(SkeletonField, PruningDoesNotChangeValues) {
  const Skeleton tree = test::random_tree(43, 120);
  Rng rng(11);
  for (auto o : all_options()) {
    const FieldPtr pruned = make_skeleton_field(tree, o);
    o.prune = false;
    const FieldPtr full = make_skeleton_field(tree, o);
    for (int i = 0; i < 300; ++i) {
      const Vec3 p = i % 2 ? point_near(tree, rng, 4.0) : random_point(rng, grown(bounding_box(tree), 3.0));
      EXPECT_EQ(pruned->value(p), full->value(p)) << name(o) << " " << p.transpose();
    }
  }
}

// Small batches reuse their thread's candidate lists (per cell of a grid, per field): a walk
// of single points and of 3-point stencils in small steps, alternating between two fields,
// gives bit for bit the values and gradients of the unpruned fields, which sum every primitive.
TEST(SkeletonField, CachedCandidatesGiveTheUnprunedValues) {
  const Skeleton a = test::random_tree(45, 150);
  const Skeleton b = test::random_tree(46, 80);
  for (auto o : all_options()) {
    const FieldPtr fa = make_skeleton_field(a, o), fb = make_skeleton_field(b, o);
    o.prune = false;
    const FieldPtr ra = make_skeleton_field(a, o), rb = make_skeleton_field(b, o);
    Rng rng(17);
    Vec3 p = point_near(a, rng, 1.0);
    const Vec3 step = 0.01 * (point_near(a, rng, 1.0) - p);
    for (int k = 0; k < 300; ++k, p += step) {
      const std::vector<Vec3> stencil = {p, p + 1e-3 * Vec3::UnitX(), p - 1e-3 * Vec3::UnitX()};
      for (const auto& [f, ref] : {std::pair{fa, ra}, std::pair{fb, rb}}) {
        std::vector<double> v(3), w(3);
        std::vector<Vec3> g(3), h(3);
        f->evaluate(std::span(stencil).first(1 + 2 * (k % 2)), std::span(v).first(1 + 2 * (k % 2)),
                    std::span(g).first(1 + 2 * (k % 2)));
        ref->evaluate(stencil, w, h);
        for (int i = 0; i < 1 + 2 * (k % 2); ++i) {
          ASSERT_EQ(v[i], w[i]) << name(o) << " step " << k;
          ASSERT_TRUE(g[i] == h[i]) << name(o) << " step " << k;
        }
      }
    }
  }
}

TEST(SkeletonField, ConcurrentEvaluationIsSafeAndIdentical) {
  const Skeleton tree = test::random_tree(44, 100);
  const FieldPtr f = make_skeleton_field(tree);
  Rng rng(12);
  std::vector<Vec3> pts(4000);
  for (auto& p : pts) p = point_near(tree, rng, 3.0);
  std::vector<double> a(pts.size()), b(pts.size()), ref(pts.size());
  f->evaluate(pts, ref);
  f->reset_evaluations();
  std::thread t1([&] { f->evaluate(pts, a); });
  std::thread t2([&] { f->evaluate(pts, b); });
  t1.join();
  t2.join();
  EXPECT_EQ(a, ref);
  EXPECT_EQ(b, ref);
  EXPECT_EQ(f->evaluations(), 2 * pts.size());
}

// ---------------------------------------------------------------------------------------------
TEST(SkeletonField, BoundIsConservative) {
  const std::vector<Skeleton> skeletons = {test::y_fork(), test::random_tree(13, 60)};
  std::uint64_t seed = 100;
  for (const auto& o : all_options()) {
    for (const Skeleton& s : skeletons) {
      const FieldPtr f = make_skeleton_field(s, o);
      check_bound_conservative(*f, s, seed++, name(o));
    }
  }
}

TEST(SkeletonField, BoundIsUsefulFarAway) {
  // Far from the skeleton the bound of a compact field is exactly 0 and excludes the surface.
  const Skeleton s = test::y_fork();
  for (const auto& o : all_options()) {
    const FieldPtr f = make_skeleton_field(s, o);
    const Aabb far(Vec3(1000, 1000, 1000), Vec3(1001, 1001, 1001));
    const Interval iv = f->bound(far);
    EXPECT_FALSE(iv.straddles(f->iso())) << name(o);
    EXPECT_LE(iv.hi, f->iso()) << name(o);
    // Deep inside the trunk: the bound says "inside" everywhere.
    const Aabb core(Vec3(-0.05, -0.05, 4.9), Vec3(0.05, 0.05, 5.1));
    EXPECT_GT(f->bound(core).lo, f->iso()) << name(o);
  }
}

TEST(SkeletonField, BoundsContainEveryInsidePoint) {
  const std::vector<Skeleton> skeletons = {test::y_fork(), test::helix(20, 0.5), test::random_tree(14, 60)};
  std::uint64_t seed = 200;
  for (const auto& o : all_options()) {
    for (const Skeleton& s : skeletons) {
      const FieldPtr f = make_skeleton_field(s, o);
      check_bounds_contain_inside(*f, s, seed++, name(o));
    }
    // A lone point too.
    Skeleton lone;
    lone.nodes = {{Vec3(3, 4, 5), 0.5}};
    const FieldPtr p = make_point_field(Vec3(3, 4, 5), 0.5, o);
    const Aabb b = p->bounds();
    EXPECT_TRUE(b.contains(Vec3(3.49, 4, 5))) << name(o);
    EXPECT_TRUE(b.contains(Vec3(3, 3.51, 5))) << name(o);
  }
}

// ---------------------------------------------------------------------------------------------
TEST(SkeletonField, RestrictIsExactInsideTheBoxAndSharesTheCounter) {
  const Skeleton tree = test::random_tree(15, 150);
  Rng rng(16);
  for (const auto& o : all_options()) {
    const FieldPtr f = make_skeleton_field(tree, o);
    for (int b = 0; b < 20; ++b) {
      const Vec3 c = point_near(tree, rng, 2.0);
      const Vec3 half = Vec3::Constant(rng.uniform(0.1, 6.0));
      const Aabb box(c - half, c + half);
      const FieldPtr r = f->restrict(box);
      ASSERT_TRUE(r != nullptr);
      EXPECT_EQ(r->iso(), f->iso());
      std::vector<Vec3> pts;
      for (int k = 0; k < 8; ++k) pts.push_back(box.corner(static_cast<Aabb::CornerType>(k)));
      for (int i = 0; i < 200; ++i) pts.push_back(random_point(rng, box));
      std::vector<double> vr(pts.size()), vf(pts.size());
      std::vector<Vec3> gr(pts.size()), gf(pts.size());
      f->reset_evaluations();
      r->evaluate(pts, vr, gr);
      EXPECT_EQ(f->evaluations(), pts.size()) << name(o);
      EXPECT_EQ(r->evaluations(), pts.size()) << name(o);
      f->evaluate(pts, vf, gf);
      EXPECT_EQ(f->evaluations(), 2 * pts.size());
      for (std::size_t i = 0; i < pts.size(); ++i) {
        ASSERT_EQ(vr[i], vf[i]) << name(o) << " " << pts[i].transpose();
        ASSERT_TRUE(gr[i] == gf[i]) << name(o) << " " << pts[i].transpose();
      }
      // Restricting again, and single-point calls, count too.
      const FieldPtr rr = r->restrict(box);
      f->reset_evaluations();
      (void)rr->value(c);
      (void)rr->gradient(c);
      EXPECT_EQ(f->evaluations(), 2U);
      EXPECT_EQ(rr->value(c), f->value(c));
    }
  }
}

TEST(SkeletonField, RestrictToEmptyRegion) {
  const FieldPtr f = make_skeleton_field(test::y_fork(), distance(Kernel{KernelKind::kWyvill, 0.0}));
  const Aabb far(Vec3(500, 500, 500), Vec3(501, 501, 501));
  const FieldPtr r = f->restrict(far);
  EXPECT_EQ(r->value(Vec3(500.5, 500.5, 500.5)), 0.0);
  EXPECT_EQ(r->value(Vec3(500.5, 500.5, 500.5)), f->value(Vec3(500.5, 500.5, 500.5)));
}

TEST(SkeletonField, CountsEvaluations) {
  const FieldPtr f = make_skeleton_field(test::y_fork());
  f->reset_evaluations();
  EXPECT_EQ(f->evaluations(), 0U);
  std::vector<Vec3> pts(37, Vec3(0, 0, 1));
  std::vector<double> v(37);
  f->evaluate(pts, v);
  (void)f->value(Vec3::Zero());
  (void)f->is_inside(Vec3::Zero());
  EXPECT_EQ(f->evaluations(), 39U);
  // numeric_gradient: central differences with 6 evaluations.
  const Vec3 p(0.3, 0.2, 4.0);
  const Vec3 ng = numeric_gradient(*f, p, 1e-6);
  EXPECT_EQ(f->evaluations(), 45U);
  EXPECT_LE((ng - test::central_gradient(*f, p, 1e-6)).norm(), 1e-12 * ng.norm());
  EXPECT_FALSE(f->describe().empty());
}

}  // namespace
}  // namespace ramiform
