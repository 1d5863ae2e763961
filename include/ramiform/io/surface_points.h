// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Oriented points for surface reconstruction (MPU, field/mpu.h), read from either a point cloud
/// or a triangle mesh: what `ramiform reconstruct`, `ramiform particles` and the scene
/// language's `mpu` take (docs/reconstruction.md).

#include <cstddef>
#include <cstdint>
#include <string>

#include "ramiform/core/geometry.h"

namespace ramiform {

/// Options of `read_surface_points`.
struct SurfacePointsOptions {
  std::size_t mesh_samples = 30000;  ///< points drawn on a mesh (> 0)
  std::uint64_t seed = 1;            ///< seed of the mesh samples
};

/// What `read_surface_points` read.
struct SurfacePoints {
  PointSet points;                 ///< positions, with normals when the file had them
  std::size_t mesh_triangles = 0;  ///< > 0: the file was a mesh of that many triangles
  std::size_t mesh_vertices = 0;   ///< its vertex count
};

/// True when `path` names a triangle mesh rather than a point cloud: `.off` and `.obj`, and a
/// `.ply` whose header declares a `face` element with at least one face. Reads only the PLY
/// header. Throws InputError for an unreadable file or a malformed PLY header.
[[nodiscard]] bool is_mesh_file(const std::string& path);

/// A point cloud (io/points_io.h: "x y z [nx ny nz]" text, `.xyz`, `.pwn`, PLY vertices with or
/// without normals) as it is; a mesh (io/mesh_io.h) as `mesh_samples` area-weighted points
/// (mesh/surface_points.h, seeded) with the unit normals of their triangles, which follow the
/// triangles' winding (counter-clockwise seen from outside). Degenerate triangles (area 0) are
/// never drawn. Throws InputError naming the file as the readers do, and for a mesh without any
/// triangle of positive area; InvalidArgument for mesh_samples 0.
[[nodiscard]] SurfacePoints read_surface_points(const std::string& path,
                                                const SurfacePointsOptions& options = {});

}  // namespace ramiform
