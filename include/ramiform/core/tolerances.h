// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Every tolerance the algorithms use, in one place. Geometric tolerances are relative to a
/// length scale (usually the scene's bounding-box diagonal or a local radius); none is absolute.

namespace ramiform::tol {

/// Relative length below which two points are treated as coincident (times the scale).
inline constexpr double kCoincident = 1e-12;

/// Infinite-support kernels (Blinn, inverse power, Cauchy) are cut off at the distance where the
/// contribution of one primitive falls below this fraction of the iso value. Between 80 % and
/// 100 % of that distance the contribution is faded out by a C1 smoothstep, so the field stays
/// continuously differentiable. The change it makes is the contribution at 80 % of the cutoff
/// at most: about 2.5x this fraction of iso for Cauchy, 1.1x for inverse power, 3-3.7x for Blinn
/// (measured); under 4x for every kernel here.
inline constexpr double kKernelCutoff = 1e-4;

/// Fraction of the cutoff radius at which the fade-out of an infinite-support kernel begins.
inline constexpr double kFadeStart = 0.8;

/// Relative step for central-difference gradients (times the local length scale).
inline constexpr double kFiniteDifference = 1e-6;

/// Relative tolerance (times the edge length) of the root finding that places polygonizer
/// vertices on the surface.
inline constexpr double kRootFinding = 1e-7;

}  // namespace ramiform::tol
