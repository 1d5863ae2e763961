// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/tetrahedral_region.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/segment.h"
#include "field/bvh.h"
#include "polygonize/delaunay.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"

namespace ramiform::detail::tets {
namespace {

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b, double& t) {
  t = segment_parameter(p, a, b);
  return (p - (a + t * (b - a))).norm();
}

// The skeleton as capsules: every edge, and every node without one (as a capsule from the node
// to itself), each with its box grown by `reach` times its larger radius.
struct Capsules {
  std::vector<std::array<std::uint32_t, 2>> nodes;
  std::vector<Aabb> boxes;
};

Capsules capsules_of(const Skeleton& s, double reach) {
  Capsules caps;
  for (const auto& e : s.edges) caps.nodes.push_back(e);
  std::vector<char> has_edge(s.nodes.size(), 0);
  for (const auto& e : s.edges) has_edge[e[0]] = has_edge[e[1]] = 1;
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    if (has_edge[i] == 0) caps.nodes.push_back({i, i});
  }
  for (const auto& c : caps.nodes) {
    const auto& a = s.nodes[c[0]];
    const auto& b = s.nodes[c[1]];
    const double grow = reach * std::max(a.radius, b.radius);
    Aabb box;
    box.extend(a.position);
    box.extend(b.position);
    box.min().array() -= grow;
    box.max().array() += grow;
    caps.boxes.push_back(box);
  }
  return caps;
}

// Marks the tetrahedra whose centroid lies within `reach` radii (interpolated along the
// capsule) of a capsule.
void mark_near_skeleton(const Skeleton& s, const Tetrahedralization& tz, double reach,
                        std::vector<char>& keep, const Context* ctx) {
  const Capsules caps = capsules_of(s, reach);
  const detail::BoxBvh capsule_bvh(caps.boxes);
  const std::vector<Vec3>& pts = tz.points;
  parallel::for_chunks(
      tz.tets.size(), 4096,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t> ids;
        for (std::size_t t = begin; t < end; ++t) {
          const Tet& tet = tz.tets[t];
          const bool far = std::any_of(tet.begin(), tet.end(), [&](std::uint32_t v) {
            return v >= tz.real_points && v < tz.real_points + 8;  // the far box's corners
          });
          if (far) continue;
          const Vec3 c = 0.25 * (pts[tet[0]] + pts[tet[1]] + pts[tet[2]] + pts[tet[3]]);
          ids.clear();
          capsule_bvh.query(Aabb(c, c), ids);
          for (const std::uint32_t k : ids) {
            const auto& a = s.nodes[caps.nodes[k][0]];
            const auto& b = s.nodes[caps.nodes[k][1]];
            double u = 0;
            const double d = segment_distance(c, a.position, b.position, u);
            if (d <= reach * ((1 - u) * a.radius + u * b.radius)) {
              keep[t] = 1;
              break;
            }
          }
        }
      },
      ctx);
}

// The tetrahedron holding x, found by a visibility walk over face neighbours from tetrahedron
// t: step across a face with x strictly on its far side until there is none. kNone if the walk
// leaves the tetrahedralization or does not end.
std::uint32_t walk_to(const Tetrahedralization& tz, std::uint32_t t, const Vec3& x) {
  for (std::size_t step = 0; t != kNone && step < tz.tets.size(); ++step) {
    int beyond = -1;
    for (int k = 0; k < 4 && beyond < 0; ++k) {
      TetPoints c = tz.corners(t);
      const int inner = detail::orient3d(c[0], c[1], c[2], c[3]);
      c[k] = x;
      if (detail::orient3d(c[0], c[1], c[2], c[3]) == -inner) beyond = k;
    }
    if (beyond < 0) return t;
    t = tz.neighbors[4 * t + static_cast<std::size_t>(beyond)];
  }
  return kNone;
}

// Every node must lie in a kept tetrahedron. Its own point (jittered by a thousandth of the
// section) is a corner of the tetrahedra around it: keep those, and walk from one of them to
// the tetrahedron holding the node's exact position.
void mark_node_tetrahedra(const Skeleton& s, const Tetrahedralization& tz,
                          const std::vector<std::uint32_t>& node_points, std::vector<char>& keep) {
  std::vector<std::uint32_t> incident(tz.points.size(), kNone);
  for (std::uint32_t t = 0; t < tz.tets.size(); ++t) {
    for (const std::uint32_t v : tz.tets[t]) incident[v] = t;
  }
  std::vector<char> is_node(tz.points.size(), 0);
  for (const std::uint32_t i : node_points) is_node[i] = 1;
  for (std::size_t t = 0; t < tz.tets.size(); ++t) {
    for (const std::uint32_t v : tz.tets[t]) {
      if (is_node[v] != 0) keep[t] = 1;
    }
  }
  for (std::size_t i = 0; i < node_points.size(); ++i) {
    const std::uint32_t t = walk_to(tz, incident[node_points[i]], s.nodes[i].position);
    if (t != kNone) keep[t] = 1;
  }
}

}  // namespace

// Consecutive axis points must be joined by an edge: both are inside, so the lattice then
// joins them along the skeleton at every level and no branch can come apart, however coarse
// the lattice. A pair that is not an edge (another branch close by, or the squares of a bend)
// gets Steiner points on the axis until it is (measured: 36 of 8,698 pairs on the 1,500-segment
// benchmark tree, 551 of 7,856 on archi_Tree_1, which came apart into 62 pieces at level 0
// without them).
Tetrahedralization tetrahedralize(std::vector<Vec3> points, std::size_t real_points,
                                  const std::vector<std::array<std::uint32_t, 2>>& axis_pairs,
                                  const Context* ctx, TetrahedralStats& st) {
  DelaunayResult delaunay = delaunay_tetrahedralize(points, axis_pairs, ctx);
  if (delaunay.duplicate_points > 0) {
    throw Failure("tetrahedral polygonizer: " + std::to_string(delaunay.duplicate_points) +
                  " bounding points coincide");
  }
  Tetrahedralization tz;
  tz.points = std::move(points);
  tz.real_points = real_points;
  // Steiner points follow the far box's corners, which keep their numbers.
  tz.points.insert(tz.points.end(), delaunay.steiner_points.begin(), delaunay.steiner_points.end());
  st.axis_points_added = delaunay.steiner_points.size();
  st.axis_edges_missing = delaunay.missing_edges;
  tz.tets = std::move(delaunay.tets);
  tz.neighbors = std::move(delaunay.neighbors);
  st.delaunay_tets = tz.tets.size();
  return tz;
}

std::vector<char> initial_region(const Skeleton& s, const Tetrahedralization& tz,
                                 const std::vector<std::uint32_t>& node_points,
                                 const TetrahedralOptions& o, const Context* ctx) {
  const double reach = 0.5 * o.section_scale * std::sqrt(2.0) * 1.05;
  std::vector<char> keep(tz.tets.size(), 0);
  mark_near_skeleton(s, tz, reach, keep, ctx);
  mark_node_tetrahedra(s, tz, node_points, keep);
  return keep;
}

}  // namespace ramiform::detail::tets
