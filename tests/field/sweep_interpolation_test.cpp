// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Interpolation weights along a skin's path (src/field/sweep_interpolation.h): each scheme
// reproduces the polynomials it is exact for, derivatives match central differences, and the
// Lebesgue bound holds on dense samples.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "field/sweep_interpolation.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

using detail::sweep::Interpolator;
using detail::sweep::Weights;

// Uneven nodes, with one close pair (0.50, 0.53) that makes naive parabolas swing.
const std::vector<double> kNodes{0.0, 0.1, 0.35, 0.5, 0.53, 0.8, 1.0};
constexpr SkinInterpolation kKinds[] = {SkinInterpolation::kLinear, SkinInterpolation::kQuadratic,
                                        SkinInterpolation::kCubic};

// sum_c w[c] D[index[c]] and its derivative, with D the function `f` at the nodes.
double combine(const Weights& w, const std::function<double(double)>& f, bool derivative) {
  double sum = 0;
  for (int c = 0; c < w.count; ++c) sum += (derivative ? w.dw[c] : w.w[c]) * f(kNodes[w.index[c]]);
  return sum;
}

TEST(SweepInterpolation, WeightsAreAPartitionOfUnity) {
  for (const SkinInterpolation kind : kKinds) {
    const Interpolator interp(kNodes, kind);
    for (int i = -10; i <= 110; ++i) {
      const Weights w = interp.at(i / 100.0);
      double sum = 0, dsum = 0;
      for (int c = 0; c < w.count; ++c) {
        sum += w.w[c];
        dsum += w.dw[c];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      EXPECT_NEAR(dsum, 0.0, 1e-9);
    }
  }
}

TEST(SweepInterpolation, NodesAreInterpolatedAndEndsHeld) {
  const auto f = [](double s) { return std::sin(5 * s) + 2; };
  for (const SkinInterpolation kind : kKinds) {
    const Interpolator interp(kNodes, kind);
    for (const double s : kNodes) EXPECT_NEAR(combine(interp.at(s), f, false), f(s), 1e-12);
    EXPECT_DOUBLE_EQ(combine(interp.at(-0.5), f, false), f(0.0));
    EXPECT_DOUBLE_EQ(combine(interp.at(1.5), f, false), f(1.0));
  }
}

TEST(SweepInterpolation, EachSchemeReproducesItsPolynomials) {
  const auto line = [](double s) { return 3 * s - 1; };
  const auto parabola = [](double s) { return 2 * s * s - s + 0.5; };
  for (int i = 1; i < 100; ++i) {
    const double s = i / 100.0;
    for (const SkinInterpolation kind : kKinds) {
      EXPECT_NEAR(combine(Interpolator(kNodes, kind).at(s), line, false), line(s), 1e-12);
      EXPECT_NEAR(combine(Interpolator(kNodes, kind).at(s), line, true), 3.0, 1e-9);
    }
    const Interpolator quadratic(kNodes, SkinInterpolation::kQuadratic);
    EXPECT_NEAR(combine(quadratic.at(s), parabola, false), parabola(s), 1e-12);
    EXPECT_NEAR(combine(quadratic.at(s), parabola, true), 4 * s - 1, 1e-9);
    // The cubic's slopes are exact for parabolas at interior nodes (Bessel), so intervals
    // between two interior nodes reproduce them; the end intervals use secants.
    if (s > kNodes[1] && s < kNodes[kNodes.size() - 2]) {
      const Interpolator cubic(kNodes, SkinInterpolation::kCubic);
      EXPECT_NEAR(combine(cubic.at(s), parabola, false), parabola(s), 1e-12) << s;
      EXPECT_NEAR(combine(cubic.at(s), parabola, true), 4 * s - 1, 1e-9) << s;
    }
  }
}

TEST(SweepInterpolation, DerivativesMatchCentralDifferences) {
  const auto f = [](double s) { return std::exp(s) * std::cos(3 * s); };
  Rng rng(7);
  for (const SkinInterpolation kind : kKinds) {
    const Interpolator interp(kNodes, kind);
    for (int i = 0; i < 200; ++i) {
      const double s = rng.uniform(0.001, 0.999);
      const double h = 1e-7;
      const double fd =
          (combine(interp.at(s + h), f, false) - combine(interp.at(s - h), f, false)) / (2 * h);
      // Skip the few samples that straddle a node, where the derivative may jump.
      bool near_node = false;
      for (const double n : kNodes) near_node = near_node || std::abs(s - n) < 2 * h;
      if (!near_node) {
        EXPECT_NEAR(combine(interp.at(s), f, true), fd, 1e-5) << s;
      }
    }
  }
}

TEST(SweepInterpolation, LebesgueBoundHoldsOnDenseSamples) {
  for (const SkinInterpolation kind : kKinds) {
    const Interpolator interp(kNodes, kind);
    double largest = 0;
    for (int i = 0; i <= 20000; ++i) {
      const Weights w = interp.at(i / 20000.0);
      double sum = 0;
      for (int c = 0; c < w.count; ++c) sum += std::abs(w.w[c]);
      largest = std::max(largest, sum);
    }
    EXPECT_GE(interp.lebesgue(), 1.0);
    EXPECT_LE(largest, interp.lebesgue() * (1 + 1e-12));
    // Hat functions never overshoot; the higher schemes do, near the close pair of nodes.
    if (kind == SkinInterpolation::kLinear) {
      EXPECT_NEAR(largest, 1.0, 1e-12);
    } else {
      EXPECT_GT(largest, 1.0);
    }
  }
}

TEST(SweepInterpolation, FewNodes) {
  const auto line = [](double s) { return 3 * s - 1; };
  const std::vector<double> one{0.4};
  for (const SkinInterpolation kind : kKinds) {
    const Weights w = Interpolator(one, kind).at(0.9);
    ASSERT_EQ(w.count, 1);
    EXPECT_EQ(w.index[0], 0);
    EXPECT_EQ(w.w[0], 1.0);
    // Two nodes: every scheme is the straight line between them.
    const Interpolator two({0.0, 1.0}, kind);
    for (int i = 0; i <= 10; ++i) {
      const Weights w2 = two.at(i / 10.0);
      double v = 0;
      for (int c = 0; c < w2.count; ++c) v += w2.w[c] * line(w2.index[c] == 0 ? 0.0 : 1.0);
      EXPECT_NEAR(v, line(i / 10.0), 1e-12);
    }
  }
}

}  // namespace
}  // namespace ramiform
