// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/normals.h"

#include <cmath>
#include <string>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

// The vertex a seam copy stands for (itself when the mesh is not split).
std::uint32_t original(const TriMesh& mesh, std::uint32_t v) {
  return mesh.welded.empty() ? v : mesh.welded[v];
}

// Area-weighted triangle normals summed per original vertex (cross products are twice the
// area times the unit normal, so summing them weights by area).
std::vector<Vec3> face_normal_sums(const TriMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  if (!mesh.welded.empty() && mesh.welded.size() != n) {
    throw InvalidArgument("normals: " + std::to_string(mesh.welded.size()) +
                          " welded entries for " + std::to_string(n) + " vertices");
  }
  std::vector<Vec3> sum(n, Vec3::Zero());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (const std::uint32_t v : tri) {
      if (v >= n || original(mesh, v) >= n) {
        throw InvalidArgument("normals: triangle " + std::to_string(t) + " has vertex index " +
                              std::to_string(v) + " out of range (" + std::to_string(n) +
                              " vertices)");
      }
    }
    const Vec3 c = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                       .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    for (const std::uint32_t v : tri) sum[original(mesh, v)] += c;
  }
  return sum;
}

Vec3 unit_or_up(const Vec3& v) {
  const double len = v.norm();
  return len > 0.0 && std::isfinite(len) ? Vec3(v / len) : Vec3(0, 0, 1);
}

}  // namespace

void set_normals_from_faces(TriMesh& mesh) {
  const std::vector<Vec3> sum = face_normal_sums(mesh);
  mesh.normals.resize(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    mesh.normals[i] = unit_or_up(sum[original(mesh, static_cast<std::uint32_t>(i))]);
  }
}

std::size_t set_normals_from_field(TriMesh& mesh, const Field& field, const Context* ctx) {
  const std::size_t n = mesh.positions.size();
  std::vector<Vec3> sum = face_normal_sums(mesh);  // also checks the indices
  std::vector<double> value(n);
  std::vector<Vec3> grad(n);
  field.evaluate(mesh.positions, value, grad, ctx);
  mesh.normals.resize(n);
  std::size_t fallbacks = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t o = original(mesh, static_cast<std::uint32_t>(i));
    const Vec3& g = grad[o];
    const double len = g.norm();
    if (len > 0.0 && std::isfinite(len)) {
      mesh.normals[i] = -g / len;
    } else {
      mesh.normals[i] = unit_or_up(sum[o]);
      if (o == i) ++fallbacks;
    }
  }
  return fallbacks;
}

void add_surface_attributes(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                            const SurfaceAttributeOptions& options, const Context* ctx,
                            BarkUvStats* uv_stats) {
  if (options.normals || options.uvs) set_normals_from_field(mesh, field, ctx);
  if (options.uvs) mesh = add_bark_uvs(mesh, skeleton, options.bark, uv_stats, ctx);
  if (!options.normals) mesh.normals.clear();
  if (!options.normals) mesh.tangents.clear();
}

}  // namespace ramiform
