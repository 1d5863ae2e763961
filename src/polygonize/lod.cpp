// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/lod.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>

#include <cmath>
#include <cstdint>

#include "core/segment.h"
#include "ramiform/core/errors.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/polygonize/coarsen.h"

namespace ramiform {
namespace {

using Tol = ToleranceOptions;

}  // namespace

void validate_lod_levels(std::span<const LodLevel> levels) {
  if (levels.empty()) throw InvalidArgument("lod: no level given");
  const bool budgets = levels[0].max_triangles > 0;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const LodLevel& l = levels[k];
    const std::string which = "lod: level " + std::to_string(k);
    if ((l.max_triangles > 0) == (l.tolerance > 0) || (l.max_triangles > 0) != budgets) {
      throw InvalidArgument(
          which + " must give a tolerance or a triangle budget, the same kind as level 0");
    }
    if (!budgets && !(l.tolerance >= Tol::kMinTolerance && l.tolerance <= Tol::kMaxTolerance)) {
      throw InvalidArgument(which + ": tolerance " + format_number(l.tolerance) + " is outside [" +
                            format_number(Tol::kMinTolerance) + ", " +
                            format_number(Tol::kMaxTolerance) + "]");
    }
    if (k > 0 && (budgets ? l.max_triangles >= levels[k - 1].max_triangles
                          : l.tolerance <= levels[k - 1].tolerance)) {
      throw InvalidArgument(which + " is not coarser than level " + std::to_string(k - 1) +
                            " (give the levels finest first: tolerances increasing, budgets "
                            "decreasing)");
    }
  }
}

namespace {

struct Attempt {
  TriMesh mesh;
  LodStats stats;
};

Attempt mesh_at(const Field& field, const Skeleton& skeleton, const Tol& base, double tolerance,
                std::size_t budget, int levels, Context* ctx) {
  Tol o = base;
  o.tolerance = std::clamp(tolerance, Tol::kMinTolerance, Tol::kMaxTolerance);
  o.max_triangles = budget;
  o.tets.levels = levels;
  Attempt a;
  a.mesh = polygonize_to_tolerance(field, skeleton, o, ctx, &a.stats.mesher);
  a.stats.tolerance = o.tolerance;
  a.stats.levels = levels;
  a.stats.triangles = a.mesh.triangle_count();
  return a;
}

// Douglas-Peucker on the chain nodes[first..last] (indices into `chain`): keeps the node
// farthest from the chord when it lies more than `tol` of the smaller end radius away, or when
// the radius along the span changes by more than a third.
void keep_span(const Skeleton& sk, const std::vector<std::uint32_t>& chain, std::size_t first,
               std::size_t last, double tol, std::vector<char>& keep) {
  if (last <= first + 1) return;
  const Vec3 a = sk.nodes[chain[first]].position;
  const Vec3 b = sk.nodes[chain[last]].position;
  const double ra = sk.nodes[chain[first]].radius, rb = sk.nodes[chain[last]].radius;
  const Vec3 d = b - a;
  double worst = -1;
  std::size_t at = first;
  for (std::size_t k = first + 1; k < last; ++k) {
    const SkeletonNode& n = sk.nodes[chain[k]];
    const double t = detail::segment_parameter(n.position, a, b);
    const double r_line = ra + t * (rb - ra);
    const double off = (n.position - (a + t * d)).norm() / std::min(ra, rb);
    const double taper = std::abs(n.radius - r_line) / r_line;  // radius off the straight taper
    const double score = std::max(off / tol, taper * 3.0);
    if (score > worst) {
      worst = score;
      at = k;
    }
  }
  if (worst > 1.0) {
    keep[at] = 1;
    keep_span(sk, chain, first, at, tol, keep);
    keep_span(sk, chain, at, last, tol, keep);
  }
}

}  // namespace

Skeleton simplify_chains(const Skeleton& skeleton, double tolerance) {
  if (!(tolerance > 0) || !std::isfinite(tolerance)) {
    throw InvalidArgument("simplify_chains: tolerance must be > 0, got " +
                          format_number(tolerance));
  }
  const std::size_t n = skeleton.nodes.size();
  std::vector<std::vector<std::uint32_t>> adj(n);
  for (const auto& e : skeleton.edges) {
    adj[e[0]].push_back(e[1]);
    adj[e[1]].push_back(e[0]);
  }
  std::vector<char> kept(n, 0);
  for (std::size_t i = 0; i < n; ++i) kept[i] = adj[i].size() != 2 ? 1 : 0;
  Skeleton out;
  std::vector<std::uint32_t> index(n, UINT32_MAX);
  const auto node_index = [&](std::uint32_t v) {
    if (index[v] == UINT32_MAX) {
      index[v] = static_cast<std::uint32_t>(out.nodes.size());
      out.nodes.push_back(skeleton.nodes[v]);
    }
    return index[v];
  };
  // Walk every chain from a kept node (nodes not of degree 2) to the next, in a fixed order.
  std::vector<char> done(n, 0);  // degree-2 nodes already walked
  const auto walk = [&](std::uint32_t start, std::uint32_t next) {
    std::vector<std::uint32_t> chain = {start};
    std::uint32_t prev = start, cur = next;
    while (!kept[cur] && !done[cur]) {
      done[cur] = 1;
      chain.push_back(cur);
      const std::uint32_t nxt = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
      prev = cur;
      cur = nxt;
    }
    if (!kept[cur] && done[cur] && cur != start) return;  // met a walked chain: a cycle's end
    chain.push_back(cur);
    std::vector<char> keep(chain.size(), 0);
    keep.front() = keep.back() = 1;
    if (chain.front() == chain.back()) {
      std::fill(keep.begin(), keep.end(), 1);  // a loop: kept whole (no doubled edge)
    } else {
      keep_span(skeleton, chain, 0, chain.size() - 1, tolerance, keep);
    }
    std::uint32_t last = node_index(chain.front());
    for (std::size_t k = 1; k < chain.size(); ++k) {
      if (!keep[k]) continue;
      const std::uint32_t v = node_index(chain[k]);
      if (v != last) out.edges.push_back({last, v});
      last = v;
    }
  };
  for (std::uint32_t v = 0; v < n; ++v) {
    if (!kept[v]) continue;
    node_index(v);
    for (const std::uint32_t w : adj[v]) {
      // Each chain once: from its smaller-index end, or (between two kept nodes) once per edge.
      if (kept[w] ? w > v : !done[w]) walk(v, w);
    }
  }
  // Cycles of degree-2 nodes only: kept as they are.
  for (std::uint32_t v = 0; v < n; ++v) {
    if (kept[v] || done[v]) continue;
    kept[v] = 1;
    walk(v, adj[v][0]);
  }
  return out;
}

namespace {

// Coarsens the attempt's mesh to `budget` and measures the result; false when the collapses
// stop short of it.
bool coarsen_attempt(Attempt& a, const Field& field, const Skeleton& skeleton, const Tol& base,
                     std::size_t budget, Context* ctx) {
  const auto start = std::chrono::steady_clock::now();
  CoarsenOptions o;
  o.max_triangles = budget;
  CoarsenStats cs;
  coarsen_to_budget(a.mesh, field, skeleton, o, ctx, &cs);
  a.stats.coarsened_from = cs.triangles_before;
  a.stats.collapsed = cs.collapsed;
  a.stats.triangles = a.mesh.triangle_count();
  if (!cs.reached) return false;
  DeviationOptions d;
  d.samples = base.samples;
  d.vertices = false;
  a.stats.mesher.deviation = measure_deviation(a.mesh, field, &skeleton, d, ctx);
  a.stats.mesher.reached = a.stats.mesher.deviation.samples.p99 <= a.stats.tolerance;
  a.stats.seconds_coarsen =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}

double p99(const LodStats& s) { return s.mesher.deviation.samples.p99; }

// A budget level: the finest mesh within `budget` found by scaling the tolerance, or a
// coarsened one (see polygonize_lods()). `finer` (may be null): the previous level.
Attempt mesh_to_budget(const Field& field, const Skeleton& skeleton, const Tol& base,
                       double tolerance, std::size_t budget, const TriMesh* finer,
                       const LodStats* finer_stats, Context* ctx) {
  constexpr int kAttempts = 5;
  constexpr double kLow = 0.75;  // a count of at least this share of the budget is good enough
  int levels = base.tets.levels;
  Attempt best;
  bool have = false;
  std::optional<Attempt> over;  // the mesh at 0 levels, when it is over the budget
  int made = 0;
  for (int i = 0; i < kAttempts; ++i) {
    Attempt a = mesh_at(field, skeleton, base, tolerance, budget, levels, ctx);
    ++made;
    const std::size_t n = a.stats.triangles;
    if (n > budget) {
      // The base mesh alone is over the budget (refinement never exceeds it).
      if (levels > TetrahedralOptions::kMinLevels) {
        --levels;
        --i;  // fewer base levels: not an attempt at the tolerance
        continue;
      }
      if (!have) over = std::move(a);
      break;
    }
    const bool stopped = a.stats.mesher.refine.budget_reached;
    // Better: within the budget and either not stopped by it where the best was, or finer.
    const bool better =
        !have || (best.stats.mesher.refine.budget_reached && !stopped) ||
        (stopped == best.stats.mesher.refine.budget_reached && n > best.stats.triangles);
    if (better) {
      best = std::move(a);
      have = true;
    }
    if (stopped) {
      tolerance = best.stats.tolerance * 1.5;  // stopped mid-way: ask for less
    } else if (static_cast<double>(n) < kLow * static_cast<double>(budget) &&
               tolerance > Tol::kMinTolerance) {
      tolerance =
          best.stats.tolerance * static_cast<double>(n) / (0.9 * static_cast<double>(budget));
    } else {
      break;
    }
    if (tolerance > Tol::kMaxTolerance && stopped) break;
  }
  // The previous level's mesh coarsened by edge collapses (coarsen.h) may lie closer to the
  // surface than what the polygonizer gives within the budget (it had to drop base levels).
  const LodStats& found = have ? best.stats : over->stats;
  if (finer != nullptr && finer->triangle_count() > budget && !found.mesher.reached &&
      p99(*finer_stats) < p99(found)) {
    Attempt c;
    c.mesh = *finer;
    c.stats = *finer_stats;
    if (coarsen_attempt(c, field, skeleton, base, budget, ctx) && p99(c.stats) < p99(found)) {
      best = std::move(c);
      have = true;
    }
  }
  if (!have) {
    // The polygonizer's coarsest mesh is over the budget: collapses take it down.
    Attempt& a = *over;
    if (!coarsen_attempt(a, field, skeleton, base, budget, ctx)) {
      throw InvalidArgument("lod: a budget of " + std::to_string(budget) +
                            " triangles is below the coarsest mesh of this skeleton (" +
                            std::to_string(a.stats.coarsened_from) + " triangles at 0 levels, " +
                            std::to_string(a.stats.triangles) +
                            " after every edge collapse that keeps it closed and on the surface)");
    }
    best = std::move(a);
  }
  best.stats.attempts = made;
  return best;
}

}  // namespace

std::vector<TriMesh> polygonize_lods(const Field& field, const Skeleton& skeleton,
                                     const ToleranceOptions& base, std::span<const LodLevel> levels,
                                     Context* ctx, std::vector<LodStats>* stats) {
  validate_lod_levels(levels);
  std::vector<TriMesh> meshes;
  std::vector<LodStats> all;
  double tolerance = base.tolerance;
  std::size_t cap = base.max_triangles;
  for (const LodLevel& l : levels) {
    Attempt a;
    if (l.max_triangles > 0) {
      a = mesh_to_budget(field, skeleton, base, tolerance, std::min(l.max_triangles, cap),
                         meshes.empty() ? nullptr : &meshes.back(),
                         all.empty() ? nullptr : &all.back(), ctx);
    } else {
      a = mesh_at(field, skeleton, base, l.tolerance, cap, base.tets.levels, ctx);
      a.stats.attempts = 1;
    }
    tolerance = a.stats.tolerance;
    cap = a.stats.triangles;
    all.push_back(a.stats);
    meshes.push_back(std::move(a.mesh));
  }
  if (stats != nullptr) *stats = std::move(all);
  return meshes;
}

}  // namespace ramiform
