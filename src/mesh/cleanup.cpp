// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/cleanup.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using Tri = std::array<std::uint32_t, 3>;
constexpr double kDeg = std::numbers::pi / 180.0;

// The sine of the smallest corner angle of the triangle a, b, c (the corner opposite the
// shortest edge, at most 60 degrees, where the sine is increasing: a cheap stand-in for the
// angle in comparisons); 0 when degenerate.
double min_angle_sine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, bc = c - b, ca = a - c;
  const double lab = ab.squaredNorm(), lbc = bc.squaredNorm(), lca = ca.squaredNorm();
  const double cross = ab.cross(-ca).norm();
  if (!(cross > tol::kCoincident * std::max({lab, lbc, lca}))) return 0.0;
  if (lbc <= lab && lbc <= lca) return cross / std::sqrt(lab * lca);  // at a
  if (lca <= lab) return cross / std::sqrt(lab * lbc);                // at b
  return cross / std::sqrt(lbc * lca);                                // at c
}

struct Candidate {
  double length;
  std::uint32_t u, v;
  std::uint32_t tri;
  bool collapsible;
};

class Collapser {
 public:
  Collapser(TriMesh& mesh, const NeedleCleanupOptions& o)
      : mesh_(mesh),
        alive_(mesh.triangles.size(), 1),
        removed_(mesh.positions.size(), 0),
        offset_(mesh.positions.size() + 1, 0),
        extra_(mesh.positions.size()),
        mark_(mesh.positions.size(), 0),
        moved_(mesh.positions.size(), 0),
        touched_(mesh.positions.size(), 0),
        min_angle_(std::sin(o.min_angle_deg * kDeg)),
        max_edge_ratio_(o.max_edge_ratio),
        cos_turn_(std::cos(o.max_normal_turn_deg * kDeg)) {
    // Vertex -> triangles as one compressed table; triangles that gain a vertex later are
    // listed in extra_ (empty for almost every vertex).
    for (const auto& t : mesh.triangles) {
      for (const std::uint32_t v : t) ++offset_[v + 1];
    }
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) offset_[v + 1] += offset_[v];
    list_.resize(offset_.back());
    std::vector<std::uint32_t> fill(offset_.begin(), offset_.end() - 1);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      for (const std::uint32_t v : mesh.triangles[t]) list_[fill[v]++] = t;
    }
  }

  // One sweep over the needles' shortest edges; returns the number of collapses.
  // One sweep over the needles' shortest edges; returns the number of changes. After the first
  // sweep only needles next to a change of the previous sweep are looked at: the others were
  // already refused and nothing around them moved.
  std::size_t sweep(bool first) {
    constexpr std::size_t kGrain = 16384;
    const std::size_t n = mesh_.triangles.size();
    std::vector<std::vector<Candidate>> parts((n + kGrain - 1) / kGrain);
    parallel::for_chunks(n, kGrain, [&](std::size_t b, std::size_t e) {
      auto& out = parts[b / kGrain];
      for (auto t = static_cast<std::uint32_t>(b); t < e; ++t) {
        if (alive_[t] == 0) continue;
        const Tri& f = mesh_.triangles[t];
        if (!first && touched_[f[0]] == 0 && touched_[f[1]] == 0 && touched_[f[2]] == 0) continue;
        if (angle_of(f) >= min_angle_) continue;
        int best = 0;
        double best_len = INFINITY, longest = 0;
        for (int k = 0; k < 3; ++k) {
          const double len = (pos(f[k]) - pos(f[(k + 1) % 3])).norm();
          if (len < best_len) best_len = len, best = k;
          longest = std::max(longest, len);
        }
        const std::uint32_t a = f[best], c = f[(best + 1) % 3];
        // A needle proper has one short edge: that one may collapse. A cap's shortest edge is
        // not short (its other two edges are), and collapsing it would move the surface: it
        // only gets its longest edge flipped.
        const bool short_edge = best_len < max_edge_ratio_ * longest;
        out.push_back({best_len, std::min(a, c), std::max(a, c), t, short_edge});
      }
    });
    // Candidates in triangle order: polygonizers emit triangles cell by cell, so this order
    // walks the mesh in space and keeps its arrays in cache (shortest-first order jumps
    // across the whole mesh and made the pass several times slower). Both triangles of an
    // edge may propose it; the second try finds it gone or refused again.
    std::vector<Candidate> candidates;
    for (auto& p : parts) candidates.insert(candidates.end(), p.begin(), p.end());
    std::fill(touched_.begin(), touched_.end(), 0);
    std::size_t done = 0;
    for (const Candidate& c : candidates) {
      if (removed_[c.u] != 0 || removed_[c.v] != 0) continue;
      if (c.collapsible && try_collapse(c.u, c.v)) {
        ++done;
      } else if (alive_[c.tri] != 0 && try_flip(c.tri)) {
        ++done;
        ++flipped_edges;
      }
    }
    return done;
  }

  // Drops dead triangles and unused vertices, keeping the order of the rest.
  void compact() {
    std::vector<Tri> tris;
    tris.reserve(mesh_.triangles.size());
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (alive_[t] != 0) tris.push_back(mesh_.triangles[t]);
    }
    std::vector<std::uint32_t> remap(mesh_.positions.size(), UINT32_MAX);
    for (const auto& t : tris) {
      for (const std::uint32_t v : t) remap[v] = 0;
    }
    std::vector<Vec3> positions;
    for (std::size_t v = 0; v < mesh_.positions.size(); ++v) {
      if (remap[v] == 0) {
        remap[v] = static_cast<std::uint32_t>(positions.size());
        positions.push_back(mesh_.positions[v]);
      }
    }
    for (auto& t : tris) {
      for (auto& v : t) v = remap[v];
    }
    mesh_.positions = std::move(positions);
    mesh_.triangles = std::move(tris);
  }

  std::size_t removed_triangles = 0;
  std::size_t flipped_edges = 0;

 private:
  const Vec3& pos(std::uint32_t v) const { return mesh_.positions[v]; }
  double angle_of(const Tri& f) const { return min_angle_sine(pos(f[0]), pos(f[1]), pos(f[2])); }

  // Alive triangles around v, ascending. The result lives until the next call but one. Once a
  // vertex has gained triangles, its whole list moves to extra_ and is pruned on every visit,
  // so lists stay as short as the vertex's current fan.
  const std::vector<std::uint32_t>& around(std::uint32_t v) {
    auto& out = scratch_[flip_ ^= 1];
    out.clear();
    auto take = [&](std::uint32_t t) {
      if (alive_[t] != 0 && has(mesh_.triangles[t], v)) out.push_back(t);
    };
    if (moved_[v] == 0) {
      for (std::uint32_t k = offset_[v]; k < offset_[v + 1]; ++k) take(list_[k]);
    }
    for (const std::uint32_t t : extra_[v]) take(t);
    if (moved_[v] != 0 || !extra_[v].empty()) {
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
      extra_[v].assign(out.begin(), out.end());
      moved_[v] = 1;
    }
    return out;
  }

  static bool has(const Tri& f, std::uint32_t v) { return f[0] == v || f[1] == v || f[2] == v; }

  // Number of distinct vertices adjacent to both u and v (stamped marks, no allocation).
  std::size_t common_neighbours(std::uint32_t u, std::uint32_t v) {
    stamp_ += 2;
    const std::uint32_t of_u = stamp_, counted = stamp_ + 1;
    for (const std::uint32_t t : around(u)) {
      for (const std::uint32_t w : mesh_.triangles[t]) {
        if (w != u) mark_[w] = of_u;
      }
    }
    std::size_t common = 0;
    for (const std::uint32_t t : around(v)) {
      for (const std::uint32_t w : mesh_.triangles[t]) {
        if (w != v && mark_[w] == of_u) {
          mark_[w] = counted;
          ++common;
        }
      }
    }
    return common;
  }

  bool adjacent(std::uint32_t c, std::uint32_t d) {
    for (const std::uint32_t t : around(c)) {
      if (has(mesh_.triangles[t], d)) return true;
    }
    return false;
  }

  // Quality of removing x into y (y keeps its position): the smallest angle of the changed
  // triangles, or -1 when the collapse is not allowed.
  double evaluate(std::uint32_t x, std::uint32_t y, const std::vector<std::uint32_t>& shared) {
    double worst_new = INFINITY;
    for (const std::uint32_t t : around(x)) {
      if (std::find(shared.begin(), shared.end(), t) != shared.end()) continue;
      const Tri& f = mesh_.triangles[t];
      std::array<Vec3, 3> p{pos(f[0]), pos(f[1]), pos(f[2])};
      const Vec3 n0 = (p[1] - p[0]).cross(p[2] - p[0]);
      for (int k = 0; k < 3; ++k) {
        if (f[k] == x) p[k] = pos(y);
      }
      const Vec3 n1 = (p[1] - p[0]).cross(p[2] - p[0]);
      if (!(n0.dot(n1) > cos_turn_ * n0.norm() * n1.norm())) return -1;
      const double a = min_angle_sine(p[0], p[1], p[2]);
      if (a <= 0) return -1;
      worst_new = std::min(worst_new, a);
    }
    return worst_new;
  }

  bool try_collapse(std::uint32_t u, std::uint32_t v) {
    std::vector<std::uint32_t> shared;
    for (const std::uint32_t t : around(u)) {
      if (has(mesh_.triangles[t], v)) shared.push_back(t);
    }
    if (shared.size() != 2) return false;
    // The edge must still belong to a needle.
    double worst_old = INFINITY;
    for (const std::uint32_t t : shared) worst_old = std::min(worst_old, angle_of(mesh_.triangles[t]));
    if (worst_old >= min_angle_) return false;
    // Link condition: the common neighbours are exactly the two opposite vertices, each of
    // which keeps at least three neighbours.
    std::array<std::uint32_t, 2> opposite{};
    for (int k = 0; k < 2; ++k) {
      for (const std::uint32_t w : mesh_.triangles[shared[k]]) {
        if (w != u && w != v) opposite[k] = w;
      }
    }
    if (opposite[0] == opposite[1]) return false;
    if (common_neighbours(u, v) != 2) return false;
    for (const std::uint32_t o : opposite) {
      if (around(o).size() <= 3) return false;  // on a closed manifold: valence = triangles
    }
    // Keep whichever end point gives the better triangles; they must all beat the needle.
    const double keep_v = evaluate(u, v, shared);
    const double keep_u = evaluate(v, u, shared);
    const bool into_v = keep_v >= keep_u;
    const double best = std::max(keep_v, keep_u);
    if (!(best > worst_old)) return false;
    const std::uint32_t x = into_v ? u : v;  // removed
    const std::uint32_t y = into_v ? v : u;  // kept
    for (const std::uint32_t t : shared) alive_[t] = 0;
    removed_triangles += 2;
    for (const std::uint32_t t : around(x)) {
      for (auto& w : mesh_.triangles[t]) {
        if (w == x) w = y;
      }
      extra_[y].push_back(t);
    }
    removed_[x] = 1;
    for (const std::uint32_t t : around(y)) {
      for (const std::uint32_t w : mesh_.triangles[t]) touched_[w] = 1;
    }
    return true;
  }

  // A cap (a needle whose shortest edge cannot go) loses its longest edge instead: the two
  // triangles (a, b, c) and (b, a, d) on it become (a, d, c) and (d, b, c), which keeps every
  // directed edge of the quad's boundary, so orientation and manifoldness stay.
  bool try_flip(std::uint32_t t1) {
    const Tri f1 = mesh_.triangles[t1];
    int k = 0;
    double longest = -1;
    for (int i = 0; i < 3; ++i) {
      const double len = (pos(f1[i]) - pos(f1[(i + 1) % 3])).squaredNorm();
      if (len > longest) longest = len, k = i;
    }
    const std::uint32_t a = f1[k], b = f1[(k + 1) % 3], c = f1[(k + 2) % 3];
    std::uint32_t t2 = UINT32_MAX;
    for (const std::uint32_t t : around(a)) {
      const Tri& f = mesh_.triangles[t];
      for (int i = 0; i < 3; ++i) {
        if (t != t1 && f[i] == b && f[(i + 1) % 3] == a) t2 = t;
      }
    }
    if (t2 == UINT32_MAX) return false;
    const Tri& f2 = mesh_.triangles[t2];
    std::uint32_t d = f2[0];
    for (const std::uint32_t w : f2) {
      if (w != a && w != b) d = w;
    }
    if (d == c) return false;
    if (adjacent(c, d)) return false;  // edge c-d exists
    const Tri g1{a, d, c}, g2{d, b, c};
    const double old_worst = std::min(angle_of(f1), angle_of(f2));
    const double new_worst = std::min(angle_of(g1), angle_of(g2));
    if (!(new_worst > old_worst)) return false;
    auto normal = [&](const Tri& f) { return Vec3((pos(f[1]) - pos(f[0])).cross(pos(f[2]) - pos(f[0]))); };
    const Vec3 n_old = normal(f1).normalized() + normal(f2).normalized();
    for (const Tri& g : {g1, g2}) {
      const Vec3 n = normal(g);
      if (!(n.dot(n_old) > cos_turn_ * n.norm() * n_old.norm())) return false;
    }
    mesh_.triangles[t1] = g1;
    mesh_.triangles[t2] = g2;
    extra_[c].push_back(t2);  // a and b lose a triangle: around() filters it out
    extra_[d].push_back(t1);
    touched_[a] = touched_[b] = touched_[c] = touched_[d] = 1;
    return true;
  }

  TriMesh& mesh_;
  std::vector<char> alive_;
  std::vector<char> removed_;
  std::vector<std::uint32_t> offset_, list_;
  std::vector<std::vector<std::uint32_t>> extra_;
  std::array<std::vector<std::uint32_t>, 2> scratch_;
  unsigned flip_ = 0;
  std::vector<std::uint32_t> mark_;
  std::vector<char> moved_;
  std::vector<char> touched_;  // vertices next to a change of the current sweep
  std::uint32_t stamp_ = 0;
  double min_angle_;  // as a sine, see min_angle_sine()
  double max_edge_ratio_;
  double cos_turn_;
};

}  // namespace

AngleSummary angle_summary(const TriMesh& mesh) {
  AngleSummary s;
  if (mesh.triangles.empty()) return s;
  std::vector<double> angles(3 * mesh.triangles.size());
  parallel::for_chunks(mesh.triangles.size(), 16384, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const auto& t = mesh.triangles[i];
      const Vec3& a = mesh.positions[t[0]];
      const Vec3& p = mesh.positions[t[1]];
      const Vec3& c = mesh.positions[t[2]];
      const Vec3 ab = p - a, bc = c - p, ca = a - c;
      const double cross = ab.cross(-ca).norm();
      angles[3 * i] = std::atan2(cross, ab.dot(-ca)) / kDeg;
      angles[3 * i + 1] = std::atan2(cross, bc.dot(-ab)) / kDeg;
      angles[3 * i + 2] = std::atan2(cross, ca.dot(-bc)) / kDeg;
    }
  });
  s.min_deg = *std::min_element(angles.begin(), angles.end());
  // The median as check_mesh() reports it: the mean of the two middle values for an even count.
  auto mid = angles.begin() + static_cast<std::ptrdiff_t>(angles.size() / 2);
  std::nth_element(angles.begin(), mid, angles.end());
  s.median_deg = *mid;
  if (angles.size() % 2 == 0) s.median_deg = 0.5 * (s.median_deg + *std::max_element(angles.begin(), mid));
  return s;
}

void clean_needles(TriMesh& mesh, const NeedleCleanupOptions& o, NeedleCleanupStats* stats) {
  if (!(o.min_angle_deg > 0 && o.min_angle_deg < 60)) {
    throw InvalidArgument("NeedleCleanupOptions.min_angle_deg must be in (0, 60), got " +
                          std::to_string(o.min_angle_deg));
  }
  if (!(o.max_normal_turn_deg > 0 && o.max_normal_turn_deg <= 90)) {
    throw InvalidArgument("NeedleCleanupOptions.max_normal_turn_deg must be in (0, 90], got " +
                          std::to_string(o.max_normal_turn_deg));
  }
  if (o.passes < 1) throw InvalidArgument("NeedleCleanupOptions.passes must be >= 1");
  if (!(o.max_edge_ratio > 0 && o.max_edge_ratio < 1)) {
    throw InvalidArgument("NeedleCleanupOptions.max_edge_ratio must be in (0, 1), got " +
                          std::to_string(o.max_edge_ratio));
  }
  NeedleCleanupStats st;
  const AngleSummary before = angle_summary(mesh);
  st.min_angle_before = before.min_deg;
  st.median_angle_before = before.median_deg;
  Collapser c(mesh, o);
  for (int pass = 0; pass < o.passes; ++pass) {
    const std::size_t n = c.sweep(pass == 0);
    st.collapsed_edges += n;
    if (n == 0) break;
  }
  st.removed_triangles = c.removed_triangles;
  st.flipped_edges = c.flipped_edges;
  c.compact();
  if (o.measure_after) {
    const AngleSummary after = angle_summary(mesh);
    st.min_angle_after = after.min_deg;
    st.median_angle_after = after.median_deg;
  }
  if (stats != nullptr) *stats = st;
}

}  // namespace ramiform
