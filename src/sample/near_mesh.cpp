// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Points near a triangle mesh (Kochhar 2010, Application of implicit methods to the interactive
// modeling of trees, M.Sc. thesis, University of Calgary, §6.3): a triangle by area, a uniform
// point in it, offset along the interpolated vertex normal.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/sample/point_sets.h"
#include "sample/common.h"

namespace ramiform {

using namespace sample_detail;

namespace {

/// Cumulative triangle areas and area-weighted vertex normals of a mesh.
struct AreaTable {
  std::vector<double> cdf;    ///< one per triangle: the sum of the areas up to it
  std::vector<Vec3> normals;  ///< one per vertex, not normalized
  double total = 0.0;
};

/// Throws InputError for a vertex index out of range or a non-finite vertex; the mesh's own
/// normals replace the computed ones when there is one per vertex.
AreaTable area_table(const TriMesh& mesh) {
  const std::size_t nv = mesh.positions.size();
  AreaTable a;
  a.cdf.reserve(mesh.triangles.size());
  a.normals.assign(nv, Vec3::Zero());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (const auto v : tri) {
      if (v >= nv) {
        throw InputError("", "triangle", t,
                         "vertex index " + std::to_string(v) + " out of range (" +
                             std::to_string(nv) + " vertices)");
      }
    }
    const Vec3 n = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                       .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    const double area = 0.5 * n.norm();
    if (!std::isfinite(area)) throw InputError("", "triangle", t, "non-finite vertex");
    a.total += area;
    a.cdf.push_back(a.total);
    // |n| is twice the area: summing it weights face normals by area.
    for (const auto v : tri) a.normals[v] += n;
  }
  if (mesh.normals.size() == nv && nv > 0) a.normals = mesh.normals;
  return a;
}

/// A triangle chosen with probability proportional to its area (one draw).
const std::array<std::uint32_t, 3>& draw_triangle(const TriMesh& mesh, const AreaTable& a,
                                                  Rng& rng) {
  // Inverse CDF: cdf[t - 1] <= u < cdf[t] (Kochhar 2010, eq. 6.1).
  const double u = rng.uniform() * a.total;
  auto it = std::upper_bound(a.cdf.begin(), a.cdf.end(), u);
  if (it == a.cdf.end()) --it;
  return mesh.triangles[static_cast<std::size_t>(it - a.cdf.begin())];
}

}  // namespace

PointSet sample_near_mesh(const TriMesh& mesh, const NearMeshOptions& options, std::uint64_t seed) {
  require(std::isfinite(options.min_offset) && std::isfinite(options.max_offset),
          "sample_near_mesh: min_offset and max_offset must be finite");
  require(options.min_offset <= options.max_offset,
          "sample_near_mesh: min_offset " + format_number(options.min_offset) + " > max_offset " +
              format_number(options.max_offset));
  check_point_memory(options.count, nullptr, "sample_near_mesh");
  const AreaTable a = area_table(mesh);
  if (!(a.total > 0.0)) {
    throw InputError("", 0, "sample_near_mesh: the mesh has no triangle of positive area");
  }
  PointSet out;
  out.positions.reserve(options.count);
  out.normals.reserve(options.count);
  Rng rng(seed);
  for (std::size_t i = 0; i < options.count; ++i) {
    const auto& tri = draw_triangle(mesh, a, rng);
    double s = rng.uniform(), t = rng.uniform();
    // Reflecting (s, t) across s + t = 1 keeps it uniform and puts it in the triangle (Turk
    // 1990, Generating random points in triangles, Graphics Gems I).
    if (s + t > 1.0) {
      s = 1.0 - s;
      t = 1.0 - t;
    }
    const Vec3 p = (1.0 - s - t) * mesh.positions[tri[0]] + s * mesh.positions[tri[1]] +
                   t * mesh.positions[tri[2]];
    Vec3 n = (1.0 - s - t) * a.normals[tri[0]] + s * a.normals[tri[1]] + t * a.normals[tri[2]];
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
