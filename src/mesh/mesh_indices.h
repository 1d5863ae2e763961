// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the index check every mesh/ entry point makes before touching positions.

#include "ramiform/mesh/trimesh.h"

namespace ramiform::detail {

/// Throws InvalidArgument, naming `who`, the triangle and the vertex, when a triangle refers to
/// a vertex that `mesh.positions` does not hold.
void check_triangle_indices(const TriMesh& mesh, const char* who);

}  // namespace ramiform::detail
