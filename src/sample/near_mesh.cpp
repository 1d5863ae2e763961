// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Points near a triangle mesh (Kochhar 2010, Application of implicit methods to the interactive
// modeling of trees, M.Sc. thesis, University of Calgary, §6.3): a triangle by area, a uniform
// point in it, offset along the interpolated vertex normal.
#include <cmath>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/mesh/surface_points.h"
#include "ramiform/sample/point_sets.h"
#include "sample/common.h"

namespace ramiform {

using namespace sample_detail;

PointSet sample_near_mesh(const TriMesh& mesh, const NearMeshOptions& options, std::uint64_t seed) {
  require(std::isfinite(options.min_offset) && std::isfinite(options.max_offset),
          "sample_near_mesh: min_offset and max_offset must be finite");
  require(options.min_offset <= options.max_offset,
          "sample_near_mesh: min_offset " + format_number(options.min_offset) + " > max_offset " +
              format_number(options.max_offset));
  check_point_memory(options.count, nullptr, "sample_near_mesh");
  const MeshAreaSampler a(mesh);
  if (!(a.total_area() > 0.0)) {
    throw InputError("", 0, "sample_near_mesh: the mesh has no triangle of positive area");
  }
  const std::vector<Vec3>& normals = a.vertex_normals();
  PointSet out;
  out.positions.reserve(options.count);
  out.normals.reserve(options.count);
  Rng rng(seed);
  for (std::size_t i = 0; i < options.count; ++i) {
    const MeshPoint m = a.draw(rng);
    const auto& tri = mesh.triangles[m.triangle];
    const Vec3 p = a.position(m);
    Vec3 n = (1.0 - m.s - m.t) * normals[tri[0]] + m.s * normals[tri[1]] + m.t * normals[tri[2]];
    if (!(n.norm() > 0.0)) {
      n = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
              .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    }
    n.normalize();
    const double offset = rng.uniform(options.min_offset, options.max_offset);
    out.positions.push_back(p + offset * n);
    out.normals.push_back(n);
  }
  return out;
}

}  // namespace ramiform
