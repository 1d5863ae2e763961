// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The portable elementary functions (core/portable_math.h): their accuracy against the C
// library's on random arguments, their special values, and bit patterns fixed here so that a
// change of a single result on any machine fails the test.

#include "ramiform/core/portable_math.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <string>

#include "ramiform/core/random.h"

namespace ramiform {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Distance in units in the last place between two finite doubles of the same sign (the
// number of representable doubles between them).
double ulps(double a, double b) {
  if (a == b) return 0;
  if (std::signbit(a) != std::signbit(b))
    return std::fabs(a - b) / std::numeric_limits<double>::denorm_min();
  const auto ia = static_cast<std::int64_t>(std::bit_cast<std::uint64_t>(std::fabs(a)));
  const auto ib = static_cast<std::int64_t>(std::bit_cast<std::uint64_t>(std::fabs(b)));
  return static_cast<double>(ia > ib ? ia - ib : ib - ia);
}

struct Case {
  const char* name;
  std::function<double(double)> ours;
  std::function<double(double)> libm;
  double lo, hi;  // uniform arguments in [lo, hi] (or log-uniform when `log_scale`)
  bool log_scale;
  double max_ulps;
};

TEST(PortableMath, AgreesWithTheCLibraryWithinAFewUlps) {
  const Case cases[] = {
      {"exp", [](double x) { return pm::exp(x); }, [](double x) { return std::exp(x); }, -745, 709,
       false, 2},
      {"exp small", [](double x) { return pm::exp(x); }, [](double x) { return std::exp(x); }, -1,
       1, false, 2},
      {"log", [](double x) { return pm::log(x); }, [](double x) { return std::log(x); }, -300, 300,
       true, 2},
      {"log near 1", [](double x) { return pm::log(x); }, [](double x) { return std::log(x); }, 0.9,
       1.1, false, 2},
      {"log1p", [](double x) { return pm::log1p(x); }, [](double x) { return std::log1p(x); },
       -0.999, 10, false, 2},
      {"log1p tiny", [](double x) { return pm::log1p(x); }, [](double x) { return std::log1p(x); },
       -20, -1, true, 2},
      {"sin", [](double x) { return pm::sin(x); }, [](double x) { return std::sin(x); }, -1000,
       1000, false, 2},
      {"cos", [](double x) { return pm::cos(x); }, [](double x) { return std::cos(x); }, -1000,
       1000, false, 2},
      {"sin small", [](double x) { return pm::sin(x); }, [](double x) { return std::sin(x); }, -3,
       3, false, 2},
      {"tan", [](double x) { return pm::tan(x); }, [](double x) { return std::tan(x); }, -10, 10,
       false, 3},
      {"atan", [](double x) { return pm::atan(x); }, [](double x) { return std::atan(x); }, -50, 50,
       false, 2},
      {"atan wide", [](double x) { return pm::atan(x); }, [](double x) { return std::atan(x); },
       -200, 200, true, 2},
      {"asin", [](double x) { return pm::asin(x); }, [](double x) { return std::asin(x); }, -1, 1,
       false, 3},
      {"acos", [](double x) { return pm::acos(x); }, [](double x) { return std::acos(x); }, -1, 1,
       false, 3},
      {"cbrt", [](double x) { return pm::cbrt(x); }, [](double x) { return std::cbrt(x); }, -300,
       300, true, 3},
      {"cbrt negative", [](double x) { return pm::cbrt(-x); },
       [](double x) { return std::cbrt(-x); }, 1e-5, 1e5, false, 3},
  };
  Rng rng(20261201);
  for (const Case& c : cases) {
    double worst = 0;
    double at = 0;
    for (int i = 0; i < 200000; ++i) {
      const double u = rng.uniform(c.lo, c.hi);
      const double x = c.log_scale ? std::pow(10.0, u) : u;
      const double e = ulps(c.ours(x), c.libm(x));
      if (e > worst) {
        worst = e;
        at = x;
      }
    }
    EXPECT_LE(worst, c.max_ulps) << c.name << " at " << at;
  }
}

TEST(PortableMath, TwoArgumentFunctionsAgreeWithinAFewUlps) {
  Rng rng(7);
  double worst_atan2 = 0, worst_hypot = 0, worst_pow_excess = 0;
  for (int i = 0; i < 200000; ++i) {
    const double y = rng.uniform(-1, 1) * std::pow(10.0, rng.uniform(-20, 20));
    const double x = rng.uniform(-1, 1) * std::pow(10.0, rng.uniform(-20, 20));
    worst_atan2 = std::max(worst_atan2, ulps(pm::atan2(y, x), std::atan2(y, x)));
    worst_hypot = std::max(worst_hypot, ulps(pm::hypot(y, x), std::hypot(y, x)));
    const double b = std::pow(10.0, rng.uniform(-10, 10));
    const double p = rng.uniform(-8, 8);
    const double bound = 2 + 2 * std::fabs(p * std::log(b));
    worst_pow_excess = std::max(worst_pow_excess, ulps(pm::pow(b, p), std::pow(b, p)) - bound);
  }
  EXPECT_LE(worst_atan2, 3);
  EXPECT_LE(worst_hypot, 2);
  EXPECT_LE(worst_pow_excess, 0);
  // Integer powers are products: exact where the power is representable.
  EXPECT_EQ(pm::pow(3.0, 20.0), 3486784401.0);
  EXPECT_EQ(pm::pow(2.0, -10.0), 1.0 / 1024.0);
  EXPECT_EQ(pm::pow(-2.0, 3.0), -8.0);
  EXPECT_EQ(pm::pow(2.0, 0.5), std::sqrt(2.0));
}

TEST(PortableMath, SpecialValuesFollowC) {
  EXPECT_EQ(pm::exp(0), 1.0);
  EXPECT_EQ(pm::exp(-kInf), 0.0);
  EXPECT_EQ(pm::exp(kInf), kInf);
  EXPECT_EQ(pm::exp(800), kInf);
  EXPECT_EQ(pm::exp(-800), 0.0);
  EXPECT_GT(pm::exp(-744), 0.0);  // subnormal results
  EXPECT_TRUE(std::isnan(pm::exp(kNaN)));
  EXPECT_EQ(pm::log(1), 0.0);
  EXPECT_EQ(pm::log(0), -kInf);
  EXPECT_EQ(pm::log(kInf), kInf);
  EXPECT_TRUE(std::isnan(pm::log(-1)));
  EXPECT_LE(ulps(pm::log(std::numeric_limits<double>::denorm_min()), -744.4400719213812), 1);
  EXPECT_EQ(pm::log1p(-1), -kInf);
  EXPECT_EQ(pm::log1p(1e-300), 1e-300);
  EXPECT_TRUE(std::isnan(pm::log1p(-2)));
  EXPECT_TRUE(std::isnan(pm::sin(kInf)));
  EXPECT_TRUE(std::isnan(pm::cos(kNaN)));
  EXPECT_EQ(pm::sin(0.0), 0.0);
  EXPECT_TRUE(std::signbit(pm::sin(-0.0)));
  EXPECT_EQ(pm::cos(0.0), 1.0);
  EXPECT_EQ(pm::atan(kInf), std::numbers::pi / 2);
  EXPECT_EQ(pm::atan(-kInf), -std::numbers::pi / 2);
  EXPECT_EQ(pm::atan2(0.0, -1.0), std::numbers::pi);
  EXPECT_EQ(pm::atan2(-0.0, -0.0), -std::numbers::pi);
  EXPECT_EQ(pm::atan2(0.0, 0.0), 0.0);
  EXPECT_TRUE(std::signbit(pm::atan2(-0.0, 1.0)));
  EXPECT_EQ(pm::atan2(kInf, kInf), std::numbers::pi / 4);
  EXPECT_EQ(pm::atan2(1.0, 0.0), std::numbers::pi / 2);
  EXPECT_EQ(pm::asin(1.0), std::numbers::pi / 2);
  EXPECT_EQ(pm::acos(-1.0), std::numbers::pi);
  EXPECT_EQ(pm::acos(1.0), 0.0);
  EXPECT_TRUE(std::isnan(pm::acos(1.5)));
  EXPECT_EQ(pm::cbrt(27.0), 3.0);
  EXPECT_EQ(pm::cbrt(-8.0), -2.0);
  EXPECT_EQ(pm::cbrt(-kInf), -kInf);
  EXPECT_EQ(pm::hypot(3, 4), 5.0);
  EXPECT_EQ(pm::hypot(kNaN, kInf), kInf);
  EXPECT_EQ(pm::hypot(1e300, 1e300), 1e300 * std::sqrt(2.0));
  EXPECT_EQ(pm::pow(0.0, -1.0), kInf);
  EXPECT_EQ(pm::pow(-0.0, -3.0), -kInf);
  EXPECT_EQ(pm::pow(kNaN, 0.0), 1.0);
  EXPECT_EQ(pm::pow(1.0, kNaN), 1.0);
  EXPECT_TRUE(std::isnan(pm::pow(-2.0, 0.5)));
  EXPECT_EQ(pm::pow(0.5, kInf), 0.0);
  EXPECT_EQ(pm::pow(2.0, -kInf), 0.0);
  EXPECT_EQ(pm::pow(-8.0, 101.0), -pm::exp(101.0 * pm::log(8.0)));
}

// A hash of many results of every function: the same bits on every machine and C library is
// the point of these functions, so the expected value is written down here. (Computed once on
// x86-64; a different value elsewhere is a bug in this file, not in the machine.)
TEST(PortableMath, ResultsAreFixedBitPatterns) {
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&h](double v) { h = (h ^ std::bit_cast<std::uint64_t>(v)) * 1099511628211ULL; };
  for (int i = 1; i <= 20000; ++i) {
    const double x = (i - 10000.5) / 997.0;  // exact decimal-free grid of [-10, 10]
    const double y = i / 1234.0;
    mix(pm::exp(x));
    mix(pm::log(y));
    mix(pm::log1p(y));
    mix(pm::pow(y, x));
    mix(pm::sin(x * 50));
    mix(pm::cos(x * 50));
    mix(pm::tan(x));
    mix(pm::atan(x));
    mix(pm::atan2(x, y - 8));
    mix(pm::asin(x / 10.000001));
    mix(pm::acos(x / 10.000001));
    mix(pm::cbrt(x * 1e5));
    mix(pm::hypot(x, y));
  }
  EXPECT_EQ(h, 0x6b4748ffe6ad88beULL) << "hash 0x" << std::hex << h;
}

}  // namespace
}  // namespace ramiform
