// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/surface_points.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ramiform/core/errors.h"

namespace ramiform {

MeshAreaSampler::MeshAreaSampler(const TriMesh& mesh) : mesh_(&mesh) {
  const std::size_t nv = mesh.positions.size();
  cdf_.reserve(mesh.triangles.size());
  normals_.assign(nv, Vec3::Zero());
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
    total_ += area;
    cdf_.push_back(total_);
    // |n| is twice the area: summing it weights face normals by area.
    for (const auto v : tri) normals_[v] += n;
  }
  if (mesh.normals.size() == nv && nv > 0) normals_ = mesh.normals;
}

MeshPoint MeshAreaSampler::draw(Rng& rng) const {
  // Inverse CDF: cdf[t - 1] <= u < cdf[t] (Kochhar 2010, eq. 6.1).
  const double u = rng.uniform() * total_;
  auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  if (it == cdf_.end()) --it;
  MeshPoint p;
  p.triangle = static_cast<std::uint32_t>(it - cdf_.begin());
  p.s = rng.uniform();
  p.t = rng.uniform();
  // Reflecting (s, t) across s + t = 1 keeps it uniform and puts it in the triangle.
  if (p.s + p.t > 1.0) {
    p.s = 1.0 - p.s;
    p.t = 1.0 - p.t;
  }
  return p;
}

Vec3 MeshAreaSampler::position(const MeshPoint& p) const {
  const auto& tri = mesh_->triangles[p.triangle];
  return (1.0 - p.s - p.t) * mesh_->positions[tri[0]] + p.s * mesh_->positions[tri[1]] +
         p.t * mesh_->positions[tri[2]];
}

}  // namespace ramiform
