// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the last part of step 4 of the tetrahedral polygonizer, from the extracted polygons
// to a triangle mesh.

#include "polygonize/tetrahedral_lattice.h"
#include "polygonize/tetrahedral_types.h"
#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/polygonize/tetrahedral.h"

namespace ramiform::detail::tets {

/// The mesh of an extraction (consumed): one vertex per distinct crossing edge, placed on the
/// surface of `field` by `options.root_steps` rounds of root finding along the edge
/// (edge_roots.h), numbered in the order the triangles first use them; one triangle per
/// triangle polygon, two per quad, split along the shorter diagonal of its placed vertices.
/// Fills the stats' `crossing_edges` and `root_evaluations`.
[[nodiscard]] TriMesh assemble_mesh(const Field& field, Extraction&& extraction,
                                    const Lattice& lattice, const TetrahedralOptions& options,
                                    const Context* ctx, TetrahedralStats& stats);

/// Numbers the vertices in the order the triangles first use them, and drops the unused ones.
void renumber_by_first_use(TriMesh& mesh);

}  // namespace ramiform::detail::tets
