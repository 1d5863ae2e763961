// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Skeleton-bounded tetrahedral polygonization after Zhu, Guo & Jin 2013 (`003` §3–5); the
// header describes the steps. Differences from the paper, and why:
// - Delaunay tetrahedralization of the bounding point set (delaunay.h) replaces TetGen (GPL); the
//   region is the set of Delaunay tetrahedra near the skeleton instead of a meshed polyhedron.
// - Holes are detected and closed (step 5) instead of hoped away with auxiliary points only.
// - Subdivision skips region tetrahedra whose field bound excludes the iso value.
// - The skeleton's own points join the bounding set, so that the lattice samples the inside
//   even at levels 0 and 1.
// - The field is evaluated once per distinct lattice point (the paper evaluates per region
//   tetrahedron), and the needle cleanup the paper lacks keeps every skeleton node inside.

#include "ramiform/polygonize/tetrahedral.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "core/bucket_order.h"
#include "field/bvh.h"
#include "polygonize/delaunay.h"
#include "polygonize/edge_roots.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/random.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/cleanup.h"
#include "ramiform/mesh/winding.h"

namespace ramiform {
namespace {

using Clock = std::chrono::steady_clock;
using Tet = std::array<std::uint32_t, 4>;
using TetPoints = std::array<Vec3, 4>;
constexpr std::uint32_t kNone = UINT32_MAX;
constexpr double kJitter = 1e-3;  // bounding point jitter / local cross-section half size
constexpr int kBoundLevel = 4;    // levels from which region tetrahedra are pruned by the bound

double seconds_since(Clock::time_point& t) {
  const auto now = Clock::now();
  const double s = std::chrono::duration<double>(now - t).count();
  t = now;
  return s;
}

void validate_options(const TetrahedralOptions& o) {
  auto fail = [](const std::string& m) { throw InvalidArgument("TetrahedralOptions." + m); };
  if (o.levels < 0 || o.levels > 6) fail("levels must be in [0, 6], got " + std::to_string(o.levels));
  if (!(o.section_scale >= 2.0) || !std::isfinite(o.section_scale)) {
    fail("section_scale must be >= 2, got " + std::to_string(o.section_scale));
  }
  if (!(o.station_spacing > 0.0) || !std::isfinite(o.station_spacing)) {
    fail("station_spacing must be > 0, got " + std::to_string(o.station_spacing));
  }
  if (o.root_steps < 0 || o.root_steps > 64) fail("root_steps must be in [0, 64]");
  if (o.max_growth_rounds < 0) fail("max_growth_rounds must be >= 0");
}

// What the bounding point set can resolve, checked before it is built (InvalidArgument, naming
// the node or edge):
// - a node's cross-section (jittered by kJitter of its half size) must stand clear of the
//   rounding of its coordinates, or its corners would coincide;
// - radii and coordinates must lie within [1e-50, 1e50]: the exact in-sphere test multiplies
//   five coordinate differences, which must neither underflow nor overflow;
// - the cross-sections every `station_spacing` radii must stay countable (a 1 m edge with a
//   1e-300 radius would ask for 10^299 of them).
constexpr double kMinRadiusPerCoordinate = 1e-11;
constexpr double kMinScale = 1e-50, kMaxScale = 1e50;
constexpr double kMaxStations = 1 << 24;
void validate_resolution(const Skeleton& s, const TetrahedralOptions& o) {
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& n = s.nodes[i];
    const double magnitude = n.position.cwiseAbs().maxCoeff();
    if (n.radius < kMinScale || magnitude > kMaxScale) {
      throw InvalidArgument("tetrahedral polygonizer: node " + std::to_string(i) + ": radius " +
                            format_number(n.radius) + " and coordinates up to " +
                            format_number(magnitude) +
                            " are outside [1e-50, 1e50], where its exact predicates cannot "
                            "underflow or overflow (rescale the skeleton)");
    }
    if (n.radius < kMinRadiusPerCoordinate * magnitude) {
      throw InvalidArgument("tetrahedral polygonizer: node " + std::to_string(i) + ": radius " +
                            format_number(n.radius) +
                            " is below 1e-11 of its largest coordinate (" +
                            format_number(magnitude) +
                            "); its cross-section would vanish in double precision (move the "
                            "skeleton near the origin, or use --method mc)");
    }
  }
  double stations = 0;
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    const auto& na = s.nodes[s.edges[e][0]];
    const auto& nb = s.nodes[s.edges[e][1]];
    const double radii = (nb.position - na.position).norm() / (0.5 * (na.radius + nb.radius));
    stations += radii / o.station_spacing;
    if (stations > kMaxStations) {
      throw InvalidArgument("tetrahedral polygonizer: the skeleton needs more than " +
                            format_number(kMaxStations) + " cross-sections (one every " +
                            format_number(o.station_spacing) + " radii; edge " + std::to_string(e) +
                            " alone is " + format_number(radii) +
                            " radii long: are the radii in the skeleton's unit?)");
    }
  }
}

// The physical memory of this machine in bytes (0 when unknown).
double physical_memory() {
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGE_SIZE)
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) return static_cast<double>(pages) * static_cast<double>(page);
#endif
  return 0;
}

// A run needs at least about 600 * 4^levels bytes per bounding point at its peak (measured on
// generated trees of 1,500 and 20,000 segments: 1.6, 3.7, 12.8 and 54 KB per point at levels 0
// to 3). A run that cannot fit in the machine's memory is refused up front instead of being
// killed by the system after minutes of work.
void check_memory(std::size_t points, const TetrahedralOptions& o) {
  const double need = static_cast<double>(points) * 600.0 * std::pow(4.0, o.levels);
  const double have = physical_memory();
  if (have > 0 && need > have) {
    throw InvalidArgument("tetrahedral polygonizer: " + std::to_string(points) +
                          " bounding points at --levels " + std::to_string(o.levels) +
                          " need at least " + format_number(need / 1e9) +
                          " GB, more than this machine's " + format_number(have / 1e9) +
                          " GB (use fewer levels, or check the radii's units)");
  }
}

// Two unit vectors completing d to an orthonormal frame.
void frame(const Vec3& d, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(d.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = d.cross(helper).normalized();
  e2 = d.cross(e1).normalized();
}

// ---------------------------------------------------------------------------------------------
// Step 1: the bounding point set (§3.1 and the auxiliary points of §5).
struct PointSetBuilder {
  std::vector<Vec3> points;
  std::vector<double> sizes;  // per point, the local cross-section half size
  std::vector<std::uint32_t> node_points;  // per skeleton node, its own point
  // Consecutive points on the skeleton's axis (a node's own point, the stations' centres, the
  // next node's point), for every edge: they must be joined by edges of the tetrahedralization.
  std::vector<std::array<std::uint32_t, 2>> axis_pairs;

  void add(const Vec3& p, double half) {
    points.push_back(p);
    sizes.push_back(half);
  }

  void square(const Vec3& c, const Vec3& d, double half) {
    Vec3 e1, e2;
    frame(d, e1, e2);
    for (const double a : {-1.0, 1.0}) {
      for (const double b : {-1.0, 1.0}) add(c + half * (a * e1 + b * e2), half);
    }
  }
};

// Which nodes get a cross-section. Forks, tips and isolated nodes always do; along a chain of
// degree-2 nodes (scanned cylinder models have many short cylinders) a node is skipped while it
// lies within `station_spacing` radii of the last section, the chain bends by less than
// kMaxBendDeg and the radius changes by less than kMaxRadiusChange since it. Closely packed
// sections would only make many small tetrahedra, each subdivided as finely as a big one.
constexpr double kMaxBendDeg = 25.0;
constexpr double kMaxRadiusChange = 0.25;
std::vector<char> section_nodes(const Skeleton& s,
                                const std::vector<std::vector<std::uint32_t>>& adjacent,
                                const TetrahedralOptions& o) {
  const std::size_t n = s.nodes.size();
  std::vector<char> section(n, 1);
  std::vector<char> visited(n, 0);
  const double cos_bend = std::cos(kMaxBendDeg * std::numbers::pi / 180.0);
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
        const bool even = std::abs(nc.radius - nk.radius) <= kMaxRadiusChange * std::max(nk.radius, nc.radius);
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

PointSetBuilder bounding_points(const Skeleton& s, const TetrahedralOptions& o) {
  PointSetBuilder pb;
  const std::size_t n = s.nodes.size();
  std::vector<std::vector<std::uint32_t>> adjacent(n);
  for (const auto& e : s.edges) {
    adjacent[e[0]].push_back(e[1]);
    adjacent[e[1]].push_back(e[0]);
  }
  const double half_scale = 0.5 * o.section_scale;
  const std::vector<char> section = section_nodes(s, adjacent, o);
  for (std::uint32_t i = 0; i < n; ++i) {
    // Every node is a point of the set: the lattice then samples the inside on the skeleton
    // itself, so even at level 0 or 1 no branch can fall between lattice points.
    pb.node_points.push_back(static_cast<std::uint32_t>(pb.points.size()));
    pb.add(s.nodes[i].position, half_scale * s.nodes[i].radius);
    if (section[i] == 0) continue;
    const Vec3& p = s.nodes[i].position;
    const double r = s.nodes[i].radius;
    const double half = half_scale * r;
    const auto& adj = adjacent[i];
    if (adj.empty()) {  // isolated node: a cube
      for (int c = 0; c < 8; ++c) {
        pb.add(p + half * Vec3((c & 1) ? 1 : -1, (c & 2) ? 1 : -1, (c & 4) ? 1 : -1), half);
      }
      continue;
    }
    // Section direction: incident edge directions aligned with the first one, summed.
    const Vec3 u0 = (s.nodes[adj[0]].position - p).normalized();
    Vec3 d = Vec3::Zero();
    for (const std::uint32_t j : adj) {
      const Vec3 u = (s.nodes[j].position - p).normalized();
      d += u.dot(u0) >= 0 ? u : Vec3(-u);
    }
    d = d.norm() > 1e-12 ? Vec3(d.normalized()) : u0;
    pb.square(p, d, half);
    if (adj.size() == 1) {  // tip: a second square and a cap point beyond it
      const Vec3 out = -u0;
      pb.square(p + out * half, out, half);
      pb.add(p + out * (2 * half), half);
    }
    if (adj.size() >= 3) {
      // §5: an auxiliary point on each side of the plane of every pair of branches, at the
      // mean length of the two edges (capped at the section size).
      for (std::size_t a = 0; a < adj.size(); ++a) {
        for (std::size_t b = a + 1; b < adj.size(); ++b) {
          const Vec3 ua = s.nodes[adj[a]].position - p;
          const Vec3 ub = s.nodes[adj[b]].position - p;
          const Vec3 nrm = ua.cross(ub);
          if (nrm.norm() <= 1e-12 * ua.norm() * ub.norm()) continue;
          const double len = std::min(0.5 * (ua.norm() + ub.norm()), 2 * half);
          pb.add(p + len * nrm.normalized(), half);
          pb.add(p - len * nrm.normalized(), half);
        }
      }
    }
  }
  // Intermediate stations along long edges.
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
      pb.square(na.position + t * d, d / len, half);
      pb.add(na.position + t * d, half);  // the station's centre, on the skeleton
      const auto centre = static_cast<std::uint32_t>(pb.points.size() - 1);
      pb.axis_pairs.push_back({axis, centre});
      axis = centre;
    }
    pb.axis_pairs.push_back({axis, pb.node_points[e[1]]});
  }
  return pb;
}

// ---------------------------------------------------------------------------------------------
Aabb box_of(const Vec3& a, const Vec3& b, const Vec3& c) {
  Aabb box;
  box.extend(a);
  box.extend(b);
  box.extend(c);
  return box;
}

Aabb box_of(const TetPoints& t) {
  Aabb box = box_of(t[0], t[1], t[2]);
  box.extend(t[3]);
  return box;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b, double& t) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Step 3 (first half): tetrahedra near the skeleton, and those holding a node.
std::vector<char> initial_region(const Skeleton& s, const std::vector<Vec3>& pts,
                                 const std::vector<Tet>& tets, std::size_t real_points,
                                 const std::vector<std::uint32_t>& neighbor,
                                 const std::vector<std::uint32_t>& node_points,
                                 const TetrahedralOptions& o, const Context* ctx) {
  const double reach = 0.5 * o.section_scale * std::sqrt(2.0) * 1.05;
  std::vector<Aabb> capsules;
  std::vector<std::array<std::uint32_t, 2>> capsule_nodes;
  for (const auto& e : s.edges) capsule_nodes.push_back(e);
  std::vector<char> has_edge(s.nodes.size(), 0);
  for (const auto& e : s.edges) has_edge[e[0]] = has_edge[e[1]] = 1;
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    if (has_edge[i] == 0) capsule_nodes.push_back({i, i});
  }
  for (const auto& c : capsule_nodes) {
    const auto& a = s.nodes[c[0]];
    const auto& b = s.nodes[c[1]];
    const double grow = reach * std::max(a.radius, b.radius);
    Aabb box;
    box.extend(a.position);
    box.extend(b.position);
    box.min().array() -= grow;
    box.max().array() += grow;
    capsules.push_back(box);
  }
  const detail::BoxBvh capsule_bvh(capsules);
  std::vector<char> keep(tets.size(), 0);
  parallel::for_chunks(
      tets.size(), 4096,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t> ids;
        for (std::size_t t = begin; t < end; ++t) {
          const Tet& tet = tets[t];
          const bool far = std::any_of(tet.begin(), tet.end(), [&](std::uint32_t v) {
            return v >= real_points && v < real_points + 8;  // the far box's corners
          });
          if (far) continue;
          const Vec3 c = 0.25 * (pts[tet[0]] + pts[tet[1]] + pts[tet[2]] + pts[tet[3]]);
          ids.clear();
          capsule_bvh.query(Aabb(c, c), ids);
          for (const std::uint32_t k : ids) {
            const auto& a = s.nodes[capsule_nodes[k][0]];
            const auto& b = s.nodes[capsule_nodes[k][1]];
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
  // Every node must lie in a kept tetrahedron. Its own point (jittered by a thousandth of the
  // section) is a corner of the tetrahedra around it: keep those, and walk from one of them to
  // the tetrahedron holding the node's exact position (a visibility walk over face neighbours).
  std::vector<std::uint32_t> incident(pts.size(), kNone);
  for (std::uint32_t t = 0; t < tets.size(); ++t) {
    for (const std::uint32_t v : tets[t]) incident[v] = t;
  }
  std::vector<char> is_node(pts.size(), 0);
  for (const std::uint32_t i : node_points) is_node[i] = 1;
  for (std::size_t t = 0; t < tets.size(); ++t) {
    for (const std::uint32_t v : tets[t]) {
      if (is_node[v] != 0) keep[t] = 1;
    }
  }
  for (std::size_t i = 0; i < node_points.size(); ++i) {
    std::uint32_t t = incident[node_points[i]];
    const Vec3& x = s.nodes[i].position;
    for (std::size_t step = 0; t != kNone && step < tets.size(); ++step) {
      int beyond = -1;  // a face with the node strictly on its far side
      for (int k = 0; k < 4 && beyond < 0; ++k) {
        TetPoints c{pts[tets[t][0]], pts[tets[t][1]], pts[tets[t][2]], pts[tets[t][3]]};
        const int inner = detail::orient3d(c[0], c[1], c[2], c[3]);
        c[k] = x;
        if (detail::orient3d(c[0], c[1], c[2], c[3]) == -inner) beyond = k;
      }
      if (beyond < 0) {
        keep[t] = 1;
        break;
      }
      t = neighbor[4 * t + static_cast<std::size_t>(beyond)];
    }
  }
  return keep;
}

// ---------------------------------------------------------------------------------------------

// One marching-tetrahedra polygon: a triangle or a quad (cyclic order), oriented outward, over
// global record indices.
struct Polygon {
  std::array<std::uint32_t, 4> record{};
  bool quad = false;
};

// What one chunk of region tetrahedra produced.
struct ChunkOutput {
  std::vector<Polygon> polygons;  // record indices local to the chunk
  // Crossing edges: (global id of the inside lattice point) << 32 | (that of the outside one).
  std::vector<std::uint64_t> records;
  // Per region tetrahedron of the chunk, bit k set when a leaf corner on its face opposite
  // corner k is inside (f > iso): the surface reaches that face.
  std::vector<std::uint8_t> face_inside;
  std::size_t leaves = 0, evaluated = 0, skipped = 0;
};

constexpr std::size_t kTetsPerChunk = 32;

// Marching tetrahedra on one leaf with corner positions `p`, corner values `f` (inside: > iso)
// and local corner ids `id`: appends the polygon with edge slots found by `slot(in, out)`.
//
// Orientation is decided in the root tetrahedron's barycentric space (`p` holds the leaf's
// integer barycentric coordinates w1, w2, w3), where every leaf has a proper volume, and
// flipped when the root tetrahedron is negatively oriented (`flip`): an affine map preserves
// which side is inside, so the result is right even for the slivers a Delaunay
// tetrahedralization contains, where a test on the model-space corners could pick either side.
template <class Slot>
void march_leaf(const TetPoints& p, bool flip, const std::array<double, 4>& f,
                const std::array<std::uint32_t, 4>& id, double iso, Slot&& slot,
                std::vector<Polygon>& out) {
  std::array<int, 4> ins{}, outs{};
  int ni = 0, no = 0;
  for (int k = 0; k < 4; ++k) {
    if (f[k] > iso) {
      ins[ni++] = k;
    } else {
      outs[no++] = k;
    }
  }
  if (ni == 0 || no == 0) return;
  // Orientation: the normal points from the inside corners to the outside ones, decided on the
  // edge midpoints, which always span a proper cross-section of the leaf.
  Vec3 in_mean = Vec3::Zero(), out_mean = Vec3::Zero();
  for (int k = 0; k < ni; ++k) in_mean += p[ins[k]] / ni;
  for (int k = 0; k < no; ++k) out_mean += p[outs[k]] / no;
  const Vec3 outward = flip ? Vec3(in_mean - out_mean) : Vec3(out_mean - in_mean);
  auto mid = [&](int a, int c) { return 0.5 * (p[a] + p[c]); };
  auto edge = [&](int a, int c) { return slot(id[a], id[c]); };  // a inside, c outside
  Polygon poly;
  if (ni == 1 || no == 1) {
    std::array<Vec3, 3> m;
    for (int k = 0; k < 3; ++k) {
      const int in = ni == 1 ? ins[0] : ins[k];
      const int ou = ni == 1 ? outs[k] : outs[0];
      poly.record[k] = edge(in, ou);
      m[k] = mid(in, ou);
    }
    if ((m[1] - m[0]).cross(m[2] - m[0]).dot(outward) < 0) std::swap(poly.record[1], poly.record[2]);
  } else {
    const int a = ins[0], c = ins[1], q0 = outs[0], q1 = outs[1];
    poly.quad = true;
    poly.record = {edge(a, q0), edge(a, q1), edge(c, q1), edge(c, q0)};
    const Vec3 m0 = mid(a, q0), m1 = mid(a, q1), m2 = mid(c, q1);
    if ((m1 - m0).cross(m2 - m0).dot(outward) < 0) std::swap(poly.record[1], poly.record[3]);
  }
  out.push_back(poly);
}

// A leaf corner in integer barycentric coordinates over the region tetrahedron's corners
// (which are sorted by point id), summing to 2^levels. Midpoints stay integer.
using Bary = std::array<std::uint8_t, 4>;
using BaryTet = std::array<Bary, 4>;

Bary midpoint(const Bary& a, const Bary& b) {
  return {static_cast<std::uint8_t>((a[0] + b[0]) / 2), static_cast<std::uint8_t>((a[1] + b[1]) / 2),
          static_cast<std::uint8_t>((a[2] + b[2]) / 2), static_cast<std::uint8_t>((a[3] + b[3]) / 2)};
}

// The position of a lattice point, (sum_k w_k p_k) / 2^levels summed in corner order. A point
// on a face or edge shared with another region tetrahedron has zero weights on the other
// corners, which add exact zeros: both tetrahedra compute bit-identical positions, so their
// crossing edges match by key and the mesh stays watertight.
Vec3 lattice_point(const TetPoints& c, const Bary& w, double inv_m) {
  double x = 0, y = 0, z = 0;
  for (int k = 0; k < 4; ++k) {
    const double wk = w[k];
    x += wk * c[k].x();
    y += wk * c[k].y();
    z += wk * c[k].z();
  }
  return {x * inv_m, y * inv_m, z * inv_m};
}

// Figure 4 on barycentric leaves: four corner tetrahedra, then the octahedron of the six edge
// midpoints split along its shortest diagonal (m1m6, m2m5 or m3m4), measured in model space.
template <class At>
void split_1_to_8(const BaryTet& t, At&& at, std::vector<BaryTet>& out) {
  const Bary m1 = midpoint(t[0], t[1]), m2 = midpoint(t[0], t[2]), m3 = midpoint(t[0], t[3]);
  const Bary m4 = midpoint(t[1], t[2]), m5 = midpoint(t[1], t[3]), m6 = midpoint(t[2], t[3]);
  out.push_back({t[0], m1, m2, m3});
  out.push_back({t[1], m1, m4, m5});
  out.push_back({t[2], m2, m4, m6});
  out.push_back({t[3], m3, m5, m6});
  const double d16 = (at(m1) - at(m6)).squaredNorm();
  const double d25 = (at(m2) - at(m5)).squaredNorm();
  const double d34 = (at(m3) - at(m4)).squaredNorm();
  const Bary* a = nullptr;
  const Bary* b = nullptr;
  std::array<const Bary*, 4> ring{};  // the other four midpoints, in cyclic order
  if (d16 <= d25 && d16 <= d34) {
    a = &m1, b = &m6, ring = {&m2, &m4, &m5, &m3};
  } else if (d25 <= d34) {
    a = &m2, b = &m5, ring = {&m1, &m3, &m6, &m4};
  } else {
    a = &m3, b = &m4, ring = {&m1, &m2, &m6, &m5};
  }
  for (int k = 0; k < 4; ++k) out.push_back({*a, *b, *ring[k], *ring[(k + 1) % 4]});
}

// Every distinct lattice point of the extracted region tetrahedra, with its position and field
// value, evaluated once. Neighbouring region tetrahedra share the lattice points on their
// common corners, edges and faces: at level 1 all 10 points of a tetrahedron lie on its
// boundary, at level 2 all but 1 of 35, and a corner is shared by some twenty tetrahedra (on
// the 1,500-segment benchmark tree at level 1: 303 k evaluations instead of 1.58 M). A point
// has one global id for the whole run, laid out per round as [new corners | new edge points |
// new face points | inner points], and is addressed through its region tetrahedron's slot
// (rounds of hole closing append slots) and barycentric coordinates. Every position comes from
// lattice_point() on the corners of the first tetrahedron that holds the point, which is
// bit-identical to what the others would compute (see lattice_point).
class Lattice {
 public:
  Lattice(const std::vector<Vec3>& pts, const std::vector<Tet>& tets,
          const std::vector<std::uint32_t>& neighbor, int levels)
      : pts_(pts),
        tets_(tets),
        neighbor_(neighbor),
        m_(1 << levels),
        side_(static_cast<std::size_t>(m_) + 1),
        vertex_(pts.size(), kNone),
        slot_of_(tets.size(), kNone) {
    build_tables();
  }

  // Adds the tetrahedra `list` (live[r] == 1: extracted) as slots [slots(), slots() +
  // list.size()), then positions and evaluates their new lattice points.
  void add_round(const Field& field, const std::vector<std::uint32_t>& list,
                 const std::vector<char>& live, const Context* ctx) {
    const auto first = static_cast<std::uint32_t>(slot_tet_.size());
    const std::size_t first_point = refs_.size();
    for (std::size_t r = 0; r < list.size(); ++r) {
      slot_tet_.push_back(list[r]);
      if (live[r] == 1) slot_of_[list[r]] = first + static_cast<std::uint32_t>(r);
    }
    const auto end = static_cast<std::uint32_t>(slot_tet_.size());
    tet_edge_.resize(6 * static_cast<std::size_t>(end), kNone);
    tet_face_.resize(4 * static_cast<std::size_t>(end), kNone);
    inner_first_.resize(end, kNone);
    auto is_live = [&](std::uint32_t slot) { return live[slot - first] == 1; };
    // Corners, by point id.
    for (std::uint32_t slot = first; slot < end; ++slot) {
      if (!is_live(slot)) continue;
      const Tet& t = tets_[slot_tet_[slot]];
      for (int k = 0; k < 4; ++k) {
        if (vertex_[t[k]] != kNone) continue;
        vertex_[t[k]] = static_cast<std::uint32_t>(refs_.size());
        Bary w{};
        w[k] = static_cast<std::uint8_t>(m_);
        refs_.emplace_back(slot, w);
      }
    }
    // Edges: the new slots' corner pairs, sorted; equal pairs share their points, and a pair
    // seen in an earlier round keeps the points it got there. At level 0 edges hold no points
    // (their sort was a tenth of a level-0 run).
    std::vector<EdgeRef> raw;
    for (std::uint32_t slot = first; m_ > 1 && slot < end; ++slot) {
      if (!is_live(slot)) continue;
      const Tet& t = tets_[slot_tet_[slot]];
      for (int e = 0; e < 6; ++e) {
        const std::uint64_t key =
            (std::uint64_t{t[kEdgeCorners[e][0]]} << 32U) | t[kEdgeCorners[e][1]];
        raw.push_back({key, 6 * slot + static_cast<std::uint32_t>(e)});
      }
    }
    const std::vector<EdgeRef> edges = sorted_edges(raw, ctx);
    std::vector<EdgeRef> known;  // (pair, first point id) of the new distinct pairs
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (i > 0 && edges[i].key == edges[i - 1].key) {
        tet_edge_[edges[i].ref] = tet_edge_[edges[i - 1].ref];
        continue;
      }
      const auto old =
          std::lower_bound(edge_points_.begin(), edge_points_.end(), EdgeRef{edges[i].key, 0});
      if (old != edge_points_.end() && old->key == edges[i].key) {
        tet_edge_[edges[i].ref] = old->ref;
        continue;
      }
      tet_edge_[edges[i].ref] = static_cast<std::uint32_t>(refs_.size());
      known.push_back({edges[i].key, static_cast<std::uint32_t>(refs_.size())});
      const std::uint32_t slot = edges[i].ref / 6;
      const auto& c = kEdgeCorners[edges[i].ref % 6];
      for (int j = 1; j < m_; ++j) {
        Bary w{};
        w[c[0]] = static_cast<std::uint8_t>(m_ - j);
        w[c[1]] = static_cast<std::uint8_t>(j);
        refs_.emplace_back(slot, w);
      }
    }
    if (!known.empty()) {
      const auto middle = static_cast<std::ptrdiff_t>(edge_points_.size());
      edge_points_.insert(edge_points_.end(), known.begin(), known.end());
      std::inplace_merge(edge_points_.begin(), edge_points_.begin() + middle, edge_points_.end());
    }
    // Faces: the face opposite corner k is shared with the face neighbour across it.
    for (std::uint32_t slot = first; slot < end; ++slot) {
      if (!is_live(slot)) continue;
      const std::uint32_t t = slot_tet_[slot];
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t nb = neighbor_[4 * static_cast<std::size_t>(t) + k];
        const std::uint32_t other = nb == kNone ? kNone : slot_of_[nb];
        if (other != kNone && other < slot) {
          for (int j = 0; j < 4; ++j) {
            if (neighbor_[4 * static_cast<std::size_t>(nb) + j] == t) {
              tet_face_[4 * static_cast<std::size_t>(slot) + k] =
                  tet_face_[4 * static_cast<std::size_t>(other) + j];
            }
          }
          continue;
        }
        tet_face_[4 * static_cast<std::size_t>(slot) + k] =
            static_cast<std::uint32_t>(refs_.size());
        for (const Bary& w : face_bary_[k]) refs_.emplace_back(slot, w);
      }
    }
    // Inner points.
    for (std::uint32_t slot = first; slot < end; ++slot) {
      if (!is_live(slot) || inner_bary_.empty()) continue;
      inner_first_[slot] = static_cast<std::uint32_t>(refs_.size());
      for (const Bary& w : inner_bary_) refs_.emplace_back(slot, w);
    }
    // Positions and one batch evaluation of the new points.
    const std::size_t count = refs_.size() - first_point;
    positions_.resize(refs_.size());
    values_.resize(refs_.size());
    const double inv_m = 1.0 / m_;
    parallel::for_chunks(
        count, 16384,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t i = first_point + b; i < first_point + e; ++i) {
            const Tet& t = tets_[slot_tet_[refs_[i].first]];
            positions_[i] = lattice_point(TetPoints{pts_[t[0]], pts_[t[1]], pts_[t[2]], pts_[t[3]]},
                                          refs_[i].second, inv_m);
          }
        },
        ctx);
    field.evaluate(std::span<const Vec3>(positions_).subspan(first_point, count),
                   std::span<double>(values_).subspan(first_point, count));
    evaluated_ += count;
  }

  // The global id of the lattice point w of the tetrahedron t in slot `slot`.
  [[nodiscard]] std::uint32_t id(std::size_t slot, const Tet& t, const Bary& w) const {
    const int nonzero = (w[0] != 0) + (w[1] != 0) + (w[2] != 0) + (w[3] != 0);
    if (nonzero == 1) {
      int k = 0;
      while (w[k] == 0) ++k;
      return vertex_[t[k]];
    }
    if (nonzero == 2) {
      const int e =
          edge_of_[(w[0] != 0) | (w[1] != 0) << 1U | (w[2] != 0) << 2U | (w[3] != 0) << 3U];
      return tet_edge_[6 * slot + e] + (w[kEdgeCorners[e][1]] - 1);
    }
    if (nonzero == 3) {
      int k = 0;
      while (w[k] != 0) ++k;
      const auto& c = kFaceCorners[k];
      return tet_face_[4 * slot + k] + face_rank_[w[c[1]] * side_ + w[c[2]]];
    }
    return inner_first_[slot] + inner_rank_[(w[1] * side_ + w[2]) * side_ + w[3]];
  }

  // Whether every lattice point of the tetrahedron t in slot `slot` lies on one side of the
  // iso value (`inside` says which): then no leaf of it holds a piece of the surface.
  [[nodiscard]] bool one_sided(std::size_t slot, const Tet& t, double iso, bool& inside) const {
    inside = values_[id(slot, t, all_bary_[0])] > iso;
    for (const Bary& w : all_bary_) {
      if ((values_[id(slot, t, w)] > iso) != inside) return false;
    }
    return true;
  }

  [[nodiscard]] const Vec3& position(std::uint32_t id) const { return positions_[id]; }
  [[nodiscard]] double value(std::uint32_t id) const { return values_[id]; }
  [[nodiscard]] std::size_t slots() const { return slot_tet_.size(); }
  [[nodiscard]] std::size_t size() const { return values_.size(); }
  [[nodiscard]] std::size_t evaluated() const { return evaluated_; }

 private:
  struct EdgeRef {
    std::uint64_t key;  // corner point ids, lower first
    std::uint32_t ref;  // 6 * slot + local edge, or the pair's first point id
    bool operator<(const EdgeRef& o) const { return key < o.key || (key == o.key && ref < o.ref); }
  };

  // `raw` in ascending order, bucketed by the lower corner (point ids are dense): linear, where
  // a comparison sort of the 950 k pairs of the benchmark tree's level-1 run took 0.028 s.
  std::vector<EdgeRef> sorted_edges(const std::vector<EdgeRef>& raw, const Context* ctx) const {
    const std::vector<std::uint32_t> order = detail::bucket_order(
        raw.size(), pts_.size(),
        [&](std::size_t i) { return static_cast<std::uint32_t>(raw[i].key >> 32U); },
        [&](std::uint32_t x, std::uint32_t y) { return raw[x] < raw[y]; }, ctx);
    std::vector<EdgeRef> out(raw.size());
    for (std::size_t i = 0; i < order.size(); ++i) out[i] = raw[order[i]];
    return out;
  }

  static constexpr std::array<std::array<int, 2>, 6> kEdgeCorners{
      {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
  static constexpr std::array<std::array<int, 3>, 4> kFaceCorners{
      {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}}};

  // Barycentric enumerations (in a fixed order) of the points strictly inside each face (the
  // face opposite corner k) and inside the tetrahedron, and the reverse lookups of id(). A
  // face's points are named by the weights (a, b) of its second and third corners in point id
  // order, which both tetrahedra sharing the face agree on (corners are sorted by id).
  void build_tables() {
    for (int e = 0; e < 6; ++e)
      edge_of_[(1U << kEdgeCorners[e][0]) | (1U << kEdgeCorners[e][1])] = e;
    face_rank_.assign(side_ * side_, 0);
    for (int k = 0; k < 4; ++k) {
      const auto& c = kFaceCorners[k];
      std::uint32_t rank = 0;
      for (int a = 1; a < m_; ++a) {
        for (int b = 1; a + b < m_; ++b) {
          Bary w{};
          w[c[0]] = static_cast<std::uint8_t>(m_ - a - b);
          w[c[1]] = static_cast<std::uint8_t>(a);
          w[c[2]] = static_cast<std::uint8_t>(b);
          face_rank_[a * side_ + b] = rank++;
          face_bary_[k].push_back(w);
        }
      }
    }
    for (int a = 0; a <= m_; ++a) {
      for (int b = 0; a + b <= m_; ++b) {
        for (int c = 0; a + b + c <= m_; ++c) {
          all_bary_.push_back({static_cast<std::uint8_t>(m_ - a - b - c),
                               static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b),
                               static_cast<std::uint8_t>(c)});
        }
      }
    }
    inner_rank_.assign(side_ * side_ * side_, 0);
    for (int a = 1; a < m_; ++a) {
      for (int b = 1; a + b < m_; ++b) {
        for (int c = 1; a + b + c < m_; ++c) {
          inner_rank_[(a * side_ + b) * side_ + c] = static_cast<std::uint32_t>(inner_bary_.size());
          inner_bary_.push_back({static_cast<std::uint8_t>(m_ - a - b - c),
                                 static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b),
                                 static_cast<std::uint8_t>(c)});
        }
      }
    }
  }

  const std::vector<Vec3>& pts_;
  const std::vector<Tet>& tets_;
  const std::vector<std::uint32_t>& neighbor_;
  int m_;
  std::size_t side_;
  std::array<int, 16> edge_of_{};
  std::array<std::vector<Bary>, 4> face_bary_;
  std::vector<std::uint32_t> face_rank_, inner_rank_;
  std::vector<Bary> inner_bary_;
  std::vector<Bary> all_bary_;           // every lattice point of a tetrahedron
  std::vector<std::uint32_t> vertex_;    // per point id, its corner's global id
  std::vector<std::uint32_t> slot_of_;   // per tetrahedron, its slot if extracted
  std::vector<std::uint32_t> slot_tet_;  // per slot, its tetrahedron
  std::vector<std::uint32_t> tet_edge_;  // per slot and local edge, the edge's first point id
  std::vector<std::uint32_t> tet_face_;  // per slot and face, the face's first point id
  std::vector<std::uint32_t> inner_first_;
  std::vector<EdgeRef> edge_points_;  // every corner pair so far, sorted, with its first id
  std::vector<std::pair<std::uint32_t, Bary>> refs_;  // per point, (slot, barycentric)
  std::vector<Vec3> positions_;
  std::vector<double> values_;
  std::size_t evaluated_ = 0;
};

// Per-thread scratch of extract_chunk: leaves, and a stamped table from lattice point to local
// corner id (no clearing between tetrahedra).
struct LatticeScratch {
  std::vector<BaryTet> leaves, next;
  std::vector<std::uint32_t> stamp, id;
  std::uint32_t generation = 0;
};

// The lattice points of one region tetrahedron, each registered (global id looked up, appended
// to the chunk's arrays) on first use through the stamped table.
struct LatticeIndex {
  LatticeScratch& sc;
  std::size_t side;
  const Lattice& lattice;
  std::size_t slot;
  const Tet& tet;
  std::vector<std::uint32_t>& gid;
  std::vector<Vec3>& bary;
  std::vector<std::uint8_t>& faces;
  std::size_t base;

  std::uint32_t id(const Bary& w) {
    const std::size_t key = (w[1] * side + w[2]) * side + w[3];
    if (sc.stamp[key] != sc.generation) {
      sc.stamp[key] = sc.generation;
      sc.id[key] = static_cast<std::uint32_t>(gid.size() - base);
      gid.push_back(lattice.id(slot, tet, w));
      bary.emplace_back(w[1], w[2], w[3]);
      faces.push_back(static_cast<std::uint8_t>((w[0] == 0 ? 1 : 0) | (w[1] == 0 ? 2 : 0) |
                                                (w[2] == 0 ? 4 : 0) | (w[3] == 0 ? 8 : 0)));
    }
    return sc.id[key];
  }
  const Vec3& at(const Bary& w) { return lattice.position(gid[base + id(w)]); }
};

// Subdivides and marches the region tetrahedra [begin, end) of `region` (in lattice slots
// first_slot + r) into `out`. live[r]: 1 to extract, 0 skipped as wholly outside, 2 skipped as
// wholly inside (field bound).
void extract_chunk(const Field& field, const std::vector<Vec3>& pts, const std::vector<Tet>& tets,
                   const std::vector<std::uint32_t>& region, std::size_t begin, std::size_t end,
                   const TetrahedralOptions& o, const std::vector<char>& live,
                   const Lattice& lattice, std::size_t first_slot, ChunkOutput& out) {
  const double iso = field.iso();
  const int m = 1 << o.levels;
  const std::size_t side = static_cast<std::size_t>(m) + 1;
  thread_local LatticeScratch sc;
  if (sc.stamp.size() < side * side * side) {
    sc.stamp.assign(side * side * side, 0);
    sc.id.assign(side * side * side, 0);
    sc.generation = 0;
  }
  std::vector<std::uint32_t> gid;      // global ids of the corners of every live tetrahedron
  std::vector<std::size_t> gid_begin;  // per live tetrahedron, its first corner in gid
  std::vector<std::array<std::uint32_t, 4>> leaf_ids;  // local corner ids of every leaf
  std::vector<std::uint8_t> corner_faces;              // per corner, the faces it lies on (bits)
  std::vector<Vec3> corner_bary;                       // per corner, its (w1, w2, w3)
  std::vector<char> live_flip;             // per live tetrahedron, negatively oriented
  std::vector<std::size_t> live_slot;      // per live tetrahedron, its index in the chunk
  out.face_inside.assign(end - begin, 0);
  const auto leaves_per_tet = static_cast<std::size_t>(1) << (3 * o.levels);
  BaryTet root{};
  for (int k = 0; k < 4; ++k) root[k][k] = static_cast<std::uint8_t>(m);
  for (std::size_t r = begin; r < end; ++r) {
    if (live[r] != 1) {
      ++out.skipped;
      if (live[r] == 2) out.face_inside[r - begin] = 0xF;  // wholly inside: every face
      continue;
    }
    const Tet& t = tets[region[r]];
    // A tetrahedron whose lattice points all lie on one side holds no surface: only its faces'
    // inside flags matter (all or none), and its leaves need not be built.
    if (bool inside = false; lattice.one_sided(first_slot + r, t, iso, inside)) {
      if (inside) out.face_inside[r - begin] = 0xF;
      continue;
    }
    const TetPoints c{pts[t[0]], pts[t[1]], pts[t[2]], pts[t[3]]};
    live_slot.push_back(r - begin);
    live_flip.push_back((c[1] - c[0]).cross(c[2] - c[0]).dot(c[3] - c[0]) < 0 ? 1 : 0);
    if (++sc.generation == 0) {  // stamps wrapped: clear once
      std::fill(sc.stamp.begin(), sc.stamp.end(), 0);
      sc.generation = 1;
    }
    const std::size_t base = gid.size();
    gid_begin.push_back(base);
    LatticeIndex index{sc, side, lattice, first_slot + r, t, gid, corner_bary, corner_faces, base};
    auto at = [&](const Bary& w) { return index.at(w); };
    sc.leaves.assign(1, root);
    for (int level = 0; level < o.levels; ++level) {
      sc.next.clear();
      for (const auto& l : sc.leaves) split_1_to_8(l, at, sc.next);
      std::swap(sc.leaves, sc.next);
    }
    for (const auto& l : sc.leaves) {
      leaf_ids.push_back({index.id(l[0]), index.id(l[1]), index.id(l[2]), index.id(l[3])});
    }
  }
  gid_begin.push_back(gid.size());
  out.leaves += leaf_ids.size();
  if (gid.empty()) return;
  std::vector<double> values(gid.size());
  for (std::size_t v = 0; v < gid.size(); ++v) values[v] = lattice.value(gid[v]);
  for (std::size_t k = 0; k + 1 < gid_begin.size(); ++k) {
    std::uint8_t flags = 0;
    for (std::size_t v = gid_begin[k]; v < gid_begin[k + 1]; ++v) {
      if (values[v] > iso) flags |= corner_faces[v];
    }
    out.face_inside[live_slot[k]] = flags;
  }
  // Marching tetrahedra per live tetrahedron, with its crossing edges made unique locally.
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> order;
  std::vector<std::uint32_t> rank;
  for (std::size_t k = 0; k + 1 < gid_begin.size(); ++k) {
    const std::size_t base = gid_begin[k];
    const std::size_t first_leaf = k * leaves_per_tet;
    const bool flip = live_flip[k] != 0;
    auto leaf_points = [&](std::size_t l) {
      const auto& id = leaf_ids[l];
      return TetPoints{corner_bary[base + id[0]], corner_bary[base + id[1]], corner_bary[base + id[2]],
                       corner_bary[base + id[3]]};
    };
    auto leaf_values = [&](std::size_t l) {
      const auto& id = leaf_ids[l];
      return std::array<double, 4>{values[base + id[0]], values[base + id[1]], values[base + id[2]],
                                   values[base + id[3]]};
    };
    auto mixed = [&](const std::array<double, 4>& f) {
      const int in = (f[0] > iso) + (f[1] > iso) + (f[2] > iso) + (f[3] > iso);
      return in > 0 && in < 4;
    };
    // One march: polygons first refer to their edges by position in `keys`; the sorted unique
    // keys then become this tetrahedron's records (the global ids of the edge's inside and
    // outside lattice points) and the polygons are renumbered to them.
    keys.clear();
    const std::size_t first_polygon = out.polygons.size();
    auto collect = [&](std::uint32_t in, std::uint32_t ou) {
      keys.push_back((std::uint64_t{in} << 32U) | ou);
      return static_cast<std::uint32_t>(keys.size() - 1);
    };
    for (std::size_t l = first_leaf; l < first_leaf + leaves_per_tet; ++l) {
      const auto f = leaf_values(l);
      if (mixed(f)) march_leaf(leaf_points(l), flip, f, leaf_ids[l], iso, collect, out.polygons);
    }
    if (keys.empty()) continue;
    order.resize(keys.size());
    for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    rank.resize(keys.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      const std::uint64_t key = keys[order[i]];
      if (i == 0 || key != keys[order[i - 1]]) {
        out.records.push_back((std::uint64_t{gid[base + (key >> 32U)]} << 32U) |
                              gid[base + (key & 0xffffffffU)]);
      }
      rank[order[i]] = static_cast<std::uint32_t>(out.records.size() - 1);
    }
    for (std::size_t q = first_polygon; q < out.polygons.size(); ++q) {
      Polygon& poly = out.polygons[q];
      const int corners = poly.quad ? 4 : 3;
      for (int c = 0; c < corners; ++c) poly.record[c] = rank[poly.record[c]];
    }
  }
}

// Steps 4 and 5 over the region tetrahedra `list`: the bound test (from kBoundLevel on), the
// new lattice points' field values, then chunks in parallel, outputs in chunk order.
std::vector<ChunkOutput> extract_list(const Field& field, const std::vector<Vec3>& pts,
                                      const std::vector<Tet>& tets,
                                      const std::vector<std::uint32_t>& list, Lattice& lattice,
                                      const TetrahedralOptions& o, const Context* ctx) {
  // The region hugs the surface, so the bound almost never excludes a region tetrahedron
  // (measured: 2 % at level 3, 0.7 % at level 2) and costs more than it saves below level 4
  // (969 lattice points per tetrahedron); above, a skipped tetrahedron saves a lot.
  std::vector<char> live(list.size(), 1);
  if (o.levels >= kBoundLevel) {
    parallel::for_each(
        list.size(), 256,
        [&](std::size_t r) {
          const Tet& t = tets[list[r]];
          const Interval bound =
              field.bound(box_of(TetPoints{pts[t[0]], pts[t[1]], pts[t[2]], pts[t[3]]}));
          if (!bound.straddles(field.iso())) live[r] = bound.lo > field.iso() ? 2 : 0;
        },
        ctx);
  }
  const std::size_t first_slot = lattice.slots();
  const std::size_t evaluated = lattice.evaluated();
  lattice.add_round(field, list, live, ctx);
  std::vector<ChunkOutput> outs((list.size() + kTetsPerChunk - 1) / kTetsPerChunk);
  parallel::for_chunks(
      list.size(), kTetsPerChunk,
      [&](std::size_t b, std::size_t e) {
        extract_chunk(field, pts, tets, list, b, e, o, live, lattice, first_slot,
                      outs[b / kTetsPerChunk]);
      },
      ctx);
  if (!outs.empty()) outs[0].evaluated = lattice.evaluated() - evaluated;
  return outs;
}

// Appends the chunk outputs to the global polygons and records (record indices rebased).
void merge_outputs(std::vector<ChunkOutput>& outs, TetrahedralStats& st,
                   std::vector<Polygon>& polygons, std::vector<std::uint64_t>& records,
                   const Context* ctx) {
  std::vector<std::size_t> poly_at(outs.size() + 1, polygons.size());
  std::vector<std::size_t> rec_at(outs.size() + 1, records.size());
  for (std::size_t i = 0; i < outs.size(); ++i) {
    poly_at[i + 1] = poly_at[i] + outs[i].polygons.size();
    rec_at[i + 1] = rec_at[i] + outs[i].records.size();
    st.leaf_tets += outs[i].leaves;
    st.vertices_evaluated += outs[i].evaluated;
    st.skipped_tets += outs[i].skipped;
  }
  polygons.resize(poly_at.back());
  records.resize(rec_at.back());
  parallel::for_chunks(
      outs.size(), 1,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const auto base = static_cast<std::uint32_t>(rec_at[i]);
          std::size_t w = poly_at[i];
          for (Polygon p : outs[i].polygons) {
            for (auto& r : p.record) r += base;
            polygons[w++] = p;
          }
          std::copy(outs[i].records.begin(), outs[i].records.end(),
                    records.begin() + static_cast<std::ptrdiff_t>(rec_at[i]));
          outs[i] = ChunkOutput{};
        }
      },
      ctx);
}

// Numbers vertices in the order the triangles first use them. The crossing edges come out of
// their sort ordered by position along x, which scatters every vertex's neighbours across the
// array; triangles come region tetrahedron by region tetrahedron, so this order keeps
// neighbours close in memory (the cleanup and every later pass over the mesh run faster).
void renumber_by_first_use(TriMesh& mesh) {
  std::vector<std::uint32_t> remap(mesh.positions.size(), UINT32_MAX);
  std::vector<Vec3> positions;
  positions.reserve(mesh.positions.size());
  for (auto& t : mesh.triangles) {
    for (auto& v : t) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<std::uint32_t>(positions.size());
        positions.push_back(mesh.positions[v]);
      }
      v = remap[v];
    }
  }
  mesh.positions = std::move(positions);
}

// Removes the small components (each under 1 % of the triangles) that enclose no skeleton
// node: blobs where the field rises above the iso value away from the skeleton, mostly next to
// fitted joints. Returns how many were removed.
std::size_t drop_strays(TriMesh& mesh, const Skeleton& skeleton, Context* ctx) {
  const TriangleComponents comps = triangle_components(mesh);
  if (comps.count <= 1) return 0;
  std::vector<std::size_t> size(comps.count, 0);
  for (const std::uint32_t l : comps.label) ++size[l];
  std::vector<char> keep(comps.count, 1);
  std::size_t dropped = 0;
  for (std::uint32_t c = 0; c < comps.count; ++c) {
    if (100 * size[c] >= mesh.triangles.size()) continue;
    TriMesh part;
    part.positions = mesh.positions;
    Aabb box;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (comps.label[t] != c) continue;
      part.triangles.push_back(mesh.triangles[t]);
      for (const std::uint32_t v : mesh.triangles[t]) box.extend(mesh.positions[v]);
    }
    std::vector<Vec3> nodes;
    for (const auto& n : skeleton.nodes) {
      if (box.contains(n.position)) nodes.push_back(n.position);
    }
    const std::vector<char> in = nodes.empty() ? std::vector<char>{} : points_inside(part, nodes, ctx);
    if (std::find(in.begin(), in.end(), 1) == in.end()) {
      keep[c] = 0;
      ++dropped;
    }
  }
  if (dropped == 0) return 0;
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (keep[comps.label[t]] != 0) tris.push_back(mesh.triangles[t]);
  }
  mesh.triangles = std::move(tris);
  renumber_by_first_use(mesh);  // drops the vertices of the removed components
  return dropped;
}

}  // namespace

TriMesh polygonize_tetrahedral(const Field& field, const Skeleton& skeleton,
                               const TetrahedralOptions& options, Context* ctx,
                               TetrahedralStats* stats_out) {
  validate_options(options);
  validate(skeleton);
  validate_resolution(skeleton, options);
  TetrahedralStats st;
  auto clock = Clock::now();

  // 1. Bounding points, jittered by a tiny deterministic amount so that Delaunay sees no
  //    cospherical sets (the squares are), plus a far box so the hull lies far outside.
  //    The jitter is relative to the local cross-section (1e-3 of its half size), so even the
  //    thinnest twig's squares are far from cospherical in floating point.
  PointSetBuilder builder = bounding_points(skeleton, options);
  check_memory(builder.points.size(), options);
  std::vector<Vec3> pts = std::move(builder.points);
  Rng rng(0x7e7a);
  const Aabb skel_box = bounding_box(skeleton);
  const double scale = skel_box.diagonal().norm();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    pts[i] += kJitter * builder.sizes[i] *
              Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  }
  const std::size_t real_points = pts.size();
  {
    const Vec3 c = skel_box.center();
    const Vec3 h = 0.5 * skel_box.diagonal() + Vec3::Constant(0.5 * scale);
    for (int k = 0; k < 8; ++k) {
      pts.push_back(c + Vec3((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z()));
    }
  }
  st.polyhedron_points = real_points;
  st.seconds_polyhedron = seconds_since(clock);
  check_cancel(ctx);

  // 2. Delaunay tetrahedralization and face adjacency. Consecutive axis points must be joined
  //    by an edge: both are inside, so the lattice then joins them along the skeleton at every
  //    level and no branch can come apart, however coarse the lattice. A pair that is not an
  //    edge (another branch close by, or the squares of a bend) gets Steiner points on the
  //    axis until it is (measured: 36 of 8,698 pairs on the 1,500-segment benchmark tree, 551
  //    of 7,856 on archi_Tree_1, which came apart into 62 pieces at level 0 without them).
  detail::DelaunayResult delaunay = detail::delaunay_tetrahedralize(pts, builder.axis_pairs, ctx);
  if (delaunay.duplicate_points > 0) {
    // The jitter makes every point distinct; equal points mean a skeleton the checks missed.
    throw Failure("tetrahedral polygonizer: " + std::to_string(delaunay.duplicate_points) +
                  " bounding points coincide");
  }
  // Steiner points follow the far box's corners, which keep their numbers.
  pts.insert(pts.end(), delaunay.steiner_points.begin(), delaunay.steiner_points.end());
  st.axis_points_added = delaunay.steiner_points.size();
  st.axis_edges_missing = delaunay.missing_edges;
  const std::vector<Tet> tets = std::move(delaunay.tets);
  const std::vector<std::uint32_t> neighbor = std::move(delaunay.neighbors);
  st.delaunay_tets = tets.size();
  st.seconds_tetrahedralize = seconds_since(clock);
  check_cancel(ctx);

  // 3. Region and hole closing.
  std::vector<char> keep =
      initial_region(skeleton, pts, tets, real_points, neighbor, builder.node_points, options, ctx);
  st.region_tets = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1));
  std::vector<std::uint32_t> list;
  for (std::uint32_t t = 0; t < tets.size(); ++t) {
    if (keep[t] != 0) list.push_back(t);
  }
  st.seconds_region = seconds_since(clock);

  // 4 + 5. Per region tetrahedron (the paper's kernels, here one task per chunk of region
  //    tetrahedra): 1:8 subdivision to `levels`, the field at the lattice points (each distinct
  //    point once, see Lattice), marching tetrahedra on the leaves. Every region tetrahedron is
  //    subdivided to the same level, so leaves of neighbours meet face to face; a region
  //    tetrahedron whose field bound excludes the iso value is skipped whole. Crossing edges
  //    are keyed by the global ids of their end points.
  // 3b. Holes are verified, not hoped away: the mesh can only open where a leaf corner on the
  //    region's boundary is inside. Every boundary face with such a corner gets the tetrahedron
  //    behind it added and extracted, round after round, until no boundary face has one; the
  //    extracted mesh is then closed by construction.
  std::vector<Polygon> polygons;
  std::vector<std::uint64_t> records;
  Lattice lattice(pts, tets, neighbor, options.levels);
  while (!list.empty()) {
    std::vector<ChunkOutput> outs = extract_list(field, pts, tets, list, lattice, options, ctx);
    std::vector<std::uint32_t> next;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::uint8_t flags = outs[i / kTetsPerChunk].face_inside[i % kTetsPerChunk];
      for (int k = 0; k < 4; ++k) {
        if ((flags & (1U << k)) == 0) continue;
        const std::uint32_t nb = neighbor[4 * list[i] + k];
        if (nb == kNone) {
          st.holes_left = true;  // the surface reaches the hull of the far box
        } else if (keep[nb] == 0) {
          keep[nb] = 1;
          next.push_back(nb);
        }
      }
    }
    merge_outputs(outs, st, polygons, records, ctx);
    if (!next.empty()) {
      if (st.growth_rounds == options.max_growth_rounds) {
        st.holes_left = true;
        break;
      }
      ++st.growth_rounds;
      st.grown_tets += next.size();
    }
    list = std::move(next);
    check_cancel(ctx);
  }
  st.seconds_subdivide = seconds_since(clock);

  // Unique crossing edges, one mesh vertex per distinct pair of global lattice ids, numbered in
  // (inside id, outside id) order: the records bucketed by their inside id, each small bucket
  // ordered by the outside id.
  std::vector<std::uint32_t> bucket_start;
  std::vector<std::uint32_t> by_inside = detail::bucket_order(
      records.size(), lattice.size(),
      [&](std::size_t i) { return static_cast<std::uint32_t>(records[i] >> 32U); },
      [&](std::uint32_t x, std::uint32_t y) {
        return records[x] < records[y] || (records[x] == records[y] && x < y);
      },
      ctx, &bucket_start);
  std::vector<std::uint32_t> vertex_of(records.size());
  std::vector<Vec3> ea, eb;
  std::vector<double> fa, fb;
  for (std::size_t in = 0; in + 1 < bucket_start.size(); ++in) {
    const auto first = by_inside.begin() + bucket_start[in];
    const auto last = by_inside.begin() + bucket_start[in + 1];
    if (first == last) continue;
    for (auto it = first; it != last; ++it) {
      if (it == first || records[*it] != records[*(it - 1)]) {
        const auto out = static_cast<std::uint32_t>(records[*it] & 0xffffffffU);
        ea.push_back(lattice.position(static_cast<std::uint32_t>(in)));
        eb.push_back(lattice.position(out));
        fa.push_back(lattice.value(static_cast<std::uint32_t>(in)));
        fb.push_back(lattice.value(out));
      }
      vertex_of[*it] = static_cast<std::uint32_t>(ea.size() - 1);
    }
  }
  records = {};
  by_inside = {};
  TriMesh mesh;
  mesh.positions = detail::find_edge_roots(field, ea, eb, std::move(fa), std::move(fb),
                                           options.root_steps, st.root_evaluations);
  st.crossing_edges = mesh.positions.size();
  // Triangles; a quad is split along the shorter diagonal of its placed vertices.
  std::vector<std::size_t> tri_offset(polygons.size());
  for (std::size_t i = 0; i < polygons.size(); ++i) tri_offset[i] = polygons[i].quad ? 2 : 1;
  const std::size_t total_tris = parallel::exclusive_scan(tri_offset);
  mesh.triangles.resize(total_tris);
  parallel::for_chunks(
      polygons.size(), 8192,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const Polygon& p = polygons[i];
          std::array<std::uint32_t, 4> v{};
          for (int k = 0; k < (p.quad ? 4 : 3); ++k) v[k] = vertex_of[p.record[k]];
          const std::size_t w = tri_offset[i];
          if (!p.quad) {
            mesh.triangles[w] = {v[0], v[1], v[2]};
            continue;
          }
          const double d02 = (mesh.positions[v[0]] - mesh.positions[v[2]]).squaredNorm();
          const double d13 = (mesh.positions[v[1]] - mesh.positions[v[3]]).squaredNorm();
          if (d02 <= d13) {
            mesh.triangles[w] = {v[0], v[1], v[2]};
            mesh.triangles[w + 1] = {v[0], v[2], v[3]};
          } else {
            mesh.triangles[w] = {v[1], v[2], v[3]};
            mesh.triangles[w + 1] = {v[1], v[3], v[0]};
          }
        }
      },
      ctx);
  renumber_by_first_use(mesh);
  st.seconds_extract = seconds_since(clock);
  if (options.cleanup) {
    NeedleCleanupStats cs;
    NeedleCleanupOptions co;
    co.measure_after = false;  // the caller's mesh check measures the result
    // No collapse or flip may move a skeleton node out of the mesh (coarse levels make thin
    // tubes of few triangles, where a collapse can cut across the axis).
    std::vector<Vec3> nodes;
    nodes.reserve(skeleton.nodes.size());
    for (const auto& n : skeleton.nodes) nodes.push_back(n.position);
    co.keep_sides = nodes;
    clean_needles(mesh, co, &cs, ctx);
    st.collapsed_edges = cs.collapsed_edges;
    st.min_angle_before = cs.min_angle_before;
    st.median_angle_before = cs.median_angle_before;
  }
  if (options.drop_strays) st.stray_components = drop_strays(mesh, skeleton, ctx);
  st.seconds_cleanup = seconds_since(clock);
  if (stats_out != nullptr) *stats_out = st;
  return mesh;
}

}  // namespace ramiform
