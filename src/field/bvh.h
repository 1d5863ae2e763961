// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: a bounding-volume hierarchy over boxes (primitive supports), for box queries.

#include <cstdint>
#include <limits>
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

  /// The item nearest to `p`: the one with the least `distance2(id)`, a squared distance from p
  /// that is never below the squared distance from p to the item's box (ties: the lower id).
  /// Best-first descent, pruning nodes whose box is farther than the best so far. Returns
  /// UINT32_MAX without items; `best_d2` (may be null) receives the least distance2.
  template <class Distance2>
  [[nodiscard]] std::uint32_t nearest(const Vec3& p, Distance2&& distance2,
                                      double* best_d2 = nullptr) const {
    std::uint32_t best = UINT32_MAX;
    double best_value = std::numeric_limits<double>::infinity();
    if (!nodes_.empty()) {
      // Each node goes on the stack with its box's squared distance, computed once (when its
      // parent orders its children); the nodes visited and the answer are those of testing
      // every node's box again when it is popped.
      struct Entry {
        std::uint32_t node;
        double d2;
      };
      Entry stack[64];
      int top = 0;
      stack[top++] = {0, squared_distance(nodes_[0].box, p)};
      while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > best_value) continue;
        const Node& n = nodes_[e.node];
        if (n.count > 0) {
          for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
            if (squared_distance(leaf_boxes_[i], p) > best_value) continue;
            const std::uint32_t id = order_[i];
            const double d2 = distance2(id);
            if (d2 < best_value || (d2 == best_value && id < best)) {
              best_value = d2;
              best = id;
            }
          }
        } else {
          // The nearer child is pushed last, so it is visited first.
          const double dl = squared_distance(nodes_[n.first].box, p);
          const double dr = squared_distance(nodes_[n.right].box, p);
          if (dl <= dr) {
            stack[top++] = {n.right, dr};
            stack[top++] = {n.first, dl};
          } else {
            stack[top++] = {n.first, dl};
            stack[top++] = {n.right, dr};
          }
        }
      }
    }
    if (best_d2 != nullptr) *best_d2 = best_value;
    return best;
  }

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
  std::uint32_t build(std::uint32_t begin, std::uint32_t end, const std::vector<Vec3>& sums);

  std::vector<Aabb> boxes_;
  std::vector<std::uint32_t> order_;
  std::vector<Aabb> leaf_boxes_;  ///< boxes_[order_[i]] at i: the leaves' boxes side by side
  std::vector<Node> nodes_;
};

}  // namespace ramiform::detail
