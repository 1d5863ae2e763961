// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Suggestive contours from the particles spread over an implicit surface.
//
// From Proença, Jorge & Costa Sousa 2008, "Suggestive Contours over Point-Set Implicits"
// (GRAPP): §5.1 (eqs. 3–8: a particle lies on a suggestive contour when n·v is smaller there
// than at the two points x± = x ± k_d·δ_i·ŵ, and the view is not too close to the normal),
// §5.2 (clusters of nearby suggestive particles, neighbour radius scaled by δ_i of §4) and §5.3
// (a minimum spanning tree per cluster, then its longest path or the tree with short leaf
// branches trimmed, smoothed). The definition is DeCarlo, Finkelstein, Rusinkiewicz & Santella
// 2003, "Suggestive Contours for Conveying Shape" (SIGGRAPH): the minima of n·v along w.
//
// Sign conventions. Particle normals n point out of the solid (n = −∇f/|∇f|, f > iso inside).
// e = (eye − x)/|eye − x| is the unit direction from the point to the eye, i.e. −v with v the
// view vector of eq. 3 (camera.h's view_vector); n·e > 0 where the surface faces the eye.
// DeCarlo et al.'s view vector points to the eye, and the suggestive contours are the local
// minima of their n·v along w, the projection of the view vector on the tangent plane (where
// n·v dips towards 0 without reaching it). The paper writes eqs. 6–7 with eq. 3's v; they hold
// as written for n·v with an inward normal ∇f/|∇f|, and for n·(−v) with ours. Only the line of
// w matters (x+ and x− are symmetric), so its sign is immaterial.
//
// Deviation: eqs. 6–7 compare dp = n·(eye − x) with the view vector not normalized (DeCarlo et
// al.'s v = c − p). Its derivative along the unit tangent ŵ is exactly κ_r |w| (the radial
// curvature times the length of the projected view vector), so its minima are the zeros of κ_r
// where κ_r grows along w, DeCarlo et al.'s definition. With eq. 3's unit vector e the
// derivative is |w_e|·(κ_r + n·e / |eye − x|), w_e the projection of e, and the minima move to
// κ_r = −n·e / |eye − x|, a bias that grows as the eye comes closer; both agree for a distant
// eye. Eq. 8 and the front-facing test use the unit vector (they are about angles).
//
// Deviation: a correction of eqs. 6–7 for the bend of w. DeCarlo et al.'s minima are along
// the integral curves of the field w, and those curves bend on the surface: their tangential
// acceleration is −(n·V) (Sŵ)⊥ / |w| (S the shape operator, V = eye − x, ⊥ the part normal to
// ŵ in the tangent plane), whereas x± = x ± h ŵ (h = k_d δ_i) sample the normal section along
// ŵ, which does not bend. dp's second derivative along the section therefore exceeds the one
// along w by dp·II(ŵ, t)² (t = n × ŵ, II the second fundamental form), and the paper's test
// passes particles where n·v has a minimum along the section but a maximum along w: the zeros
// of κ_r with D_w κ_r < 0, next to where suggestive contours end and wherever w runs oblique to
// the principal directions (measured on a torus: particles 2.7 δ beyond DeCarlo's contour, on
// its κ_r = 0, D_w κ_r < 0 continuation). The fix subtracts the difference from both sides:
// dp + Δ < dp± with Δ = dp·h²·II(ŵ, t)² / 2, and II(ŵ, t) ≈ t·(n+ − n−) / 2h from the two
// normals the test evaluates anyway. Δ ≥ 0, so the test only tightens (and dp < dp− stays a
// necessary condition, which the two-batch evaluation below relies on).
//
// The normal at x±: from ∇f at x± directly, as the paper's Figure 4 does, not after
// re-projecting x± onto the surface. x± lie on the tangent plane, off the surface by about
// κ_r (k_d δ)² / 2 along n (the normal curvature along ±ŵ is κ_r for both). For a distance-like
// field ∇f at x± is the normal at the nearest surface point, and dp± comes out smaller than
// there by that offset: a bias that vanishes where κ_r does, so it does not move the zero set,
// and elsewhere is k_d δ / (2|w|) times the first-order change κ_r |w| k_d δ that eqs. 6–7
// detect (|w| is of the order of the distance to the eye). A re-projection would cost two or
// three more batched evaluations per candidate for no change in which particles pass. dp at x
// uses the particle's stored normal, which spread_particles() computed from ∇f at that very
// position.
//
// Clustering (§5.2): each suggestive particle links to its cluster_k nearest suggestive
// particles closer than cluster_radius·δ_i. The paper grows clusters by breadth-first search and
// merges clusters that meet; both amount to the connected components of this graph with its
// links taken both ways. Kruskal's algorithm over the graph's edges (3-D lengths, ties by the
// index pair) yields those components and the minimum spanning tree of each at once (§5.3).
//
// Trimming (§5.3): at each node of degree ≥ 3, every branch that runs through nodes of degree 2
// to a leaf and holds fewer than k_trim particles is removed, except that a node keeps at least
// two branches (the longest of the short ones come back first), so a fork of short twigs at a
// line's end continues the line along its longest twig instead of cutting the line back. What
// remains is split into polylines at the nodes of degree ≠ 2.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <utility>
#include <vector>

#include "field/point_kdtree.h"
#include "ramiform/core/parallel.h"
#include "ramiform/lines/lines.h"

namespace ramiform {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kDeg = std::numbers::pi / 180.0;
// |w| = sin(angle between n and e) below this: the view is along the normal and w has no
// reliable direction (eq. 8 rejects such particles anyway unless θ_sc is 0).
constexpr double kMinTangentView = 1e-6;
// Re-projection of smoothed points: Newton steps along ∇f until |f − iso| / |∇f| is at most
// this fraction of the point's δ, at most kProjectSteps steps (points that do not converge keep
// their position before the smoothing pass, which was on the surface).
constexpr double kProjectTolerance = 1e-7;
constexpr int kProjectSteps = 8;
// One Newton step moves a point by at most this many δ (a step beyond it means the point is
// near a critical point of f, where the linearisation is not to be trusted).
constexpr double kMaxProjectStep = 1.0;
// Laplacian smoothing weight: p ← p + λ (mean of the two neighbours − p).
constexpr double kSmoothing = 0.5;
constexpr std::size_t kGrain = 256;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Union–find over [0, n), path halving, union by smaller index as the root (deterministic).
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
  }
  std::uint32_t find(std::uint32_t a) {
    while (parent_[a] != a) {
      parent_[a] = parent_[parent_[a]];
      a = parent_[a];
    }
    return a;
  }
  // Joins the sets of a and b; false when they were one already.
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
    return true;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

// §5.1: the indices (ascending) of the particles that pass eqs. 6–8 and face the eye.
std::vector<std::uint32_t> suggestive_particles(const Field& field, const ParticleSystem& system,
                                                const Camera& camera, const LineOptions& options,
                                                const Context* ctx) {
  const std::vector<SurfaceParticle>& particles = system.particles;
  const double cos_theta = std::cos(options.theta_sc_deg * kDeg);

  // Candidates: front-facing (n·e > 0), eq. 8 (acos(n·e) > θ_sc, i.e. n·e < cos θ_sc), and a
  // tangent direction w. Cheap, serial, in index order.
  std::vector<std::uint32_t> candidate;
  std::vector<Vec3> offset;   // k_d·δ_i·ŵ per candidate
  std::vector<double> dp;     // n·(eye − x) at the particle per candidate
  std::vector<double> w_len;  // |w| = |eye − x|·sin(angle(n, e)) per candidate (t_d's scale)
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const SurfaceParticle& p = particles[i];
    if (!is_finite(p.position) || !is_finite(p.normal) || !(p.delta > 0)) continue;
    const Vec3 to_eye = camera.eye - p.position;
    const double dist = to_eye.norm();
    if (!(dist > 0)) continue;
    const double facing = p.normal.dot(to_eye) / dist;
    if (!(facing > 0) || !(facing < cos_theta)) continue;
    const Vec3 w = to_eye / dist - facing * p.normal;
    const double w_norm = w.norm();
    if (!(w_norm > kMinTangentView)) continue;
    candidate.push_back(static_cast<std::uint32_t>(i));
    offset.push_back((options.k_d * p.delta / w_norm) * w);
    dp.push_back(p.normal.dot(to_eye));
    w_len.push_back(dist * w_norm);
  }

  // Eqs. 4–7 in two batched evaluations with gradients: x− = x − k_d·δ_i·ŵ for every candidate,
  // then x+ only for those with dp < dp−. ŵ points towards the eye's side, so where the surface
  // is convex along w dp grows along ŵ and eq. 7 already fails at x−: the second batch is a
  // fraction of the first (about 40 % on an MPU bunny), which saves about 30 % of the
  // evaluations that dominate the cost. dp± = n(x±)·(eye − x±) with n(x±) = −∇f/|∇f| there.
  const std::size_t m = candidate.size();
  std::vector<Vec3> points, gradients, normal_minus(m);
  std::vector<double> values, dp_minus(m);
  auto evaluate_at = [&](const std::vector<std::size_t>& which, double sign) {
    points.resize(which.size());
    for (std::size_t k = 0; k < which.size(); ++k) {
      const std::size_t j = which[k];
      points[k] = particles[candidate[j]].position + sign * offset[j];
    }
    values.resize(points.size());
    gradients.resize(points.size());
    field.evaluate(points, values, gradients, ctx);
  };
  // The unit normal at points[k], false where ∇f vanishes.
  auto normal_at = [&](std::size_t k, Vec3& n) {
    const double g = gradients[k].norm();
    if (!(g > 0) || !std::isfinite(g)) return false;
    n = gradients[k] / -g;
    return true;
  };

  std::vector<std::size_t> all(m), below_minus;
  std::iota(all.begin(), all.end(), std::size_t{0});
  evaluate_at(all, -1.0);
  for (std::size_t j = 0; j < m; ++j) {
    if (!normal_at(j, normal_minus[j])) continue;
    dp_minus[j] = normal_minus[j].dot(camera.eye - points[j]);
    if (dp[j] < dp_minus[j]) below_minus.push_back(j);  // eq. 7, necessary for the full test
  }
  evaluate_at(below_minus, 1.0);
  std::vector<std::uint32_t> result;
  for (std::size_t k = 0; k < below_minus.size(); ++k) {
    const std::size_t j = below_minus[k];
    Vec3 normal_plus;
    if (!normal_at(k, normal_plus)) continue;
    const double dp_plus = normal_plus.dot(camera.eye - points[k]);
    // The curvature of w's integral curve (see the file comment): with h = k_d·δ_i and t the
    // unit tangent normal to ŵ, II(ŵ, t) ≈ t·(n+ − n−) / 2h, and both inequalities tighten by
    // Δ = dp·h²·II(ŵ, t)² / 2 = dp·((n × h ŵ)·(n+ − n−))² / 8h².
    const SurfaceParticle& p = particles[candidate[j]];
    const double h2 = offset[j].squaredNorm();
    const double twist = p.normal.cross(offset[j]).dot(normal_plus - normal_minus[j]);
    const double tighten = dp[j] * twist * twist / (8 * h2);
    if (!(dp[j] + tighten < dp_plus && dp[j] + tighten < dp_minus[j])) continue;
    // DeCarlo et al.'s t_d (see the file comment): δ²·D_ŵ κ_r from the second difference.
    const double h_over_delta2 = options.k_d * options.k_d;
    const double dkr = (dp_plus + dp_minus[j] - 2 * (dp[j] + tighten)) / (h_over_delta2 * w_len[j]);
    if (options.t_d > 0 && !(dkr > options.t_d)) continue;
    result.push_back(candidate[j]);
  }
  return result;
}

struct Edge {
  std::uint32_t a, b;  // a < b
  double length2;
};

// §5.2–5.3: the edges of the minimum spanning forest of the cluster graph over `pos` (each
// point linked to its k nearest within radius[i]), whose trees are the clusters.
std::vector<Edge> spanning_forest(const std::vector<Vec3>& pos, const std::vector<double>& radius,
                                  int k, const Context* ctx) {
  const std::size_t n = pos.size();
  const std::size_t kk = static_cast<std::size_t>(k);
  std::vector<std::uint32_t> neighbour(n * kk);
  std::vector<std::uint32_t> count(n, 0);
  if (n > 1) {
    const detail::PointKdTree tree(pos);
    parallel::for_chunks(
        n, kGrain,
        [&](std::size_t begin, std::size_t end) {
          std::vector<std::pair<std::uint32_t, double>> found;
          for (std::size_t i = begin; i < end; ++i) {
            tree.within(pos[i], radius[i], found);  // nearest first, ties by index
            std::uint32_t c = 0;
            for (const auto& [j, d2] : found) {
              if (j == i) continue;
              neighbour[i * kk + c] = j;
              if (++c == kk) break;
            }
            count[i] = c;
          }
        },
        ctx);
  }
  std::vector<Edge> edges;
  edges.reserve(n * kk);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t c = 0; c < count[i]; ++c) {
      const std::uint32_t j = neighbour[i * kk + c];
      const std::uint32_t a = std::min(static_cast<std::uint32_t>(i), j);
      const std::uint32_t b = std::max(static_cast<std::uint32_t>(i), j);
      edges.push_back({a, b, (pos[a] - pos[b]).squaredNorm()});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    if (x.length2 != y.length2) return x.length2 < y.length2;
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  // Kruskal; a link found from both ends appears twice in a row and the second is a cycle.
  DisjointSets sets(n);
  std::vector<Edge> forest;
  for (const Edge& e : edges) {
    if (sets.unite(e.a, e.b)) forest.push_back(e);
  }
  return forest;
}

// A forest as adjacency lists (CSR), each node's neighbours in ascending order.
struct Forest {
  std::vector<std::uint32_t> first;  // node i's neighbours: adj[first[i] .. first[i + 1])
  std::vector<std::uint32_t> adj;
  std::vector<double> length;  // the edge length to adj[k]

  Forest(std::size_t n, const std::vector<Edge>& edges) : first(n + 1, 0) {
    for (const Edge& e : edges) {
      ++first[e.a + 1];
      ++first[e.b + 1];
    }
    for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
    std::vector<std::pair<std::uint32_t, double>> entries(first[n]);
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (const Edge& e : edges) {
      const double l = std::sqrt(e.length2);
      entries[fill[e.a]++] = {e.b, l};
      entries[fill[e.b]++] = {e.a, l};
    }
    adj.resize(entries.size());
    length.resize(entries.size());
    for (std::size_t i = 0; i < n; ++i) {
      std::sort(entries.begin() + first[i], entries.begin() + first[i + 1]);
      for (std::uint32_t k = first[i]; k < first[i + 1]; ++k) {
        adj[k] = entries[k].first;
        length[k] = entries[k].second;
      }
    }
  }
  [[nodiscard]] std::uint32_t degree(std::uint32_t i) const { return first[i + 1] - first[i]; }
};

// Path lengths from `root` over its tree; `parent` gets the tree rooted there. Returns the
// farthest node (ties: the smallest index). `dist` and `parent` are indexed by node.
std::uint32_t farthest(const Forest& forest, std::uint32_t root,
                       const std::vector<std::uint32_t>& members, std::vector<double>& dist,
                       std::vector<std::uint32_t>& parent, std::vector<std::uint32_t>& stack) {
  dist[root] = 0;
  parent[root] = root;
  stack.assign(1, root);
  while (!stack.empty()) {
    const std::uint32_t u = stack.back();
    stack.pop_back();
    for (std::uint32_t k = forest.first[u]; k < forest.first[u + 1]; ++k) {
      const std::uint32_t v = forest.adj[k];
      if (v == parent[u]) continue;
      parent[v] = u;
      dist[v] = dist[u] + forest.length[k];
      stack.push_back(v);
    }
  }
  std::uint32_t best = root;
  for (const std::uint32_t v : members) {
    if (dist[v] > dist[best] || (dist[v] == dist[best] && v < best)) best = v;
  }
  return best;
}

// kLongestPath: the path between the two ends of the tree's diameter (double sweep).
std::vector<std::uint32_t> longest_path(const Forest& forest,
                                        const std::vector<std::uint32_t>& members,
                                        std::vector<double>& dist,
                                        std::vector<std::uint32_t>& parent,
                                        std::vector<std::uint32_t>& stack) {
  const std::uint32_t a = farthest(forest, members.front(), members, dist, parent, stack);
  const std::uint32_t b = farthest(forest, a, members, dist, parent, stack);
  std::vector<std::uint32_t> path;
  for (std::uint32_t v = b; v != a; v = parent[v]) path.push_back(v);
  path.push_back(a);
  std::reverse(path.begin(), path.end());  // from a to b
  return path;
}

// kTrim: the tree with short leaf branches removed, split into polylines at nodes of
// degree ≠ 2 (see the file comment). `removed` is indexed by node and left cleared.
void trimmed_paths(const Forest& forest, const std::vector<std::uint32_t>& members, int k_trim,
                   std::vector<std::uint8_t>& removed,
                   std::vector<std::vector<std::uint32_t>>& out) {
  struct Branch {
    std::vector<std::uint32_t> nodes;  // from the fork's neighbour to the leaf
    double length = 0;
  };
  // The walk from `from` into its neighbour at adjacency slot k, through nodes of degree 2.
  auto walk = [&](std::uint32_t from, std::uint32_t k, auto&& degree_of, auto&& keep,
                  std::vector<std::uint32_t>& nodes, double& length) {
    nodes.clear();
    length = forest.length[k];
    std::uint32_t prev = from, cur = forest.adj[k];
    nodes.push_back(cur);
    while (degree_of(cur) == 2) {
      std::uint32_t next = prev;
      double step = 0;
      for (std::uint32_t q = forest.first[cur]; q < forest.first[cur + 1]; ++q) {
        const std::uint32_t v = forest.adj[q];
        if (v != prev && keep(v)) {
          next = v;
          step = forest.length[q];
          break;
        }
      }
      prev = cur;
      cur = next;
      length += step;
      nodes.push_back(cur);
    }
  };
  auto all = [](std::uint32_t) { return true; };
  auto full_degree = [&](std::uint32_t v) { return forest.degree(v); };

  std::vector<Branch> leaf_branches;
  std::vector<std::size_t> order;
  Branch scratch;
  for (const std::uint32_t c : members) {
    if (forest.degree(c) < 3) continue;
    leaf_branches.clear();
    for (std::uint32_t k = forest.first[c]; k < forest.first[c + 1]; ++k) {
      walk(c, k, full_degree, all, scratch.nodes, scratch.length);
      if (forest.degree(scratch.nodes.back()) == 1) leaf_branches.push_back(scratch);
    }
    // Short leaf branches go, but the fork keeps two branches at least: the longest short ones
    // (by particles, then length; ties by their first node, the adjacency order) stay.
    order.resize(leaf_branches.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      const Branch& p = leaf_branches[x];
      const Branch& q = leaf_branches[y];
      if (p.nodes.size() != q.nodes.size()) return p.nodes.size() > q.nodes.size();
      return p.length > q.length;
    });
    const std::size_t others = forest.degree(c) - leaf_branches.size();
    std::size_t kept = others;
    for (const std::size_t x : order) {
      const Branch& b = leaf_branches[x];
      if (b.nodes.size() >= static_cast<std::size_t>(k_trim) || kept < 2) {
        ++kept;
        continue;
      }
      for (const std::uint32_t v : b.nodes) removed[v] = 1;
    }
  }

  auto keep = [&](std::uint32_t v) { return removed[v] == 0; };
  auto kept_degree = [&](std::uint32_t v) {
    std::uint32_t d = 0;
    for (std::uint32_t q = forest.first[v]; q < forest.first[v + 1]; ++q) d += keep(forest.adj[q]);
    return d;
  };
  std::vector<std::uint32_t> nodes;
  double length = 0;
  for (const std::uint32_t u : members) {
    if (!keep(u)) continue;
    const std::uint32_t d = kept_degree(u);
    if (d == 2 || d == 0) continue;
    for (std::uint32_t k = forest.first[u]; k < forest.first[u + 1]; ++k) {
      if (!keep(forest.adj[k])) continue;
      walk(u, k, kept_degree, keep, nodes, length);
      // Each chain is found from both of its ends: keep it once, from its smaller end.
      if (u > nodes.back()) continue;
      std::vector<std::uint32_t> line;
      line.reserve(nodes.size() + 1);
      line.push_back(u);
      line.insert(line.end(), nodes.begin(), nodes.end());
      out.push_back(std::move(line));
    }
  }
  for (const std::uint32_t v : members) removed[v] = 0;
}

// Moves points[i] for i in `which` onto f == iso by Newton steps along ∇f, batched; a point that
// does not get there within the tolerance goes back to fallback[i].
void reproject(const Field& field, std::vector<Vec3>& points, const std::vector<double>& delta,
               const std::vector<Vec3>& fallback, std::vector<std::size_t> which,
               const Context* ctx) {
  const double iso = field.iso();
  std::vector<Vec3> at;
  std::vector<double> values;
  std::vector<Vec3> gradients;
  for (int step = 0; step <= kProjectSteps && !which.empty(); ++step) {
    at.resize(which.size());
    for (std::size_t j = 0; j < which.size(); ++j) at[j] = points[which[j]];
    values.resize(which.size());
    gradients.resize(which.size());
    field.evaluate(at, values, gradients, ctx);
    std::size_t left = 0;
    for (std::size_t j = 0; j < which.size(); ++j) {
      const std::size_t i = which[j];
      const double g2 = gradients[j].squaredNorm();
      const double r = values[j] - iso;
      const bool usable = g2 > 0 && std::isfinite(g2) && std::isfinite(r);
      if (usable && std::abs(r) <= kProjectTolerance * delta[i] * std::sqrt(g2)) continue;
      const Vec3 move = (r / g2) * gradients[j];
      if (!usable || step == kProjectSteps || !(move.norm() <= kMaxProjectStep * delta[i])) {
        points[i] = fallback[i];
        continue;
      }
      points[i] = at[j] - move;
      which[left++] = i;
    }
    which.resize(left);
  }
}

}  // namespace

std::vector<Polyline> suggestive_contours(const Field& field, const ParticleSystem& particles,
                                          const Camera& camera, const LineOptions& options,
                                          LineStats* stats, const Context* ctx) {
  validate(camera);
  validate(options);
  const auto start = Clock::now();
  const std::uint64_t evals_before = field.evaluations();
  if (ctx != nullptr) ctx->report("lines: suggestive", 0.0);

  // §5.1.
  const std::vector<std::uint32_t> chosen =
      suggestive_particles(field, particles, camera, options, ctx);
  check_cancel(ctx);
  const std::size_t n = chosen.size();
  std::vector<Vec3> pos(n);
  std::vector<double> delta(n), radius(n);
  for (std::size_t i = 0; i < n; ++i) {
    const SurfaceParticle& p = particles.particles[chosen[i]];
    pos[i] = p.position;
    delta[i] = p.delta;
    radius[i] = options.cluster_radius * p.delta;
  }

  // §5.2–5.3: clusters and their spanning trees.
  const std::vector<Edge> edges = spanning_forest(pos, radius, options.cluster_k, ctx);
  check_cancel(ctx);
  const Forest forest(n, edges);
  DisjointSets sets(n);
  for (const Edge& e : edges) sets.unite(e.a, e.b);
  std::vector<std::uint32_t> cluster_of(n);
  std::vector<std::vector<std::uint32_t>> clusters;  // members ascending, by smallest member
  {
    std::vector<std::uint32_t> id_of_root(n, UINT32_MAX);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t r = sets.find(i);
      if (id_of_root[r] == UINT32_MAX) {
        id_of_root[r] = static_cast<std::uint32_t>(clusters.size());
        clusters.emplace_back();
      }
      cluster_of[i] = id_of_root[r];
      clusters[cluster_of[i]].push_back(i);
    }
  }

  // §5.3: each large enough cluster's line(s), as node sequences.
  std::vector<std::vector<std::uint32_t>> paths;
  {
    std::vector<double> dist(n, 0);
    std::vector<std::uint32_t> parent(n, 0), stack;
    std::vector<std::uint8_t> removed(n, 0);
    for (const std::vector<std::uint32_t>& members : clusters) {
      if (members.size() < static_cast<std::size_t>(options.min_cluster)) continue;
      if (options.fit == SuggestiveFit::kLongestPath) {
        paths.push_back(longest_path(forest, members, dist, parent, stack));
      } else {
        trimmed_paths(forest, members, options.k_trim, removed, paths);
      }
    }
  }

  // Points, then `smoothing` passes of Laplacian smoothing with fixed ends, each re-projected.
  std::vector<std::size_t> first(paths.size() + 1, 0);
  for (std::size_t l = 0; l < paths.size(); ++l) first[l + 1] = first[l] + paths[l].size();
  std::vector<Vec3> points(first.back());
  std::vector<double> point_delta(first.back());
  for (std::size_t l = 0; l < paths.size(); ++l) {
    for (std::size_t j = 0; j < paths[l].size(); ++j) {
      points[first[l] + j] = pos[paths[l][j]];
      point_delta[first[l] + j] = delta[paths[l][j]];
    }
  }
  std::vector<std::size_t> interior;
  for (std::size_t l = 0; l < paths.size(); ++l) {
    for (std::size_t i = first[l] + 1; i + 1 < first[l + 1]; ++i) interior.push_back(i);
  }
  if (!interior.empty()) {
    std::vector<Vec3> before;
    for (int pass = 0; pass < options.smoothing; ++pass) {
      check_cancel(ctx);
      before = points;
      for (const std::size_t i : interior) {
        const Vec3 mean = 0.5 * (before[i - 1] + before[i + 1]);
        points[i] = before[i] + kSmoothing * (mean - before[i]);
      }
      reproject(field, points, point_delta, before, interior, ctx);
    }
  }

  std::vector<Polyline> lines;
  lines.reserve(paths.size());
  double total = 0;
  for (std::size_t l = 0; l < paths.size(); ++l) {
    Polyline line;
    line.kind = LineKind::kSuggestive;
    line.points.assign(points.begin() + static_cast<std::ptrdiff_t>(first[l]),
                       points.begin() + static_cast<std::ptrdiff_t>(first[l + 1]));
    double length = 0, mean_delta = 0;
    for (std::size_t j = 1; j < line.points.size(); ++j)
      length += (line.points[j] - line.points[j - 1]).norm();
    for (std::size_t i = first[l]; i < first[l + 1]; ++i) mean_delta += point_delta[i];
    mean_delta /= static_cast<double>(paths[l].size());
    if (length < options.min_line_length * mean_delta) continue;
    total += length;
    lines.push_back(std::move(line));
  }

  if (stats != nullptr) {
    stats->suggestive_particles += n;
    stats->suggestive_clusters += clusters.size();
    stats->lines[static_cast<int>(LineKind::kSuggestive)] += lines.size();
    stats->length[static_cast<int>(LineKind::kSuggestive)] += total;
    stats->seconds_suggestive += seconds_since(start);
    stats->field_evals += field.evaluations() - evals_before;
  }
  if (ctx != nullptr) ctx->report("lines: suggestive", 1.0);
  return lines;
}

}  // namespace ramiform
