// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/skeleton/skeleton.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_set>

#include "ramiform/core/errors.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

}  // namespace

void validate(const Skeleton& skeleton, const std::string& source) {
  if (skeleton.nodes.empty()) throw InputError(source, 0, "skeleton has no nodes");
  if (!skeleton.node_types.empty() && skeleton.node_types.size() != skeleton.nodes.size()) {
    throw InputError(source, 0,
                     std::to_string(skeleton.node_types.size()) + " node types for " +
                         std::to_string(skeleton.nodes.size()) + " nodes (need none or one each)");
  }
  if (!skeleton.open_ends.empty() && skeleton.open_ends.size() != skeleton.nodes.size()) {
    throw InputError(source, 0,
                     std::to_string(skeleton.open_ends.size()) + " open-end flags for " +
                         std::to_string(skeleton.nodes.size()) + " nodes (need none or one each)");
  }
  Aabb box;
  for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
    const auto& n = skeleton.nodes[i];
    if (!is_finite(n.position)) throw InputError(source, "node", i, "position is not finite");
    if (!std::isfinite(n.radius)) throw InputError(source, "node", i, "radius is not finite");
    if (n.radius <= 0.0) {
      throw InputError(source, "node", i, "radius must be > 0, got " + fmt(n.radius));
    }
    // The box grows node by node so that the message names the first node that makes the
    // span overflow (the rule of the point readers).
    box.extend(n.position);
    if (!std::isfinite(box.diagonal().norm())) {
      throw InputError(source, "node", i,
                       "with this node the coordinates span more than double precision can hold "
                       "(from " +
                           format_number(box.min().minCoeff()) + " to " +
                           format_number(box.max().maxCoeff()) + ")");
    }
  }
  const double scale = std::max(box.diagonal().norm(), 1.0);
  std::unordered_set<std::uint64_t> seen;
  seen.reserve(skeleton.edges.size() * 2);
  const auto count = static_cast<std::uint32_t>(skeleton.nodes.size());
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto [a, b] = skeleton.edges[e];
    if (a >= count || b >= count) {
      throw InputError(source, "edge", e,
                       "node index " + std::to_string(a >= count ? a : b) + " out of range (" +
                           std::to_string(count) + " nodes)");
    }
    if (a == b) throw InputError(source, "edge", e, "self-loop at node " + std::to_string(a));
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32U) | std::max(a, b);
    if (!seen.insert(key).second) {
      throw InputError(source, "edge", e,
                       "duplicate edge " + std::to_string(a) + "-" + std::to_string(b));
    }
    const double len = (skeleton.nodes[a].position - skeleton.nodes[b].position).norm();
    if (len <= tol::kCoincident * scale) {
      throw InputError(source, "edge", e,
                       "zero-length edge between nodes " + std::to_string(a) + " and " +
                           std::to_string(b));
    }
  }
}

SkeletonComponents connected_components(const Skeleton& skeleton) {
  const auto n = static_cast<std::uint32_t>(skeleton.nodes.size());
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0U);
  for (const auto& e : skeleton.edges) {
    const std::uint32_t ra = find_root(parent, e[0]);
    const std::uint32_t rb = find_root(parent, e[1]);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  SkeletonComponents out;
  out.label.assign(n, 0);
  std::vector<std::uint32_t> root_label(n, UINT32_MAX);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t r = find_root(parent, i);
    if (root_label[r] == UINT32_MAX) root_label[r] = out.count++;
    out.label[i] = root_label[r];
  }
  return out;
}

Aabb bounding_box(const Skeleton& skeleton) {
  Aabb box;
  for (const auto& n : skeleton.nodes) {
    box.extend(n.position - Vec3::Constant(n.radius));
    box.extend(n.position + Vec3::Constant(n.radius));
  }
  return box;
}

std::vector<std::uint32_t> degrees(const Skeleton& skeleton) {
  std::vector<std::uint32_t> deg(skeleton.nodes.size(), 0);
  for (const auto& e : skeleton.edges) {
    ++deg[e[0]];
    ++deg[e[1]];
  }
  return deg;
}

}  // namespace ramiform
