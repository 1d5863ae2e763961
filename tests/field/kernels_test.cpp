// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/kernels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using test::reference_kernel;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

const Kernel kWyvill{KernelKind::kWyvill, 0.0};
const Kernel kBlinn{KernelKind::kBlinn, 0.0};
const Kernel kMetaball{KernelKind::kMetaball, 0.0};
const Kernel kPower{KernelKind::kInversePower, 0.0};
const Kernel kCauchy{KernelKind::kCauchy, 0.0};

TEST(Kernels, WyvillKnownValues) {
  EXPECT_DOUBLE_EQ(kWyvill.value(0.0), 1.0);
  EXPECT_NEAR(kWyvill.value(0.5), 0.5, 1e-15);
  EXPECT_NEAR(kWyvill.value(1.0), 0.0, 1e-15);
  EXPECT_NEAR(kWyvill.derivative(1.0), 0.0, 1e-14);
  EXPECT_EQ(kWyvill.derivative(0.0), 0.0);
  EXPECT_EQ(kWyvill.value(1.5), 0.0);
  EXPECT_EQ(kWyvill.value(100.0), 0.0);
  EXPECT_EQ(kWyvill.derivative(1.5), 0.0);
  // Kochhar 2010 §3.2 coefficients: a = -4/9, b = 17/9, c = -22/9.
  for (double x : {0.1, 0.3, 0.77, 0.99}) {
    EXPECT_NEAR(kWyvill.value(x), reference_kernel(KernelKind::kWyvill, 0, x), 1e-15) << x;
    const double d = -44.0 / 9 * x + 68.0 / 9 * x * x * x - 24.0 / 9 * std::pow(x, 5);
    EXPECT_NEAR(kWyvill.derivative(x), d, 1e-14) << x;
  }
  EXPECT_EQ(kWyvill.default_iso(), 0.5);
  EXPECT_NEAR(kWyvill.x_at(0.5), 0.5, 1e-15);
  EXPECT_EQ(kWyvill.support(0.5), 1.0);
  EXPECT_EQ(kWyvill.shape(), 0.0);
}

TEST(Kernels, MetaballKnownValuesAndContinuity) {
  EXPECT_EQ(kMetaball.value(0.0), 1.0);
  const double third = 1.0 / 3;
  // Both pieces meet at 1/3 with value 2/3 and slope -2 (C1).
  EXPECT_NEAR(kMetaball.value(std::nextafter(third, 0.0)), 2.0 / 3, 1e-15);
  EXPECT_NEAR(kMetaball.value(std::nextafter(third, 1.0)), 2.0 / 3, 1e-15);
  EXPECT_NEAR(kMetaball.derivative(std::nextafter(third, 0.0)), -2.0, 1e-14);
  EXPECT_NEAR(kMetaball.derivative(std::nextafter(third, 1.0)), -2.0, 1e-14);
  for (double x : {0.1, 0.2, 0.3}) {
    EXPECT_NEAR(kMetaball.value(x), 1 - 3 * x * x, 1e-15);
    EXPECT_NEAR(kMetaball.derivative(x), -6 * x, 1e-14);
  }
  for (double x : {0.4, 0.6, 0.9}) {
    EXPECT_NEAR(kMetaball.value(x), 1.5 * (1 - x) * (1 - x), 1e-15);
    EXPECT_NEAR(kMetaball.derivative(x), -3 * (1 - x), 1e-14);
  }
  EXPECT_NEAR(kMetaball.value(1.0), 0.0, 1e-15);
  EXPECT_EQ(kMetaball.value(1.2), 0.0);
  EXPECT_EQ(kMetaball.derivative(1.2), 0.0);
  EXPECT_NEAR(kMetaball.x_at(0.5), 1 - 1 / std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(kMetaball.x_at(0.8), std::sqrt(0.2 / 3), 1e-15);  // first piece
  EXPECT_EQ(kMetaball.support(0.5), 1.0);
  EXPECT_EQ(kMetaball.default_iso(), 0.5);
}

TEST(Kernels, BlinnIsGaussian) {
  for (double b : {0.0, 1.0, 2.5, 9.0}) {
    const Kernel k{KernelKind::kBlinn, b};
    const double bb = b == 0 ? 4.0 : b;
    EXPECT_EQ(k.shape(), bb);
    for (double x : {0.0, 0.2, 0.5, 1.0, 1.7}) {
      EXPECT_NEAR(k.value(x), std::exp(-bb * x * x), 1e-15) << b << " " << x;
      EXPECT_NEAR(k.derivative(x), -2 * bb * x * std::exp(-bb * x * x), 1e-14) << b << " " << x;
    }
    EXPECT_NEAR(k.x_at(0.5), std::sqrt(std::log(2.0) / bb), 1e-15);
    // Support: where k falls to kKernelCutoff * iso.
    for (double iso : {0.5, 0.2}) {
      EXPECT_NEAR(k.support(iso), std::sqrt(std::log(1 / (tol::kKernelCutoff * iso)) / bb), 1e-12);
    }
  }
  EXPECT_EQ(kBlinn.default_iso(), 0.5);
}

TEST(Kernels, InversePower) {
  for (double alpha : {0.0, 2.0, 3.0, 4.5}) {
    const Kernel k{KernelKind::kInversePower, alpha};
    const double a = alpha == 0 ? 3.0 : alpha;
    EXPECT_EQ(k.shape(), a);
    for (double x : {0.1, 0.5, 1.0, 2.0, 10.0}) {
      EXPECT_NEAR(k.value(x) / std::pow(x, -(a - 1)), 1.0, 1e-14) << a << " " << x;
      EXPECT_NEAR(k.derivative(x) / (-(a - 1) * std::pow(x, -a)), 1.0, 1e-14) << a << " " << x;
    }
    EXPECT_NEAR(k.x_at(1.0), 1.0, 1e-15);
    EXPECT_NEAR(k.x_at(0.25), std::pow(0.25, -1 / (a - 1)), 1e-13);
    EXPECT_NEAR(k.support(1.0), std::pow(tol::kKernelCutoff, -1 / (a - 1)), 1e-10);
  }
  EXPECT_EQ(kPower.default_iso(), 1.0);
  EXPECT_EQ(kPower.value(1.0), 1.0);
}

TEST(Kernels, Cauchy) {
  EXPECT_EQ(kCauchy.default_iso(), 1.0);
  EXPECT_EQ(kCauchy.shape(), 1.0);
  EXPECT_EQ((Kernel{KernelKind::kCauchy, 2.0}.shape()), 2.0);
  for (double x : {0.0, 0.5, 1.0, 3.0}) {
    EXPECT_NEAR(kCauchy.value(x), 1 / std::pow(1 + x * x, 2), 1e-15);
    EXPECT_NEAR(kCauchy.derivative(x), -4 * x / std::pow(1 + x * x, 3), 1e-15);
  }
  EXPECT_THROW((void)kCauchy.x_at(1.0), InvalidArgument);
  // 1 / (1 + x^2)^2 = 1/2 at x = sqrt(sqrt(2) - 1).
  EXPECT_NEAR(kCauchy.x_at(0.5), std::sqrt(std::sqrt(2.0) - 1), 1e-15);
  EXPECT_NEAR(kCauchy.value(kCauchy.x_at(0.25)), 0.25, 1e-15);
  // Support where 1/(1+x^2)^2 = kKernelCutoff * iso.
  const double s = kCauchy.support(1.0);
  EXPECT_NEAR(1 / std::pow(1 + s * s, 2), tol::kKernelCutoff, 1e-12);
}

TEST(Kernels, DerivativeMatchesFiniteDifferences) {
  std::vector<Kernel> all = test::distance_kernels();
  all.push_back(kCauchy);
  all.push_back(Kernel{KernelKind::kCauchy, 0.3});
  Rng rng(17);
  for (const Kernel& k : all) {
    const bool compact = k.kind == KernelKind::kWyvill || k.kind == KernelKind::kMetaball;
    for (int i = 0; i < 300; ++i) {
      const double x = compact ? rng.uniform(0.001, 1.3) : rng.uniform(0.05, 4.0);
      if (std::abs(x - 1.0 / 3) < 1e-3 || std::abs(x - 1.0) < 1e-3) continue;  // breakpoints
      const double h = 1e-6 * std::max(x, 0.01);
      const double fd = (k.value(x + h) - k.value(x - h)) / (2 * h);
      const double d = k.derivative(x);
      EXPECT_NEAR(d, fd, 1e-7 * std::max(1.0, std::abs(d)))
          << kernel_name(k.kind) << ":" << k.parameter << " x " << x;
      // And the value against the formula.
      EXPECT_NEAR(k.value(x), reference_kernel(k.kind, k.parameter, x),
                  1e-14 * std::max(1.0, std::abs(k.value(x))))
          << kernel_name(k.kind) << " x " << x;
    }
  }
}

TEST(Kernels, XAtReachesIso) {
  for (const Kernel& k : test::distance_kernels()) {
    for (double iso : {0.05, 0.2, 0.5, 0.7, 0.95}) {
      const double x = k.x_at(iso);
      EXPECT_GE(x, 0.0);
      EXPECT_NEAR(k.value(x), iso, 1e-12 * iso) << kernel_name(k.kind) << " iso " << iso;
      EXPECT_NEAR(reference_kernel(k.kind, k.parameter, x), iso, 1e-12 * iso)
          << kernel_name(k.kind) << " iso " << iso;
      // Support beyond the iso point.
      EXPECT_GT(k.support(iso), x);
    }
  }
  // Power kernels reach every positive iso, even above 1.
  EXPECT_NEAR(kPower.value(kPower.x_at(4.0)), 4.0, 1e-12);
}

TEST(Kernels, XAtThrowsWhenIsoUnreachable) {
  // iso >= k(0) = 1 for the bounded kernels.
  for (const Kernel& k : {kWyvill, kBlinn, kMetaball}) {
    EXPECT_THROW((void)k.x_at(1.0), InvalidArgument) << kernel_name(k.kind);
    EXPECT_THROW((void)k.x_at(1.5), InvalidArgument) << kernel_name(k.kind);
  }
}

TEST(Kernels, InfiniteSupportIsCutoffPoint) {
  for (const Kernel& k : test::distance_kernels()) {
    if (!test::is_infinite_kernel(k.kind)) continue;
    for (double iso : {0.5, 1.0}) {
      const double s = k.support(iso);
      EXPECT_NEAR(reference_kernel(k.kind, k.parameter, s), tol::kKernelCutoff * iso,
                  1e-10 * tol::kKernelCutoff * iso)
          << kernel_name(k.kind);
    }
  }
}

TEST(Kernels, ValidateParameters) {
  for (const Kernel& k : test::distance_kernels()) EXPECT_NO_THROW(k.validate());
  EXPECT_NO_THROW(kCauchy.validate());
  EXPECT_NO_THROW((Kernel{KernelKind::kInversePower, 2.0}.validate()));
  for (double bad : {-1.0, kNaN, kInf, -kInf}) {
    EXPECT_THROW((Kernel{KernelKind::kBlinn, bad}.validate()), InvalidArgument) << bad;
    EXPECT_THROW((Kernel{KernelKind::kInversePower, bad}.validate()), InvalidArgument) << bad;
    EXPECT_THROW((Kernel{KernelKind::kCauchy, bad}.validate()), InvalidArgument) << bad;
  }
  // alpha must be >= 2.
  EXPECT_THROW((Kernel{KernelKind::kInversePower, 1.5}.validate()), InvalidArgument);
  EXPECT_THROW((Kernel{KernelKind::kInversePower, 1.0}.validate()), InvalidArgument);
}

TEST(Kernels, ParseKernel) {
  struct Case {
    const char* text;
    KernelKind kind;
    double parameter;
  };
  for (const Case& c : {Case{"wyvill", KernelKind::kWyvill, 0.0}, Case{"blinn", KernelKind::kBlinn, 0.0},
                        Case{"blinn:3", KernelKind::kBlinn, 3.0},
                        Case{"blinn:2.5", KernelKind::kBlinn, 2.5},
                        Case{"metaball", KernelKind::kMetaball, 0.0},
                        Case{"inverse-power", KernelKind::kInversePower, 0.0},
                        Case{"power", KernelKind::kInversePower, 0.0},
                        Case{"power:4", KernelKind::kInversePower, 4.0},
                        Case{"inverse-power:2", KernelKind::kInversePower, 2.0},
                        Case{"cauchy", KernelKind::kCauchy, 0.0},
                        Case{"cauchy:0.5", KernelKind::kCauchy, 0.5}}) {
    const Kernel k = parse_kernel(c.text);
    EXPECT_EQ(k.kind, c.kind) << c.text;
    EXPECT_EQ(k.parameter, c.parameter) << c.text;
  }
  EXPECT_EQ(parse_kernel("blinn:3").shape(), 3.0);
  EXPECT_EQ(parse_kernel("blinn").shape(), 4.0);
}

TEST(Kernels, ParseKernelRejectsBadText) {
  for (const char* bad : {"", "gauss", "wyvil", "blinn:", "blinn:abc", "blinn:3x", "blinn:-1",
                          "power:1", "cauchy:0x", ":3", "blinn:nan"}) {
    EXPECT_THROW((void)parse_kernel(bad), InvalidArgument) << "'" << bad << "'";
  }
  try {
    (void)parse_kernel("gauss");
    ADD_FAILURE();
  } catch (const InvalidArgument& e) {
    const std::string what = e.what();
    for (const char* name : {"gauss", "wyvill", "blinn", "metaball", "power", "cauchy"}) {
      EXPECT_NE(what.find(name), std::string::npos) << what << " lacks " << name;
    }
  }
}

TEST(Kernels, KernelNameRoundTrips) {
  for (KernelKind kind : {KernelKind::kWyvill, KernelKind::kBlinn, KernelKind::kMetaball,
                          KernelKind::kInversePower, KernelKind::kCauchy}) {
    EXPECT_EQ(parse_kernel(kernel_name(kind)).kind, kind) << kernel_name(kind);
  }
  EXPECT_EQ(kernel_name(KernelKind::kWyvill), "wyvill");
  EXPECT_EQ(kernel_name(KernelKind::kBlinn), "blinn");
  EXPECT_EQ(kernel_name(KernelKind::kMetaball), "metaball");
  EXPECT_EQ(kernel_name(KernelKind::kCauchy), "cauchy");
}

}  // namespace
}  // namespace ramiform
