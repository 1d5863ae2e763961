// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/skeleton_field.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <string>
#include <unordered_map>

#include "field/bvh.h"
#include "field/cutoff.h"
#include "field/skeleton_field_simd.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using detail::cauchy_segment_reach;
using detail::fade_of;
using detail::PrimitiveMode;
using tol::kSupportMargin;
// Relative widening of bound() results: the bound is computed by scalar code and the values by
// vector code, which may round differently in the last bits.
constexpr double kBoundSlack = 1e-12;

// One primitive as built, before it goes into the SoA table.
struct Primitive {
  Vec3 a, b;
  double ra = 1, rb = 1;  // surface radii at a and b
  double weight = 1;      // user weight (>= 0)
};

PrimitiveMode mode_of(const SkeletonFieldOptions& o) {
  if (o.surface == SurfaceKind::kConvolution) return PrimitiveMode::kCauchySegment;
  switch (o.kernel.kind) {
    case KernelKind::kWyvill: return PrimitiveMode::kWyvill;
    case KernelKind::kBlinn: return PrimitiveMode::kBlinn;
    case KernelKind::kMetaball: return PrimitiveMode::kMetaball;
    case KernelKind::kInversePower: return PrimitiveMode::kInversePower;
    case KernelKind::kCauchy: break;
  }
  return PrimitiveMode::kCauchyPoint;
}

// Distance from any point of `box` to the segment [a, b]: a lower bound, and the exact maximum.
struct DistanceRange {
  double min = 0, max = 0;
};
// The segment [a, a + ab], its box and |ab|^2: what lower_distance() needs of it.
struct SegmentBounds {
  Vec3 a, ab;
  Aabb box;
  double l2 = 0;
};

SegmentBounds segment_bounds(const Vec3& a, const Vec3& b) {
  SegmentBounds s{a, b - a, Aabb(a), 0.0};
  s.box.extend(b);
  s.l2 = s.ab.squaredNorm();
  return s;
}

// The distance from the box's centre to the segment less the box's half diagonal: a lower
// bound of the distance from any point of the box to it (the other is the box-to-box distance).
double centre_lower_distance(const Aabb& box, const SegmentBounds& s) {
  const Vec3 c = box.center();
  const double t = s.l2 > 0 ? std::clamp((c - s.a).dot(s.ab) / s.l2, 0.0, 1.0) : 0.0;
  const double dc = (c - (s.a + t * s.ab)).norm();
  return dc - 0.5 * box.diagonal().norm();
}

// A lower bound of the distance from any point of the box to the segment: the larger of the
// box-to-box distance and centre_lower_distance().
double lower_distance(const Aabb& box, const SegmentBounds& s) {
  return std::max({0.0, std::sqrt(squared_distance(box, s.box)), centre_lower_distance(box, s)});
}

double lower_distance(const Aabb& box, const Vec3& a, const Vec3& b) {
  return lower_distance(box, segment_bounds(a, b));
}

DistanceRange box_segment_distance(const Aabb& box, const Vec3& a, const Vec3& b) {
  auto dist = [&](const Vec3& p) {
    const Vec3 ab = b - a;
    const double l2 = ab.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
    return (p - (a + t * ab)).norm();
  };
  DistanceRange r;
  r.min = lower_distance(box, a, b);
  // Distance to a convex set is convex, so its maximum over the box is at a corner.
  for (int c = 0; c < 8; ++c) r.max = std::max(r.max, dist(box.corner(static_cast<Aabb::CornerType>(c))));
  return r;
}

// Upper bound of the Cauchy segment integral at distance >= d from a segment of length len.
double cauchy_segment_max(double s, double len, double d) {
  const double q = 1 + s * s * d * d;
  return std::min(len / (q * q), std::numbers::pi / (2 * s * q * std::sqrt(q)));
}

class SkeletonField final : public Field {
 public:
  SkeletonField(const SkeletonFieldOptions& o, const std::vector<Primitive>& prims)
      : Field(o.iso), kernel_(o.kernel), surface_(o.surface), prune_(o.prune) {
    mode_.mode = mode_of(o);
    mode_.shape = o.kernel.shape();
    mode_.fades = mode_.mode != PrimitiveMode::kWyvill && mode_.mode != PrimitiveMode::kMetaball;
    for (const auto& p : prims) add(p);
    finish();
  }

  // A restriction of `source` to the primitives `ids` (ascending).
  SkeletonField(const SkeletonField& source, const std::vector<std::uint32_t>& ids)
      : Field(source.iso(), source),
        kernel_(source.kernel_),
        surface_(source.surface_),
        prune_(source.prune_),
        mode_(source.mode_) {
    for (const std::uint32_t i : ids) copy_from(source, i);
    finish();
  }

  Interval bound(const Aabb& box) const override {
    thread_local std::vector<std::uint32_t> ids;
    ids.clear();
    bvh_.query(box, ids);
    std::sort(ids.begin(), ids.end());
    // Cheap first pass: upper ends from the nearest distance only. When they already prove the
    // box outside (f <= iso everywhere), [0, hi] is a valid and sufficient answer.
    // The weights and kernel values are non-negative, so the sum only grows: once it passes iso
    // the box cannot be proven outside and the rest of the pass is skipped.
    double quick_hi = 0;
    bool passed = false;
    for (const std::uint32_t i : ids) {
      quick_hi += primitive_upper(i, box);
      if (quick_hi > iso()) {
        passed = true;
        break;
      }
    }
    quick_hi += kBoundSlack * quick_hi;
    if (!passed && quick_hi <= iso()) return {0.0, quick_hi};
    double lo = 0, hi = 0;
    for (const std::uint32_t i : ids) {
      const auto [plo, phi] = primitive_bound(i, box);
      lo += plo;
      hi += phi;
    }
    return {lo - kBoundSlack * lo, hi + kBoundSlack * hi};
  }

  Aabb bounds() const override { return surface_box_; }

  FieldPtr restrict(const Aabb& box) const override {
    std::vector<std::uint32_t> ids;
    bvh_.query(box, ids);
    if (ids.size() == table_.size()) return shared_from_this();
    std::sort(ids.begin(), ids.end());
    return std::make_shared<SkeletonField>(*this, ids);
  }

  std::string describe() const override {
    std::string s = std::to_string(table_.size()) + " primitives, ";
    s += surface_ == SurfaceKind::kConvolution ? "convolution" : "distance";
    return s + " surface, " + kernel_name(kernel_.kind) + " kernel, iso " + std::to_string(iso());
  }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    const std::size_t n = points.size();
    const bool with_gradient = !gradients.empty();
    // Spatially coherent chunks: sort points along a Morton curve when the batch spans several
    // chunks, so each chunk's box (and so its candidate primitives) stays small. A batch that
    // is small but scattered (a line tracer's few points spread over a tree) is sorted too and
    // cut wherever a chunk's box would grow past split_diagonal_, so that each chunk meets the
    // supports near its own points instead of most of the field's. The values do not depend on
    // the chunks: a primitive out of reach of a point adds exactly +0 to it.
    std::vector<std::uint32_t> order;
    if (n > detail::kChunk) {
      order = morton_order(points, ctx);
    } else if (n > 1 && prune_) {
      Aabb all;
      for (const Vec3& p : points) all.extend(p);
      if (all.diagonal().norm() > split_diagonal_) order = morton_order(points, ctx);
    }
    const auto point_at = [&](std::size_t k) -> const Vec3& {
      return points[order.empty() ? k : order[k]];
    };
    std::vector<std::size_t> starts;  // chunk c is [starts[c], starts[c + 1])
    if (order.empty()) {
      for (std::size_t b = 0; b < n; b += detail::kChunk) starts.push_back(b);
    } else {
      // (Squared lengths: the chunks only need to stay small, and no value depends on them.)
      const double split2 = split_diagonal_ * split_diagonal_;
      Aabb box;
      for (std::size_t k = 0; k < n; ++k) {
        Aabb grown = box;
        grown.extend(point_at(k));
        if (k == 0 || k - starts.back() == detail::kChunk ||
            grown.diagonal().squaredNorm() > split2) {
          starts.push_back(k);
          box = Aabb(point_at(k), point_at(k));
        } else {
          box = grown;
        }
      }
    }
    const std::size_t chunks = starts.size();
    starts.push_back(n);
    // Groups of up to kGroupChunks consecutive chunks of more than kCachedChunk points (the
    // Morton order keeps them near each other) share one query of the BVH for the group's box;
    // each chunk then keeps the group's candidates that may reach its own box. A candidate list
    // is a superset of what reaches its points either way, so the values are the same; one
    // query per chunk was a tenth of a dense tree's polygonization.
    std::vector<std::size_t> group_starts;  // group g is chunks [group_starts[g], [g + 1])
    std::vector<Aabb> chunk_boxes;
    if (prune_ && chunks >= 2) {
      chunk_boxes.resize(chunks);
      parallel::for_each(
          chunks, 64,
          [&](std::size_t c) {
            for (std::size_t k = starts[c]; k < starts[c + 1]; ++k) {
              chunk_boxes[c].extend(point_at(k));
            }
          },
          ctx);
      Aabb group_box;
      for (std::size_t c = 0; c < chunks; ++c) {
        Aabb grown = group_box;
        grown.extend(chunk_boxes[c]);
        const bool joins = c > 0 && c - group_starts.back() < kGroupChunks &&
                           starts[c + 1] - starts[c] > kCachedChunk &&
                           starts[c] - starts[c - 1] > kCachedChunk &&
                           grown.diagonal().squaredNorm() <= 4 * split_diagonal_ * split_diagonal_;
        if (joins) {
          group_box = grown;
        } else {
          group_starts.push_back(c);
          group_box = chunk_boxes[c];
        }
      }
    } else {
      for (std::size_t c = 0; c < chunks; ++c) group_starts.push_back(c);
    }
    const std::size_t groups = group_starts.size();
    group_starts.push_back(chunks);
    auto run_chunk = [&](std::size_t c, const std::vector<std::uint32_t>* group_ids) {
      detail::Chunk chunk;
      thread_local std::vector<std::uint32_t> ids;  // every primitive, when not pruning
      thread_local std::vector<std::uint32_t> kept;  // the group's candidates for this chunk
      const std::size_t begin = starts[c];
      const std::size_t count = starts[c + 1] - begin;
      auto point_index = [&](std::size_t k) {
        return order.empty() ? begin + k : static_cast<std::size_t>(order[begin + k]);
      };
      // The chunk's box: made above when the chunks were grouped, else here.
      const bool boxed = !chunk_boxes.empty();
      Aabb box = boxed ? chunk_boxes[c] : Aabb();
      for (std::size_t k = 0; k < count; ++k) {
        const Vec3& p = points[point_index(k)];
        chunk.px[k] = p.x();
        chunk.py[k] = p.y();
        chunk.pz[k] = p.z();
        if (!boxed) box.extend(p);
      }
      chunk.padded = (count + 15) / 16 * 16;
      chunk.count = count;
      for (std::size_t k = count; k < chunk.padded; ++k) {
        chunk.px[k] = chunk.px[0];
        chunk.py[k] = chunk.py[0];
        chunk.pz[k] = chunk.pz[0];
      }
      std::fill_n(chunk.value, chunk.padded, 0.0);
      if (with_gradient) {
        std::fill_n(chunk.gx, chunk.padded, 0.0);
        std::fill_n(chunk.gy, chunk.padded, 0.0);
        std::fill_n(chunk.gz, chunk.padded, 0.0);
      }
      const std::vector<std::uint32_t>* use = &ids;
      if (group_ids != nullptr) {
        kept.clear();
        for (const std::uint32_t i : *group_ids) {
          if (!out_of_reach(i, box)) kept.push_back(i);
        }
        use = &kept;
      } else if (prune_ && !box.isEmpty() && box.min().allFinite() && box.max().allFinite()) {
        use = &candidates(box, count);
      } else {
        ids.clear();
        for (std::uint32_t i = 0; i < table_.size(); ++i) ids.push_back(i);
      }
      detail::accumulate(table_, mode_, use->data(), use->size(), chunk, with_gradient);
      for (std::size_t k = 0; k < count; ++k) {
        const std::size_t i = point_index(k);
        values[i] = chunk.value[k];
        if (with_gradient) gradients[i] = Vec3(chunk.gx[k], chunk.gy[k], chunk.gz[k]);
      }
    };
    auto run_group = [&](std::size_t g) {
      const std::size_t first = group_starts[g], last = group_starts[g + 1];
      const Aabb box = last - first >= 2 ? std::accumulate(chunk_boxes.begin() + first + 1,
                                                           chunk_boxes.begin() + last,
                                                           chunk_boxes[first], extended)
                                         : Aabb();
      if (last - first < 2 || !box.min().allFinite() || !box.max().allFinite()) {
        for (std::size_t c = first; c < last; ++c) run_chunk(c, nullptr);
        return;
      }
      thread_local std::vector<std::uint32_t> group_ids;
      collect(box, group_ids);
      for (std::size_t c = first; c < last; ++c) run_chunk(c, &group_ids);
    };
    // A small batch (a line tracer's few scattered points, cut into chunks of one to three)
    // runs on the calling thread: handing its few microseconds of chunks to a second thread
    // cost more than it saved (the studio's quick line drawing of its tree, two threads, 8,000
    // such batches per camera). The chunks, and so the values, are the same either way.
    if (groups >= 2 && n > kSerialBatch) {
      parallel::for_each(groups, 1, run_group, ctx);
    } else {
      for (std::size_t g = 0; g < groups; ++g) run_group(g);
    }
  }

 private:
  // Chunks of at most this many points take their candidates from their thread's cache
  // (candidates()).
  static constexpr std::size_t kCachedChunk = 16;
  // Batches of at most this many points are evaluated on the calling thread (do_evaluate).
  static constexpr std::size_t kSerialBatch = 32;
  // Most lists a thread's cache holds before it starts afresh.
  static constexpr std::size_t kCachedLists = std::size_t{1} << 14;

  // Chunks of more than kCachedChunk points share a BVH query in groups of at most this many.
  static constexpr std::size_t kGroupChunks = 4;

  static Aabb extended(Aabb a, const Aabb& b) {
    a.extend(b);
    return a;
  }

  // Whether primitive i's support provably misses `box`: lower_distance() beyond the reach
  // grown by kSupportMargin, from the segment data kept for it (reach_bounds_), the box-to-box
  // distance compared in squares first. It may differ from comparing lower_distance() itself
  // only by rounding, far inside kSupportMargin, and a primitive out of reach adds exactly +0:
  // the candidates it keeps give the same values. It was a tenth of a dense tree's field time
  // with the BVH query.
  bool out_of_reach(std::uint32_t i, const Aabb& box) const {
    const SegmentBounds& seg = reach_bounds_[i];
    const double limit = reach_[i] * (1 + kSupportMargin);
    return squared_distance(box, seg.box) > limit * limit ||
           centre_lower_distance(box, seg) > limit;
  }

  // Into `ids`, ascending: the primitives of the BVH's support boxes that meet `box`, less those
  // whose segment is provably out of reach (the support boxes are loose around slanted
  // segments).
  void collect(const Aabb& box, std::vector<std::uint32_t>& ids) const {
    ids.clear();
    bvh_.query(box, ids);
    std::erase_if(ids, [&](std::uint32_t i) { return out_of_reach(i, box); });
    std::sort(ids.begin(), ids.end());
  }

  // The primitives whose support may reach `box`, ascending: those of the BVH's support boxes
  // that meet it, less those whose segment is provably out of reach (lower_distance). A superset
  // is as good: a primitive out of reach of a point adds exactly +0 to it, so the sums, and the
  // values, are bit for bit the same. Small chunks (a line tracer's or a root finder's few
  // points, each trace's a little further on in the next call) are looked up in a per-thread
  // cache of lists made for the cells of a grid of split_diagonal_ / 16, each grown by half a
  // cell on every side: a small chunk whose box lies in its centre's grown cell uses that
  // cell's list, made on first use.
  const std::vector<std::uint32_t>& candidates(const Aabb& box, std::size_t count) const {
    struct Cache {
      std::uint64_t field = 0;  // serial_ of the field the lists are for (0: none)
      std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> lists;
    };
    thread_local Cache cache;
    thread_local std::vector<std::uint32_t> fresh;
    if (count <= kCachedChunk && std::isfinite(split_diagonal_) && split_diagonal_ > 0) {
      const double cell = split_diagonal_ / 16;
      const Vec3 at = box.center() / cell;
      constexpr double kRange = double{1 << 20};
      if ((at.array().abs() < kRange).all()) {
        std::uint64_t key = 0;
        Aabb grown;
        for (int k = 0; k < 3; ++k) {
          const double lo = std::floor(at[k]);
          grown.min()[k] = (lo - 0.5) * cell;
          grown.max()[k] = (lo + 1.5) * cell;
          key = key << 21 | static_cast<std::uint64_t>(static_cast<std::int64_t>(lo) + (1 << 20));
        }
        if (grown.contains(box)) {
          if (cache.field != serial_ || cache.lists.size() >= kCachedLists) {
            cache.lists.clear();
            cache.field = serial_;
          }
          const auto [it, is_new] = cache.lists.try_emplace(key);
          if (is_new) {
            try {
              collect(grown, it->second);
            } catch (...) {
              cache.lists.erase(it);
              throw;
            }
          }
          return it->second;
        }
      }
    }
    collect(box, fresh);
    return fresh;
  }

  static std::uint64_t next_serial() {
    static std::atomic<std::uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
  }

  // Returns an order of the points along a Morton curve, or an empty vector when the points
  // already arrive in spatially coherent chunks (their boxes on average under 2 % of the
  // batch's diagonal). A looser test (25 %) let the polygonizer's root-finding batches through
  // unsorted: in a dense crown a chunk box that size meets thousands of Cauchy supports
  // (20,000-segment tree: 20 % more time placing vertices). Parallel on ctx's threads; the
  // order (by code, ties by index) does not depend on them. It was sequential, about 7 % of the
  // benchmark tree's polygonization on two threads.
  // Batches of at most this many points are Morton-sorted by comparison (morton_order()).
  static constexpr std::size_t kSmallSort = 1024;

  static std::vector<std::uint32_t> morton_order(std::span<const Vec3> points, const Context* ctx) {
    const std::size_t n = points.size();
    const std::size_t chunk_count = (n + detail::kChunk - 1) / detail::kChunk;
    // The chunks' boxes in parallel, summed in chunk order.
    std::vector<Aabb> chunk_boxes(chunk_count);
    parallel::for_each(
        chunk_count, 256,
        [&](std::size_t c) {
          const std::size_t begin = c * detail::kChunk;
          const std::size_t end = std::min(n, begin + detail::kChunk);
          Aabb chunk_box;
          for (std::size_t i = begin; i < end; ++i) {
            if (points[i].allFinite()) chunk_box.extend(points[i]);
          }
          chunk_boxes[c] = chunk_box;
        },
        ctx);
    Aabb box;
    double chunk_diagonals = 0;
    for (const Aabb& chunk_box : chunk_boxes) {
      if (!chunk_box.isEmpty()) chunk_diagonals += chunk_box.diagonal().norm();
      box.extend(chunk_box);
    }
    if (box.isEmpty()) return {};
    const double diagonal = box.diagonal().norm();
    if (chunk_diagonals <= 0.02 * diagonal * static_cast<double>(chunk_count)) return {};
    const Vec3 lo = box.min();
    const double extent = std::max(box.diagonal().maxCoeff(), 1e-300);
    auto spread = [](std::uint32_t v) {  // 10 bits -> every third bit of 30
      v &= 0x3ffU;
      v = (v | v << 16U) & 0x030000ffU;
      v = (v | v << 8U) & 0x0300f00fU;
      v = (v | v << 4U) & 0x030c30c3U;
      v = (v | v << 2U) & 0x09249249U;
      return v;
    };
    // Keys: the 30-bit code above the point's index, so that a key carries its index through the
    // sort (no gathers) and ties keep input order.
    // (Left uninitialized: every element is written before it is read, and zeroing 16 bytes a
    // point on one thread cost as much as computing the codes.)
    std::unique_ptr<std::uint64_t[]> key(new std::uint64_t[n]), other(new std::uint64_t[n]);
    parallel::for_each(
        n, 4096,
        [&](std::size_t i) {
          std::uint32_t c = 0;
          for (int k = 0; k < 3; ++k) {
            const double t = (points[i][k] - lo[k]) / extent;
            const double cl = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
            c |= spread(static_cast<std::uint32_t>(cl * 1023.0)) << k;
          }
          key[i] = static_cast<std::uint64_t>(c) << 32U | i;
        },
        ctx);
    // A small batch (a line tracer's scattered points, many calls a drawing) is sorted directly:
    // the keys are unique, so this is the radix sort's order, without its 1,024-digit passes.
    if (n <= kSmallSort) {
      std::sort(key.get(), key.get() + n);
      std::vector<std::uint32_t> order(n);
      for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(key[i]);
      return order;
    }
    // Stable LSD radix sort on the codes, three passes of 10 bits, each over fixed blocks of the
    // keys: the blocks count their digits in parallel, and each scatters its keys in parallel
    // behind those of the blocks before it (the result does not depend on the thread count).
    constexpr std::size_t kBlock = 1 << 15;
    constexpr std::size_t kDigits = 1 << 10;
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<std::size_t> offset(blocks * kDigits);
    for (unsigned shift = 32; shift < 62; shift += 10) {
      auto digit = [shift](std::uint64_t k) { return (k >> shift) & (kDigits - 1); };
      parallel::for_each(
          blocks, 1,
          [&](std::size_t b) {
            std::size_t* count = offset.data() + b * kDigits;
            std::fill_n(count, kDigits, 0);
            for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
              ++count[digit(key[i])];
            }
          },
          ctx);
      std::size_t sum = 0;
      for (std::size_t d = 0; d < kDigits; ++d) {
        for (std::size_t b = 0; b < blocks; ++b) {
          const std::size_t c = offset[b * kDigits + d];
          offset[b * kDigits + d] = sum;
          sum += c;
        }
      }
      parallel::for_each(
          blocks, 1,
          [&](std::size_t b) {
            std::size_t* at = offset.data() + b * kDigits;
            for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
              other[at[digit(key[i])]++] = key[i];
            }
          },
          ctx);
      key.swap(other);
    }
    std::vector<std::uint32_t> order(n);
    parallel::for_each(
        n, 4096, [&](std::size_t i) { order[i] = static_cast<std::uint32_t>(key[i]); }, ctx);
    return order;
  }

  void add(const Primitive& p) {
    if (p.weight == 0) return;
    const Vec3 d = p.b - p.a;
    const double len = d.norm();
    const Vec3 u = len > 0 ? Vec3(d / len) : Vec3::UnitX();
    const double c = kernel_.shape();
    double r0 = 0, dr = 0, weight = p.weight, s = 0, inv_cut = 1, reach = 0;
    const double floor_value = tol::kKernelCutoff * iso();
    if (mode_.mode == PrimitiveMode::kCauchySegment && len > 0) {
      const double r = 0.5 * (p.ra + p.rb);
      s = c / r;
      weight *= 2 * c * iso() * pm::pow(1 + c * c, 1.5) / (std::numbers::pi * r);
      reach = cauchy_segment_reach(s, len, weight, floor_value);
      if (reach <= 0) return;
      inv_cut = 1 / (reach * reach);
    } else if (mode_.mode == PrimitiveMode::kCauchySegment || mode_.mode == PrimitiveMode::kCauchyPoint) {
      // Point convolution primitive: the kernel itself, R = 1/s, weight so that f(r) = iso.
      const double r = 0.5 * (p.ra + p.rb);
      s = c / r;
      r0 = 1 / s;
      weight *= iso() * (1 + c * c) * (1 + c * c);
      const double xc = Kernel{KernelKind::kCauchy, c}.support(iso() / weight);
      if (xc <= 0) return;
      inv_cut = 1 / (xc * xc);
      reach = xc * r0;
    } else {
      const double x_iso = kernel_.x_at(iso());
      r0 = p.ra / x_iso;
      dr = len > 0 ? (p.rb - p.ra) / x_iso / len : 0;
      const double xc = kernel_.support(iso() / weight);
      if (xc <= 0) return;
      inv_cut = 1 / (xc * xc);
      reach = xc * std::max(p.ra, p.rb) / x_iso;
    }
    table_.ax.push_back(p.a.x());
    table_.ay.push_back(p.a.y());
    table_.az.push_back(p.a.z());
    table_.ux.push_back(u.x());
    table_.uy.push_back(u.y());
    table_.uz.push_back(u.z());
    table_.len.push_back(len);
    table_.r0.push_back(r0);
    table_.dr.push_back(dr);
    table_.weight.push_back(weight);
    table_.s.push_back(s);
    table_.inv_cut.push_back(inv_cut);
    reach_.push_back(reach);
  }

  void copy_from(const SkeletonField& o, std::uint32_t i) {
    const auto& t = o.table_;
    table_.ax.push_back(t.ax[i]);
    table_.ay.push_back(t.ay[i]);
    table_.az.push_back(t.az[i]);
    table_.ux.push_back(t.ux[i]);
    table_.uy.push_back(t.uy[i]);
    table_.uz.push_back(t.uz[i]);
    table_.len.push_back(t.len[i]);
    table_.r0.push_back(t.r0[i]);
    table_.dr.push_back(t.dr[i]);
    table_.weight.push_back(t.weight[i]);
    table_.s.push_back(t.s[i]);
    table_.inv_cut.push_back(t.inv_cut[i]);
    reach_.push_back(o.reach_[i]);
  }

  Vec3 point_a(std::uint32_t i) const { return {table_.ax[i], table_.ay[i], table_.az[i]}; }
  Vec3 point_b(std::uint32_t i) const {
    return point_a(i) + table_.len[i] * Vec3(table_.ux[i], table_.uy[i], table_.uz[i]);
  }

  Aabb segment_box(std::uint32_t i, double grow) const {
    Aabb box;
    box.extend(point_a(i));
    box.extend(point_b(i));
    box.min().array() -= grow;
    box.max().array() += grow;
    return box;
  }

  // Builds the BVH over the supports and the conservative surface box.
  void finish() {
    reach_bounds_.resize(table_.size());
    for (std::uint32_t i = 0; i < table_.size(); ++i) {
      reach_bounds_[i] = segment_bounds(point_a(i), point_b(i));
    }
    std::vector<Aabb> supports(table_.size());
    for (std::uint32_t i = 0; i < table_.size(); ++i) {
      supports[i] = segment_box(i, reach_[i] * (1 + kSupportMargin));
    }
    bvh_ = detail::BoxBvh(supports);
    // Chunks of a scattered batch are cut at twice the median support radius (do_evaluate).
    if (!reach_.empty()) {
      std::vector<double> r = reach_;
      std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2), r.end());
      split_diagonal_ = 2 * r[r.size() / 2];
    }
    // Surface box: a point outside every primitive's "reach at level iso / K_i", where K_i is
    // the number of supports overlapping primitive i's support, gets fewer than K_i
    // contributions each below iso / K_i, so f < iso there.
    // In parallel (a query of the BVH per primitive: 2 % of the studio's 4,578-node tree's
    // meshing, all of it on one thread); the box is a union, the same in any order.
    surface_box_ = parallel::reduce(
        table_.size(), 256, Aabb(),
        [&](std::size_t begin, std::size_t end) {
          Aabb box;
          std::vector<std::uint32_t> ids;
          for (std::size_t k = begin; k < end; ++k) {
            const auto i = static_cast<std::uint32_t>(k);
            ids.clear();
            bvh_.query(supports[i], ids);
            const double level = iso() / static_cast<double>(std::max<std::size_t>(ids.size(), 1));
            const double reach = reach_at(i, level);
            if (reach > 0) box.extend(segment_box(i, reach * (1 + kSupportMargin)));
          }
          return box;
        },
        [](Aabb a, const Aabb& b) {
          a.extend(b);
          return a;
        });
  }

  // Distance from primitive i beyond which its contribution stays below `level`.
  double reach_at(std::uint32_t i, double level) const {
    const double w = table_.weight[i];
    if (mode_.mode == PrimitiveMode::kCauchySegment && table_.len[i] > 0) {
      return std::min(reach_[i], cauchy_segment_reach(table_.s[i], table_.len[i], w, level));
    }
    const double rmax = std::max(table_.r0[i], table_.r0[i] + table_.dr[i] * table_.len[i]);
    const Kernel k = distance_kernel();
    const double target = level / w;
    if (target >= k.value(0)) return 0;
    return std::min(reach_[i], k.x_at(target) * rmax);
  }

  // Upper end of primitive i over the box from a lower bound of the distance alone.
  double primitive_upper(std::uint32_t i, const Aabb& box) const {
    const Vec3 a = point_a(i);
    const Vec3 b = point_b(i);
    const double dmin = lower_distance(box, a, b);
    const double w = table_.weight[i];
    if (mode_.mode == PrimitiveMode::kCauchySegment && table_.len[i] > 0) {
      return w * cauchy_segment_max(table_.s[i], table_.len[i], dmin);
    }
    const double rmax = std::max(table_.r0[i], table_.r0[i] + table_.dr[i] * table_.len[i]);
    return w * distance_kernel().value(dmin / rmax);
  }

  Kernel distance_kernel() const {
    return mode_.mode == PrimitiveMode::kCauchyPoint || mode_.mode == PrimitiveMode::kCauchySegment
               ? Kernel{KernelKind::kCauchy, kernel_.shape()}
               : kernel_;
  }

  Interval primitive_bound(std::uint32_t i, const Aabb& box) const {
    const Vec3 a = point_a(i);
    const Vec3 b = point_b(i);
    const DistanceRange dist = box_segment_distance(box, a, b);
    const double w = table_.weight[i];
    if (mode_.mode == PrimitiveMode::kCauchySegment && table_.len[i] > 0) {
      return cauchy_bound(i, box, a, b, dist);
    }
    const double r_end = table_.r0[i] + table_.dr[i] * table_.len[i];
    const double rmin = std::min(table_.r0[i], r_end);
    const double rmax = std::max(table_.r0[i], r_end);
    const Kernel k = distance_kernel();
    const double x_near = dist.min / rmax;
    const double x_far = dist.max / rmin;
    double lo = w * k.value(x_far);
    if (mode_.fades) lo *= fade_of(x_far * x_far * table_.inv_cut[i]);
    return {lo, w * k.value(x_near)};
  }

  // Bounds of a Cauchy segment over a box with centre c and half-diagonal rho. For every point p
  // of the box and q of the segment, |c - q| - rho <= |p - q| <= |c - q| + rho, and for any
  // e > 0, (d + rho)^2 <= (1 + e) d^2 + (1 + 1/e) rho^2 and, for e in (0, 1),
  // max(d - rho, 0)^2 >= (1 - e) d^2 - (1/e - 1) rho^2. With A = 1 + s^2 (1 +- 1/e) rho^2 the
  // kernel bound 1 / (A + s^2 (1 +- e) d^2)^2 integrates in closed form: F_s'(c) / A^2 with
  // s'^2 = s^2 (1 +- e) / A.
  Interval cauchy_bound(std::uint32_t i, const Aabb& box, const Vec3& a, const Vec3& b,
                        const DistanceRange& dist) const {
    const double w = table_.weight[i];
    const double s = table_.s[i];
    const double s2 = s * s;
    const double len = table_.len[i];
    const Vec3 c = box.center();
    const double rho = 0.5 * box.diagonal().norm();
    const double rho2 = rho * rho;
    const Vec3 ab = b - a;
    const double t = std::clamp((c - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    const double dc = (c - (a + t * ab)).norm();
    // Upper end: the infinite-line / whole-length bound, tightened by the centre bound.
    double hi = w * cauchy_segment_max(s, len, dist.min);
    const double e_hi = std::clamp(rho / std::max(dc, 2 * rho), 0.05, 0.5);
    const double a_hi = 1 - s2 * (1 / e_hi - 1) * rho2;
    if (a_hi > 0) {
      const double s_hi = std::sqrt(s2 * (1 - e_hi) / a_hi);
      hi = std::min(hi, w * cauchy_segment_integral(c, a, b, s_hi) / (a_hi * a_hi));
    }
    double lo = 0;
    const double fade = fade_of(dist.max * dist.max * table_.inv_cut[i]);
    if (fade > 0) {
      const double e_lo = rho > 0 ? rho / std::max(dc, rho) : 1.0;
      const double a_lo = 1 + s2 * (1 + 1 / e_lo) * rho2;
      const double s_lo = std::sqrt(s2 * (1 + e_lo) / a_lo);
      lo = w * cauchy_segment_integral(c, a, b, s_lo) / (a_lo * a_lo) * fade;
    }
    // The closed forms above are evaluated in floating point: widen by a relative 1e-9.
    return {lo * (1 - 1e-9), hi * (1 + 1e-9)};
  }

  Kernel kernel_;
  SurfaceKind surface_;
  bool prune_ = true;
  detail::ModeParams mode_;
  detail::PrimitiveTable table_;
  std::vector<double> reach_;  // support radius of each primitive (model units)
  std::vector<SegmentBounds> reach_bounds_;  // per primitive, see out_of_reach()
  double split_diagonal_ = std::numeric_limits<double>::infinity();  // see do_evaluate
  const std::uint64_t serial_ = next_serial();  // this field among all (candidates()' cache)
  detail::BoxBvh bvh_;
  Aabb surface_box_;
};

void check_radius(double r, const std::string& what) {
  if (!std::isfinite(r) || r <= 0) {
    throw InvalidArgument(what + " must be finite and > 0, got " + std::to_string(r));
  }
}

}  // namespace

SkeletonFieldOptions SkeletonFieldOptions::resolved() const {
  SkeletonFieldOptions o = *this;
  o.kernel.validate();
  if (o.surface == SurfaceKind::kConvolution && o.kernel.kind != KernelKind::kCauchy) {
    throw InvalidArgument("convolution surfaces need the cauchy kernel, got " +
                          kernel_name(o.kernel.kind));
  }
  if (!std::isfinite(o.iso) || o.iso < 0) {
    throw InvalidArgument("iso must be finite and > 0 (0 = kernel default), got " + std::to_string(o.iso));
  }
  if (o.iso == 0) o.iso = o.kernel.default_iso();
  if (o.surface == SurfaceKind::kDistance && o.kernel.kind != KernelKind::kCauchy) {
    (void)o.kernel.x_at(o.iso);  // throws if the iso is unreachable
  }
  return o;
}

FieldPtr make_skeleton_field(const Skeleton& skeleton, const SkeletonFieldOptions& options,
                             std::span<const double> edge_weights) {
  const SkeletonFieldOptions o = options.resolved();
  validate(skeleton);
  if (!edge_weights.empty() && edge_weights.size() != skeleton.edges.size()) {
    throw InvalidArgument("edge_weights: " + std::to_string(edge_weights.size()) + " weights for " +
                          std::to_string(skeleton.edges.size()) + " edges");
  }
  std::vector<Primitive> prims;
  prims.reserve(skeleton.edges.size());
  std::vector<char> has_edge(skeleton.nodes.size(), 0);
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const double w = edge_weights.empty() ? 1.0 : edge_weights[e];
    if (!std::isfinite(w) || w < 0) {
      throw InvalidArgument("edge_weights[" + std::to_string(e) + "] must be finite and >= 0, got " +
                            std::to_string(w));
    }
    const auto& na = skeleton.nodes[skeleton.edges[e][0]];
    const auto& nb = skeleton.nodes[skeleton.edges[e][1]];
    prims.push_back({na.position, nb.position, na.radius, nb.radius, w});
    has_edge[skeleton.edges[e][0]] = has_edge[skeleton.edges[e][1]] = 1;
  }
  for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
    if (has_edge[i] == 0) {
      const auto& n = skeleton.nodes[i];
      prims.push_back({n.position, n.position, n.radius, n.radius, 1.0});
    }
  }
  return std::make_shared<SkeletonField>(o, prims);
}

FieldPtr make_point_field(const Vec3& center, double radius, const SkeletonFieldOptions& options) {
  if (!center.allFinite()) throw InvalidArgument("point primitive: center is not finite");
  check_radius(radius, "point primitive: radius");
  return std::make_shared<SkeletonField>(options.resolved(),
                                         std::vector<Primitive>{{center, center, radius, radius, 1.0}});
}

FieldPtr make_segment_field(const Vec3& a, double ra, const Vec3& b, double rb,
                            const SkeletonFieldOptions& options) {
  if (!a.allFinite() || !b.allFinite()) throw InvalidArgument("segment primitive: endpoint is not finite");
  check_radius(ra, "segment primitive: radius at a");
  check_radius(rb, "segment primitive: radius at b");
  return std::make_shared<SkeletonField>(options.resolved(), std::vector<Primitive>{{a, b, ra, rb, 1.0}});
}

}  // namespace ramiform
