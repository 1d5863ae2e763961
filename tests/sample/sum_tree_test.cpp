// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The sum tree behind Lane's method, checked against independent linear scans: selection by
// prefix sum, selection frequencies, exact totals after updates.
#include "sample/sum_tree.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "ramiform/core/random.h"

namespace ramiform::sample_detail {
namespace {

/// The leaf a linear scan picks for u: the first leaf whose running sum exceeds u.
std::size_t linear_find(const std::vector<double>& w, double u) {
  double prefix = 0.0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    prefix += w[i];
    if (u < prefix) return i;
  }
  return w.size();
}

/// Small integer weights, about a third of them 0: every sum is exact in double.
std::vector<double> integer_weights(std::size_t n, Rng& rng) {
  std::vector<double> w(n);
  for (auto& x : w) x = rng.below(3) == 0 ? 0.0 : double(rng.below(8));
  return w;
}

TEST(SampleSumTree, LeafCountIsThePowerOfTwoAboveAndPaddingWeighsNothing) {
  for (const std::size_t n : {1U, 2U, 3U, 5U, 8U, 9U, 1000U}) {
    SumTree tree(n);
    std::size_t p = 1;
    while (p < n) p *= 2;
    EXPECT_EQ(tree.leaf_count(), p);
    EXPECT_EQ(tree.total(), 0.0);
    tree.set_all(std::vector<double>(n, 1.0));
    EXPECT_EQ(tree.total(), double(n));
    const auto leaves = tree.leaves();
    ASSERT_EQ(leaves.size(), p);
    for (std::size_t i = n; i < p; ++i) EXPECT_EQ(leaves[i], 0.0);
  }
}

TEST(SampleSumTree, FindMatchesALinearScanAtEveryBoundaryAndBetween) {
  Rng rng(11);
  for (const std::size_t n : {1U, 2U, 3U, 7U, 16U, 33U, 257U}) {
    SCOPED_TRACE(n);
    std::vector<double> w = integer_weights(n, rng);
    w[rng.below(n)] = 3.0;  // at least one positive weight
    SumTree tree(n);
    tree.set_all(w);
    const double total = std::accumulate(w.begin(), w.end(), 0.0);
    ASSERT_EQ(tree.total(), total);
    // Every prefix sum below the total is a boundary: u there starts the next positive leaf.
    double prefix = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (prefix < total) {
        const std::size_t leaf = tree.find(prefix);
        EXPECT_EQ(leaf, linear_find(w, prefix)) << "u = " << prefix;
        EXPECT_GT(w[leaf], 0.0);
      }
      prefix += w[i];
    }
    for (int k = 0; k < 2000; ++k) {
      const double u = rng.uniform() * total;
      const std::size_t leaf = tree.find(u);
      ASSERT_EQ(leaf, linear_find(w, u)) << "u = " << u;
      ASSERT_GT(w[leaf], 0.0);
    }
    // The largest u below the total picks the last positive leaf.
    const double last = std::nextafter(total, 0.0);
    EXPECT_EQ(tree.find(last), linear_find(w, last));
  }
}

TEST(SampleSumTree, SelectionFrequenciesMatchTheWeights) {
  const std::vector<double> w = {0.5, 0.0, 2.0, 1.25, 0.0, 0.0, 3.0, 0.25, 1.0, 0.0, 4.0, 0.75};
  SumTree tree(w.size());
  tree.set_all(w);
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  constexpr std::size_t kDraws = 400000;
  std::vector<std::size_t> hits(w.size(), 0);
  Rng rng(2024);
  for (std::size_t d = 0; d < kDraws; ++d) ++hits[tree.find(rng.uniform() * tree.total())];
  double chi2 = 0.0;
  std::size_t categories = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0.0) {
      EXPECT_EQ(hits[i], 0U) << "leaf " << i << " has weight 0";
      continue;
    }
    const double expected = double(kDraws) * w[i] / total;
    chi2 += (double(hits[i]) - expected) * (double(hits[i]) - expected) / expected;
    ++categories;
  }
  // 7 degrees of freedom: P(chi2 > 24.3) = 0.001.
  ASSERT_EQ(categories, 8U);
  EXPECT_LT(chi2, 24.3);
}

TEST(SampleSumTree, UpdatesKeepTheTotalExact) {
  constexpr std::size_t kLeaves = 300;
  Rng rng(5);
  SumTree tree(kLeaves);
  std::vector<double> w(kLeaves, 0.0);
  // Multiples of 1/16 below 64: every partial sum of 300 of them is exact.
  for (int step = 0; step < 20000; ++step) {
    const std::size_t i = rng.below(kLeaves);
    w[i] = double(rng.below(1024)) / 16.0;
    tree.set(i, w[i]);
    ASSERT_EQ(tree.get(i), w[i]);
    if (step % 97 == 0) {
      ASSERT_EQ(tree.total(), std::accumulate(w.begin(), w.end(), 0.0));
    }
  }
  EXPECT_EQ(tree.total(), std::accumulate(w.begin(), w.end(), 0.0));
}

TEST(SampleSumTree, UpdatedTreeEqualsAFreshTreeBitForBit) {
  // Arbitrary weights, multiplied as Lane's kernel does: the sums round, but no more than a
  // tree built from scratch over the same leaves.
  constexpr std::size_t kLeaves = 1000;
  Rng rng(8);
  SumTree tree(kLeaves);
  std::vector<double> w(kLeaves);
  for (auto& x : w) x = rng.uniform();
  tree.set_all(w);
  for (int step = 0; step < 50000; ++step) {
    const std::size_t i = rng.below(kLeaves);
    w[i] *= rng.uniform(0.0, 2.0);
    tree.set(i, w[i]);
  }
  SumTree fresh(kLeaves);
  fresh.set_all(w);
  EXPECT_EQ(tree.total(), fresh.total());
  for (int k = 0; k < 1000; ++k) {
    const double u = rng.uniform() * tree.total();
    ASSERT_EQ(tree.find(u), fresh.find(u));
  }
  // And the total is the pairwise sum, within rounding of the plain running sum.
  const double scan = std::accumulate(w.begin(), w.end(), 0.0);
  EXPECT_NEAR(tree.total(), scan, 1e-12 * scan);
}

TEST(SampleSumTree, ZeroedLeavesAreNeverDrawn) {
  constexpr std::size_t kLeaves = 64;
  SumTree tree(kLeaves);
  tree.set_all(std::vector<double>(kLeaves, 1.0));
  for (std::size_t i = 0; i < kLeaves; i += 2) tree.set(i, 0.0);  // Lane's disk kernel
  EXPECT_EQ(tree.total(), double(kLeaves / 2));
  Rng rng(3);
  for (int k = 0; k < 10000; ++k) {
    ASSERT_EQ(tree.find(rng.uniform() * tree.total()) % 2, 1U);
  }
}

}  // namespace
}  // namespace ramiform::sample_detail
