// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/tetrahedral_points.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <queue>

#include "core/segment.h"
#include "field/bvh.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/random.h"

namespace ramiform::detail::tets {
namespace {

using Adjacency = std::vector<std::vector<std::uint32_t>>;

// Two unit vectors completing d to an orthonormal frame.
void frame(const Vec3& d, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(d.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = d.cross(helper).normalized();
  e2 = d.cross(e1).normalized();
}

void add(BoundingPoints& pb, const Vec3& p, double half) {
  pb.points.push_back(p);
  pb.sizes.push_back(half);
}

void add_square(BoundingPoints& pb, const Vec3& c, const Vec3& d, double half) {
  Vec3 e1, e2;
  frame(d, e1, e2);
  for (const double a : {-1.0, 1.0}) {
    for (const double b : {-1.0, 1.0}) add(pb, c + half * (a * e1 + b * e2), half);
  }
}

Adjacency adjacency(const Skeleton& s) {
  Adjacency adjacent(s.nodes.size());
  for (const auto& e : s.edges) {
    adjacent[e[0]].push_back(e[1]);
    adjacent[e[1]].push_back(e[0]);
  }
  return adjacent;
}

// Which nodes get a cross-section. Forks, tips and isolated nodes always do; along a chain of
// degree-2 nodes (scanned cylinder models have many short cylinders) a node is skipped while it
// lies within `station_spacing` radii of the last section, the chain bends by less than
// kMaxBendDeg and the radius changes by less than kMaxRadiusChange since it. Closely packed
// sections would only make many small tetrahedra, each subdivided as finely as a big one.
constexpr double kMaxBendDeg = 25.0;
constexpr double kMaxRadiusChange = 0.25;
std::vector<char> section_nodes(const Skeleton& s, const Adjacency& adjacent,
                                const TetrahedralOptions& o) {
  const std::size_t n = s.nodes.size();
  std::vector<char> section(n, 1);
  std::vector<char> visited(n, 0);
  const double cos_bend = pm::cos(kMaxBendDeg * std::numbers::pi / 180.0);
  for (std::uint32_t i = 0; i < n; ++i) {
    if (adjacent[i].size() == 2) continue;
    for (const std::uint32_t first : adjacent[i]) {
      std::uint32_t prev = i, cur = first, kept = i;
      while (adjacent[cur].size() == 2 && visited[cur] == 0) {
        visited[cur] = 1;
        const std::uint32_t next = adjacent[cur][0] == prev ? adjacent[cur][1] : adjacent[cur][0];
        const auto& nk = s.nodes[kept];
        const auto& nc = s.nodes[cur];
        const Vec3 along = nc.position - nk.position;
        const Vec3 ahead = s.nodes[next].position - nc.position;
        const double r = std::min(nk.radius, nc.radius);
        const bool near = along.norm() < o.station_spacing * r;
        const bool straight = along.dot(ahead) >= cos_bend * along.norm() * ahead.norm();
        const bool even =
            std::abs(nc.radius - nk.radius) <= kMaxRadiusChange * std::max(nk.radius, nc.radius);
        if (near && straight && even) {
          section[cur] = 0;
        } else {
          kept = cur;
        }
        prev = cur;
        cur = next;
      }
    }
  }
  return section;
}

// §5: an auxiliary point on each side of the plane of every pair of branches at the fork p, at
// the mean length of the two edges (capped at the section size).
//
// Crotch points (ours): where two branches leave the fork at less than kCrotchDeg, the surface
// dips into the V between them in a saddle whose concave radius is a fraction of the branch
// radius. The Delaunay tetrahedra there span from the fork's section to the first stations of
// both branches, so the level-1 lattice crosses the crotch with edges a branch radius long; the
// refinement's splits there fold against the coarse triangles and are left off the surface
// (0.3-0.8 radii outside: the largest deviations of generated trees, at 1.4-1.9 radii from both
// axes). So three points go where the two tubes meet on the bisector, r / sin(theta / 2) from
// the fork (at most 0.8 of the shorter edge), one on the bisector and one half a radius to each
// side of the branches' plane: +3-4 % triangles on generated trees. (The bisector point alone
// left a crotch at 0.66 radii; five points, a cross, or three along the bisector at 0.7, 1 and
// 1.4 of the distance, gave no smaller maxima for 8-10 % more triangles.)
constexpr double kCrotchDeg = 110.0;
void add_fork_points(BoundingPoints& pb, const Skeleton& s, const std::vector<std::uint32_t>& adj,
                     const Vec3& p, double radius, double half, bool crotch) {
  const double cos_crotch = pm::cos(kCrotchDeg * std::numbers::pi / 180.0);
  for (std::size_t a = 0; a < adj.size(); ++a) {
    for (std::size_t b = a + 1; b < adj.size(); ++b) {
      const Vec3 ua = s.nodes[adj[a]].position - p;
      const Vec3 ub = s.nodes[adj[b]].position - p;
      const Vec3 nrm = ua.cross(ub);
      if (nrm.norm() <= 1e-12 * ua.norm() * ub.norm()) continue;
      const double len = std::min(0.5 * (ua.norm() + ub.norm()), 2 * half);
      const Vec3 side = nrm.normalized();
      add(pb, p + len * side, half);
      add(pb, p - len * side, half);
      const Vec3 da = ua.normalized();
      const Vec3 db = ub.normalized();
      const double cos_ab = da.dot(db);
      if (!crotch || !(cos_ab > cos_crotch)) continue;
      // sin(theta / 2) from the half-angle identity; the cross product above is not zero, so
      // theta > 0.
      const double sin_half = std::sqrt(0.5 * (1.0 - cos_ab));
      const double reach =
          std::min(radius / std::max(sin_half, 1e-12), 0.8 * std::min(ua.norm(), ub.norm()));
      const Vec3 meet = p + reach * (da + db).normalized();
      add(pb, meet, half);
      add(pb, meet + 0.5 * radius * side, half);
      add(pb, meet - 0.5 * radius * side, half);
      pb.crotch_points += 3;
    }
  }
}

// The cross-section of node i with half size `half`: a cube around an isolated node; otherwise
// a square across the mean direction of its edges, with a second square and a cap beyond a tip
// and the auxiliary points around a fork.
void add_node_section(BoundingPoints& pb, const Skeleton& s, const Adjacency& adjacent,
                      std::uint32_t i, double half, bool crotch) {
  const Vec3& p = s.nodes[i].position;
  const auto& adj = adjacent[i];
  if (adj.empty()) {
    for (int c = 0; c < 8; ++c) {
      add(pb, p + half * Vec3((c & 1) ? 1 : -1, (c & 2) ? 1 : -1, (c & 4) ? 1 : -1), half);
    }
    return;
  }
  // Section direction: incident edge directions aligned with the first one, summed.
  const Vec3 u0 = (s.nodes[adj[0]].position - p).normalized();
  Vec3 d = Vec3::Zero();
  for (const std::uint32_t j : adj) {
    const Vec3 u = (s.nodes[j].position - p).normalized();
    d += u.dot(u0) >= 0 ? u : Vec3(-u);
  }
  d = d.norm() > 1e-12 ? Vec3(d.normalized()) : u0;
  add_square(pb, p, d, half);
  if (adj.size() == 1) {
    const Vec3 out = -u0;
    add_square(pb, p + out * half, out, half);
    add(pb, p + out * (2 * half), half);
  }
  if (adj.size() >= 3) add_fork_points(pb, s, adj, p, s.nodes[i].radius, half, crotch);
}

// Intermediate stations along long edges, each a square and its centre on the skeleton, and
// the axis pairs that join the centres from node to node.
void add_edge_stations(BoundingPoints& pb, const Skeleton& s, const TetrahedralOptions& o) {
  const double half_scale = 0.5 * o.section_scale;
  for (const auto& e : s.edges) {
    const auto& na = s.nodes[e[0]];
    const auto& nb = s.nodes[e[1]];
    const Vec3 d = nb.position - na.position;
    const double len = d.norm();
    const double r_mean = 0.5 * (na.radius + nb.radius);
    const int stations = static_cast<int>(std::ceil(len / (o.station_spacing * r_mean))) - 1;
    std::uint32_t axis = pb.node_points[e[0]];
    for (int k = 1; k <= stations; ++k) {
      const double t = static_cast<double>(k) / (stations + 1);
      const double half = half_scale * ((1 - t) * na.radius + t * nb.radius);
      add_square(pb, na.position + t * d, d / len, half);
      add(pb, na.position + t * d, half);
      const auto centre = static_cast<std::uint32_t>(pb.points.size() - 1);
      pb.axis_pairs.push_back({axis, centre});
      axis = centre;
    }
    pb.axis_pairs.push_back({axis, pb.node_points[e[1]]});
  }
}

// Points in the narrow gaps between branches the skeleton does not join. Where two edges that
// share no node pass close to each other's tube (a twig's tip or side beside another branch),
// the level-1 lattice has tetrahedron edges from inside the one tube to inside the other that
// meet no root, and the mesh bridges the gap with a handle the surface does not have (its
// vertices 1-3 twig radii off the surface: the largest deviations of generated trees). So
// along the thinner edge, at stations three of its radii apart, wherever the gap between the
// tubes (axis distance less both radii) is open but narrower than kGapRadii thinner radii or
// kGapThick thicker ones (the thick branch's lattice is coarse), five points are placed across
// the gap half way: a cross spaced by the thinner radius or half the gap, whichever is more;
// a cross centred within one radius of an earlier one of the same scale is left out. (One
// point per station left a bridge on one of four trees; a 3 x 3 grid gave no smaller deviations
// than the cross for twice its extra triangles, 6 % instead of 3 %.)
constexpr double kGapRadii = 3.0;
constexpr double kGapThick = 1.5;
constexpr int kGapMaxStations = 64;
// Stations this many thinner radii apart; a cross within kGapApart times its radius of an
// earlier one of the same scale is left out. (2 and 0.5 placed twice the points, 80 k on a
// 10,000-segment tree, for 11 % more triangles instead of 6 % and no smaller deviations. 1.5
// instead of 1 left out the cross at the narrowest spot where a twig passes the fork of another
// branch: the crosses towards the fork's outgoing edges lay 1.2 radii from it, and the lattice
// joined twig and fork by a handle.)
constexpr double kGapStation = 3.0;
constexpr double kGapApart = 1.0;
// Edges closer than this many times the sum of their largest radii along the skeleton are one
// branch, not two.
constexpr double kGapPath = 4.0;
// Field samples across a gap, its middle among them (an odd number).
constexpr int kGapSamples = 13;
// Edges per parallel task of the gap search.
constexpr std::size_t kGapGrain = 512;

// A lower bound of the distance between the segments p0p1 and q0q1: their exact distance
// (Ericson 2005, "Real-Time Collision Detection", §5.1.9) where the segments are far from
// parallel, else the distance from the middle of p0p1 to q0q1 less its half length (whose
// error does not grow as the segments turn parallel).
double segment_distance_below(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 mid = 0.5 * (p0 + p1);
  const double half = 0.5 * (p1 - p0).norm();
  const double coarse = (mid - (q0 + segment_parameter(mid, q0, q1) * (q1 - q0))).norm() - half;
  const Vec3 d1 = p1 - p0, d2 = q1 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), b = d1.dot(d2);
  if (!(a * e - b * b > 1e-6 * a * e))
    return coarse;  // parallel within 0.06 degrees, or degenerate
  const auto [sp, tq] = closest_parameters(p0, p1, q0, q1);
  return std::max(coarse, ((p0 + sp * d1) - (q0 + tq * d2)).norm());
}

void add_gap_points(BoundingPoints& pb, const Skeleton& s, const Adjacency& adjacent,
                    const TetrahedralOptions& o, const Field* field, const Context* ctx) {
  const std::size_t ne = s.edges.size();
  if (ne < 2) return;
  auto radius_at = [&](std::size_t e, double t) {
    return (1 - t) * s.nodes[s.edges[e][0]].radius + t * s.nodes[s.edges[e][1]].radius;
  };
  auto rmax = [&](std::size_t e) {
    return std::max(s.nodes[s.edges[e][0]].radius, s.nodes[s.edges[e][1]].radius);
  };
  std::vector<Aabb> boxes(ne);
  for (std::size_t e = 0; e < ne; ++e) {
    const Vec3& a = s.nodes[s.edges[e][0]].position;
    const Vec3& b = s.nodes[s.edges[e][1]].position;
    boxes[e] = Aabb(a.cwiseMin(b), a.cwiseMax(b));
    boxes[e].min().array() -= (1 + kGapRadii) * rmax(e);
    boxes[e].max().array() += (1 + kGapRadii) * rmax(e);
  }
  const BoxBvh bvh(boxes);
  std::map<std::array<std::int64_t, 4>, std::vector<Vec3>> placed;
  auto place = [&](const Vec3& mid, const Vec3& dir, double r, double gap) {
    const int level = static_cast<int>(std::floor(std::log2(r)));
    const double cell = std::ldexp(1.0, level);
    const Vec3 at = (mid / cell).array().floor();
    // (A cell index beyond 2^60 — a radius far below the model's extent — cannot key the table;
    // such a gap is left without points.)
    if (!(at.cwiseAbs().maxCoeff() < 0x1p60)) return;
    const std::array<std::int64_t, 4> key{level, static_cast<std::int64_t>(at.x()),
                                          static_cast<std::int64_t>(at.y()),
                                          static_cast<std::int64_t>(at.z())};
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = placed.find({key[0], key[1] + dx, key[2] + dy, key[3] + dz});
          if (it == placed.end()) continue;
          for (const Vec3& c : it->second)
            if ((c - mid).norm() < kGapApart * r) return;
        }
    placed[key].push_back(mid);
    pb.gap_points += 5;
    Vec3 e1, e2;
    frame(dir, e1, e2);
    const double step = std::max(r, 0.5 * gap);
    const double half = 0.5 * o.section_scale * r;
    add(pb, mid, half);
    for (const Vec3& side : {e1, e2}) {
      add(pb, mid + step * side, half);
      add(pb, mid - step * side, half);
    }
  };
  // The shortest paths along the skeleton from the nearer of a0 and a1 to every node within
  // `limit` of them (a Dijkstra search cut there) into `dist`, the nodes reached into `seen`
  // (`dist` all infinity on entry outside `seen`; forget() restores it). Searched once per
  // edge and reused for each of its pairs (again with a longer limit when a pair needs one):
  // a distance within a limit is the same whatever longer limit the search had, as no path
  // through a node beyond it comes back shorter. (One search per pair, cut at the pair's other
  // end, was most of step 1 at 100,000 generated segments, where a thick branch has thousands
  // of twigs beside it.)
  auto search_from = [&](std::uint32_t a0, std::uint32_t a1, double limit,
                         std::vector<double>& dist, std::vector<std::uint32_t>& seen) {
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (const std::uint32_t a : {a0, a1}) {
      dist[a] = 0;
      seen.push_back(a);
      queue.emplace(0.0, a);
    }
    while (!queue.empty()) {
      const auto [d, n] = queue.top();
      queue.pop();
      if (d > dist[n]) continue;
      for (const std::uint32_t m : adjacent[n]) {
        const double dm = d + (s.nodes[m].position - s.nodes[n].position).norm();
        if (dm > limit || dm >= dist[m]) continue;
        if (std::isinf(dist[m])) seen.push_back(m);
        dist[m] = dm;
        queue.emplace(dm, m);
      }
    }
  };
  auto forget = [](std::vector<double>& dist, std::vector<std::uint32_t>& seen) {
    for (const std::uint32_t n : seen) dist[n] = std::numeric_limits<double>::infinity();
    seen.clear();
  };
  // The crosses to place, found per edge in parallel (chunks of kGapGrain edges, each its
  // requests in the order of the sequential scan), then placed one after the other in edge
  // order, so the set does not depend on the thread count.
  struct Request {
    Vec3 mid, dir;
    double r, gap;
  };
  const std::size_t chunks = (ne + kGapGrain - 1) / kGapGrain;
  std::vector<std::vector<Request>> requests(chunks);
  parallel::for_chunks(
      ne, kGapGrain,
      [&](std::size_t begin, std::size_t end) {
        std::vector<Request>& out = requests[begin / kGapGrain];
        // The path search's distances, all infinity between searches (per thread: a skeleton's
        // worth of doubles per chunk would cost more than the search).
        thread_local std::vector<double> dist;
        if (dist.size() != s.nodes.size())
          dist.assign(s.nodes.size(), std::numeric_limits<double>::infinity());
        std::vector<std::uint32_t> seen, ids;
        std::vector<Request> pending;
        for (auto e = static_cast<std::uint32_t>(begin); e < end; ++e) {
          double searched = -1.0;  // the limit of the search from e's ends in dist (none: < 0)
          ids.clear();
          bvh.query(boxes[e], ids);
          std::sort(ids.begin(), ids.end());
          for (const std::uint32_t f : ids) {
            if (f <= e) continue;
            const auto [ea, eb] = s.edges[e];
            const auto [fa, fb] = s.edges[f];
            if (ea == fa || ea == fb || eb == fa || eb == fb) continue;
            // Walk the thinner edge (th), measuring against the other (ot).
            const bool e_thin = radius_at(e, 0.5) <= radius_at(f, 0.5);
            const std::uint32_t th = e_thin ? e : f, ot = e_thin ? f : e;
            const Vec3& p0 = s.nodes[s.edges[th][0]].position;
            const Vec3& p1 = s.nodes[s.edges[th][1]].position;
            const Vec3& q0 = s.nodes[s.edges[ot][0]].position;
            const Vec3& q1 = s.nodes[s.edges[ot][1]].position;
            // A station's gap d - rp - rq is at most max(kGapRadii rp, kGapThick rq), so its
            // axis distance d at most (1 + kGapRadii) rmax(th) + (1 + kGapThick) rmax(ot): a
            // pair whose segments lie farther apart than that (with a thousandth to spare for
            // rounding) has no station to look at. In a dense crown most pairs whose boxes
            // meet are such (the boxes are loose around slanted edges).
            const double reach = (1 + kGapRadii) * rmax(th) + (1 + kGapThick) * rmax(ot);
            if (segment_distance_below(p0, p1, q0, q1) > 1.001 * reach) continue;
            const double len = (p1 - p0).norm();
            const double r_thin =
                std::min(s.nodes[s.edges[th][0]].radius, s.nodes[s.edges[th][1]].radius);
            // (Clamped before the conversion: an edge 1e300 radii long must not overflow the
            // int.)
            const int stations = static_cast<int>(
                std::clamp(std::ceil(len / (kGapStation * r_thin)), 1.0, double{kGapMaxStations}));
            pending.clear();
            for (int k = 0; k <= stations; ++k) {
              const double t = static_cast<double>(k) / stations;
              const Vec3 c = p0 + t * (p1 - p0);
              const double v = segment_parameter(c, q0, q1);
              const Vec3 q = q0 + v * (q1 - q0);
              const double d = (q - c).norm();
              const double rp = radius_at(th, t), rq = radius_at(ot, v);
              const double gap = d - rp - rq;
              if (!(gap > 0.0) || gap > std::max(kGapRadii * rp, kGapThick * rq)) continue;
              const Vec3 dir = (q - c) / d;
              pending.push_back({c + (rp + 0.5 * gap) * dir, dir, std::min(rp, rq), gap});
            }
            // Two edges a short way apart along the skeleton (within kGapPath times the sum of
            // their largest radii: a bend, a chain of short cylinders) are one branch: the
            // surface between them is its own. (Searched only for a pair with a gap.)
            if (pending.empty()) continue;
            const double limit = kGapPath * (rmax(e) + rmax(f));
            if (limit > searched) {
              forget(dist, seen);
              search_from(ea, eb, limit, dist, seen);
              searched = limit;
            }
            if (std::min(dist[fa], dist[fb]) <= limit) continue;
            out.insert(out.end(), pending.begin(), pending.end());
          }
          forget(dist, seen);
        }
      },
      ctx);
  std::vector<Request> all;
  for (const auto& chunk : requests) all.insert(all.end(), chunk.begin(), chunk.end());
  if (field != nullptr && !all.empty()) {
    // A blend swells both tubes towards each other: the middle of the gap between the tubes
    // the radii give may lie inside the surface, whose gap is then narrower and elsewhere on
    // the line (a 0.02 twig's tube 0.047 from a 0.10 branch's: the field 1.003-1.04 of iso at
    // the middle, 0.99 at 0.64 of the way). There the cross goes to the least of 13 samples
    // across the gap where that is below iso; where the line stays inside (the tubes join) or
    // the middle is outside, the cross stays in the middle. (Moving every cross to the least
    // value sent those of a twig entering a branch steeply deep into the crotch: 0.19 -> 2.0
    // local radii off on a generated tree.)
    std::vector<Vec3> at(all.size() * kGapSamples);
    for (std::size_t i = 0; i < all.size(); ++i) {
      for (int k = 0; k < kGapSamples; ++k) {
        const double u = static_cast<double>(k) / (kGapSamples - 1) - 0.5;
        at[i * kGapSamples + k] = all[i].mid + u * all[i].gap * all[i].dir;
      }
    }
    std::vector<double> value(at.size());
    field->evaluate(at, value, {}, ctx);
    for (std::size_t i = 0; i < all.size(); ++i) {
      const double* v = value.data() + i * kGapSamples;
      if (v[kGapSamples / 2] < field->iso()) continue;
      const auto least = std::min_element(v, v + kGapSamples) - v;
      if (v[least] < field->iso()) all[i].mid = at[i * kGapSamples + least];
    }
  }
  for (const Request& r : all) place(r.mid, r.dir, r.r, r.gap);
}

}  // namespace

BoundingPoints bounding_points(const Skeleton& s, const TetrahedralOptions& o, const Context* ctx,
                               const Field* field) {
  BoundingPoints pb;
  const Adjacency adjacent = adjacency(s);
  const double half_scale = 0.5 * o.section_scale;
  const std::vector<char> section = section_nodes(s, adjacent, o);
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    // Every node is a point of the set: the lattice then samples the inside on the skeleton
    // itself, so even at level 0 or 1 no branch can fall between lattice points.
    pb.node_points.push_back(static_cast<std::uint32_t>(pb.points.size()));
    const double half = half_scale * s.nodes[i].radius;
    add(pb, s.nodes[i].position, half);
    if (section[i] != 0) add_node_section(pb, s, adjacent, i, half, o.crotch_points);
  }
  add_edge_stations(pb, s, o);
  add_gap_points(pb, s, adjacent, o, field, ctx);
  return pb;
}

// The jitter is relative to the local cross-section, so even the thinnest twig's squares are
// far from cospherical in floating point.
std::vector<Vec3> jitter_and_enclose(BoundingPoints& set, const Skeleton& skeleton) {
  std::vector<Vec3> pts = std::move(set.points);
  Rng rng(0x7e7a);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    pts[i] +=
        kJitter * set.sizes[i] * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  }
  const Aabb skel_box = bounding_box(skeleton);
  const double scale = skel_box.diagonal().norm();
  const Vec3 c = skel_box.center();
  const Vec3 h = 0.5 * skel_box.diagonal() + Vec3::Constant(0.5 * scale);
  for (int k = 0; k < 8; ++k) {
    pts.push_back(
        c + Vec3((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z()));
  }
  return pts;
}

}  // namespace ramiform::detail::tets
