// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/particle_merge.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <unordered_map>
#include <utility>

#include "core/segment.h"
#include "core/union_find.h"
#include "ramiform/core/errors.h"

namespace ramiform::detail {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// A branch runs into a thicker edge g when a node of it (or its closest approach) lies inside
// g's tube (within R_g of its axis): it is then moved onto that axis, and stays inside the
// surface. Two alike branches (the same R) meet half way: one joins the other when within
// R_g + kReach R_own, where their tubes overlap.
constexpr double kReach = 1.0;
// g counts as another branch only when the skeleton leaves g's tube between them: no path from
// the branch's node to g's ends stays within R_g + kNear R_own of g's axis.
constexpr double kNear = 2.0;
// Joins on one edge closer than kCluster R_g become one junction; a join within kEndZone R_g of
// the edge's end goes to that end's node.
constexpr double kCluster = 2.0;
constexpr double kEndZone = 1.5;
// A node the mesh left outside (the mesher's repair) joins a thicker edge of another branch
// whose axis lies within kForceReach R_g of it.
constexpr double kForceReach = 3.0;
// With the field (ours): a node, or an edge's closest approach, beside a thicker edge g (outside
// its tube, but the tubes overlap: axes within R_g + R_own) joins g when their surfaces merge
// there broadly: the field is above kMerged times its iso value all along the segment between
// the two axes (at kBridgeSamples points evenly inside it). For two parallel lines of the
// equipotential radii mode, whose potential falls like r^-(alpha - 2), the least value between
// axes D apart is iso (D_m / D)^(alpha - 2), D_m = (R_g^(p/(p+1)) + R_own^(p/(p+1)))^((p+1)/p)
// with p = alpha - 2 the distance at which they start to merge; kMerged 2 asks for D <= 0.71
// D_m at alpha 4, which for alike radii is R_g + R_own (so overlapping tubes is implied there).
// Joins that touch the surface only by a thin neck (kMerged 1) folded more than they removed.
// Every join (but the repair's forced ones) then puts its joined node at the neck, the sample
// of least value along that segment, instead of on the thicker axis.
constexpr int kBridgeSamples = 8;
constexpr double kMerged = 2.0;

struct Segment {
  Vec3 a, b;
};

// A spatial hash of the edges' boxes (widened by twice their radius) in cubes of side h.
class EdgeGrid {
 public:
  EdgeGrid(const std::vector<Segment>& seg, const std::vector<double>& radius, double h)
      : h_(h) {
    for (std::size_t e = 0; e < seg.size(); ++e) {
      const double m = 2 * radius[e];
      const Vec3 lo = seg[e].a.cwiseMin(seg[e].b) - Vec3::Constant(m);
      const Vec3 hi = seg[e].a.cwiseMax(seg[e].b) + Vec3::Constant(m);
      for_cells(lo, hi, [&](std::uint64_t key) {
        cells_[key].push_back(static_cast<std::uint32_t>(e));
      });
    }
  }
  // Edges whose widened box may reach the box [lo, hi]; ascending, unique.
  std::vector<std::uint32_t> near(const Vec3& lo, const Vec3& hi) const {
    std::vector<std::uint32_t> out;
    for_cells(lo, hi, [&](std::uint64_t key) {
      const auto it = cells_.find(key);
      if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
    });
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  template <class F>
  void for_cells(const Vec3& lo, const Vec3& hi, F&& f) const {
    const auto cell = [&](double x) { return static_cast<std::int64_t>(std::floor(x / h_)); };
    for (std::int64_t i = cell(lo.x()); i <= cell(hi.x()); ++i) {
      for (std::int64_t j = cell(lo.y()); j <= cell(hi.y()); ++j) {
        for (std::int64_t k = cell(lo.z()); k <= cell(hi.z()); ++k) {
          f((static_cast<std::uint64_t>(i & 0x1fffff) << 42) |
            (static_cast<std::uint64_t>(j & 0x1fffff) << 21) |
            static_cast<std::uint64_t>(k & 0x1fffff));
        }
      }
    }
  }
  double h_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

struct Graph {
  std::vector<std::vector<std::uint32_t>> adjacent;  // per node, its neighbours
  std::vector<std::uint32_t> component;              // per node, its connected component
};

// Whether edge g is another branch for the sources (nodes of the branch that runs into g's
// tube): true unless the skeleton leads from a source to an end of g through nodes that all lie
// within `reach` of g's axis (a child leaving its parent's tube at a fork, a branch that runs on
// inside it, is reached so). An edge of another component of the skeleton is never one: the mesh
// keeps one piece per connected skeleton component, so two separate trees (or crossing branches
// that the skeleton does not connect) stay two pieces even where their surfaces merge.
bool another_branch(const Graph& graph, const Skeleton& s, const std::vector<Segment>& seg,
                    const std::vector<std::uint32_t>& sources, std::uint32_t g, double reach) {
  const std::array<std::uint32_t, 2> ends = s.edges[g];
  if (sources.empty() || graph.component[sources.front()] != graph.component[ends[0]]) {
    return false;
  }
  const auto inside = [&](std::uint32_t v) {
    const Vec3& p = s.nodes[v].position;
    const double t = segment_parameter(p, seg[g].a, seg[g].b);
    return (seg[g].a + t * (seg[g].b - seg[g].a) - p).norm() <= reach;
  };
  std::vector<std::uint32_t> stack;
  std::vector<std::uint32_t> seen;
  for (const std::uint32_t v : sources) {
    if (inside(v)) {
      stack.push_back(v);
      seen.push_back(v);
    }
  }
  while (!stack.empty()) {
    const std::uint32_t v = stack.back();
    stack.pop_back();
    if (v == ends[0] || v == ends[1]) return false;
    for (const std::uint32_t w : graph.adjacent[v]) {
      if (std::find(seen.begin(), seen.end(), w) != seen.end() || !inside(w)) continue;
      seen.push_back(w);
      stack.push_back(w);
    }
  }
  return true;
}

// A join: the point at parameter t of edge `target` takes node `source` (an original node, or
// a new node splitting a crossing edge).
struct Join {
  std::uint32_t target = 0;
  double t = 0;
  std::uint32_t source = 0;
  // With the field: the joined node goes to `place`, the neck between the two axes (before, the
  // joining point of the source's axis).
  bool at_neck = false;
  Vec3 place = Vec3::Zero();
};

}  // namespace

MergedSkeleton join_merging_branches(const Skeleton& skeleton,
                                     const std::vector<double>& edge_radius,
                                     const std::vector<double>& edge_spacing,
                                     const std::vector<std::uint8_t>& open_end,
                                     const std::vector<std::uint8_t>& force, const Field* field,
                                     const Context* ctx) {
  MergedSkeleton out;
  out.skeleton.nodes = skeleton.nodes;
  out.skeleton.edges = skeleton.edges;
  out.edge_radius = edge_radius;
  out.edge_spacing = edge_spacing;
  out.open_end = open_end;
  const Skeleton& s = skeleton;
  const std::size_t nodes = s.nodes.size();
  const std::size_t edges = s.edges.size();
  if (edges < 2) return out;

  std::vector<Segment> seg(edges);
  std::vector<double> node_r(nodes, 0.0);
  Graph graph;
  graph.adjacent.resize(nodes);
  {
    UnionFind component(static_cast<std::uint32_t>(nodes));
    for (const auto& [a, b] : s.edges) component.unite(a, b);
    graph.component.resize(nodes);
    for (std::uint32_t v = 0; v < nodes; ++v) graph.component[v] = component.find(v);
  }
  double max_r = 0;
  for (std::size_t e = 0; e < edges; ++e) {
    const auto [a, b] = s.edges[e];
    seg[e] = {s.nodes[a].position, s.nodes[b].position};
    graph.adjacent[a].push_back(b);
    graph.adjacent[b].push_back(a);
    node_r[a] = std::max(node_r[a], edge_radius[e]);
    node_r[b] = std::max(node_r[b], edge_radius[e]);
    max_r = std::max(max_r, edge_radius[e]);
  }
  const EdgeGrid grid(seg, edge_radius, 4 * max_r);
  // An open leaf keeps its loop: it is never joined, and a join is never put on it.
  const auto open_leaf = [&](std::uint32_t v) {
    return v < open_end.size() && open_end[v] != 0 && graph.adjacent[v].size() == 1;
  };

  // The thicker edge (not adjacent in the skeleton) that `p`, of own radius r, runs into:
  // the one reaching furthest over p, or kNone.
  // With `forced`, any thicker edge within kForceReach R_g counts (the nearest relative to R_g).
  const auto find_target = [&](const Vec3& p, double r, std::uint32_t skip_a, std::uint32_t skip_b,
                               const std::vector<std::uint32_t>& sources, bool forced,
                               double& t_out) {
    std::uint32_t best = kNone;
    double best_excess = 0;
    const Vec3 margin = Vec3::Constant(forced ? kForceReach * max_r : 0.0);
    for (const std::uint32_t g : grid.near(p - margin, p + margin)) {
      const auto [a, b] = s.edges[g];
      if (a == skip_a || a == skip_b || b == skip_a || b == skip_b) continue;
      const double rg = edge_radius[g];
      if (rg < r) continue;
      const double t = segment_parameter(p, seg[g].a, seg[g].b);
      const double d = (seg[g].a + t * (seg[g].b - seg[g].a) - p).norm();
      // > 0: p is within reach
      const double excess = forced ? kForceReach - d / rg : (rg == r ? rg + kReach * r : rg) - d;
      if (!(excess > best_excess)) continue;
      // (A forced node farther out than rg + kNear r is a source of the search all the same.)
      const double reach = std::max(rg, forced ? d : 0.0) + kNear * r;
      if (!another_branch(graph, s, seg, sources, g, reach)) continue;
      best = g;
      best_excess = excess;
      t_out = t;
    }
    return best;
  };

  std::vector<Join> joins;
  std::vector<std::uint8_t> joined(nodes, 0);
  for (std::uint32_t v = 0; v < nodes; ++v) {
    if (graph.adjacent[v].empty() || open_leaf(v)) continue;
    double t = 0;
    const std::uint8_t mode = force.empty() ? kJoinAsFound : force[v];
    if (mode == kJoinNever) continue;
    const bool forced = mode == kJoinNearby;
    const std::uint32_t g = find_target(s.nodes[v].position, node_r[v], v, v, {v}, forced, t);
    if (g == kNone) continue;
    joins.push_back({g, t, v, false, s.nodes[v].position});
    joined[v] = 1;
  }
  // Edges passing through a thicker tube between their nodes: split at the closest approach.
  struct Split {
    std::uint32_t edge;
    double s;
    std::uint32_t node;
  };
  std::vector<Split> splits;
  std::uint32_t next_node = static_cast<std::uint32_t>(nodes);
  for (std::uint32_t e = 0; e < edges; ++e) {
    const auto [u, w] = s.edges[e];
    if (joined[u] != 0 || joined[w] != 0) continue;
    const double re = edge_radius[e];
    const double length = (seg[e].b - seg[e].a).norm();
    const Vec3 lo = seg[e].a.cwiseMin(seg[e].b);
    const Vec3 hi = seg[e].a.cwiseMax(seg[e].b);
    std::uint32_t best = kNone;
    double best_excess = 0, best_s = 0, best_t = 0;
    for (const std::uint32_t g : grid.near(lo, hi)) {
      const auto [a, b] = s.edges[g];
      if (a == u || a == w || b == u || b == w) continue;
      const double rg = edge_radius[g];
      if (rg < re || (rg == re && g > e)) continue;  // of two alike, the first takes the other
      const auto [ps, pt] = closest_parameters(seg[e].a, seg[e].b, seg[g].a, seg[g].b);
      // Near a node of e, the node's own test decides.
      if (ps * length < rg + re || (1 - ps) * length < rg + re) continue;
      const Vec3 p = seg[e].a + ps * (seg[e].b - seg[e].a);
      const double d = (seg[g].a + pt * (seg[g].b - seg[g].a) - p).norm();
      const double excess = (rg == re ? rg + kReach * re : rg) - d;
      if (!(excess > best_excess)) continue;
      if (!another_branch(graph, s, seg, {u, w}, g, rg + kNear * re)) continue;
      best = g;
      best_excess = excess;
      best_s = ps;
      best_t = pt;
    }
    if (best == kNone) continue;
    splits.push_back({e, best_s, next_node});
    joins.push_back({best, best_t, next_node, false, seg[e].a + best_s * (seg[e].b - seg[e].a)});
    ++next_node;
  }

  // With the field: the place of each join, and joins beside the thicker tube.
  if (field != nullptr) {
    // A bridge: the segment from a point of the joining branch's axis to the nearest point of
    // the thicker axis (`target` at t).
    struct Bridge {
      std::uint32_t source;  // a node, an edge, or a join (an index into `joins`)
      std::uint32_t target;
      double s, t;  // parameters on the source edge (edges only) and on the target
      Vec3 from, to;
      double least = 0;          // the least field value along it
      Vec3 neck = Vec3::Zero();  // where it is least
    };
    // The least field value along each bridge and where it is, all in one batch.
    const auto measure = [&](std::vector<Bridge>& bridges) {
      std::vector<Vec3> points;
      points.reserve(bridges.size() * kBridgeSamples);
      for (const Bridge& b : bridges) {
        for (int k = 1; k <= kBridgeSamples; ++k) {
          const double u = static_cast<double>(k) / (kBridgeSamples + 1);
          points.push_back(b.from + u * (b.to - b.from));
        }
      }
      std::vector<double> values(points.size());
      field->evaluate(points, values, {}, ctx);
      for (std::size_t i = 0; i < bridges.size(); ++i) {
        const auto first = values.begin() + static_cast<std::ptrdiff_t>(i * kBridgeSamples);
        const auto least = std::min_element(first, first + kBridgeSamples);
        bridges[i].least = *least;
        bridges[i].neck = points[i * kBridgeSamples + static_cast<std::size_t>(least - first)];
      }
    };
    // Per source (bridges grouped by source), the merged bridge with the largest least value;
    // calls take(bridge) for it.
    const auto choose = [&](std::vector<Bridge>& bridges, auto&& take) {
      measure(bridges);
      for (std::size_t i = 0; i < bridges.size();) {
        std::size_t best = bridges.size();
        std::size_t j = i;
        for (; j < bridges.size() && bridges[j].source == bridges[i].source; ++j) {
          if (!(bridges[j].least > kMerged * field->iso())) continue;
          if (best == bridges.size() || bridges[j].least > bridges[best].least) best = j;
        }
        if (best != bridges.size()) take(bridges[best]);
        i = j;
      }
    };

    // The joins into the tube take their necks (the repair's forced ones keep the axis).
    {
      std::vector<Bridge> bridges;
      for (std::uint32_t k = 0; k < joins.size(); ++k) {
        const Join& j = joins[k];
        if (j.source < nodes && !force.empty() && force[j.source] == kJoinNearby) continue;
        const Vec3 q = seg[j.target].a + j.t * (seg[j.target].b - seg[j.target].a);
        bridges.push_back({k, j.target, 0, j.t, j.place, q});
      }
      measure(bridges);
      for (const Bridge& b : bridges) {
        joins[b.source].at_neck = true;
        joins[b.source].place = b.neck;
      }
    }

    // Nodes beside a thicker tube.
    std::vector<Bridge> bridges;
    for (std::uint32_t v = 0; v < nodes; ++v) {
      if (graph.adjacent[v].empty() || joined[v] != 0 || open_leaf(v)) continue;
      if (!force.empty() && force[v] == kJoinNever) continue;
      const Vec3& p = s.nodes[v].position;
      const double r = node_r[v];
      const Vec3 margin = Vec3::Constant(max_r + r);
      for (const std::uint32_t g : grid.near(p - margin, p + margin)) {
        const auto [a, b] = s.edges[g];
        if (a == v || b == v) continue;
        const double rg = edge_radius[g];
        if (rg < r) continue;
        const double t = segment_parameter(p, seg[g].a, seg[g].b);
        const Vec3 q = seg[g].a + t * (seg[g].b - seg[g].a);
        const double d = (q - p).norm();
        if (d > rg + r) continue;
        if (!another_branch(graph, s, seg, {v}, g, std::max(rg, d) + kNear * r)) continue;
        bridges.push_back({v, g, 0, t, p, q});
      }
    }
    choose(bridges, [&](const Bridge& b) {
      joins.push_back({b.target, b.t, b.source, true, b.neck});
      joined[b.source] = 1;
    });

    // Edges beside a thicker tube (none of whose nodes is joined, and not split yet).
    bridges.clear();
    std::vector<std::uint8_t> split(edges, 0);
    for (const Split& sp : splits) split[sp.edge] = 1;
    for (std::uint32_t e = 0; e < edges; ++e) {
      const auto [u, w] = s.edges[e];
      if (split[e] != 0 || joined[u] != 0 || joined[w] != 0) continue;
      const double re = edge_radius[e];
      const double length = (seg[e].b - seg[e].a).norm();
      const Vec3 margin = Vec3::Constant(max_r + re);
      const Vec3 lo = seg[e].a.cwiseMin(seg[e].b) - margin;
      const Vec3 hi = seg[e].a.cwiseMax(seg[e].b) + margin;
      for (const std::uint32_t g : grid.near(lo, hi)) {
        const auto [a, b] = s.edges[g];
        if (a == u || a == w || b == u || b == w) continue;
        const double rg = edge_radius[g];
        if (rg < re || (rg == re && g > e)) continue;
        const auto [ps, pt] = closest_parameters(seg[e].a, seg[e].b, seg[g].a, seg[g].b);
        if (ps * length < rg + re || (1 - ps) * length < rg + re) continue;  // the node's test
        const Vec3 p = seg[e].a + ps * (seg[e].b - seg[e].a);
        const Vec3 q = seg[g].a + pt * (seg[g].b - seg[g].a);
        const double d = (q - p).norm();
        if (d > rg + re) continue;
        if (!another_branch(graph, s, seg, {u, w}, g, std::max(rg, d) + kNear * re)) continue;
        bridges.push_back({e, g, ps, pt, p, q});
      }
    }
    choose(bridges, [&](const Bridge& b) {
      splits.push_back({b.source, b.s, next_node});
      joins.push_back({b.target, b.t, next_node, true, b.neck});
      ++next_node;
    });
  }
  // Neurites that start on a soma: a node without edges is a sphere of its radius (as the SWC
  // reader makes a soma). Per other component, the node nearest its centre whose tube reaches
  // the sphere (centre distance at most R + its own R, and thinner than the sphere) joins it:
  // the class lies at the soma's centre, and the layout makes it a junction with the soma's
  // sphere (`node_sphere`), so the soma and its neurites are one piece instead of a sphere the
  // neurites' tubes run into.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> soma_links;  // neurite node, soma
  if (std::any_of(graph.adjacent.begin(), graph.adjacent.end(),
                  [](const auto& a) { return a.empty(); })) {
    UnionFind component(static_cast<std::uint32_t>(nodes));
    for (const auto& [a, b] : s.edges) component.unite(a, b);
    for (std::uint32_t c = 0; c < nodes; ++c) {
      if (!graph.adjacent[c].empty()) continue;
      const Vec3& centre = s.nodes[c].position;
      const double radius = s.nodes[c].radius;
      // Per component: (distance, node), the nearest (the first among equals).
      std::vector<std::pair<std::uint32_t, std::pair<double, std::uint32_t>>> nearest;
      const Vec3 margin = Vec3::Constant(radius + max_r);
      for (const std::uint32_t g : grid.near(centre - margin, centre + margin)) {
        for (const std::uint32_t v : s.edges[g]) {
          const double d = (s.nodes[v].position - centre).norm();
          if (!(d <= radius + node_r[v]) || !(node_r[v] < radius)) continue;
          const std::uint32_t k = component.find(v);
          const auto it = std::find_if(nearest.begin(), nearest.end(),
                                       [&](const auto& x) { return x.first == k; });
          if (it == nearest.end()) {
            nearest.push_back({k, {d, v}});
          } else if (std::pair(d, v) < it->second) {
            it->second = {d, v};
          }
        }
      }
      std::sort(nearest.begin(), nearest.end());
      for (const auto& [k, dv] : nearest) {
        // (The repair's kJoinNever: a neurite whose node the joined layout left outside keeps
        // its own cap inside the soma's sphere.)
        if (!force.empty() && force[dv.second] == kJoinNever) continue;
        soma_links.emplace_back(dv.second, c);
      }
    }
  }
  if (joins.empty() && soma_links.empty()) return out;

  // New nodes: first the crossing splits' (already numbered), then the targets' points.
  std::vector<SkeletonNode> new_nodes;
  std::vector<double> new_r;  // the radius of the edge each new node lies on
  for (const Split& sp : splits) {
    const auto [u, w] = s.edges[sp.edge];
    new_nodes.push_back({seg[sp.edge].a + sp.s * (seg[sp.edge].b - seg[sp.edge].a),
                         (1 - sp.s) * s.nodes[u].radius + sp.s * s.nodes[w].radius});
    new_r.push_back(edge_radius[sp.edge]);
  }
  // Per edge, its inner points (parameter, node) after all joins.
  std::vector<std::vector<std::pair<double, std::uint32_t>>> inner(edges);
  for (const Split& sp : splits) inner[sp.edge].emplace_back(sp.s, sp.node);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> unite;  // source, target node
  // Per pair of `unite`, its join.
  std::vector<const Join*> unite_join;
  std::sort(joins.begin(), joins.end(), [](const Join& x, const Join& y) {
    return x.target != y.target ? x.target < y.target
                                : (x.t != y.t ? x.t < y.t : x.source < y.source);
  });
  for (std::size_t i = 0; i < joins.size();) {
    const std::uint32_t g = joins[i].target;
    const double length = (seg[g].b - seg[g].a).norm();
    const double rg = edge_radius[g];
    std::size_t j = i;
    double sum = 0;
    while (j < joins.size() && joins[j].target == g &&
           (joins[j].t - joins[i].t) * length < kCluster * rg) {
      sum += joins[j].t;
      ++j;
    }
    const double t = sum / static_cast<double>(j - i);
    std::uint32_t point;
    if (t * length < kEndZone * rg) {
      point = s.edges[g][0];
    } else if ((1 - t) * length < kEndZone * rg) {
      point = s.edges[g][1];
    } else {
      point = kNone;
    }
    if (point != kNone && open_leaf(point)) {
      i = j;  // (these joins are left out: the branches stay apart)
      continue;
    }
    if (point == kNone) {
      point = next_node++;
      const auto [a, b] = s.edges[g];
      new_nodes.push_back({seg[g].a + t * (seg[g].b - seg[g].a),
                           (1 - t) * s.nodes[a].radius + t * s.nodes[b].radius});
      new_r.push_back(rg);
      inner[g].emplace_back(t, point);
    }
    for (std::size_t k = i; k < j; ++k) {
      unite.emplace_back(joins[k].source, point);
      unite_join.push_back(&joins[k]);
    }
    i = j;
  }

  // All nodes (old, then new), classes of joined nodes, each placed at its thickest member.
  std::vector<SkeletonNode> all = s.nodes;
  all.insert(all.end(), new_nodes.begin(), new_nodes.end());
  std::vector<double> weight = node_r;
  weight.insert(weight.end(), new_r.begin(), new_r.end());
  for (const auto& [v, c] : soma_links) weight[c] = s.nodes[c].radius;
  std::vector<std::uint8_t> open(all.size(), 0);
  for (std::size_t v = 0; v < open_end.size(); ++v) open[v] = open_end[v];
  UnionFind uf(all.size());
  for (const auto& [a, b] : unite) uf.unite(a, b);
  for (const auto& [v, c] : soma_links) uf.unite(v, c);

  // Edges: each original edge as the chain through its inner points.
  struct Piece {
    std::uint32_t a, b, edge;
  };
  std::vector<Piece> pieces;
  for (std::uint32_t e = 0; e < edges; ++e) {
    auto& points = inner[e];
    std::sort(points.begin(), points.end());
    std::uint32_t prev = s.edges[e][0];
    for (const auto& [t, v] : points) {
      pieces.push_back({prev, v, e});
      prev = v;
    }
    pieces.push_back({prev, s.edges[e][1], e});
  }
  // Pieces too short for the layout (their ends joined to points next to each other): their
  // ends become one node, until none is left.
  const auto representatives = [&] {
    std::vector<std::uint32_t> rep(all.size(), kNone);
    for (std::uint32_t v = 0; v < all.size(); ++v) {
      const std::uint32_t root = uf.find(v);
      if (rep[root] == kNone || weight[v] > weight[rep[root]]) rep[root] = v;
    }
    return rep;
  };
  for (;;) {
    const std::vector<std::uint32_t> rep = representatives();
    bool changed = false;
    for (const Piece& p : pieces) {
      const std::uint32_t a = uf.find(p.a);
      const std::uint32_t b = uf.find(p.b);
      if (a == b) continue;
      if ((all[rep[a]].position - all[rep[b]].position).norm() < 0.05 * edge_radius[p.edge]) {
        uf.unite(a, b);
        changed = true;
      }
    }
    if (!changed) break;
  }

  // Compact: one node per class, at its thickest member (the first among equals).
  const std::vector<std::uint32_t> rep = representatives();
  std::vector<std::uint8_t> joined_class(all.size(), 0);
  for (const auto& [source, target] : unite) joined_class[uf.find(source)] = 1;
  // (A soma's neurites start at its sphere with their own radii.)
  for (const auto& [v, c] : soma_links) joined_class[uf.find(c)] = 0;
  std::vector<std::uint32_t> index(all.size(), kNone);
  Skeleton merged;
  std::vector<std::uint8_t> merged_open;
  std::vector<int> ties;
  for (std::uint32_t v = 0; v < all.size(); ++v) {
    const std::uint32_t root = uf.find(v);
    if (index[root] == kNone) {
      index[root] = static_cast<std::uint32_t>(merged.nodes.size());
      merged.nodes.push_back({Vec3::Zero(), all[rep[root]].radius});
      merged_open.push_back(0);
      ties.push_back(0);
    }
    const std::uint32_t i = index[root];
    merged_open[i] |= open[v];
    // At the thickest member's place; between several equally thick ones (two alike branches
    // that run side by side), at their mean.
    if (weight[v] == weight[rep[root]]) {
      merged.nodes[i].position += all[v].position;
      ++ties[i];
    }
  }
  for (std::size_t i = 0; i < merged.nodes.size(); ++i) {
    merged.nodes[i].position /= static_cast<double>(ties[i]);
  }
  // With the field, a class whose joins all have necks lies at their mean, between the axes,
  // so that the junction's sphere and the rings of both branches around it enclose the merged
  // surface's waist (on the thicker axis, the rings of a thinner branch beside it would start
  // on the far side of its own axis). A class with a forced join, or with a node marked
  // kJoinNever, stays at its thickest member.
  {
    std::vector<std::uint32_t> on_axis(merged.nodes.size(), 0);
    std::vector<std::uint32_t> at_necks(merged.nodes.size(), 0);
    std::vector<Vec3> necks(merged.nodes.size(), Vec3::Zero());
    for (std::size_t k = 0; k < unite.size(); ++k) {
      const std::uint32_t i = index[uf.find(unite[k].first)];
      if (unite_join[k]->at_neck) {
        ++at_necks[i];
        necks[i] += unite_join[k]->place;
      } else {
        ++on_axis[i];
      }
    }
    for (std::uint32_t v = 0; v < force.size(); ++v) {
      if (force[v] == kJoinNever) ++on_axis[index[uf.find(v)]];
    }
    for (const auto& [v, c] : soma_links) ++on_axis[index[uf.find(c)]];  // a soma stays put
    for (std::size_t i = 0; i < merged.nodes.size(); ++i) {
      if (at_necks[i] != 0 && on_axis[i] == 0) {
        merged.nodes[i].position = necks[i] / static_cast<double>(at_necks[i]);
      }
    }
  }
  // Edges in the order of the pieces, without self-loops and repeats.
  MergedSkeleton result;
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  for (const Piece& p : pieces) {
    const std::uint32_t a = index[uf.find(p.a)];
    const std::uint32_t b = index[uf.find(p.b)];
    if (a == b || !seen.insert({std::min(a, b), std::max(a, b)}).second) continue;
    // A thinner branch's piece that ends in a join starts from the thicker tube, as a child
    // does at a fork: its placement radius is the mean of the two, as R is the mean of an
    // edge's node radii there, so that its rings start outside the blend.
    double r = edge_radius[p.edge];
    for (const std::uint32_t end : {p.a, p.b}) {
      const std::uint32_t root = uf.find(end);
      if (joined_class[root] != 0 && weight[rep[root]] > edge_radius[p.edge]) {
        r = std::max(r, 0.5 * (edge_radius[p.edge] + weight[rep[root]]));
      }
    }
    result.skeleton.edges.push_back({a, b});
    result.edge_radius.push_back(r);
    result.edge_spacing.push_back(edge_spacing[p.edge]);
  }
  result.moved.assign(nodes, 0);
  for (std::uint32_t v = 0; v < nodes; ++v) {
    result.moved[v] = merged.nodes[index[uf.find(v)]].position != s.nodes[v].position ? 1 : 0;
  }
  if (!soma_links.empty()) {
    result.node_sphere.assign(merged.nodes.size(), 0.0);
    for (const auto& [v, c] : soma_links) {
      result.node_sphere[index[uf.find(c)]] = s.nodes[c].radius;
    }
  }
  result.skeleton.nodes = std::move(merged.nodes);
  if (!open_end.empty()) result.open_end = std::move(merged_open);
  const auto links = static_cast<long long>(nodes + result.skeleton.edges.size()) -
                     static_cast<long long>(result.skeleton.nodes.size() + edges);
  result.joins = static_cast<std::size_t>(std::max(0LL, links));
  try {
    validate(result.skeleton);
  } catch (const InputError&) {
    return out;  // a join the layout could not take: keep the skeleton's own connectivity
  }
  return result;
}

}  // namespace ramiform::detail
