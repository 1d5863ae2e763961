// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/cleanup.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "mesh/mesh_indices.h"
#include "ramiform/core/errors.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using Tri = std::array<std::uint32_t, 3>;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr std::uint32_t kNone = UINT32_MAX;  // end of a corner chain
// Chunk of the parallel scans over triangles and vertices.
constexpr std::size_t kGrain = 16384;
// Blocks of the first parallel round are runs of 2^kBlockBits vertex indices. Polygonizers
// emit triangles cell by cell and number vertices by first use, so such a block is a compact
// piece of surface and most needles lie inside one.
constexpr int kBlockBits = 13;
// The second round's blocks are the cells of a grid with this many cells along each axis.
constexpr std::size_t kGridCells = 16;
// A block of a round looks at its cancellation once per this many needles.
constexpr std::size_t kNeedlesPerCancelCheck = 4096;

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

// Collapses and flips, in blocks that run in parallel. An operation on the needle edge u-v
// reads and writes only the triangles around u and v and the corner chains of u, v and their
// neighbours (every vertex of those triangles), and no vertex moves. So operations whose
// vertices all belong to one block never meet those of another block: a block works through
// its needles alone, and a needle that reaches a vertex of another block is left for the next
// round, which splits the mesh differently; the last round is one serial block. Which
// operations run and in which order depends on the mesh only, never on the threads.
class Collapser {
 public:
  // `ctx` gives the threads; a cancellation of `cancel` stops the rounds between needles.
  Collapser(TriMesh& mesh, const NeedleCleanupOptions& o, const Context* ctx, const Context* cancel)
      : mesh_(mesh),
        ctx_(ctx),
        cancel_(cancel),
        alive_(mesh.triangles.size(), 1),
        head_(mesh.positions.size(), kNone),
        next_(std::make_unique_for_overwrite<std::uint32_t[]>(3 * mesh.triangles.size())),
        touched_(mesh.positions.size(), 0),
        min_angle_(pm::sin(o.min_angle_deg * kDeg)),
        max_edge_ratio_(o.max_edge_ratio),
        cos_turn_(pm::cos(o.max_normal_turn_deg * kDeg)),
        keep_(o.keep_sides.begin(), o.keep_sides.end()) {
    std::sort(keep_.begin(), keep_.end(),
              [](const Vec3& a, const Vec3& b) { return a.x() < b.x(); });
    Vec3 high = Vec3::Constant(-INFINITY);
    for (const Vec3& p : mesh.positions) {
      low_ = low_.cwiseMin(p);
      high = high.cwiseMax(p);
    }
    for (int i = 0; i < 3; ++i) {
      cell_scale_[i] =
          high[i] > low_[i] ? static_cast<double>(kGridCells) / (high[i] - low_[i]) : 0;
    }
    // The chains are built serially, but their memory is first touched in parallel: on big
    // meshes the page faults of a fresh array cost more than the build.
    parallel::for_chunks(
        3 * mesh.triangles.size(), kGrain,
        [&](std::size_t b, std::size_t e) { std::fill(next_.get() + b, next_.get() + e, kNone); },
        ctx);
    // Corner c = 3 t + k (vertex k of triangle t) is chained to the next corner of the same
    // vertex; going backwards leaves every chain ascending.
    for (std::size_t t = mesh.triangles.size(); t-- > 0;) {
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t v = mesh.triangles[t][k];
        const auto c = static_cast<std::uint32_t>(3 * t + k);
        next_[c] = head_[v];
        head_[v] = c;
      }
    }
  }

  // One sweep over the needles; returns the number of changes. After the first sweep only
  // needles next to a change of the previous sweep are looked at: the others were already
  // refused and nothing around them moved.
  std::size_t sweep(bool first) {
    relaxed_ = !first;
    const std::size_t n = mesh_.triangles.size();
    std::vector<std::vector<std::uint32_t>> parts((n + kGrain - 1) / kGrain);
    parallel::for_chunks(
        n, kGrain,
        [&](std::size_t b, std::size_t e) {
          auto& out = parts[b / kGrain];
          for (auto t = static_cast<std::uint32_t>(b); t < e; ++t) {
            if (alive_[t] == 0) continue;
            const Tri& f = mesh_.triangles[t];
            if (!first && touched_[f[0]] == 0 && touched_[f[1]] == 0 && touched_[f[2]] == 0) {
              continue;
            }
            if (angle_of(f) < min_angle_) out.push_back(t);
          }
        },
        ctx_);
    std::fill(touched_.begin(), touched_.end(), 0);
    std::vector<std::uint32_t> needles;
    for (const auto& p : parts) needles.insert(needles.end(), p.begin(), p.end());
    std::size_t done = 0;
    for (const Split split : {Split::kIndex, Split::kSpace, Split::kNone}) {
      needles = run(needles, split, done);
    }
    return done;
  }

  // Drops dead triangles and unused vertices, keeping the order of the rest. In place and
  // serially: fresh memory for copies costs more than the pass itself.
  void compact() {
    // A vertex is used exactly when its corner chain is not empty; its new index replaces the
    // chain head, which is not needed any more.
    std::vector<std::uint32_t>& remap = head_;
    const bool with_normals = mesh_.normals.size() == mesh_.positions.size();
    std::uint32_t kept = 0;
    for (std::uint32_t v = 0; v < remap.size(); ++v) {
      if (remap[v] == kNone) continue;
      mesh_.positions[kept] = mesh_.positions[v];
      if (with_normals) mesh_.normals[kept] = mesh_.normals[v];
      remap[v] = kept++;
    }
    mesh_.positions.resize(kept);
    if (with_normals) mesh_.normals.resize(kept);
    std::size_t alive = 0;
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (alive_[t] == 0) continue;
      const Tri& f = mesh_.triangles[t];
      mesh_.triangles[alive++] = {remap[f[0]], remap[f[1]], remap[f[2]]};
    }
    mesh_.triangles.resize(alive);
  }

  std::size_t removed_triangles = 0;
  std::size_t flipped_edges = 0;

 private:
  // How a round splits the mesh into blocks: by vertex index (runs of 2^kBlockBits indices),
  // by space (cells of a kGridCells^3 grid over the bounding box, so that the needles next to
  // index blocks' borders mostly lie inside a cell), or not at all (one serial block).
  enum class Split { kIndex, kSpace, kNone };

  // One block of a round: what it did, the needles it left for the next round, and scratch
  // lists reused from needle to needle.
  struct Block {
    Split split = Split::kNone;
    std::size_t id = 0;
    std::size_t changes = 0, flips = 0, removed = 0;
    std::vector<std::uint32_t> deferred;
    std::vector<std::uint32_t> around_u, around_v, neighbours_u, neighbours_v;
    std::vector<Tri> before, after;  // scratch of the keep_sides test
  };

  std::size_t blocks(Split split) const {
    switch (split) {
      case Split::kIndex:
        return (mesh_.positions.size() >> kBlockBits) + 1;
      case Split::kSpace:
        return kGridCells * kGridCells * kGridCells;
      case Split::kNone:
        break;
    }
    return 1;
  }

  std::size_t block_of(std::uint32_t v, Split split) const {
    switch (split) {
      case Split::kIndex:
        return v >> kBlockBits;
      case Split::kSpace: {
        std::size_t cell = 0;  // x varies fastest
        for (int i = 2; i >= 0; --i) {
          const double x = (pos(v)[i] - low_[i]) * cell_scale_[i];
          cell = kGridCells * cell +
                 std::min(kGridCells - 1, static_cast<std::size_t>(std::max(0.0, x)));
        }
        return cell;
      }
      case Split::kNone:
        break;
    }
    return 0;
  }

  bool is_cancelled() const { return cancel_ != nullptr && cancel_->is_cancelled(); }
  const Vec3& pos(std::uint32_t v) const { return mesh_.positions[v]; }
  double angle_of(const Tri& f) const { return min_angle_sine(pos(f[0]), pos(f[1]), pos(f[2])); }
  static bool has(const Tri& f, std::uint32_t v) { return f[0] == v || f[1] == v || f[2] == v; }
  bool owns(const Block& blk, std::uint32_t v) const { return block_of(v, blk.split) == blk.id; }

  // Visits `needles` block by block, the blocks in parallel, each in the order given (triangle
  // order at first: polygonizers emit triangles cell by cell, so this order walks the block in
  // space and keeps its arrays in cache; shortest-first order jumps around and made the pass
  // several times slower). Adds the changes to `done`; returns the needles left over, block by
  // block. A needle's block is that of its first vertex, read before the blocks start: the
  // triangle keeps a vertex of that block, so no other block changes it.
  std::vector<std::uint32_t> run(const std::vector<std::uint32_t>& needles, Split split,
                                 std::size_t& done) {
    if (needles.empty()) return {};
    const std::size_t n_blocks = blocks(split);
    std::vector<std::size_t> start(n_blocks + 1, 0);
    for (const std::uint32_t t : needles) ++start[block_of(mesh_.triangles[t][0], split) + 1];
    for (std::size_t b = 0; b < n_blocks; ++b) start[b + 1] += start[b];
    std::vector<std::uint32_t> order(needles.size());
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (const std::uint32_t t : needles) order[fill[block_of(mesh_.triangles[t][0], split)]++] = t;
    std::vector<Block> results(n_blocks);
    parallel::for_chunks(
        n_blocks, 1,
        [&](std::size_t b, std::size_t) {
          Block& r = results[b];
          r.split = split;
          r.id = b;
          for (std::size_t i = start[b]; i < start[b + 1]; ++i) {
            if ((i - start[b]) % kNeedlesPerCancelCheck == 0 && is_cancelled()) break;
            if (!visit(order[i], r)) r.deferred.push_back(order[i]);
          }
        },
        ctx_);
    std::vector<std::uint32_t> left;
    for (const Block& r : results) {
      done += r.changes;
      flipped_edges += r.flips;
      removed_triangles += r.removed;
      left.insert(left.end(), r.deferred.begin(), r.deferred.end());
    }
    return left;
  }

  // Collects the triangles around v and its distinct neighbours; false when v or one of them
  // belongs to another block (then nothing around v may be read).
  bool gather(std::uint32_t v, const Block& blk, std::vector<std::uint32_t>& around,
              std::vector<std::uint32_t>& neighbours) const {
    around.clear();
    neighbours.clear();
    if (!owns(blk, v)) return false;
    for (std::uint32_t c = head_[v]; c != kNone; c = next_[c]) {
      around.push_back(c / 3);
      for (const std::uint32_t w : mesh_.triangles[c / 3]) {
        if (w == v || std::find(neighbours.begin(), neighbours.end(), w) != neighbours.end()) {
          continue;
        }
        if (!owns(blk, w)) return false;
        neighbours.push_back(w);
      }
    }
    return true;
  }

  std::size_t valence(std::uint32_t v) const {  // triangles around v
    std::size_t n = 0;
    for (std::uint32_t c = head_[v]; c != kNone; c = next_[c]) ++n;
    return n;
  }

  void link(std::uint32_t c) {
    const std::uint32_t v = mesh_.triangles[c / 3][c % 3];
    next_[c] = head_[v];
    head_[v] = c;
  }

  void unlink(std::uint32_t c) {
    std::uint32_t* p = &head_[mesh_.triangles[c / 3][c % 3]];
    while (*p != c) p = &next_[*p];
    *p = next_[c];
  }

  // Tries the needle t; false when its neighbourhood reaches another block (t waits for the
  // serial round). The needle is looked at afresh: operations since the sweep began may have
  // changed or removed it.
  bool visit(std::uint32_t t, Block& blk) {
    if (alive_[t] == 0) return true;
    const Tri f = mesh_.triangles[t];
    if (angle_of(f) >= min_angle_) return true;
    int best = 0;
    double best_len = INFINITY, longest = 0;
    for (int k = 0; k < 3; ++k) {
      const double len = (pos(f[k]) - pos(f[(k + 1) % 3])).norm();
      if (len < best_len) best_len = len, best = k;
      longest = std::max(longest, len);
    }
    const std::uint32_t u = f[best], v = f[(best + 1) % 3];
    // Every triangle a collapse of u-v or a flip of t's longest edge reads or changes is
    // around u or v (the flipped edge has u or v as an end), so all their vertices must be
    // this block's.
    if (!gather(u, blk, blk.around_u, blk.neighbours_u) ||
        !gather(v, blk, blk.around_v, blk.neighbours_v)) {
      return false;
    }
    // A needle proper has one short edge: that one may collapse. A cap's shortest edge is
    // not short (its other two edges are), and collapsing it would move the surface: it only
    // gets its longest edge flipped.
    if (best_len < max_edge_ratio_ * longest && try_collapse(u, v, blk)) {
      ++blk.changes;
    } else if (try_flip(t)) {
      ++blk.changes;
      ++blk.flips;
    }
    return true;
  }

  // The smallest angle (as a sine) of the triangles `around`.
  double worst_of(const std::vector<std::uint32_t>& around) const {
    double worst = INFINITY;
    for (const std::uint32_t t : around) worst = std::min(worst, angle_of(mesh_.triangles[t]));
    return worst;
  }

  // Quality of removing x into y (y keeps its position), over the triangles around x: the
  // smallest angle of the changed triangles, or -1 when the collapse is not allowed.
  double evaluate(std::uint32_t x, std::uint32_t y, const std::vector<std::uint32_t>& around_x,
                  const std::array<std::uint32_t, 2>& shared) const {
    double worst_new = INFINITY;
    for (const std::uint32_t t : around_x) {
      if (t == shared[0] || t == shared[1]) continue;
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

  // Whether replacing the triangles `before` by `after` (same boundary) would move a keep_sides
  // point across the surface: its winding number with respect to the closed surface `before`
  // plus `after` reversed is +-1 (Jacobson et al. 2013 solid angles) instead of 0. Only points
  // in the box of `before`'s corners can be swept.
  template <class Before, class After>
  bool sweeps_kept_point(const Before& before, const After& after) const {
    if (keep_.empty()) return false;
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    for (const Tri& f : before) {
      for (const std::uint32_t w : f) {
        lo = lo.cwiseMin(pos(w));
        hi = hi.cwiseMax(pos(w));
      }
    }
    auto first = std::lower_bound(keep_.begin(), keep_.end(), lo.x(),
                                  [](const Vec3& p, double x) { return p.x() < x; });
    for (auto it = first; it != keep_.end() && it->x() <= hi.x(); ++it) {
      const Vec3& p = *it;
      if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any()) continue;
      double w = 0;
      for (const Tri& f : before)
        w += detail::solid_angle_fraction(pos(f[0]) - p, pos(f[1]) - p, pos(f[2]) - p);
      for (const Tri& f : after)
        w -= detail::solid_angle_fraction(pos(f[0]) - p, pos(f[1]) - p, pos(f[2]) - p);
      if (std::abs(w) > 0.5) return true;
    }
    return false;
  }

  bool try_collapse(std::uint32_t u, std::uint32_t v, Block& blk) {
    std::array<std::uint32_t, 2> shared{};
    std::size_t n_shared = 0;
    for (const std::uint32_t t : blk.around_u) {
      if (!has(mesh_.triangles[t], v)) continue;
      if (n_shared == 2) return false;
      shared[n_shared++] = t;
    }
    if (n_shared != 2) return false;
    // The edge must still belong to a needle.
    const double worst_old =
        std::min(angle_of(mesh_.triangles[shared[0]]), angle_of(mesh_.triangles[shared[1]]));
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
    std::size_t common = 0;
    for (const std::uint32_t w : blk.neighbours_v) {
      common +=
          static_cast<std::size_t>(std::count(blk.neighbours_u.begin(), blk.neighbours_u.end(), w));
    }
    if (common != 2) return false;
    for (const std::uint32_t o : opposite) {
      if (valence(o) <= 3) return false;  // on a closed manifold: valence = triangles
    }
    // Keep whichever end point gives the better triangles; they must all beat the needle.
    const double keep_v = evaluate(u, v, blk.around_u, shared);
    const double keep_u = evaluate(v, u, blk.around_v, shared);
    const bool into_v = keep_v >= keep_u;
    const double best = std::max(keep_v, keep_u);
    // The changed triangles must beat the needle. Later sweeps accept a collapse that beats the
    // worst triangle around the removed end before (a worse needle next to this one): the local
    // minimum angle still rises. Measured (triangles below 1 / 5 degrees, smallest angle): the
    // 1,500-segment benchmark tree at level 1, 48 / 628 / 0.035 -> 35 / 394 / 0.042; the
    // 31-segment tree at level 3, 156 / 1,325 / 0.042 -> 124 / 1,215 / 0.042. Relaxed from the
    // first sweep on, it left fewer small angles but a smaller smallest one (0.001 degrees).
    const double bar = relaxed_ ? worst_of(into_v ? blk.around_u : blk.around_v) : worst_old;
    if (!(best > bar)) return false;
    const std::uint32_t x = into_v ? u : v;  // removed
    const std::uint32_t y = into_v ? v : u;  // kept
    if (!keep_.empty()) {
      std::vector<Tri>& before = blk.before;
      std::vector<Tri>& after = blk.after;
      before.clear();
      after.clear();
      for (const std::uint32_t t : into_v ? blk.around_u : blk.around_v) {
        before.push_back(mesh_.triangles[t]);
        if (t == shared[0] || t == shared[1]) continue;
        Tri g = mesh_.triangles[t];
        for (auto& w : g) w = w == x ? y : w;
        after.push_back(g);
      }
      if (sweeps_kept_point(before, after)) return false;
    }
    for (const std::uint32_t t : shared) {
      alive_[t] = 0;
      for (std::uint32_t k = 0; k < 3; ++k) unlink(3 * t + k);
    }
    blk.removed += 2;
    // x's corners become y's: relabel them and put x's chain in front of y's.
    std::uint32_t last = kNone;
    for (std::uint32_t c = head_[x]; c != kNone; c = next_[c]) {
      mesh_.triangles[c / 3][c % 3] = y;
      last = c;
    }
    if (last != kNone) {
      next_[last] = head_[y];
      head_[y] = head_[x];
      head_[x] = kNone;
    }
    for (std::uint32_t c = head_[y]; c != kNone; c = next_[c]) {
      for (const std::uint32_t w : mesh_.triangles[c / 3]) touched_[w] = 1;
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
    std::uint32_t t2 = kNone;
    for (std::uint32_t corner = head_[a]; corner != kNone; corner = next_[corner]) {
      const std::uint32_t t = corner / 3;
      const Tri& f = mesh_.triangles[t];
      if (t != t1 && f[(corner + 2) % 3] == b) t2 = t;  // the directed edge b -> a
    }
    if (t2 == kNone) return false;
    const Tri f2 = mesh_.triangles[t2];
    std::uint32_t d = f2[0];
    for (const std::uint32_t w : f2) {
      if (w != a && w != b) d = w;
    }
    if (d == c) return false;
    for (std::uint32_t corner = head_[c]; corner != kNone; corner = next_[corner]) {
      if (has(mesh_.triangles[corner / 3], d)) return false;  // edge c-d exists
    }
    const Tri g1{a, d, c}, g2{d, b, c};
    const double old_worst = std::min(angle_of(f1), angle_of(f2));
    const double new_worst = std::min(angle_of(g1), angle_of(g2));
    if (!(new_worst > old_worst)) return false;
    if (sweeps_kept_point(std::array<Tri, 2>{f1, f2}, std::array<Tri, 2>{g1, g2})) return false;
    auto normal = [&](const Tri& f) {
      return Vec3((pos(f[1]) - pos(f[0])).cross(pos(f[2]) - pos(f[0])));
    };
    const Vec3 n_old = normal(f1).normalized() + normal(f2).normalized();
    for (const Tri& g : {g1, g2}) {
      const Vec3 n = normal(g);
      if (!(n.dot(n_old) > cos_turn_ * n.norm() * n_old.norm())) return false;
    }
    for (const std::uint32_t t : {t1, t2}) {
      for (std::uint32_t i = 0; i < 3; ++i) unlink(3 * t + i);
    }
    mesh_.triangles[t1] = g1;
    mesh_.triangles[t2] = g2;
    for (const std::uint32_t t : {t1, t2}) {
      for (std::uint32_t i = 0; i < 3; ++i) link(3 * t + i);
    }
    touched_[a] = touched_[b] = touched_[c] = touched_[d] = 1;
    return true;
  }

  TriMesh& mesh_;
  const Context* ctx_;
  const Context* cancel_;
  std::vector<char> alive_;
  // Corner chains: head_[v] is v's first corner, next_[c] the next corner of the same vertex
  // (kNone ends a chain); they list exactly the alive triangles around each vertex.
  std::vector<std::uint32_t> head_;
  std::unique_ptr<std::uint32_t[]> next_;
  std::vector<char> touched_;  // vertices next to a change of the current sweep
  bool relaxed_ = false;       // later sweeps: see try_collapse
  double min_angle_;           // as a sine, see min_angle_sine()
  double max_edge_ratio_;
  double cos_turn_;
  Vec3 low_ = Vec3::Constant(INFINITY);  // the grid of Split::kSpace: its low corner
  Vec3 cell_scale_ = Vec3::Zero();       // and cells per unit length along each axis
  std::vector<Vec3> keep_;               // options.keep_sides, sorted by x
};

// Angle statistics without an atan2 per corner: the angles are ranked by a pseudo-angle (a
// monotone function of the angle computed from its sine and cosine scaled alike), counted in
// buckets of it, and only the corners in the buckets around the median get their exact angle.
constexpr std::size_t kAngleBuckets = 4096;
constexpr std::size_t kAngleGrain = 65536;  // triangles per histogram

// 0 at 0 degrees, 1 at 90, 2 at 180; s >= 0. Matches atan2(s, c) at the ends, -0 included.
double pseudo_angle(double s, double c) {
  const double sum = s + std::abs(c);
  if (!(sum > 0)) return std::signbit(c) ? 2.0 : 0.0;
  return std::signbit(c) ? 2.0 - s / sum : s / sum;
}

std::size_t angle_bucket(double pseudo) {
  return std::min(kAngleBuckets - 1, static_cast<std::size_t>(pseudo * (0.5 * kAngleBuckets)));
}

// Calls fn(s, c) for the three corners of triangle i, with the angle's sine and cosine times
// the same factor, so that atan2(s, c) is the angle.
template <class Fn>
void for_corners(const TriMesh& mesh, std::size_t i, Fn&& fn) {
  const auto& t = mesh.triangles[i];
  const Vec3& a = mesh.positions[t[0]];
  const Vec3& p = mesh.positions[t[1]];
  const Vec3& c = mesh.positions[t[2]];
  const Vec3 ab = p - a, bc = c - p, ca = a - c;
  const double cross = ab.cross(-ca).norm();
  fn(cross, ab.dot(-ca));
  fn(cross, bc.dot(-ab));
  fn(cross, ca.dot(-bc));
}

}  // namespace

AngleSummary angle_summary(const TriMesh& mesh, const Context* ctx) {
  AngleSummary s;
  const std::size_t nt = mesh.triangles.size();
  if (nt == 0) return s;
  struct Part {
    std::vector<std::uint32_t> count;
    double min_pseudo = INFINITY;
    double min_deg = 0;
  };
  std::vector<Part> parts((nt + kAngleGrain - 1) / kAngleGrain);
  parallel::for_chunks(
      nt, kAngleGrain,
      [&](std::size_t b, std::size_t e) {
        Part& part = parts[b / kAngleGrain];
        part.count.assign(kAngleBuckets, 0);
        for (std::size_t i = b; i < e; ++i) {
          for_corners(mesh, i, [&](double sine, double cosine) {
            const double q = pseudo_angle(sine, cosine);
            ++part.count[angle_bucket(q)];
            if (q < part.min_pseudo) {
              part.min_pseudo = q;
              part.min_deg = pm::atan2(sine, cosine) / kDeg;
            }
          });
        }
      },
      ctx);
  std::vector<std::size_t> count(kAngleBuckets, 0);
  double min_pseudo = INFINITY;
  for (const Part& part : parts) {
    for (std::size_t k = 0; k < kAngleBuckets; ++k) count[k] += part.count[k];
    if (part.min_pseudo < min_pseudo) min_pseudo = part.min_pseudo, s.min_deg = part.min_deg;
  }
  // The median as check_mesh() reports it: the mean of the two middle values for an even
  // count. The exact angles of the buckets holding them and of one bucket either side (the
  // pseudo-angle and atan2 may round apart at a bucket's edge) settle it.
  const std::size_t n = 3 * nt;
  const std::size_t upper = n / 2, lower = n % 2 == 0 ? upper - 1 : upper;
  std::size_t first = 0, below = 0;
  while (below + count[first] <= lower) below += count[first++];
  std::size_t last = first, through = below;
  while (through + count[last] <= upper) through += count[last++];
  if (first > 0) below -= count[--first];
  last = std::min(last + 1, kAngleBuckets - 1);
  std::vector<std::vector<double>> window(parts.size());
  parallel::for_chunks(
      nt, kAngleGrain,
      [&](std::size_t b, std::size_t e) {
        auto& out = window[b / kAngleGrain];
        for (std::size_t i = b; i < e; ++i) {
          for_corners(mesh, i, [&](double sine, double cosine) {
            const std::size_t k = angle_bucket(pseudo_angle(sine, cosine));
            if (k >= first && k <= last) out.push_back(pm::atan2(sine, cosine) / kDeg);
          });
        }
      },
      ctx);
  std::vector<double> angles;
  for (const auto& w : window) angles.insert(angles.end(), w.begin(), w.end());
  auto mid = angles.begin() + static_cast<std::ptrdiff_t>(upper - below);
  std::nth_element(angles.begin(), mid, angles.end());
  s.median_deg = *mid;
  if (lower != upper) s.median_deg = 0.5 * (s.median_deg + *std::max_element(angles.begin(), mid));
  return s;
}

void clean_needles(TriMesh& mesh, const NeedleCleanupOptions& o, NeedleCleanupStats* stats,
                   const Context* ctx) {
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
  check_cancel(ctx);
  // The loops that change the mesh get only the thread count: a cancellation inside them would
  // leave a broken mesh. The sweeps stop between needles instead, and the mesh is compacted
  // (valid, cleaned less) before Cancelled is thrown.
  const Context threads(ctx != nullptr ? ctx->threads() : 0);
  NeedleCleanupStats st;
  const AngleSummary before = angle_summary(mesh, ctx);
  st.min_angle_before = before.min_deg;
  st.median_angle_before = before.median_deg;
  Collapser c(mesh, o, &threads, ctx);
  check_cancel(ctx);  // building the corner chains changed nothing yet
  for (int pass = 0; pass < o.passes; ++pass) {
    const std::size_t n = c.sweep(pass == 0);
    st.collapsed_edges += n;
    if (ctx != nullptr && ctx->is_cancelled()) {
      c.compact();
      ctx->check();
    }
    if (n == 0) break;
  }
  st.removed_triangles = c.removed_triangles;
  st.flipped_edges = c.flipped_edges;
  c.compact();
  if (o.measure_after) {
    const AngleSummary after = angle_summary(mesh, &threads);
    st.min_angle_after = after.min_deg;
    st.median_angle_after = after.median_deg;
  }
  if (stats != nullptr) *stats = st;
}

std::size_t remove_small_pieces(TriMesh& mesh, double min_diagonal) {
  const TriangleComponents c = triangle_components(mesh);
  if (c.count <= 1) return 0;
  std::vector<Aabb> boxes(c.count);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) boxes[c.label[t]].extend(mesh.positions[v]);
  }
  std::vector<bool> drop(c.count);
  std::size_t dropped = 0;
  for (std::uint32_t k = 0; k < c.count; ++k) {
    drop[k] = boxes[k].diagonal().norm() < min_diagonal;
    dropped += drop[k] ? 1 : 0;
  }
  if (dropped == 0 || dropped == c.count) return 0;
  TriMesh kept;
  std::vector<std::uint32_t> index(mesh.positions.size(), UINT32_MAX);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (drop[c.label[t]]) continue;
    std::array<std::uint32_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[t][static_cast<std::size_t>(k)];
      if (index[v] == UINT32_MAX) {
        index[v] = static_cast<std::uint32_t>(kept.positions.size());
        kept.positions.push_back(mesh.positions[v]);
        if (!mesh.normals.empty()) kept.normals.push_back(mesh.normals[v]);
      }
      tri[static_cast<std::size_t>(k)] = index[v];
    }
    kept.triangles.push_back(tri);
  }
  mesh = std::move(kept);
  return dropped;
}

}  // namespace ramiform
