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
  /// Optional texture coordinates: empty, or one (u, v) per vertex. A textured mesh has its
  /// vertices split along the texture's seams (one copy per side), so that each vertex has one
  /// (u, v); `welded` then says which copies are the same point of the surface.
  std::vector<Vec2> uvs;
  /// Optional, only with `uvs`: one tangent per vertex, xyz the unit direction of increasing u
  /// orthogonal to the normal and w = +1 or -1 such that cross(normal, xyz) * w points along
  /// increasing v (glTF 2.0's TANGENT convention).
  std::vector<Vec4> tangents;
  /// Optional: empty, or for each vertex the index of the vertex it is a copy of along a seam
  /// (welded[i] <= i, and welded[welded[i]] == welded[i]). Copies share the position and the
  /// normal; a writer that stores texture coordinates per corner (OBJ) writes one vertex per
  /// welded group, and mesh checks look through the copies.
  std::vector<std::uint32_t> welded;
  /// Optional: empty, or one integer label per vertex (e.g. the SWC type of the nearest
  /// skeleton node, see cli mesh). Seam copies carry their original's label. PLY writes it as
  /// `property int swc_type`; OBJ, OFF and glTF ignore it.
  std::vector<std::int32_t> vertex_labels;

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
