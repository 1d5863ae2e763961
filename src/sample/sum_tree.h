// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: a sum tree (a complete binary tree whose inner nodes hold the
/// sums of their children) over non-negative weights. It draws index i with probability
/// w_i / sum(w) by inverse-CDF search and changes one weight, both in O(log n) — what Lane and
/// Prusinkiewicz's method needs, since its discrete pdf changes after every point (Lane &
/// Prusinkiewicz 2002, *Generating spatial distributions for multilevel models of plant
/// communities*, Graphics Interface; as used by Kochhar 2010, *Application of implicit methods
/// to the interactive modeling of trees*, M.Sc. thesis, University of Calgary, §5.2.2 and §6.1).

#include <cstddef>
#include <vector>

namespace ramiform::sample_detail {

/// Non-negative weights, one per leaf, in a binary tree of sums. The leaf count is rounded up
/// to a power of two; the extra leaves weigh 0. Every inner node is recomputed from its two
/// children, so after any sequence of updates each node equals the sum a freshly built tree of
/// the same leaves would hold, bit for bit (no drift).
class SumTree {
 public:
  /// n leaves of weight 0.
  explicit SumTree(std::size_t n);

  /// Replaces every weight: w[i] for leaf i < w.size(), 0 for the rest. Precondition:
  /// w.size() <= leaf_count(), every w[i] >= 0.
  void set_all(const std::vector<double>& w);
  /// The weight of leaf i.
  [[nodiscard]] double get(std::size_t i) const { return node_[size_ + i]; }
  /// Sets the weight of leaf i (>= 0) and updates its ancestors.
  void set(std::size_t i, double w);
  /// The sum of every weight.
  [[nodiscard]] double total() const { return node_[1]; }
  /// The leaf where the prefix sum passes u: the leaf i of positive weight with
  /// w_0 + ... + w_{i-1} <= u < w_0 + ... + w_i (up to rounding of the inner sums).
  /// Precondition: 0 <= u < total().
  [[nodiscard]] std::size_t find(double u) const;
  /// Every leaf weight, leaf_count() of them.
  [[nodiscard]] std::vector<double> leaves() const;
  /// Number of leaves (a power of two, >= the n given).
  [[nodiscard]] std::size_t leaf_count() const { return size_; }

 private:
  std::size_t size_ = 1;
  std::vector<double> node_;  ///< node 1 is the root; node k has children 2k and 2k + 1
};

}  // namespace ramiform::sample_detail
