// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Stratified (jittered grid) sampling: one uniform point per cell of a cubic grid, the grid
// refined until at least `count` of them are inside, then a random subset of exactly `count`.
#include <algorithm>
#include <cmath>
#include <vector>

#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/sample/point_sets.h"
#include "sample/common.h"
#include "sample/dart.h"
#include "sample/region.h"
#include "sample/voxel_grid.h"

namespace ramiform {

using namespace sample_detail;

namespace {

/// Refinement rounds before the sampler gives up (saturated).
constexpr int kStratifiedRounds = 12;

/// The jittered points of grid row `row` (one per cell) that are inside; none when the field's
/// bound shows the row to hold no inside point.
std::vector<Vec3> jittered_row(const Field& field, const VoxelGrid& grid, const Target& target,
                               std::size_t row, Rng& rng) {
  const auto j = static_cast<std::int64_t>(row) % grid.n[1];
  const auto k = static_cast<std::int64_t>(row) / grid.n[1];
  std::vector<Vec3> inside;
  if (classify(field.bound(grid.box(0, j, k, grid.n[0], j + 1, k + 1)), target) ==
      CellClass::kEmpty) {
    return inside;  // the row's stream is its own: skipping its draws changes no other row
  }
  std::vector<Vec3> pts(static_cast<std::size_t>(grid.n[0]));
  for (std::int64_t i = 0; i < grid.n[0]; ++i) {
    pts[static_cast<std::size_t>(i)] =
        grid.origin + grid.h * Vec3(double(i) + rng.uniform(), double(j) + rng.uniform(),
                                    double(k) + rng.uniform());
  }
  std::vector<double> values(pts.size());
  field.evaluate(pts, values);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (target.contains(values[i])) inside.push_back(pts[i]);
  }
  return inside;
}

/// The inside points of round `round`'s jittered grid of cell `grid.h`, in grid order.
std::vector<Vec3> jittered_inside(const Field& field, const VoxelGrid& grid, const Target& target,
                                  std::uint64_t seed, int round, const Context* ctx) {
  const auto rows = static_cast<std::size_t>(grid.n[1] * grid.n[2]);
  // One random sub-stream per grid row: independent of how rows are split among threads.
  std::vector<std::vector<Vec3>> inside(rows);
  const Rng base = Rng(seed).split(1000 + static_cast<std::uint64_t>(round));
  parallel::for_each(
      rows, 1,
      [&](std::size_t row) {
        Rng rng = base.split(row);
        inside[row] = jittered_row(field, grid, target, row, rng);
      },
      ctx);
  std::vector<Vec3> all;
  for (auto& r : inside) all.insert(all.end(), r.begin(), r.end());
  return all;
}

/// Exactly `count` of `all` (count <= all.size()): a seeded random subset (partial
/// Fisher-Yates), kept in grid order.
PointSet random_subset(const std::vector<Vec3>& all, std::size_t count, std::uint64_t seed) {
  std::vector<std::uint32_t> idx(all.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<std::uint32_t>(i);
  Rng pick = Rng(seed).split(0x7069636bULL);  // "pick"
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t j = i + pick.below(idx.size() - i);
    std::swap(idx[i], idx[j]);
  }
  idx.resize(count);
  std::sort(idx.begin(), idx.end());
  PointSet out;
  out.positions.reserve(count);
  for (const auto i : idx) out.positions.push_back(all[i]);
  return out;
}

}  // namespace

PointSet sample_stratified(const Field& field, const StratifiedOptions& options, std::uint64_t seed,
                           Context* ctx, SampleStats* stats) {
  check_point_memory(options.count, ctx, "sample_stratified");
  return sample_in_bounds(
      field, "sample_stratified", stats, [&](const Aabb& box, SampleStats& st) -> PointSet {
        if (options.count == 0) return {};
        const Target target = inside_target(field);
        const Region region(field, box, target, kRegionInside, ctx);
        const double volume = estimate_volume(field, region, target, seed, ctx);
        if (!(volume > 0.0)) {
          st.saturated = true;
          return {};
        }
        // A cell a bit smaller than the volume per point, so the first grid usually suffices.
        double h = pm::cbrt(volume / (1.1 * double(options.count)));
        for (int round = 0; round < kStratifiedRounds; ++round) {
          check_cancel(ctx);
          const VoxelGrid grid(box, h);
          const std::vector<Vec3> all = jittered_inside(field, grid, target, seed, round, ctx);
          st.attempts += grid.size();
          if (all.size() >= options.count) return random_subset(all, options.count, seed);
          h *= all.empty() ? 0.5 : 0.98 * pm::cbrt(double(all.size()) / double(options.count));
        }
        st.saturated = true;
        return {};
      });
}

}  // namespace ramiform
