// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors

#include "ramiform/io/surface_points.h"

#include "io/ply_format.h"
#include "io/text_scan.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/mesh/surface_points.h"

namespace ramiform {

using namespace io_detail;

bool is_mesh_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".off" || ext == ".obj") return true;
  if (ext != ".ply") return false;
  const PlyHeader header = parse_ply_header(read_whole_file(path), path);
  const std::optional<std::size_t> face = header.find("face");
  return face && header.elements[*face].count > 0;
}

SurfacePoints read_surface_points(const std::string& path, const SurfacePointsOptions& options) {
  if (options.mesh_samples == 0) {
    throw InvalidArgument("read_surface_points: mesh_samples must be > 0");
  }
  SurfacePoints out;
  if (!is_mesh_file(path)) {
    out.points = read_points(path);
    return out;
  }
  const TriMesh mesh = read_mesh(path);
  out.mesh_triangles = mesh.triangles.size();
  out.mesh_vertices = mesh.positions.size();
  const MeshAreaSampler sampler(mesh);
  if (!(sampler.total_area() > 0.0)) {
    throw InputError(path, 0, "the mesh has no triangle of positive area to sample");
  }
  Rng rng(options.seed);
  out.points.positions.reserve(options.mesh_samples);
  out.points.normals.reserve(options.mesh_samples);
  for (std::size_t i = 0; i < options.mesh_samples; ++i) {
    const MeshPoint p = sampler.draw(rng);
    const auto& t = mesh.triangles[p.triangle];
    const Vec3& a = mesh.positions[t[0]];
    const Vec3 n = (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
    out.points.positions.push_back(sampler.position(p));
    out.points.normals.push_back(n.normalized());
  }
  return out;
}

}  // namespace ramiform
