// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/bark_uv.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/union_find.h"
#include "field/bvh.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"

namespace ramiform {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMaxDeltaU = 0.05;           // largest correction of u away from the angle / 2 pi
constexpr std::size_t kMaxBinsPerEdge = 256;  // bounds the bins of a very long, thin edge
constexpr std::size_t kMinBinSamples = 3;     // fewer vertices than this do not make a median

/// One skeleton edge, oriented along its chain, with its frame.
struct Seg {
  Vec3 a = Vec3::Zero();      // start point (chain order)
  Vec3 d = Vec3::UnitZ();     // unit direction
  double len = 0.0;           // length
  double ra = 1.0, rb = 1.0;  // node radii at a and at a + len d
  Vec3 n = Vec3::UnitX();     // frame: n, b = d x n, both orthogonal to d
  Vec3 b = Vec3::UnitY();
  std::uint32_t chain = 0;
  double s0 = 0.0;          // arc length of a along the chain
  bool free_start = false;  // the chain's root end (a cap follows)
  bool free_end = false;    // the chain's tip end (a cap follows)
  // Radius bins over this edge (first bin index into the chain's knots, count).
  std::size_t bin_first = 0, bin_count = 1;
};

/// A chain of edges with one (u, v) chart.
struct Chain {
  std::vector<std::uint32_t> segs;
  std::uint32_t parent = kNone;
  double fork_s = 0.0;           // arc length along the parent where this chain starts
  double theta0 = 0.0;           // angle of u = 0 in the transported frame
  std::vector<double> knot_s;    // bin centres (arc length)
  std::vector<double> knot_rho;  // the surface's radius there
  std::vector<double> knot_int;  // integral of 1 / rho from 0 to knot_s
  double v0 = 0.0;               // v at s = 0
};

/// Where a vertex sits relative to an edge.
struct Placement {
  std::uint32_t seg = kNone;
  double t = 0.0;         // axial coordinate along the edge's line (0 at a)
  Vec3 o = Vec3::Zero();  // offset from the axis, orthogonal to d
};

/// Over a cap (a chain's free end), in units of the end's radius: the inverse Gudermannian
/// asinh(tan phi) of the angle phi = atan2(beyond, r) past the end (Mercator's latitude), so that
/// v keeps pace with u as the circles shrink towards the pole and texels stay square; phi is
/// capped at kCapMaxAngle, where the texture has repeated half a time more along v.
constexpr double kCapMaxAngle = 85.0 * std::numbers::pi / 180.0;
double cap_offset(double beyond, double r) {
  return std::asinh(std::tan(std::min(std::atan2(beyond, r), kCapMaxAngle)));
}

double interpolated_radius(const Seg& g, double tc) {
  return g.len > 0.0 ? g.ra + (g.rb - g.ra) * (tc / g.len) : g.ra;
}

/// The relative distance of the assignment: (|p - q| + overshoot) / r.
double score(const Seg& g, const Vec3& p) {
  const Vec3 w = p - g.a;
  const double t = w.dot(g.d);
  const double tc = std::clamp(t, 0.0, g.len);
  const double dist = (w - tc * g.d).norm();
  return (dist + std::abs(t - tc)) / interpolated_radius(g, tc);
}

Placement place(const std::vector<Seg>& segs, std::uint32_t k, const Vec3& p) {
  const Seg& g = segs[k];
  const Vec3 w = p - g.a;
  Placement out;
  out.seg = k;
  out.t = w.dot(g.d);
  out.o = w - out.t * g.d;
  return out;
}

/// Any unit vector orthogonal to the unit vector d (deterministic).
Vec3 perpendicular(const Vec3& d) {
  const Vec3 axis = std::abs(d.x()) <= std::abs(d.y()) && std::abs(d.x()) <= std::abs(d.z())
                        ? Vec3::UnitX()
                        : (std::abs(d.y()) <= std::abs(d.z()) ? Vec3::UnitY() : Vec3::UnitZ());
  return (axis - axis.dot(d) * d).normalized();
}

double median_of(std::vector<double>& values) {
  const std::size_t mid = (values.size() - 1) / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  return values[mid];
}

class BarkChart {
 public:
  BarkChart(const Skeleton& skeleton, const BarkUvOptions& options)
      : skeleton_(skeleton), options_(options) {
    build_chains();
    build_frames();
  }

  [[nodiscard]] const std::vector<Seg>& segs() const { return segs_; }
  [[nodiscard]] std::size_t chain_count() const { return chains_.size(); }
  /// The chain chain `c` branches off (kNone for a root) and where along it, in arc length.
  [[nodiscard]] std::uint32_t parent_of(std::uint32_t c) const { return chains_[c].parent; }
  [[nodiscard]] double fork_s_of(std::uint32_t c) const { return chains_[c].fork_s; }
  /// The surface's radius measured at the start of chain `c` (its first bin).
  [[nodiscard]] double start_rho(std::uint32_t c) const { return chains_[c].knot_rho.front(); }
  /// The surface's radius measured along chain `c` at arc length s (the nearest bin).
  [[nodiscard]] double rho_at(std::uint32_t c, double s) const {
    const auto& ks = chains_[c].knot_s;
    const auto j = static_cast<std::size_t>(std::lower_bound(ks.begin(), ks.end(), s) - ks.begin());
    return chains_[c].knot_rho[std::min(j, ks.size() - 1)];
  }

  /// The edge a point belongs to (least relative distance; ties: the lower edge).
  [[nodiscard]] std::uint32_t nearest_seg(const Vec3& p) const {
    return bvh_.nearest(p, [&](std::uint32_t k) {
      const double s = score(segs_[k], p) * max_radius_;
      return s * s;
    });
  }

  /// The edge of chain `c` a point belongs to.
  [[nodiscard]] std::uint32_t nearest_seg_of_chain(std::uint32_t c, const Vec3& p) const {
    std::uint32_t best = kNone;
    double best_score = std::numeric_limits<double>::infinity();
    for (const std::uint32_t k : chains_[c].segs) {
      const double s = score(segs_[k], p);
      if (s < best_score) {
        best_score = s;
        best = k;
      }
    }
    return best;
  }

  /// Measures the surface's radius along every chain from the placed vertices, then sets the
  /// v functions and the charts' starting v.
  void fit_radii(const std::vector<Placement>& placed) {
    // Bins: per edge, about `radius_bin` node radii long.
    std::vector<std::vector<double>> samples;
    for (auto& chain : chains_) {
      for (const std::uint32_t k : chain.segs) {
        Seg& g = segs_[k];
        const double r = 0.5 * (g.ra + g.rb);
        const double want = std::ceil(g.len / (options_.radius_bin * r));
        g.bin_count =
            static_cast<std::size_t>(std::clamp(want, 1.0, static_cast<double>(kMaxBinsPerEdge)));
        g.bin_first = chain.knot_s.size();
        for (std::size_t j = 0; j < g.bin_count; ++j) {
          chain.knot_s.push_back(g.s0 + (static_cast<double>(j) + 0.5) * g.len /
                                            static_cast<double>(g.bin_count));
          chain.knot_rho.push_back(kNaN);
        }
      }
    }
    // Samples in vertex order (deterministic), only projections inside their edge (caps and
    // the outer side of bends would bias the median).
    std::vector<std::vector<std::vector<double>>> bins(chains_.size());
    for (std::size_t c = 0; c < chains_.size(); ++c) bins[c].resize(chains_[c].knot_s.size());
    std::vector<double> ratios;
    for (const Placement& pl : placed) {
      const Seg& g = segs_[pl.seg];
      if (!(pl.t >= 0.0 && pl.t <= g.len)) continue;
      const double r = pl.o.norm();
      const std::size_t j =
          g.len > 0.0
              ? std::min(g.bin_count - 1,
                         static_cast<std::size_t>(pl.t / g.len * static_cast<double>(g.bin_count)))
              : 0;
      bins[g.chain][g.bin_first + j].push_back(r);
      ratios.push_back(r / interpolated_radius(g, pl.t));
    }
    const double global_ratio =
        options_.measure_radius && !ratios.empty() ? median_of(ratios) : 1.0;
    for (std::size_t c = 0; c < chains_.size(); ++c) {
      Chain& chain = chains_[c];
      const std::size_t m = chain.knot_s.size();
      bool any = false;
      if (options_.measure_radius) {
        for (std::size_t j = 0; j < m; ++j) {
          if (bins[c][j].size() >= kMinBinSamples) {
            const double rho = median_of(bins[c][j]);
            if (rho > 0.0) {
              chain.knot_rho[j] = rho;
              any = true;
            }
          }
        }
      }
      if (!any) {
        // No measure: the node radii (scaled by the surface's overall ratio to them).
        for (const std::uint32_t k : chain.segs) {
          const Seg& g = segs_[k];
          for (std::size_t j = 0; j < g.bin_count; ++j) {
            const double tc = chain.knot_s[g.bin_first + j] - g.s0;
            chain.knot_rho[g.bin_first + j] = global_ratio * interpolated_radius(g, tc);
          }
        }
      } else {
        // Empty bins: linear between the measured neighbours, constant beyond the last.
        std::size_t prev = m;
        for (std::size_t j = 0; j < m; ++j) {
          if (std::isnan(chain.knot_rho[j])) continue;
          if (prev == m) {
            for (std::size_t i = 0; i < j; ++i) chain.knot_rho[i] = chain.knot_rho[j];
          } else {
            for (std::size_t i = prev + 1; i < j; ++i) {
              const double f =
                  (chain.knot_s[i] - chain.knot_s[prev]) / (chain.knot_s[j] - chain.knot_s[prev]);
              chain.knot_rho[i] =
                  chain.knot_rho[prev] + f * (chain.knot_rho[j] - chain.knot_rho[prev]);
            }
          }
          prev = j;
        }
        for (std::size_t i = prev + 1; i < m; ++i) chain.knot_rho[i] = chain.knot_rho[prev];
      }
      // The integral of 1 / rho, with 1 / rho linear between knots and constant outside.
      chain.knot_int.assign(m, 0.0);
      chain.knot_int[0] = chain.knot_s[0] / chain.knot_rho[0];
      for (std::size_t j = 1; j < m; ++j) {
        chain.knot_int[j] =
            chain.knot_int[j - 1] + 0.5 * (chain.knot_s[j] - chain.knot_s[j - 1]) *
                                        (1.0 / chain.knot_rho[j - 1] + 1.0 / chain.knot_rho[j]);
      }
    }
    // Charts start where their parent's v is at the fork (parents come first).
    for (auto& chain : chains_) {
      chain.v0 = chain.parent == kNone ? 0.0 : v_at(chains_[chain.parent], chain.fork_s);
    }
  }

  /// (u, v) of a placement in its edge's chart (u in [0, 1)).
  [[nodiscard]] Vec2 uv(const Placement& pl) const {
    const Seg& g = segs_[pl.seg];
    const Chain& chain = chains_[g.chain];
    const double r = pl.o.norm();
    double s = g.s0 + pl.t;
    if (pl.t < 0.0 && g.free_start) {
      s = g.s0 - chain.knot_rho.front() * cap_offset(-pl.t, r);
    } else if (pl.t > g.len && g.free_end) {
      s = g.s0 + g.len + chain.knot_rho.back() * cap_offset(pl.t - g.len, r);
    }
    const double theta = r > 0.0 ? std::atan2(pl.o.dot(g.b), pl.o.dot(g.n)) : 0.0;
    double u = (theta - chain.theta0) / kTwoPi;
    u -= std::floor(u);
    if (u >= 1.0) u = 0.0;  // -tiny - floor(-tiny) rounds to 1
    return {u, v_at(chain, s)};
  }

 private:
  [[nodiscard]] double v_at(const Chain& chain, double s) const {
    const auto& ks = chain.knot_s;
    const std::size_t m = ks.size();
    double integral = 0.0;
    if (s <= ks[0]) {
      integral = s / chain.knot_rho[0];
    } else if (s >= ks[m - 1]) {
      integral = chain.knot_int[m - 1] + (s - ks[m - 1]) / chain.knot_rho[m - 1];
    } else {
      const std::size_t j =
          static_cast<std::size_t>(std::upper_bound(ks.begin(), ks.end(), s) - ks.begin());
      const double h = ks[j] - ks[j - 1];
      const double f = h > 0.0 ? (s - ks[j - 1]) / h : 0.0;
      const double i0 = 1.0 / chain.knot_rho[j - 1], i1 = 1.0 / chain.knot_rho[j];
      // Integral of the linear 1 / rho from ks[j-1] to s.
      integral = chain.knot_int[j - 1] + (s - ks[j - 1]) * (i0 + 0.5 * f * (i1 - i0));
    }
    return chain.v0 + integral / kTwoPi;
  }

  struct Pending {
    std::uint32_t node, edge, parent;
    double fork_s;
  };

  void build_chains() {
    const auto& nodes = skeleton_.nodes;
    const auto& edges = skeleton_.edges;
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> adj(nodes.size());
    for (std::uint32_t e = 0; e < edges.size(); ++e) {
      adj[edges[e][0]].push_back({edges[e][1], e});
      adj[edges[e][1]].push_back({edges[e][0], e});
    }
    std::vector<char> visited(nodes.size(), 0), used(edges.size(), 0);
    const SkeletonComponents comps = connected_components(skeleton_);
    // Root of each component: the thickest leaf (ties: lower index), else the thickest node.
    std::vector<std::uint32_t> root(comps.count, kNone);
    std::vector<char> root_is_leaf(comps.count, 0);
    for (std::uint32_t i = 0; i < nodes.size(); ++i) {
      const std::uint32_t c = comps.label[i];
      const bool leaf = adj[i].size() <= 1;
      if (root[c] == kNone || (leaf && !root_is_leaf[c]) ||
          (leaf == static_cast<bool>(root_is_leaf[c]) && nodes[i].radius > nodes[root[c]].radius)) {
        root[c] = i;
        root_is_leaf[c] = leaf ? 1 : 0;
      }
    }
    auto pick = [&](std::uint32_t x, const Vec3& dir_in,
                    const std::vector<std::uint32_t>& candidates) {
      std::uint32_t best = kNone;
      double best_r = -1.0, best_align = -2.0;
      for (const std::uint32_t e : candidates) {
        const std::uint32_t y = edges[e][0] == x ? edges[e][1] : edges[e][0];
        const double r = nodes[y].radius;
        const double align = dir_in.dot((nodes[y].position - nodes[x].position).normalized());
        if (r > best_r || (r == best_r && align > best_align)) {
          best = e;
          best_r = r;
          best_align = align;
        }
      }
      return best;
    };
    std::deque<Pending> pending;
    for (std::uint32_t c = 0; c < comps.count; ++c) {
      const std::uint32_t x = root[c];
      visited[x] = 1;
      if (adj[x].empty()) {
        // An isolated node: a sphere, one chart over a zero-length edge.
        Chain chain;
        Seg g;
        g.a = nodes[x].position;
        g.ra = g.rb = nodes[x].radius;
        g.chain = static_cast<std::uint32_t>(chains_.size());
        g.free_start = g.free_end = true;
        chain.segs.push_back(static_cast<std::uint32_t>(segs_.size()));
        segs_.push_back(g);
        chains_.push_back(std::move(chain));
        continue;
      }
      std::vector<std::uint32_t> candidates;
      for (const auto& [y, e] : adj[x]) candidates.push_back(e);
      const std::uint32_t first = pick(x, Vec3::Zero(), candidates);
      const auto root_chain = static_cast<std::uint32_t>(chains_.size());
      walk(x, first, kNone, 0.0, adj, visited, used, pending, pick, true);
      for (const std::uint32_t e : candidates) {
        if (e != first) pending.push_back({x, e, root_chain, 0.0});
      }
      while (!pending.empty()) {
        const Pending p = pending.front();
        pending.pop_front();
        if (used[p.edge] != 0) continue;
        walk(p.node, p.edge, p.parent, p.fork_s, adj, visited, used, pending, pick, false);
      }
    }
  }

  template <class Pick>
  void walk(std::uint32_t x, std::uint32_t e, std::uint32_t parent, double fork_s,
            const std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>>& adj,
            std::vector<char>& visited, std::vector<char>& used, std::deque<Pending>& pending,
            Pick& pick, bool is_root) {
    const auto& nodes = skeleton_.nodes;
    const auto& edges = skeleton_.edges;
    const auto c = static_cast<std::uint32_t>(chains_.size());
    chains_.emplace_back();
    chains_[c].parent = parent;
    chains_[c].fork_s = fork_s;
    double s = 0.0;
    for (;;) {
      used[e] = 1;
      const std::uint32_t y = edges[e][0] == x ? edges[e][1] : edges[e][0];
      Seg g;
      g.a = nodes[x].position;
      const Vec3 ab = nodes[y].position - nodes[x].position;
      g.len = ab.norm();
      g.d = ab / g.len;
      g.ra = nodes[x].radius;
      g.rb = nodes[y].radius;
      g.chain = c;
      g.s0 = s;
      g.free_start = is_root && chains_[c].segs.empty();
      s += g.len;
      const bool closes_cycle = visited[y] != 0;
      visited[y] = 1;
      std::vector<std::uint32_t> candidates;
      if (!closes_cycle) {
        for (const auto& [z, f] : adj[y]) {
          if (used[f] == 0) candidates.push_back(f);
        }
      }
      g.free_end = !closes_cycle && candidates.empty();
      chains_[c].segs.push_back(static_cast<std::uint32_t>(segs_.size()));
      segs_.push_back(g);
      if (candidates.empty()) return;
      // Edges to visited nodes close cycles: chains of their own, like side branches.
      std::vector<std::uint32_t> open;
      for (const std::uint32_t f : candidates) {
        const std::uint32_t z = edges[f][0] == y ? edges[f][1] : edges[f][0];
        if (visited[z] == 0) open.push_back(f);
      }
      const std::uint32_t next = open.empty() ? kNone : pick(y, g.d, open);
      for (const std::uint32_t f : candidates) {
        if (f != next) pending.push_back({y, f, c, s});
      }
      if (next == kNone) {
        segs_.back().free_end = false;
        return;
      }
      x = y;
      e = next;
    }
  }

  void build_frames() {
    Vec3 away = -options_.facing;
    const double an = away.norm();
    if (an > 0.0) away /= an;
    std::vector<Aabb> boxes;
    boxes.reserve(segs_.size());
    for (auto& chain : chains_) {
      Vec3 n = Vec3::Zero();
      Vec3 prev_d = Vec3::Zero();
      double x = 0.0, y = 0.0;
      for (const std::uint32_t k : chain.segs) {
        Seg& g = segs_[k];
        if (n.isZero()) {
          n = perpendicular(g.d);
        } else {
          // Discrete parallel transport: the smallest rotation taking prev_d to d.
          const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(prev_d, g.d);
          n = q * n;
          n = (n - n.dot(g.d) * g.d);
          n = n.norm() > 0.0 ? n.normalized() : perpendicular(g.d);
        }
        g.n = n;
        g.b = g.d.cross(n);
        prev_d = g.d;
        const double w = std::max(g.len, 1e-300) * 0.5 * (g.ra + g.rb);
        x += w * away.dot(g.n);
        y += w * away.dot(g.b);
      }
      chain.theta0 = (x != 0.0 || y != 0.0) ? std::atan2(y, x) : 0.0;
    }
    max_radius_ = 0.0;
    for (const Seg& g : segs_) {
      Aabb box;
      box.extend(g.a);
      box.extend(g.a + g.len * g.d);
      boxes.push_back(box);
      max_radius_ = std::max({max_radius_, g.ra, g.rb});
    }
    bvh_ = detail::BoxBvh(std::move(boxes));
  }

  const Skeleton& skeleton_;
  const BarkUvOptions& options_;
  std::vector<Seg> segs_;
  std::vector<Chain> chains_;
  detail::BoxBvh bvh_;
  double max_radius_ = 1.0;
};

/// One triangle of a chart: its corners (the chart's unknowns), the gradients of its three hat
/// functions, its area and n x grad u (the conformal gradient for v).
struct ChartTri {
  std::array<std::uint32_t, 3> at{};
  std::array<Vec3, 3> grad{};
  double area = 0.0;
  Vec3 g = Vec3::Zero();
  Vec3 grad_u = Vec3::Zero();
  Vec3 normal = Vec3::Zero();
};

using Sparse = Eigen::SparseMatrix<double>;

constexpr int kRefineSteps = 3;           // Gauss-Newton steps of refine_stretch()
constexpr double kConformalWeight = 0.1;  // weight of |grad v - n x grad u|^2 there
constexpr double kAngleWeight = 0.03;     // weight of |grad du|^2 (u stays near the angle)
constexpr double kRobustStretch = 0.2;    // stretch error beyond which a triangle weighs less

/// The sparsity both of a chart's systems share, in one fill-reducing order. The chart's vertex
/// graph (each unknown with its triangles' other corners and itself) is ordered once by
/// approximate minimum degree; the conformal system (one unknown per vertex) and the stretch
/// system (v and du per vertex, side by side) are then assembled directly in that order, upper
/// triangle only, so that their factorizations need neither an ordering of their own nor a
/// permuted copy per step (the stretch system's graph is the vertex graph with 2 x 2 blocks).
class ChartPattern {
 public:
  ChartPattern(const std::vector<ChartTri>& tris, std::size_t m) : pos_(m) {
    // The vertex graph (each edge both ways, and every diagonal) as sorted unique (column, row)
    // pairs.
    std::vector<std::uint64_t> pairs;
    pairs.reserve(6 * tris.size() + m);
    for (const ChartTri& t : tris) {
      if (!(t.area > 0.0)) continue;
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          if (t.at[a] != t.at[b]) pairs.push_back(std::uint64_t{t.at[a]} << 32 | t.at[b]);
        }
      }
    }
    for (std::size_t i = 0; i < m; ++i) pairs.push_back(std::uint64_t{i} << 32 | i);
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    const auto M = static_cast<Eigen::Index>(m);
    Sparse graph(M, M);
    graph.resizeNonZeros(static_cast<Eigen::Index>(pairs.size()));
    std::fill(graph.outerIndexPtr(), graph.outerIndexPtr() + m + 1, 0);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      ++graph.outerIndexPtr()[(pairs[k] >> 32) + 1];
      graph.innerIndexPtr()[k] = static_cast<int>(pairs[k] & 0xffffffffu);
      graph.valuePtr()[k] = 1.0;
    }
    for (std::size_t j = 0; j < m; ++j) graph.outerIndexPtr()[j + 1] += graph.outerIndexPtr()[j];
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
    Eigen::AMDOrdering<int>()(graph, inverse);
    for (std::size_t k = 0; k < m; ++k) pos_[static_cast<std::size_t>(inverse.indices()[k])] = k;
    // The upper triangle in that order: column q holds the rows p <= q of its graph neighbours.
    std::vector<std::uint64_t> upper;
    upper.reserve(pairs.size() / 2 + m);
    for (const std::uint64_t e : pairs) {
      const std::size_t p = pos_[e >> 32], q = pos_[e & 0xffffffffu];
      if (p <= q) upper.push_back(std::uint64_t{q} << 32 | p);
    }
    std::sort(upper.begin(), upper.end());
    upper.erase(std::unique(upper.begin(), upper.end()), upper.end());
    single_ = Sparse(M, M);
    single_.resizeNonZeros(static_cast<Eigen::Index>(upper.size()));
    std::fill(single_.outerIndexPtr(), single_.outerIndexPtr() + m + 1, 0);
    // The stretch system: unknown 2p is v, 2p + 1 du of the vertex at position p.
    std::size_t double_nnz = 0;
    for (const std::uint64_t e : upper) double_nnz += (e >> 32) == (e & 0xffffffffu) ? 3 : 4;
    double_ = Sparse(2 * M, 2 * M);
    double_.resizeNonZeros(static_cast<Eigen::Index>(double_nnz));
    std::fill(double_.outerIndexPtr(), double_.outerIndexPtr() + 2 * m + 1, 0);
    std::size_t next = 0;
    for (std::size_t k = 0, begin = 0; k <= upper.size(); ++k) {
      if (k < upper.size() && (upper[k] >> 32) == (upper[begin] >> 32)) continue;
      // upper[begin, k) is one column q, rows ascending (the last is q itself).
      const std::size_t q = upper[begin] >> 32;
      for (int b = 0; b < 2; ++b) {
        for (std::size_t e = begin; e < k; ++e) {
          const std::size_t p = upper[e] & 0xffffffffu;
          double_.innerIndexPtr()[next++] = static_cast<int>(2 * p);
          if (p < q || b == 1) double_.innerIndexPtr()[next++] = static_cast<int>(2 * p + 1);
        }
        double_.outerIndexPtr()[2 * q + b + 1] = static_cast<int>(next);
      }
      begin = k;
    }
    for (std::size_t k = 0; k < upper.size(); ++k) {
      ++single_.outerIndexPtr()[(upper[k] >> 32) + 1];
      single_.innerIndexPtr()[k] = static_cast<int>(upper[k] & 0xffffffffu);
    }
    for (std::size_t j = 0; j < m; ++j)
      single_.outerIndexPtr()[j + 1] += single_.outerIndexPtr()[j];
    // Columns of the stretch system with no rows cannot occur (each has its diagonal), so the
    // running ends written above are every column's end.
  }

  /// The elimination position of the chart's unknown i.
  [[nodiscard]] std::size_t pos(std::size_t i) const { return pos_[i]; }
  /// The conformal system's upper triangle (values to be filled).
  [[nodiscard]] Sparse& single() { return single_; }
  /// The stretch system's upper triangle (values to be filled).
  [[nodiscard]] Sparse& stretch() { return double_; }

  /// The value slot of (row, col), row <= col, in `matrix`.
  [[nodiscard]] static std::size_t slot(const Sparse& matrix, std::size_t row, std::size_t col) {
    const int* begin = matrix.innerIndexPtr() + matrix.outerIndexPtr()[col];
    const int* end = matrix.innerIndexPtr() + matrix.outerIndexPtr()[col + 1];
    return static_cast<std::size_t>(std::lower_bound(begin, end, static_cast<int>(row)) -
                                    matrix.innerIndexPtr());
  }

 private:
  std::vector<std::size_t> pos_;
  Sparse single_, double_;
};

/// The factorization both systems use: the pattern's own order, no permuted copies.
using OrderedLdlt = Eigen::SimplicialLDLT<Sparse, Eigen::Upper, Eigen::NaturalOrdering<int>>;

/// The stretch of a triangle is |grad v| / |grad u|, whatever the angle between the two, and
/// the least-squares conjugate fits two components of grad v per triangle with one vertex per
/// two triangles, so it leaves a spread of stretch on coarse, curved parts (caps, forks). This
/// refines v, and u by a correction du per vertex, towards |grad v| = |grad u| per triangle,
/// each triangle weighted alike (the share by count is what is asked) and less when far off
/// (a pole's triangles cannot be helped; weight 1 / (1 + (e / kRobustStretch)^2) for a stretch
/// error e), keeping kConformalWeight of the conformal fit (grad v near n x grad u, so texels
/// stay nearly square in angle too) and kAngleWeight of |grad du|^2: kRefineSteps Gauss-Newton
/// steps on sum_t [(|grad v| - |grad u|)^2 + cw |grad v - n x grad u|^2 + aw |grad du|^2] / |g|^2
/// over the chart's triangles (g = n x grad u of the angle). x holds v on entry and exit, du
/// the correction of u (both as of the last step that succeeded; du = 0 if none did).
void refine_stretch(const std::vector<ChartTri>& tris, double sign, double eps,
                    const std::vector<double>& mass, double mass_floor,
                    const std::vector<std::uint32_t>& members, const std::vector<double>& ref,
                    ChartPattern& pattern, Eigen::VectorXd& x, Eigen::VectorXd& du) {
  const std::size_t m = members.size();
  const auto M = static_cast<Eigen::Index>(m);
  du = Eigen::VectorXd::Zero(M);
  OrderedLdlt solver;
  double scale = 0.0;
  std::size_t counted = 0;
  for (const ChartTri& t : tris) {
    const double g2 = t.g.squaredNorm();
    if (t.area > 0.0 && g2 > 0.0 && std::isfinite(g2)) {
      scale += t.area * g2;
      ++counted;
    }
  }
  if (counted == 0) return;
  scale /= static_cast<double>(counted);
  // The system's unknowns in the pattern's order: v of unknown i at 2 pos(i), du at 2 pos(i) + 1.
  auto corners = [&](const ChartTri& t) {
    std::array<std::size_t, 6> idx{};
    for (int k = 0; k < 3; ++k) {
      idx[k] = 2 * pattern.pos(t.at[k]);
      idx[k + 3] = idx[k] + 1;
    }
    return idx;
  };
  auto is_used = [](const ChartTri& t) {
    const double g2 = t.g.squaredNorm();
    return t.area > 0.0 && g2 > 0.0 && std::isfinite(g2);
  };
  Sparse& K = pattern.stretch();
  // The upper triangle's slot of each (a, b) of each used triangle (kNone below the diagonal;
  // the local matrix is symmetric, so the pairs kept sum to the whole of it).
  std::vector<std::uint32_t> slots;
  slots.reserve(36 * tris.size());
  for (const ChartTri& t : tris) {
    if (!is_used(t)) continue;
    const std::array<std::size_t, 6> idx = corners(t);
    for (int a = 0; a < 6; ++a) {
      for (int b = 0; b < 6; ++b) {
        slots.push_back(idx[a] <= idx[b]
                            ? static_cast<std::uint32_t>(ChartPattern::slot(K, idx[a], idx[b]))
                            : kNone);
      }
    }
  }
  std::vector<std::size_t> diag_slots(2 * m);
  for (std::size_t i = 0; i < 2 * m; ++i) diag_slots[i] = ChartPattern::slot(K, i, i);
  // The conformal and angle rows do not change from step to step: their normal matrix and
  // right-hand side per used triangle, once.
  struct Fixed {
    Eigen::Matrix<double, 6, 6> matrix;
    Eigen::Matrix<double, 6, 1> rhs;
  };
  std::vector<Fixed> fixed;
  fixed.reserve(tris.size());
  for (const ChartTri& t : tris) {
    if (!is_used(t)) continue;
    Fixed f;
    f.matrix.setZero();
    f.rhs.setZero();
    Eigen::Matrix<double, 6, 1> c;
    // grad v - sign n x grad u = 0 (conformal), per component.
    const Vec3 target = sign * t.normal.cross(t.grad_u);
    std::array<Vec3, 3> turned{};
    for (int k = 0; k < 3; ++k) turned[k] = sign * t.normal.cross(t.grad[k]);
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        c[k] = t.grad[k][i];
        c[k + 3] = -turned[k][i];
      }
      f.matrix.noalias() += kConformalWeight * c * c.transpose();
      f.rhs += kConformalWeight * target[i] * c;
    }
    // grad du = 0 (u stays near the angle).
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        c[k] = 0.0;
        c[k + 3] = t.grad[k][i];
      }
      f.matrix.noalias() += kAngleWeight * c * c.transpose();
    }
    fixed.push_back(f);
  }
  solver.analyzePattern(K);
  double* values = K.valuePtr();
  const auto nnz = static_cast<std::size_t>(K.nonZeros());
  for (int step = 0; step < kRefineSteps; ++step) {
    std::fill(values, values + nnz, 0.0);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * M);
    // Per triangle the 6 x 6 normal matrix of its rows (v at its corners, then du).
    Eigen::Matrix<double, 6, 6> local;
    Eigen::Matrix<double, 6, 1> local_rhs;
    std::size_t next_slot = 0, used = 0;
    for (const ChartTri& t : tris) {
      if (!is_used(t)) continue;
      const Fixed& f = fixed[used++];
      const double g2 = t.g.squaredNorm();
      Vec3 grad_v = Vec3::Zero(), grad_u = t.grad_u;
      for (int k = 0; k < 3; ++k) {
        grad_v += x[t.at[k]] * t.grad[k];
        grad_u += du[t.at[k]] * t.grad[k];
      }
      const double lv = grad_v.norm(), lu = grad_u.norm();
      const bool usable = lv > 0.0 && lu > 0.0;
      const Vec3 dv = usable ? Vec3(grad_v / lv) : Vec3::Zero();
      const Vec3 dunit = usable ? Vec3(grad_u / lu) : Vec3::Zero();
      const double res = usable ? lv / lu - 1.0 : 0.0;
      const double robust = 1.0 / (1.0 + (res / kRobustStretch) * (res / kRobustStretch));
      const double w = usable ? robust * scale / g2 : 0.0;
      // |grad v| - |grad u| = 0, linearized, with the fixed rows, all weighted by w.
      Eigen::Matrix<double, 6, 1> c;
      for (int k = 0; k < 3; ++k) {
        c[k] = dv.dot(t.grad[k]);
        c[k + 3] = -dunit.dot(t.grad[k]);
      }
      local.noalias() = w * (f.matrix + c * c.transpose());
      local_rhs.noalias() = w * (f.rhs + dunit.dot(t.grad_u) * c);
      const std::array<std::size_t, 6> idx = corners(t);
      for (int a = 0; a < 6; ++a) {
        rhs[static_cast<Eigen::Index>(idx[a])] += local_rhs[a];
        for (int b = 0; b < 6; ++b, ++next_slot) {
          if (slots[next_slot] != kNone) values[slots[next_slot]] += local(a, b);
        }
      }
    }
    for (std::size_t i = 0; i < m; ++i) {
      const double wr = eps * (mass[i] + mass_floor);
      const std::size_t p = 2 * pattern.pos(i);
      values[diag_slots[p]] += wr;
      rhs[static_cast<Eigen::Index>(p)] += wr * ref[members[i]];
      // du's constant (a turn of the whole chart, moving its seam) is held harder than v's.
      values[diag_slots[p + 1]] += 1e3 * wr;
    }
    solver.factorize(K);
    if (solver.info() != Eigen::Success) return;
    const Eigen::VectorXd next = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !next.allFinite()) return;
    for (std::size_t i = 0; i < m; ++i) {
      const auto p = static_cast<Eigen::Index>(2 * pattern.pos(i));
      x[static_cast<Eigen::Index>(i)] = next[p];
      du[static_cast<Eigen::Index>(i)] = next[p + 1];
    }
  }
}

/// v chart by chart as the least-squares conjugate of u: the v whose gradient comes closest
/// (area-weighted, over the chart's triangles) to n x grad u, the gradient that makes the map
/// conformal (square texels) wherever u is. On a surface of revolution this is Mercator's
/// v = integral of dl / (2 pi rho) along the meridian with each point's own rho, so it follows
/// caps, bulges and non-round cross-sections that a radius measured per bin cannot. Each chart's
/// constant is set so that v matches the measured-radius v (`out.uvs` on entry) near the chart's
/// start plus the drift its parent has at the fork; wrap copies share their original's v.
/// refine_stretch() then evens out |grad v| / |grad u| per triangle and corrects u by at most
/// kMaxDeltaU (wrap copies keep u + 1; original u may leave [0, 1) by that much).
void conformal_v(TriMesh& out, const std::vector<Placement>& placed,
                 const std::vector<std::uint32_t>& tri_chart, const BarkChart& chart,
                 const Context* ctx) {
  const std::vector<Seg>& segs = chart.segs();
  const std::size_t n = out.positions.size();
  const std::uint64_t chains = chart.chain_count();
  std::vector<std::uint32_t> unk(n);
  std::unordered_map<std::uint64_t, std::uint32_t> index;
  std::vector<std::uint32_t> unk_chart;
  std::vector<double> ref, arc;
  for (std::size_t j = 0; j < n; ++j) {
    const Seg& g = segs[placed[j].seg];
    const std::uint64_t key = std::uint64_t{out.welded[j]} * chains + g.chain;
    const auto [it, is_new] = index.emplace(key, static_cast<std::uint32_t>(ref.size()));
    if (is_new) {
      unk_chart.push_back(g.chain);
      ref.push_back(out.uvs[j].y());
      arc.push_back(g.s0 + placed[j].t);
    }
    unk[j] = it->second;
  }
  const std::size_t nu = ref.size();
  std::vector<std::vector<std::uint32_t>> chart_tris(chains), chart_unknowns(chains);
  for (std::size_t i = 0; i < nu; ++i)
    chart_unknowns[unk_chart[i]].push_back(static_cast<std::uint32_t>(i));
  for (std::size_t t = 0; t < out.triangles.size(); ++t) {
    chart_tris[tri_chart[t]].push_back(static_cast<std::uint32_t>(t));
  }
  std::vector<double> v = ref;
  std::vector<double> delta_u(nu, 0.0), base_u(nu, 0.0);
  for (std::size_t j = 0; j < n; ++j) base_u[unk[j]] = out.uvs[j].x() - std::floor(out.uvs[j].x());
  // The charts' systems are independent: they are solved in parallel (each the same on any
  // thread), then placed one after another in chart order, since a chart's constant follows
  // its parent's drift at the fork.
  struct ChartSolve {
    bool ok = false;
    std::vector<std::uint32_t> members;  // the chart's unknowns, in the order of its triangles
    std::vector<std::uint32_t> piece;    // per member: its connected piece's root member
    Eigen::VectorXd x, du;
  };
  std::vector<ChartSolve> solves(chains);
  parallel::for_each(
      chains, 1,
      [&](std::size_t c) {
        check_cancel(ctx);
        const std::vector<std::uint32_t>& ts = chart_tris[c];
        if (ts.empty()) return;
        ChartSolve& out_c = solves[c];
        std::vector<std::uint32_t>& members = out_c.members;
        std::unordered_map<std::uint32_t, std::uint32_t> local;
        local.reserve(2 * ts.size());
        for (const std::uint32_t t : ts) {
          for (const std::uint32_t j : out.triangles[t]) {
            if (local.emplace(unk[j], static_cast<std::uint32_t>(members.size())).second) {
              members.push_back(unk[j]);
            }
          }
        }
        const std::size_t m = members.size();
        std::vector<ChartTri> tris;
        tris.reserve(ts.size());
        double orientation = 0.0;
        for (const std::uint32_t t : ts) {
          const auto& tri = out.triangles[t];
          ChartTri x;
          for (int k = 0; k < 3; ++k) x.at[k] = local.at(unk[tri[k]]);
          const Vec3& p0 = out.positions[tri[0]];
          const Vec3& p1 = out.positions[tri[1]];
          const Vec3& p2 = out.positions[tri[2]];
          const Vec3 nrm = (p1 - p0).cross(p2 - p0);
          const double twice = nrm.norm();
          if (!(twice > 0.0) || !std::isfinite(twice)) {
            tris.push_back(x);
            continue;
          }
          const Vec3 nh = nrm / twice;
          x.grad[0] = nh.cross(p2 - p1) / twice;
          x.grad[1] = nh.cross(p0 - p2) / twice;
          x.grad[2] = nh.cross(p1 - p0) / twice;
          x.area = 0.5 * twice;
          Vec3 grad_u = Vec3::Zero();
          for (int k = 0; k < 3; ++k) grad_u += out.uvs[tri[k]].x() * x.grad[k];
          x.g = nh.cross(grad_u);
          x.grad_u = grad_u;
          x.normal = nh;
          orientation += x.area * x.g.dot(segs[placed[tri[0]].seg].d);
          tris.push_back(x);
        }
        const double sign = orientation < 0.0 ? -1.0 : 1.0;
        ChartPattern pattern(tris, m);
        Sparse& K = pattern.single();
        double* values = K.valuePtr();
        std::fill(values, values + K.nonZeros(), 0.0);
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m));
        std::vector<double> mass(m, 0.0), diag(m, 0.0);
        for (const ChartTri& x : tris) {
          if (x.area == 0.0) continue;
          for (int a = 0; a < 3; ++a) {
            const std::size_t pa = pattern.pos(x.at[a]);
            mass[x.at[a]] += x.area / 3.0;
            rhs[static_cast<Eigen::Index>(pa)] += x.area * sign * x.grad[a].dot(x.g);
            for (int b = 0; b < 3; ++b) {
              const double k = x.area * x.grad[a].dot(x.grad[b]);
              const std::size_t pb = pattern.pos(x.at[b]);
              if (pa <= pb) values[ChartPattern::slot(K, pa, pb)] += k;
              if (a == b) diag[x.at[a]] += k;
            }
          }
        }
        // A faint pull towards the reference v makes the system definite (its null space is the
        // constant per connected piece) without moving the solution measurably.
        double diag_sum = 0.0, mass_sum = 0.0;
        for (std::size_t i = 0; i < m; ++i) {
          diag_sum += diag[i];
          mass_sum += mass[i];
        }
        if (!(mass_sum > 0.0) || !(diag_sum > 0.0)) return;
        const double eps = 1e-11 * diag_sum / mass_sum;
        const double mass_floor = 1e-3 * mass_sum / static_cast<double>(m);
        for (std::size_t i = 0; i < m; ++i) {
          const double w = eps * (mass[i] + mass_floor);
          const std::size_t p = pattern.pos(i);
          values[ChartPattern::slot(K, p, p)] += w;
          rhs[static_cast<Eigen::Index>(p)] += w * ref[members[i]];
        }
        OrderedLdlt solver(K);
        if (solver.info() != Eigen::Success) return;
        const Eigen::VectorXd solved = solver.solve(rhs);
        if (solver.info() != Eigen::Success || !solved.allFinite()) return;
        out_c.x.resize(static_cast<Eigen::Index>(m));
        for (std::size_t i = 0; i < m; ++i) {
          out_c.x[static_cast<Eigen::Index>(i)] = solved[static_cast<Eigen::Index>(pattern.pos(i))];
        }
        refine_stretch(tris, sign, eps, mass, mass_floor, members, ref, pattern, out_c.x, out_c.du);
        // Connected pieces of the chart, each with its own constant.
        detail::UnionFind pieces(m);
        for (const ChartTri& t : tris) {
          for (int k = 1; k < 3; ++k) pieces.unite(t.at[0], t.at[k]);
        }
        out_c.piece.resize(m);
        for (std::size_t i = 0; i < m; ++i) {
          out_c.piece[i] = pieces.find(static_cast<std::uint32_t>(i));
        }
        out_c.ok = true;
      },
      ctx);
  std::vector<char> solved(nu, 0);
  for (std::uint32_t c = 0; c < chains; ++c) {
    ChartSolve& sc = solves[c];
    if (!sc.ok) continue;
    const std::vector<std::uint32_t>& members = sc.members;
    const std::size_t m = members.size();
    for (std::size_t i = 0; i < m; ++i) delta_u[members[i]] = sc.du[static_cast<Eigen::Index>(i)];
    // The drift (v - reference) the parent has at the fork, over about a radius of it.
    double offset = 0.0;
    const std::uint32_t parent = chart.parent_of(c);
    if (parent != kNone) {
      const double fs = chart.fork_s_of(c), reach = chart.rho_at(parent, fs);
      double sum = 0.0;
      std::size_t count = 0;
      for (const std::uint32_t i : chart_unknowns[parent]) {
        if (solved[i] != 0 && std::abs(arc[i] - fs) <= reach) {
          sum += v[i] - ref[i];
          ++count;
        }
      }
      if (count > 0) offset = sum / static_cast<double>(count);
    }
    // Each piece's drift over the chart's first two radii (else over all of it) is `offset`.
    const double window = 2.0 * chart.start_rho(c);
    std::vector<double> near_sum(m, 0.0), all_sum(m, 0.0);
    std::vector<std::size_t> near_count(m, 0), all_count(m, 0);
    for (std::size_t i = 0; i < m; ++i) {
      const std::uint32_t r = sc.piece[i];
      const double d = sc.x[static_cast<Eigen::Index>(i)] - ref[members[i]];
      all_sum[r] += d;
      ++all_count[r];
      const double s = arc[members[i]];
      if (s >= 0.0 && s <= window) {
        near_sum[r] += d;
        ++near_count[r];
      }
    }
    for (std::size_t i = 0; i < m; ++i) {
      const std::uint32_t r = sc.piece[i];
      const double mean = near_count[r] > 0 ? near_sum[r] / static_cast<double>(near_count[r])
                                            : all_sum[r] / static_cast<double>(all_count[r]);
      v[members[i]] = sc.x[static_cast<Eigen::Index>(i)] - mean + offset;
      solved[members[i]] = 1;
    }
    sc = ChartSolve{};  // its memory is no longer needed
  }
  // Not wrapped back into [0, 1): a corrected u just past the seam stays consistent with the
  // triangles around it (wrapping it would need the splits redone).
  for (std::size_t i = 0; i < nu; ++i) {
    base_u[i] += std::clamp(delta_u[i], -kMaxDeltaU, kMaxDeltaU);
  }
  for (std::size_t j = 0; j < n; ++j) {
    out.uvs[j] = Vec2(base_u[unk[j]] + std::floor(out.uvs[j].x()), v[unk[j]]);
  }
}

void validate_inputs(const TriMesh& mesh, const Skeleton& skeleton, const BarkUvOptions& o) {
  if (!o.facing.allFinite()) throw InvalidArgument("BarkUvOptions::facing must be finite");
  if (!(o.radius_bin > 0.0 && o.radius_bin <= 1000.0)) {
    throw InvalidArgument("BarkUvOptions::radius_bin must be in (0, 1000], got " +
                          std::to_string(o.radius_bin));
  }
  if (skeleton.nodes.empty()) throw InvalidArgument("add_bark_uvs: the skeleton has no nodes");
  for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
    const auto& nd = skeleton.nodes[i];
    if (!nd.position.allFinite() || !std::isfinite(nd.radius) || !(nd.radius > 0.0)) {
      throw InvalidArgument("add_bark_uvs: skeleton node " + std::to_string(i) +
                            " has a non-finite position or a radius that is not > 0");
    }
  }
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto& ed = skeleton.edges[e];
    if (ed[0] >= skeleton.nodes.size() || ed[1] >= skeleton.nodes.size()) {
      throw InvalidArgument("add_bark_uvs: skeleton edge " + std::to_string(e) +
                            " has a node index out of range");
    }
    if (skeleton.nodes[ed[0]].position == skeleton.nodes[ed[1]].position) {
      throw InvalidArgument("add_bark_uvs: skeleton edge " + std::to_string(e) +
                            " has zero length");
    }
  }
  const std::size_t nv = mesh.positions.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t i : mesh.triangles[t]) {
      if (i >= nv) {
        throw InvalidArgument("add_bark_uvs: triangle " + std::to_string(t) + " has vertex index " +
                              std::to_string(i) + " out of range (" + std::to_string(nv) +
                              " vertices)");
      }
    }
  }
  if (!mesh.normals.empty() && mesh.normals.size() != nv) {
    throw InvalidArgument("add_bark_uvs: " + std::to_string(mesh.normals.size()) + " normals for " +
                          std::to_string(nv) + " vertices");
  }
  for (std::size_t i = 0; i < nv; ++i) {
    if (!mesh.positions[i].allFinite()) {
      throw InvalidArgument("add_bark_uvs: vertex " + std::to_string(i) + " is not finite");
    }
  }
}

/// dP/du and dP/dv of a triangle (zero when its (u, v) are degenerate).
std::pair<Vec3, Vec3> jacobian(const TriMesh& m, const std::array<std::uint32_t, 3>& t) {
  const Vec3 e1 = m.positions[t[1]] - m.positions[t[0]];
  const Vec3 e2 = m.positions[t[2]] - m.positions[t[0]];
  const Vec2 d1 = m.uvs[t[1]] - m.uvs[t[0]];
  const Vec2 d2 = m.uvs[t[2]] - m.uvs[t[0]];
  const double det = d1.x() * d2.y() - d2.x() * d1.y();
  if (det == 0.0 || !std::isfinite(det)) return {Vec3::Zero(), Vec3::Zero()};
  return {(e1 * d2.y() - e2 * d1.y()) / det, (e2 * d1.x() - e1 * d2.x()) / det};
}

}  // namespace

std::vector<double> uv_stretch(const TriMesh& textured) {
  const std::size_t nv = textured.positions.size();
  if (textured.uvs.size() != nv) {
    throw InvalidArgument("uv_stretch: " + std::to_string(textured.uvs.size()) + " uvs for " +
                          std::to_string(nv) + " vertices");
  }
  std::vector<double> out(textured.triangles.size(), kNaN);
  for (std::size_t t = 0; t < textured.triangles.size(); ++t) {
    for (const std::uint32_t i : textured.triangles[t]) {
      if (i >= nv) {
        throw InvalidArgument("uv_stretch: triangle " + std::to_string(t) + " has vertex index " +
                              std::to_string(i) + " out of range");
      }
    }
    const auto [pu, pv] = jacobian(textured, textured.triangles[t]);
    const double lv = pv.norm();
    if (lv > 0.0 && std::isfinite(lv)) out[t] = pu.norm() / lv;
  }
  return out;
}

TriMesh add_bark_uvs(const TriMesh& mesh, const Skeleton& skeleton, const BarkUvOptions& options,
                     BarkUvStats* stats, const Context* ctx) {
  validate_inputs(mesh, skeleton, options);
  BarkChart chart(skeleton, options);
  const std::vector<Seg>& segs = chart.segs();
  const std::size_t nv = mesh.positions.size();

  // 1. Every vertex to its edge (the per-vertex work; parallel, each result independent).
  std::vector<Placement> placed(nv);
  parallel::for_each(
      nv, 2048,
      [&](std::size_t i) {
        const Vec3& p = mesh.positions[i];
        placed[i] = place(segs, chart.nearest_seg(p), p);
      },
      ctx);
  chart.fit_radii(placed);
  std::vector<Vec2> uv(nv);
  parallel::for_each(
      nv, 2048, [&](std::size_t i) { uv[i] = chart.uv(placed[i]); }, ctx);
  check_cancel(ctx);

  // 2. Normals (the mesh's, else area-weighted triangle normals) for the tangents.
  std::vector<Vec3> normals = mesh.normals;
  if (normals.empty()) {
    normals.assign(nv, Vec3::Zero());
    for (const auto& t : mesh.triangles) {
      const Vec3 fn = (mesh.positions[t[1]] - mesh.positions[t[0]])
                          .cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
      for (const std::uint32_t i : t) normals[i] += fn;
    }
    for (std::size_t i = 0; i < nv; ++i) {
      const double len = normals[i].norm();
      normals[i] = len > 0.0 ? Vec3(normals[i] / len) : Vec3::Zero();
    }
  }

  // 3. Seams: per triangle its chart, then copies of the corners that need other (u, v).
  TriMesh out;
  out.positions = mesh.positions;
  out.normals = mesh.normals;
  out.triangles = mesh.triangles;
  out.uvs = uv;
  out.welded.resize(nv);
  for (std::size_t i = 0; i < nv; ++i) out.welded[i] = static_cast<std::uint32_t>(i);
  std::vector<Placement> out_placed = placed;
  std::vector<Vec3> out_normals = normals;
  const std::uint64_t chains = chart.chain_count();
  std::unordered_map<std::uint64_t, std::uint32_t> copies;
  std::unordered_map<std::uint64_t, std::pair<Placement, Vec2>> foreign;
  std::vector<std::uint32_t> tri_chart(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if ((t & 0xffff) == 0) check_cancel(ctx);
    const auto& tri = mesh.triangles[t];
    std::array<std::uint32_t, 3> own{};
    for (int k = 0; k < 3; ++k) own[k] = segs[placed[tri[k]].seg].chain;
    // The chart of most corners; ties: the earliest chain.
    std::uint32_t c = std::min({own[0], own[1], own[2]});
    for (int k = 0; k < 3; ++k) {
      if (own[k] == own[(k + 1) % 3]) c = own[k];
    }
    tri_chart[t] = c;
    std::array<Placement, 3> pl{};
    std::array<Vec2, 3> tuv{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = tri[k];
      if (own[k] == c) {
        pl[k] = placed[i];
        tuv[k] = uv[i];
      } else {
        const std::uint64_t key = std::uint64_t{i} * chains + c;
        auto it = foreign.find(key);
        if (it == foreign.end()) {
          const Vec3& p = mesh.positions[i];
          const Placement q = place(segs, chart.nearest_seg_of_chain(c, p), p);
          it = foreign.emplace(key, std::make_pair(q, chart.uv(q))).first;
        }
        pl[k] = it->second.first;
        tuv[k] = it->second.second;
      }
    }
    // Around the wrap: cut the circle of u at the widest gap between the corners, and move
    // the corners before the cut to u + 1 (none when the widest gap is the one across u = 0).
    std::array<int, 3> order{0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int x, int y) { return tuv[x].x() < tuv[y].x(); });
    const double g01 = tuv[order[1]].x() - tuv[order[0]].x();
    const double g12 = tuv[order[2]].x() - tuv[order[1]].x();
    const double g20 = tuv[order[0]].x() + 1.0 - tuv[order[2]].x();
    std::array<bool, 3> shifted{false, false, false};
    if (g01 > g20 && g01 >= g12) {
      shifted[order[0]] = true;
    } else if (g12 > g20 && g12 > g01) {
      shifted[order[0]] = shifted[order[1]] = true;
    }
    for (int k = 0; k < 3; ++k) {
      const bool shift = shifted[k];
      if (own[k] == c && !shift) continue;
      const std::uint32_t i = tri[k];
      const std::uint64_t key = (std::uint64_t{i} * chains + c) * 2 + (shift ? 1 : 0);
      auto it = copies.find(key);
      if (it == copies.end()) {
        const auto j = static_cast<std::uint32_t>(out.positions.size());
        out.positions.push_back(mesh.positions[i]);
        if (!mesh.normals.empty()) out.normals.push_back(mesh.normals[i]);
        out_normals.push_back(normals[i]);
        out.uvs.push_back(shift ? Vec2(tuv[k].x() + 1.0, tuv[k].y()) : tuv[k]);
        out.welded.push_back(i);
        out_placed.push_back(pl[k]);
        it = copies.emplace(key, j).first;
      }
      out.triangles[t][k] = it->second;
    }
  }
  check_cancel(ctx);
  if (options.measure_radius) conformal_v(out, out_placed, tri_chart, chart, ctx);

  // 4. Tangents: d x offset projected orthogonal to the normal; w from the triangles' dP/dv.
  const std::size_t n_out = out.positions.size();
  std::vector<Vec3> sum_pu(n_out, Vec3::Zero()), sum_pv(n_out, Vec3::Zero());
  for (const auto& t : out.triangles) {
    const auto [pu, pv] = jacobian(out, t);
    const double area = 0.5 * (out.positions[t[1]] - out.positions[t[0]])
                                  .cross(out.positions[t[2]] - out.positions[t[0]])
                                  .norm();
    const double lu = pu.norm(), lv = pv.norm();
    for (const std::uint32_t i : t) {
      if (lu > 0.0 && std::isfinite(lu)) sum_pu[i] += area / lu * pu;
      if (lv > 0.0 && std::isfinite(lv)) sum_pv[i] += area / lv * pv;
    }
  }
  out.tangents.resize(n_out);
  parallel::for_each(
      n_out, 2048,
      [&](std::size_t i) {
        const Seg& g = segs[out_placed[i].seg];
        Vec3 nrm = out_normals[i];
        if (nrm.isZero())
          nrm = out_placed[i].o.norm() > 0.0 ? Vec3(out_placed[i].o.normalized())
                                             : perpendicular(g.d);
        auto project = [&](const Vec3& x) { return Vec3(x - x.dot(nrm) * nrm); };
        Vec3 tan = project(g.d.cross(out_placed[i].o));
        if (!(tan.norm() > 1e-9 * out_placed[i].o.norm()) || tan.isZero()) tan = project(sum_pu[i]);
        if (tan.isZero()) tan = perpendicular(nrm);
        tan.normalize();
        const Vec3 along_v = sum_pv[i].isZero() ? g.d : sum_pv[i];
        const double w = nrm.cross(tan).dot(along_v) < 0.0 ? -1.0 : 1.0;
        out.tangents[i] = Vec4(tan.x(), tan.y(), tan.z(), w);
      },
      ctx);

  if (stats != nullptr) {
    BarkUvStats st;
    st.branches = chart.chain_count();
    st.split_vertices = n_out - nv;
    // Seam edges: an edge of the input whose two sides use different copies of its ends.
    struct Side {
      std::uint64_t edge;
      std::uint64_t ends;
      std::uint32_t chart;
    };
    std::vector<Side> sides;
    sides.reserve(3 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      for (int k = 0; k < 3; ++k) {
        std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
        std::uint32_t na = out.triangles[t][k], nb = out.triangles[t][(k + 1) % 3];
        if (a > b) {
          std::swap(a, b);
          std::swap(na, nb);
        }
        sides.push_back(
            {(std::uint64_t{a} << 32) | b, (std::uint64_t{na} << 32) | nb, tri_chart[t]});
      }
    }
    std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
      return x.edge != y.edge ? x.edge < y.edge : x.ends < y.ends;
    });
    for (std::size_t i = 0; i < sides.size();) {
      std::size_t j = i + 1;
      bool differ = false, fork = false;
      while (j < sides.size() && sides[j].edge == sides[i].edge) {
        differ = differ || sides[j].ends != sides[i].ends;
        fork = fork || sides[j].chart != sides[i].chart;
        ++j;
      }
      if (differ) {
        ++st.seam_edges;
        ++(fork ? st.fork_seam_edges : st.wrap_seam_edges);
      }
      i = j;
    }
    const std::vector<double> stretch = uv_stretch(out);
    std::vector<double> finite;
    double area_in = 0.0, area_all = 0.0;
    std::size_t in = 0;
    for (std::size_t t = 0; t < stretch.size(); ++t) {
      const auto& tri = out.triangles[t];
      const double area = 0.5 * (out.positions[tri[1]] - out.positions[tri[0]])
                                    .cross(out.positions[tri[2]] - out.positions[tri[0]])
                                    .norm();
      area_all += area;
      if (std::isnan(stretch[t])) continue;
      finite.push_back(stretch[t]);
      if (stretch[t] >= 0.9 && stretch[t] <= 1.1) {
        ++in;
        area_in += area;
      }
    }
    if (!finite.empty()) {
      const std::size_t mid = (finite.size() + 1) / 2 - 1;
      std::nth_element(finite.begin(), finite.begin() + static_cast<std::ptrdiff_t>(mid),
                       finite.end());
      st.stretch_p50 = finite[mid];
    }
    if (!stretch.empty()) {
      st.within_10_percent = static_cast<double>(in) / static_cast<double>(stretch.size());
    }
    if (area_all > 0.0) st.within_10_percent_area = area_in / area_all;
    *stats = st;
  }
  return out;
}

}  // namespace ramiform
