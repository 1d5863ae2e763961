// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The bracketed root finder (core/roots.h): known roots to tight tolerances, bounded step
// counts, the safeguards (flat ends, vanished ends, creeping steps) and step-wise driving.

#include "ramiform/core/roots.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

struct Known {
  const char* name;
  std::function<double(double)> g;
  double a, b, root;
  int max_evaluations;  // the two ends included
};

// Roots known in closed form (or to all digits), to 1e-14 of the bracket or |g| <= 1e-15.
TEST(FindRoot, KnownRootsToTightTolerance) {
  const std::vector<Known> cases = {
      {"x^2 - 2", [](double x) { return x * x - 2; }, 0, 2, std::sqrt(2.0), 5},
      {"2 - x^2 (falling)", [](double x) { return 2 - x * x; }, 0, 2, std::sqrt(2.0), 5},
      {"x^3 - 2x - 5 (Wallis)", [](double x) { return x * x * x - 2 * x - 5; }, 2, 3,
       2.0945514815423265, 8},
      {"cos x - x", [](double x) { return std::cos(x) - x; }, 0, 1, 0.7390851332151607, 8},
      {"e^x - 10", [](double x) { return std::exp(x) - 10; }, 0, 5, std::log(10.0), 15},
      {"ln x + 1 (near 0)", [](double x) { return std::log(x) + 1; }, 1e-3, 4, std::exp(-1.0), 14},
      {"sin x on [3, 4]", [](double x) { return std::sin(x); }, 3, 4, std::numbers::pi, 8},
      {"tanh(50 (x - 0.6)) (steep)", [](double x) { return std::tanh(50 * (x - 0.6)); }, 0, 1, 0.6,
       13},
  };
  for (const Known& k : cases) {
    RootOptions o;
    o.tolerance = 1e-14;
    o.value_tolerance = 1e-15;
    const RootResult r = find_root(k.g, k.a, k.b, o);
    EXPECT_TRUE(r.converged) << k.name;
    EXPECT_NEAR(r.x, k.root, 1e-14 * (k.b - k.a)) << k.name;
    EXPECT_LE(r.evaluations, k.max_evaluations) << k.name;
  }
}

TEST(FindRoot, BracketWidthAloneConvergesToo) {
  // Without a value tolerance the bracket itself must shrink. Interpolation converges from one
  // side and leaves the far end in place; the creeping rule then bisects, so the width reaches
  // 1e-14 of the bracket in a bounded number of steps.
  RootOptions o;
  o.tolerance = 1e-14;
  const RootResult wallis = find_root([](double x) { return x * x * x - 2 * x - 5; }, 2, 3, o);
  EXPECT_TRUE(wallis.converged);
  EXPECT_NEAR(wallis.x, 2.0945514815423265, 1e-14);
  EXPECT_LE(wallis.evaluations, 60);
  // A triple root: g is below 1e-15 over a band 2e-5 wide, where only the width decides.
  const RootResult triple = find_root([](double x) { return std::pow(x - 1.0 / 3, 3); }, 0, 1, o);
  EXPECT_TRUE(triple.converged);
  EXPECT_NEAR(triple.x, 1.0 / 3, 1e-14);
  EXPECT_LE(triple.evaluations, 2 + o.max_steps);
}

TEST(FindRoot, QuadraticsConvergeInAFewSteps) {
  // The quadratic step is exact on a quadratic: after the first secant, one step lands on the
  // root to rounding (plus one to confirm the bracket).
  const auto g = [](double x) { return 1 - (1 + 400 * x * x) / 3.0; };  // root 1/sqrt(200)
  RootOptions o;
  o.tolerance = 0;
  o.value_tolerance = 1e-15;
  const RootResult r = find_root(g, 0, 1, o);
  EXPECT_NEAR(r.x, 1 / std::sqrt(200.0), 1e-15);
  EXPECT_LE(r.evaluations, 2 + 4);
}

TEST(FindRoot, FlatAtOneEnd) {
  // A compactly supported bump (a Wyvill-like kernel) minus a level: g is constant -0.5 beyond
  // x = 0.5, so interpolation from that end creeps; the creeping rule bisects.
  const auto g = [](double x) {
    const double q = 1 - 4 * x * x;
    return (q > 0 ? q * q * q : 0.0) - 0.5;
  };
  const double root = std::sqrt((1 - std::cbrt(0.5)) / 4);
  RootOptions o;
  o.tolerance = 1e-13;
  const RootResult r = find_root(g, 0, 10, o);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x, root, 2e-12);
  EXPECT_LE(r.evaluations, 40);
}

TEST(FindRoot, VanishedEndStepsInFromTheLiveEnd) {
  // g = 1 - (f / iso)^(-2/3) of a Cauchy falloff f = 2.8 iso (1 + (L x)^2)^(-3/2): exactly
  // quadratic, and beyond -1e4 at x = 1 (the field has all but vanished there). The root
  // sits at 2.3e-5 of the bracket.
  constexpr double kL = 5e4;
  const auto g = [](double x) { return 1 - (1 + kL * kL * x * x) / std::cbrt(2.8 * 2.8); };
  const double root = std::sqrt(std::cbrt(2.8 * 2.8) - 1) / kL;
  ASSERT_LT(g(1), -1e4);
  RootOptions o;
  o.tolerance = 1e-12;
  o.vanish_level = -1e4;
  const RootResult r = find_root(g, 0, 1, o);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.x, root, 1e-12);
  EXPECT_LE(r.evaluations, 2 + 60);
  // The first probe is the midpoint, the next ones step 1/32 in from the live end.
  RootBracket bracket(0, g(0), 1, g(1), -1e4);
  EXPECT_TRUE(bracket.is_vanished());
  EXPECT_EQ(bracket.probe(), 0.5);
  bracket.update(0.5, g(0.5));
  EXPECT_EQ(bracket.probe(), 0.5 / 32);
}

TEST(RootBracket, ProbesStayInsideAndTheBracketKeepsItsSignChange) {
  const auto g = [](double x) { return std::exp(3 * x) - 7 + std::sin(20 * x); };
  RootBracket r(0, g(0), 1.5, g(1.5));
  ASSERT_LT(g(0), 0);
  ASSERT_GT(g(1.5), 0);
  double width = r.width();
  for (int step = 0; step < 40 && r.width() > 1e-15; ++step) {
    const double x = r.probe();
    EXPECT_GT(x, r.lower());
    EXPECT_LT(x, r.upper());
    r.update(x, g(x));
    EXPECT_EQ(r.updates(), step + 1);
    EXPECT_LE(r.width(), width);
    width = r.width();
    if (r.width() > 0) {
      EXPECT_LT(r.lower_value(), 0);
      EXPECT_GT(r.upper_value(), 0);
    }
  }
  EXPECT_LE(r.width(), 1e-15);
  EXPECT_NEAR(g(r.estimate()), 0.0, 1e-13);
}

TEST(RootBracket, ZerosAndNaNsEndTheSearch) {
  // A zero at an end collapses the bracket onto it.
  const RootBracket at_a(2, 0.0, 3, 1.0);
  EXPECT_EQ(at_a.width(), 0);
  EXPECT_EQ(at_a.estimate(), 2);
  const RootBracket at_b(2, -1.0, 3, 0.0);
  EXPECT_EQ(at_b.estimate(), 3);
  // Both ends zero: collapsed onto b, negative width (never probed by a width test).
  const RootBracket both(2, 0.0, 3, 0.0);
  EXPECT_LT(both.width(), 0);
  // A zero or NaN value at a probe is the root.
  RootBracket r(0, -1, 1, 1);
  r.update(0.25, 0.0);
  EXPECT_EQ(r.estimate(), 0.25);
  RootBracket s(0, -1, 1, 1);
  s.update(0.75, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(s.estimate(), 0.75);
  // safeguard: inside stays, on or beyond an end becomes the midpoint.
  EXPECT_EQ(RootBracket(0, -1, 1, 1).safeguard(0.3), 0.3);
  EXPECT_EQ(RootBracket(0, -1, 1, 1).safeguard(1.0), 0.5);
  EXPECT_EQ(RootBracket(0, -1, 1, 1).safeguard(std::nan("")), 0.5);
}

TEST(RootBracket, StepWiseDrivingMatchesTheOneCallWrapper) {
  // Many brackets advanced in lockstep (one batch of evaluations per round, as the
  // polygonizers do) give exactly the wrapper's answers and evaluation counts.
  std::vector<double> shift;
  for (int k = 0; k < 50; ++k) shift.push_back(0.02 + 0.0191 * k);
  auto g = [](double c, double x) { return std::cbrt(x - c) + 0.1 * (x - c); };
  std::vector<RootBracket> brackets;
  for (const double c : shift) brackets.emplace_back(0, g(c, 0), 1, g(c, 1));
  std::vector<int> evaluations(shift.size(), 2);
  const double tolerance = 1e-12;
  for (int round = 0; round < 100; ++round) {
    for (std::size_t k = 0; k < shift.size(); ++k) {
      RootBracket& b = brackets[k];
      if (!(b.width() > tolerance)) continue;
      const double x = b.probe();
      b.update(x, g(shift[k], x));
      ++evaluations[k];
    }
  }
  RootOptions o;
  o.tolerance = tolerance;
  for (std::size_t k = 0; k < shift.size(); ++k) {
    const RootResult r = find_root([&](double x) { return g(shift[k], x); }, 0, 1, o);
    EXPECT_EQ(r.x, brackets[k].estimate()) << k;
    EXPECT_EQ(r.evaluations, evaluations[k]) << k;
    EXPECT_NEAR(r.x, shift[k], 1e-11) << k;  // the cube root is steep: creeping, then bisection
    EXPECT_LE(r.evaluations, 2 + 70) << k;
  }
}

TEST(FindRoot, StopsAtTheStepLimitAndChecksItsArguments) {
  const auto g = [](double x) { return x - 0.3; };
  RootOptions o;
  o.max_steps = 0;
  const RootResult linear = find_root(g, 0, 1, o);
  EXPECT_EQ(linear.evaluations, 2);
  EXPECT_FALSE(linear.converged);
  EXPECT_NEAR(linear.x, 0.3, 1e-15);               // the secant of the ends: exact for a line
  EXPECT_EQ(find_root(g, 0.3, 1).evaluations, 2);  // a root at an end
  EXPECT_EQ(find_root(g, 0.3, 1).x, 0.3);
  EXPECT_THROW((void)find_root(g, 0.5, 1), InvalidArgument);  // no sign change
  EXPECT_THROW((void)find_root(g, 1, 0), InvalidArgument);
  EXPECT_THROW((void)find_root(g, 0, std::numeric_limits<double>::infinity()), InvalidArgument);
  EXPECT_THROW((void)find_root([](double) { return std::nan(""); }, 0, 1), InvalidArgument);
  RootOptions bad;
  bad.tolerance = -1;
  EXPECT_THROW((void)find_root(g, 0, 1, bad), InvalidArgument);
  bad = {};
  bad.max_steps = -1;
  EXPECT_THROW((void)find_root(g, 0, 1, bad), InvalidArgument);
  bad = {};
  bad.value_tolerance = std::nan("");
  EXPECT_THROW((void)find_root(g, 0, 1, bad), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
