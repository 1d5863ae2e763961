// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Thinning (Kochhar 2010, "Application of implicit methods to the interactive modeling of trees"
// (M.Sc. thesis), §7.1, point_set_thin): a random share of the points that
// lie inside a secondary surface is removed.
#include <cmath>
#include <span>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/random.h"
#include "ramiform/sample/point_sets.h"
#include "sample/common.h"

namespace ramiform {

using namespace sample_detail;

namespace {

// The indices of the points inside `secondary` (f > iso), in order.
std::vector<std::uint32_t> inside_indices(const PointSet& points, const Field& secondary,
                                          const Context* ctx) {
  std::vector<double> values(points.positions.size());
  parallel::for_chunks(
      points.positions.size(), kEvalGrain,
      [&](std::size_t b, std::size_t e) {
        secondary.evaluate(std::span<const Vec3>(points.positions.data() + b, e - b),
                           std::span<double>(values.data() + b, e - b));
      },
      ctx);
  std::vector<std::uint32_t> inside;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i] > secondary.iso()) inside.push_back(static_cast<std::uint32_t>(i));
  }
  return inside;
}

}  // namespace

PointSet thin_points(const PointSet& points, const Field& secondary, double percent,
                     std::uint64_t seed, const Context* ctx) {
  require(std::isfinite(percent) && percent >= 0.0 && percent <= 100.0,
          "thin_points: percent " + format_number(percent) + " is not in [0, 100]");
  require(points.normals.empty() || points.normals.size() == points.positions.size(),
          "thin_points: normal count differs from point count");
  std::vector<std::uint32_t> inside = inside_indices(points, secondary, ctx);
  const auto remove =
      static_cast<std::size_t>(std::floor(percent / 100.0 * double(inside.size()) + 0.5));
  // A partial Fisher-Yates shuffle: the first `remove` entries are a uniform random subset.
  Rng rng(seed);
  for (std::size_t i = 0; i < remove; ++i) {
    const std::size_t j = i + rng.below(inside.size() - i);
    std::swap(inside[i], inside[j]);
  }
  std::vector<std::uint8_t> removed(points.positions.size(), 0);
  for (std::size_t i = 0; i < remove; ++i) removed[inside[i]] = 1;
  PointSet out;
  for (std::size_t i = 0; i < points.positions.size(); ++i) {
    if (removed[i] != 0) continue;
    out.positions.push_back(points.positions[i]);
    if (!points.normals.empty()) out.normals.push_back(points.normals[i]);
  }
  return out;
}

}  // namespace ramiform
