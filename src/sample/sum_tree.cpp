// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/sum_tree.h"

#include <algorithm>

namespace ramiform::sample_detail {

SumTree::SumTree(std::size_t n) {
  while (size_ < n) size_ *= 2;
  node_.assign(2 * size_, 0.0);
}

void SumTree::set_all(const std::vector<double>& w) {
  std::fill(node_.begin(), node_.end(), 0.0);
  std::copy(w.begin(), w.end(), node_.begin() + static_cast<std::ptrdiff_t>(size_));
  for (std::size_t i = size_ - 1; i >= 1; --i) node_[i] = node_[2 * i] + node_[2 * i + 1];
}

void SumTree::set(std::size_t i, double w) {
  std::size_t k = size_ + i;
  node_[k] = w;
  // Parents are recomputed from their children (not adjusted by the difference), so sums
  // never drift from those of a fresh tree.
  for (k /= 2; k >= 1; k /= 2) node_[k] = node_[2 * k] + node_[2 * k + 1];
}

std::size_t SumTree::find(double u) const {
  std::size_t k = 1;
  while (k < size_) {
    // Going left when the right subtree is empty keeps rounding (u a hair above the left sum
    // while the right weighs 0) from landing on a leaf of weight 0.
    if (u < node_[2 * k] || !(node_[2 * k + 1] > 0.0)) {
      k = 2 * k;
    } else {
      u -= node_[2 * k];
      k = 2 * k + 1;
    }
  }
  return k - size_;
}

std::vector<double> SumTree::leaves() const {
  return {node_.begin() + static_cast<std::ptrdiff_t>(size_), node_.end()};
}

}  // namespace ramiform::sample_detail
