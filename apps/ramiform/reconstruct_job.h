// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Point clouds and meshes to MPU implicits (field/mpu.h), shared by `ramiform reconstruct`,
// `ramiform particles` and the Python module: read, orient the normals, fit, and (reconstruct)
// mesh by marching cubes at a cell size from the point spacing.

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/field/mpu.h"
#include "ramiform/field/point_normals.h"
#include "ramiform/io/surface_points.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/polygonize/marching_cubes.h"

namespace ramiform::cli {

/// Everything `reconstruct` can be told.
struct ReconstructOptions {
  SurfacePointsOptions read;  ///< --mesh-samples, --seed
  NormalOptions normals;      ///< --neighbours
  MpuOptions mpu;             ///< --tolerance, --support, --min-points, --max-depth, --no-sharp
  /// Marching cubes cell size in model units; 0 = `spacing_cells` × the points' sampling
  /// spacing (1/sqrt(density), from the median distance to the 6th nearest neighbour), kept
  /// between 32 and 512 cells along the longest side.
  double cell_size = 0.0;
  int resolution = 0;          ///< cells along the longest side instead (0 = from cell_size)
  double spacing_cells = 1.0;  ///< the default cell size in point spacings
  /// Pieces of the mesh smaller than this many cells (bounding-box diagonal) are removed as
  /// specks (details below the grid's resolution); 0 keeps every piece.
  double speck_cells = 3.0;
};

/// The MPU surface of a point file, before meshing.
struct PointSurface {
  PointSet points;  ///< as oriented
  FieldPtr field;
  double spacing = 0.0;   ///< sampling spacing of the points, 1/sqrt(surface density)
  double diagonal = 0.0;  ///< of the points' bounding box
  nlohmann::json stats;   ///< points, normals, mpu, interpolation
};

/// Reads `path` (a point cloud or a mesh), orients its normals and fits the MPU implicit.
/// `timer_lap(name)` is called after each stage (read, normals, mpu).
[[nodiscard]] PointSurface build_point_surface(const std::string& path,
                                               const ReconstructOptions& options, Context& ctx,
                                               const std::function<void(const char*)>& lap);

/// The marching cubes options `reconstruct` uses for `surface`.
[[nodiscard]] MarchingCubesOptions reconstruct_mc_options(const PointSurface& surface,
                                                          const ReconstructOptions& options);

/// Meshes `surface` (marching cubes with bound pruning), removes specks (`speck_cells`) and adds
/// "mesh" figures to its stats: vertices, triangles, cell_size, specks_removed, watertight,
/// oriented, manifold, components, and the vertex
/// deviation from the MPU surface (|f − iso| / |∇f|, median and max, relative to the diagonal).
[[nodiscard]] TriMesh mesh_point_surface(PointSurface& surface, const ReconstructOptions& options,
                                         Context& ctx, MeshReport* report = nullptr);

}  // namespace ramiform::cli
