// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Distance-surface primitives of the implicit modeler (Kochhar 2010, "Application of implicit
/// methods to the interactive modeling of trees" (M.Sc. thesis), §3.2, §4.1): torus, rounded box,
/// rounded cylinder, rounded cone and half-space. Each is
///
///   f(p) = weight * k(d(p) / R),   R = radius / kernel.x_at(iso),
///
/// where d is the Euclidean distance to a skeletal element (a circle, or a solid: distance 0
/// inside it) and k a distance kernel (kernels.h, Wyvill by default, iso 0.5). With weight 1 the
/// surface f == iso lies exactly `radius` away from the element (for the rounded solids the
/// element is the solid shrunk by `rounding`, and `radius` is `rounding`; for the half-space it
/// is `falloff`). A weight other than 1 keeps R and so moves the surface (as blend weights do).
///
/// Infinite kernels (Blinn, inverse power) are cut off and faded out exactly as in the skeleton
/// field (tolerances.h: kKernelCutoff, kFadeStart): f is multiplied by a C1 smoothstep of
/// (x / x_c)^2 between x = 0.8 x_c and x_c, where x_c = kernel.support(iso / weight), so every
/// primitive but the half-space has a finite support box. The Cauchy kernel is rejected (it is
/// a convolution kernel). Gradients are analytic. See docs/modeling_fields.md.

#include "ramiform/field/field.h"
#include "ramiform/field/kernels.h"

namespace ramiform {

/// Options shared by the distance-surface primitives.
struct DistancePrimitiveOptions {
  /// The distance kernel: Wyvill, Blinn, Metaball or inverse power (Cauchy throws).
  Kernel kernel = Kernel{KernelKind::kWyvill, 0.0};
  double iso = 0.0;     ///< iso value (> 0, reachable by the kernel); 0 = kernel.default_iso()
  double weight = 1.0;  ///< multiplies the kernel; finite and > 0
};

/// Torus: the skeletal element is the circle of radius `circle_radius` around `center` in the
/// plane normal to `normal` (any non-zero length); the surface lies `radius` away from it.
/// `circle_radius` > 0, `radius` > 0 (radius >= circle_radius gives a spindle torus). Throws
/// InvalidArgument naming the bad parameter (non-finite, non-positive, zero normal, bad options).
[[nodiscard]] FieldPtr make_circle_field(const Vec3& center, const Vec3& normal,
                                         double circle_radius, double radius,
                                         const DistancePrimitiveOptions& options = {});

/// Rounded box: the skeletal element is the solid box center ± (half_size - rounding) (distance
/// 0 inside it); the surface lies `rounding` away, so it touches the faces center ± half_size
/// and its edges and corners are rounded with radius `rounding`. Requires every half_size > 0
/// and 0 < rounding <= min(half_size) (InvalidArgument otherwise).
[[nodiscard]] FieldPtr make_box_field(const Vec3& center, const Vec3& half_size, double rounding,
                                      const DistancePrimitiveOptions& options = {});

/// Rounded solid cylinder with axis a -> b and radius `radius`, its rims rounded with radius
/// `rounding`: the skeletal element is the solid cylinder shrunk by `rounding` on all sides
/// (axis a + rounding u -> b - rounding u, radius radius - rounding, u = (b - a) / |b - a|).
/// Requires a != b and 0 < rounding <= min(radius, |b - a| / 2) (InvalidArgument otherwise).
[[nodiscard]] FieldPtr make_cylinder_field(const Vec3& a, const Vec3& b, double radius,
                                           double rounding,
                                           const DistancePrimitiveOptions& options = {});

/// Rounded solid truncated cone with radius `ra` at a and `rb` at b (one of them may be 0: a
/// cone), rims rounded with radius `rounding`. The skeletal element is the inward offset of the
/// solid cone by `rounding` (the set of centres of balls of radius `rounding` inside it, itself a
/// truncated cone), so the surface coincides exactly with the requested cone's flat caps and
/// side away from the rims, and rims and apex are rounded with radius `rounding`. Requires
/// a != b, ra, rb >= 0 and not both 0, and 0 < rounding <= the inradius of the cone's meridian
/// section (the largest ball that fits; it is <= |b - a| / 2 and <= max(ra, rb)).
[[nodiscard]] FieldPtr make_cone_field(const Vec3& a, double ra, const Vec3& b, double rb,
                                       double rounding,
                                       const DistancePrimitiveOptions& options = {});

/// Half-space: inside is {p : normal·(p - point) < 0} (normal any non-zero length, pointing
/// out), the surface is the plane itself. The skeletal element is the half-space shifted inward
/// by `falloff` (> 0, distance 0 inside it) and R = falloff / x_iso, so the field falls from the
/// plane to 0 over the distance (support - x_iso) R outside. bounds() is unbounded: ±infinity on
/// every axis, except the one side of an axis that `normal` is parallel to; describe() says so.
[[nodiscard]] FieldPtr make_plane_field(const Vec3& point, const Vec3& normal, double falloff,
                                        const DistancePrimitiveOptions& options = {});

}  // namespace ramiform
