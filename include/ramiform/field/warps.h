// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Barr's global deformations: taper, twist and bend (A. Barr, "Global and local deformations of
/// solid primitives", SIGGRAPH 1984; Kochhar 2010, "Application of implicit methods to the
/// interactive modeling of trees" (M.Sc. thesis), §4.1). A warp field shows its child's shape
/// deformed by the forward map W:
///
///   f(p) = f_child(W^-1(p)),   grad f(p) = J_{W^-1}(p)^T grad f_child(W^-1(p)).
///
/// The iso value is the child's. bound(box) passes a conservative box containing W^-1(box) to
/// the child, bounds() is a conservative box containing W(child->bounds()), and restrict(box)
/// restricts the child to the same box as bound(). Warps are not isometries: the field's values
/// are the child's, but its gradient length changes with the local stretch. See
/// docs/modeling_fields.md for the formulas.

#include "ramiform/field/field.h"

namespace ramiform {

/// Taper along `axis`: W scales the two coordinates other than `axis` by r(t), where t is the
/// coordinate along `axis` and r is linear from `scale_start` at t = start to `scale_end` at
/// t = end and constant beyond (Barr's taper with a piecewise-linear profile).
struct TaperOptions {
  int axis = 2;            ///< 0 = x, 1 = y, 2 = z
  double start = 0;        ///< t where the profile starts (model units); start < end
  double end = 1;          ///< t where the profile ends (model units)
  double scale_start = 1;  ///< r(start); finite and > 0
  double scale_end = 0.5;  ///< r(end); finite and > 0
};

/// Twist about `axis`: W rotates the plane normal to `axis` by the angle rate·(t - origin)
/// (right-handed about the axis), t the coordinate along `axis`.
struct TwistOptions {
  int axis = 2;       ///< 0 = x, 1 = y, 2 = z
  double rate = 1.0;  ///< radians per unit length along the axis (any finite value; 0 = identity)
  double origin = 0;  ///< t where the angle is 0
};

/// Barr's bend of the y axis in the y–z plane. With y^ = clamp(y, min, max),
/// theta = rate (y^ - center), C = cos theta, S = sin theta:
///   X = x,
///   Y = -S (z - 1/rate) + center + C (y - y^),
///   Z =  C (z - 1/rate) + 1/rate + S (y - y^),
/// i.e. the slab min <= y <= max is bent around the line y = center, z = 1/rate (parallel to x)
/// and the parts beyond continue straight along the tangent. The inverse (Barr's closed form) is
/// exact for points whose preimage lies on the axis side of the centre of curvature
/// (1 - rate z > 0, i.e. z < 1/rate for rate > 0) when the total bend angle
/// |rate| (max - min) is below pi; elsewhere the map is not one-to-one and the inverse returns
/// one preimage (always finite).
struct BendOptions {
  double rate = 0.5;  ///< bending rate k = 1 / radius of curvature (1/model units); 0 = identity
  double center = 0;  ///< y0: y where the bend angle is 0; min <= center <= max
  double min = -1;    ///< lower end of the bent region along y
  double max = 1;     ///< upper end of the bent region along y
};

/// A tapered child. Throws InvalidArgument for a null child, an axis outside 0..2, non-finite
/// values, start >= end or a scale <= 0.
[[nodiscard]] FieldPtr make_taper(FieldPtr child, const TaperOptions& options);
/// A twisted child. Throws InvalidArgument for a null child, an axis outside 0..2 or non-finite
/// values.
[[nodiscard]] FieldPtr make_twist(FieldPtr child, const TwistOptions& options);
/// A bent child. Throws InvalidArgument for a null child, non-finite values or
/// not min <= center <= max.
[[nodiscard]] FieldPtr make_bend(FieldPtr child, const BendOptions& options);

/// The forward map W of the taper (options are not validated here).
[[nodiscard]] Vec3 taper_forward(const Vec3& p, const TaperOptions& options);
/// The inverse map W^-1 of the taper.
[[nodiscard]] Vec3 taper_inverse(const Vec3& p, const TaperOptions& options);
/// The forward map W of the twist.
[[nodiscard]] Vec3 twist_forward(const Vec3& p, const TwistOptions& options);
/// The inverse map W^-1 of the twist.
[[nodiscard]] Vec3 twist_inverse(const Vec3& p, const TwistOptions& options);
/// Barr's forward bend (see BendOptions).
[[nodiscard]] Vec3 bend_forward(const Vec3& p, const BendOptions& options);
/// Barr's inverse bend: exact where documented in BendOptions, finite everywhere.
[[nodiscard]] Vec3 bend_inverse(const Vec3& p, const BendOptions& options);

}  // namespace ramiform
