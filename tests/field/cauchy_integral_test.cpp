// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The closed-form Cauchy segment integral (Zhu, Guo & Jin 2013, "Efficient polygonization of tree
// trunks modeled by convolution surfaces", eq. 5) against adaptive Gauss–Kronrod quadrature in long
// double, and its gradient against central differences.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "field/field_test_util.h"
#include "ramiform/field/kernels.h"

namespace ramiform {
namespace {

using LD = long double;

// Adaptive Gauss–Kronrod 7/15 on [a, b] until |K15 - G7| <= tol on every piece.
LD gauss_kronrod(const std::function<LD(LD)>& f, LD a, LD b, LD tol, LD floor = 0, int depth = 0) {
  static const LD xgk[8] = {0.991455371120812639206854697526329L, 0.949107912342758524526189684047851L,
                            0.864864423359769072789712788640926L, 0.741531185599394439863864773280788L,
                            0.586087235467691130294144845693013L, 0.405845151377397166906606412076961L,
                            0.207784955007898467600689403773245L, 0.0L};
  static const LD wgk[8] = {0.022935322010529224963732008058970L, 0.063092092629978553290700663189204L,
                            0.104790010322250183839876322541518L, 0.140653259715525918745189590510238L,
                            0.169004726639267902826583426598550L, 0.190350578064785409913256402421014L,
                            0.204432940075298892414161999234649L, 0.209482141084727828012999174891714L};
  static const LD wg[4] = {0.129484966168869693270611432679082L, 0.279705391489276667901467771423780L,
                           0.381830050505118944950369775488975L, 0.417959183673469387755102040816327L};
  const LD c = (a + b) / 2, h = (b - a) / 2;
  LD k = wgk[7] * f(c);
  LD g = wg[3] * f(c);
  for (int i = 0; i < 7; ++i) {
    const LD v = f(c - h * xgk[i]) + f(c + h * xgk[i]);
    k += wgk[i] * v;
    if (i % 2 == 1) g += wg[i / 2] * v;
  }
  k *= h;
  g *= h;
  if (std::fabs(k - g) <= std::max(tol, floor) || depth > 40) return k;
  return gauss_kronrod(f, a, c, tol / 2, floor, depth + 1) + gauss_kronrod(f, c, b, tol / 2, floor, depth + 1);
}

// Integral over q on [a, b] (arc length) of 1/(1 + s^2 |p - q|^2)^2 (component -1) or of its
// derivative with respect to p_k, -4 s^2 (p - q)_k / (1 + s^2 |p - q|^2)^3 (component k), in
// long double.
LD reference_integral(const Vec3& p, const Vec3& a, const Vec3& b, double s, int component = -1) {
  LD len2 = 0;
  for (int k = 0; k < 3; ++k) len2 += (LD(b[k]) - LD(a[k])) * (LD(b[k]) - LD(a[k]));
  const LD len = std::sqrt(len2);
  const LD s2 = LD(s) * LD(s);
  auto f = [&](LD u) {
    const LD t = u / len;
    LD d[3];
    LD d2 = 0;
    for (int k = 0; k < 3; ++k) {
      d[k] = LD(p[k]) - (LD(a[k]) + t * (LD(b[k]) - LD(a[k])));
      d2 += d[k] * d[k];
    }
    const LD q = 1 + s2 * d2;
    if (component < 0) return 1 / (q * q);
    return -4 * s2 * d[component] / (q * q * q);
  };
  auto abs_f = [&](LD u) { return std::fabs(f(u)); };
  // Split at the foot of p (where the integrand peaks) and at a few widths around it.
  LD foot = 0;
  for (int k = 0; k < 3; ++k) foot += (LD(p[k]) - LD(a[k])) * (LD(b[k]) - LD(a[k]));
  foot /= len;
  std::vector<LD> cuts = {0, len};
  for (LD off : {0.0L, -1.0L, 1.0L, -10.0L, 10.0L}) {
    const LD c = foot + off / LD(s);
    if (c > 0 && c < len) cuts.push_back(c);
  }
  std::sort(cuts.begin(), cuts.end());
  // Magnitude of the integral of |f| first; tolerances relative to it.
  LD rough = 0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) rough += gauss_kronrod(abs_f, cuts[i], cuts[i + 1], 1e-6L);
  const LD tol = rough * 1e-17L;
  LD total = 0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    total += gauss_kronrod(f, cuts[i], cuts[i + 1], tol, rough * 1e-21L);
  }
  return total;
}

struct Case {
  Vec3 p, a, b;
  double s;
};

// Random segments with points near, far, on the line beyond the ends, and on the segment.
std::vector<Case> cases(std::uint64_t seed, int n, double max_far) {
  Rng rng(seed);
  std::vector<Case> out;
  for (int i = 0; i < n; ++i) {
    Case c;
    c.a = Vec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    const double len = std::exp(rng.uniform(std::log(0.05), std::log(20.0)));
    c.b = c.a + len * test::random_unit(rng);
    c.s = std::exp(rng.uniform(std::log(0.1), std::log(10.0)));
    const double t = rng.uniform(-0.5, 1.5);
    const Vec3 on = c.a + t * (c.b - c.a);
    // Distance in units of the kernel width 1/s, log-uniform from 1e-3 to max_far.
    const double dist = std::exp(rng.uniform(std::log(1e-3), std::log(max_far))) / c.s;
    switch (i % 4) {
      case 0:
      case 1:
        c.p = on + dist * test::random_unit(rng);
        break;
      case 2: {  // perpendicular to the segment
        Vec3 dir = (c.b - c.a).normalized();
        Vec3 perp = dir.unitOrthogonal();
        c.p = on + dist * perp;
        break;
      }
      case 3:  // on the segment's line (h = 0), inside or beyond the ends
        c.p = on;
        break;
    }
    out.push_back(c);
  }
  return out;
}

TEST(CauchySegmentIntegral, MatchesAdaptiveQuadrature) {
  // Up to 20 kernel widths: the cutoff of the Cauchy kernel is at about 10 widths.
  int worst_i = -1;
  double worst = 0;
  const auto cs = cases(101, 2000, 20.0);
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const Case& c = cs[i];
    const double got = cauchy_segment_integral(c.p, c.a, c.b, c.s);
    const LD ref = reference_integral(c.p, c.a, c.b, c.s);
    const double rel = static_cast<double>(std::fabs((LD(got) - ref) / ref));
    if (rel > worst) {
      worst = rel;
      worst_i = static_cast<int>(i);
    }
    EXPECT_LT(rel, 1e-9) << "p " << c.p.transpose() << " a " << c.a.transpose() << " b "
                         << c.b.transpose() << " s " << c.s << " got " << got << " ref "
                         << static_cast<double>(ref);
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
  (void)worst_i;
}

TEST(CauchySegmentIntegral, KnownValues) {
  // On the axis of a unit segment, at its middle, s = 1: integral of 1/(1+u^2)^2 over
  // [-0.5, 0.5] = [u/(2(1+u^2)) + atan(u)/2] = 0.5/1.25 + atan(0.5).
  const double v = cauchy_segment_integral(Vec3(0.5, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), 1.0);
  EXPECT_NEAR(v, 0.5 / 1.25 + std::atan(0.5), 1e-15);
  // Symmetric in the endpoints.
  const Vec3 p(0.3, 0.7, -0.2), a(-1, 0, 0), b(2, 0.5, 0.1);
  EXPECT_NEAR(cauchy_segment_integral(p, a, b, 1.3), cauchy_segment_integral(p, b, a, 1.3), 1e-15);
  // A long segment seen from its middle at distance h tends to pi / (2 s P^(3/2)).
  const double s = 2.0, h = 0.4;
  const double P = 1 + s * s * h * h;
  const double longv = cauchy_segment_integral(Vec3(0, h, 0), Vec3(-1e4, 0, 0), Vec3(1e4, 0, 0), s);
  EXPECT_NEAR(longv, std::numbers::pi / (2 * s * std::pow(P, 1.5)), 1e-9);
  // Additive over a split segment.
  const Vec3 m = 0.3 * a + 0.7 * b;
  EXPECT_NEAR(cauchy_segment_integral(p, a, b, 0.8),
              cauchy_segment_integral(p, a, m, 0.8) + cauchy_segment_integral(p, m, b, 0.8), 1e-14);
}

TEST(CauchySegmentIntegral, FarFieldStaysAccurate) {
  // Beyond the cutoff the field is not used, but the closed form should not break down
  // (atan2 form) out to 100 kernel widths: report the worst error, require 1e-6.
  double worst = 0;
  for (const Case& c : cases(202, 1000, 100.0)) {
    const double got = cauchy_segment_integral(c.p, c.a, c.b, c.s);
    const LD ref = reference_integral(c.p, c.a, c.b, c.s);
    const double rel = static_cast<double>(std::fabs((LD(got) - ref) / ref));
    worst = std::max(worst, rel);
    EXPECT_LT(rel, 1e-6) << "p " << c.p.transpose() << " a " << c.a.transpose() << " b "
                         << c.b.transpose() << " s " << c.s;
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(CauchySegmentIntegral, GradientMatchesQuadrature) {
  for (const Case& c : cases(303, 1000, 20.0)) {
    Vec3 g;
    const double v = cauchy_segment_integral(c.p, c.a, c.b, c.s, &g);
    EXPECT_EQ(v, cauchy_segment_integral(c.p, c.a, c.b, c.s));
    Vec3 ref;
    for (int k = 0; k < 3; ++k) ref[k] = static_cast<double>(reference_integral(c.p, c.a, c.b, c.s, k));
    // Relative to the gradient, with a floor at the gradient's natural scale v * s (on the
    // segment's line near its middle the gradient itself nearly vanishes).
    EXPECT_LE((g - ref).norm(), 1e-9 * std::max(ref.norm(), 1e-4 * v * c.s))
        << "p " << c.p.transpose() << " a " << c.a.transpose() << " b " << c.b.transpose()
        << " s " << c.s << " g " << g.transpose() << " ref " << ref.transpose();
  }
}

TEST(CauchySegmentIntegral, GradientMatchesCentralDifferences) {
  int checked = 0;
  for (const Case& c : cases(304, 3000, 20.0)) {
    // Within the cutoff (about 10 kernel widths): farther out the closed form's own rounding
    // (a cancellation of order (s d)^2 eps) swamps a finite difference.
    const double dist = test::brute_distance(c.p, c.a, c.b);
    if (c.s * dist > 10) continue;
    ++checked;
    Vec3 g;
    const double v = cauchy_segment_integral(c.p, c.a, c.b, c.s, &g);
    // Local length scale: the kernel width, or the distance to the segment when smaller.
    const double ell = std::min(1 / c.s, std::max(dist, 0.01 / c.s));
    const double h = 1e-4 * ell;
    Vec3 fd;
    for (int k = 0; k < 3; ++k) {
      Vec3 p1 = c.p, p2 = c.p;
      p1[k] += h;
      p2[k] -= h;
      fd[k] = (cauchy_segment_integral(p1, c.a, c.b, c.s) - cauchy_segment_integral(p2, c.a, c.b, c.s)) /
              (2 * h);
    }
    // Relative to the gradient, with a floor from the value's own scale (v / ell).
    EXPECT_LE((g - fd).norm(), 1e-6 * std::max(g.norm(), 1e-3 * v / ell))
        << "p " << c.p.transpose() << " a " << c.a.transpose() << " b " << c.b.transpose()
        << " s " << c.s << " g " << g.transpose() << " fd " << fd.transpose();
  }
  EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace ramiform
