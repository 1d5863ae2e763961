// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Independent reference computations for the field tests: kernels written out from their
// formulas, brute-force point-segment distance, central differences, random helpers.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "ramiform/core/random.h"
#include "ramiform/core/types.h"
#include "ramiform/field/field.h"
#include "ramiform/field/kernels.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::test {

/// k(x) written out from the table in kernels.h, without any cutoff.
inline double reference_kernel(KernelKind kind, double param, double x) {
  switch (kind) {
    case KernelKind::kWyvill: {
      if (x >= 1) return 0;
      const double x2 = x * x;
      return 1 - 22.0 / 9 * x2 + 17.0 / 9 * x2 * x2 - 4.0 / 9 * x2 * x2 * x2;
    }
    case KernelKind::kBlinn:
      return std::exp(-(param == 0 ? 4.0 : param) * x * x);
    case KernelKind::kMetaball:
      if (x <= 1.0 / 3) return 1 - 3 * x * x;
      if (x <= 1) return 1.5 * (1 - x) * (1 - x);
      return 0;
    case KernelKind::kInversePower:
      return std::pow(x, -((param == 0 ? 3.0 : param) - 1));
    case KernelKind::kCauchy:
      return 1 / ((1 + x * x) * (1 + x * x));
  }
  return std::numeric_limits<double>::quiet_NaN();
}

/// Natural iso value per kernel (kernels.h table).
inline double reference_iso(KernelKind kind) {
  return kind == KernelKind::kInversePower || kind == KernelKind::kCauchy ? 1.0 : 0.5;
}

/// True for kernels with infinite support (cut off and faded by the implementation).
inline bool is_infinite_kernel(KernelKind kind) {
  return kind == KernelKind::kBlinn || kind == KernelKind::kInversePower ||
         kind == KernelKind::kCauchy;
}

/// Squared distance from p to the point a + t (b - a), in long double.
inline long double squared_distance_at(const Vec3& p, const Vec3& a, const Vec3& b, long double t) {
  long double s = 0;
  for (int k = 0; k < 3; ++k) {
    const long double q = static_cast<long double>(a[k]) +
                          t * (static_cast<long double>(b[k]) - static_cast<long double>(a[k]));
    const long double d = static_cast<long double>(p[k]) - q;
    s += d * d;
  }
  return s;
}

/// Closest point parameter t in [0, 1] of p on segment [a, b], by dense sampling then bisection
/// on the derivative of the squared distance, in long double (no projection formula).
inline long double brute_closest_t(const Vec3& p, const Vec3& a, const Vec3& b) {
  auto d2 = [&](long double t) { return squared_distance_at(p, a, b, t); };
  constexpr int kSamples = 2000;
  int best = 0;
  long double best_d = d2(0);
  for (int i = 1; i <= kSamples; ++i) {
    const long double v = d2(static_cast<long double>(i) / kSamples);
    if (v < best_d) {
      best_d = v;
      best = i;
    }
  }
  // Refine by bisection on the sign of the derivative of the squared distance, (q(t) - p).(b - a),
  // which locates a flat minimum to full precision (a ternary search on the value would not).
  auto slope = [&](long double t) {
    long double s = 0;
    for (int k = 0; k < 3; ++k) {
      const long double ab = static_cast<long double>(b[k]) - static_cast<long double>(a[k]);
      const long double q = static_cast<long double>(a[k]) + t * ab;
      s += (q - static_cast<long double>(p[k])) * ab;
    }
    return s;
  };
  long double lo = std::max(0.0L, static_cast<long double>(best - 1) / kSamples);
  long double hi = std::min(1.0L, static_cast<long double>(best + 1) / kSamples);
  if (slope(lo) >= 0) return lo;  // minimum at the lower end (t = 0)
  if (slope(hi) <= 0) return hi;  // minimum at the upper end (t = 1)
  for (int it = 0; it < 100; ++it) {
    const long double m = (lo + hi) / 2;
    (slope(m) < 0 ? lo : hi) = m;
  }
  return (lo + hi) / 2;
}

/// Distance from p to segment [a, b] by brute force (see brute_closest_t).
inline double brute_distance(const Vec3& p, const Vec3& a, const Vec3& b,
                             long double* t_out = nullptr) {
  const long double t = brute_closest_t(p, a, b);
  if (t_out != nullptr) *t_out = t;
  return static_cast<double>(std::sqrt(squared_distance_at(p, a, b, t)));
}

/// Central-difference gradient of a field (own implementation; the library's
/// numeric_gradient is tested separately against it).
inline Vec3 central_gradient(const Field& f, const Vec3& p, double h) {
  Vec3 g;
  for (int k = 0; k < 3; ++k) {
    Vec3 a = p, b = p;
    a[k] += h;
    b[k] -= h;
    g[k] = (f.value(a) - f.value(b)) / (2 * h);
  }
  return g;
}

inline Vec3 random_unit(Rng& rng) {
  for (;;) {
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const double n = v.norm();
    if (n > 0.1 && n <= 1) return v / n;
  }
}

inline Vec3 random_point(Rng& rng, const Aabb& box) {
  return Vec3(rng.uniform(box.min().x(), box.max().x()), rng.uniform(box.min().y(), box.max().y()),
              rng.uniform(box.min().z(), box.max().z()));
}

/// A box grown by `margin` on every side.
/// Checks `f.bound(box)` against f at the box's corners, its centre and `samples` random points
/// in it: every value within the bound, and a bound that straddles iso when the values do.
/// Returns true when the values straddle iso (sets `failed` on a violation, which is reported).
inline bool check_bound_in_box(const Field& f, const Aabb& box, Rng& rng, int samples,
                               const std::string& what, bool& failed) {
  const Interval iv = f.bound(box);
  std::vector<Vec3> pts;
  for (int k = 0; k < 8; ++k) pts.push_back(box.corner(static_cast<Aabb::CornerType>(k)));
  pts.push_back(box.center());
  for (int i = 0; i < samples; ++i) pts.push_back(random_point(rng, box));
  std::vector<double> v(pts.size());
  f.evaluate(pts, v);
  bool in = false, out = false;
  failed = !(iv.lo <= iv.hi);
  EXPECT_FALSE(failed) << what << ": empty bound [" << iv.lo << ", " << iv.hi << "]";
  for (std::size_t i = 0; i < pts.size() && !failed; ++i) {
    failed = !iv.contains(v[i]);
    EXPECT_FALSE(failed) << what << ": box " << box.min().transpose() << " / "
                         << box.max().transpose() << " bound [" << iv.lo << ", " << iv.hi
                         << "] but f(" << pts[i].transpose() << ") = " << v[i];
    in |= v[i] > f.iso();
    out |= v[i] <= f.iso();
  }
  if (in && out) {
    EXPECT_TRUE(iv.straddles(f.iso())) << what;
  }
  return in && out;
}

inline Aabb grown(const Aabb& b, double margin) {
  return Aabb(b.min() - Vec3::Constant(margin), b.max() + Vec3::Constant(margin));
}

/// All kinds of distance kernels, with their default parameters and one non-default one.
inline std::vector<Kernel> distance_kernels() {
  return {Kernel{KernelKind::kWyvill, 0.0},       Kernel{KernelKind::kBlinn, 0.0},
          Kernel{KernelKind::kBlinn, 2.5},        Kernel{KernelKind::kMetaball, 0.0},
          Kernel{KernelKind::kInversePower, 0.0}, Kernel{KernelKind::kInversePower, 4.0}};
}

// A random point near the skeleton: on a random edge, offset by up to `spread` local radii.
inline Vec3 point_near(const Skeleton& s, Rng& rng, double spread) {
  const auto& e = s.edges[rng.below(s.edges.size())];
  const double t = rng.uniform();
  const auto& a = s.nodes[e[0]];
  const auto& b = s.nodes[e[1]];
  const double r = (1 - t) * a.radius + t * b.radius;
  return (1 - t) * a.position + t * b.position + rng.uniform(0, spread) * r * random_unit(rng);
}

// bound(box) is conservative: sampled values never leave it.
inline void check_bound_conservative(const Field& f, const Skeleton& s, std::uint64_t seed,
                                     const std::string& what) {
  Rng rng(seed);
  double rmax = 0;
  for (const auto& n : s.nodes) rmax = std::max(rmax, n.radius);
  int straddling = 0;
  for (int b = 0; b < 150; ++b) {
    const Vec3 c =
        b % 3 == 0 ? random_point(rng, grown(bounding_box(s), 3 * rmax)) : point_near(s, rng, 3.0);
    const Vec3 half(std::exp(rng.uniform(std::log(0.02), std::log(10.0))) * rmax,
                    std::exp(rng.uniform(std::log(0.02), std::log(10.0))) * rmax,
                    std::exp(rng.uniform(std::log(0.02), std::log(10.0))) * rmax);
    const Aabb box(c - half, c + half);
    const Interval iv = f.bound(box);
    ASSERT_LE(iv.lo, iv.hi) << what;
    std::vector<Vec3> pts;
    for (int k = 0; k < 8; ++k) pts.push_back(box.corner(static_cast<Aabb::CornerType>(k)));
    pts.push_back(c);
    for (int i = 0; i < 120; ++i) pts.push_back(random_point(rng, box));
    std::vector<double> v(pts.size());
    f.evaluate(pts, v);
    bool in = false, out = false;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      ASSERT_TRUE(iv.contains(v[i])) << what << ": box " << box.min().transpose() << " / "
                                     << box.max().transpose() << " bound [" << iv.lo << ", "
                                     << iv.hi << "] but f(" << pts[i].transpose() << ") = " << v[i];
      in |= v[i] > f.iso();
      out |= v[i] <= f.iso();
    }
    if (in && out) {
      ++straddling;
      EXPECT_TRUE(iv.straddles(f.iso())) << what;
    }
  }
  EXPECT_GT(straddling, 5) << what << ": too few boxes cross the surface for a useful test";
}

// Points outside bounds() are never inside; inside points lie in bounds().
inline void check_bounds_contain_inside(const Field& f, const Skeleton& s, std::uint64_t seed,
                                        const std::string& what) {
  Rng rng(seed);
  const Aabb b = f.bounds();
  ASSERT_FALSE(b.isEmpty()) << what;
  double rmax = 0;
  for (const auto& n : s.nodes) rmax = std::max(rmax, n.radius);
  const Aabb sample = grown(b, 0.5 * b.diagonal().norm());
  int outside = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p = i % 2 ? random_point(rng, sample) : point_near(s, rng, 4.0);
    if (b.contains(p)) continue;
    ++outside;
    ASSERT_LE(f.value(p), f.iso())
        << what << ": " << p.transpose() << " is inside but outside bounds " << b.min().transpose()
        << " / " << b.max().transpose();
  }
  EXPECT_GT(outside, 500);
  // Every node is inside and in the box.
  for (const auto& n : s.nodes) {
    if (f.is_inside(n.position)) {
      EXPECT_TRUE(b.contains(n.position)) << what;
    }
  }
}

}  // namespace ramiform::test
