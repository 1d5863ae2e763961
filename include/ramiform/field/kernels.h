// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Radial kernels k(x) of a normalized distance x = d / R (distance surfaces), and the Cauchy
/// convolution kernel with its closed-form integral along a segment.
///
// clang-format off
/// | kernel | k(x) | iso | x at iso | support | source |
/// |---|---|---|---|---|---|
/// | Wyvill | 1 - 22/9 x^2 + 17/9 x^4 - 4/9 x^6 | 0.5 | 1/2 | x <= 1 | Wyvill, McPheeters, Wyvill 1986; Kochhar 2010 §3.2 (a = -0.44444, b = 1.888889, c = -2.44444) |
/// | Blinn | exp(-B x^2) | 0.5 | sqrt(ln 2 / B) | infinite (cut off) | Blinn 1982; Kochhar 2010 §3.2, g = b exp(-a r^2) |
/// | Metaball | 1 - 3x^2 (x <= 1/3), 3/2 (1 - x)^2 (x <= 1) | 0.5 | 1 - 1/sqrt(3) | x <= 1 | Nishimura et al. 1985 (Murakami's "metaballs"), Kochhar 2010 §3.2 |
/// | Inverse power | x^-(alpha - 1) | 1 | 1 | infinite (cut off) | Gruber & Wallner 2014 eq. 1 (point charge q / r^(alpha-1)) |
/// | Cauchy | 1 / (1 + s^2 r^2)^2 | user | - | infinite (cut off) | McCormack & Sherstyuk 1998; Zhu, Guo & Jin 2013 eq. 5 |
// clang-format on
///
/// Sources: Kochhar 2010, "Application of implicit methods to the interactive modeling of trees"
/// (M.Sc. thesis); Gruber & Wallner 2014, "Polygonization of Line Skeletons by Using
/// Equipotential Surfaces – A Practical Description"; Zhu, Guo & Jin 2013, "Efficient
/// polygonization of tree trunks modeled by convolution surfaces".
///
/// For distance surfaces the radius of influence R is chosen from a requested surface radius r
/// as R = r / x_iso, so that a lone point primitive has exactly radius r.

#include <string>
#include <string_view>

#include "ramiform/core/types.h"

namespace ramiform {

enum class KernelKind {
  kWyvill,        ///< compact polynomial, iso 0.5 at x = 1/2
  kBlinn,         ///< Gaussian exp(-B x^2); parameter B (blobbiness), default 4
  kMetaball,      ///< Murakami/Nishimura piecewise quadratic
  kInversePower,  ///< x^-(alpha-1); parameter alpha >= 2, default 3
  kCauchy,        ///< Cauchy convolution kernel; parameter s*r (dimensionless width), default 1
};

/// A kernel and its one shape parameter (ignored by Wyvill and Metaball).
struct Kernel {
  KernelKind kind = KernelKind::kWyvill;  ///< which kernel
  double parameter = 0.0;  ///< B (Blinn), alpha (inverse power), s*r (Cauchy); 0 = default

  /// The parameter with defaults applied (B = 4, alpha = 3, s*r = 1); 0 for kernels without one.
  [[nodiscard]] double shape() const;
  /// The natural iso value of the kernel (Cauchy: 1).
  [[nodiscard]] double default_iso() const;
  /// Normalized distance at which k(x) == iso for a lone point primitive of unit weight.
  /// Throws InvalidArgument when no x >= 0 reaches iso (iso <= 0, or iso >= k(0) = 1 for the
  /// bounded kernels).
  [[nodiscard]] double x_at(double iso) const;
  /// Normalized support: k(x) == 0 for x >= support (compact kernels); for infinite kernels the
  /// x where k(x) falls to `tol::kKernelCutoff * iso`.
  [[nodiscard]] double support(double iso) const;
  /// k(x) for x >= 0 (distance kernels; for Cauchy 1/(1+x^2)^2 with x = s r).
  [[nodiscard]] double value(double x) const;
  /// dk/dx.
  [[nodiscard]] double derivative(double x) const;
  /// Validates the parameter; throws InvalidArgument naming it.
  void validate() const;
};

/// Parses "wyvill", "blinn", "metaball", "inverse-power" (or "power"), "cauchy", optionally with
/// ":PARAM" ("blinn:3", "power:4"). Throws InvalidArgument listing the valid names.
[[nodiscard]] Kernel parse_kernel(std::string_view text);
/// The canonical name of a kernel kind ("wyvill", ...).
[[nodiscard]] std::string kernel_name(KernelKind kind);

/// Closed-form integral of the Cauchy kernel 1/(1 + s^2 |p - q|^2)^2 over q on the segment
/// [a, b] (arc-length measure, not scaled by a weight): the segment field of McCormack &
/// Sherstyuk; Zhu, Guo & Jin 2013 eq. 5. With u the coordinate along the segment relative to the
/// foot of p, h the distance of p from the segment's line and P = 1 + s^2 h^2:
///   F = [u / (2P (P + s^2 u^2)) + atan(s u / sqrt(P)) / (2 s P^(3/2))] from u = -x to l - x.
/// The atan difference is taken as one atan2 so that it does not cancel far from the segment.
/// `gradient` may be null.
[[nodiscard]] double cauchy_segment_integral(const Vec3& p, const Vec3& a, const Vec3& b, double s,
                                            Vec3* gradient = nullptr);

}  // namespace ramiform
