// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Curve-based distance surfaces of Kochhar 2010, "Application of implicit methods to the
/// interactive modeling of trees" (M.Sc. thesis), §4.1–4.2: implicit surfaces of revolution,
/// sweep surfaces and implicit skinning. Each is a distance surface (thesis §3.2) whose skeletal
/// element is built from curves (field/curves.h):
///
///   f(p) = weight · k(d(p) / R),   R = radius / kernel.x_at(iso),
///
/// so that with weight 1 the surface lies `radius` from the skeletal element. Closed cross-section
/// and profile curves are filled regions (d = 0 inside them), open ones are curves. The curves
/// are flattened (`flatten`, chord error `tolerance`) and d is measured to the flattened 2-D
/// curves; the path of sweeps and skins is evaluated exactly (Newton projection).
/// Infinite-support kernels are cut off and faded as in skeleton_field.h (tol::kKernelCutoff).
/// See docs/skinning.md for the formulas, the frames and the interpolation schemes.

#include <vector>

#include "ramiform/field/curves.h"
#include "ramiform/field/field.h"
#include "ramiform/field/kernels.h"

namespace ramiform {

/// Options shared by the curve-based surfaces. Validated by every make_* (InvalidArgument).
struct CurveSurfaceOptions {
  Kernel kernel = Kernel{KernelKind::kWyvill, 0.0};  ///< distance kernel k (kernels.h)
  double iso = 0.0;        ///< iso value, > 0; 0 = the kernel's default_iso()
  double weight = 1.0;     ///< factor on k, finite and > 0 (weight != 1 moves the surface)
  double radius = 0.1;     ///< surface offset from the skeletal element, model units, > 0
  /// Flattening chord error of every curve, model units, >= 0; 0 = 1e-3 × each curve's own
  /// extent (the diagonal of its control points' bounding box).
  double tolerance = 0.0;
};

/// Surface of revolution (thesis §4.1, Figure 4.3): `profile` lies in the (r, z) half-plane
/// (r = the x coordinate of its points, which must be >= 0; z = the y coordinate) and is revolved
/// about the world z axis: d(p) = the 2-D distance from (sqrt(px² + py²), pz) to the profile (to
/// the region it bounds when closed). Throws InvalidArgument for an invalid profile (validate),
/// a point with x < 0, or bad options.
[[nodiscard]] FieldPtr make_revolution_field(const Curve2& profile,
                                             const CurveSurfaceOptions& options = {});

/// How the distances of cross-sections at distinct s are interpolated along the path.
enum class SkinInterpolation {
  kLinear,     ///< thesis §4.2.3: d = (1 - u) d_i + u d_i+1, u = (s - s_i) / (s_i+1 - s_i)
  kQuadratic,  ///< Lagrange parabola through three neighbouring s values (the tighter triple)
  kCubic,      ///< cubic Hermite with Bessel (three-point parabolic) slopes: non-uniform Catmull–Rom
};

/// A planar cross-section attached to the path. Its 2-D coordinates (x, y) map to
/// origin + x N + y B of the frame at s (path_frame).
struct SkinSection {
  Curve2 curve;  ///< the cross-section (closed = filled region)
  double s = 0;  ///< normalized arc length on the path, in [0, 1]
};

/// Options of make_skin_field.
struct SkinOptions {
  CurveSurfaceOptions surface;                                  ///< kernel, radius, ...
  SkinInterpolation interpolation = SkinInterpolation::kLinear;  ///< along the path
};

/// Implicit skinning (thesis §4.2). A point p is projected on the path (closest point: coarse on
/// the flattened path, then Newton–Raphson on (C(t) − p)·C'(t) = 0, eq. 4.1, with a fallback to
/// the coarse result); with O = C(t), s the normalized arc length at t and (T, N, B) the
/// rotation-minimizing frame there, p − O = a T + x N + y B. The in-plane distance d2 is
/// interpolated at s from the section distances at (x, y) (eq. 4.2): sections sharing one s
/// combine by min (their union, so Figure 4.10's four legs at s = 0 work); before the first /
/// after the last section s the nearest section's distance is used; a negative interpolated
/// value (quadratic/cubic overshoot) counts as 0. Then d = sqrt(d2² + a²): a is 0 where the
/// projection is interior and is the axial distance past the end where it is clamped at s = 0 or
/// 1, so ends are capped. Throws InvalidArgument for an invalid path or section, a path of zero
/// length, no sections, an s outside [0, 1], or bad options.
[[nodiscard]] FieldPtr make_skin_field(const Curve3& path, std::vector<SkinSection> sections,
                                       const SkinOptions& options = {});

/// Sweep surface (thesis §4.1): one section along the whole path (= skinning with the section
/// at s = 0 and s = 1).
[[nodiscard]] FieldPtr make_sweep_field(const Curve3& path, const Curve2& section,
                                        const CurveSurfaceOptions& options = {});

/// The frame at normalized arc length s: origin on the path, T the unit tangent, N and B spanning
/// the section plane (T, N, B orthonormal, B = T × N); section coordinates (x, y) map to
/// origin + x N + y B. Rotation-minimizing frames by double reflection (Wang, Jüttler, Zheng &
/// Liu 2008) along the flattened path, starting from N0 = normalize(e − (e·T0) T0) with e the
/// world x axis (the y axis when |T0·x| > 0.9). These are the frames the fields use when built
/// with the same flattening tolerance (0 = the default 1e-3 × the path's extent).
/// Throws InvalidArgument for an invalid or zero-length path or s outside [0, 1].
struct PathFrame {
  Vec3 origin;    ///< point of the path at s
  Vec3 tangent;   ///< unit tangent T
  Vec3 normal;    ///< unit normal N (section x axis)
  Vec3 binormal;  ///< unit binormal B = T × N (section y axis)
};
[[nodiscard]] PathFrame path_frame(const Curve3& path, double s);
[[nodiscard]] PathFrame path_frame(const Curve3& path, double s, double tolerance);

/// The projection of a point on a path as the skin and sweep fields compute it.
struct PathProjection {
  double t = 0;               ///< curve parameter of the projected point, in [0, 1]
  double s = 0;               ///< normalized arc length there, in [0, 1]
  Vec3 point;                 ///< C(t)
  bool newton_used = false;   ///< Newton's result was accepted (false: the coarse polyline one)
};
/// Projects `p` on the path: the closest point of the flattened path (tolerance as in
/// path_frame), refined by Newton–Raphson on (C(t) − p)·C'(t) = 0 (thesis eq. 4.1); Newton's
/// result is kept only when it converged inside [0, 1] without increasing the distance.
[[nodiscard]] PathProjection project_on_path(const Curve3& path, const Vec3& p, double tolerance = 0);

}  // namespace ramiform
