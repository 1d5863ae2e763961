// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Planar (2-D) and space (3-D) curves for the curve-based surfaces of Kochhar 2010, "Application
/// of implicit methods to the interactive modeling of trees" (M.Sc. thesis), §4.1–4.2 (surfaces of
/// revolution, sweeps, implicit skinning; see field/sweep.h and docs/skinning.md): a curve is a
/// kind and a list of points. All curves are parameterized over t in [0, 1].
///
// clang-format off
/// | kind | curve | parameterization |
/// |---|---|---|
/// | kPolyline | straight pieces through the points (closed: plus the piece back to the first) | t uniform per piece: piece j covers [j/m, (j+1)/m], m = number of pieces |
/// | kBezier | ONE Bezier curve of degree n-1 through the n control points (closed: the first point is appended, degree n), de Casteljau | the Bezier parameter |
/// | kBSpline | uniform B-spline of degree p = min(3, n-1); open: clamped (open-uniform knots, passes through the end points); closed: periodic over the n points | open: knots 0 (p+1 times), i/(n-p), 1 (p+1 times); closed: uniform knots, t = (u - p) / n |
// clang-format on
///
/// Curve files are read by io/curve_io.h.

#include <string>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform {

using Vec2 = Eigen::Vector2d;  ///< a point in a plane (model units)

enum class CurveKind {
  kPolyline,  ///< straight pieces through the points
  kBezier,    ///< one Bezier curve of degree n-1 through n control points (de Casteljau)
  kBSpline,   ///< uniform B-spline of degree min(3, n-1): clamped when open, periodic when closed
};

/// A planar curve. `closed`: the curve returns to its start; a closed planar curve bounds a
/// region (distance 0 inside it, even-odd rule). The first point is not repeated at the end.
struct Curve2 {
  CurveKind kind = CurveKind::kPolyline;  ///< how the points define the curve
  std::vector<Vec2> points;               ///< points / control points, model units
  bool closed = false;                    ///< returns to its start and bounds a region
};

/// A space curve (a path for sweeps and skinning); always open.
struct Curve3 {
  CurveKind kind = CurveKind::kPolyline;  ///< how the points define the curve
  std::vector<Vec3> points;               ///< points / control points, model units
};

/// Validates a curve: a known kind, >= 2 points (>= 3 when closed), every coordinate finite.
/// Throws InvalidArgument naming the problem (and the offending point's index).
void validate(const Curve2& curve);
void validate(const Curve3& curve);

/// The curve point at parameter t in [0, 1] (see the table above). Validates the curve and t;
/// throws InvalidArgument for an invalid curve or a t outside [0, 1] (or not finite).
[[nodiscard]] Vec3 curve_point(const Curve3& curve, double t);
[[nodiscard]] Vec2 curve_point(const Curve2& curve, double t);
/// dC/dt at t in [0, 1]. At the joints of polyline pieces and B-spline spans where the
/// derivative jumps, the piece/span that starts at t is used (the last one at t = 1).
[[nodiscard]] Vec3 curve_derivative(const Curve3& curve, double t);
[[nodiscard]] Vec2 curve_derivative(const Curve2& curve, double t);
/// d²C/dt² at t in [0, 1] (0 on polylines); same joint rule as curve_derivative.
[[nodiscard]] Vec3 curve_second_derivative(const Curve3& curve, double t);

/// Flattens a curve to a polyline whose chord error is at most `tolerance` (absolute, model
/// units, finite and > 0): every curve point C(t) lies within `tolerance` of the point at the
/// same parameter on the chord between the two neighbouring returned points. Each Bezier curve /
/// B-spline span is split uniformly in its parameter into m pieces, with m the smallest count for
/// which (h² / 8) max|C''| <= tolerance (h the piece's parameter length; max|C''| bounded by the
/// control points of the second derivative, convex hull property), so the bound is guaranteed.
/// Polylines are returned as is. Closed curves: the first point is not repeated at the end (the
/// closing piece from the last point back to the first is implied). Throws InvalidArgument for
/// an invalid curve, a bad tolerance, or more than 10^7 points.
[[nodiscard]] std::vector<Vec2> flatten(const Curve2& curve, double tolerance);
[[nodiscard]] std::vector<Vec3> flatten(const Curve3& curve, double tolerance);

/// flatten() with the curve parameter of each returned point (ascending from 0; the last is 1
/// for open curves; for closed curves the implied closing piece runs to t = 1).
struct FlattenedCurve3 {
  std::vector<Vec3> points;         ///< as flatten() returns them
  std::vector<double> parameters;   ///< one curve parameter t per point
};
struct FlattenedCurve2 {
  std::vector<Vec2> points;         ///< as flatten() returns them
  std::vector<double> parameters;   ///< one curve parameter t per point
};
[[nodiscard]] FlattenedCurve3 flatten_with_parameters(const Curve3& curve, double tolerance);
[[nodiscard]] FlattenedCurve2 flatten_with_parameters(const Curve2& curve, double tolerance);

}  // namespace ramiform
