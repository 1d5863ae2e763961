// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: a k-d tree over a vector of points (nanoflann), with neighbour queries whose results
// are sorted by (distance, index), so that ties never depend on the tree's traversal order.

#include <nanoflann.hpp>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform::detail {

class PointKdTree {
 public:
  /// Keeps a reference to `points`, which must outlive the tree.
  explicit PointKdTree(const std::vector<Vec3>& points)
      : cloud_{&points},
        tree_(std::make_unique<Tree>(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(16))) {
    tree_->buildIndex();
  }

  /// The `k` nearest points to `q` (fewer when there are fewer points) as (index, squared
  /// distance), nearest first, ties by index. Thread-safe.
  void nearest(const Vec3& q, std::size_t k,
               std::vector<std::pair<std::uint32_t, double>>& out) const {
    k = std::min(k, cloud_.points->size());
    std::vector<std::uint32_t> index(k);
    std::vector<double> d2(k);
    const std::size_t found = tree_->knnSearch(q.data(), k, index.data(), d2.data());
    out.resize(found);
    for (std::size_t i = 0; i < found; ++i) out[i] = {index[i], d2[i]};
    sort(out);
  }

  /// Every point closer than `radius` to `q` (open ball) as (index, squared distance),
  /// nearest first, ties by index. Thread-safe.
  void within(const Vec3& q, double radius,
              std::vector<std::pair<std::uint32_t, double>>& out) const {
    within_by_index(q, radius, out);
    sort(out);
  }

  /// As `within`, sorted by index instead.
  void within_by_index(const Vec3& q, double radius,
                       std::vector<std::pair<std::uint32_t, double>>& out) const {
    out.clear();
    tree_->radiusSearch(q.data(), radius * radius, out, nanoflann::SearchParams(32, 0, false));
    std::sort(out.begin(), out.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
  }

 private:
  struct Cloud {
    const std::vector<Vec3>* points;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return points->size(); }
    [[nodiscard]] double kdtree_get_pt(std::size_t i, std::size_t dim) const {
      return (*points)[i][static_cast<Eigen::Index>(dim)];
    }
    template <class Box>
    bool kdtree_get_bbox(Box& /*box*/) const {
      return false;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>,
                                                   Cloud, 3, std::uint32_t>;

  static void sort(std::vector<std::pair<std::uint32_t, double>>& v) {
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
      return a.second != b.second ? a.second < b.second : a.first < b.first;
    });
  }

  Cloud cloud_;
  std::unique_ptr<Tree> tree_;
};

}  // namespace ramiform::detail
