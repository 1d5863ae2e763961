// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: steps 3 to 5 of the tetrahedral polygonizer (tetrahedral.h; Zhu, Guo & Jin 2013,
// "Efficient polygonization of tree trunks modeled by convolution surfaces", §3.2.2, §4.2 and
// §5): every region tetrahedron subdivided 1:8 to `levels` (Figure 4), marching tetrahedra on
// the leaves, and the region grown across every boundary face the surface reaches until none
// is left.

#include <vector>

#include "polygonize/tetrahedral_lattice.h"
#include "polygonize/tetrahedral_types.h"
#include "ramiform/core/context.h"
#include "ramiform/field/field.h"
#include "ramiform/polygonize/tetrahedral.h"

namespace ramiform::detail::tets {

/// Extracts the surface of `field` in the region `keep` (per tetrahedron of `tz`, 1 = in the
/// region; grown in place) into polygons over crossing edges keyed by the global ids of
/// `lattice`, which is filled round by round. A region-boundary face with an inside lattice
/// point gets the tetrahedron behind it added and extracted in the next round, until no such
/// face is left or `options.max_growth_rounds` is reached; the surface reaching the far box's
/// hull, or the limit, sets `stats.holes_left`. Fills the stats' growth, leaf, skip and
/// evaluation counts. Every region tetrahedron is subdivided to the same level, so leaves of
/// neighbours meet face to face; from level 4 on, one whose field bound excludes the iso value
/// is skipped whole. Deterministic for any thread count.
[[nodiscard]] Extraction extract_surface(const Field& field, const Tetrahedralization& tz,
                                         std::vector<char>& keep, Lattice& lattice,
                                         const TetrahedralOptions& options, const Context* ctx,
                                         TetrahedralStats& stats);

}  // namespace ramiform::detail::tets
