// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/bvh.h"

#include <algorithm>
#include <numeric>

namespace ramiform::detail {
namespace {
constexpr std::uint32_t kLeafSize = 4;
}

BoxBvh::BoxBvh(std::vector<Aabb> boxes) : boxes_(std::move(boxes)) {
  order_.resize(boxes_.size());
  std::iota(order_.begin(), order_.end(), 0U);
  if (!boxes_.empty()) {
    nodes_.reserve(2 * boxes_.size() / kLeafSize + 2);
    // Twice each box's centre, once: the splits compare it (local_radii() builds a BVH over the
    // skeleton's edges on every call, several times a refinement round).
    std::vector<Vec3> sums(boxes_.size());
    for (std::size_t i = 0; i < boxes_.size(); ++i) sums[i] = boxes_[i].min() + boxes_[i].max();
    build(0, static_cast<std::uint32_t>(boxes_.size()), sums);
  }
  leaf_boxes_.resize(boxes_.size());
  for (std::size_t i = 0; i < order_.size(); ++i) leaf_boxes_[i] = boxes_[order_[i]];
}

std::uint32_t BoxBvh::build(std::uint32_t begin, std::uint32_t end, const std::vector<Vec3>& sums) {
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    Aabb box;
    for (std::uint32_t i = begin; i < end; ++i) box.extend(boxes_[order_[i]]);
    nodes_[index].box = box;
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return index;
  }
  // (Twice the centres: the box of the centres scaled by two has the same longest axis.)
  Aabb centers;
  for (std::uint32_t i = begin; i < end; ++i) centers.extend(sums[order_[i]]);
  int axis = 0;
  centers.diagonal().maxCoeff(&axis);
  const std::uint32_t mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](std::uint32_t a, std::uint32_t b) {
                     const double ca = sums[a][axis];
                     const double cb = sums[b][axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  const std::uint32_t left = build(begin, mid, sums);
  const std::uint32_t right = build(mid, end, sums);
  // An inner node's box is its children's: the union of the same boxes.
  Aabb box = nodes_[left].box;
  box.extend(nodes_[right].box);
  nodes_[index].box = box;
  nodes_[index].first = left;
  nodes_[index].right = right;
  nodes_[index].count = 0;
  return index;
}

void BoxBvh::query(const Aabb& q, std::vector<std::uint32_t>& out) const {
  if (nodes_.empty() || q.isEmpty()) return;
  // Children are tested before they are pushed, and a leaf's boxes lie side by side
  // (leaf_boxes_): the same nodes and items are visited in the same order as when every node
  // was tested on being popped, so the ids come out in the same order.
  const double lo0 = q.min().x(), lo1 = q.min().y(), lo2 = q.min().z();
  const double hi0 = q.max().x(), hi1 = q.max().y(), hi2 = q.max().z();
  const auto meets = [&](const Aabb& b) {
    return b.min().x() <= hi0 && lo0 <= b.max().x() && b.min().y() <= hi1 && lo1 <= b.max().y() &&
           b.min().z() <= hi2 && lo2 <= b.max().z();
  };
  if (!meets(nodes_[0].box)) return;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (n.count > 0) {
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
        if (meets(leaf_boxes_[i])) out.push_back(order_[i]);
      }
    } else {
      if (meets(nodes_[n.first].box)) stack[top++] = n.first;
      if (meets(nodes_[n.right].box)) stack[top++] = n.right;
    }
  }
}

}  // namespace ramiform::detail
