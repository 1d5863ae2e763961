// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/grow/space_colonization.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"

namespace ramiform {
namespace {

constexpr std::uint32_t kNone = UINT32_MAX;

// |sum of unit vectors| <= kCancelFraction * count counts as "the pulls cancel": the direction
// would be rounding noise (the sums are exact fixed-point integers quantized at 2^-40 or finer).
constexpr double kCancelFraction = 1e-9;
// A proposal closer than this fraction of D to an existing node is a duplicate. Re-proposals of
// an unchanged set are bit-identical (exact integer sums), so any small fraction catches them;
// this one also catches a child growing straight back onto its parent (rounding ~1e-16 D).
constexpr double kDuplicateFraction = 1e-6;
// Upper bound on the number of cells of the point grid, as a multiple of the point count.
constexpr double kCellsPerPoint = 2.0;
// Upper bound on the rounds that enlarge the grid's cells (a handful in practice).
constexpr int kMaxGridRounds = 200;

void check(bool ok, const std::string& what) {
  if (!ok) throw InvalidArgument("space colonization: " + what);
}

// Radii from tips to roots given a parent array where every node's parent has a smaller position
// in `order` (order lists parents before children).
void pipe_radii(std::vector<SkeletonNode>& nodes, const std::vector<std::uint32_t>& parent,
                const std::vector<std::uint32_t>& order, double tip_radius, double exponent) {
  std::vector<double> sum(nodes.size(), 0.0);
  for (std::size_t k = order.size(); k-- > 0;) {
    const std::uint32_t i = order[k];
    const double r = sum[i] > 0 ? pm::pow(sum[i], 1.0 / exponent) : tip_radius;
    nodes[i].radius = r;
    if (parent[i] != kNone) sum[parent[i]] += pm::pow(r, exponent);
  }
}

// Exact fixed-point accumulator of unit vectors: integer sums do not depend on the order of
// additions and removals, so a node whose set S(v) returns to an earlier state proposes exactly
// the same position again (and the duplicate rule recognises it).
struct Accumulator {
  std::array<std::int64_t, 3> sum{0, 0, 0};
  std::uint32_t count = 0;
};

struct Change {
  std::uint32_t point;
  std::uint32_t old_node;  // kNone: was not associated
  std::uint32_t new_node;  // kNone: killed
  std::array<std::int64_t, 3> q_old;
  std::array<std::int64_t, 3> q_new;
};

struct Proposal {
  std::uint32_t parent;
  Vec3 direction;
  Vec3 position;
  bool trunk;
  bool rejected;
};

enum class TrunkState { kGrowing, kDone, kStopped };

struct Tree {
  bool has_points = false;
  TrunkState trunk = TrunkState::kGrowing;
  std::uint32_t tip = 0;
  double box_d2 = 0;  // squared distance of the trunk tip to the points' bounding box
  std::string stop_reason;
};

std::uint64_t hash_cell(std::int64_t x, std::int64_t y, std::int64_t z) {
  auto mix = [](std::uint64_t v) {
    v ^= v >> 33;
    v *= 0xff51afd7ed558ccdULL;
    v ^= v >> 33;
    return v;
  };
  return mix(static_cast<std::uint64_t>(x)) ^ (mix(static_cast<std::uint64_t>(y)) * 31) ^
         (mix(static_cast<std::uint64_t>(z)) * 1031);
}

}  // namespace

BranchCleanupOptions ColonizationOptions::cleanup() const {
  BranchCleanupOptions c;
  c.smooth_iterations = smooth_iterations;
  c.max_turn_deg = max_turn_deg;
  c.prune_length = prune_steps * step;
  c.tip_radius = tip_radius;
  c.pipe_exponent = pipe_exponent;
  c.short_length = kShortTipSteps * step;
  return c;
}

void ColonizationOptions::validate() const {
  check(std::isfinite(step) && step > 0,
        "step must be finite and > 0 (got " + format_number(step) + ")");
  check(std::isfinite(kill) && kill > 0,
        "kill must be finite and > 0 (got " + format_number(kill) + ")");
  check(std::isfinite(influence) && influence > kill,
        "influence must be finite and > kill (got " + format_number(influence) + ")");
  check(!roots.empty(), "roots must not be empty");
  for (std::size_t i = 0; i < roots.size(); ++i) {
    check(is_finite(roots[i]), "root " + std::to_string(i) + " is not finite");
    for (std::size_t j = 0; j < i; ++j)
      check((roots[i] - roots[j]).norm() > kDuplicateFraction * step,
            "roots " + std::to_string(j) + " and " + std::to_string(i) + " coincide");
  }
  check(is_finite(direction) && direction.norm() > 0, "direction must be finite and non-zero");
  check(is_finite(tropism), "tropism must be finite");
  check(max_iterations >= 0, "max_iterations must be >= 0");
  check(std::isfinite(tip_radius) && tip_radius > 0,
        "tip_radius must be finite and > 0 (got " + format_number(tip_radius) + ")");
  check(pipe_exponent >= kMinPipeExponent && pipe_exponent <= kMaxPipeExponent,
        "pipe_exponent must be in " + range_text(kMinPipeExponent, kMaxPipeExponent) + " (got " +
            format_number(pipe_exponent) + ")");
  check(smooth_iterations >= 0 && smooth_iterations <= BranchCleanupOptions::kMaxSmoothIterations,
        "smooth_iterations must be in " +
            range_text(0, BranchCleanupOptions::kMaxSmoothIterations) + " (got " +
            std::to_string(smooth_iterations) + ")");
  check(max_turn_deg > 0 && max_turn_deg <= 180,
        "max_turn_deg must be in (0, 180] (got " + format_number(max_turn_deg) + ")");
  check(std::isfinite(prune_steps) && prune_steps >= 0,
        "prune_steps must be finite and >= 0 (got " + format_number(prune_steps) + ")");
  check(std::isfinite(prune_steps * step), "prune_steps * step must be finite (got " +
                                               format_number(prune_steps) + " steps of " +
                                               format_number(step) + ")");
}

struct SpaceColonization::Impl {
  ColonizationOptions opt;
  Context* ctx = nullptr;
  double kill2 = 0, infl2 = 0, dup = 0;
  Vec3 dir0;

  // Attraction points and their state (each point is owned by exactly one grid cell).
  std::vector<Vec3> points;
  std::vector<std::uint8_t> alive;
  std::vector<std::uint32_t> node_of;
  std::vector<double> best_d2;
  std::vector<std::uint32_t> original;  // caller's index of each (cell-ordered) point
  std::size_t alive_count = 0;
  std::size_t reached = 0;
  Aabb box;

  // Uniform grid of the live points, cells >= d_i (CSR, each cell's live prefix is compacted).
  Vec3 origin = Vec3::Zero();
  double cell = 1;
  std::array<std::int64_t, 3> dims{1, 1, 1};
  std::vector<std::uint32_t> cell_begin, cell_end, ids;

  // Fixed-point scale of the accumulators.
  double scale = 1;

  // Nodes.
  std::vector<Vec3> pos;
  std::vector<std::uint32_t> parent;
  std::vector<std::uint32_t> tree_of;
  std::vector<Accumulator> acc;
  std::vector<std::uint8_t> blocked;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> node_cells;
  std::vector<std::uint32_t> active;
  std::vector<Tree> trees;

  std::size_t iterations = 0;
  ColonizationStatus status = ColonizationStatus::kGrowing;
  std::string reason;

  // ---- point grid --------------------------------------------------------------------------

  std::int64_t linear(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return (z * dims[1] + y) * dims[0] + x;
  }

  // Cell coordinates of `p`, clamped to [-2, dims + 1]: callers only ask whether a position is
  // in the grid or at most one cell outside it, and a far node (or a tiny cell) must not convert
  // an out-of-range double to an integer.
  std::array<std::int64_t, 3> raw_cell(const Vec3& p) const {
    const Vec3 c = (p - origin) / cell;
    std::array<std::int64_t, 3> out;
    for (int a = 0; a < 3; ++a)
      out[a] = static_cast<std::int64_t>(
          std::clamp(std::floor(c[a]), -2.0, static_cast<double>(dims[a] + 1)));
    return out;
  }

  // The point grid is sized from the points' extent and the accumulators quantize directions
  // between points and nodes, so every point must be finite and the extent must have a finite
  // length (the rule of skeleton validate()). The roots are held to the same rule together with
  // the points: the trunk's stop test measures their distance to the points' box.
  static void check_extent(std::span<const Vec3> pts, const std::vector<Vec3>& roots) {
    Aabb all;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (!is_finite(pts[i]))
        throw InvalidArgument("space colonization: attraction point " + std::to_string(i) +
                              " is not finite");
      all.extend(pts[i]);
      if (!std::isfinite(all.diagonal().norm()))
        throw InvalidArgument(
            "space colonization: the attraction points' coordinates span more than double "
            "precision can hold (with point " +
            std::to_string(i) + " they range from " + format_number(all.min().minCoeff()) + " to " +
            format_number(all.max().maxCoeff()) + ")");
    }
    if (pts.empty()) return;
    for (std::size_t r = 0; r < roots.size(); ++r) {
      Aabb with_root = all;
      with_root.extend(roots[r]);
      if (!std::isfinite(with_root.diagonal().norm()))
        throw InvalidArgument(
            "space colonization: root " + std::to_string(r) +
            " is too far from the attraction points: together they span more than double "
            "precision can hold (from " +
            format_number(with_root.min().minCoeff()) + " to " +
            format_number(with_root.max().maxCoeff()) + ")");
    }
  }

  void build_grid() {
    for (const Vec3& p : points) box.extend(p);
    const std::size_t n = points.size();
    if (n == 0) {
      cell_begin.assign(2, 0);
      cell_end.assign(1, 0);
      return;
    }
    origin = box.min();
    const Vec3 ext = box.max() - box.min();  // finite: check_extent ran
    cell = opt.influence;
    const double max_cells = std::max(1.0, kCellsPerPoint * static_cast<double>(n));
    // At this size the grid is one cell (and it is >= d_i): where the enlarging stops at the
    // latest. Every round multiplies the cell by >= 1.01 and a product of the ratio that
    // overflows jumps straight to it, so the loop ends; the round cap bounds it regardless.
    const double widest = std::max(cell, 2.0 * ext.maxCoeff());
    for (int round = 0;; ++round) {
      check_cancel(ctx);
      double total = 1;
      for (int a = 0; a < 3; ++a) total *= std::floor(ext[a] / cell) + 1;
      if (total <= max_cells || cell >= widest) break;
      if (!std::isfinite(total) || round >= kMaxGridRounds) {
        cell = widest;
        continue;
      }
      cell = std::min(widest, cell * std::max(1.01, pm::cbrt(total / max_cells)));
    }
    for (int a = 0; a < 3; ++a) dims[a] = static_cast<std::int64_t>(std::floor(ext[a] / cell)) + 1;
    const auto cells = static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);
    std::vector<std::uint32_t> cell_of(n);
    cell_begin.assign(cells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      auto c = raw_cell(points[i]);
      for (int a = 0; a < 3; ++a) c[a] = std::clamp<std::int64_t>(c[a], 0, dims[a] - 1);
      cell_of[i] = static_cast<std::uint32_t>(linear(c[0], c[1], c[2]));
      ++cell_begin[cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < cells; ++c) cell_begin[c + 1] += cell_begin[c];
    cell_end.assign(cell_begin.begin(), cell_begin.end() - 1);
    ids.resize(n);
    for (std::size_t i = 0; i < n; ++i) ids[cell_end[cell_of[i]]++] = static_cast<std::uint32_t>(i);
    // Store the points in cell order (memory locality); `original` maps back to the caller's
    // indices, which the tie rules and alive() use.
    original = ids;
    std::vector<Vec3> sorted(n);
    for (std::size_t k = 0; k < n; ++k) {
      sorted[k] = points[ids[k]];
      ids[k] = static_cast<std::uint32_t>(k);
    }
    points = std::move(sorted);
  }

  std::array<std::int64_t, 3> quantize(const Vec3& from, const Vec3& to) const {
    const Vec3 u = (to - from).normalized();
    return {std::llround(u.x() * scale), std::llround(u.y() * scale), std::llround(u.z() * scale)};
  }

  // ---- association and kill around the nodes [first, pos.size()) -----------------------------

  // Returns the nodes whose accumulators changed (may repeat) and adds to `killed`.
  std::vector<std::uint32_t> associate(std::uint32_t first, std::size_t& killed) {
    std::vector<std::uint32_t> dirty;
    if (alive_count == 0) return dirty;
    // New nodes by (clamped) cell; a node more than one cell outside the grid reaches no point.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> by_cell;
    std::vector<std::uint32_t> touched;
    for (std::uint32_t v = first; v < pos.size(); ++v) {
      auto c = raw_cell(pos[v]);
      bool reach = true;
      for (int a = 0; a < 3; ++a) {
        if (c[a] < -1 || c[a] > dims[a]) reach = false;
        c[a] = std::clamp<std::int64_t>(c[a], 0, dims[a] - 1);
      }
      if (!reach) continue;
      by_cell.emplace_back(static_cast<std::uint32_t>(linear(c[0], c[1], c[2])), v);
      for (std::int64_t z = std::max<std::int64_t>(c[2] - 1, 0); z <= std::min(c[2] + 1, dims[2] - 1); ++z)
        for (std::int64_t y = std::max<std::int64_t>(c[1] - 1, 0); y <= std::min(c[1] + 1, dims[1] - 1); ++y)
          for (std::int64_t x = std::max<std::int64_t>(c[0] - 1, 0); x <= std::min(c[0] + 1, dims[0] - 1); ++x) {
            const auto l = static_cast<std::uint32_t>(linear(x, y, z));
            if (cell_end[l] > cell_begin[l]) touched.push_back(l);
          }
    }
    std::sort(by_cell.begin(), by_cell.end());
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());

    constexpr std::size_t kGrain = 16;
    const std::size_t chunks = (touched.size() + kGrain - 1) / kGrain;
    std::vector<std::vector<Change>> changes(chunks);
    parallel::for_chunks(
        touched.size(), kGrain,
        [&](std::size_t b, std::size_t e) {
          std::vector<Change>& out = changes[b / kGrain];
          std::vector<std::uint32_t> near;
          for (std::size_t t = b; t < e; ++t) {
            const std::uint32_t l = touched[t];
            const std::int64_t x0 = l % dims[0], y0 = (l / dims[0]) % dims[1], z0 = l / (dims[0] * dims[1]);
            near.clear();
            for (std::int64_t z = std::max<std::int64_t>(z0 - 1, 0); z <= std::min(z0 + 1, dims[2] - 1); ++z)
              for (std::int64_t y = std::max<std::int64_t>(y0 - 1, 0); y <= std::min(y0 + 1, dims[1] - 1); ++y)
                for (std::int64_t x = std::max<std::int64_t>(x0 - 1, 0); x <= std::min(x0 + 1, dims[0] - 1); ++x) {
                  const auto key = static_cast<std::uint32_t>(linear(x, y, z));
                  auto it = std::lower_bound(by_cell.begin(), by_cell.end(), std::make_pair(key, 0u));
                  for (; it != by_cell.end() && it->first == key; ++it) near.push_back(it->second);
                }
            std::sort(near.begin(), near.end());  // ties go to the smaller node index
            std::uint32_t w = cell_begin[l];
            for (std::uint32_t k = cell_begin[l]; k < cell_end[l]; ++k) {
              const std::uint32_t p = ids[k];
              if (!alive[p]) continue;
              double bd = std::numeric_limits<double>::infinity();
              std::uint32_t bn = kNone;
              for (const std::uint32_t v : near) {
                const double d2 = (points[p] - pos[v]).squaredNorm();
                if (d2 < bd) {
                  bd = d2;
                  bn = v;
                }
              }
              if (bd <= kill2) {
                Change c{p, node_of[p], kNone, {}, {}};
                if (c.old_node != kNone) c.q_old = quantize(pos[c.old_node], points[p]);
                out.push_back(c);
                alive[p] = 0;
                continue;
              }
              ids[w++] = p;
              // New nodes have larger indices than every older node: equal distance keeps the old.
              if (bd <= infl2 && bd < best_d2[p]) {
                Change c{p, node_of[p], bn, {}, quantize(pos[bn], points[p])};
                if (c.old_node != kNone) c.q_old = quantize(pos[c.old_node], points[p]);
                out.push_back(c);
                node_of[p] = bn;
                best_d2[p] = bd;
              }
            }
            cell_end[l] = w;
          }
        },
        ctx);

    for (const auto& chunk : changes)
      for (const Change& c : chunk) {
        if (c.old_node != kNone) {
          Accumulator& a = acc[c.old_node];
          for (int k = 0; k < 3; ++k) a.sum[k] -= c.q_old[k];
          --a.count;
          dirty.push_back(c.old_node);
        }
        if (c.new_node != kNone) {
          Accumulator& a = acc[c.new_node];
          for (int k = 0; k < 3; ++k) a.sum[k] += c.q_new[k];
          ++a.count;
          dirty.push_back(c.new_node);
          trees[tree_of[c.new_node]].has_points = true;
        } else {
          ++killed;
          ++reached;
          --alive_count;
        }
      }
    return dirty;
  }

  // ---- nodes ---------------------------------------------------------------------------------

  // Hash-grid cell of a (finite) node position. Clamped so that a far node never converts an
  // out-of-range double: clamped cells only share a hash bucket, is_duplicate compares distances.
  std::array<std::int64_t, 3> node_cell(const Vec3& p) const {
    constexpr double kLimit = 0x1p62;
    std::array<std::int64_t, 3> out;
    for (int a = 0; a < 3; ++a)
      out[a] = static_cast<std::int64_t>(std::clamp(std::floor(p[a] / opt.step), -kLimit, kLimit));
    return out;
  }

  bool is_duplicate(const Vec3& q) const {
    const auto lo = node_cell(q - Vec3::Constant(dup));
    const auto hi = node_cell(q + Vec3::Constant(dup));
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
          auto it = node_cells.find(hash_cell(x, y, z));
          if (it == node_cells.end()) continue;
          for (const std::uint32_t v : it->second)
            if ((pos[v] - q).norm() <= dup) return true;
        }
    return false;
  }

  std::uint32_t add_node(const Vec3& q, std::uint32_t par, std::uint32_t tree) {
    const auto v = static_cast<std::uint32_t>(pos.size());
    pos.push_back(q);
    parent.push_back(par);
    tree_of.push_back(tree);
    acc.emplace_back();
    blocked.push_back(0);
    const auto c = node_cell(q);
    node_cells[hash_cell(c[0], c[1], c[2])].push_back(v);
    return v;
  }

  // Direction of node v's growth from its accumulator (count > 0).
  Vec3 growth_direction(std::uint32_t v) const {
    const Accumulator& a = acc[v];
    const Vec3 s(static_cast<double>(a.sum[0]) / scale, static_cast<double>(a.sum[1]) / scale,
                 static_cast<double>(a.sum[2]) / scale);
    Vec3 d;
    if (s.norm() > kCancelFraction * a.count) {
      d = s.normalized();
    } else {
      // The pulls cancel: grow toward the closest associated point (ties: smaller index).
      double bd = std::numeric_limits<double>::infinity();
      std::uint32_t bp = kNone;
      auto c = raw_cell(pos[v]);
      for (int k = 0; k < 3; ++k) c[k] = std::clamp<std::int64_t>(c[k], 0, dims[k] - 1);
      for (std::int64_t z = std::max<std::int64_t>(c[2] - 1, 0); z <= std::min(c[2] + 1, dims[2] - 1); ++z)
        for (std::int64_t y = std::max<std::int64_t>(c[1] - 1, 0); y <= std::min(c[1] + 1, dims[1] - 1); ++y)
          for (std::int64_t x = std::max<std::int64_t>(c[0] - 1, 0); x <= std::min(c[0] + 1, dims[0] - 1); ++x) {
            const auto l = static_cast<std::size_t>(linear(x, y, z));
            for (std::uint32_t k = cell_begin[l]; k < cell_end[l]; ++k) {
              const std::uint32_t p = ids[k];
              if (!alive[p] || node_of[p] != v) continue;
              if (best_d2[p] < bd || (best_d2[p] == bd && original[p] < original[bp])) {
                bd = best_d2[p];
                bp = p;
              }
            }
          }
      d = bp != kNone ? (points[bp] - pos[v]).normalized() : dir0;
    }
    const Vec3 t = d + opt.tropism;
    if (t.norm() > kCancelFraction) d = t.normalized();
    return d;
  }

  // Evaluates the obstacle at `where` for the listed proposals; returns inside flags.
  std::vector<std::uint8_t> inside(const std::vector<Vec3>& where) const {
    std::vector<double> values(where.size());
    parallel::for_chunks(
        where.size(), 256,
        [&](std::size_t b, std::size_t e) {
          opt.obstacle->evaluate(std::span<const Vec3>(where).subspan(b, e - b),
                                 std::span<double>(values).subspan(b, e - b));
        },
        ctx);
    std::vector<std::uint8_t> in(where.size());
    for (std::size_t i = 0; i < where.size(); ++i) in[i] = values[i] > opt.obstacle->iso();
    return in;
  }

  void apply_obstacle(std::vector<Proposal>& props) const {
    if (opt.obstacle == nullptr || props.empty()) return;
    std::vector<Vec3> where(props.size());
    for (std::size_t i = 0; i < props.size(); ++i) where[i] = props[i].position;
    const auto in = inside(where);
    std::vector<std::size_t> hit;
    for (std::size_t i = 0; i < props.size(); ++i)
      if (in[i]) hit.push_back(i);
    if (hit.empty()) return;
    // Deflect: remove the inward component of d along grad f at the parent (f grows inward).
    std::vector<Vec3> at(hit.size());
    for (std::size_t k = 0; k < hit.size(); ++k) at[k] = pos[props[hit[k]].parent];
    std::vector<double> values(hit.size());
    std::vector<Vec3> grads(hit.size());
    opt.obstacle->evaluate(at, values, grads, ctx);
    std::vector<Vec3> retry;
    std::vector<std::size_t> retry_of;
    for (std::size_t k = 0; k < hit.size(); ++k) {
      Proposal& p = props[hit[k]];
      p.rejected = true;
      const double gn = grads[k].norm();
      if (!(gn > 0) || !std::isfinite(gn)) continue;
      const Vec3 n = grads[k] / gn;
      const Vec3 d = p.direction - std::max(0.0, p.direction.dot(n)) * n;
      if (d.norm() <= kCancelFraction) continue;
      p.direction = d.normalized();
      p.position = pos[p.parent] + opt.step * p.direction;
      retry.push_back(p.position);
      retry_of.push_back(hit[k]);
    }
    const auto in2 = inside(retry);
    for (std::size_t k = 0; k < retry.size(); ++k)
      if (!in2[k]) props[retry_of[k]].rejected = false;
  }

  void refresh_active(const std::vector<std::uint32_t>& dirty, std::uint32_t first_new) {
    std::vector<std::uint32_t> next = active;
    next.insert(next.end(), dirty.begin(), dirty.end());
    for (std::uint32_t v = first_new; v < pos.size(); ++v) next.push_back(v);
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    active.clear();
    for (const std::uint32_t v : next)
      if (acc[v].count > 0 && blocked[v] == 0) active.push_back(v);
  }

  void finish_check(std::size_t added) {
    if (alive_count == 0) {
      status = ColonizationStatus::kCompleted;
      if (points.empty()) {
        status = ColonizationStatus::kStalled;
        reason = "no attraction points";
      }
      return;
    }
    const bool trunk_growing = std::any_of(trees.begin(), trees.end(), [](const Tree& t) {
      return !t.has_points && t.trunk == TrunkState::kGrowing;
    });
    if (added == 0 && active.empty() && !trunk_growing) {
      status = ColonizationStatus::kStalled;
      std::size_t blocked_nodes = 0;
      for (std::size_t v = 0; v < pos.size(); ++v)
        if (acc[v].count > 0 && blocked[v]) ++blocked_nodes;
      std::ostringstream s;
      s << alive_count << " attraction points remain: ";
      if (blocked_nodes > 0)
        s << blocked_nodes
          << " nodes influenced by them cannot grow (their next positions duplicate existing nodes"
          << (opt.obstacle != nullptr ? " or lie inside the obstacle)" : ")");
      else
        s << "none is within the influence distance d_i = " << opt.influence
          << " of any node (is d_i below the point spacing?)";
      for (std::size_t t = 0; t < trees.size(); ++t)
        if (trees[t].trunk == TrunkState::kStopped)
          s << "; the trunk of root " << t << " stopped: " << trees[t].stop_reason;
      reason = s.str();
      return;
    }
    if (iterations >= static_cast<std::size_t>(opt.max_iterations)) {
      status = ColonizationStatus::kMaxIterations;
      reason = "max_iterations (" + std::to_string(opt.max_iterations) + ") reached with " +
               std::to_string(alive_count) + " attraction points left";
    }
  }

  Impl(std::span<const Vec3> pts, const ColonizationOptions& options, Context* context)
      : opt(options), ctx(context) {
    opt.validate();
    kill2 = opt.kill * opt.kill;
    infl2 = opt.influence * opt.influence;
    dup = kDuplicateFraction * opt.step;
    dir0 = opt.direction.normalized();
    check_extent(pts, opt.roots);
    points.assign(pts.begin(), pts.end());
    alive.assign(points.size(), 1);
    node_of.assign(points.size(), kNone);
    best_d2.assign(points.size(), std::numeric_limits<double>::infinity());
    alive_count = points.size();
    // Bits so that count * 2^bits < 2^63 for any count <= the number of points.
    const int bits = std::min(52, 62 - static_cast<int>(std::bit_width(points.size() + 1)));
    scale = std::ldexp(1.0, bits);
    build_grid();
    if (opt.obstacle != nullptr) {
      std::vector<Vec3> roots(opt.roots.begin(), opt.roots.end());
      const auto in = inside(roots);
      for (std::size_t r = 0; r < in.size(); ++r)
        check(!in[r], "root " + std::to_string(r) + " lies inside the obstacle");
    }
    for (std::uint32_t r = 0; r < opt.roots.size(); ++r) {
      trees.push_back({});
      trees.back().tip = add_node(opt.roots[r], kNone, r);
      trees.back().box_d2 = points.empty() ? 0 : squared_distance(box, opt.roots[r]);
    }
    std::size_t killed = 0;
    const auto dirty = associate(0, killed);
    refresh_active(dirty, 0);
    finish_check(1);
  }

  ColonizationStep step() {
    ColonizationStep report;
    if (status != ColonizationStatus::kGrowing) {
      report.iteration = iterations;
      report.points_alive = alive_count;
      report.status = status;
      return report;
    }
    check_cancel(ctx);
    ++iterations;
    report.iteration = iterations;

    // Proposals: influenced nodes, then trunk tips, in parent-index order.
    std::vector<Proposal> props(active.size());
    parallel::for_chunks(
        active.size(), 256,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) {
            const std::uint32_t v = active[i];
            const Vec3 d = growth_direction(v);
            props[i] = {v, d, pos[v] + opt.step * d, false, false};
          }
        },
        ctx);
    for (const Tree& t : trees)
      if (!t.has_points && t.trunk == TrunkState::kGrowing)
        props.push_back({t.tip, dir0, pos[t.tip] + opt.step * dir0, true, false});
    std::sort(props.begin(), props.end(),
              [](const Proposal& a, const Proposal& b) { return a.parent < b.parent; });
    apply_obstacle(props);

    const auto first_new = static_cast<std::uint32_t>(pos.size());
    for (const Proposal& p : props) {
      // A position past the largest double (a huge step near the end of the range) is refused
      // like a duplicate: nodes stay finite, so their cells and distances do.
      const bool finite = is_finite(p.position);
      const bool ok = !p.rejected && finite && !is_duplicate(p.position);
      Tree& tree = trees[tree_of[p.parent]];
      if (!ok) {
        ++report.nodes_blocked;
        blocked[p.parent] = 1;
        if (p.trunk) {
          tree.trunk = TrunkState::kStopped;
          tree.stop_reason = p.rejected ? "it would enter the obstacle"
                             : !finite  ? "its next node would not be finite"
                                        : "it would duplicate a node";
        }
        continue;
      }
      const std::uint32_t v = add_node(p.position, p.parent, tree_of[p.parent]);
      if (p.trunk) {
        tree.tip = v;
        const double d2 = squared_distance(box, p.position);
        if (d2 > infl2 && d2 > tree.box_d2) {
          tree.trunk = TrunkState::kStopped;
          tree.stop_reason = "it moves away from the attraction points and is farther than d_i";
        }
        tree.box_d2 = d2;
      }
    }
    report.nodes_added = pos.size() - first_new;

    const auto dirty = associate(first_new, report.points_killed);
    for (const std::uint32_t v : dirty) blocked[v] = 0;  // a changed set may grow elsewhere
    refresh_active(dirty, first_new);
    finish_check(report.nodes_added);
    report.points_alive = alive_count;
    report.status = status;
    if (ctx != nullptr && !points.empty())
      ctx->report("grow", static_cast<double>(reached) / static_cast<double>(points.size()));
    return report;
  }

  Skeleton skeleton() const {
    Skeleton s;
    s.nodes.resize(pos.size());
    s.edges.reserve(pos.size());
    std::vector<std::uint32_t> order(pos.size());
    for (std::uint32_t v = 0; v < pos.size(); ++v) {
      s.nodes[v].position = pos[v];
      order[v] = v;
      if (parent[v] != kNone) s.edges.push_back({parent[v], v});
    }
    pipe_radii(s.nodes, parent, order, opt.tip_radius, opt.pipe_exponent);
    return s;
  }
};

SpaceColonization::SpaceColonization(std::span<const Vec3> points,
                                     const ColonizationOptions& options, Context* ctx)
    : impl_(std::make_unique<Impl>(points, options, ctx)) {}
SpaceColonization::~SpaceColonization() = default;
SpaceColonization::SpaceColonization(SpaceColonization&&) noexcept = default;
SpaceColonization& SpaceColonization::operator=(SpaceColonization&&) noexcept = default;

ColonizationStep SpaceColonization::step() { return impl_->step(); }
bool SpaceColonization::done() const { return impl_->status != ColonizationStatus::kGrowing; }
ColonizationStatus SpaceColonization::status() const { return impl_->status; }
const std::string& SpaceColonization::stall_reason() const { return impl_->reason; }
Skeleton SpaceColonization::skeleton() const { return impl_->skeleton(); }
std::size_t SpaceColonization::iterations() const { return impl_->iterations; }
std::size_t SpaceColonization::node_count() const { return impl_->pos.size(); }
std::size_t SpaceColonization::points_alive() const { return impl_->alive_count; }
std::size_t SpaceColonization::points_total() const { return impl_->points.size(); }
std::vector<bool> SpaceColonization::alive() const {
  std::vector<bool> out(impl_->points.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[impl_->original[k]] = impl_->alive[k] != 0;
  return out;
}
const std::vector<std::uint32_t>& SpaceColonization::parents() const { return impl_->parent; }

ColonizationResult grow_space_colonization(std::span<const Vec3> points,
                                           const ColonizationOptions& options, Context* ctx) {
  const auto start = std::chrono::steady_clock::now();
  SpaceColonization sc(points, options, ctx);
  while (!sc.done()) sc.step();
  ColonizationResult r;
  r.skeleton = sc.skeleton();
  std::vector<std::uint32_t> roots(options.roots.size());
  for (std::uint32_t k = 0; k < roots.size(); ++k) roots[k] = k;
  r.cleanup = clean_branches(r.skeleton, roots, options.cleanup(), ctx);
  r.iterations = sc.iterations();
  r.points_total = sc.points_total();
  r.points_reached = r.points_total - sc.points_alive();
  r.status = sc.status();
  r.stalled = r.status != ColonizationStatus::kCompleted;
  r.stall_reason = sc.stall_reason();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::string no_branch_reason(const ColonizationResult& result, std::span<const Vec3> points,
                             const ColonizationOptions& options) {
  if (result.skeleton.edge_count() > 0) return {};
  if (!result.stall_reason.empty()) return result.stall_reason;
  // Completed without an edge: the constructor killed every point within d_k of a root, so no
  // node ever had a point to grow toward.
  double farthest = 0.0;
  for (const Vec3& p : points) {
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec3& root : options.roots) nearest = std::min(nearest, (p - root).norm());
    farthest = std::max(farthest, nearest);
  }
  const Vec3& r0 = options.roots.front();
  const std::string root = options.roots.size() == 1
                               ? "the root (" + format_shortest(r0.x()) + "," +
                                     format_shortest(r0.y()) + "," + format_shortest(r0.z()) + ")"
                               : "a root";
  const bool one = points.size() == 1;
  return (one ? "the one attraction point lies"
              : "all " + std::to_string(points.size()) + " attraction points lie") +
         " within the kill distance d_k = " + format_number(options.kill) + " of " + root + " (" +
         (one ? "at distance " : "the farthest at distance ") + format_number(farthest) + "), so " +
         (one ? "it was" : "they were") + " reached before any branch grew";
}

void assign_pipe_radii(Skeleton& skeleton, std::span<const std::uint32_t> roots, double tip_radius,
                       double exponent) {
  auto fail = [](const std::string& what) { throw InvalidArgument("assign_pipe_radii: " + what); };
  if (!(std::isfinite(tip_radius) && tip_radius > 0))
    fail("tip_radius must be finite and > 0 (got " + format_number(tip_radius) + ")");
  constexpr double lo = ColonizationOptions::kMinPipeExponent;
  constexpr double hi = ColonizationOptions::kMaxPipeExponent;
  if (!(exponent >= lo && exponent <= hi))
    fail("exponent must be in " + range_text(lo, hi) + " (got " + format_number(exponent) + ")");
  const std::size_t n = skeleton.nodes.size();
  std::vector<std::vector<std::uint32_t>> adj(n);
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto [a, b] = skeleton.edges[e];
    if (a >= n || b >= n || a == b) fail("edge " + std::to_string(e) + " is invalid");
    adj[a].push_back(b);
    adj[b].push_back(a);
  }
  std::vector<std::uint32_t> parent(n, kNone), order;
  std::vector<std::uint8_t> seen(n, 0);
  order.reserve(n);
  for (const std::uint32_t r : roots) {
    if (r >= n) fail("root " + std::to_string(r) + " is out of range");
    if (seen[r]) fail("root " + std::to_string(r) + " is repeated or shares a component with another root");
    seen[r] = 1;
    std::size_t head = order.size();
    order.push_back(r);
    for (; head < order.size(); ++head) {
      const std::uint32_t v = order[head];
      for (const std::uint32_t w : adj[v]) {
        if (w == parent[v]) continue;
        if (seen[w]) fail("the skeleton has a cycle or joins two roots (at node " + std::to_string(w) + ")");
        seen[w] = 1;
        parent[w] = v;
        order.push_back(w);
      }
    }
  }
  for (std::uint32_t v = 0; v < n; ++v)
    if (!seen[v]) {
      if (!adj[v].empty()) fail("node " + std::to_string(v) + " is not connected to any root");
      order.push_back(v);
    }
  pipe_radii(skeleton.nodes, parent, order, tip_radius, exponent);
}

}  // namespace ramiform
