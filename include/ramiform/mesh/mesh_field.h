// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// A closed triangle mesh as an implicit shape: f(p) is the mesh's generalized winding number
/// (mesh/winding.h; Jacobson et al. 2013, fast evaluation by Barill et al. 2018), 1 inside and 0
/// outside, with iso 0.5. It lets meshes take part in CSG, serve as obstacles that grown trees
/// wrap around (Kochhar 2010, "Application of implicit methods to the interactive modeling of
/// trees" (M.Sc. thesis), §7.2 "also around triangle meshes") and be sampled like any shape.
///
/// The field is a step function: its gradient is a central difference with a step of
/// 1e-3 of the mesh's bounding-box diagonal (non-zero only within that distance of the surface).
/// bound(box): a box the surface cannot reach (the distance from its centre to the nearest
/// triangle centroid, less the largest centroid-to-corner distance, exceeds its half diagonal;
/// a kd-tree over the centroids answers it) has one winding number w throughout, so the bound
/// is w(centre) +- 0.05; boxes outside the mesh's bounding box get [-0.05, 0.05]; others
/// [-0.05, 1.05]. The fast winding number's error stays below 0.01 on closed meshes.

#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"

namespace ramiform {

/// The winding-number field of `mesh`. Throws InvalidArgument when the mesh is not closed
/// (watertight, oriented, manifold — a winding number is only a clean inside test then) or has
/// no triangles.
[[nodiscard]] FieldPtr make_mesh_field(const TriMesh& mesh);

}  // namespace ramiform
