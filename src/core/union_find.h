// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Union-find over dense indices with path halving. A union attaches the larger root to the
/// smaller, so the final structure (and every root) depends only on the order of the unions:
/// the same on any thread count.

#include <cstddef>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace ramiform::detail {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent[a] = b;
  }
};

}  // namespace ramiform::detail
