// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// `TriMesh` and `PointSet`: the plain copyable data that several stages share (polygonizers
/// produce meshes, samplers read and write point sets, `mesh/` checks and repairs meshes, `io/`
/// reads and writes both), so they live below every stage.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform {

/// A triangle mesh. Triangles list vertex indices counter-clockwise seen from outside.
struct TriMesh {
  std::vector<Vec3> positions;                          ///< one per vertex
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< vertex indices, CCW from outside
  std::vector<Vec3> normals;  ///< optional: empty, or one unit normal per vertex

  [[nodiscard]] std::size_t vertex_count() const { return positions.size(); }
  [[nodiscard]] std::size_t triangle_count() const { return triangles.size(); }
};

/// A set of points with optional normals.
struct PointSet {
  std::vector<Vec3> positions;  ///< one per point
  std::vector<Vec3> normals;    ///< optional: empty, or one per point

  [[nodiscard]] std::size_t size() const { return positions.size(); }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
};

}  // namespace ramiform
