// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Elementary functions that give the same bits on every machine. glibc's libm picks an FMA
/// variant of exp, log, pow, sin, cos, atan, ... at run time on CPUs that have FMA (measured
/// on glibc 2.36: on 2e6 random arguments each of those differs somewhere between the FMA and
/// the SSE2 variants), and other libm versions round differently again, so a mesh computed
/// with std:: functions depends on the CPU and the C library. These are written with plain
/// IEEE operations (+, -, *, /, sqrt, exact scaling by powers of two) in a fixed order and the
/// project's -ffp-contract=off, so their results depend on neither. Every code path of the
/// library that decides an output uses them instead of <cmath>'s transcendental functions.
///
/// Accuracy, measured against glibc's (correctly rounded or within 1 ulp) on random arguments
/// in tests/core/portable_math_test.cpp: exp, log, log1p, atan, sin, cos and hypot within 2 ulp,
/// atan2, asin, acos, tan and cbrt within 3 ulp; pow within 2 + 2 |y ln x| ulp (it is
/// exp(y log x) in double precision; integer exponents up to 64 by repeated squaring, y = 1/2
/// by the correctly rounded sqrt). sin, cos and tan reduce their argument with a
/// three-part pi/2 that is exact for |x| < 1.6e6; beyond that they stay deterministic but lose
/// accuracy. Special values (NaN, infinities, signed zeros, domain errors) follow C's rules,
/// without setting errno.

#include "ramiform/core/types.h"

namespace ramiform::pm {

[[nodiscard]] double exp(double x);
[[nodiscard]] double log(double x);
[[nodiscard]] double log1p(double x);
[[nodiscard]] double pow(double x, double y);
[[nodiscard]] double sin(double x);
[[nodiscard]] double cos(double x);
[[nodiscard]] double tan(double x);
[[nodiscard]] double atan(double x);
[[nodiscard]] double atan2(double y, double x);
[[nodiscard]] double asin(double x);
[[nodiscard]] double acos(double x);
[[nodiscard]] double cbrt(double x);
[[nodiscard]] double hypot(double x, double y);

/// The rotation by `angle` radians about the unit vector `axis` (right-handed), the matrix of
/// Eigen::AngleAxisd(angle, axis) with the sine and cosine above (Eigen's uses <cmath>'s).
[[nodiscard]] Mat3 rotation(double angle, const Vec3& axis);

/// The polynomial coefficients, shared with the SIMD field code (field/skeleton_field_simd.cpp),
/// which evaluates exp, log and atan in the same order lane by lane. They are Chebyshev fits
/// (mpmath 1.3 chebyfit at 50 digits, coefficients rounded to double) of the remainder of each
/// function's series on its reduced range.
namespace detail {
/// (e^r - 1 - r) / r^2 on |r| <= ln 2 / 2, 11 terms (fit error 1.4e-18).
inline constexpr double kExpPoly[] = {0.5,
                                      0.1666666666666667,
                                      0.04166666666666667,
                                      0.008333333333326141,
                                      0.0013888888888883752,
                                      0.00019841269874800493,
                                      2.4801587325533363e-05,
                                      2.7557255425746435e-06,
                                      2.7557273661348637e-07,
                                      2.510520637395701e-08,
                                      2.0914679376583935e-09};
/// (2 atanh(s) - 2 s) / s^3 in z = s^2 on |s| <= (sqrt 2 - 1) / (sqrt 2 + 1), 7 terms (3.1e-16,
/// scaled by z / 2 <= 0.015 in the result).
inline constexpr double kLogPoly[] = {0.666666666666667,  0.39999999999899505, 0.28571428625975487,
                                      0.2222221113479508, 0.18182889125261723, 0.15331721600556042,
                                      0.14616449685043406};
/// (atan(t) / t - 1) / t^2 in w = t^2 on |t| <= tan(pi / 8), 11 terms (3.2e-17, scaled by
/// w <= 0.17 in the result).
inline constexpr double kAtanPoly[] = {
    -0.3333333333333333,  0.1999999999999552,  -0.14285714284666542, 0.11111111015256361,
    -0.09090904578123903, 0.07692183190826087, -0.06664511447381948, 0.0585814891280221,
    -0.0508544973794026,  0.03923165829558719, -0.01917688711906226};
/// 1.5 * 2^52: x + kRoundMagic - kRoundMagic rounds |x| < 2^51 to the nearest integer (ties to
/// even), and the low bits of x + kRoundMagic hold that integer in two's complement.
inline constexpr double kRoundMagic = 6755399441055744.0;
/// ln 2 split so that k * kLn2Hi is exact for |k| < 2^21 (fdlibm's split).
inline constexpr double kLn2Hi = 6.93147180369123816490e-01;
inline constexpr double kLn2Lo = 1.90821492927058770002e-10;
inline constexpr double kInvLn2 = 1.44269504088896338700;
}  // namespace detail

}  // namespace ramiform::pm
