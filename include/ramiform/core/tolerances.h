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

/// Relative margin by which primitive support boxes are grown (times the support radius), so
/// that every point outside a box lies strictly beyond the cut-off in floating point and a
/// pruned primitive would have contributed exactly 0.
inline constexpr double kSupportMargin = 1e-9;

/// Relative step for central-difference gradients (times the local length scale).
inline constexpr double kFiniteDifference = 1e-6;

/// Relative tolerance (times the edge length) of the root finding that places polygonizer
/// vertices on the surface.
inline constexpr double kRootFinding = 1e-7;
/// The root finding also stops once |f - iso| is below this fraction of iso: the vertex is then
/// within about 1e-8 of a branch radius of the surface, and steep fields (the convolution field
/// near thin branches) no longer spend every round shrinking the bracket.
inline constexpr double kRootValue = 1e-8;

// Cylinder-model import (io/qsm_io.h), as fractions of the local cylinder radius r. Chosen on
// archi_Tree_1_TreeQSM.txt, where the start of a branch's next cylinder lies a median 0.27 r
// (90 %: 1.2 r) from its parent's end, side branches start at 1.0 r from the parent's axis, and
// 1 % of cylinders are shorter than 0.5 r.

/// A child cylinder whose start lies within this fraction of min(r_parent, r_child) of its
/// parent's axis starts at the parent's axis node (no connector edge).
inline constexpr double kQsmJoin = 0.5;

/// Points closer than this fraction of r along one cylinder axis share one node (split nodes,
/// tiny cylinders, duplicate and overlapping cylinders).
inline constexpr double kQsmMerge = 0.25;

}  // namespace ramiform::tol
