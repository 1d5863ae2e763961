// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/winding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "mesh/mesh_indices.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"

namespace ramiform {
namespace {

constexpr double kInv4Pi = 0.25 / std::numbers::pi;
using detail::solid_angle_fraction;

}  // namespace

double winding_number(const TriMesh& mesh, const Vec3& p) {
  detail::check_triangle_indices(mesh, "winding_number");
  double w = 0.0;
  for (const auto& t : mesh.triangles) {
    w += solid_angle_fraction(mesh.positions[t[0]] - p, mesh.positions[t[1]] - p,
                              mesh.positions[t[2]] - p);
  }
  return w;
}

struct WindingNumber::Impl {
  struct Node {
    Vec3 center = Vec3::Zero();  // area-weighted centroid of the node's triangles
    double area = 0.0;           // total triangle area
    double radius = 0.0;         // max distance from center to a vertex of the node
    Vec3 dipole = Vec3::Zero();  // sum of area * normal (order 0)
    Mat3 moment = Mat3::Zero();  // sum of area * normal (centroid - center)^T (order 1)
    // Order 2: second[i] = sum over triangles of (area normal)_i times the triangle's integral
    // of (x - center)(x - center)^T over its area, divided by its area.
    std::array<Mat3, 3> second{Mat3::Zero(), Mat3::Zero(), Mat3::Zero()};
    std::uint32_t begin = 0;  // triangle range [begin, end) in `tris`
    std::uint32_t end = 0;
    std::uint32_t left = 0;  // child indices; 0 for a leaf (the root is never a child)
    std::uint32_t right = 0;
  };
  // Triangle corners in BVH order, three per triangle.
  std::vector<Vec3> corners;
  std::vector<Node> nodes;
  double beta2 = 4.0;

  double exact_leaf(const Node& n, const Vec3& p) const {
    double w = 0.0;
    for (std::size_t t = n.begin; t < n.end; ++t) {
      w += solid_angle_fraction(corners[3 * t] - p, corners[3 * t + 1] - p, corners[3 * t + 2] - p);
    }
    return w;
  }

  double query(const Vec3& p) const {
    if (nodes.empty()) return 0.0;
    double w = 0.0;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes[stack[--top]];
      const Vec3 y = n.center - p;
      const double d2 = y.squaredNorm();
      if (d2 > beta2 * n.radius * n.radius) {
        // Far field: Taylor expansion of the dipole kernel y / (4 pi |y|^3) about the centre.
        const double inv_d = 1.0 / std::sqrt(d2);
        const double inv_d3 = inv_d * inv_d * inv_d;
        const double inv_d5 = inv_d3 * inv_d * inv_d;
        const double inv_d7 = inv_d5 * inv_d * inv_d;
        const double order0 = n.dipole.dot(y) * inv_d3;
        const double order1 = n.moment.trace() * inv_d3 - 3.0 * y.dot(n.moment * y) * inv_d5;
        // Order 2 (Barill et al. eq. 16 written out): with C_ijk = second[i](j, k),
        // 1/2 sum H_ijk C_ijk, H_ijk = -3 (d_ij y_k + d_ik y_j + d_jk y_i) / |y|^5
        //                              + 15 y_i y_j y_k / |y|^7.
        Vec3 a = Vec3::Zero();  // a_k = sum_i C_iik
        double yty = 0.0;       // sum_i y_i y^T C_i y
        double yt = 0.0;        // sum_i y_i trace(C_i)
        for (int i = 0; i < 3; ++i) {
          a += n.second[i].row(i).transpose();
          yty += y[i] * y.dot(n.second[i] * y);
          yt += y[i] * n.second[i].trace();
        }
        const double order2 = 0.5 * (-3.0 * (2.0 * y.dot(a) + yt) * inv_d5 + 15.0 * yty * inv_d7);
        w += (order0 + order1 + order2) * kInv4Pi;
      } else if (n.left == 0) {
        w += exact_leaf(n, p);
      } else {
        stack[top++] = n.right;
        stack[top++] = n.left;
      }
    }
    return w;
  }

  /// Builds the subtree over order[begin, end) and returns its node id. Leaves compute their
  /// moments from their triangles; inner nodes combine their children's moments, shifted to the
  /// node's centre (exact), so the build costs O(T log T) for the splits only.
  std::uint32_t build(std::vector<std::uint32_t>& order, const std::vector<Vec3>& centroid,
                      const std::vector<Vec3>& area_normal, const std::vector<double>& area,
                      const TriMesh& mesh, std::uint32_t begin, std::uint32_t end, int leaf_size,
                      int depth) {
    const auto id = static_cast<std::uint32_t>(nodes.size());
    nodes.emplace_back();
    Node n;
    n.begin = begin;
    n.end = end;
    // The stack in query() holds at most depth + 1 entries; keep the tree shallow enough.
    if (static_cast<int>(end - begin) <= leaf_size || depth >= 100) {
      Vec3 weighted = Vec3::Zero();
      Vec3 plain = Vec3::Zero();
      for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t t = order[i];
        n.area += area[t];
        weighted += area[t] * centroid[t];
        plain += centroid[t];
      }
      n.center = n.area > 0.0 ? Vec3(weighted / n.area) : Vec3(plain / (end - begin));
      for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t t = order[i];
        n.dipole += area_normal[t];
        const Vec3 dc = centroid[t] - n.center;
        n.moment += area_normal[t] * dc.transpose();
        // Exact mean of (x - center)(x - center)^T over the triangle.
        Mat3 cov = dc * dc.transpose();
        for (const std::uint32_t v : mesh.triangles[t]) {
          const Vec3 dv = mesh.positions[v] - centroid[t];
          cov += dv * dv.transpose() / 12.0;
          n.radius = std::max(n.radius, (mesh.positions[v] - n.center).norm());
        }
        for (int k = 0; k < 3; ++k) n.second[k] += area_normal[t][k] * cov;
      }
      nodes[id] = n;
      return id;
    }
    Aabb cbox;
    for (std::uint32_t i = begin; i < end; ++i) cbox.extend(centroid[order[i]]);
    int axis = 0;
    cbox.sizes().maxCoeff(&axis);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       const double ca = centroid[a][axis];
                       const double cb = centroid[b][axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    n.left = build(order, centroid, area_normal, area, mesh, begin, mid, leaf_size, depth + 1);
    n.right = build(order, centroid, area_normal, area, mesh, mid, end, leaf_size, depth + 1);
    const Node l = nodes[n.left];  // copies: `nodes` grew during the recursion
    const Node r = nodes[n.right];
    n.area = l.area + r.area;
    n.center = n.area > 0.0 ? Vec3((l.area * l.center + r.area * r.center) / n.area)
                            : Vec3(((l.end - l.begin) * l.center + (r.end - r.begin) * r.center) /
                                   static_cast<double>(end - begin));
    for (const Node* c : {&l, &r}) {
      // Shift the child's expansion from its centre to ours: x - ours = (x - its) + d.
      const Vec3 d = c->center - n.center;
      n.dipole += c->dipole;
      n.moment += c->moment + c->dipole * d.transpose();
      for (int k = 0; k < 3; ++k) {
        const Vec3 m = c->moment.row(k).transpose();
        n.second[k] +=
            c->second[k] + m * d.transpose() + d * m.transpose() + c->dipole[k] * d * d.transpose();
      }
      // A bounding radius (not the tightest): nodes are approximated a little less often.
      n.radius = std::max(n.radius, c->radius + d.norm());
    }
    nodes[id] = n;
    return id;
  }
};

WindingNumber::WindingNumber(const TriMesh& mesh, const WindingOptions& options)
    : impl_(std::make_unique<Impl>()) {
  if (!(options.beta > 1.0) || !std::isfinite(options.beta)) {
    throw InvalidArgument("WindingOptions.beta must be a finite number > 1, got " +
                          std::to_string(options.beta));
  }
  if (options.leaf_size < 1) {
    throw InvalidArgument("WindingOptions.leaf_size must be >= 1, got " +
                          std::to_string(options.leaf_size));
  }
  detail::check_triangle_indices(mesh, "WindingNumber");
  impl_->beta2 = options.beta * options.beta;
  const std::size_t nt = mesh.triangles.size();
  if (nt == 0) return;
  if (nt >= (std::size_t{1} << 31)) throw InvalidArgument("WindingNumber: too many triangles");
  std::vector<Vec3> centroid(nt);
  std::vector<Vec3> area_normal(nt);
  std::vector<double> area(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Vec3& a = mesh.positions[mesh.triangles[t][0]];
    const Vec3& b = mesh.positions[mesh.triangles[t][1]];
    const Vec3& c = mesh.positions[mesh.triangles[t][2]];
    centroid[t] = (a + b + c) / 3.0;
    area_normal[t] = 0.5 * (b - a).cross(c - a);
    area[t] = area_normal[t].norm();
  }
  std::vector<std::uint32_t> order(nt);
  for (std::size_t t = 0; t < nt; ++t) order[t] = static_cast<std::uint32_t>(t);
  impl_->nodes.reserve(2 * nt / static_cast<std::size_t>(options.leaf_size) + 2);
  impl_->build(order, centroid, area_normal, area, mesh, 0, static_cast<std::uint32_t>(nt),
               options.leaf_size, 0);
  impl_->corners.resize(3 * nt);
  for (std::size_t i = 0; i < nt; ++i) {
    for (int k = 0; k < 3; ++k)
      impl_->corners[3 * i + k] = mesh.positions[mesh.triangles[order[i]][k]];
  }
}

WindingNumber::~WindingNumber() = default;
WindingNumber::WindingNumber(WindingNumber&&) noexcept = default;
WindingNumber& WindingNumber::operator=(WindingNumber&&) noexcept = default;

double WindingNumber::operator()(const Vec3& p) const { return impl_->query(p); }

std::vector<double> WindingNumber::evaluate(std::span<const Vec3> points,
                                            const Context* ctx) const {
  std::vector<double> w(points.size());
  parallel::for_chunks(
      points.size(), 64,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) w[i] = impl_->query(points[i]);
      },
      ctx);
  return w;
}

std::vector<char> points_inside(const TriMesh& mesh, std::span<const Vec3> points,
                                const Context* ctx) {
  const WindingNumber wn(mesh);
  const std::vector<double> w = wn.evaluate(points, ctx);
  std::vector<char> inside(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) inside[i] = w[i] > 0.5 ? 1 : 0;
  return inside;
}

}  // namespace ramiform
