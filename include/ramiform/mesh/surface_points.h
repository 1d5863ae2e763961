// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Area-weighted points on a triangle mesh: a triangle chosen with probability proportional to
/// its area (inverse CDF over the cumulative areas), then a uniform point in it (Turk 1990,
/// "Generating random points in triangles", Graphics Gems I: two uniforms reflected across
/// s + t = 1). Shared by the points-near-a-mesh sampler (sample/) and the deviation measure
/// (mesh/deviation.h).

#include <cstdint>
#include <vector>

#include "ramiform/core/geometry.h"
#include "ramiform/core/random.h"

namespace ramiform {

/// A point of a triangle: barycentric (1 - s - t, s, t) on its corners.
struct MeshPoint {
  std::uint32_t triangle = 0;
  double s = 0.0;
  double t = 0.0;
};

/// Cumulative triangle areas of a mesh, for drawing area-weighted points. Keeps a reference to
/// the mesh, which must outlive it.
class MeshAreaSampler {
 public:
  /// Throws InputError (element "triangle") for a vertex index out of range or a non-finite
  /// vertex. A mesh without triangles of positive area has total_area() 0; draw() then must not
  /// be called.
  explicit MeshAreaSampler(const TriMesh& mesh);

  [[nodiscard]] double total_area() const { return total_; }
  /// Area-weighted vertex normals (not normalized); the mesh's own normals when it has one per
  /// vertex.
  [[nodiscard]] const std::vector<Vec3>& vertex_normals() const { return normals_; }

  /// One point, drawn with exactly three `rng.uniform()` calls (triangle, s, t).
  [[nodiscard]] MeshPoint draw(Rng& rng) const;
  /// The position of `p`.
  [[nodiscard]] Vec3 position(const MeshPoint& p) const;

 private:
  const TriMesh* mesh_;
  std::vector<double> cdf_;  // one per triangle: the sum of the areas up to it
  std::vector<Vec3> normals_;
  double total_ = 0.0;
};

}  // namespace ramiform
