// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: a bounding-volume hierarchy over boxes (primitive supports), for box queries.

#include <cstdint>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform::detail {

class BoxBvh {
 public:
  BoxBvh() = default;
  /// Builds over `boxes` (one per item); item ids are the indices into `boxes`.
  explicit BoxBvh(std::vector<Aabb> boxes);

  /// Appends to `out` the ids of every item whose box intersects `query`, in no particular order.
  void query(const Aabb& query, std::vector<std::uint32_t>& out) const;

  [[nodiscard]] const Aabb& item_box(std::uint32_t id) const { return boxes_[id]; }
  [[nodiscard]] std::size_t size() const { return boxes_.size(); }
  /// Box of all items (empty when there are none).
  [[nodiscard]] Aabb root_box() const { return nodes_.empty() ? Aabb() : nodes_[0].box; }

 private:
  struct Node {
    Aabb box;
    std::uint32_t first = 0;  ///< leaf: first index into order_; inner: left child
    std::uint32_t count = 0;  ///< leaf: number of items; inner: 0 (right child = first + 1 ... )
    std::uint32_t right = 0;  ///< inner: right child
  };
  std::uint32_t build(std::uint32_t begin, std::uint32_t end);

  std::vector<Aabb> boxes_;
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;
};

}  // namespace ramiform::detail
