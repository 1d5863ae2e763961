// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors

#include "reconstruct_job.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <nanoflann.hpp>
#include <numbers>

#include "mesh_job.h"
#include "ramiform/core/errors.h"
#include "ramiform/mesh/cleanup.h"

namespace ramiform::cli {
namespace {

// The sampling spacing 1/sqrt(ρ) of points of surface density ρ: k points lie within the
// distance r_k of a point, on a disk of area k/ρ = π r_k², so 1/sqrt(ρ) = r_k sqrt(π/k), taken
// at the median r_k (k = 6). Unlike the nearest-neighbour distance, it does not shrink for
// random samples (a mesh's area-weighted points), whose nearest neighbours are often close.
// 0 for fewer than k + 1 points.
double sampling_spacing(const std::vector<Vec3>& positions) {
  constexpr std::size_t k = 6;
  if (positions.size() < k + 1) return 0.0;
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using Tree = nanoflann::KDTreeEigenMatrixAdaptor<Matrix, 3, nanoflann::metric_L2_Simple>;
  Matrix m(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    m.row(static_cast<Eigen::Index>(i)) = positions[i].transpose();
  }
  const Tree tree(3, std::cref(m), 16);
  std::vector<double> d(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    Eigen::Index idx[k + 1];
    double sq[k + 1];
    const std::size_t found = tree.index->knnSearch(positions[i].data(), k + 1, idx, sq);
    d[i] = found < k + 1 ? 0.0 : std::sqrt(sq[k]);  // the point itself comes first
  }
  const auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  return *mid * std::sqrt(std::numbers::pi / static_cast<double>(k));
}

// The q-quantile (0..1) of `v` (reordered), 0 for an empty v.
double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  const auto at = v.begin() + static_cast<std::ptrdiff_t>(
                                  std::min(v.size() - 1, static_cast<std::size_t>(q * v.size())));
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

// |f − iso| / |∇f| at every point, relative to `scale`: median, p99 and max.
nlohmann::json first_order_distances(const Field& field, std::span<const Vec3> points, double scale,
                                     Context& ctx) {
  std::vector<double> values(points.size());
  std::vector<Vec3> gradients(points.size());
  field.evaluate(points, values, gradients, &ctx);
  std::vector<double> d(points.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double g = gradients[i].norm();
    d[i] = g > 0 ? std::abs(values[i] - field.iso()) / g / scale
                 : std::numeric_limits<double>::infinity();
    worst = std::max(worst, d[i]);
  }
  nlohmann::json j;
  j["median"] = quantile(d, 0.5);
  j["p99"] = quantile(d, 0.99);
  j["max"] = worst;
  return j;
}

}  // namespace

PointSurface build_point_surface(const std::string& path, const ReconstructOptions& options,
                                 Context& ctx, const std::function<void(const char*)>& lap) {
  PointSurface s;
  const SurfacePoints read = read_surface_points(path, options.read);
  s.stats["points"] = read.points.size();
  if (read.mesh_triangles > 0) {
    s.stats["mesh_input"] = {{"triangles", read.mesh_triangles},
                             {"vertices", read.mesh_vertices},
                             {"samples", read.points.size()}};
  }
  lap("read");
  NormalReport nr;
  const bool given = read.points.has_normals();
  // The library names the point (0-based); the user needs the file too.
  const auto in_file = [&path](const auto& work) {
    try {
      return work();
    } catch (const InvalidArgument& e) {
      throw InputError(path, 0, e.what());
    }
  };
  s.points = in_file([&] { return orient_normals(read.points, options.normals, &nr, &ctx); });
  s.stats["normals"] = {{"given", given},
                        {"estimated", nr.estimated},
                        {"flipped", nr.flipped},
                        {"components", nr.components}};
  lap("normals");
  Aabb box;
  for (const Vec3& p : s.points.positions) box.extend(p);
  s.diagonal = box.diagonal().norm();
  s.spacing = sampling_spacing(s.points.positions);
  MpuStats ms;
  s.field = in_file([&] { return make_mpu_field(s.points, options.mpu, &ms, &ctx); });
  lap("mpu");
  s.stats["spacing"] = s.spacing;
  s.stats["diagonal"] = s.diagonal;
  s.stats["mpu"] = {{"tolerance", options.mpu.tolerance},
                    {"cells", ms.cells},
                    {"leaves", ms.leaves},
                    {"depth", ms.depth},
                    {"general_quadrics", ms.general_quadrics},
                    {"bivariate", ms.bivariate},
                    {"sharp", ms.sharp},
                    {"fit_error_max", ms.fit_error_max},
                    {"seconds", ms.seconds}};
  // How closely the surface passes through its points, relative to the bounding-box diagonal.
  s.stats["interpolation"] =
      first_order_distances(*s.field, s.points.positions, s.diagonal > 0 ? s.diagonal : 1.0, ctx);
  lap("interpolation");
  return s;
}

MarchingCubesOptions reconstruct_mc_options(const PointSurface& surface,
                                            const ReconstructOptions& options) {
  MarchingCubesOptions mc;
  if (options.resolution > 0) {
    mc.resolution = options.resolution;
    return mc;
  }
  if (options.cell_size > 0) {
    mc.cell_size = options.cell_size;
    return mc;
  }
  const Aabb b = surface.field->bounds();
  const double longest = b.isEmpty() ? 0.0 : b.sizes().maxCoeff();
  double cell = options.spacing_cells * surface.spacing;
  if (longest > 0) cell = std::clamp(cell, longest / 512.0, longest / 32.0);
  if (!(cell > 0)) {
    mc.resolution = 96;
    return mc;
  }
  mc.cell_size = cell;
  return mc;
}

TriMesh mesh_point_surface(PointSurface& surface, const ReconstructOptions& options, Context& ctx,
                           MeshReport* report) {
  MarchingCubesStats st;
  TriMesh mesh =
      marching_cubes(*surface.field, reconstruct_mc_options(surface, options), &ctx, &st);
  const std::size_t specks =
      options.speck_cells > 0 ? remove_small_pieces(mesh, options.speck_cells * st.cell_size) : 0;
  nlohmann::json j = check_json(mesh, nullptr, ctx, report);  // the figures of `check`
  j["cell_size"] = st.cell_size;
  j["blocks_skipped"] = st.blocks_skipped;
  j["blocks_total"] = st.blocks_total;
  j["specks_removed"] = specks;
  // Where the vertices sit against the MPU surface they approximate.
  j["vertex_deviation"] = first_order_distances(*surface.field, mesh.positions,
                                                surface.diagonal > 0 ? surface.diagonal : 1.0, ctx);
  surface.stats["mesh"] = j;
  return mesh;
}

}  // namespace ramiform::cli
