// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/lane.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ramiform/core/parallel.h"
#include "ramiform/core/random.h"
#include "sample/point_grid.h"
#include "sample/sum_tree.h"
#include "sample/voxel_grid.h"

namespace ramiform::sample_detail {

namespace {

constexpr auto kEmpty = static_cast<std::uint8_t>(CellClass::kEmpty);
constexpr auto kPartial = static_cast<std::uint8_t>(CellClass::kPartial);
constexpr auto kFull = static_cast<std::uint8_t>(CellClass::kFull);

/// Drops the partial voxels that overlap no cube of the cache (§6.2.3: the pdf is non-zero only
/// near the surface).
void drop_uncached(const VoxelGrid& grid, const FieldCache& cache, std::vector<std::uint8_t>& cls,
                   const Context* ctx) {
  parallel::for_each(
      static_cast<std::size_t>(grid.n[2]), 1,
      [&](std::size_t kz) {
        const auto k = static_cast<std::int64_t>(kz);
        for (std::int64_t j = 0; j < grid.n[1]; ++j) {
          for (std::int64_t i = 0; i < grid.n[0]; ++i) {
            auto& c = cls[grid.index(i, j, k)];
            if (c == kPartial && !cache.overlaps(grid.box(i, j, k, i + 1, j + 1, k + 1)))
              c = kEmpty;
          }
        }
      },
      ctx);
}

/// The CellClass of every voxel: all partial without pruning, else from the bound descent (and
/// the cache, when there is one).
std::vector<std::uint8_t> voxel_classes(const Field& field, const VoxelGrid& grid,
                                        const LaneSpec& spec, const Context* ctx) {
  std::vector<std::uint8_t> cls(grid.size(), kPartial);
  if (!spec.prune) return cls;
  std::fill(cls.begin(), cls.end(), kEmpty);
  // Blocks write disjoint voxels, so the parallel descent is race-free and deterministic.
  struct None {};
  (void)descend<None>(
      field, grid, spec.target,
      [&](const IndexBox& b, CellClass c, std::vector<None>&) {
        for_each_voxel(b, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
          cls[grid.index(i, j, k)] = static_cast<std::uint8_t>(c);
        });
      },
      ctx);
  if (spec.cache != nullptr) drop_uncached(grid, *spec.cache, cls, ctx);
  return cls;
}

/// The initial pdf: weight 1 in every voxel that may hold a target point, 0 elsewhere.
SumTree initial_pdf(const std::vector<std::uint8_t>& cls) {
  std::vector<double> weights(cls.size());
  for (std::size_t v = 0; v < cls.size(); ++v) weights[v] = cls[v] != 0 ? 1.0 : 0.0;
  SumTree tree(cls.size());
  tree.set_all(weights);
  return tree;
}

/// Multiplies the weight of every voxel whose centre lies within the kernel's reach of p by the
/// kernel's factor at that distance; `r` bounds the reach in voxels.
void deform_pdf(SumTree& tree, const VoxelGrid& grid, const LaneKernel& kernel, const Vec3& p,
                std::int64_t r) {
  const double reach = kernel.reach();
  const IndexBox b =
      neighbourhood(grid, grid.coord(p.x(), 0), grid.coord(p.y(), 1), grid.coord(p.z(), 2), r);
  for_each_voxel(b, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    const std::size_t w = grid.index(i, j, k);
    const double old = tree.get(w);
    if (old == 0.0) return;
    const Vec3 c = grid.origin + grid.h * Vec3(double(i) + 0.5, double(j) + 0.5, double(k) + 0.5);
    const double d = (c - p).norm();
    if (d >= reach) return;
    const double f = kernel.factor(d);
    if (f != 1.0) tree.set(w, old * f);
  });
}

/// Clustering kernels multiply weights without limit: rescale before they overflow (a power of
/// two would be exact; 1e-200 is what the outputs were made with).
void rescale_if_huge(SumTree& tree, std::size_t voxels) {
  if (!(tree.total() > 1e200)) return;
  auto leaves = tree.leaves();
  for (auto& x : leaves) x *= 1e-200;
  leaves.resize(voxels);
  tree.set_all(leaves);
}

/// True when candidate p of voxel class `cls` is in the target set, asking the cache first.
bool in_target(const Field& field, const LaneSpec& spec, std::uint8_t cls, const Vec3& p) {
  if (cls == kFull) return true;
  bool evaluate = true;
  if (spec.cache != nullptr) {
    const auto verdict = spec.cache->classify(p);
    if (verdict == FieldCache::Verdict::kReject) return false;
    evaluate = verdict == FieldCache::Verdict::kEvaluate;
  }
  return !evaluate || spec.target.contains(field.value(p));
}

}  // namespace

PointSet run_lane(const Field& field, const Aabb& box, const LaneSpec& spec, std::uint64_t seed,
                  Context* ctx, SampleStats& st) {
  PointSet out;
  if (spec.count == 0) return out;
  if (box.isEmpty() || !(box.sizes().maxCoeff() > 0.0)) {
    st.saturated = true;
    return out;
  }
  const VoxelGrid grid(box, box.sizes().maxCoeff() / double(spec.grid));
  const std::vector<std::uint8_t> cls = voxel_classes(field, grid, spec, ctx);
  SumTree tree = initial_pdf(cls);
  PointGrid near(box, spec.kernel.zero_radius());
  Rng rng(seed);
  const auto r = static_cast<std::int64_t>(std::ceil(spec.kernel.reach() / grid.h)) + 1;
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
    // Inverse CDF over the voxels, then a uniform point in the chosen voxel.
    const std::size_t v = tree.find(rng.uniform() * total);
    const std::int64_t vi = static_cast<std::int64_t>(v) % grid.n[0];
    const std::int64_t vj = (static_cast<std::int64_t>(v) / grid.n[0]) % grid.n[1];
    const std::int64_t vk = static_cast<std::int64_t>(v) / (grid.n[0] * grid.n[1]);
    const Vec3 p =
        grid.origin + grid.h * Vec3(double(vi) + rng.uniform(), double(vj) + rng.uniform(),
                                    double(vk) + rng.uniform());
    if (near.has_near(p) || !in_target(field, spec, cls[v], p)) continue;
    near.add(p);
    out.positions.push_back(p);
    if (spec.kernel.reach() <= 0.0) continue;
    deform_pdf(tree, grid, spec.kernel, p, r);
    rescale_if_huge(tree, cls.size());
  }
  return out;
}

}  // namespace ramiform::sample_detail
