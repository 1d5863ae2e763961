// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/radius_fit_detail.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "ramiform/core/errors.h"

namespace ramiform::detail {
namespace {

Vec3 perpendicular(const Vec3& d) {
  const Vec3 helper = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return d.cross(helper).normalized();
}

}  // namespace

std::vector<EdgeGeometry> edge_geometry(const Skeleton& skeleton) {
  std::vector<EdgeGeometry> out(skeleton.edges.size());
  for (std::size_t e = 0; e < out.size(); ++e) {
    EdgeGeometry& g = out[e];
    const auto& na = skeleton.nodes[skeleton.edges[e][0]];
    const auto& nb = skeleton.nodes[skeleton.edges[e][1]];
    g.a = na.position;
    g.b = nb.position;
    g.ra = na.radius;
    g.rb = nb.radius;
    g.len = (g.b - g.a).norm();
    g.u = (g.b - g.a) / g.len;  // validate() rejects zero-length edges
    g.e1 = perpendicular(g.u);
    g.e2 = g.u.cross(g.e1);
  }
  return out;
}

TubeIndex::TubeIndex(const std::vector<EdgeGeometry>& edges) : edges_(edges) {
  std::vector<Aabb> boxes(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    Aabb box;
    box.extend(edges[e].a);
    box.extend(edges[e].b);
    const double r = std::max(edges[e].ra, edges[e].rb);
    box.min().array() -= r;
    box.max().array() += r;
    boxes[e] = box;
  }
  bvh_ = BoxBvh(std::move(boxes));
}

bool TubeIndex::inside(const Vec3& p, std::uint32_t e, double margin) const {
  const EdgeGeometry& g = edges_[e];
  const double t = std::clamp((p - g.a).dot(g.u) / g.len, 0.0, 1.0);
  const double r = (1 - t) * g.ra + t * g.rb;
  return (p - (g.a + t * g.len * g.u)).norm() < r * (1 - margin);
}

bool TubeIndex::inside_other(const Vec3& p, std::uint32_t own, std::vector<std::uint32_t>& ids,
                             double margin) const {
  ids.clear();
  bvh_.query(Aabb(p, p), ids);
  for (const std::uint32_t e : ids) {
    if (e != own && inside(p, e, margin)) return true;
  }
  return false;
}

void check_at_least(int v, int min, const std::string& what) {
  if (v < min)
    throw InvalidArgument(what + " must be >= " + std::to_string(min) + ", got " +
                          std::to_string(v));
}

}  // namespace ramiform::detail
