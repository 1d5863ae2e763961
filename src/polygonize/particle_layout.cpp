// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/particle_layout.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <utility>

#include "polygonize/delaunay.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/mesh/winding.h"

namespace ramiform::detail {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr double kPi = std::numbers::pi;

// Cap angles at a junction are at most this fraction of the angle to the nearest other incident
// edge, so that the caps of two edges (and the sphere particles kept between them) never touch.
constexpr double kCapShare = 0.4;
// Two incident edges of a junction closer than this angle (radians; 0.006 degrees) leave caps so
// small that the convex hull of the projected points would hinge on differences near rounding
// (for collinear edges, which the skeleton validator allows when they end at different nodes,
// the caps coincide): such a junction is joined by the combinatorial patch instead, and the cap
// angle is floored at kCapShare times this so that rings keep a non-zero radius.
constexpr double kMinForkAngle = 1e-4;
// Sphere particles are removed within max(kCapExclusion x beta, beta + kCapGap x spacing) of an
// incident edge's direction (beta its cap angle, spacing the mean angular spacing of the sphere
// points): none comes near a ring, and the ring's plane keeps a margin far above rounding to
// the points outside the cap, so each ring edge is robustly a hull edge.
constexpr double kCapExclusion = 1.15;
constexpr double kCapGap = 0.3;
// Along an edge whose other end is a junction, a junction ring stays within this fraction of
// the length from its node; otherwise (leaf ends, vertex rings) within kReserveAlone.
constexpr double kReserveShared = 0.45;
constexpr double kReserveAlone = 0.9;
// Interior rings keep this fraction of the ring spacing clear of an end structure's zone.
constexpr double kRingMargin = 0.25;

// A degree-two node whose edges bend (180 degrees minus the angle between them) by at most
// kGentleBendDegrees, or by at most kChainBendDegrees with its shorter edge under the junction
// sphere's radius, lies inside a chain: its rings follow the chain's smoothed course (chain_tube)
// instead of a junction sphere of its own. A sharper bend keeps the sphere, which covers its
// corner where rings cannot follow it.
constexpr double kGentleBendDegrees = 45;
constexpr double kChainBendDegrees = 100;
// Along a chain, a ring's plane is normal to the chord from the chain point kSmoothWindow x R
// behind it to the one as far ahead (R the ring's radius): a zig-zag of edges shorter than the
// radius (the connectors of scanned cylinder models) averages out instead of tilting the rings.
constexpr double kSmoothWindow = 1.5;
// Two consecutive rings of a chain must be disjoint and in order even when scaled by this factor
// about their centres (the surface lies beyond R where tubes blend); a ring that is not is left
// out and the band spans the gap.
constexpr double kClearance = 1.5;

// A junction's ring into a chain moves out along it (to clear a close edge) only as far as the
// chain's nodes stay within this many R of the straight line from the junction.
constexpr double kStraightTolerance = 0.25;
// Layouts built at most, each making the chain nodes its chains' rings left outside junctions.
constexpr int kLayoutPasses = 4;
// Rings on either side of a chain node whose bands make the tube it is tested against.
constexpr std::size_t kTubeWindow = 3;
// Bisection steps of the tilt that makes a chain's ring clear the previous one.
constexpr int kTiltSteps = 12;

enum class NodeKind : std::uint8_t {
  kIsolated,
  kClosedLeaf,
  kOpenLeaf,
  kStraight,
  kJunction,
  kChain,
  kAbsorbed  // a closed leaf whose short edge and cap lie inside its junction's sphere
};

// What absorb_short_leaves() made of a node, before classify() gives it its kind.
enum class ShortLeafRole : std::uint8_t {
  kNone,
  kAbsorbed,  // a short leaf: no particles of its own (NodeKind::kAbsorbed)
  kHost       // the junction a short leaf hangs from: stays a junction whatever its degree
};

// n_circ particles, numbered consecutively from `first`; point k lies at angle 2 pi k / n_circ
// in the frame (u, w), counter-clockwise about u x w.
struct Ring {
  std::uint32_t first = 0;
  double radius = 0;
  Vec3 center = Vec3::Zero();
  Vec3 u = Vec3::UnitX();
  Vec3 w = Vec3::UnitY();
};

// An edge as the layout walks it: from a to b, t the unit direction, (u, w, t) right-handed.
struct EdgeFrame {
  std::uint32_t a = 0;
  std::uint32_t b = 0;
  double length = 0;
  Vec3 t = Vec3::UnitZ();
  Vec3 u = Vec3::UnitX();
  Vec3 w = Vec3::UnitY();
  std::uint32_t ring_a = kNone;  // end rings (ids into rings_)
  std::uint32_t ring_b = kNone;
  double z_a = 0;  // length along the edge taken by the end structures
  double z_b = 0;
};

double angle_between(const Vec3& a, const Vec3& b) {
  return pm::atan2(a.cross(b).norm(), a.dot(b));
}

// The minimal rotation taking unit vector `from` to unit vector `to` (not opposite), applied to
// x (Rodrigues' formula without trigonometry).
Vec3 transport(const Vec3& from, const Vec3& to, const Vec3& x) {
  const double c = from.dot(to);
  const Vec3 k = from.cross(to);
  return c * x + k.cross(x) + k * (k.dot(x) / (1.0 + c));
}

// u made orthogonal to the unit vector t and normalized, and w = t x u.
void orthonormalize(const Vec3& t, Vec3& u, Vec3& w) {
  u = (u - u.dot(t) * t).normalized();
  w = t.cross(u);
}

// The deterministic frame of a chain's first edge: from the least aligned coordinate axis.
void initial_frame(const Vec3& t, Vec3& u, Vec3& w) {
  int axis = 0;
  for (int i = 1; i < 3; ++i) {
    if (std::abs(t[i]) < std::abs(t[axis])) axis = i;
  }
  u = Vec3::Unit(axis);
  orthonormalize(t, u, w);
}

// `n` points evenly on the unit sphere (a Fibonacci spiral about the z axis).
std::vector<Vec3> fibonacci_sphere(int n) {
  std::vector<Vec3> points;
  points.reserve(static_cast<std::size_t>(n));
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * i;
    points.emplace_back(r * pm::cos(phi), r * pm::sin(phi), z);
  }
  return points;
}

using Triangle = std::array<std::uint32_t, 3>;
using DirectedEdge = std::pair<std::uint32_t, std::uint32_t>;

// True when `patch` is a consistently oriented surface whose only boundary is `loops`, each
// loop's edges used exactly once, from loop[k + 1] to loop[k]; every other edge is used once
// in each direction and no triangle repeats an index.
bool is_patch_with_loops(const std::vector<Triangle>& patch,
                         const std::vector<std::vector<std::uint32_t>>& loops) {
  std::vector<DirectedEdge> used;
  used.reserve(3 * patch.size());
  for (const Triangle& t : patch) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return false;
    for (int k = 0; k < 3; ++k) used.emplace_back(t[k], t[(k + 1) % 3]);
  }
  std::sort(used.begin(), used.end());
  if (std::adjacent_find(used.begin(), used.end()) != used.end()) return false;
  std::vector<DirectedEdge> boundary;
  for (const auto& loop : loops) {
    for (std::size_t k = 0; k < loop.size(); ++k) {
      boundary.emplace_back(loop[(k + 1) % loop.size()], loop[k]);
    }
  }
  std::sort(boundary.begin(), boundary.end());
  std::size_t found = 0;
  for (const DirectedEdge& e : used) {
    const bool has_reverse =
        std::binary_search(used.begin(), used.end(), DirectedEdge{e.second, e.first});
    const bool is_boundary = std::binary_search(boundary.begin(), boundary.end(), e);
    if (is_boundary) {
      if (has_reverse) return false;
      ++found;
    } else if (!has_reverse) {
      return false;
    }
  }
  return found == boundary.size();
}

// The boundary faces of the convex hull of `unit_points` (local coordinates, all hull vertices
// except perhaps points[0]), oriented away from the hull's interior, through the Delaunay
// tetrahedralization. Empty when it fails (duplicate points, too few points).
std::vector<Triangle> hull_faces(const std::vector<Vec3>& unit_points) {
  // Points on a sphere are cospherical: every in-sphere test of the tetrahedralization would
  // be 0 up to rounding and go to exact arithmetic. A fixed linear map (upper triangular,
  // positive diagonal: orientation-preserving) puts them on a generic ellipsoid instead; the
  // convex hull's combinatorics are invariant under it.
  Mat3 map;
  map << 1.0, 0.13, 0.07, 0.0, 1.1, 0.17, 0.0, 0.0, 1.25;
  std::vector<Vec3> points;
  points.reserve(unit_points.size());
  for (const Vec3& p : unit_points) points.push_back(map * p);
  const DelaunayResult dt = delaunay_tetrahedralize(points, {}, nullptr);
  std::vector<Triangle> faces;
  if (dt.duplicate_points != 0 || dt.tets.empty()) return faces;
  for (std::size_t t = 0; t < dt.tets.size(); ++t) {
    const auto& tet = dt.tets[t];
    for (int k = 0; k < 4; ++k) {
      if (dt.neighbors[4 * t + k] != kNone) continue;
      Triangle f{};
      int j = 0;
      for (int i = 0; i < 4; ++i) {
        if (i != k) f[j++] = tet[i];
      }
      const int side = orient3d(points[f[0]], points[f[1]], points[f[2]], points[tet[k]]);
      if (side == 0) return {};
      if (side > 0) std::swap(f[1], f[2]);
      faces.push_back(f);
    }
  }
  return faces;
}

class Builder {
 public:
  // `junctions`: sorted degree-two nodes that get a junction sphere whatever their bend.
  Builder(const ParticleLayoutInput& input, const ParticleLayoutOptions& options,
          const std::vector<std::uint32_t>& junctions)
      : s_(*input.skeleton),
        in_(input),
        o_(options),
        n_(static_cast<std::uint32_t>(options.n_circ)),
        forced_junction_(junctions) {
    for (std::uint32_t k = 0; k < n_; ++k) {
      const double angle = 2.0 * kPi * k / n_;
      cos_.push_back(pm::cos(angle));
      sin_.push_back(pm::sin(angle));
    }
    sphere_ = fibonacci_sphere(o_.n_sphere);
    sphere_spacing_ = std::sqrt(4.0 * kPi / o_.n_sphere);
  }

  ParticleLayout run() {
    classify();
    orient_edges();
    const std::size_t node_count = s_.nodes.size();
    for (std::uint32_t v = 0; v < node_count; ++v) node_rings(v);
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      if (absorbed_edge_[e] != 0) continue;
      const EdgeFrame& f = frames_[e];
      if (kind_[f.b] == NodeKind::kChain) {
        if (kind_[f.a] != NodeKind::kChain) chain_tube(e);
      } else if (kind_[f.a] != NodeKind::kChain) {
        edge_tube(e);
      }
    }
    for (std::uint32_t v = 0; v < node_count; ++v) {
      switch (kind_[v]) {
        case NodeKind::kClosedLeaf:
          cap(v);
          break;
        case NodeKind::kOpenLeaf:
          open_loop(v);
          break;
        case NodeKind::kJunction:
          junction(v);
          break;
        case NodeKind::kIsolated:
          isolated(v);
          break;
        case NodeKind::kStraight:
        case NodeKind::kChain:
        case NodeKind::kAbsorbed:
          break;
      }
    }
    return std::move(out_);
  }

  // The chain nodes whose chain's rings left them outside its tube (chain_tube), sorted.
  [[nodiscard]] std::vector<std::uint32_t> cut_off() const {
    std::vector<std::uint32_t> nodes = cut_off_;
    std::sort(nodes.begin(), nodes.end());
    return nodes;
  }

 private:
  [[nodiscard]] std::uint32_t other_end(std::uint32_t e, std::uint32_t v) const {
    return s_.edges[e][0] == v ? s_.edges[e][1] : s_.edges[e][0];
  }
  [[nodiscard]] const Vec3& pos(std::uint32_t v) const { return s_.nodes[v].position; }
  [[nodiscard]] double sphere_of(std::uint32_t v) const {
    return in_.node_sphere.empty() ? 0.0 : in_.node_sphere[v];
  }
  // Degree-two nodes the edge frames are transported through.
  [[nodiscard]] bool passes_through(std::uint32_t v) const {
    return kind_[v] == NodeKind::kStraight || kind_[v] == NodeKind::kChain;
  }
  // Unit direction of edge e from its end v toward the other end.
  [[nodiscard]] Vec3 direction_from(std::uint32_t e, std::uint32_t v) const {
    return frames_[e].a == v ? frames_[e].t : Vec3(-frames_[e].t);
  }

  void classify() {
    const std::size_t nodes = s_.nodes.size();
    incident_.assign(nodes, {});
    for (std::uint32_t e = 0; e < s_.edges.size(); ++e) {
      incident_[s_.edges[e][0]].push_back(e);
      incident_[s_.edges[e][1]].push_back(e);
    }
    absorb_short_leaves();
    const double cos_gamma = pm::cos(o_.gamma_degrees * kPi / 180.0);
    const double cos_chain = pm::cos((180.0 - kChainBendDegrees) * kPi / 180.0);
    const double cos_gentle = pm::cos((180.0 - kGentleBendDegrees) * kPi / 180.0);
    kind_.assign(nodes, NodeKind::kJunction);
    for (std::uint32_t v = 0; v < nodes; ++v) {
      const auto& inc = incident_[v];
      if (short_leaf_role_[v] == ShortLeafRole::kAbsorbed) {
        kind_[v] = NodeKind::kAbsorbed;
      } else if (short_leaf_role_[v] == ShortLeafRole::kHost) {
        kind_[v] = NodeKind::kJunction;
      } else if (inc.empty()) {
        kind_[v] = NodeKind::kIsolated;
      } else if (inc.size() == 1) {
        const bool open = !in_.open_end.empty() && in_.open_end[v] != 0;
        kind_[v] = open ? NodeKind::kOpenLeaf : NodeKind::kClosedLeaf;
      } else if (inc.size() == 2) {
        const Vec3 d0 = (pos(other_end(inc[0], v)) - pos(v)).normalized();
        const Vec3 d1 = (pos(other_end(inc[1], v)) - pos(v)).normalized();
        const double shorter = std::min((pos(other_end(inc[0], v)) - pos(v)).norm(),
                                        (pos(other_end(inc[1], v)) - pos(v)).norm());
        const double r = std::max(in_.edge_radius[inc[0]], in_.edge_radius[inc[1]]);
        if (d0.dot(d1) < cos_gentle || (d0.dot(d1) < cos_chain && shorter < o_.sphere_factor * r)) {
          kind_[v] = NodeKind::kChain;
        } else if (d0.dot(d1) < cos_gamma) {
          kind_[v] = NodeKind::kStraight;
        }
      }
    }
    for (const std::uint32_t v : forced_junction_) {
      if (kind_[v] == NodeKind::kChain || kind_[v] == NodeKind::kStraight) {
        kind_[v] = NodeKind::kJunction;
      }
    }
    // A node with a sphere of its own (a soma) is a junction whatever its degree.
    for (std::uint32_t v = 0; v < nodes; ++v) {
      if (!incident_[v].empty() && sphere_of(v) > 0 && kind_[v] != NodeKind::kAbsorbed) {
        kind_[v] = NodeKind::kJunction;
      }
    }
    // A cycle of chain nodes has no end structure to start its rings from: its nodes get the
    // paper's vertex rings (bends up to 180 - gamma) and spheres instead.
    std::vector<char> seen(nodes, 0);
    for (std::uint32_t v0 = 0; v0 < nodes; ++v0) {
      if (kind_[v0] != NodeKind::kChain || seen[v0] != 0) continue;
      std::vector<std::uint32_t> run{v0};
      seen[v0] = 1;
      bool cycle = false;
      for (const std::uint32_t first : incident_[v0]) {
        std::uint32_t e = first;
        std::uint32_t v = other_end(e, v0);
        while (kind_[v] == NodeKind::kChain) {
          if (v == v0) {
            cycle = true;
            break;
          }
          if (seen[v] != 0) break;
          seen[v] = 1;
          run.push_back(v);
          const auto& inc = incident_[v];
          e = inc[0] == e ? inc[1] : inc[0];
          v = other_end(e, v);
        }
        if (cycle) break;
      }
      if (!cycle) continue;
      for (const std::uint32_t v : run) {
        const auto& inc = incident_[v];
        const Vec3 d0 = (pos(other_end(inc[0], v)) - pos(v)).normalized();
        const Vec3 d1 = (pos(other_end(inc[1], v)) - pos(v)).normalized();
        kind_[v] = d0.dot(d1) < cos_gamma ? NodeKind::kStraight : NodeKind::kJunction;
      }
    }
  }

  // A closed leaf whose edge is shorter than the sphere of the junction it hangs from, cap
  // included (length + R < sphere_factor x the largest R of the junction's other edges), gets no
  // particles of its own: its ring and cap would lie inside that sphere, whose particles cover
  // its bulge of the surface instead. The junction keeps at least two edges and its sphere.
  void absorb_short_leaves() {
    const std::size_t nodes = s_.nodes.size();
    short_leaf_role_.assign(nodes, ShortLeafRole::kNone);
    absorbed_edge_.assign(s_.edges.size(), 0);
    for (std::uint32_t v = 0; v < nodes; ++v) {
      if (incident_[v].size() != 1 || short_leaf_role_[v] != ShortLeafRole::kNone ||
          (!in_.open_end.empty() && in_.open_end[v] != 0)) {
        continue;
      }
      const std::uint32_t e = incident_[v][0];
      const std::uint32_t w = other_end(e, v);
      auto& at_w = incident_[w];
      if (at_w.size() < 3) continue;
      double r_max = 0;
      for (const std::uint32_t k : at_w) {
        if (k != e) r_max = std::max(r_max, in_.edge_radius[k]);
      }
      const double length = (pos(w) - pos(v)).norm();
      if (!(length + in_.edge_radius[e] < o_.sphere_factor * r_max)) continue;
      at_w.erase(std::find(at_w.begin(), at_w.end(), e));
      incident_[v].clear();
      short_leaf_role_[v] = ShortLeafRole::kAbsorbed;
      short_leaf_role_[w] = ShortLeafRole::kHost;  // its sphere covers the short leaf
      absorbed_edge_[e] = 1;
    }
  }

  // Orients every edge and gives it a frame. Along a chain of straight-through nodes the edges
  // are walked head to tail and the frame is parallel-transported, so that ring point k of
  // consecutive edges and of the vertex ring between them correspond.
  void orient_edges() {
    const std::size_t edges = s_.edges.size();
    frames_.assign(edges, {});
    std::vector<char> done(absorbed_edge_.begin(), absorbed_edge_.end());
    for (std::uint32_t e0 = 0; e0 < edges; ++e0) {
      if (done[e0] != 0) continue;
      // Back to the chain's start: a node that is not straight-through, or e0 again (a cycle).
      std::uint32_t e = e0;
      std::uint32_t start = s_.edges[e0][0];
      while (passes_through(start)) {
        const auto& inc = incident_[start];
        const std::uint32_t previous = inc[0] == e ? inc[1] : inc[0];
        if (previous == e0) {
          e = e0;
          start = s_.edges[e0][0];
          break;
        }
        e = previous;
        start = other_end(e, start);
      }
      std::uint32_t v = start;
      std::uint32_t previous = kNone;
      for (;;) {
        EdgeFrame& f = frames_[e];
        f.a = v;
        f.b = other_end(e, v);
        const Vec3 d = pos(f.b) - pos(f.a);
        f.length = d.norm();
        f.t = d / f.length;
        if (previous == kNone) {
          initial_frame(f.t, f.u, f.w);
        } else {
          const EdgeFrame& p = frames_[previous];
          f.u = transport(p.t, f.t, p.u);
          orthonormalize(f.t, f.u, f.w);
        }
        done[e] = 1;
        if (!passes_through(f.b)) break;
        const auto& inc = incident_[f.b];
        const std::uint32_t next = inc[0] == e ? inc[1] : inc[0];
        if (done[next] != 0) break;  // the cycle is closed
        previous = e;
        v = f.b;
        e = next;
      }
    }
  }

  std::uint32_t add_particle(const Vec3& p, std::uint32_t node, std::uint32_t edge) {
    out_.positions.push_back(p);
    out_.node.push_back(node);
    out_.edge.push_back(edge);
    return static_cast<std::uint32_t>(out_.positions.size() - 1);
  }

  std::uint32_t add_ring(const Vec3& center, const Vec3& u, const Vec3& w, double radius,
                         std::uint32_t node, std::uint32_t edge) {
    Ring ring;
    ring.first = static_cast<std::uint32_t>(out_.positions.size());
    ring.radius = radius;
    ring.center = center;
    ring.u = u;
    ring.w = w;
    for (std::uint32_t k = 0; k < n_; ++k) {
      add_particle(center + radius * (cos_[k] * u + sin_[k] * w), node, edge);
    }
    rings_.push_back(ring);
    return static_cast<std::uint32_t>(rings_.size() - 1);
  }

  [[nodiscard]] std::uint32_t ring_point(std::uint32_t ring, std::uint32_t k) const {
    return rings_[ring].first + k % n_;
  }

  // The rings that sit at node v: the vertex ring of a straight-through node, the ring at a
  // leaf, the boundary rings of a junction; and the length each takes along its edge.
  void node_rings(std::uint32_t v) {
    const auto& inc = incident_[v];
    switch (kind_[v]) {
      case NodeKind::kIsolated:
        return;
      case NodeKind::kClosedLeaf:
      case NodeKind::kOpenLeaf: {
        const std::uint32_t e = inc[0];
        EdgeFrame& f = frames_[e];
        Vec3 u = f.u;
        Vec3 w = f.w;
        if (kind_[other_end(e, v)] == NodeKind::kChain) {
          // Into a chain: normal to the chord over kSmoothWindow radii, as the chain's rings.
          std::vector<Vec3> point;
          std::vector<double> arc;
          std::uint32_t far = 0;
          chain_polyline(e, v, point, arc, far);
          const Vec3 d = along_polyline(point, arc, kSmoothWindow * in_.edge_radius[e]) - pos(v);
          if (d.norm() > 0) {
            const Vec3 normal = f.a == v ? Vec3(d.normalized()) : Vec3(-d.normalized());
            if (std::abs(u.dot(normal)) > 0.9) u = f.w;
            orthonormalize(normal, u, w);
          }
        }
        const std::uint32_t ring = add_ring(pos(v), u, w, in_.edge_radius[e], v, e);
        (f.a == v ? f.ring_a : f.ring_b) = ring;
        return;
      }
      case NodeKind::kStraight: {
        // Edges are oriented head to tail through v: one arrives, one leaves.
        const std::uint32_t in = frames_[inc[0]].b == v ? inc[0] : inc[1];
        const std::uint32_t out = in == inc[0] ? inc[1] : inc[0];
        const EdgeFrame& fi = frames_[in];
        const EdgeFrame& fo = frames_[out];
        const Vec3 m = (fi.t + fo.t).normalized();  // normal of the symmetry plane
        Vec3 u = transport(fi.t, m, fi.u);
        Vec3 w;
        orthonormalize(m, u, w);
        const double radius = 0.5 * (in_.edge_radius[in] + in_.edge_radius[out]);
        const std::uint32_t ring = add_ring(pos(v), u, w, radius, v, std::min(in, out));
        // The tilted ring reaches radius x tan(half the bend) along each edge.
        const double c = std::clamp(fi.t.dot(m), 0.0, 1.0);
        const double extent = radius * std::sqrt(std::max(0.0, 1.0 - c * c)) / std::max(c, 0.5);
        frames_[in].ring_b = ring;
        frames_[in].z_b = extent;
        frames_[out].ring_a = ring;
        frames_[out].z_a = extent;
        return;
      }
      case NodeKind::kJunction:
        junction_rings(v);
        return;
      case NodeKind::kChain:  // chain_tube
      case NodeKind::kAbsorbed:
        return;
    }
  }

  struct Junction {
    double rho = 0;                // sphere radius
    std::vector<Vec3> directions;  // per incident edge, unit, away from v
    std::vector<double> beta;      // per incident edge, the cap angle
    bool use_fallback = false;     // incident edges too close for the hull
  };

  // Where a junction's own sphere particles start: on its sphere, or on a soma's own sphere
  // (inside the junction's): there they land on the soma near where they start instead of
  // sliding from the far sphere onto a thin neurite's tube, which folded over its first nodes
  // (a 0.6 axon on a soma of 8).
  [[nodiscard]] double patch_radius(std::uint32_t v, const Junction& j) const {
    return sphere_of(v) > 0 ? sphere_of(v) : j.rho;
  }

  // The polyline of the chain that leaves node v by edge e, through chain nodes up to the first
  // node that is not one (`far`): its points, their arc lengths from v and its edges.
  void chain_polyline(std::uint32_t e, std::uint32_t v, std::vector<Vec3>& point,
                      std::vector<double>& arc, std::uint32_t& far,
                      std::vector<std::uint32_t>* edges = nullptr) const {
    point.assign(1, pos(v));
    arc.assign(1, 0.0);
    for (;;) {
      if (edges != nullptr) edges->push_back(e);
      const std::uint32_t w = other_end(e, v);
      point.push_back(pos(w));
      arc.push_back(arc.back() + frames_[e].length);
      if (kind_[w] != NodeKind::kChain) {
        far = w;
        return;
      }
      const auto& inc = incident_[w];
      e = inc[0] == e ? inc[1] : inc[0];
      v = w;
    }
  }

  // The point at arc length s along a polyline (clamped to its ends).
  static Vec3 along_polyline(const std::vector<Vec3>& point, const std::vector<double>& arc,
                             double s) {
    s = std::clamp(s, 0.0, arc.back());
    const std::size_t k = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin()),
        arc.size() - 1);
    const std::size_t i = k - 1;
    const double span = arc[k] - arc[i];
    const double x = span > 0 ? (s - arc[i]) / span : 0.0;
    return point[i] + x * (point[k] - point[i]);
  }

  void junction_rings(std::uint32_t v) {
    const auto& inc = incident_[v];
    Junction j;
    double r_max = 0;
    for (const std::uint32_t e : inc) r_max = std::max(r_max, in_.edge_radius[e]);
    // Around a soma the sphere is the soma's times sphere_factor: the neurites' rings start
    // where their tubes leave the soma's blend.
    j.rho = o_.sphere_factor * std::max(r_max, sphere_of(v));
    // Per incident edge, the farthest its ring may go (model units from v). Into a chain, the
    // direction is the chord to the chain's point where the ring would sit (not the first edge's,
    // which may be a short connector at any angle), and the ring may go as far along the chain.
    std::vector<double> limit;
    for (const std::uint32_t e : inc) {
      const std::uint32_t w = other_end(e, v);
      if (kind_[w] != NodeKind::kChain) {
        j.directions.push_back(direction_from(e, v));
        limit.push_back((kind_[w] == NodeKind::kJunction || passes_through(w) ? kReserveShared
                                                                              : kReserveAlone) *
                        frames_[e].length);
        continue;
      }
      std::vector<Vec3> point;
      std::vector<double> arc;
      std::uint32_t far = 0;
      chain_polyline(e, v, point, arc, far);
      const double reserve =
          (kind_[far] == NodeKind::kJunction ? kReserveShared : kReserveAlone) * arc.back();
      const double r = in_.edge_radius[e];
      const double reach = std::min(std::sqrt(std::max(0.0, j.rho * j.rho - r * r)), reserve);
      Vec3 d = along_polyline(point, arc, reach) - pos(v);
      if (!(d.norm() > 0)) d = direction_from(e, v);
      j.directions.push_back(d.normalized());
      // Beyond `reach`, the ring may move out (to clear a close edge) only as far as the chain
      // runs straight: its nodes within kStraightTolerance x R of the line from v.
      double straight = reach;
      for (std::size_t k = 1; k < point.size() && arc[k] <= reserve; ++k) {
        const Vec3 axis = (point[k] - pos(v)).normalized();
        bool within = true;
        for (std::size_t i = 1; i < k && within; ++i) {
          const Vec3 off = point[i] - pos(v);
          within = (off - off.dot(axis) * axis).norm() <= kStraightTolerance * r;
        }
        if (!within) break;
        straight = std::max(straight, arc[k]);
      }
      limit.push_back((along_polyline(point, arc, std::min(straight, reserve)) - pos(v)).norm());
    }
    for (std::size_t i = 0; i < inc.size(); ++i) {
      double nearest = kPi;
      for (std::size_t k = 0; k < inc.size(); ++k) {
        if (k != i) nearest = std::min(nearest, angle_between(j.directions[i], j.directions[k]));
      }
      if (nearest < kMinForkAngle) j.use_fallback = true;
      const double beta = std::min(pm::asin(std::min(1.0, in_.edge_radius[inc[i]] / j.rho)),
                                   kCapShare * std::max(nearest, kMinForkAngle));
      j.beta.push_back(beta);
      const std::uint32_t e = inc[i];
      EdgeFrame& f = frames_[e];
      const double tan_beta = pm::tan(beta);
      const double along = std::min(in_.edge_radius[e] / tan_beta, limit[i]);
      // The ring's frame: (u, w, t') right-handed with t' along the edge's orientation.
      const Vec3 normal = f.a == v ? j.directions[i] : Vec3(-j.directions[i]);
      Vec3 u = f.u;
      Vec3 w;
      if (std::abs(u.dot(normal)) > 0.9) u = f.w;
      orthonormalize(normal, u, w);
      const std::uint32_t ring =
          add_ring(pos(v) + along * j.directions[i], u, w, along * tan_beta, v, e);
      if (f.a == v) {
        f.ring_a = ring;
        f.z_a = along;
      } else {
        f.ring_b = ring;
        f.z_b = along;
      }
    }
    junctions_.emplace(v, std::move(j));
  }

  // Joins ring A to ring B, B further along `t` than A, both counter-clockwise about t. B's
  // numbering is shifted to A's frame (they agree except where a cycle of straight-through
  // nodes closes with the transported frame turned).
  void band(std::uint32_t ring_a, std::uint32_t ring_b) {
    band_triangles(rings_[ring_a], rings_[ring_b], out_.positions, out_.triangles);
  }

  // band's triangles between two rings whose points are numbered from their `first` in `p`.
  void band_triangles(const Ring& A, const Ring& B, const std::vector<Vec3>& p,
                      std::vector<Triangle>& triangles) const {
    const double phi = pm::atan2(B.u.dot(A.w), B.u.dot(A.u));
    const auto shift = static_cast<long long>(std::llround(phi * n_ / (2.0 * kPi)));
    const auto offset = static_cast<std::uint32_t>(((-shift) % n_ + n_) % n_);
    for (std::uint32_t k = 0; k < n_; ++k) {
      const std::uint32_t a0 = A.first + k % n_;
      const std::uint32_t a1 = A.first + (k + 1) % n_;
      const std::uint32_t b0 = B.first + (k + offset) % n_;
      const std::uint32_t b1 = B.first + (k + 1 + offset) % n_;
      if ((p[a0] - p[b1]).squaredNorm() <= (p[a1] - p[b0]).squaredNorm()) {
        triangles.push_back({a0, a1, b1});
        triangles.push_back({a0, b1, b0});
      } else {
        triangles.push_back({a0, a1, b0});
        triangles.push_back({a1, b1, b0});
      }
    }
  }

  // A fan from ring `ring` to `apex`, the apex beyond it along t (`apex_after`) or before it.
  void fan(std::uint32_t ring, std::uint32_t apex, bool apex_after) {
    for (std::uint32_t k = 0; k < n_; ++k) {
      const std::uint32_t r0 = ring_point(ring, k);
      const std::uint32_t r1 = ring_point(ring, k + 1);
      if (apex_after) {
        out_.triangles.push_back({r0, r1, apex});
      } else {
        out_.triangles.push_back({apex, r1, r0});
      }
    }
  }

  // The interior rings of edge e, at its charges clear of both end structures, and the bands
  // between consecutive rings.
  void edge_tube(std::uint32_t e) {
    const EdgeFrame f = frames_[e];
    const double radius = in_.edge_radius[e];
    const std::size_t count = edge_charge_count(f.length, in_.edge_spacing[e]);
    const double step = f.length / static_cast<double>(count + 1);
    const double margin = kRingMargin * step;
    std::uint32_t last = f.ring_a;
    for (std::size_t k = 1; k <= count; ++k) {
      const double along = step * static_cast<double>(k);
      if (along <= f.z_a + margin || along >= f.length - f.z_b - margin) continue;
      const std::uint32_t node = along <= 0.5 * f.length ? f.a : f.b;
      const std::uint32_t ring = add_ring(pos(f.a) + along * f.t, f.u, f.w, radius, node, e);
      band(last, ring);
      last = ring;
    }
    band(last, f.ring_b);
  }

  // A ring as the chain's clearance test sees it: centre, unit normal (forward), radius.
  struct Disk {
    Vec3 center;
    Vec3 normal;
    double radius = 0;
  };

  // True when disk b, ahead of disk a, and a are disjoint and in order even when both radii are
  // scaled by kClearance: every point of b lies ahead of a's plane, every point of a behind b's.
  static bool clear(const Disk& a, const Disk& b) {
    const double c = a.normal.dot(b.normal);
    if (!(c > 0)) return false;
    const double sine = std::sqrt(std::max(0.0, 1.0 - c * c));
    const Vec3 d = b.center - a.center;
    return d.dot(a.normal) > kClearance * b.radius * sine &&
           d.dot(b.normal) > kClearance * a.radius * sine;
  }

  // The rings along a chain of degree-two nodes that starts with edge `first` (from a node that
  // is not a chain node, to the next one that is not): one at every charge and every chain node,
  // centred on the polyline and normal to its chord over kSmoothWindow radii on either side, less
  // those that would cross the previous ring kept or the end structure's ring (kClearance).
  void chain_tube(std::uint32_t first) {
    std::vector<Vec3> point;
    std::vector<double> arc;
    std::vector<std::uint32_t> chain;
    std::uint32_t far = 0;
    chain_polyline(first, frames_[first].a, point, arc, far, &chain);
    const double total = arc.back();
    const auto at = [&](double s) { return along_polyline(point, arc, s); };
    const EdgeFrame& f0 = frames_[first];
    const EdgeFrame& f1 = frames_[chain.back()];
    const Ring& start = rings_[f0.ring_a];
    const Ring& end = rings_[f1.ring_b];
    struct Station {
      Disk disk;
      std::uint32_t node;
      std::uint32_t edge;
      bool at_node;  // centred on a chain node: kept, so that the node stays inside the tube
      double arc;    // arc length along the chain
    };
    // Every station, its normal the chord's.
    std::vector<Station> stations;
    const auto station = [&](double s, double radius, std::uint32_t node, std::uint32_t edge,
                             bool at_node) {
      if (s <= f0.z_a || s >= total - f1.z_b) return;
      const Vec3 chord = at(s + kSmoothWindow * radius) - at(s - kSmoothWindow * radius);
      const double norm = chord.norm();
      if (norm > 0) stations.push_back({{at(s), chord / norm, radius}, node, edge, at_node, s});
    };
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const std::uint32_t e = chain[k];
      const EdgeFrame& f = frames_[e];
      if (k > 0) {
        const std::uint32_t before = chain[k - 1];
        station(arc[k], 0.5 * (in_.edge_radius[before] + in_.edge_radius[e]), f.a,
                std::min(before, e), true);
      }
      const std::size_t count = edge_charge_count(f.length, in_.edge_spacing[e]);
      const double step = f.length / static_cast<double>(count + 1);
      for (std::size_t i = 1; i <= count; ++i) {
        const double along = step * static_cast<double>(i);
        station(arc[k] + along, in_.edge_radius[e], along <= 0.5 * f.length ? f.a : f.b, e, false);
      }
    }
    // Tilts `disk` back toward the normal of `last` as little as makes it clear `last`
    // (bisection on the blend of the normals); false when not even `last`'s normal clears it.
    const auto fit = [](const Disk& last, Disk& disk) {
      if (clear(last, disk)) return true;
      const Vec3 wanted = disk.normal;
      disk.normal = last.normal;
      if (!clear(last, disk)) return false;
      double lo = 0;
      double hi = 1;
      for (int k = 0; k < kTiltSteps; ++k) {
        const double mid = 0.5 * (lo + hi);
        Disk trial = disk;
        trial.normal = (last.normal + mid * (wanted - last.normal)).normalized();
        (clear(last, trial) ? lo : hi) = mid;
      }
      disk.normal = (last.normal + lo * (wanted - last.normal)).normalized();
      return true;
    };
    // From each end toward the middle, keep the stations that clear the last ring kept, each
    // tilted as `fit` does. A station between nodes that does not is left out. A station at a
    // node is not: the rings kept before it that are between nodes are left out instead, from
    // the last back, until it clears (a band spanning a node's corner cuts the node off). If it
    // still does not (the previous ring is at a node too), it is left out. The backward half
    // runs with reversed normals.
    const auto sweep = [&](const Disk& begin, auto first, auto stop) {
      std::vector<Station> kept;
      for (auto it = first; it != stop; ++it) {
        Station st = *it;
        bool fits = fit(kept.empty() ? begin : kept.back().disk, st.disk);
        while (!fits && st.at_node && !kept.empty() && !kept.back().at_node) {
          kept.pop_back();
          st = *it;
          fits = fit(kept.empty() ? begin : kept.back().disk, st.disk);
        }
        if (fits) kept.push_back(st);
      }
      return kept;
    };
    const Disk begin_disk{start.center, start.u.cross(start.w), start.radius};
    const Disk finish{end.center, end.u.cross(end.w), end.radius};
    const Disk finish_back{finish.center, -finish.normal, finish.radius};
    const std::size_t half = stations.size() / 2;
    // Where the halves meet, rings are left out until the last of each clears the other: the
    // one nearer the middle unless only the other is between nodes. When no pair clears (the
    // chain turns back on itself), every ring stays: one band spanning the whole chain would cut
    // its nodes off.
    std::vector<Station> kept =
        sweep(begin_disk, stations.begin(), stations.begin() + static_cast<std::ptrdiff_t>(half));
    for (Station& st : stations) st.disk.normal = -st.disk.normal;
    std::vector<Station> back =
        sweep(finish_back, stations.rbegin(), stations.rend() - static_cast<std::ptrdiff_t>(half));
    for (Station& st : back) st.disk.normal = -st.disk.normal;
    std::size_t i = kept.size();
    std::size_t j = back.size();
    for (;;) {
      const Disk& a = i == 0 ? begin_disk : kept[i - 1].disk;
      const Disk& b = j == 0 ? finish : back[j - 1].disk;
      if (clear(a, b)) break;
      if (i == 0 && j == 0) {
        i = kept.size();
        j = back.size();
        break;
      }
      const bool node_a = i == 0 || kept[i - 1].at_node;
      const bool node_b = j == 0 || back[j - 1].at_node;
      bool drop_a = i >= j;
      if (node_a != node_b) drop_a = node_b;
      (drop_a ? i : j) -= 1;
    }
    kept.resize(i);
    kept.insert(kept.end(), back.rend() - static_cast<std::ptrdiff_t>(j), back.rend());
    // The rings kept, framed as they will be built: u transported from the start ring's along
    // the normals.
    std::vector<Ring> all{start};
    {
      Vec3 normal = begin_disk.normal;
      Vec3 u = start.u;
      for (const Station& st : kept) {
        u = transport(normal, st.disk.normal, u);
        normal = st.disk.normal;
        Ring ring;
        ring.center = st.disk.center;
        ring.radius = st.disk.radius;
        orthonormalize(normal, u, ring.w);
        ring.u = u;
        all.push_back(ring);
      }
    }
    all.push_back(end);
    // The chain's nodes beyond the end structures that lie outside the tube of these rings are
    // cut off by a band across their corner: the next layout makes them junctions. The tube
    // near a node is that of the kTubeWindow rings on either side of it, closed by a fan across
    // each end ring (generalized winding number).
    {
      std::vector<double> ring_arc{0.0};
      for (const Station& st : kept) ring_arc.push_back(st.arc);
      ring_arc.push_back(total);
      for (std::size_t k = 1; k < chain.size(); ++k) {
        if (arc[k] <= f0.z_a || arc[k] >= total - f1.z_b) continue;
        const auto next = static_cast<std::size_t>(
            std::lower_bound(ring_arc.begin(), ring_arc.end(), arc[k]) - ring_arc.begin());
        const std::size_t lo = next > kTubeWindow ? next - kTubeWindow : 0;
        const std::size_t hi = std::min(next + kTubeWindow - 1, all.size() - 1);
        TriMesh tube;
        std::vector<Ring> piece(all.begin() + static_cast<std::ptrdiff_t>(lo),
                                all.begin() + static_cast<std::ptrdiff_t>(hi) + 1);
        for (Ring& ring : piece) {
          ring.first = static_cast<std::uint32_t>(tube.positions.size());
          for (std::uint32_t i = 0; i < n_; ++i) {
            tube.positions.push_back(ring.center +
                                     ring.radius * (cos_[i] * ring.u + sin_[i] * ring.w));
          }
        }
        for (std::size_t i = 0; i + 1 < piece.size(); ++i) {
          band_triangles(piece[i], piece[i + 1], tube.positions, tube.triangles);
        }
        const auto centre = static_cast<std::uint32_t>(tube.positions.size());
        tube.positions.push_back(piece.front().center);
        tube.positions.push_back(piece.back().center);
        for (std::uint32_t i = 0; i < n_; ++i) {
          tube.triangles.push_back(
              {centre, piece.front().first + (i + 1) % n_, piece.front().first + i});
          tube.triangles.push_back(
              {piece.back().first + i, piece.back().first + (i + 1) % n_, centre + 1});
        }
        if (!(std::abs(winding_number(tube, point[k])) > 0.5)) {
          cut_off_.push_back(frames_[chain[k]].a);
        }
      }
    }
    std::uint32_t previous = f0.ring_a;
    for (std::size_t k = 0; k < kept.size(); ++k) {
      const Ring& r = all[k + 1];
      const std::uint32_t ring = add_ring(r.center, r.u, r.w, r.radius, kept[k].node, kept[k].edge);
      band(previous, ring);
      previous = ring;
    }
    band(previous, f1.ring_b);
  }

  // A half-sphere of radius R beyond the leaf: latitude rings and a pole.
  void cap(std::uint32_t v) {
    const std::uint32_t e = incident_[v][0];
    const EdgeFrame& f = frames_[e];
    const bool outward_is_t = f.b == v;  // the cap continues along the ring's normal
    const std::uint32_t equator = outward_is_t ? f.ring_b : f.ring_a;
    const Vec3 u = rings_[equator].u;
    const Vec3 w = rings_[equator].w;
    const Vec3 normal = u.cross(w);
    const Vec3 out = outward_is_t ? normal : Vec3(-normal);
    const double radius = in_.edge_radius[e];
    const int latitudes = std::max(1, o_.n_circ / 4);
    std::uint32_t last = equator;
    for (int i = 1; i <= latitudes; ++i) {
      const double phi = 0.5 * kPi * i / (latitudes + 1);
      const std::uint32_t ring =
          add_ring(pos(v) + radius * pm::sin(phi) * out, u, w, radius * pm::cos(phi), v, e);
      if (outward_is_t) {
        band(last, ring);
      } else {
        band(ring, last);
      }
      last = ring;
    }
    const std::uint32_t pole = add_particle(pos(v) + radius * out, v, kNone);
    fan(last, pole, outward_is_t);
  }

  void open_loop(std::uint32_t v) {
    const std::uint32_t e = incident_[v][0];
    const EdgeFrame& f = frames_[e];
    const std::uint32_t ring = f.b == v ? f.ring_b : f.ring_a;
    std::vector<std::uint32_t> loop;
    for (std::uint32_t k = 0; k < n_; ++k) loop.push_back(ring_point(ring, k));
    out_.open_loops.push_back(std::move(loop));
    out_.open_loop_node.push_back(v);
  }

  // The sphere with one hole per incident edge around junction v: the convex hull of the ring
  // and sphere points projected onto the unit sphere around v, less the disks spanned by the
  // rings (Delaunay, exact predicates). Checked; the combinatorial patch when the check fails.
  void junction(std::uint32_t v) {
    const Junction& j = junctions_.at(v);
    const auto& inc = incident_[v];
    // Per incident edge, its ring counter-clockwise about the outward direction: the patch
    // must use the ring's edges from loop[k + 1] to loop[k].
    std::vector<std::vector<std::uint32_t>> loops;
    for (const std::uint32_t e : inc) {
      const EdgeFrame& f = frames_[e];
      const std::uint32_t ring = f.a == v ? f.ring_a : f.ring_b;
      std::vector<std::uint32_t> loop(n_);
      for (std::uint32_t k = 0; k < n_; ++k) {
        loop[k] = ring_point(ring, f.a == v ? k : n_ - k);
      }
      loops.push_back(std::move(loop));
    }
    if (!j.use_fallback && hull_patch(v, j, loops)) return;
    ++out_.fallback_junctions;
    combinatorial_patch(v, j, loops);
  }

  bool hull_patch(std::uint32_t v, const Junction& j,
                  const std::vector<std::vector<std::uint32_t>>& loops) {
    // Local points: [center], the rings' points, the sphere points outside every cap.
    std::vector<Vec3> local;
    std::vector<std::uint32_t> global;  // per local point, its particle (kNone: not yet one)
    std::vector<std::int32_t> ring_of;  // per local point, its loop or -1
    local.push_back(Vec3::Zero());
    global.push_back(kNone);
    ring_of.push_back(-1);
    for (std::size_t i = 0; i < loops.size(); ++i) {
      for (const std::uint32_t p : loops[i]) {
        local.push_back((out_.positions[p] - pos(v)).normalized());
        global.push_back(p);
        ring_of.push_back(static_cast<std::int32_t>(i));
      }
    }
    // A soma's sphere is far larger than its neurites' rings: its points are spaced as the
    // thinnest neurite's ring points are (at the soma's own radius; at most 20,000), not
    // n_sphere over it (coarser, a thin axon's hole was bridged by long triangles).
    std::vector<Vec3> soma_points;
    double spacing = sphere_spacing_;
    if (sphere_of(v) > 0) {
      double r_edge = std::numeric_limits<double>::infinity();
      for (const std::uint32_t e : incident_[v]) r_edge = std::min(r_edge, in_.edge_radius[e]);
      const double ring_spacing = 2 * kPi * r_edge / n_;
      const double count = 4 * kPi * sphere_of(v) * sphere_of(v) / (ring_spacing * ring_spacing);
      const int n = static_cast<int>(
          std::clamp(std::round(count), static_cast<double>(o_.n_sphere), 20000.0));
      soma_points = fibonacci_sphere(n);
      spacing = std::sqrt(4.0 * kPi / n);
    }
    const std::vector<Vec3>& sphere = soma_points.empty() ? sphere_ : soma_points;
    std::vector<double> cos_exclusion;
    for (const double beta : j.beta) {
      const double exclusion =
          std::min(std::max(kCapExclusion * beta, beta + kCapGap * spacing), kPi);
      cos_exclusion.push_back(pm::cos(exclusion));
    }
    const std::size_t first_sphere = local.size();
    for (const Vec3& p : sphere) {
      bool inside_cap = false;
      for (std::size_t i = 0; i < j.directions.size(); ++i) {
        if (p.dot(j.directions[i]) > cos_exclusion[i]) inside_cap = true;
      }
      if (inside_cap) continue;
      local.push_back(p);
      global.push_back(kNone);
      ring_of.push_back(-1);
    }
    // With the center the tetrahedra are cones from it, far from the cospherical degeneracy;
    // without it when the center is not inside the hull.
    for (const bool with_center : {true, false}) {
      std::vector<Vec3> points = local;
      std::size_t skip = 0;
      if (!with_center) {
        points.erase(points.begin());
        skip = 1;
      }
      std::vector<Triangle> faces = hull_faces(points);
      if (faces.empty()) continue;
      std::vector<Triangle> patch;
      bool touches_center = false;
      for (Triangle f : faces) {
        for (auto& x : f) x += static_cast<std::uint32_t>(skip);
        if (f[0] == 0 || f[1] == 0 || f[2] == 0) touches_center = true;
        const std::int32_t r = ring_of[f[0]];
        if (r >= 0 && ring_of[f[1]] == r && ring_of[f[2]] == r) continue;  // a ring's disk
        patch.push_back(f);
      }
      if (touches_center) continue;
      // Check in local numbering with the ring points given their particles' numbers: sphere
      // points get numbers above every particle for now.
      std::vector<std::uint32_t> id = global;
      const auto base = static_cast<std::uint32_t>(out_.positions.size());
      for (std::size_t i = first_sphere; i < id.size(); ++i) {
        id[i] = base + static_cast<std::uint32_t>(i - first_sphere);
      }
      std::vector<Triangle> mapped;
      for (const Triangle& f : patch) mapped.push_back({id[f[0]], id[f[1]], id[f[2]]});
      if (!is_patch_with_loops(mapped, loops)) continue;
      // The sphere points the hull uses become particles (others lie inside it, none should).
      std::vector<std::uint32_t> particle(local.size(), kNone);
      for (std::size_t i = 0; i < first_sphere; ++i) particle[i] = global[i];
      for (const Triangle& f : patch) {
        for (const std::uint32_t x : f) {
          if (particle[x] == kNone) {
            particle[x] = add_particle(pos(v) + patch_radius(v, j) * local[x], v, kNone);
          }
        }
      }
      for (const Triangle& f : patch) {
        out_.triangles.push_back({particle[f[0]], particle[f[1]], particle[f[2]]});
      }
      return true;
    }
    return false;
  }

  // A sphere with one hole per loop, by construction (for junctions the hull cannot join):
  // poles N and S on an axis away from the edges; each loop's upper arc fans to N, its lower
  // arc to S, and consecutive loops (by azimuth about the axis) are joined by an edge with one
  // triangle towards each pole. Euler characteristic 2 - m for m loops; needs m >= 2.
  void combinatorial_patch(std::uint32_t v, const Junction& j,
                           const std::vector<std::vector<std::uint32_t>>& loops) {
    Vec3 axis = Vec3::UnitZ();
    double best = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 6; ++a) {
      const Vec3 candidate = (a % 2 == 0 ? 1.0 : -1.0) * Vec3::Unit(a / 2);
      double worst = -1;
      for (const Vec3& d : j.directions) worst = std::max(worst, candidate.dot(d));
      if (worst < best) {
        best = worst;
        axis = candidate;
      }
    }
    Vec3 x;
    Vec3 y;
    initial_frame(axis, x, y);
    const std::size_t m = loops.size();
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t i = 0; i < m; ++i) {
      order.emplace_back(pm::atan2(j.directions[i].dot(y), j.directions[i].dot(x)), i);
    }
    std::sort(order.begin(), order.end());
    const std::uint32_t north = add_particle(pos(v) + patch_radius(v, j) * axis, v, kNone);
    const std::uint32_t south = add_particle(pos(v) - patch_radius(v, j) * axis, v, kNone);
    const std::uint32_t h = n_ / 2;
    // Per loop, its points rotated so that the upper arc q[0..h] faces the north pole.
    std::vector<std::vector<std::uint32_t>> q(m);
    for (std::size_t i = 0; i < m; ++i) {
      const auto& loop = loops[order[i].second];
      std::uint32_t top = 0;
      for (std::uint32_t k = 1; k < n_; ++k) {
        if (out_.positions[loop[k]].dot(axis) > out_.positions[loop[top]].dot(axis)) top = k;
      }
      const std::uint32_t start = (top + n_ - h / 2) % n_;
      for (std::uint32_t k = 0; k <= n_; ++k) q[i].push_back(loop[(start + k) % n_]);
    }
    for (std::size_t i = 0; i < m; ++i) {
      for (std::uint32_t k = 0; k < h; ++k) out_.triangles.push_back({north, q[i][k + 1], q[i][k]});
      for (std::uint32_t k = h; k < n_; ++k) {
        out_.triangles.push_back({south, q[i][k + 1], q[i][k]});
      }
      const auto& next = q[(i + 1) % m];
      out_.triangles.push_back({north, q[i][0], next[h]});
      out_.triangles.push_back({south, next[h], q[i][0]});
    }
  }

  // An isolated node: the convex hull of n_sphere points on a sphere of its radius (an
  // octahedron should that ever fail).
  void isolated(std::uint32_t v) {
    const double radius = s_.nodes[v].radius;
    std::vector<Vec3> local{Vec3::Zero()};
    local.insert(local.end(), sphere_.begin(), sphere_.end());
    std::vector<Triangle> faces = hull_faces(local);
    bool valid = !faces.empty();
    for (const Triangle& f : faces) {
      if (f[0] == 0 || f[1] == 0 || f[2] == 0) valid = false;
    }
    valid = valid && is_patch_with_loops(faces, {});
    if (!valid) {
      ++out_.fallback_junctions;
      local = {Vec3::Zero(),   Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(),
               -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
      faces = {{1, 3, 5}, {3, 2, 5}, {2, 4, 5}, {4, 1, 5},
               {3, 1, 6}, {2, 3, 6}, {4, 2, 6}, {1, 4, 6}};
    }
    std::vector<std::uint32_t> particle(local.size(), kNone);
    for (const Triangle& f : faces) {
      for (const std::uint32_t x : f) {
        if (particle[x] == kNone) particle[x] = add_particle(pos(v) + radius * local[x], v, kNone);
      }
      out_.triangles.push_back({particle[f[0]], particle[f[1]], particle[f[2]]});
    }
  }

  const Skeleton& s_;
  const ParticleLayoutInput& in_;
  const ParticleLayoutOptions& o_;
  const std::uint32_t n_;
  std::vector<double> cos_;
  std::vector<double> sin_;
  std::vector<Vec3> sphere_;
  double sphere_spacing_ = 0;
  std::vector<std::vector<std::uint32_t>> incident_;
  std::vector<NodeKind> kind_;
  std::vector<ShortLeafRole> short_leaf_role_;
  std::vector<char> absorbed_edge_;
  std::vector<EdgeFrame> frames_;
  std::vector<Ring> rings_;
  std::map<std::uint32_t, Junction> junctions_;
  const std::vector<std::uint32_t>& forced_junction_;
  std::vector<std::uint32_t> cut_off_;
  ParticleLayout out_;
};

void check(const ParticleLayoutInput& in, const ParticleLayoutOptions& o) {
  if (o.n_circ < 3) {
    throw InvalidArgument("build_particle_layout: n_circ must be >= 3, got " +
                          std::to_string(o.n_circ));
  }
  if (o.n_sphere < 4) {
    throw InvalidArgument("build_particle_layout: n_sphere must be >= 4, got " +
                          std::to_string(o.n_sphere));
  }
  if (!std::isfinite(o.sphere_factor) || !(o.sphere_factor > 1)) {
    throw InvalidArgument("build_particle_layout: sphere_factor must be finite and > 1, got " +
                          std::to_string(o.sphere_factor));
  }
  if (!(o.gamma_degrees > 0 && o.gamma_degrees <= 180)) {
    throw InvalidArgument("build_particle_layout: gamma_degrees must be in (0, 180], got " +
                          std::to_string(o.gamma_degrees));
  }
  if (in.skeleton == nullptr) throw InvalidArgument("build_particle_layout: no skeleton");
  const Skeleton& s = *in.skeleton;
  validate(s);
  const std::size_t edges = s.edges.size();
  if (in.edge_radius.size() != edges || in.edge_spacing.size() != edges) {
    throw InvalidArgument(
        "build_particle_layout: edge_radius and edge_spacing need one value "
        "per edge (" +
        std::to_string(edges) + "), got " + std::to_string(in.edge_radius.size()) + " and " +
        std::to_string(in.edge_spacing.size()));
  }
  for (std::size_t e = 0; e < edges; ++e) {
    if (!std::isfinite(in.edge_radius[e]) || !(in.edge_radius[e] > 0)) {
      throw InvalidArgument("build_particle_layout: edge_radius of edge " + std::to_string(e) +
                            " must be finite and > 0, got " + std::to_string(in.edge_radius[e]));
    }
    if (!std::isfinite(in.edge_spacing[e]) || !(in.edge_spacing[e] > 0)) {
      throw InvalidArgument("build_particle_layout: edge_spacing of edge " + std::to_string(e) +
                            " must be finite and > 0, got " + std::to_string(in.edge_spacing[e]));
    }
  }
  if (!in.node_sphere.empty() && in.node_sphere.size() != s.nodes.size()) {
    throw InvalidArgument(
        "build_particle_layout: node_sphere must be empty or have one entry per node (" +
        std::to_string(s.nodes.size()) + "), got " + std::to_string(in.node_sphere.size()));
  }
  if (!in.open_end.empty() && in.open_end.size() != s.nodes.size()) {
    throw InvalidArgument(
        "build_particle_layout: open_end must be empty or have one entry per "
        "node (" +
        std::to_string(s.nodes.size()) + "), got " + std::to_string(in.open_end.size()));
  }
}

}  // namespace

ParticleLayout build_particle_layout(const ParticleLayoutInput& input,
                                     const ParticleLayoutOptions& options) {
  check(input, options);
  // A chain node that its chain's rings cannot keep inside becomes a junction, whose sphere
  // surrounds it, and the layout is built again (its neighbours' chains change: repeated while
  // new ones appear, at most kLayoutPasses times).
  std::vector<std::uint32_t> junctions;
  for (int pass = 1;; ++pass) {
    Builder builder(input, options, junctions);
    ParticleLayout layout = builder.run();
    const std::vector<std::uint32_t> cut = builder.cut_off();
    if (cut.empty() || pass == kLayoutPasses) return layout;
    std::vector<std::uint32_t> merged;
    std::set_union(junctions.begin(), junctions.end(), cut.begin(), cut.end(),
                   std::back_inserter(merged));
    junctions = std::move(merged);
  }
}

}  // namespace ramiform::detail
