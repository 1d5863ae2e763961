// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: placing polygonizer vertices on the surface along crossing edges.

#include <cstdint>
#include <vector>

#include "ramiform/core/types.h"
#include "ramiform/field/field.h"

namespace ramiform::detail {

/// For every edge e from a[e] (field value fa[e]) to b[e] (fb[e]), where exactly one end is
/// inside (f > iso), returns the point where f = iso, found by `steps` rounds of Illinois
/// regula falsi with bisection safeguard; every round evaluates all unconverged edges in one
/// batch. Steps = 0 gives linear interpolation. Adds the evaluations made to `evaluations`.
std::vector<Vec3> find_edge_roots(const Field& field, const std::vector<Vec3>& a,
                                  const std::vector<Vec3>& b, std::vector<double> fa,
                                  std::vector<double> fb, int steps, std::uint64_t& evaluations);

}  // namespace ramiform::detail
