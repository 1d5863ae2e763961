// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Skeleton primitives: a point, a segment and a whole line skeleton (one primitive per edge,
/// one point primitive per isolated node), as distance surfaces or convolution surfaces. The
/// primitives of one field are summed (blended); each has a non-negative weight.
///
/// Distance surface: f(p) = sum_i w_i k(d_i(p) / R_i(p)), where d_i is the distance to the
/// segment, R_i = r_i / x_iso is the radius of influence interpolated linearly along the segment
/// at the closest point, and k is a distance kernel (Wyvill by default, see kernels.h).
///
/// Convolution surface (Cauchy kernel only): f(p) = sum_i w_i lambda_i F_i(p), where F_i is the
/// closed-form integral of 1/(1 + s_i^2 r^2)^2 along segment i (Zhu, Guo & Jin 2013, "Efficient
/// polygonization of tree trunks modeled by convolution surfaces", eq. 1, 5), s_i = c / r_i with c
/// the kernel's width parameter and r_i the mean radius of the segment's two nodes, and lambda_i =
/// 2 c iso (1 + c^2)^(3/2) / (pi r_i) makes an infinitely long segment's surface a cylinder of
/// radius exactly r_i. Point primitives use the kernel itself (no integral).
///
/// Infinite kernels are cut off (tolerances.h, kKernelCutoff), so every primitive has a finite
/// support box; evaluation and restrict() prune through a BVH over those boxes.

#include <span>

#include "ramiform/field/field.h"
#include "ramiform/field/kernels.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

enum class SurfaceKind {
  kDistance,     ///< f = sum w k(d / R)
  kConvolution,  ///< f = sum w lambda integral of the Cauchy kernel along the skeleton
};

/// Options of every skeleton primitive field.
struct SkeletonFieldOptions {
  SurfaceKind surface = SurfaceKind::kConvolution;  ///< distance or convolution surface
  /// The kernel. Convolution surfaces need KernelKind::kCauchy (the default). Distance surfaces
  /// take any kernel (set e.g. KernelKind::kWyvill); Cauchy there means the point-convolution
  /// kernel 1/(1 + s^2 d^2)^2 with s = c / r.
  Kernel kernel = Kernel{KernelKind::kCauchy, 0.0};
  double iso = 0.0;  ///< iso value; 0 means the kernel's default_iso()
  /// Prune primitives through the BVH over their supports (true), or evaluate every primitive
  /// at every point (false: same values, for benchmarks and checks only).
  bool prune = true;

  /// Validates and fills defaults; throws InvalidArgument naming the bad option.
  [[nodiscard]] SkeletonFieldOptions resolved() const;
};

/// A line-skeleton field: one primitive per edge (radius interpolated between the two nodes),
/// plus a point primitive per node without edges. `edge_weights` is empty (all 1) or one
/// non-negative finite weight per edge. Validates the skeleton (InputError) and options
/// (InvalidArgument).
[[nodiscard]] FieldPtr make_skeleton_field(const Skeleton& skeleton,
                                           const SkeletonFieldOptions& options = {},
                                           std::span<const double> edge_weights = {});

/// A single point primitive of surface radius `radius` (> 0).
[[nodiscard]] FieldPtr make_point_field(const Vec3& center, double radius,
                                        const SkeletonFieldOptions& options = {});

/// A single segment primitive from a (radius ra) to b (radius rb).
[[nodiscard]] FieldPtr make_segment_field(const Vec3& a, double ra, const Vec3& b, double rb,
                                          const SkeletonFieldOptions& options = {});

}  // namespace ramiform
