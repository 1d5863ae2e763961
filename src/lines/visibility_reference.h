// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The exhaustive reference of classify_visibility's kRays (internal; for tests).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/field/field.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform::detail {

/// The visibility flags kRays stands for, found without any bound: the same shortened segments
/// and the same samples (src/lines/visibility.cpp), every sample of every segment evaluated. One
/// flag per line point, lines in order. classify_visibility with Visibility::kRays gives these
/// flags exactly, up to rounding in the field's interval bounds.
std::vector<std::uint8_t> rays_visibility_exhaustive(
    const Field& field, const ParticleSystem& particles, const Camera& camera,
    std::span<const Polyline> lines, double occlusion_tolerance, const Context* ctx = nullptr);

}  // namespace ramiform::detail
