// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The reductions follow the classic designs (Cody & Waite's split constants, fdlibm's kernel
// polynomials for sin and cos on [-pi/4, pi/4], Kahan's log1p); the code is our own.
#include "ramiform/core/portable_math.h"

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

namespace ramiform::pm {
namespace {

using namespace detail;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// pi/2, pi/4 and pi as a double plus the double nearest to the rest.
constexpr double kPio2Hi = 1.5707963267948966;
constexpr double kPio2Lo = 6.123233995736766e-17;
constexpr double kPio4Hi = 0.78539816339744828;
constexpr double kPio4Lo = 3.061616997868383e-17;
constexpr double kPiHi = 3.1415926535897931;
constexpr double kPiLo = 1.2246467991473532e-16;
constexpr double kTanPi8 = 0.41421356237309503;

// pi/2 in three parts of 33 bits (fdlibm's pio2_1, pio2_2, pio2_3; their sum is pi/2 within
// 8.5e-32): k * part is exact for |k| < 2^20.
constexpr double kPio2Part1 = 1.57079632673412561417e+00;
constexpr double kPio2Part2 = 6.07710050630396597660e-11;
constexpr double kPio2Part3 = 2.02226624871116645580e-21;
constexpr double kTwoOverPi = 6.36619772367581382433e-01;

// sin(r) = r + r^3 S(r^2) and cos(r) = 1 - r^2 / 2 + r^4 C(r^2) on |r| <= pi/4 (fdlibm's
// kernel coefficients).
constexpr double kSinPoly[] = {-1.66666666666666324348e-01, 8.33333333332248946124e-03,
                               -1.98412698298579493134e-04, 2.75573137070700676789e-06,
                               -2.50507602534068634195e-08, 1.58969099521155010221e-10};
constexpr double kCosPoly[] = {4.16666666666666019037e-02, -1.38888888888741095749e-03,
                               2.48015872894767294178e-05, -2.75573143513906633035e-07,
                               2.08757232129817482790e-09, -1.13596475577881948265e-11};

// c[0] + c[1] x + ... + c[N-1] x^(N-1), Horner's rule (the order of the SIMD code).
template <std::size_t N>
double horner(double x, const double (&c)[N]) {
  double p = c[N - 1];
  for (std::size_t k = N - 1; k-- > 0;) p = p * x + c[k];
  return p;
}

// Nearest integer of |x| < 2^51, ties to even (no dependence on the rounding-mode functions).
double round_nearest(double x) { return (x + kRoundMagic) - kRoundMagic; }

// atan(p / q) for 0 <= p <= q (q > 0), without overflow: reduced to |t| <= tan(pi/8).
double atan_ratio(double p, double q) {
  const bool mid = p > kTanPi8 * q;
  const double t = mid ? (p - q) / (p + q) : p / q;
  const double w = t * t;
  const double at = (t * w) * horner(w, kAtanPoly) + t;
  return mid ? kPio4Hi + (at + kPio4Lo) : at;
}

double sin_kernel(double r) {
  const double z = r * r;
  return r + (z * r) * horner(z, kSinPoly);
}

double cos_kernel(double r) {
  const double z = r * r;
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  // w carries the leading 1 - z/2; what its rounding lost is added back with the tail.
  return w + (((1.0 - w) - hz) + (z * z) * horner(z, kCosPoly));
}

// x = k pi/2 + r with |r| <~ pi/4; returns r and sets quadrant = k mod 4.
double reduce_half_pi(double x, int& quadrant) {
  if (std::fabs(x) <= kPio4Hi) {
    quadrant = 0;
    return x;
  }
  const double k = round_nearest(x * kTwoOverPi);
  quadrant = static_cast<int>(static_cast<std::int64_t>(k) & 3);
  return ((x - k * kPio2Part1) - k * kPio2Part2) - k * kPio2Part3;
}

}  // namespace

double exp(double x) {
  if (std::isnan(x)) return x;
  // Outside [-746, 710] e^x rounds to 0 or overflows: the clamp keeps k in the exponent range.
  const double xc = std::fmin(std::fmax(x, -746.0), 710.0);
  const double k = (xc * kInvLn2 + kRoundMagic) - kRoundMagic;
  const double r = (xc - k * kLn2Hi) - k * kLn2Lo;
  const double p = 1.0 + ((r * r) * horner(r, kExpPoly) + r);
  return std::ldexp(p, static_cast<int>(k));  // exact scaling, one rounding when subnormal
}

double log(double x) {
  if (std::isnan(x)) return x;
  if (x < 0.0) return kNaN;
  if (x == 0.0) return -kInf;
  if (x == kInf) return x;
  double shift = 0.0;
  if (x < std::numeric_limits<double>::min()) {  // subnormal: scale into the normal range
    x *= 18014398509481984.0;                    // 2^54, exact
    shift = 54.0;
  }
  // x = 2^e m with m in [sqrt(2)/2, sqrt(2)): as in the SIMD code (field/skeleton_field_simd).
  const std::uint64_t bits =
      std::bit_cast<std::uint64_t>(x) + (0x3ff0000000000000ULL - 0x3fe6a09e00000000ULL);
  const double e = static_cast<double>(static_cast<std::int64_t>(bits >> 52) - 1023) - shift;
  const double m = std::bit_cast<double>((bits & 0x000fffffffffffffULL) + 0x3fe6a09e00000000ULL);
  const double f = m - 1.0;  // exact (Sterbenz)
  // ln(1 + f) = 2 atanh(s), s = f / (2 + f); 2 s = f - s f keeps the leading term exact.
  const double s = f / (2.0 + f);
  const double z = s * s;
  const double ln_m = f - s * (f - z * horner(z, kLogPoly));
  return e * kLn2Hi + (e * kLn2Lo + ln_m);
}

double log1p(double x) {
  if (std::isnan(x)) return x;
  if (x < -1.0) return kNaN;
  if (x == kInf) return x;
  const double u = 1.0 + x;
  if (u == 1.0) return x;  // |x| below half an ulp of 1: ln(1 + x) = x to double precision
  if (u == 0.0) return -kInf;
  // Kahan: ln(u) x / (u - 1) cancels the rounding of 1 + x.
  return log(u) * (x / (u - 1.0));
}

double pow(double x, double y) {
  if (y == 0.0 || x == 1.0) return 1.0;
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  const bool integer = std::fabs(y) < 9007199254740992.0 && round_nearest(y) == y;
  const bool odd = integer && std::fmod(y, 2.0) != 0.0;
  if (integer && std::fabs(y) <= 64.0) {
    // Repeated squaring: exact where the powers are, a few roundings otherwise.
    auto n = static_cast<unsigned>(std::fabs(y));
    double base = x;
    double acc = 1.0;
    while (n != 0) {
      if ((n & 1U) != 0) acc *= base;
      n >>= 1U;
      if (n != 0) base *= base;
    }
    return y < 0.0 ? 1.0 / acc : acc;
  }
  if (y == 0.5 && x >= 0.0 && x != kInf) return std::sqrt(x);  // correctly rounded
  if (std::isinf(y)) {
    const double ax = std::fabs(x);
    if (ax == 1.0) return 1.0;
    return (ax > 1.0) == (y > 0.0) ? kInf : 0.0;
  }
  if (x == 0.0 || std::isinf(x)) {
    const bool big = (x == 0.0) == (y < 0.0);  // 0^negative and inf^positive are infinite
    const double magnitude = big ? kInf : 0.0;
    return odd && std::signbit(x) ? -magnitude : magnitude;
  }
  if (x < 0.0) {
    if (!integer) return kNaN;
    const double r = exp(y * log(-x));
    return odd ? -r : r;
  }
  return exp(y * log(x));
}

double sin(double x) {
  if (!std::isfinite(x)) return kNaN;
  if (x == 0.0) return x;  // keeps the sign of zero
  int q = 0;
  const double r = reduce_half_pi(x, q);
  switch (q) {
    case 0:
      return sin_kernel(r);
    case 1:
      return cos_kernel(r);
    case 2:
      return -sin_kernel(r);
    default:
      return -cos_kernel(r);
  }
}

double cos(double x) {
  if (!std::isfinite(x)) return kNaN;
  int q = 0;
  const double r = reduce_half_pi(x, q);
  switch (q) {
    case 0:
      return cos_kernel(r);
    case 1:
      return -sin_kernel(r);
    case 2:
      return -cos_kernel(r);
    default:
      return sin_kernel(r);
  }
}

double tan(double x) {
  if (!std::isfinite(x)) return kNaN;
  if (x == 0.0) return x;
  int q = 0;
  const double r = reduce_half_pi(x, q);
  const double s = sin_kernel(r);
  const double c = cos_kernel(r);
  return (q & 1) == 0 ? s / c : -c / s;
}

double atan(double x) {
  if (std::isnan(x)) return x;
  const double a = std::fabs(x);
  const double angle = a > 1.0 ? kPio2Hi - (atan_ratio(1.0, a) - kPio2Lo) : atan_ratio(a, 1.0);
  return std::copysign(angle, x);
}

double atan2(double y, double x) {
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  const double ay = std::fabs(y);
  const double ax = std::fabs(x);
  double angle = 0.0;
  if (std::isinf(ax) && std::isinf(ay)) {
    angle = kPio4Hi;
  } else if (ax == 0.0 && ay == 0.0) {
    angle = 0.0;
  } else if (ay > ax) {
    angle = kPio2Hi - (atan_ratio(ax, ay) - kPio2Lo);
  } else {
    angle = atan_ratio(ay, ax);
  }
  // The left half plane (x < 0, or x = -0): pi - angle.
  if (std::signbit(x)) angle = kPiHi - (angle - kPiLo);
  return std::copysign(angle, y);
}

double asin(double x) {
  if (std::isnan(x) || std::fabs(x) > 1.0) return kNaN;
  return atan2(x, std::sqrt((1.0 - x) * (1.0 + x)));
}

double acos(double x) {
  if (std::isnan(x) || std::fabs(x) > 1.0) return kNaN;
  return atan2(std::sqrt((1.0 - x) * (1.0 + x)), x);
}

double cbrt(double x) {
  if (!std::isfinite(x) || x == 0.0) return x;
  // |x| = f 2^e, f in [0.5, 1); move e to a multiple of 3, leaving f' in [0.5, 4).
  int e = 0;
  double f = std::frexp(std::fabs(x), &e);
  const int r = ((e % 3) + 3) % 3;
  f = std::ldexp(f, r);
  e -= r;
  // Newton's iteration t <- t - (t - f / t^2) / 3 from (f' + 2) / 3: six steps reach double
  // precision from the worst start on [0.5, 4).
  double t = (f + 2.0) / 3.0;
  for (int step = 0; step < 6; ++step) t = t - (t - f / (t * t)) / 3.0;
  return std::copysign(std::ldexp(t, e / 3), x);
}

double hypot(double x, double y) {
  double a = std::fabs(x);
  double b = std::fabs(y);
  if (std::isinf(a) || std::isinf(b)) return kInf;
  if (std::isnan(a) || std::isnan(b)) return kNaN;
  if (a < b) std::swap(a, b);
  if (a == 0.0) return 0.0;
  const double q = b / a;
  return a * std::sqrt(1.0 + q * q);
}

Mat3 rotation(double angle, const Vec3& axis) {
  // Rodrigues: R = c I + s [axis]x + (1 - c) axis axis^T.
  const double c = cos(angle);
  const double s = sin(angle);
  const double t = 1.0 - c;
  const Vec3 a = axis;
  Mat3 r;
  r << t * a.x() * a.x() + c, t * a.x() * a.y() - s * a.z(), t * a.x() * a.z() + s * a.y(),
      t * a.x() * a.y() + s * a.z(), t * a.y() * a.y() + c, t * a.y() * a.z() - s * a.x(),
      t * a.x() * a.z() - s * a.y(), t * a.y() * a.z() + s * a.x(), t * a.z() * a.z() + c;
  return r;
}

}  // namespace ramiform::pm
