// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/grow/branch_cleanup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"
#include "ramiform/grow/space_colonization.h"

namespace ramiform {
namespace {

constexpr std::uint32_t kNone = UINT32_MAX;
// A tip branch counts as shorter than L when its length is below L (1 + kLengthTie): a grown
// branch of exactly k steps has length k D only up to rounding, and it should fall on the same
// side of "shorter than k steps" every time (the short side, so prune = 2 removes 2-step stubs).
constexpr double kLengthTie = 1e-6;

[[noreturn]] void fail(const char* who, const std::string& what) {
  throw InvalidArgument(std::string(who) + ": " + what);
}

// Orients the edges away from the roots (breadth first): one parent per node, kNone for roots
// and isolated nodes. The same checks as assign_pipe_radii, so both accept the same skeletons.
std::vector<std::uint32_t> orient(const Skeleton& skeleton, std::span<const std::uint32_t> roots,
                                  const char* who) {
  const std::size_t n = skeleton.nodes.size();
  std::vector<std::vector<std::uint32_t>> adj(n);
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto [a, b] = skeleton.edges[e];
    if (a >= n || b >= n || a == b) fail(who, "edge " + std::to_string(e) + " is invalid");
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
  std::vector<std::uint32_t> parent(n, kNone), queue;
  std::vector<std::uint8_t> seen(n, 0);
  queue.reserve(n);
  for (const std::uint32_t r : roots) {
    if (r >= n) fail(who, "root " + std::to_string(r) + " is out of range");
    if (seen[r])
      fail(who,
           "root " + std::to_string(r) + " is repeated or shares a component with another root");
    seen[r] = 1;
    std::size_t head = queue.size();
    queue.push_back(r);
    for (; head < queue.size(); ++head) {
      const std::uint32_t v = queue[head];
      for (const std::uint32_t w : adj[v]) {
        if (w == parent[v]) continue;
        if (seen[w])
          fail(who,
               "the skeleton has a cycle or joins two roots (at node " + std::to_string(w) + ")");
        seen[w] = 1;
        parent[w] = v;
        queue.push_back(w);
      }
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (!seen[v] && !adj[v].empty())
      fail(who, "node " + std::to_string(v) + " is not connected to any root");
  return parent;
}

// Angle between the edges a->v and v->b, degrees (0: straight on). atan2 of |cross| and dot is
// accurate near 0 and 180 degrees, where acos of a normalized dot is not.
double turn_deg(const Vec3& a, const Vec3& v, const Vec3& b) {
  const Vec3 u = v - a;
  const Vec3 w = b - v;
  return pm::atan2(u.cross(w).norm(), u.dot(w)) * (180.0 / std::numbers::pi);
}

double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double at = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(at));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (at - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

double extent(const Skeleton& skeleton) {
  if (skeleton.nodes.empty()) return 0.0;
  Vec3 lo = skeleton.nodes.front().position, hi = lo;
  for (const SkeletonNode& node : skeleton.nodes) {
    lo = lo.cwiseMin(node.position);
    hi = hi.cwiseMax(node.position);
  }
  return (hi - lo).norm();
}

// The working state of clean_branches: the oriented forest with removed nodes skipped.
struct Forest {
  std::vector<std::uint32_t> parent;  // nearest surviving ancestor, kNone for roots
  std::vector<std::uint8_t> is_root;
  std::vector<std::uint8_t> alive;
  std::vector<std::uint32_t> children;  // surviving children
  std::vector<std::uint32_t> child;     // one surviving child (the only one when children == 1)

  void count_children() {
    std::fill(children.begin(), children.end(), 0);
    for (std::uint32_t v = 0; v < parent.size(); ++v) {
      if (!alive[v] || parent[v] == kNone) continue;
      ++children[parent[v]];
      child[parent[v]] = v;
    }
  }
  [[nodiscard]] bool is_chain(std::uint32_t v) const {
    return alive[v] && !is_root[v] && parent[v] != kNone && children[v] == 1;
  }
};

}  // namespace

void BranchCleanupOptions::validate() const {
  const char* who = "branch cleanup";
  if (smooth_iterations < 0 || smooth_iterations > kMaxSmoothIterations)
    fail(who, "smooth_iterations must be in " + range_text(0, kMaxSmoothIterations) + " (got " +
                  std::to_string(smooth_iterations) + ")");
  if (!(max_turn_deg > 0 && max_turn_deg <= 180))
    fail(who, "max_turn_deg must be in (0, 180] (got " + format_number(max_turn_deg) + ")");
  if (!(std::isfinite(prune_length) && prune_length >= 0))
    fail(who, "prune_length must be finite and >= 0 (got " + format_number(prune_length) + ")");
  if (!(short_length >= 0))  // +inf is fine: every tip branch counts as short
    fail(who, "short_length must be >= 0 (got " + format_number(short_length) + ")");
  if (!(std::isfinite(tip_radius) && tip_radius > 0))
    fail(who, "tip_radius must be finite and > 0 (got " + format_number(tip_radius) + ")");
  constexpr double lo = ColonizationOptions::kMinPipeExponent;
  constexpr double hi = ColonizationOptions::kMaxPipeExponent;
  if (!(pipe_exponent >= lo && pipe_exponent <= hi))
    fail(who, "pipe_exponent must be in " + range_text(lo, hi) + " (got " +
                  format_number(pipe_exponent) + ")");
}

BranchShape measure_branches(const Skeleton& skeleton, std::span<const std::uint32_t> roots,
                             double short_length) {
  const char* who = "measure_branches";
  const std::size_t n = skeleton.nodes.size();
  std::vector<std::vector<std::uint32_t>> adj(n);
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto [a, b] = skeleton.edges[e];
    if (a >= n || b >= n || a == b) fail(who, "edge " + std::to_string(e) + " is invalid");
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
  std::vector<std::uint8_t> is_root(n, 0);
  for (const std::uint32_t r : roots) {
    if (r >= n) fail(who, "root " + std::to_string(r) + " is out of range");
    is_root[r] = 1;
  }
  BranchShape shape;
  std::vector<double> turns;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (adj[v].size() != 2) continue;
    turns.push_back(turn_deg(skeleton.nodes[adj[v][0]].position, skeleton.nodes[v].position,
                             skeleton.nodes[adj[v][1]].position));
  }
  std::sort(turns.begin(), turns.end());
  shape.chain_nodes = turns.size();
  shape.turn_p50_deg = percentile(turns, 0.5);
  shape.turn_p90_deg = percentile(turns, 0.9);
  shape.turn_max_deg = turns.empty() ? 0.0 : turns.back();
  for (std::uint32_t t = 0; t < n; ++t) {
    if (adj[t].size() != 1 || is_root[t]) continue;
    ++shape.tip_branches;
    double length = 0;
    std::uint32_t prev = t, cur = adj[t][0];
    length += (skeleton.nodes[cur].position - skeleton.nodes[t].position).norm();
    // Walk through chain nodes; n steps bound it even on a malformed (cyclic) input.
    for (std::size_t k = 0; k < n && adj[cur].size() == 2 && !is_root[cur]; ++k) {
      const std::uint32_t next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
      length += (skeleton.nodes[next].position - skeleton.nodes[cur].position).norm();
      prev = cur;
      cur = next;
    }
    if (length < short_length * (1 + kLengthTie)) ++shape.short_tip_branches;
  }
  return shape;
}

BranchCleanupReport clean_branches(Skeleton& skeleton, std::span<const std::uint32_t> roots,
                                   const BranchCleanupOptions& options, Context* ctx) {
  options.validate();
  const double short_length =
      options.short_length > 0 ? options.short_length : options.prune_length;
  const std::size_t n = skeleton.nodes.size();
  Forest f;
  f.parent = orient(skeleton, roots, "clean_branches");
  BranchCleanupReport report;
  report.before = measure_branches(skeleton, roots, short_length);
  f.is_root.assign(n, 0);
  for (const std::uint32_t r : roots) f.is_root[r] = 1;
  f.alive.assign(n, 1);
  f.children.assign(n, 0);
  f.child.assign(n, kNone);

  std::vector<Vec3> x0(n);
  for (std::size_t v = 0; v < n; ++v) x0[v] = skeleton.nodes[v].position;
  const double coincident = tol::kCoincident * extent(skeleton);
  const bool smoothing = options.smooth_iterations > 0;
  std::vector<Vec3> x;
  std::vector<std::uint32_t> chain;
  std::vector<Vec3> next;
  std::vector<std::uint8_t> dead(n, 0);
  for (;;) {
    check_cancel(ctx);
    ++report.rounds;
    f.count_children();
    // Smoothing from the input positions: the result depends only on the topology and N.
    x = x0;
    chain.clear();
    for (std::uint32_t v = 0; v < n; ++v)
      if (f.is_chain(v)) chain.push_back(v);
    next.resize(chain.size());
    for (int it = 0; it < options.smooth_iterations; ++it) {
      for (std::size_t k = 0; k < chain.size(); ++k) {
        const std::uint32_t v = chain[k];
        // Three products, not (a + b) / 4: no overflow near the end of the double range.
        next[k] = 0.5 * x[v] + 0.25 * x[f.parent[v]] + 0.25 * x[f.child[v]];
      }
      for (std::size_t k = 0; k < chain.size(); ++k) x[chain[k]] = next[k];
    }

    std::fill(dead.begin(), dead.end(), 0);
    bool removed = false;
    // Stubs first, so that a kink inside a pruned stub counts as part of the stub.
    if (options.prune_length > 0) {
      struct Stub {
        std::uint32_t tip, fork;
        double length;
      };
      std::vector<Stub> stubs;
      std::vector<std::uint32_t> stub_count(n, 0);
      for (std::uint32_t t = 0; t < n; ++t) {
        if (!f.alive[t] || f.is_root[t] || f.parent[t] == kNone || f.children[t] != 0) continue;
        double length = 0;
        std::uint32_t u = t;
        for (;;) {
          const std::uint32_t p = f.parent[u];
          length += (x[u] - x[p]).norm();
          if (f.is_root[p] || f.children[p] != 1) {
            u = p;
            break;
          }
          u = p;
        }
        if (f.children[u] >= 2 && length < options.prune_length * (1 + kLengthTie)) {
          stubs.push_back({t, u, length});
          ++stub_count[u];
        }
      }
      // A node whose every child branch is a stub keeps its longest (ties: smaller tip index).
      std::vector<std::uint32_t> keep(n, kNone);
      std::vector<double> keep_length(n, -1.0);
      for (const Stub& s : stubs) {
        if (stub_count[s.fork] != f.children[s.fork]) continue;
        if (s.length > keep_length[s.fork]) {
          keep_length[s.fork] = s.length;
          keep[s.fork] = s.tip;
        }
      }
      for (const Stub& s : stubs) {
        if (keep[s.fork] == s.tip) continue;
        ++report.stubs_pruned;
        for (std::uint32_t u = s.tip; u != s.fork; u = f.parent[u]) {
          dead[u] = 1;
          ++report.nodes_removed;
        }
        removed = true;
      }
    }
    if (smoothing) {
      for (const std::uint32_t v : chain) {
        if (dead[v]) continue;
        const Vec3& a = x[f.parent[v]];
        const Vec3& b = x[f.child[v]];
        const bool degenerate = (x[v] - a).norm() <= coincident || (b - x[v]).norm() <= coincident;
        if (degenerate || turn_deg(a, x[v], b) > options.max_turn_deg) {
          dead[v] = 2;
          ++report.kinks_removed;
          ++report.nodes_removed;
          removed = true;
        }
      }
    }
    if (!removed) break;
    // Join every survivor to its nearest surviving ancestor. Pruned nodes are never ancestors
    // of survivors (a stub holds the whole subtree below its fork), kinks may be.
    std::vector<std::uint32_t> parent = f.parent;
    for (std::uint32_t v = 0; v < n; ++v) {
      if (!f.alive[v] || dead[v]) continue;
      std::uint32_t p = f.parent[v];
      while (p != kNone && dead[p]) p = f.parent[p];
      parent[v] = p;
    }
    f.parent = std::move(parent);
    for (std::uint32_t v = 0; v < n; ++v)
      if (dead[v]) f.alive[v] = 0;
  }

  for (std::uint32_t v = 0; v < n; ++v)
    if (f.alive[v] && x[v] != x0[v]) ++report.nodes_moved;
  std::vector<std::uint32_t> new_roots(roots.begin(), roots.end());
  if (report.nodes_removed == 0) {
    // Same topology: only positions change, edges and radii stay as given.
    for (std::size_t v = 0; v < n; ++v) skeleton.nodes[v].position = x[v];
  } else {
    std::vector<std::uint32_t> index(n, kNone);
    Skeleton out;
    for (std::uint32_t v = 0; v < n; ++v) {
      if (!f.alive[v]) continue;
      index[v] = static_cast<std::uint32_t>(out.nodes.size());
      out.nodes.push_back({x[v], skeleton.nodes[v].radius});
    }
    for (std::uint32_t v = 0; v < n; ++v)
      if (f.alive[v] && f.parent[v] != kNone) out.edges.push_back({index[f.parent[v]], index[v]});
    for (std::uint32_t& r : new_roots) r = index[r];
    assign_pipe_radii(out, new_roots, options.tip_radius, options.pipe_exponent);
    skeleton = std::move(out);
  }
  report.after = measure_branches(skeleton, new_roots, short_length);
  return report;
}

std::string cleanup_summary(const BranchCleanupReport& report, const std::string& short_what) {
  auto fixed = [](double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return std::string(buf);
  };
  auto turns = [&](const BranchShape& s) {
    return fixed(s.turn_p50_deg) + "/" + fixed(s.turn_p90_deg) + "/" + fixed(s.turn_max_deg) +
           " deg";
  };
  auto tips = [&](const BranchShape& s) {
    return std::to_string(s.short_tip_branches) + " of " + std::to_string(s.tip_branches) + " (" +
           fixed(100.0 * s.short_share()) + " %)";
  };
  std::string out = "cleanup: " + std::to_string(report.nodes_moved) + " nodes moved, " +
                    std::to_string(report.nodes_removed) + " removed (" +
                    std::to_string(report.kinks_removed) + " kinks, " +
                    std::to_string(report.stubs_pruned) + " stubs pruned); ";
  out += "turn at chain nodes p50/p90/max " + turns(report.before) + " -> " + turns(report.after) +
         "; tip branches shorter than " + short_what + " " + tips(report.before) + " -> " +
         tips(report.after);
  return out;
}

}  // namespace ramiform
