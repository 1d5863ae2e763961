// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Variational implicit surfaces (Turk & O'Brien, "Shape transformation using variational
/// implicit functions", SIGGRAPH 1999; "Modelling with implicit surfaces that interpolate",
/// ACM TOG 21(4), 2002; Kochhar 2010, "Application of implicit methods to the interactive modeling
/// of trees" (M.Sc. thesis), §3.2, §4.1): the smoothest function through given values,
///
///   f_rbf(p) = sum_j w_j |p - c_j|^3 + c0 + c·p,
///
/// with the cubic radial basis |r|^3 that Turk & O'Brien use in 3D. The weights solve
/// the (n+4)×(n+4) symmetric system [A P; P^T 0] [w; c0, c] = [h; 0], A_ij = |c_i - c_j|^3,
/// P_i = (1, c_i), so that f_rbf(c_i) = h_i and the w are orthogonal to linear polynomials.
///
/// f_rbf grows without bound away from the constraints and may be > iso far away, so the field
/// is clipped to the constraints' bounding box padded by `margin` × its diagonal:
///
///   f(p) = min(f_rbf(p), iso + kappa s(p)),
///
/// where s is the signed distance to the clip box (> 0 inside, < 0 outside) and kappa the
/// smallest slope that keeps every constraint value (f(c_i) = h_i), times 2. Nothing outside the
/// box is inside, and inside the box the surface f == iso is the one of f_rbf (the clip only
/// lowers values that are already > iso).

#include <span>
#include <vector>

#include "ramiform/field/field.h"

namespace ramiform {

/// One interpolation constraint f(position) = value; value > iso marks an inside point.
struct RbfConstraint {
  Vec3 position;     ///< model units; finite
  double value = 0;  ///< field value there; finite
};

/// Options of the variational field.
struct RbfOptions {
  double iso = 0.0;      ///< iso value (finite)
  double margin = 0.25;  ///< clip box padding, fraction of the constraints' box diagonal (> 0)
};

/// Solves for the interpolating field. Needs >= 4 constraints at distinct, non-coplanar
/// positions; throws InvalidArgument for fewer, for non-finite data, for two positions closer
/// than tol::kCoincident × the box diagonal (naming both indices), for coplanar positions and
/// when the system is numerically singular. The solve is dense, O(n^3) (n up to a few thousand);
/// evaluation is O(n) per point.
[[nodiscard]] FieldPtr make_rbf_field(std::span<const RbfConstraint> constraints,
                                      const RbfOptions& options = {});

/// Turk & O'Brien's normal constraints: for each point a constraint of value `iso` at the point
/// and one of value iso + 1 at point - offset · n/|n| (inside). `normals` are outward, one per
/// point, any non-zero length; `offset` > 0 (model units). Throws InvalidArgument for a size
/// mismatch, non-finite data, a zero normal or a bad offset.
[[nodiscard]] std::vector<RbfConstraint> rbf_constraints_from_normals(std::span<const Vec3> points,
                                                                      std::span<const Vec3> normals,
                                                                      double offset,
                                                                      double iso = 0.0);

}  // namespace ramiform
