// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/skeleton/skeleton.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_set>

#include "core/bernstein.h"
#include "core/extent_check.h"
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

// The most inner control points of a curved edge (degree 16 curves are refused).
constexpr std::size_t kMaxInnerControls = 14;

// `extent`: the nodes'; the curve's controls must keep the span within double precision too
// (the straightened nodes lie in their hull).
void validate_curve(const EdgeCurve& c, std::size_t e, const std::string& source,
                    detail::ExtentCheck extent) {
  if (c.controls.size() > kMaxInnerControls) {
    throw InputError(source, "edge", e,
                     std::to_string(c.controls.size()) + " control points (at most " +
                         std::to_string(kMaxInnerControls) + ", a curve of degree " +
                         std::to_string(kMaxInnerControls + 1) + ")");
  }
  for (std::size_t k = 0; k < c.controls.size(); ++k) {
    if (!is_finite(c.controls[k])) {
      throw InputError(source, "edge", e, "control point " + std::to_string(k) + " is not finite");
    }
    if (!extent.add(c.controls[k])) {
      throw InputError(source, "edge", e,
                       "control point " + std::to_string(k) + ": " + extent.problem("it"));
    }
  }
  if (!c.radii.empty() && c.radii.size() != c.controls.size()) {
    throw InputError(source, "edge", e,
                     std::to_string(c.radii.size()) + " radii for " +
                         std::to_string(c.controls.size()) +
                         " control points (need none or one each)");
  }
  for (std::size_t k = 0; k < c.radii.size(); ++k) {
    if (!std::isfinite(c.radii[k]) || c.radii[k] <= 0) {
      throw InputError(source, "edge", e,
                       "radius " + std::to_string(k) + " must be finite and > 0, got " +
                           fmt(c.radii[k]));
    }
  }
}

// de Casteljau on a control polygon of points (or radii).
template <class T>
T casteljau(std::vector<T> work, double t) {
  return detail::casteljau_in_place(work.data(), static_cast<int>(work.size()) - 1, t, 0,
                                    work[0]);
}

// At most this many straight pieces per curved edge, and in all.
constexpr std::size_t kMaxPiecesPerEdge = 4096;
constexpr std::size_t kMaxStraightenedPieces = std::size_t{1} << 22;

// Pieces of a curved edge with control polygon `points` and radii: max|C''| <= n (n - 1)
// max|second difference|, and the same for the radius; the chord of a piece of parameter
// length h deviates from the curve by at most h^2 / 8 max|C''|.
std::size_t curve_pieces(const std::vector<Vec3>& points, const std::vector<double>& radii,
                         double relative_tolerance) {
  const std::size_t n = points.size() - 1;
  double second = 0, second_r = 0;
  for (std::size_t k = 0; k + 2 <= n; ++k) {
    second = std::max(second, (points[k + 2] - 2 * points[k + 1] + points[k]).norm());
    second_r = std::max(second_r, std::abs(radii[k + 2] - 2 * radii[k + 1] + radii[k]));
  }
  const double scale = static_cast<double>(n * (n - 1)) / 8;
  const double r_min = *std::min_element(radii.begin(), radii.end());
  const double need = std::max(scale * second, scale * second_r) / (relative_tolerance * r_min);
  if (!(need < 1e12)) return kMaxPiecesPerEdge;
  return std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(std::sqrt(need))), 1,
                                 kMaxPiecesPerEdge);
}

}  // namespace

bool Skeleton::has_curves() const {
  return std::any_of(curves.begin(), curves.end(),
                     [](const EdgeCurve& c) { return !c.controls.empty(); });
}

void edge_controls(const Skeleton& skeleton, std::size_t e, std::vector<Vec3>& points,
                   std::vector<double>& radii) {
  const auto [a, b] = skeleton.edges.at(e);
  const SkeletonNode& na = skeleton.nodes[a];
  const SkeletonNode& nb = skeleton.nodes[b];
  const EdgeCurve* curve = skeleton.curves.empty() ? nullptr : &skeleton.curves[e];
  const std::size_t inner = curve != nullptr ? curve->controls.size() : 0;
  const std::size_t n = inner + 1;  // degree
  points.assign(1, na.position);
  radii.assign(1, na.radius);
  for (std::size_t k = 0; k < inner; ++k) {
    points.push_back(curve->controls[k]);
    const double f = static_cast<double>(k + 1) / static_cast<double>(n);
    radii.push_back(curve->radii.empty() ? (1 - f) * na.radius + f * nb.radius : curve->radii[k]);
  }
  points.push_back(nb.position);
  radii.push_back(nb.radius);
}

Skeleton straighten_curves(const Skeleton& skeleton, double relative_tolerance) {
  if (!(relative_tolerance > 0 && relative_tolerance <= 1)) {
    throw InvalidArgument("straighten_curves: relative_tolerance must be in (0, 1], got " +
                          fmt(relative_tolerance));
  }
  Skeleton out = skeleton;
  out.curves.clear();
  if (!skeleton.has_curves()) return out;
  validate(skeleton);
  out.edges.clear();
  std::vector<Vec3> points;
  std::vector<double> radii;
  // Pieces per edge first, so that a hostile file is refused before anything is allocated.
  std::vector<std::size_t> pieces_of(skeleton.edges.size(), 1);
  std::size_t total = 0;
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    if (skeleton.curves[e].controls.empty()) continue;
    edge_controls(skeleton, e, points, radii);
    pieces_of[e] = curve_pieces(points, radii, relative_tolerance);
    total += pieces_of[e];
  }
  if (total > kMaxStraightenedPieces) {
    throw InvalidArgument("straighten_curves: the curved edges need " + std::to_string(total) +
                          " straight pieces at relative tolerance " + fmt(relative_tolerance) +
                          " (at most " + std::to_string(kMaxStraightenedPieces) + ")");
  }
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto [a, b] = skeleton.edges[e];
    if (skeleton.curves[e].controls.empty()) {
      out.edges.push_back(skeleton.edges[e]);
      continue;
    }
    edge_controls(skeleton, e, points, radii);
    const std::size_t pieces = pieces_of[e];
    auto previous = a;
    for (std::size_t k = 1; k < pieces; ++k) {
      const double t = static_cast<double>(k) / static_cast<double>(pieces);
      out.nodes.push_back({casteljau(points, t), casteljau(radii, t)});
      if (!out.node_types.empty()) out.node_types.push_back(skeleton.node_types[a]);
      if (!out.open_ends.empty()) out.open_ends.push_back(0);
      const auto next = static_cast<std::uint32_t>(out.nodes.size() - 1);
      out.edges.push_back({previous, next});
      previous = next;
    }
    out.edges.push_back({previous, b});
  }
  return out;
}

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
  detail::ExtentCheck extent;
  for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
    const auto& n = skeleton.nodes[i];
    if (!is_finite(n.position)) throw InputError(source, "node", i, "position is not finite");
    if (!std::isfinite(n.radius)) throw InputError(source, "node", i, "radius is not finite");
    if (n.radius <= 0.0) {
      throw InputError(source, "node", i, "radius must be > 0, got " + fmt(n.radius));
    }
    if (!extent.add(n.position)) throw InputError(source, "node", i, extent.problem("this node"));
  }
  if (!skeleton.curves.empty() && skeleton.curves.size() != skeleton.edges.size()) {
    throw InputError(source, 0,
                     std::to_string(skeleton.curves.size()) + " edge curves for " +
                         std::to_string(skeleton.edges.size()) + " edges (need none or one each)");
  }
  const double scale = std::max(extent.box().diagonal().norm(), 1.0);
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
    if (!skeleton.curves.empty()) validate_curve(skeleton.curves[e], e, source, extent);
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
