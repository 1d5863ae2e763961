// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/coarsen.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numbers>
#include <queue>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "field/bvh.h"
#include "polygonize/in_tetrahedron.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"
#include "ramiform/mesh/deviation.h"

namespace ramiform {
namespace {

using detail::in_tetrahedron;
using Tri = std::array<std::uint32_t, 3>;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr double kDeg = std::numbers::pi / 180.0;
// Newton steps onto the surface, as refine_to_surface() and improve_triangles() take them.
constexpr int kNewtonSteps = 8;
constexpr double kNewtonStop = 3e-3;
constexpr std::size_t kCheckEvery = 4096;  // heap entries between cancellation checks
// The weight of the squared edge length (in local radii) in a quadric priority.
constexpr double kLengthWeight = 1e-2;

void validate(const CoarsenOptions& o) {
  if (o.max_triangles == 0) throw InvalidArgument("coarsen: max_triangles must be > 0");
  if (!(o.min_angle_deg >= 0.0 && o.min_angle_deg < 60.0)) {
    throw InvalidArgument("coarsen: min_angle_deg must be in [0, 60), got " +
                          format_number(o.min_angle_deg));
  }
  if (!(o.max_turn_deg > 0.0 && o.max_turn_deg <= 90.0)) {
    throw InvalidArgument("coarsen: max_turn_deg must be in (0, 90], got " +
                          format_number(o.max_turn_deg));
  }
  if (!(o.max_deviation > 0.0) || !std::isfinite(o.max_deviation)) {
    throw InvalidArgument("coarsen: max_deviation must be finite and > 0, got " +
                          format_number(o.max_deviation));
  }
}

// The sine of the smallest corner angle of the triangle a, b, c (at most 60 degrees, where the
// sine increases with the angle); 0 when degenerate.
double min_angle_sine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, bc = c - b, ca = a - c;
  const double lab = ab.squaredNorm(), lbc = bc.squaredNorm(), lca = ca.squaredNorm();
  const double cross = ab.cross(-ca).norm();
  if (!(cross > tol::kCoincident * std::max({lab, lbc, lca}))) return 0.0;
  if (lbc <= lab && lbc <= lca) return cross / std::sqrt(lab * lca);
  if (lca <= lab) return cross / std::sqrt(lab * lbc);
  return cross / std::sqrt(lbc * lca);
}

// A plane quadric (Garland & Heckbert 1997): the sum of squared distances to planes,
// x^T A x + 2 b.x + c, A symmetric (xx, xy, xz, yy, yz, zz).
struct Quadric {
  std::array<double, 6> A{};
  Vec3 b = Vec3::Zero();
  double c = 0;
  void add_plane(const Vec3& n, double d) {  // n.x + d = 0, |n| = 1
    A[0] += n.x() * n.x();
    A[1] += n.x() * n.y();
    A[2] += n.x() * n.z();
    A[3] += n.y() * n.y();
    A[4] += n.y() * n.z();
    A[5] += n.z() * n.z();
    b += d * n;
    c += d * d;
  }
  Quadric& operator+=(const Quadric& q) {
    for (int i = 0; i < 6; ++i) A[i] += q.A[i];
    b += q.b;
    c += q.c;
    return *this;
  }
  [[nodiscard]] double at(const Vec3& x) const {
    const double ax = A[0] * x.x() + A[1] * x.y() + A[2] * x.z();
    const double ay = A[1] * x.x() + A[3] * x.y() + A[4] * x.z();
    const double az = A[2] * x.x() + A[4] * x.y() + A[5] * x.z();
    return std::max(0.0, x.dot(Vec3(ax, ay, az)) + 2.0 * b.dot(x) + c);
  }
};

// A queued edge (a < b) with the stamps of its end points when it was queued: it is stale when
// either has changed since.
struct Entry {
  double priority;
  std::uint32_t a, b;
  std::uint32_t stamp_a, stamp_b;
};
struct Later {
  bool operator()(const Entry& x, const Entry& y) const {
    if (x.priority != y.priority) return x.priority > y.priority;
    if (x.a != y.a) return x.a > y.a;
    return x.b > y.b;
  }
};

class Coarsener {
 public:
  Coarsener(TriMesh& mesh, const Field& field, const Skeleton& skeleton, const CoarsenOptions& o,
            Context* ctx)
      : mesh_(mesh),
        pos_(mesh.positions),
        field_(field),
        skeleton_(skeleton),
        o_(o),
        ctx_(ctx),
        sin_floor_(pm::sin(o.min_angle_deg * kDeg)),
        cos_turn_(pm::cos(o.max_turn_deg * kDeg)),
        alive_(mesh.triangles.size(), 1),
        fan_(mesh.positions.size()),
        stamp_(mesh.positions.size(), 0) {
    const std::size_t nv = pos_.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (const std::uint32_t v : mesh.triangles[t]) {
        if (v >= nv) {
          throw InvalidArgument("coarsen: triangle " + std::to_string(t) + " has vertex " +
                                std::to_string(v) + " of " + std::to_string(nv));
        }
        fan_[v].push_back(static_cast<std::uint32_t>(t));
      }
    }
    radius_ = local_radii(skeleton, pos_, ctx);
    quadric_.resize(nv);
    if (o.priority == CoarsenPriority::kQuadric) {
      for (const Tri& f : mesh.triangles) {
        const Vec3 n = (pos_[f[1]] - pos_[f[0]]).cross(pos_[f[2]] - pos_[f[0]]);
        const double len = n.norm();
        if (!(len > 0.0)) continue;
        const Vec3 u = n / len;
        for (const std::uint32_t v : f) quadric_[v].add_plane(u, -u.dot(pos_[f[0]]));
      }
    }
    std::vector<Aabb> boxes;
    boxes.reserve(skeleton.nodes.size());
    for (const auto& n : skeleton.nodes) boxes.emplace_back(n.position, n.position);
    nodes_ = detail::BoxBvh(std::move(boxes));
    count_ = mesh.triangles.size();
    for (const Tri& f : mesh.triangles) {
      for (int k = 0; k < 3; ++k) {
        if (f[k] < f[(k + 1) % 3]) push(f[k], f[(k + 1) % 3]);
      }
    }
  }

  void run(CoarsenStats& st) {
    std::size_t popped = 0;
    while (count_ > o_.max_triangles && !heap_.empty()) {
      if (++popped % kCheckEvery == 0) check_cancel(ctx_);
      const Entry e = heap_.top();
      heap_.pop();
      if (stamp_[e.a] != e.stamp_a || stamp_[e.b] != e.stamp_b || fan_[e.a].empty() ||
          fan_[e.b].empty()) {
        continue;
      }
      if (collapse(e.a, e.b)) {
        ++st.collapsed;
      } else {
        ++st.refused;
      }
    }
  }

  // Drops removed triangles and unused vertices, keeping the order of the rest.
  void compact() {
    std::vector<std::uint32_t> remap(pos_.size(), kNone);
    std::vector<Vec3> positions;
    std::vector<Tri> triangles;
    triangles.reserve(count_);
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (alive_[t] == 0) continue;
      triangles.push_back(mesh_.triangles[t]);
    }
    std::vector<char> used(pos_.size(), 0);
    for (const Tri& f : triangles) {
      for (const std::uint32_t v : f) used[v] = 1;
    }
    for (std::size_t v = 0; v < pos_.size(); ++v) {
      if (used[v] == 0) continue;
      remap[v] = static_cast<std::uint32_t>(positions.size());
      positions.push_back(pos_[v]);
    }
    for (Tri& f : triangles) {
      for (std::uint32_t& v : f) v = remap[v];
    }
    mesh_.positions = std::move(positions);
    mesh_.triangles = std::move(triangles);
    mesh_.normals.clear();
    mesh_.uvs.clear();
    mesh_.tangents.clear();
    mesh_.welded.clear();
  }

  [[nodiscard]] std::size_t count() const { return count_; }

 private:
  void push(std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    const double r = std::min(radius_[a], radius_[b]);
    const double len = (pos_[a] - pos_[b]).norm();
    double priority = std::numeric_limits<double>::infinity();
    if (r > 0 && o_.priority == CoarsenPriority::kShortestEdge) {
      priority = len / r;
    } else if (r > 0) {
      // The squared distance of the midpoint to the planes around a and b, in local radii,
      // plus a little of the edge's length so that flat stretches coarsen evenly.
      Quadric q = quadric_[a];
      q += quadric_[b];
      priority = q.at(0.5 * (pos_[a] + pos_[b])) / (r * r) + kLengthWeight * (len * len) / (r * r);
    }
    heap_.push({priority, a, b, stamp_[a], stamp_[b]});
  }

  void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (const std::uint32_t t : fan_[v]) {
      for (const std::uint32_t w : mesh_.triangles[t]) {
        if (w != v) out.push_back(w);
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  static std::uint32_t third(const Tri& f, std::uint32_t a, std::uint32_t b) {
    for (const std::uint32_t w : f) {
      if (w != a && w != b) return w;
    }
    return kNone;
  }

  // The first-order distance to the surface and the outward unit normal at each point.
  void probe(const std::vector<Vec3>& points) {
    values_.resize(points.size());
    grads_.resize(points.size());
    field_.evaluate(points, values_, grads_, ctx_);
  }

  // The Newton projection of p onto the surface (scale: the local radius); false when it does
  // not converge within `reach` of p (beyond p's own first-order distance).
  bool project(Vec3 p, double scale, double reach, Vec3& z) const {
    const Vec3 start = p;
    const double iso = field_.iso();
    double d0 = 0;
    for (int step = 0; step < kNewtonSteps; ++step) {
      double v = 0;
      Vec3 g = Vec3::Zero();
      field_.evaluate(std::span<const Vec3>(&p, 1), std::span<double>(&v, 1),
                      std::span<Vec3>(&g, 1), ctx_);
      const double gg = g.squaredNorm();
      if (!std::isfinite(v) || !(gg > 0.0) || !std::isfinite(gg)) return false;
      const double dist = std::abs(v - iso) / std::sqrt(gg);
      if (step == 0) d0 = dist;
      if (dist <= tol::kRootFinding * scale) {
        z = p;
        return (z - start).norm() <= reach + 2.0 * d0;
      }
      const Vec3 s = ((v - iso) / gg) * g;
      p -= s;
      if (s.norm() <= kNewtonStop * scale) {
        z = p;
        return (z - start).norm() <= reach + 2.0 * d0;
      }
    }
    return false;
  }

  // Collapses edge (a, b) when allowed (see the header); true when done.
  bool collapse(std::uint32_t a, std::uint32_t b) {
    std::array<std::uint32_t, 2> both{kNone, kNone};
    int shared = 0;
    for (const std::uint32_t t : fan_[a]) {
      const Tri& f = mesh_.triangles[t];
      if (f[0] != b && f[1] != b && f[2] != b) continue;
      if (shared < 2) both[shared] = t;
      ++shared;
    }
    if (shared != 2) return false;
    const std::uint32_t c = third(mesh_.triangles[both[0]], a, b);
    const std::uint32_t d = third(mesh_.triangles[both[1]], a, b);
    if (c == d || c == kNone || d == kNone) return false;
    if (fan_[c].size() <= 3 || fan_[d].size() <= 3) return false;
    // Link condition: the common neighbours of a and b are exactly c and d.
    neighbours(a, na_);
    neighbours(b, nb_);
    common_.clear();
    std::set_intersection(na_.begin(), na_.end(), nb_.begin(), nb_.end(),
                          std::back_inserter(common_));
    if (common_.size() != 2) return false;
    const std::uint32_t lo = std::min(c, d), hi = std::max(c, d);
    if (common_[0] != lo || common_[1] != hi) return false;
    // The smallest angle around a and b before.
    double old_worst = 1.0;
    for (const std::uint32_t v : {a, b}) {
      for (const std::uint32_t t : fan_[v]) {
        const Tri& f = mesh_.triangles[t];
        old_worst = std::min(old_worst, min_angle_sine(pos_[f[0]], pos_[f[1]], pos_[f[2]]));
      }
    }
    const double ra = radius_[a], rb = radius_[b];
    const double rz = std::min(ra, rb);
    const Vec3 mid = 0.5 * (pos_[a] + pos_[b]);
    const double len = (pos_[a] - pos_[b]).norm();
    Vec3 z;
    if (project(mid, rz, 0.5 * len, z) && allowed(a, b, z, rz, both, old_worst)) {
      apply(a, b, z, rz, both);
      return true;
    }
    // Else one end point, taken onto the surface too (a polygonizer may leave a few vertices
    // off it; on it, the point stays where it is).
    for (const std::uint32_t keep : {a, b}) {
      if (!project(pos_[keep], rz, 0.0, z)) continue;
      if (allowed(a, b, z, rz, both, old_worst)) {
        apply(a, b, z, rz, both);
        return true;
      }
    }
    return false;
  }

  // Whether a and b may become one vertex at z (local radius rz).
  bool allowed(std::uint32_t a, std::uint32_t b, const Vec3& z, double rz,
               const std::array<std::uint32_t, 2>& both, double old_worst) {
    const auto corner = [&](std::uint32_t w) -> const Vec3& {
      return w == a || w == b ? z : pos_[w];
    };
    const auto corner_radius = [&](std::uint32_t w) { return w == a || w == b ? rz : radius_[w]; };
    // Geometry of the new triangles: no flip, no angle below the floor unless it improves.
    fresh_.clear();
    Aabb box(z, z);
    box.extend(pos_[a]);
    box.extend(pos_[b]);
    for (const std::uint32_t v : {a, b}) {
      for (const std::uint32_t t : fan_[v]) {
        if (t == both[0] || t == both[1]) continue;
        const Tri& f = mesh_.triangles[t];
        const Vec3 &p0 = corner(f[0]), &p1 = corner(f[1]), &p2 = corner(f[2]);
        for (const std::uint32_t w : f) box.extend(pos_[w]);
        if (p0 == pos_[f[0]] && p1 == pos_[f[1]] && p2 == pos_[f[2]]) continue;  // unmoved
        const Vec3 n_old = (pos_[f[1]] - pos_[f[0]]).cross(pos_[f[2]] - pos_[f[0]]);
        const Vec3 n_new = (p1 - p0).cross(p2 - p0);
        if (!(n_new.dot(n_old) > 0.0)) return false;
        const double s = min_angle_sine(p0, p1, p2);
        if (s < sin_floor_ && s < old_worst) return false;
        fresh_.push_back(t);
      }
    }
    // The skeleton's nodes: none in a tetrahedron swept by a moving triangle, a first, then b.
    hits_.clear();
    nodes_.query(box, hits_);
    if (!hits_.empty()) {
      tets_.clear();
      if (!(z == pos_[a])) {
        for (const std::uint32_t t : fan_[a]) {
          const Tri& f = mesh_.triangles[t];
          int k = f[0] == a ? 0 : (f[1] == a ? 1 : 2);
          tets_.push_back({pos_[a], z, pos_[f[(k + 1) % 3]], pos_[f[(k + 2) % 3]]});
        }
      }
      if (!(z == pos_[b])) {
        for (const std::uint32_t t : fan_[b]) {
          const Tri& f = mesh_.triangles[t];
          int k = f[0] == b ? 0 : (f[1] == b ? 1 : 2);
          const std::uint32_t p = f[(k + 1) % 3], q = f[(k + 2) % 3];
          tets_.push_back({pos_[b], z, p == a ? z : pos_[p], q == a ? z : pos_[q]});
        }
      }
      for (const std::uint32_t h : hits_) {
        const Vec3& p = skeleton_.nodes[h].position;
        for (const auto& q : tets_) {
          if (in_tetrahedron(p, q[0], q[1], q[2], q[3])) return false;
        }
      }
    }
    // The surface: centroids (distance and turn) and new edges' midpoints (distance).
    points_.clear();
    scales_.clear();
    for (const std::uint32_t t : fresh_) {
      const Tri& f = mesh_.triangles[t];
      points_.push_back((corner(f[0]) + corner(f[1]) + corner(f[2])) / 3.0);
      scales_.push_back(std::min({corner_radius(f[0]), corner_radius(f[1]), corner_radius(f[2])}));
    }
    const std::size_t centroids = points_.size();
    for (const std::vector<std::uint32_t>* ring : {&na_, &nb_}) {
      for (const std::uint32_t w : *ring) {
        if (w == a || w == b) continue;
        if (ring == &nb_ && std::binary_search(na_.begin(), na_.end(), w)) continue;
        if (pos_[w] == z) continue;
        const bool moved = ring == &na_ ? !(z == pos_[a]) : !(z == pos_[b]);
        const bool joined = ring == &na_ ? std::binary_search(nb_.begin(), nb_.end(), w) : false;
        if (!moved && !joined) continue;  // the edge (w, a) or (w, b) stays where it was
        points_.push_back(0.5 * (z + pos_[w]));
        scales_.push_back(std::min(rz, radius_[w]));
      }
    }
    if (points_.empty()) return true;
    probe(points_);
    const double iso = field_.iso();
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const double g = grads_[i].norm();
      if (!std::isfinite(values_[i]) || !(g > 0.0) || !std::isfinite(g)) return false;
      const double dist = std::abs(values_[i] - iso) / g;
      if (!(scales_[i] > 0.0) || dist > o_.max_deviation * scales_[i]) return false;
      if (i < centroids) {
        const Tri& f = mesh_.triangles[fresh_[i]];
        const Vec3 &p0 = corner(f[0]), &p1 = corner(f[1]), &p2 = corner(f[2]);
        const Vec3 n = (p1 - p0).cross(p2 - p0);
        if (!(n.dot(-grads_[i]) > cos_turn_ * n.norm() * g)) return false;
      }
    }
    return true;
  }

  void apply(std::uint32_t a, std::uint32_t b, const Vec3& z, double rz,
             const std::array<std::uint32_t, 2>& both) {
    for (const std::uint32_t t : both) {
      alive_[t] = 0;
      for (const std::uint32_t w : mesh_.triangles[t]) std::erase(fan_[w], t);
    }
    for (const std::uint32_t t : fan_[b]) {
      for (std::uint32_t& w : mesh_.triangles[t]) {
        if (w == b) w = a;
      }
      fan_[a].push_back(t);
    }
    fan_[b].clear();
    pos_[a] = z;
    radius_[a] = rz;
    quadric_[a] += quadric_[b];
    count_ -= 2;
    // Re-queue the edges of a and of its neighbours (their neighbourhoods changed).
    neighbours(a, na_);
    ++stamp_[a];
    ++stamp_[b];
    for (const std::uint32_t w : na_) ++stamp_[w];
    edges_.clear();
    for (const std::uint32_t w : na_) edges_.push_back({std::min(a, w), std::max(a, w)});
    for (const std::uint32_t w : na_) {
      neighbours(w, nb_);
      for (const std::uint32_t x : nb_) edges_.push_back({std::min(w, x), std::max(w, x)});
    }
    std::sort(edges_.begin(), edges_.end());
    edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
    for (const auto& e : edges_) push(e[0], e[1]);
  }

  TriMesh& mesh_;
  std::vector<Vec3>& pos_;
  const Field& field_;
  const Skeleton& skeleton_;
  const CoarsenOptions& o_;
  Context* ctx_;
  double sin_floor_, cos_turn_;
  std::vector<char> alive_;
  std::vector<std::vector<std::uint32_t>> fan_;  // the triangles around each vertex
  std::vector<std::uint32_t> stamp_;
  std::vector<double> radius_;
  std::vector<Quadric> quadric_;
  detail::BoxBvh nodes_;
  std::priority_queue<Entry, std::vector<Entry>, Later> heap_;
  std::size_t count_ = 0;
  // Scratch.
  std::vector<std::uint32_t> na_, nb_, common_, fresh_, hits_;
  std::vector<std::array<Vec3, 4>> tets_;
  std::vector<Vec3> points_;
  std::vector<double> scales_, values_;
  std::vector<Vec3> grads_;
  std::vector<std::array<std::uint32_t, 2>> edges_;
};

}  // namespace

void coarsen_to_budget(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                       const CoarsenOptions& options, Context* ctx, CoarsenStats* stats) {
  validate(options);
  if (skeleton.nodes.empty()) throw InvalidArgument("coarsen: the skeleton has no nodes");
  CoarsenStats st;
  st.triangles_before = mesh.triangles.size();
  if (mesh.triangles.size() > options.max_triangles) {
    Coarsener c(mesh, field, skeleton, options, ctx);
    c.run(st);
    if (st.collapsed > 0) c.compact();
  }
  st.triangles_after = mesh.triangles.size();
  st.reached = st.triangles_after <= options.max_triangles;
  if (stats != nullptr) *stats = st;
}

}  // namespace ramiform
