// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The one parallel layer (over oneTBB). Work is split into fixed chunks that depend only on the
/// range and the grain, never on the thread count, and reductions combine chunk results in
/// index order, so results are identical for any number of threads (including the serial path).

#include <cstddef>
#include <functional>
#include <vector>

#include "ramiform/core/context.h"

namespace ramiform::parallel {

/// Calls `body(begin, end)` for consecutive chunks [begin, end) of [0, n), each at most `grain`
/// long, in parallel on `ctx->threads()` threads (all when ctx is null or threads is 0; serial
/// when threads is 1). A loop without a Context nested in another loop keeps that loop's thread
/// count (serial inside a serial loop, the same task arena inside a parallel one). Checks
/// cancellation between chunks and throws `Cancelled`.
void for_chunks(std::size_t n, std::size_t grain,
                const std::function<void(std::size_t begin, std::size_t end)>& body,
                const Context* ctx = nullptr);

/// Calls `body(i)` for every i in [0, n) in parallel (see for_chunks).
template <class Fn>
void for_each(std::size_t n, std::size_t grain, Fn&& body, const Context* ctx = nullptr) {
  for_chunks(
      n, grain,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) body(i);
      },
      ctx);
}

/// Runs `first()` and `second()` side by side (as two chunks of for_chunks; one after the other
/// on one thread). Neither may depend on the other's results.
template <class First, class Second>
void both(First&& first, Second&& second, const Context* ctx = nullptr) {
  for_chunks(
      2, 1,
      [&](std::size_t task, std::size_t) {
        if (task == 0) {
          first();
        } else {
          second();
        }
      },
      ctx);
}

/// Deterministic map-reduce: `map(begin, end)` computes a partial result for each fixed chunk,
/// then the partials are folded left to right with `combine(acc, partial)` starting at `init`.
template <class T, class Map, class Combine>
T reduce(std::size_t n, std::size_t grain, T init, Map&& map, Combine&& combine,
         const Context* ctx = nullptr) {
  if (grain == 0) grain = 1;
  const std::size_t chunks = (n + grain - 1) / grain;
  std::vector<T> partial(chunks, init);
  for_chunks(
      chunks, 1,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t c = b; c < e; ++c) {
          const std::size_t lo = c * grain;
          const std::size_t hi = lo + grain < n ? lo + grain : n;
          partial[c] = map(lo, hi);
        }
      },
      ctx);
  T acc = std::move(init);
  for (auto& p : partial) acc = combine(std::move(acc), std::move(p));
  return acc;
}

/// Exclusive prefix sum of `counts` (returns the total). Serial: it is never the bottleneck.
std::size_t exclusive_scan(std::vector<std::size_t>& counts);

}  // namespace ramiform::parallel
