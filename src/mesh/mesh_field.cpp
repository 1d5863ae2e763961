// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/mesh_field.h"

#include <algorithm>
#include <functional>
#include <nanoflann.hpp>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/winding.h"

namespace ramiform {
namespace {

class MeshField final : public Field {
 public:
  MeshField(const TriMesh& mesh, std::size_t triangles)
      : Field(0.5), winding_(mesh), triangles_(triangles), centroids_(mesh.triangles.size(), 3) {
    for (const Vec3& p : mesh.positions) box_.extend(p);
    step_ = 1e-3 * box_.diagonal().norm();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const Vec3 c = (mesh.positions[tri[0]] + mesh.positions[tri[1]] + mesh.positions[tri[2]]) / 3;
      centroids_.row(static_cast<Eigen::Index>(t)) = c.transpose();
      for (std::uint32_t v : tri) reach_ = std::max(reach_, (mesh.positions[v] - c).norm());
    }
    tree_ = std::make_unique<Tree>(3, std::cref(centroids_), 16);
  }

  Interval bound(const Aabb& box) const override {
    // Outside a closed mesh's box the winding number is 0 (up to the fast evaluation's error).
    if (box.intersection(box_).isEmpty()) return {-0.05, 0.05};
    // A box the surface does not reach has one winding number throughout: every surface point
    // lies within `reach_` of a triangle centroid, so the surface is at least
    // |centre - nearest centroid| - reach_ from the box's centre.
    const Vec3 centre = box.center();
    Eigen::Index nearest = 0;
    double squared = 0;
    tree_->index->knnSearch(centre.data(), 1, &nearest, &squared);
    if (std::sqrt(squared) - reach_ > 0.5 * box.diagonal().norm()) {
      const double w = winding_(centre);
      return {w - 0.05, w + 0.05};
    }
    return {-0.05, 1.05};
  }

  Aabb bounds() const override { return box_; }

  std::string describe() const override {
    return "closed mesh of " + std::to_string(triangles_) + " triangles (winding number)";
  }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    const std::vector<double> w = winding_.evaluate(points, ctx);
    std::copy(w.begin(), w.end(), values.begin());
    if (gradients.empty()) return;
    std::vector<Vec3> probes;
    probes.reserve(points.size() * 6);
    for (const Vec3& p : points) {
      for (int k = 0; k < 3; ++k) {
        probes.push_back(p + step_ * Vec3::Unit(k));
        probes.push_back(p - step_ * Vec3::Unit(k));
      }
    }
    const std::vector<double> v = winding_.evaluate(probes, ctx);
    for (std::size_t i = 0; i < points.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        const std::size_t at = i * 6 + static_cast<std::size_t>(k) * 2;
        gradients[i][k] = (v[at] - v[at + 1]) / (2 * step_);
      }
    }
  }

 private:
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using Tree = nanoflann::KDTreeEigenMatrixAdaptor<Matrix, 3, nanoflann::metric_L2_Simple>;

  WindingNumber winding_;
  std::size_t triangles_;
  Matrix centroids_;
  std::unique_ptr<Tree> tree_;
  double reach_ = 0;  // largest distance of a triangle's corner from its centroid
  Aabb box_;
  double step_ = 0;
};

}  // namespace

FieldPtr make_mesh_field(const TriMesh& mesh) {
  if (mesh.triangles.empty()) throw InvalidArgument("mesh field: the mesh has no triangles");
  const MeshReport r = check_mesh(mesh);
  if (!r.watertight || !r.oriented || !r.manifold) {
    throw InvalidArgument("mesh field: the mesh must be closed (watertight " +
                          std::string(r.watertight ? "yes" : "no") + ", oriented " +
                          (r.oriented ? "yes" : "no") + ", manifold " +
                          (r.manifold ? "yes" : "no") + ")");
  }
  if (signed_volume(mesh) < 0) {  // oriented inside out: flip, so that the inside is inside
    TriMesh flipped = mesh;
    for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
    return std::make_shared<MeshField>(flipped, mesh.triangles.size());
  }
  return std::make_shared<MeshField>(mesh, mesh.triangles.size());
}

}  // namespace ramiform
