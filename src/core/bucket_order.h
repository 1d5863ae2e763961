// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Ordering by a dense integer key first: a counting sort into buckets (linear, stable), then
/// each bucket sorted on its own, the buckets in parallel. The polygonizer orders several long
/// lists whose keys are point ids with a few entries each (Delaunay tetrahedra by their smallest
/// corner, lattice edges and crossing edges by their lower point id); a comparison sort of the
/// whole list cost several times as much.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "ramiform/core/parallel.h"

namespace ramiform::detail {

/// bucket_of's value for an item to leave out.
inline constexpr std::uint32_t kNoBucket = UINT32_MAX;

/// The indices i < n with bucket_of(i) != kNoBucket (bucket_of(i) < buckets otherwise), by
/// bucket and within a bucket by `less(i, j)` (a strict weak order on indices). With `start`,
/// also the offset of every bucket in the result (buckets + 1 entries). The result does not
/// depend on the thread count when `less` is a total order.
template <class BucketOf, class Less>
std::vector<std::uint32_t> bucket_order(std::size_t n, std::size_t buckets, BucketOf&& bucket_of,
                                        Less&& less, const Context* ctx,
                                        std::vector<std::uint32_t>* start = nullptr) {
  std::vector<std::uint32_t> offset(buckets + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t b = bucket_of(i);
    if (b != kNoBucket) ++offset[b + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) offset[b + 1] += offset[b];
  std::vector<std::uint32_t> order(offset[buckets]);
  {
    std::vector<std::uint32_t> cursor(offset.begin(), offset.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t b = bucket_of(i);
      if (b != kNoBucket) order[cursor[b]++] = static_cast<std::uint32_t>(i);
    }
  }
  parallel::for_chunks(
      buckets, 8192,
      [&](std::size_t first, std::size_t last) {
        for (std::size_t b = first; b < last; ++b) {
          std::sort(order.begin() + offset[b], order.begin() + offset[b + 1], less);
        }
      },
      ctx);
  if (start != nullptr) *start = std::move(offset);
  return order;
}

}  // namespace ramiform::detail
