// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: step 6 of the tetrahedral polygonizer, the cleanup of its mesh. Zhu, Guo & Jin
// 2013, "Efficient polygonization of tree trunks modeled by convolution surfaces", §6, name its
// needle triangles their method's weakness; the cleanup here collapses them.

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::detail::tets {

/// Needle cleanup (mesh/cleanup.h; no change may move a skeleton node across the surface)
/// when `options.cleanup`, then, when `options.drop_strays`, removal of the small components
/// (each under 1 % of the triangles) that enclose no skeleton node. Fills the stats'
/// `collapsed_edges`, angles before cleanup and `stray_components`.
void clean_up(TriMesh& mesh, const Skeleton& skeleton, const TetrahedralOptions& options,
              Context* ctx, TetrahedralStats& stats);

}  // namespace ramiform::detail::tets
