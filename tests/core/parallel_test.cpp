// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/parallel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

struct Chunk {
  std::size_t begin, end;
};

// Runs for_chunks and records every index hit and every chunk.
void check_cover(std::size_t n, std::size_t grain, const Context* ctx) {
  std::vector<std::atomic<int>> hits(n);
  for (auto& h : hits) h = 0;
  std::mutex m;
  std::vector<Chunk> chunks;
  parallel::for_chunks(
      n, grain,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) hits[i].fetch_add(1);
        std::lock_guard<std::mutex> lock(m);
        chunks.push_back({b, e});
      },
      ctx);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << "index " << i;
  const std::size_t g = grain == 0 ? 1 : grain;
  EXPECT_EQ(chunks.size(), (n + g - 1) / g);
  for (const auto& c : chunks) {
    EXPECT_LT(c.begin, c.end);
    EXPECT_LE(c.end - c.begin, g);
    // Fixed chunks: boundaries depend only on n and grain.
    EXPECT_EQ(c.begin % g, 0U);
    EXPECT_TRUE(c.end == n || c.end % g == 0);
  }
}

TEST(Parallel, ForChunksCoversEveryIndexOnce) {
  Context one(1), two(2), all(0);
  for (const Context* ctx : {static_cast<const Context*>(nullptr), static_cast<const Context*>(&one),
                             static_cast<const Context*>(&two), static_cast<const Context*>(&all)}) {
    for (std::size_t n : {0UL, 1UL, 63UL, 64UL, 65UL, 10007UL}) {
      for (std::size_t grain : {0UL, 1UL, 7UL, 64UL, 100000UL}) {
        SCOPED_TRACE(testing::Message() << "n " << n << " grain " << grain << " threads "
                                        << (ctx ? ctx->threads() : -1));
        check_cover(n, grain, ctx);
      }
    }
  }
}

TEST(Parallel, ForEachCoversEveryIndexOnce) {
  Context two(2);
  std::vector<std::atomic<int>> hits(5000);
  for (auto& h : hits) h = 0;
  parallel::for_each(hits.size(), 33, [&](std::size_t i) { hits[i].fetch_add(1); }, &two);
  for (auto& h : hits) EXPECT_EQ(h.load(), 1);
}

TEST(Parallel, BothRunsEachTaskOnceOnAnyThreadCount) {
  for (const int threads : {1, 2}) {
    Context ctx(threads);
    std::atomic<int> first{0}, second{0};
    std::vector<int> a, b;
    parallel::both(
        [&] {
          ++first;
          a.assign(1000, 1);
        },
        [&] {
          ++second;
          b.assign(2000, 2);
        },
        &ctx);
    EXPECT_EQ(first.load(), 1) << threads;
    EXPECT_EQ(second.load(), 1) << threads;
    EXPECT_EQ(a, std::vector<int>(1000, 1));
    EXPECT_EQ(b, std::vector<int>(2000, 2));
  }
}

TEST(Parallel, ReduceIsBitIdenticalForAnyThreadCount) {
  // Values of wildly different magnitudes so that the summation order matters.
  Rng rng(31);
  std::vector<double> v(100003);
  for (auto& x : v) x = std::ldexp(rng.uniform(-1, 1), static_cast<int>(rng.below(80)) - 40);
  auto sum_with = [&](const Context* ctx) {
    return parallel::reduce(
        v.size(), 97, 0.0,
        [&](std::size_t b, std::size_t e) {
          double s = 0;
          for (std::size_t i = b; i < e; ++i) s += v[i];
          return s;
        },
        [](double a, double b) { return a + b; }, ctx);
  };
  // Independent expected value: partial sums per fixed chunk of 97, folded left to right.
  double expected = 0;
  for (std::size_t b = 0; b < v.size(); b += 97) {
    double s = 0;
    for (std::size_t i = b; i < std::min(v.size(), b + 97); ++i) s += v[i];
    expected += s;
  }
  Context one(1), two(2), all(0);
  const double s1 = sum_with(&one);
  const double s2 = sum_with(&two);
  const double s0 = sum_with(&all);
  const double sn = sum_with(nullptr);
  EXPECT_EQ(std::memcmp(&s1, &expected, sizeof(double)), 0) << s1 << " vs " << expected;
  EXPECT_EQ(std::memcmp(&s1, &s2, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&s1, &s0, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&s1, &sn, sizeof(double)), 0);
  // Repeated runs with many threads stay identical.
  for (int i = 0; i < 20; ++i) EXPECT_EQ(sum_with(&two), s1);
}

TEST(Parallel, ReduceCombinesInIndexOrder) {
  // A non-commutative combine (concatenation) shows the fold order.
  Context two(2);
  const auto order = parallel::reduce(
      100, 10, std::vector<std::size_t>{},
      [](std::size_t b, std::size_t e) { return std::vector<std::size_t>{b, e}; },
      [](std::vector<std::size_t> acc, std::vector<std::size_t> p) {
        acc.insert(acc.end(), p.begin(), p.end());
        return acc;
      },
      &two);
  ASSERT_EQ(order.size(), 20U);
  for (std::size_t c = 0; c < 10; ++c) {
    EXPECT_EQ(order[2 * c], 10 * c);
    EXPECT_EQ(order[2 * c + 1], 10 * c + 10);
  }
  // Empty range: init.
  const double empty = parallel::reduce(
      0, 10, 42.0, [](std::size_t, std::size_t) { return 1.0; },
      [](double a, double b) { return a + b; }, &two);
  EXPECT_EQ(empty, 42.0);
}

TEST(Parallel, CancelledContextThrows) {
  for (int threads : {1, 2, 0}) {
    Context ctx(threads);
    ctx.cancel();
    EXPECT_TRUE(ctx.is_cancelled());
    std::atomic<int> calls{0};
    EXPECT_THROW(parallel::for_chunks(1000, 10, [&](std::size_t, std::size_t) { ++calls; }, &ctx),
                 Cancelled);
    EXPECT_EQ(calls.load(), 0) << "threads " << threads;
  }
}

TEST(Parallel, CancelDuringWorkStopsBetweenChunks) {
  Context ctx(1);
  int calls = 0;
  EXPECT_THROW(parallel::for_chunks(
                   1000, 10,
                   [&](std::size_t b, std::size_t) {
                     ++calls;
                     if (b == 50) ctx.cancel();
                   },
                   &ctx),
               Cancelled);
  EXPECT_EQ(calls, 6);  // chunks 0..5 ran, the check before chunk 6 threw

  Context two(2);
  std::atomic<int> calls2{0};
  EXPECT_THROW(parallel::for_chunks(
                   100000, 1,
                   [&](std::size_t b, std::size_t) {
                     ++calls2;
                     if (b == 10) two.cancel();
                   },
                   &two),
               Cancelled);
  EXPECT_LT(calls2.load(), 100000);
}

// threads = 1 is one thread all the way down: loops nested without a Context (as inside a field
// evaluation) run on the calling thread; with 2 threads they use at most the loop's 2.
std::size_t distinct_threads_of_nested_loops(int threads) {
  std::mutex m;
  std::vector<std::thread::id> seen;
  const Context ctx(threads);
  parallel::for_chunks(
      8, 1,
      [&](std::size_t, std::size_t) {
        parallel::for_chunks(64, 1, [&](std::size_t, std::size_t) {
          volatile double x = 0;
          for (int k = 0; k < 20000; ++k) x = x + std::sqrt(static_cast<double>(k));
          const std::lock_guard<std::mutex> lock(m);
          if (std::find(seen.begin(), seen.end(), std::this_thread::get_id()) == seen.end()) {
            seen.push_back(std::this_thread::get_id());
          }
        });
      },
      &ctx);
  return seen.size();
}

TEST(Parallel, NestedLoopsKeepTheThreadCount) {
  EXPECT_EQ(distinct_threads_of_nested_loops(1), 1u);
  EXPECT_LE(distinct_threads_of_nested_loops(2), 2u);
}

TEST(Context, CheckAndProgress) {
  Context ctx;
  EXPECT_EQ(ctx.threads(), 0);
  EXPECT_NO_THROW(ctx.check());
  EXPECT_NO_THROW(check_cancel(nullptr));
  EXPECT_NO_THROW(check_cancel(&ctx));
  std::vector<std::pair<std::string, double>> seen;
  ctx.report("ignored", 0.5);  // no callback: no-op
  ctx.set_progress([&](const std::string& s, double f) { seen.emplace_back(s, f); });
  ctx.report("stage", 0.25);
  ASSERT_EQ(seen.size(), 1U);
  EXPECT_EQ(seen[0].first, "stage");
  EXPECT_EQ(seen[0].second, 0.25);
  ctx.set_threads(3);
  EXPECT_EQ(ctx.threads(), 3);
  ctx.cancel();
  EXPECT_THROW(ctx.check(), Cancelled);
  EXPECT_THROW(check_cancel(&ctx), Cancelled);
  EXPECT_EQ(Context(2).threads(), 2);
}

TEST(Parallel, ExclusiveScan) {
  std::vector<std::size_t> c = {3, 0, 5, 1};
  EXPECT_EQ(parallel::exclusive_scan(c), 9U);
  EXPECT_EQ(c, (std::vector<std::size_t>{0, 3, 3, 8}));
  std::vector<std::size_t> empty;
  EXPECT_EQ(parallel::exclusive_scan(empty), 0U);
}

}  // namespace
}  // namespace ramiform
