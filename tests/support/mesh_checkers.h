// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Shared gtest checkers of mesh invariants (see ramiform/mesh/checks.h for the definitions).
/// The `is_*` forms return an AssertionResult for EXPECT_TRUE/ASSERT_TRUE (failures then point
/// at the caller's line); the `expect_*` forms add a non-fatal failure themselves.

#include <gtest/gtest.h>

#include <cstddef>

#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::test {

/// One line summarizing a report, for failure messages.
std::string describe(const MeshReport& report);

::testing::AssertionResult is_watertight(const TriMesh& mesh);
::testing::AssertionResult is_oriented(const TriMesh& mesh);
::testing::AssertionResult is_manifold(const TriMesh& mesh);
::testing::AssertionResult has_components(const TriMesh& mesh, std::size_t n);

void expect_watertight(const TriMesh& mesh);
void expect_oriented(const TriMesh& mesh);
void expect_manifold(const TriMesh& mesh);
void expect_components(const TriMesh& mesh, std::size_t n);
/// Watertight, oriented and manifold, with an even Euler characteristic (closed orientable
/// surfaces of any genus); returns the report for further checks.
MeshReport expect_closed_manifold(const TriMesh& mesh);
/// expect_closed_manifold, with `components` components and Euler characteristic `euler` (2 per
/// sphere-like component, 0 per torus).
void expect_closed_surface(const TriMesh& mesh, std::size_t components, long long euler);

/// How many of `skeleton`'s nodes (each moved by `transform` first, e.g. into a file's axes)
/// lie outside the closed mesh (mesh/winding.h points_inside).
[[nodiscard]] std::size_t nodes_outside(const TriMesh& mesh, const Skeleton& skeleton,
                                        Vec3 (*transform)(const Vec3&) = nullptr);

/// How many triangles face along `field`'s gradient summed at their corners, i.e. into the
/// surface (f > iso inside): folded triangles, counted independently of any mesher's own count.
[[nodiscard]] std::size_t triangles_facing_inwards(const TriMesh& mesh, const Field& field);

}  // namespace ramiform::test
