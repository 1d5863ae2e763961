// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: the candidate-block loop shared by dart throwing and
/// near-surface projection.

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/core/random.h"
#include "sample/common.h"
#include "sample/point_grid.h"
#include "sample/region.h"

namespace ramiform::sample_detail {

/// Runs candidate blocks of kBlock until `block_fn` says stop or the budget is spent. Block b
/// draws its candidates from Rng(seed).split(stream).split(b), so the points never depend on the
/// thread count. `block_fn(rng, n, near, out)` handles n candidates, appends the accepted points
/// to `out` (and `near`, the min-distance grid of radius `min_distance` over `box`) and returns
/// true to stop. Spending the budget of `max_attempts` candidates sets st.saturated, and so
/// does an empty region (at once). Checks cancellation and reports progress once per block.
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

}  // namespace ramiform::sample_detail
