// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: placing polygonizer vertices on the surface along crossing edges.

#include <cstdint>
#include <vector>

#include "ramiform/core/tolerances.h"
#include "ramiform/core/types.h"
#include "ramiform/field/field.h"

namespace ramiform::detail {

/// When the root finding of an edge stops (find_edge_roots_along).
struct RootStop {
  double width = tol::kRootFinding;  ///< the bracket in t (0..1 along the edge) at most this
  double value = tol::kRootValue;    ///< or |f - iso| at the last point at most this times |iso|
};

/// For every edge e, the segment a[e] + t d[e] with t in [0, 1] (field values fa[e] at t = 0,
/// fb[e] at t = 1), where exactly one end is inside (f > iso), returns the point where f = iso,
/// found by `steps` rounds of bracketed root finding (a log-secant first step, then quadratic
/// interpolation of 1 - (f/iso)^(-2/3) where f > 0 at both ends, Anderson-Björck regula falsi
/// when the steps creep from one end, then bisection: RootBracket of core/roots.h, driven for
/// all edges at once; see the .cpp); every round
/// evaluates all unconverged edges in one batch and an edge stops once its bracket in t is at
/// most tol::kRootFinding or |f - iso| at the last point is at most tol::kRootValue |iso|.
/// Steps = 0 gives linear interpolation. A NaN value counts as on the surface. `stop` may
/// loosen both stopping rules (the tetrahedral polygonizer's do, see tetrahedral_mesh.cpp). Adds
/// the evaluations made to `evaluations`. `d`, `fa` and `fb` have the size of `a`. Runs on `ctx`'s
/// threads and checks it for cancellation (nullptr: all cores, never cancelled).
std::vector<Vec3> find_edge_roots_along(const Field& field, const std::vector<Vec3>& a,
                                        const std::vector<Vec3>& d, std::vector<double> fa,
                                        std::vector<double> fb, int steps,
                                        std::uint64_t& evaluations, const Context* ctx = nullptr,
                                        const RootStop& stop = {});

/// find_edge_roots_along for the edges from a[e] to b[e] (d = b - a).
std::vector<Vec3> find_edge_roots(const Field& field, const std::vector<Vec3>& a,
                                  const std::vector<Vec3>& b, std::vector<double> fa,
                                  std::vector<double> fb, int steps, std::uint64_t& evaluations,
                                  const Context* ctx = nullptr, const RootStop& stop = {});

}  // namespace ramiform::detail
