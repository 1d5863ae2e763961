// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/kernels.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

// Wyvill, McPheeters & Wyvill (1986) coefficients as printed in Kochhar 2010, "Application of
// implicit methods to the interactive modeling of trees" (M.Sc. thesis), §3.2: the exact fractions
// -4/9, 17/9, -22/9 solve k(1/2) = 1/2, k(1) = 0, k'(1) = 0.
constexpr double kWyvillA = -4.0 / 9.0;
constexpr double kWyvillB = 17.0 / 9.0;
constexpr double kWyvillC = -22.0 / 9.0;
// Below this normalized distance the inverse power kernel is held constant (it is singular at 0).
constexpr double kInversePowerMinX = 1e-6;

std::string lower(std::string_view s) {
  std::string out(s);
  for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

}  // namespace

double Kernel::shape() const {
  switch (kind) {
    case KernelKind::kBlinn: return parameter > 0 ? parameter : 4.0;
    case KernelKind::kInversePower: return parameter > 0 ? parameter : 3.0;
    case KernelKind::kCauchy: return parameter > 0 ? parameter : 1.0;
    default: return 0.0;
  }
}

double Kernel::default_iso() const {
  switch (kind) {
    case KernelKind::kInversePower:
    case KernelKind::kCauchy: return 1.0;
    default: return 0.5;
  }
}

void Kernel::validate() const {
  if (!std::isfinite(parameter) || parameter < 0) {
    throw InvalidArgument("kernel " + kernel_name(kind) + ": parameter must be finite and >= 0 (0 = default), got " +
                          std::to_string(parameter));
  }
  if (kind == KernelKind::kInversePower && parameter != 0 && parameter < 2) {
    throw InvalidArgument("kernel inverse-power: alpha must be >= 2, got " + std::to_string(parameter));
  }
}

double Kernel::value(double x) const {
  switch (kind) {
    case KernelKind::kWyvill: {
      if (x >= 1) return 0;
      const double y = x * x;
      return 1 + y * (kWyvillC + y * (kWyvillB + y * kWyvillA));
    }
    case KernelKind::kBlinn: return pm::exp(-shape() * x * x);
    case KernelKind::kMetaball:
      if (x <= 1.0 / 3.0) return 1 - 3 * x * x;
      if (x < 1) return 1.5 * (1 - x) * (1 - x);
      return 0;
    case KernelKind::kInversePower: return pm::pow(std::max(x, kInversePowerMinX), -(shape() - 1));
    case KernelKind::kCauchy: {
      const double q = 1 + x * x;
      return 1 / (q * q);
    }
  }
  return 0;
}

double Kernel::derivative(double x) const {
  switch (kind) {
    case KernelKind::kWyvill: {
      if (x >= 1) return 0;
      const double y = x * x;
      return 2 * x * (kWyvillC + y * (2 * kWyvillB + 3 * kWyvillA * y));
    }
    case KernelKind::kBlinn: return -2 * shape() * x * pm::exp(-shape() * x * x);
    case KernelKind::kMetaball:
      if (x <= 1.0 / 3.0) return -6 * x;
      if (x < 1) return -3 * (1 - x);
      return 0;
    case KernelKind::kInversePower:
      if (x < kInversePowerMinX) return 0;
      return -(shape() - 1) * pm::pow(x, -shape());
    case KernelKind::kCauchy: {
      const double q = 1 + x * x;
      return -4 * x / (q * q * q);
    }
  }
  return 0;
}

double Kernel::x_at(double iso) const {
  if (!(iso > 0)) throw InvalidArgument("iso value must be > 0, got " + std::to_string(iso));
  switch (kind) {
    case KernelKind::kWyvill: {
      if (iso >= 1) break;
      // k is strictly decreasing on [0, 1]: bisection to full precision.
      double lo = 0, hi = 1;
      for (int i = 0; i < 200 && hi - lo > 0; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid == lo || mid == hi) break;
        (value(mid) > iso ? lo : hi) = mid;
      }
      return iso == 0.5 ? 0.5 : 0.5 * (lo + hi);
    }
    case KernelKind::kBlinn:
      if (iso >= 1) break;
      return std::sqrt(-pm::log(iso) / shape());
    case KernelKind::kMetaball:
      if (iso >= 1) break;
      if (iso >= 2.0 / 3.0) return std::sqrt((1 - iso) / 3);
      return 1 - std::sqrt(iso / 1.5);
    case KernelKind::kInversePower: return pm::pow(iso, -1 / (shape() - 1));
    case KernelKind::kCauchy:
      if (iso >= 1) break;
      return std::sqrt(1 / std::sqrt(iso) - 1);
  }
  throw InvalidArgument("iso value " + std::to_string(iso) + " is not reached by the " +
                        kernel_name(kind) + " kernel (its maximum is 1)");
}

double Kernel::support(double iso) const {
  const double floor_value = tol::kKernelCutoff * iso;
  switch (kind) {
    case KernelKind::kWyvill:
    case KernelKind::kMetaball: return 1.0;
    case KernelKind::kBlinn: return floor_value >= 1 ? 0.0 : std::sqrt(-pm::log(floor_value) / shape());
    case KernelKind::kInversePower: return pm::pow(floor_value, -1 / (shape() - 1));
    case KernelKind::kCauchy: return floor_value >= 1 ? 0.0 : std::sqrt(1 / std::sqrt(floor_value) - 1);
  }
  return 1.0;
}

Kernel parse_kernel(std::string_view text) {
  const auto colon = text.find(':');
  const std::string name = lower(text.substr(0, colon));
  Kernel k;
  if (name == "wyvill") {
    k.kind = KernelKind::kWyvill;
  } else if (name == "blinn") {
    k.kind = KernelKind::kBlinn;
  } else if (name == "metaball" || name == "murakami") {
    k.kind = KernelKind::kMetaball;
  } else if (name == "inverse-power" || name == "power") {
    k.kind = KernelKind::kInversePower;
  } else if (name == "cauchy") {
    k.kind = KernelKind::kCauchy;
  } else {
    throw InvalidArgument("unknown kernel '" + std::string(text) +
                          "' (expected wyvill, blinn[:B], metaball, inverse-power[:alpha] or "
                          "cauchy[:s*r])");
  }
  if (colon != std::string_view::npos) {
    const std::string_view num = text.substr(colon + 1);
    double v = 0;
    if (parse_number(num, v) != NumberStatus::kOk || v <= 0) {
      throw InvalidArgument("kernel '" + std::string(text) + "': parameter '" + std::string(num) +
                            "' is not a positive number");
    }
    if (k.kind == KernelKind::kWyvill || k.kind == KernelKind::kMetaball) {
      throw InvalidArgument("kernel '" + std::string(text) + "' takes no parameter");
    }
    k.parameter = v;
  }
  k.validate();
  return k;
}

std::string kernel_name(KernelKind kind) {
  switch (kind) {
    case KernelKind::kWyvill: return "wyvill";
    case KernelKind::kBlinn: return "blinn";
    case KernelKind::kMetaball: return "metaball";
    case KernelKind::kInversePower: return "inverse-power";
    case KernelKind::kCauchy: return "cauchy";
  }
  return "?";
}

double cauchy_segment_integral(const Vec3& p, const Vec3& a, const Vec3& b, double s,
                               Vec3* gradient) {
  const Vec3 d = b - a;
  const double len = d.norm();
  const Vec3 w = p - a;
  if (len == 0) {
    if (gradient != nullptr) gradient->setZero();
    return 0;
  }
  const Vec3 u = d / len;
  const double x = w.dot(u);
  const Vec3 q = w - x * u;  // component of w normal to the segment
  const double h2 = q.squaredNorm();
  const double s2 = s * s;
  const double P = 1 + s2 * h2;
  const double root_p = std::sqrt(P);
  const double u1 = len - x;
  const double u0 = -x;
  const double d1 = P + s2 * u1 * u1;  // 1 + s^2 |p - b|^2
  const double d0 = P + s2 * u0 * u0;  // 1 + s^2 |p - a|^2
  const double rational = u1 / (2 * P * d1) - u0 / (2 * P * d0);
  // atan(A) + atan(B) with A = s u1 / sqrt(P), B = s x / sqrt(P): arg((1 + iA)(1 + iB)), and
  // A + B = s len / sqrt(P) > 0, so atan2(A + B, 1 - AB) = pi/2 - atan((1 - AB) / (A + B)).
  const double A = s * u1 / root_p;
  const double B = s * x / root_p;
  const double angle = std::numbers::pi / 2 - pm::atan((1 - A * B) / (A + B));
  const double F = rational + angle / (2 * s * P * root_p);
  if (gradient != nullptr) {
    // dF/dx = k(|p-a|) - k(|p-b|); dF/dP = -2 int (P + s^2 u^2)^-3 du, by the reduction formula
    // int (P + s^2u^2)^-3 = u / (4P (P + s^2u^2)^2) + 3/(4P) int (P + s^2u^2)^-2; grad P = 2 s^2 q.
    const double dfdx = 1 / (d0 * d0) - 1 / (d1 * d1);
    const double j = u1 / (4 * P * d1 * d1) - u0 / (4 * P * d0 * d0) + 3 * F / (4 * P);
    *gradient = dfdx * u + (-2 * j) * (2 * s2) * q;
  }
  return F;
}

}  // namespace ramiform
