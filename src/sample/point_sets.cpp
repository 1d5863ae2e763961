// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/sample/point_sets.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <unordered_map>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/random.h"

namespace ramiform {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Candidates per block: the unit of random sub-streams, parallel evaluation and cancellation.
constexpr std::size_t kBlock = 2048;
/// Field evaluations per parallel chunk.
constexpr std::size_t kEvalGrain = 256;
/// Cells of the bound-pruned candidate region along the longest axis.
constexpr int kRegionInside = 32;
constexpr int kRegionBand = 128;

// Values (and, when `gradients` is given, gradients) of `points`, evaluated in parallel chunks.
void evaluate_parallel(const Field& field, const std::vector<Vec3>& points,
                       std::vector<double>& values, std::vector<Vec3>* gradients,
                       const Context* ctx) {
  values.resize(points.size());
  if (gradients != nullptr) gradients->resize(points.size());
  parallel::for_chunks(
      points.size(), kEvalGrain,
      [&](std::size_t b, std::size_t e) {
        field.evaluate(std::span<const Vec3>(points.data() + b, e - b),
                       std::span<double>(values.data() + b, e - b),
                       gradients != nullptr ? std::span<Vec3>(gradients->data() + b, e - b)
                                            : std::span<Vec3>());
      },
      ctx);
}

// ---------------------------------------------------------------------------------------------
// Target sets {lo < f < hi} and their classification by a conservative bound.

struct Target {
  double lo = -kInf;  ///< exclusive
  double hi = kInf;   ///< exclusive
  [[nodiscard]] bool contains(double v) const { return v > lo && v < hi; }
};

enum class CellClass : std::uint8_t { kEmpty = 0, kPartial = 1, kFull = 2 };

CellClass classify(const Interval& b, const Target& t) {
  if (!(b.hi > t.lo) || !(b.lo < t.hi)) return CellClass::kEmpty;
  if (b.lo > t.lo && b.hi < t.hi) return CellClass::kFull;
  return CellClass::kPartial;
}

struct Stopwatch {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  [[nodiscard]] double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
};

/// Fills SampleStats on scope exit from whichever path returns.
class StatsScope {
 public:
  StatsScope(const Field* field, SampleStats* out) : field_(field), out_(out) {
    if (field_ != nullptr) evals0_ = field_->evaluations();
  }
  ~StatsScope() {
    if (out_ == nullptr) return;
    stats.seconds = watch_.seconds();
    if (field_ != nullptr) stats.field_evals = field_->evaluations() - evals0_;
    *out_ = stats;
  }
  StatsScope(const StatsScope&) = delete;
  StatsScope& operator=(const StatsScope&) = delete;
  SampleStats stats;

 private:
  const Field* field_;
  SampleStats* out_;
  std::uint64_t evals0_ = 0;
  Stopwatch watch_;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidArgument(message);
}

std::size_t attempt_budget(std::size_t max_attempts, std::size_t count) {
  if (max_attempts != 0) return max_attempts;
  const std::size_t cap = std::numeric_limits<std::size_t>::max() / 2000;
  return 1000 * std::min(count, cap) + 1000000;
}

void check_box(const Aabb& box, const std::string& what) {
  if (box.isEmpty()) return;
  if (!box.min().allFinite() || !box.max().allFinite()) {
    throw InvalidArgument(
        what + ": the sampling box is unbounded (" + format_number(box.min().x()) + ", " +
        format_number(box.min().y()) + ", " + format_number(box.min().z()) + ") - (" +
        format_number(box.max().x()) + ", " + format_number(box.max().y()) + ", " +
        format_number(box.max().z()) + "); intersect the field with a bounded shape first");
  }
}

// ---------------------------------------------------------------------------------------------
// A cubic voxel grid over a box and a bound-driven classification of its voxels.

struct VoxelGrid {
  Vec3 origin = Vec3::Zero();
  double h = 0.0;
  std::array<std::int64_t, 3> n{0, 0, 0};

  VoxelGrid() = default;
  VoxelGrid(const Aabb& box, double cell) : origin(box.min()), h(cell) {
    const Vec3 size = box.sizes();
    for (int a = 0; a < 3; ++a) {
      n[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(size[a] / h - 1e-9)));
    }
  }
  [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(n[0] * n[1] * n[2]); }
  [[nodiscard]] Aabb box(std::int64_t i0, std::int64_t j0, std::int64_t k0, std::int64_t i1,
                         std::int64_t j1, std::int64_t k1) const {
    return Aabb(origin + h * Vec3(double(i0), double(j0), double(k0)),
                origin + h * Vec3(double(i1), double(j1), double(k1)));
  }
  [[nodiscard]] std::size_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return static_cast<std::size_t>(i + n[0] * (j + n[1] * k));
  }
  [[nodiscard]] std::int64_t coord(double x, int a) const {
    const auto c = static_cast<std::int64_t>(std::floor((x - origin[a]) / h));
    return std::clamp<std::int64_t>(c, 0, n[a] - 1);
  }
};

struct IndexBox {
  std::array<std::int64_t, 3> lo;
  std::array<std::int64_t, 3> hi;  // exclusive
};

/// Recursively classifies index boxes of `grid` against `target` by field.bound(): calls
/// `emit(IndexBox, CellClass)` for every non-empty leaf (a full box at any level, or a single
/// partial voxel). Top-level blocks of `top` voxels a side run in parallel; each block's emits
/// are collected in order, so the result does not depend on the thread count.
template <class Leaf>
std::vector<std::vector<Leaf>> descend(
    const Field& field, const VoxelGrid& grid, const Target& target,
    const std::function<void(const IndexBox&, CellClass, std::vector<Leaf>&)>& emit,
    const Context* ctx, std::int64_t top = 8) {
  std::array<std::int64_t, 3> blocks{};
  for (int a = 0; a < 3; ++a) blocks[a] = (grid.n[a] + top - 1) / top;
  const auto count = static_cast<std::size_t>(blocks[0] * blocks[1] * blocks[2]);
  std::vector<std::vector<Leaf>> out(count);
  std::function<void(const IndexBox&, std::vector<Leaf>&)> rec = [&](const IndexBox& b,
                                                                     std::vector<Leaf>& o) {
    const CellClass c = classify(
        field.bound(grid.box(b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2])), target);
    if (c == CellClass::kEmpty) return;
    const bool single = b.hi[0] - b.lo[0] == 1 && b.hi[1] - b.lo[1] == 1 && b.hi[2] - b.lo[2] == 1;
    if (c == CellClass::kFull || single) {
      emit(b, c, o);
      return;
    }
    std::array<std::array<std::int64_t, 3>, 3> cuts{};  // lo, mid, hi per axis
    for (int a = 0; a < 3; ++a) {
      cuts[a] = {b.lo[a], b.lo[a] + (b.hi[a] - b.lo[a] + 1) / 2, b.hi[a]};
    }
    for (int z = 0; z < 2; ++z) {
      for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
          IndexBox child{{cuts[0][x], cuts[1][y], cuts[2][z]},
                         {cuts[0][x + 1], cuts[1][y + 1], cuts[2][z + 1]}};
          if (child.lo[0] < child.hi[0] && child.lo[1] < child.hi[1] && child.lo[2] < child.hi[2]) {
            rec(child, o);
          }
        }
      }
    }
  };
  parallel::for_each(
      count, 1,
      [&](std::size_t t) {
        const auto bx = static_cast<std::int64_t>(t) % blocks[0];
        const auto by = (static_cast<std::int64_t>(t) / blocks[0]) % blocks[1];
        const auto bz = static_cast<std::int64_t>(t) / (blocks[0] * blocks[1]);
        IndexBox b{{bx * top, by * top, bz * top},
                   {std::min(grid.n[0], (bx + 1) * top), std::min(grid.n[1], (by + 1) * top),
                    std::min(grid.n[2], (bz + 1) * top)}};
        rec(b, out[t]);
      },
      ctx);
  return out;
}

// ---------------------------------------------------------------------------------------------
// The candidate region: bound-pruned cells, drawn from in proportion to their volume.

struct Cell {
  Aabb box;
  bool full = false;  ///< every point of the cell is in the target set
};

class Region {
 public:
  /// resolution 0: one partial cell, the whole box (no pruning).
  Region(const Field& field, const Aabb& box, const Target& target, int resolution,
         const Context* ctx, std::int64_t top = 8) {
    if (box.isEmpty()) return;
    const double longest = box.sizes().maxCoeff();
    if (!(longest > 0.0)) return;
    if (resolution == 0) {
      cells_.push_back({box, false});
      volume_ = box.volume();
      cdf_.push_back(volume_);
      return;
    }
    const VoxelGrid grid(box, longest / resolution);
    const auto parts = descend<Cell>(
        field, grid, target,
        [&](const IndexBox& b, CellClass c, std::vector<Cell>& o) {
          o.push_back({grid.box(b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]),
                       c == CellClass::kFull});
        },
        ctx, top);
    for (const auto& p : parts) cells_.insert(cells_.end(), p.begin(), p.end());
    cdf_.reserve(cells_.size());
    for (const auto& c : cells_) {
      volume_ += c.box.volume();
      cdf_.push_back(volume_);
    }
  }

  [[nodiscard]] bool is_empty() const { return cells_.empty() || !(volume_ > 0.0); }
  [[nodiscard]] double volume() const { return volume_; }
  [[nodiscard]] std::size_t cell_count() const { return cells_.size(); }

  /// A point uniform in the union of the cells; `full` says whether its cell is full.
  Vec3 draw(Rng& rng, bool& full) const {
    const double u = rng.uniform() * volume_;
    auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    if (it == cdf_.end()) --it;
    const Cell& c = cells_[static_cast<std::size_t>(it - cdf_.begin())];
    full = c.full;
    const Vec3 t(rng.uniform(), rng.uniform(), rng.uniform());
    return c.box.min() + c.box.sizes().cwiseProduct(t);
  }

 private:
  std::vector<Cell> cells_;
  std::vector<double> cdf_;
  double volume_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
// A background grid of accepted points for minimum-distance queries.

class PointGrid {
 public:
  PointGrid(const Aabb& box, double radius) : r2_(radius * radius) {
    if (!(radius > 0.0) || box.isEmpty()) return;
    grid_ = VoxelGrid(box, radius);
    dense_ = grid_.size() <= (std::size_t{1} << 24);
    if (dense_) head_.assign(grid_.size(), -1);
    active_ = true;
  }

  [[nodiscard]] bool is_active() const { return active_; }

  /// True when some stored point lies strictly closer than the radius to p.
  [[nodiscard]] bool has_near(const Vec3& p) const {
    if (!active_) return false;
    const std::int64_t ci = grid_.coord(p.x(), 0), cj = grid_.coord(p.y(), 1),
                       ck = grid_.coord(p.z(), 2);
    for (std::int64_t k = std::max<std::int64_t>(0, ck - 1); k <= std::min(grid_.n[2] - 1, ck + 1);
         ++k) {
      for (std::int64_t j = std::max<std::int64_t>(0, cj - 1);
           j <= std::min(grid_.n[1] - 1, cj + 1); ++j) {
        for (std::int64_t i = std::max<std::int64_t>(0, ci - 1);
             i <= std::min(grid_.n[0] - 1, ci + 1); ++i) {
          const std::size_t c = grid_.index(i, j, k);
          if (dense_) {
            for (std::int32_t q = head_[c]; q >= 0; q = next_[static_cast<std::size_t>(q)]) {
              if ((points_[static_cast<std::size_t>(q)] - p).squaredNorm() < r2_) return true;
            }
          } else if (const auto it = sparse_.find(c); it != sparse_.end()) {
            for (const std::uint32_t q : it->second) {
              if ((points_[q] - p).squaredNorm() < r2_) return true;
            }
          }
        }
      }
    }
    return false;
  }

  void add(const Vec3& p) {
    if (!active_) return;
    const std::size_t c =
        grid_.index(grid_.coord(p.x(), 0), grid_.coord(p.y(), 1), grid_.coord(p.z(), 2));
    const auto id = static_cast<std::int32_t>(points_.size());
    points_.push_back(p);
    if (dense_) {
      next_.push_back(head_[c]);
      head_[c] = id;
    } else {
      sparse_[c].push_back(static_cast<std::uint32_t>(id));
    }
  }

 private:
  double r2_ = 0.0;
  bool active_ = false;
  bool dense_ = true;
  VoxelGrid grid_;
  std::vector<std::int32_t> head_;
  std::vector<std::int32_t> next_;
  std::unordered_map<std::size_t, std::vector<std::uint32_t>> sparse_;
  std::vector<Vec3> points_;
};

// ---------------------------------------------------------------------------------------------
// §6.2.2 field cache: hashed cubes along the target set with cached corner values.

class FieldCache {
 public:
  enum class Verdict { kReject, kEvaluate, kAccept };

  FieldCache(const Field& field, const Aabb& box, double cell, const Target& target,
             double tolerance, const Context* ctx)
      : grid_(box, cell), target_(target), tolerance_(tolerance) {
    struct Leaf {
      std::size_t key;
      bool full;
    };
    const auto parts = descend<Leaf>(
        field, grid_, target,
        [&](const IndexBox& b, CellClass c, std::vector<Leaf>& o) {
          for (std::int64_t k = b.lo[2]; k < b.hi[2]; ++k) {
            for (std::int64_t j = b.lo[1]; j < b.hi[1]; ++j) {
              for (std::int64_t i = b.lo[0]; i < b.hi[0]; ++i) {
                o.push_back({grid_.index(i, j, k), c == CellClass::kFull});
              }
            }
          }
        },
        ctx);
    std::vector<Leaf> leaves;
    for (const auto& p : parts) leaves.insert(leaves.end(), p.begin(), p.end());
    cubes_.resize(leaves.size());
    index_.reserve(leaves.size() * 2);
    // Corners are shared between cubes: give each distinct corner one slot.
    std::unordered_map<std::size_t, std::uint32_t> corner_slot;
    std::vector<Vec3> corner_points;
    const std::size_t cx = static_cast<std::size_t>(grid_.n[0] + 1);
    const std::size_t cy = static_cast<std::size_t>(grid_.n[1] + 1);
    std::vector<std::array<std::uint32_t, 8>> slots(leaves.size());
    for (std::size_t c = 0; c < leaves.size(); ++c) {
      const std::size_t key = leaves[c].key;
      index_.emplace(key, static_cast<std::uint32_t>(c));
      cubes_[c].full = leaves[c].full;
      if (leaves[c].full) continue;
      const std::size_t i = key % static_cast<std::size_t>(grid_.n[0]);
      const std::size_t j =
          (key / static_cast<std::size_t>(grid_.n[0])) % static_cast<std::size_t>(grid_.n[1]);
      const std::size_t k = key / static_cast<std::size_t>(grid_.n[0] * grid_.n[1]);
      for (int v = 0; v < 8; ++v) {
        const std::size_t ci = i + (v & 1), cj = j + ((v >> 1) & 1), ck = k + ((v >> 2) & 1);
        const std::size_t ckey = ci + cx * (cj + cy * ck);
        auto [it, inserted] =
            corner_slot.emplace(ckey, static_cast<std::uint32_t>(corner_points.size()));
        if (inserted) {
          corner_points.push_back(grid_.origin +
                                  grid_.h * Vec3(double(ci), double(cj), double(ck)));
        }
        slots[c][static_cast<std::size_t>(v)] = it->second;
      }
    }
    std::vector<double> corner_values;
    evaluate_parallel(field, corner_points, corner_values, nullptr, ctx);
    for (std::size_t c = 0; c < cubes_.size(); ++c) {
      if (cubes_[c].full) continue;
      double lo = kInf, hi = -kInf;
      for (int v = 0; v < 8; ++v) {
        const double value = corner_values[slots[c][static_cast<std::size_t>(v)]];
        cubes_[c].corner[static_cast<std::size_t>(v)] = value;
        lo = std::min(lo, value);
        hi = std::max(hi, value);
      }
      cubes_[c].slack =
          tolerance_ > 0.0 ? tolerance_ : std::max(target_.hi - target_.lo, 0.25 * (hi - lo));
    }
  }

  [[nodiscard]] std::size_t cube_count() const { return cubes_.size(); }

  [[nodiscard]] Verdict classify(const Vec3& p) const {
    std::array<std::int64_t, 3> c{};
    Vec3 t;
    for (int a = 0; a < 3; ++a) {
      const double x = (p[a] - grid_.origin[a]) / grid_.h;
      c[a] = static_cast<std::int64_t>(std::floor(x));
      if (c[a] < 0 || c[a] >= grid_.n[a]) {
        if (c[a] == grid_.n[a] && x <= double(grid_.n[a])) {
          c[a] = grid_.n[a] - 1;  // a point on the far face
        } else {
          return Verdict::kReject;
        }
      }
      t[a] = std::clamp(x - double(c[a]), 0.0, 1.0);
    }
    const auto it = index_.find(grid_.index(c[0], c[1], c[2]));
    if (it == index_.end()) return Verdict::kReject;  // no target point can be in this cube
    const Cube& cube = cubes_[it->second];
    if (cube.full) return Verdict::kAccept;
    const auto& v = cube.corner;
    const double x00 = v[0] + t.x() * (v[1] - v[0]);
    const double x10 = v[2] + t.x() * (v[3] - v[2]);
    const double x01 = v[4] + t.x() * (v[5] - v[4]);
    const double x11 = v[6] + t.x() * (v[7] - v[6]);
    const double y0 = x00 + t.y() * (x10 - x00);
    const double y1 = x01 + t.y() * (x11 - x01);
    const double f = y0 + t.z() * (y1 - y0);
    return (f > target_.lo - cube.slack && f < target_.hi + cube.slack) ? Verdict::kEvaluate
                                                                        : Verdict::kReject;
  }

  /// True when the box overlaps some cached cube (for Lane's grid initialization).
  [[nodiscard]] bool overlaps(const Aabb& box) const {
    std::array<std::int64_t, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max<std::int64_t>(
          0, static_cast<std::int64_t>(std::floor((box.min()[a] - grid_.origin[a]) / grid_.h)));
      hi[a] = std::min<std::int64_t>(
          grid_.n[a] - 1,
          static_cast<std::int64_t>(std::floor((box.max()[a] - grid_.origin[a]) / grid_.h)));
      if (lo[a] > hi[a]) return false;
    }
    for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
          if (index_.count(grid_.index(i, j, k)) != 0) return true;
        }
      }
    }
    return false;
  }

 private:
  struct Cube {
    std::array<double, 8> corner{};  // x fastest, then y, then z
    double slack = 0.0;
    bool full = false;
  };
  VoxelGrid grid_;
  Target target_;
  double tolerance_;
  std::vector<Cube> cubes_;
  std::unordered_map<std::size_t, std::uint32_t> index_;
};

// ---------------------------------------------------------------------------------------------
// Dart throwing: candidates from the region, optional density and minimum distance.

struct DartSpec {
  Target target;
  std::function<double(double)> density;  ///< acceptance probability given f; empty = 1
  double min_distance = 0.0;
  std::size_t count = 0;
  std::size_t max_attempts = 0;
  std::size_t max_failures = 0;  ///< 0 = never saturate on failures
  const FieldCache* cache = nullptr;
  std::uint64_t stream = 0;  ///< sub-stream index of the candidate blocks
};

// The candidate-block loop shared by dart throwing and projection: block b draws its candidates
// from Rng(seed).split(stream).split(b), so the points never depend on the thread count.
// `block_fn(rng, n, near, out)` handles n candidates, appends the accepted points to `out` (and
// `near`) and returns true to stop; the loop also stops when the attempt budget is spent
// (saturated). An empty region saturates at once.
template <class BlockFn>
PointSet run_blocks(const Region& region, const Aabb& box, double min_distance, std::size_t count,
                    std::size_t max_attempts, std::uint64_t seed, std::uint64_t stream,
                    Context* ctx, SampleStats& st, BlockFn&& block_fn) {
  PointSet out;
  if (count == 0) return out;
  if (region.is_empty()) {
    st.saturated = true;
    return out;
  }
  const Rng base = Rng(seed).split(stream);
  PointGrid near(box, min_distance);
  out.positions.reserve(std::min<std::size_t>(count, 1 << 20));
  for (std::uint64_t block = 0;; ++block) {
    check_cancel(ctx);
    if (st.attempts >= max_attempts) {
      st.saturated = true;
      break;
    }
    const std::size_t n = std::min(kBlock, max_attempts - st.attempts);
    Rng rng = base.split(block);
    st.attempts += n;
    const bool stop = block_fn(rng, n, near, out);
    if (ctx != nullptr) ctx->report("sample", double(out.positions.size()) / double(count));
    if (stop) break;
  }
  return out;
}

PointSet run_dart(const Field& field, const Region& region, const Aabb& box, const DartSpec& spec,
                  std::uint64_t seed, Context* ctx, SampleStats& st) {
  std::vector<Vec3> cand(kBlock);
  std::vector<double> coin(kBlock);
  std::vector<std::uint8_t> state(kBlock);  // 0 reject, 1 evaluate, 2 accept (no evaluation)
  std::vector<std::uint8_t> too_close(kBlock);
  std::vector<double> value(kBlock);
  std::vector<Vec3> eval_points;
  std::vector<double> eval_values;
  std::vector<std::uint32_t> eval_index;
  std::size_t failures = 0;
  const bool needs_value = static_cast<bool>(spec.density);
  auto block_fn = [&](Rng& rng, std::size_t n, PointGrid& near, PointSet& out) {
    eval_points.clear();
    eval_index.clear();
    for (std::size_t i = 0; i < n; ++i) {
      bool full = false;
      cand[i] = region.draw(rng, full);
      coin[i] = rng.uniform();
      // Points accepted before this block are fixed: a candidate too close to them fails
      // whatever its value, so it needs no evaluation (same outcome as testing in order).
      too_close[i] = near.has_near(cand[i]) ? 1 : 0;
      state[i] = full ? 2 : 1;
      if (too_close[i] == 0 && state[i] == 1 && spec.cache != nullptr) {
        switch (spec.cache->classify(cand[i])) {
          case FieldCache::Verdict::kReject:
            state[i] = 0;
            break;
          case FieldCache::Verdict::kAccept:
            state[i] = 2;
            break;
          case FieldCache::Verdict::kEvaluate:
            break;
        }
      }
      if (too_close[i] == 0 && (state[i] == 1 || (state[i] == 2 && needs_value))) {
        eval_index.push_back(static_cast<std::uint32_t>(i));
        eval_points.push_back(cand[i]);
      }
    }
    evaluate_parallel(field, eval_points, eval_values, nullptr, ctx);
    for (std::size_t e = 0; e < eval_index.size(); ++e) value[eval_index[e]] = eval_values[e];
    bool stop = false;
    for (std::size_t i = 0; i < n && !stop; ++i) {
      if (too_close[i] != 0) {
        if (spec.max_failures != 0 && ++failures >= spec.max_failures) {
          st.saturated = true;
          stop = true;
        }
        continue;
      }
      if (state[i] == 0) continue;
      if (state[i] == 1 && !spec.target.contains(value[i])) continue;
      if (needs_value && !(coin[i] < spec.density(value[i]))) continue;
      if (near.has_near(cand[i])) {
        if (spec.max_failures != 0 && ++failures >= spec.max_failures) {
          st.saturated = true;
          stop = true;
        }
        continue;
      }
      failures = 0;
      near.add(cand[i]);
      out.positions.push_back(cand[i]);
      if (out.positions.size() == spec.count) stop = true;
    }
    return stop;
  };
  return run_blocks(region, box, spec.min_distance, spec.count, spec.max_attempts, seed,
                    spec.stream, ctx, st, block_fn);
}

/// Inside volume estimated from the region and a pilot batch of candidates.
double estimate_volume(const Field& field, const Region& region, const Target& target,
                       std::uint64_t seed, Context* ctx) {
  if (region.is_empty()) return 0.0;
  constexpr std::size_t kPilot = 8192;
  Rng rng = Rng(seed).split(0x70696c6f74ULL);  // "pilot"
  std::vector<Vec3> pts;
  std::size_t full_count = 0;
  for (std::size_t i = 0; i < kPilot; ++i) {
    bool full = false;
    const Vec3 p = region.draw(rng, full);
    if (full) {
      ++full_count;
    } else {
      pts.push_back(p);
    }
  }
  std::vector<double> values;
  evaluate_parallel(field, pts, values, nullptr, ctx);
  std::size_t in = full_count;
  for (const double v : values) in += target.contains(v) ? 1 : 0;
  return region.volume() * double(in) / double(kPilot);
}

Target inside_target(const Field& field) { return Target{field.iso(), kInf}; }

// ---------------------------------------------------------------------------------------------
// Near-surface projection: a uniform sample of a wider band, compressed onto the band by Newton
// steps along the gradient (NearSurfaceOptions::Method::kProject).

/// Top-level block side (voxels) of the projection region's descent: a band meets few of the
/// 8-voxel blocks the other samplers start from, and every block costs a bound() call, so
/// larger blocks need about 4x fewer calls here; 32 still gives dozens of parallel tasks.
constexpr std::int64_t kProjectTop = 32;
/// Cells of the pilot region (along the longest axis) that estimates the gradient norm.
constexpr int kProjectPilotRegion = 32;
constexpr std::size_t kProjectPilot = 2048;
/// Automatic wider-band thickness, in sampling cells: thin enough that the field is close to
/// affine across it for features a cell wide, thick enough that a good share of the
/// candidates in the cells meeting it lie in it. On the benchmark surface (bench_sample.cpp)
/// wider bands of 0.09-0.22 cells gave 20k-point sets that two-sample chi-square tests on
/// 100-1200 bins could not tell from rejection sampling's.
constexpr double kProjectCells = 0.2;
/// Newton steps per candidate (the second only when the first misses the band).
constexpr int kProjectSteps = 2;

struct ProjectSpec {
  Target band;            ///< the band (iso - epsilon, iso)
  double width = 0.0;     ///< W: the wider band is |f - c| < W / 2, c the band's centre
  double max_step = 0.0;  ///< longest Newton step (model units)
  double min_distance = 0.0;
  std::size_t count = 0;
  std::size_t max_attempts = 0;
  std::uint64_t stream = 0;  ///< sub-stream index of the candidate blocks
};

/// The automatic W: kProjectCells * `cell` * the median |grad f| of pilot points whose
/// linearized distance |f - c| / |grad f| to the band's centre level is below one cell, at most
/// the distance from c to the smallest and to the largest pilot value (a wider band reaching a
/// flat value, such as the 0 outside compact-support primitives, would hold whole regions), and
/// at least epsilon (epsilon when no pilot point qualifies: then projection is rejection).
double automatic_project_width(const Field& field, const Aabb& box, const Target& band, double cell,
                               std::uint64_t seed, Context* ctx) {
  const double epsilon = band.hi - band.lo;
  const Region pilot_region(field, box, band, kProjectPilotRegion, ctx);
  if (pilot_region.is_empty()) return epsilon;
  Rng rng = Rng(seed).split(0x70726f6a656374ULL);  // "project"
  std::vector<Vec3> pts(kProjectPilot);
  for (auto& p : pts) {
    bool full = false;
    p = pilot_region.draw(rng, full);
  }
  std::vector<double> values;
  std::vector<Vec3> gradients;
  evaluate_parallel(field, pts, values, &gradients, ctx);
  const double centre = 0.5 * (band.lo + band.hi);
  std::vector<double> norms;
  double lowest = kInf, highest = -kInf;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!std::isfinite(values[i])) continue;
    lowest = std::min(lowest, values[i]);
    highest = std::max(highest, values[i]);
    const double g = gradients[i].norm();
    if (!(g > 0.0) || !std::isfinite(g)) continue;
    if (std::abs(values[i] - centre) < cell * g) norms.push_back(g);
  }
  if (norms.empty()) return epsilon;
  const auto mid = norms.begin() + static_cast<std::ptrdiff_t>(norms.size() / 2);
  std::nth_element(norms.begin(), mid, norms.end());
  const double w = std::min({kProjectCells * cell * *mid, centre - lowest, highest - centre});
  return std::isfinite(w) ? std::max(epsilon, w) : epsilon;
}

/// The wider band |f - c| < W / 2 around the band's centre c.
Target wide_band(const Target& band, double width) {
  const double centre = 0.5 * (band.lo + band.hi);
  return Target{centre - 0.5 * width, centre + 0.5 * width};
}

/// One Newton step from p (value f, gradient g) to the value t: false when the gradient is zero
/// or not finite, the step is longer than max_step, or it leaves the box.
bool newton_step(const Vec3& p, double f, const Vec3& g, double t, double max_step, const Aabb& box,
                 Vec3& out) {
  const double g2 = g.squaredNorm();
  if (!(g2 > 0.0) || !std::isfinite(g2)) return false;
  const Vec3 step = ((t - f) / g2) * g;
  const double length = step.norm();
  if (!(length <= max_step)) return false;  // also false for NaN
  out = p + step;
  return box.contains(out);
}

PointSet run_project(const Field& field, const Region& region, const Aabb& box,
                     const ProjectSpec& spec, std::uint64_t seed, Context* ctx, SampleStats& st) {
  const double centre = 0.5 * (spec.band.lo + spec.band.hi);
  const Target wide = wide_band(spec.band, spec.width);
  const double squeeze = (spec.band.hi - spec.band.lo) / spec.width;  // epsilon / W <= 1
  std::vector<Vec3> cand(kBlock);
  std::vector<double> target(kBlock);
  std::vector<std::uint8_t> found(kBlock);  // 1: result[i] is a band point
  std::vector<Vec3> result(kBlock);
  std::vector<Vec3> pts;
  std::vector<double> values;
  std::vector<Vec3> gradients;
  std::vector<std::uint32_t> index;
  auto block_fn = [&](Rng& rng, std::size_t n, PointGrid& near, PointSet& out) {
    for (std::size_t i = 0; i < n; ++i) {
      bool full = false;  // the wider band is not the target: every candidate is evaluated
      cand[i] = region.draw(rng, full);
    }
    std::fill(found.begin(), found.begin() + static_cast<std::ptrdiff_t>(n), 0);
    // Step 0 evaluates the candidates; step k the points after k Newton steps. Gradients are
    // needed for every step but the last (they cost little next to the values).
    pts.assign(cand.begin(), cand.begin() + static_cast<std::ptrdiff_t>(n));
    index.resize(n);
    for (std::size_t i = 0; i < n; ++i) index[i] = static_cast<std::uint32_t>(i);
    for (int step = 0; step <= kProjectSteps && !pts.empty(); ++step) {
      evaluate_parallel(field, pts, values, step < kProjectSteps ? &gradients : nullptr, ctx);
      std::size_t kept = 0;
      for (std::size_t e = 0; e < pts.size(); ++e) {
        const std::uint32_t i = index[e];
        const double f = values[e];
        if (step == 0) {
          if (!wide.contains(f)) continue;
          target[i] = squeeze == 1.0 ? f : centre + (f - centre) * squeeze;
          if (target[i] == f) {  // already at its target (W == epsilon: plain rejection)
            if (spec.band.contains(f)) {
              result[i] = pts[e];
              found[i] = 1;
            }
            continue;
          }
        } else if (spec.band.contains(f)) {
          result[i] = pts[e];
          found[i] = 1;
          continue;
        }
        if (step == kProjectSteps) continue;
        Vec3 next;
        if (!newton_step(pts[e], f, gradients[e], target[i], spec.max_step, box, next)) continue;
        pts[kept] = next;
        index[kept] = i;
        ++kept;
      }
      pts.resize(kept);
      index.resize(kept);
    }
    bool stop = false;
    for (std::size_t i = 0; i < n && !stop; ++i) {
      if (found[i] == 0) continue;
      if (near.has_near(result[i])) continue;
      near.add(result[i]);
      out.positions.push_back(result[i]);
      if (out.positions.size() == spec.count) stop = true;
    }
    return stop;
  };
  return run_blocks(region, box, spec.min_distance, spec.count, spec.max_attempts, seed,
                    spec.stream, ctx, st, block_fn);
}

// ---------------------------------------------------------------------------------------------
// Lane and Prusinkiewicz: a voxel pdf in a sum tree, deformed by a kernel after each point.

class SumTree {
 public:
  explicit SumTree(std::size_t n) {
    size_ = 1;
    while (size_ < n) size_ *= 2;
    node_.assign(2 * size_, 0.0);
  }
  void set_all(const std::vector<double>& w) {
    std::fill(node_.begin(), node_.end(), 0.0);
    std::copy(w.begin(), w.end(), node_.begin() + static_cast<std::ptrdiff_t>(size_));
    for (std::size_t i = size_ - 1; i >= 1; --i) node_[i] = node_[2 * i] + node_[2 * i + 1];
  }
  [[nodiscard]] double get(std::size_t i) const { return node_[size_ + i]; }
  void set(std::size_t i, double w) {
    std::size_t k = size_ + i;
    node_[k] = w;
    // Parents are recomputed from their children, so sums never drift.
    for (k /= 2; k >= 1; k /= 2) node_[k] = node_[2 * k] + node_[2 * k + 1];
  }
  [[nodiscard]] double total() const { return node_[1]; }
  /// The leaf where the prefix sum passes u (0 <= u < total).
  [[nodiscard]] std::size_t find(double u) const {
    std::size_t k = 1;
    while (k < size_) {
      if (u < node_[2 * k] || !(node_[2 * k + 1] > 0.0)) {
        k = 2 * k;
      } else {
        u -= node_[2 * k];
        k = 2 * k + 1;
      }
    }
    return k - size_;
  }
  [[nodiscard]] std::vector<double> leaves() const {
    return {node_.begin() + static_cast<std::ptrdiff_t>(size_), node_.end()};
  }

 private:
  std::size_t size_ = 1;
  std::vector<double> node_;
};

struct LaneSpec {
  Target target;
  LaneKernel kernel;
  std::size_t grid = 64;
  bool prune = true;
  std::size_t count = 0;
  std::size_t max_attempts = 0;
  const FieldCache* cache = nullptr;
};

PointSet run_lane(const Field& field, const Aabb& box, const LaneSpec& spec, std::uint64_t seed,
                  Context* ctx, SampleStats& st) {
  PointSet out;
  if (spec.count == 0) return out;
  if (box.isEmpty() || !(box.sizes().maxCoeff() > 0.0)) {
    st.saturated = true;
    return out;
  }
  const VoxelGrid grid(box, box.sizes().maxCoeff() / double(spec.grid));
  const std::size_t nv = grid.size();
  std::vector<std::uint8_t> cls(nv, static_cast<std::uint8_t>(CellClass::kPartial));
  if (spec.prune) {
    std::fill(cls.begin(), cls.end(), static_cast<std::uint8_t>(CellClass::kEmpty));
    // Blocks write disjoint voxels, so the parallel descent is race-free and deterministic.
    struct None {};
    (void)descend<None>(
        field, grid, spec.target,
        [&](const IndexBox& b, CellClass c, std::vector<None>&) {
          for (std::int64_t k = b.lo[2]; k < b.hi[2]; ++k) {
            for (std::int64_t j = b.lo[1]; j < b.hi[1]; ++j) {
              for (std::int64_t i = b.lo[0]; i < b.hi[0]; ++i) {
                cls[grid.index(i, j, k)] = static_cast<std::uint8_t>(c);
              }
            }
          }
        },
        ctx);
    if (spec.cache != nullptr) {
      parallel::for_each(
          static_cast<std::size_t>(grid.n[2]), 1,
          [&](std::size_t kz) {
            const auto k = static_cast<std::int64_t>(kz);
            for (std::int64_t j = 0; j < grid.n[1]; ++j) {
              for (std::int64_t i = 0; i < grid.n[0]; ++i) {
                auto& c = cls[grid.index(i, j, k)];
                if (c == static_cast<std::uint8_t>(CellClass::kPartial) &&
                    !spec.cache->overlaps(grid.box(i, j, k, i + 1, j + 1, k + 1))) {
                  c = static_cast<std::uint8_t>(CellClass::kEmpty);
                }
              }
            }
          },
          ctx);
    }
  }
  std::vector<double> weights(nv);
  for (std::size_t v = 0; v < nv; ++v) weights[v] = cls[v] != 0 ? 1.0 : 0.0;
  SumTree tree(nv);
  tree.set_all(weights);
  weights.clear();
  weights.shrink_to_fit();

  const double reach = spec.kernel.reach();
  const double zero = spec.kernel.zero_radius();
  PointGrid near(box, zero);
  Rng rng(seed);
  const auto r = static_cast<std::int64_t>(std::ceil(reach / grid.h)) + 1;
  std::size_t since_report = 0;
  while (out.positions.size() < spec.count) {
    if (++since_report == kBlock) {
      since_report = 0;
      check_cancel(ctx);
      if (ctx != nullptr) ctx->report("sample", double(out.positions.size()) / double(spec.count));
    }
    const double total = tree.total();
    if (!(total > 0.0) || st.attempts >= spec.max_attempts) {
      st.saturated = true;
      break;
    }
    ++st.attempts;
    const std::size_t v = tree.find(rng.uniform() * total);
    const std::int64_t vi = static_cast<std::int64_t>(v) % grid.n[0];
    const std::int64_t vj = (static_cast<std::int64_t>(v) / grid.n[0]) % grid.n[1];
    const std::int64_t vk = static_cast<std::int64_t>(v) / (grid.n[0] * grid.n[1]);
    const Vec3 p =
        grid.origin + grid.h * Vec3(double(vi) + rng.uniform(), double(vj) + rng.uniform(),
                                    double(vk) + rng.uniform());
    if (near.has_near(p)) continue;
    if (cls[v] != static_cast<std::uint8_t>(CellClass::kFull)) {
      bool evaluate = true;
      if (spec.cache != nullptr) {
        const auto verdict = spec.cache->classify(p);
        if (verdict == FieldCache::Verdict::kReject) continue;
        evaluate = verdict == FieldCache::Verdict::kEvaluate;
      }
      if (evaluate && !spec.target.contains(field.value(p))) continue;
    }
    near.add(p);
    out.positions.push_back(p);
    if (reach <= 0.0) continue;
    // Deform the pdf: every voxel centre within the kernel's reach gets its factor.
    const std::int64_t ci = grid.coord(p.x(), 0), cj = grid.coord(p.y(), 1),
                       ck = grid.coord(p.z(), 2);
    for (std::int64_t k = std::max<std::int64_t>(0, ck - r); k <= std::min(grid.n[2] - 1, ck + r);
         ++k) {
      for (std::int64_t j = std::max<std::int64_t>(0, cj - r); j <= std::min(grid.n[1] - 1, cj + r);
           ++j) {
        for (std::int64_t i = std::max<std::int64_t>(0, ci - r);
             i <= std::min(grid.n[0] - 1, ci + r); ++i) {
          const std::size_t w = grid.index(i, j, k);
          const double old = tree.get(w);
          if (old == 0.0) continue;
          const Vec3 c =
              grid.origin + grid.h * Vec3(double(i) + 0.5, double(j) + 0.5, double(k) + 0.5);
          const double d = (c - p).norm();
          if (d >= reach) continue;
          const double f = spec.kernel.factor(d);
          if (f != 1.0) tree.set(w, old * f);
        }
      }
    }
    // Clustering kernels multiply weights without limit: rescale before they overflow.
    if (tree.total() > 1e200) {
      auto leaves = tree.leaves();
      for (auto& x : leaves) x *= 1e-200;
      leaves.resize(nv);
      tree.set_all(leaves);
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Option checks shared by the typed functions and generate_points (which maps them to lines).

struct OptionError {
  std::string option;
  std::string problem;
};
using Check = std::optional<OptionError>;

Check check_nonneg(const char* name, double v) {
  if (!std::isfinite(v) || v < 0.0) return OptionError{name, "must be finite and >= 0"};
  return std::nullopt;
}
Check check_grid(std::size_t g) {
  if (g < 2 || g > 512) return OptionError{"grid", "must be in 2..512"};
  return std::nullopt;
}

Check check(const PoissonOptions& o) {
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  return std::nullopt;
}
Check check(const LaneOptions& o) {
  if (auto e = check_grid(o.grid)) return e;
  try {
    o.kernel.validate();
  } catch (const InvalidArgument& e) {
    return OptionError{"kernel", e.what()};
  }
  return std::nullopt;
}
Check check(const FieldDensityOptions& o, double iso) {
  if (auto e = check_nonneg("exponent", o.exponent)) return e;
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  if (!(iso > 0.0)) {
    return OptionError{"exponent", "density (iso / f)^exponent needs a field with iso > 0 (iso = " +
                                       format_number(iso) + ")"};
  }
  return std::nullopt;
}
Check check(const BoundaryOptions& o) {
  if (auto e = check_nonneg("width", o.width)) return e;
  if (!std::isfinite(o.interior_density) || o.interior_density < 0.0 || o.interior_density > 1.0) {
    return OptionError{"interior_density", "must be in [0, 1]"};
  }
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  return std::nullopt;
}
Check check(const NearSurfaceOptions& o) {
  if (!std::isfinite(o.epsilon) || !(o.epsilon > 0.0)) {
    return OptionError{"epsilon", "must be finite and > 0"};
  }
  if (auto e = check_nonneg("min_distance", o.min_distance)) return e;
  if (auto e = check_nonneg("cache_cell", o.cache_cell)) return e;
  if (auto e = check_nonneg("cache_tolerance", o.cache_tolerance)) return e;
  if (auto e = check_grid(o.grid)) return e;
  if (o.method != NearSurfaceOptions::Method::kProject &&
      o.method != NearSurfaceOptions::Method::kReject) {
    return OptionError{"method", "must be project or reject"};
  }
  if (!std::isfinite(o.project_width) || o.project_width < 0.0 ||
      (o.project_width > 0.0 && o.project_width < o.epsilon)) {
    return OptionError{"project_width", "must be 0 (automatic) or finite and >= epsilon (" +
                                            format_number(o.epsilon) + "), got " +
                                            format_number(o.project_width)};
  }
  if (!o.box.isEmpty() && (!o.box.min().allFinite() || !o.box.max().allFinite())) {
    return OptionError{"box", "must be finite"};
  }
  return std::nullopt;
}

void throw_if(const Check& c, const std::string& fn) {
  if (c) throw InvalidArgument(fn + ": option " + c->option + " " + c->problem);
}

/// The box holding every point with f > iso - epsilon: bounds() grown until the field's bound
/// on the six slabs from the box out to a far box is <= iso - epsilon.
Aabb band_box(const Field& field, double epsilon) {
  const Aabb b = field.bounds();
  if (b.isEmpty()) return b;
  check_box(b, "sample_near_surface");
  const double diag = std::max(b.sizes().norm(), 1e-300);
  const double floor_value = field.iso() - epsilon;
  const Vec3 far = Vec3::Constant(1000.0 * diag);
  for (int step = 0; step <= 8; ++step) {
    Aabb g = b;
    const Vec3 grow = Vec3::Constant(step * diag / 8.0);
    g.min() -= grow;
    g.max() += grow;
    const Aabb big(g.min() - far, g.max() + far);
    bool clear = true;
    for (int a = 0; a < 3 && clear; ++a) {
      for (int side = 0; side < 2 && clear; ++side) {
        Aabb slab = big;
        if (side == 0) {
          slab.max()[a] = g.min()[a];
        } else {
          slab.min()[a] = g.max()[a];
        }
        clear = field.bound(slab).hi <= floor_value;
      }
    }
    if (clear) return g;
  }
  Aabb g = b;
  g.min() -= Vec3::Constant(diag);
  g.max() += Vec3::Constant(diag);
  return g;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// LaneKernel

LaneKernel LaneKernel::disk(double radius) {
  LaneKernel k;
  k.table = {{0.0, 0.0}, {radius, 0.0}, {radius, 1.0}};
  k.validate();
  return k;
}

LaneKernel LaneKernel::ring(double zero_radius, double ring_radius, double factor) {
  LaneKernel k;
  k.table = {{0.0, 0.0},
             {zero_radius, 0.0},
             {zero_radius, factor},
             {ring_radius, factor},
             {ring_radius, 1.0}};
  k.validate();
  return k;
}

LaneKernel LaneKernel::parse(const std::string& text) {
  std::string s = text;
  for (char& c : s) {
    if (c == ',') c = ' ';
  }
  std::istringstream in(s);
  std::string kind;
  in >> kind;
  std::vector<double> v;
  std::string word;
  while (in >> word) {
    double x = 0.0;
    const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), x);
    if (ec != std::errc() || ptr != word.data() + word.size() || !std::isfinite(x)) {
      throw InvalidArgument("kernel: '" + word + "' is not a finite number");
    }
    v.push_back(x);
  }
  const auto need = [&](std::size_t n) {
    if (v.size() != n) {
      throw InvalidArgument("kernel '" + kind + "' takes " + std::to_string(n) + " numbers, got " +
                            std::to_string(v.size()));
    }
  };
  if (kind == "none") {
    need(0);
    return {};
  }
  if (kind == "disk") {
    need(1);
    return disk(v[0]);
  }
  if (kind == "ring") {
    need(3);
    return ring(v[0], v[1], v[2]);
  }
  if (kind == "table") {
    if (v.empty() || v.size() % 2 != 0) {
      throw InvalidArgument("kernel 'table' takes (distance, factor) pairs");
    }
    LaneKernel k;
    for (std::size_t i = 0; i < v.size(); i += 2) k.table.emplace_back(v[i], v[i + 1]);
    k.validate();
    return k;
  }
  throw InvalidArgument("unknown kernel '" + kind + "' (valid: none, disk R, ring R0 R1 F, " +
                        "table d0 f0 d1 f1 ...)");
}

void LaneKernel::validate() const {
  for (std::size_t i = 0; i < table.size(); ++i) {
    const auto [d, f] = table[i];
    const std::string where = "kernel pair " + std::to_string(i) + " (" + format_number(d) + ", " +
                              format_number(f) + ")";
    if (!std::isfinite(d) || !std::isfinite(f)) throw InvalidArgument(where + ": not finite");
    if (f < 0.0) throw InvalidArgument(where + ": factor must be >= 0");
    if (i == 0 && d != 0.0) throw InvalidArgument(where + ": the first distance must be 0");
    if (i > 0 && d < table[i - 1].first) {
      throw InvalidArgument(where + ": distances must not decrease");
    }
  }
}

double LaneKernel::factor(double d) const {
  if (table.empty() || d >= table.back().first) return 1.0;
  // The last pair whose distance is <= d (at a step the later factor applies).
  const auto it = std::upper_bound(table.begin(), table.end(), d,
                                   [](double x, const auto& pr) { return x < pr.first; });
  const auto& a = *(it - 1);
  const auto& b = *it;
  if (b.first <= a.first) return b.second;
  return a.second + (b.second - a.second) * (d - a.first) / (b.first - a.first);
}

double LaneKernel::zero_radius() const {
  double z = 0.0;
  for (std::size_t i = 0; i + 1 < table.size(); ++i) {
    if (table[i].second == 0.0 && table[i + 1].second == 0.0) {
      z = table[i + 1].first;
    } else {
      break;
    }
  }
  return z;
}

double LaneKernel::reach() const { return table.empty() ? 0.0 : table.back().first; }

// ---------------------------------------------------------------------------------------------
// The samplers.

PointSet sample_uniform(const Field& field, const UniformOptions& options, std::uint64_t seed,
                        Context* ctx, SampleStats* stats) {
  StatsScope scope(&field, stats);
  const Aabb box = field.bounds();
  check_box(box, "sample_uniform");
  const Target target = inside_target(field);
  const Region region(field, box, target, kRegionInside, ctx);
  DartSpec spec;
  spec.target = target;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  PointSet out = run_dart(field, region, box, spec, seed, ctx, scope.stats);
  scope.stats.points = out.size();
  return out;
}

PointSet sample_stratified(const Field& field, const StratifiedOptions& options, std::uint64_t seed,
                           Context* ctx, SampleStats* stats) {
  StatsScope scope(&field, stats);
  PointSet out;
  const Aabb box = field.bounds();
  check_box(box, "sample_stratified");
  if (options.count == 0) return out;
  const Target target = inside_target(field);
  const Region region(field, box, target, kRegionInside, ctx);
  const double volume = estimate_volume(field, region, target, seed, ctx);
  if (!(volume > 0.0)) {
    scope.stats.saturated = true;
    return out;
  }
  double h = std::cbrt(volume / (1.1 * double(options.count)));
  for (int round = 0; round < 12; ++round) {
    check_cancel(ctx);
    const VoxelGrid grid(box, h);
    const auto rows = static_cast<std::size_t>(grid.n[1] * grid.n[2]);
    // One random sub-stream per grid row: independent of how rows are split among threads.
    std::vector<std::vector<Vec3>> inside(rows);
    const Rng base = Rng(seed).split(1000 + static_cast<std::uint64_t>(round));
    parallel::for_each(
        rows, 1,
        [&](std::size_t row) {
          Rng rng = base.split(row);
          const auto j = static_cast<std::int64_t>(row) % grid.n[1];
          const auto k = static_cast<std::int64_t>(row) / grid.n[1];
          std::vector<Vec3> pts(static_cast<std::size_t>(grid.n[0]));
          for (std::int64_t i = 0; i < grid.n[0]; ++i) {
            pts[static_cast<std::size_t>(i)] =
                grid.origin + grid.h * Vec3(double(i) + rng.uniform(), double(j) + rng.uniform(),
                                            double(k) + rng.uniform());
          }
          // Skip rows the field's bound shows to hold no inside point.
          if (classify(field.bound(grid.box(0, j, k, grid.n[0], j + 1, k + 1)), target) ==
              CellClass::kEmpty) {
            return;
          }
          std::vector<double> values(pts.size());
          field.evaluate(pts, values);
          for (std::size_t i = 0; i < pts.size(); ++i) {
            if (target.contains(values[i])) inside[row].push_back(pts[i]);
          }
        },
        ctx);
    std::vector<Vec3> all;
    for (auto& r : inside) all.insert(all.end(), r.begin(), r.end());
    scope.stats.attempts += grid.size();
    if (all.size() < options.count) {
      if (all.empty()) {
        h *= 0.5;
      } else {
        h *= 0.98 * std::cbrt(double(all.size()) / double(options.count));
      }
      continue;
    }
    // Keep exactly `count`: a seeded random subset (partial Fisher-Yates), in grid order.
    std::vector<std::uint32_t> idx(all.size());
    for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<std::uint32_t>(i);
    Rng pick = Rng(seed).split(0x7069636bULL);
    for (std::size_t i = 0; i < options.count; ++i) {
      const std::size_t j = i + pick.below(idx.size() - i);
      std::swap(idx[i], idx[j]);
    }
    idx.resize(options.count);
    std::sort(idx.begin(), idx.end());
    out.positions.reserve(options.count);
    for (const auto i : idx) out.positions.push_back(all[i]);
    scope.stats.points = out.size();
    return out;
  }
  scope.stats.saturated = true;
  scope.stats.points = 0;
  return out;
}

PointSet sample_poisson(const Field& field, const PoissonOptions& options, std::uint64_t seed,
                        Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_poisson");
  StatsScope scope(&field, stats);
  const Aabb box = field.bounds();
  check_box(box, "sample_poisson");
  const Target target = inside_target(field);
  const Region region(field, box, target, kRegionInside, ctx);
  double r = options.min_distance;
  if (r == 0.0 && options.count > 0) {
    r = 0.75 * std::cbrt(estimate_volume(field, region, target, seed, ctx) / double(options.count));
  }
  DartSpec spec;
  spec.target = target;
  spec.min_distance = r;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  spec.max_failures = options.max_failures;
  PointSet out = run_dart(field, region, box, spec, seed, ctx, scope.stats);
  scope.stats.points = out.size();
  return out;
}

PointSet sample_lane(const Field& field, const LaneOptions& options, std::uint64_t seed,
                     Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_lane");
  StatsScope scope(&field, stats);
  const Aabb box = field.bounds();
  check_box(box, "sample_lane");
  LaneSpec spec;
  spec.target = inside_target(field);
  spec.kernel = options.kernel;
  spec.grid = options.grid;
  spec.prune = options.prune_grid;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  PointSet out = run_lane(field, box, spec, seed, ctx, scope.stats);
  scope.stats.points = out.size();
  return out;
}

PointSet sample_field_density(const Field& field, const FieldDensityOptions& options,
                              std::uint64_t seed, Context* ctx, SampleStats* stats) {
  throw_if(check(options, field.iso()), "sample_field_density");
  StatsScope scope(&field, stats);
  const Aabb box = field.bounds();
  check_box(box, "sample_field_density");
  const Target target = inside_target(field);
  const Region region(field, box, target, kRegionInside, ctx);
  DartSpec spec;
  spec.target = target;
  const double iso = field.iso();
  const double exponent = options.exponent;
  spec.density = [iso, exponent](double f) { return std::pow(iso / f, exponent); };
  spec.min_distance = options.min_distance;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  PointSet out = run_dart(field, region, box, spec, seed, ctx, scope.stats);
  scope.stats.points = out.size();
  return out;
}

PointSet sample_boundary(const Field& field, const BoundaryOptions& options, std::uint64_t seed,
                         Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_boundary");
  StatsScope scope(&field, stats);
  const Aabb box = field.bounds();
  check_box(box, "sample_boundary");
  const double iso = field.iso();
  const double width =
      options.width > 0.0 ? options.width : (iso != 0.0 ? 0.2 * std::abs(iso) : 0.2);
  DartSpec spec;
  if (options.interior_density > 0.0) {
    spec.target = inside_target(field);
    const double edge = iso + width;
    const double interior = options.interior_density;
    spec.density = [edge, interior](double f) { return f < edge ? 1.0 : interior; };
  } else {
    spec.target = Target{iso, iso + width};  // the layer alone: prune the deep inside too
  }
  const Region region(field, box, spec.target, kRegionBand, ctx);
  spec.min_distance = options.min_distance;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  PointSet out = run_dart(field, region, box, spec, seed, ctx, scope.stats);
  scope.stats.points = out.size();
  return out;
}

PointSet sample_near_surface(const Field& field, const NearSurfaceOptions& options,
                             std::uint64_t seed, Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_near_surface");
  StatsScope scope(&field, stats);
  const Aabb box = options.box.isEmpty() ? band_box(field, options.epsilon) : options.box;
  check_box(box, "sample_near_surface");
  const Target target{field.iso() - options.epsilon, field.iso()};
  std::optional<FieldCache> cache;
  if (options.use_cache && !box.isEmpty() && box.sizes().maxCoeff() > 0.0) {
    const double cell =
        options.cache_cell > 0.0 ? options.cache_cell : box.sizes().maxCoeff() / 64.0;
    cache.emplace(field, box, cell, target, options.cache_tolerance, ctx);
  }
  PointSet out;
  const bool project = options.method == NearSurfaceOptions::Method::kProject &&
                       !options.use_cache && !options.use_lane_grid && options.prune;
  if (project) {
    if (options.count > 0) {
      ProjectSpec spec;
      spec.band = target;
      spec.max_step = box.isEmpty() ? 0.0 : box.sizes().maxCoeff() / kRegionBand;
      spec.width = options.project_width > 0.0
                       ? options.project_width
                       : automatic_project_width(field, box, target, spec.max_step, seed, ctx);
      spec.min_distance = options.min_distance;
      spec.count = options.count;
      spec.max_attempts = attempt_budget(options.max_attempts, options.count);
      const Region region(field, box, wide_band(target, spec.width), kRegionBand, ctx, kProjectTop);
      out = run_project(field, region, box, spec, seed, ctx, scope.stats);
    }
  } else if (options.use_lane_grid) {
    LaneSpec spec;
    spec.target = target;
    if (options.min_distance > 0.0) spec.kernel = LaneKernel::disk(options.min_distance);
    spec.grid = options.grid;
    spec.prune = options.prune;
    spec.count = options.count;
    spec.max_attempts = attempt_budget(options.max_attempts, options.count);
    spec.cache = cache ? &*cache : nullptr;
    out = run_lane(field, box, spec, seed, ctx, scope.stats);
  } else {
    const Region region(field, box, target, options.prune ? kRegionBand : 0, ctx);
    DartSpec spec;
    spec.target = target;
    spec.min_distance = options.min_distance;
    spec.count = options.count;
    spec.max_attempts = attempt_budget(options.max_attempts, options.count);
    spec.cache = cache ? &*cache : nullptr;
    out = run_dart(field, region, box, spec, seed, ctx, scope.stats);
  }
  scope.stats.points = out.size();
  return out;
}

PointSet sample_near_mesh(const TriMesh& mesh, const NearMeshOptions& options, std::uint64_t seed) {
  require(std::isfinite(options.min_offset) && std::isfinite(options.max_offset),
          "sample_near_mesh: min_offset and max_offset must be finite");
  require(options.min_offset <= options.max_offset,
          "sample_near_mesh: min_offset " + format_number(options.min_offset) + " > max_offset " +
              format_number(options.max_offset));
  const std::size_t nv = mesh.positions.size();
  const bool own_normals = mesh.normals.size() == nv && nv > 0;
  std::vector<double> cdf;
  cdf.reserve(mesh.triangles.size());
  std::vector<Vec3> normals(nv, Vec3::Zero());
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (const auto v : tri) {
      if (v >= nv) {
        throw InputError("", "triangle", t,
                         "vertex index " + std::to_string(v) + " out of range (" +
                             std::to_string(nv) + " vertices)");
      }
    }
    const Vec3 n = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
                       .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    const double area = 0.5 * n.norm();
    if (!std::isfinite(area)) throw InputError("", "triangle", t, "non-finite vertex");
    total += area;
    cdf.push_back(total);
    // |n| is twice the area: summing it weights face normals by area.
    for (const auto v : tri) normals[v] += n;
  }
  if (!(total > 0.0)) {
    throw InputError("", 0, "sample_near_mesh: the mesh has no triangle of positive area");
  }
  if (own_normals) normals = mesh.normals;
  PointSet out;
  out.positions.reserve(options.count);
  out.normals.reserve(options.count);
  Rng rng(seed);
  for (std::size_t i = 0; i < options.count; ++i) {
    // Inverse CDF: cdf[t - 1] <= u < cdf[t] (thesis eq. 6.1).
    const double u = rng.uniform() * total;
    auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
    if (it == cdf.end()) --it;
    const auto& tri = mesh.triangles[static_cast<std::size_t>(it - cdf.begin())];
    double s = rng.uniform(), t = rng.uniform();
    if (s + t > 1.0) {  // reflect into the triangle (Turk)
      s = 1.0 - s;
      t = 1.0 - t;
    }
    const Vec3 p = (1.0 - s - t) * mesh.positions[tri[0]] + s * mesh.positions[tri[1]] +
                   t * mesh.positions[tri[2]];
    Vec3 n = (1.0 - s - t) * normals[tri[0]] + s * normals[tri[1]] + t * normals[tri[2]];
    if (!(n.norm() > 0.0)) {
      n = (mesh.positions[tri[1]] - mesh.positions[tri[0]])
              .cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    }
    n.normalize();
    const double offset = rng.uniform(options.min_offset, options.max_offset);
    out.positions.push_back(p + offset * n);
    out.normals.push_back(n);
  }
  return out;
}

PointSet thin_points(const PointSet& points, const Field& secondary, double percent,
                     std::uint64_t seed) {
  require(std::isfinite(percent) && percent >= 0.0 && percent <= 100.0,
          "thin_points: percent " + format_number(percent) + " is not in [0, 100]");
  require(points.normals.empty() || points.normals.size() == points.positions.size(),
          "thin_points: normal count differs from point count");
  std::vector<double> values(points.positions.size());
  parallel::for_chunks(points.positions.size(), kEvalGrain, [&](std::size_t b, std::size_t e) {
    secondary.evaluate(std::span<const Vec3>(points.positions.data() + b, e - b),
                       std::span<double>(values.data() + b, e - b));
  });
  std::vector<std::uint32_t> inside;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] > secondary.iso()) inside.push_back(static_cast<std::uint32_t>(i));
  }
  const auto remove =
      static_cast<std::size_t>(std::floor(percent / 100.0 * double(inside.size()) + 0.5));
  Rng rng(seed);
  for (std::size_t i = 0; i < remove; ++i) {
    const std::size_t j = i + rng.below(inside.size() - i);
    std::swap(inside[i], inside[j]);
  }
  std::vector<std::uint8_t> removed(points.positions.size(), 0);
  for (std::size_t i = 0; i < remove; ++i) removed[inside[i]] = 1;
  PointSet out;
  for (std::size_t i = 0; i < points.positions.size(); ++i) {
    if (removed[i] != 0) continue;
    out.positions.push_back(points.positions[i]);
    if (!points.normals.empty()) out.normals.push_back(points.normals[i]);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Names, props keys and the one entry point.

std::vector<std::string> distribution_names() {
  return {"uniform", "stratified", "poisson", "lane", "field", "boundary", "near_surface"};
}

std::vector<std::string> distribution_keys(const std::string& name) {
  if (name == "uniform") return {"count", "max_attempts"};
  if (name == "stratified") return {"count"};
  if (name == "poisson") return {"count", "min_distance", "max_failures", "max_attempts"};
  if (name == "lane") return {"count", "kernel", "grid", "prune_grid", "max_attempts"};
  if (name == "field") return {"count", "exponent", "min_distance", "max_attempts"};
  if (name == "boundary") {
    return {"count", "width", "interior_density", "min_distance", "max_attempts"};
  }
  if (name == "near_surface") {
    return {"count",         "epsilon", "min_distance", "method",
            "project_width", "cache",   "cache_cell",   "cache_tolerance",
            "lane_grid",     "grid",    "prune",        "max_attempts"};
  }
  const std::string hint = closest_key(name, distribution_names());
  std::string msg = "unknown distribution '" + name + "'";
  if (!hint.empty()) msg += " (did you mean '" + hint + "'?)";
  msg += "; valid:";
  for (const auto& n : distribution_names()) msg += " " + n;
  throw InvalidArgument(msg);
}

PointSet generate_points(const Field& field, const std::string& name, const Props& props,
                         std::uint64_t seed, std::size_t count_override, Context* ctx,
                         SampleStats* stats) {
  const PropsReader in(props, distribution_keys(name), "distribution '" + name + "'");
  const std::size_t count = count_override > 0 ? count_override : in.count("count", 1000);
  // Maps an option check to the props line that set it (option names equal the keys, except
  // the two flags).
  const auto raise = [&](const Check& c) {
    if (!c) return;
    std::string key = c->option;
    if (key == "use_cache") key = "cache";
    if (key == "use_lane_grid") key = "lane_grid";
    in.fail(key, c->problem);
  };
  if (name == "uniform") {
    UniformOptions o;
    o.count = count;
    o.max_attempts = in.count("max_attempts", 0);
    return sample_uniform(field, o, seed, ctx, stats);
  }
  if (name == "stratified") {
    StratifiedOptions o;
    o.count = count;
    return sample_stratified(field, o, seed, ctx, stats);
  }
  if (name == "poisson") {
    PoissonOptions o;
    o.count = count;
    o.min_distance = in.number("min_distance", 0.0);
    o.max_failures = in.count("max_failures", o.max_failures);
    o.max_attempts = in.count("max_attempts", 0);
    raise(check(o));
    return sample_poisson(field, o, seed, ctx, stats);
  }
  if (name == "lane") {
    LaneOptions o;
    o.count = count;
    try {
      o.kernel = LaneKernel::parse(in.text("kernel", "none"));
    } catch (const InvalidArgument& e) {
      in.fail("kernel", e.what());
    }
    o.grid = in.count("grid", o.grid);
    o.prune_grid = in.flag("prune_grid", o.prune_grid);
    o.max_attempts = in.count("max_attempts", 0);
    raise(check(o));
    return sample_lane(field, o, seed, ctx, stats);
  }
  if (name == "field") {
    FieldDensityOptions o;
    o.count = count;
    o.exponent = in.number("exponent", o.exponent);
    o.min_distance = in.number("min_distance", 0.0);
    o.max_attempts = in.count("max_attempts", 0);
    raise(check(o, field.iso()));
    return sample_field_density(field, o, seed, ctx, stats);
  }
  if (name == "boundary") {
    BoundaryOptions o;
    o.count = count;
    o.width = in.number("width", 0.0);
    o.interior_density = in.number("interior_density", 0.0);
    o.min_distance = in.number("min_distance", 0.0);
    o.max_attempts = in.count("max_attempts", 0);
    raise(check(o));
    return sample_boundary(field, o, seed, ctx, stats);
  }
  // near_surface (distribution_keys rejected every other name)
  NearSurfaceOptions o;
  o.count = count;
  o.epsilon = in.number("epsilon", o.epsilon);
  o.min_distance = in.number("min_distance", 0.0);
  const std::string method = in.text("method", "project");
  if (method == "project") {
    o.method = NearSurfaceOptions::Method::kProject;
  } else if (method == "reject") {
    o.method = NearSurfaceOptions::Method::kReject;
  } else {
    in.fail("method", "must be project or reject");
  }
  o.project_width = in.number("project_width", 0.0);
  o.use_cache = in.flag("cache", false);
  o.cache_cell = in.number("cache_cell", 0.0);
  o.cache_tolerance = in.number("cache_tolerance", 0.0);
  o.use_lane_grid = in.flag("lane_grid", false);
  o.grid = in.count("grid", o.grid);
  o.prune = in.flag("prune", o.prune);
  o.max_attempts = in.count("max_attempts", 0);
  raise(check(o));
  return sample_near_surface(field, o, seed, ctx, stats);
}

}  // namespace ramiform
