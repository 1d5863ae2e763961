// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/region.h"

#include <algorithm>

#include "sample/voxel_grid.h"

namespace ramiform::sample_detail {

Region::Region(const Field& field, const Aabb& box, const Target& target, int resolution,
               const Context* ctx, std::int64_t top) {
  if (box.isEmpty()) return;
  const double longest = box.sizes().maxCoeff();
  if (!(longest > 0.0)) return;
  if (resolution == 0) {
    cells_.push_back({box, false});
    volume_ = box.volume();
    cdf_.push_back(volume_);
    return;
  }
  const VoxelGrid grid(box, longest / resolution);
  const auto parts = descend<Cell>(
      field, grid, target,
      [&](const IndexBox& b, CellClass c, std::vector<Cell>& o) {
        o.push_back({grid.box(b.lo[0], b.lo[1], b.lo[2], b.hi[0], b.hi[1], b.hi[2]),
                     c == CellClass::kFull});
      },
      ctx, top);
  for (const auto& p : parts) cells_.insert(cells_.end(), p.begin(), p.end());
  cdf_.reserve(cells_.size());
  for (const auto& c : cells_) {
    volume_ += c.box.volume();
    cdf_.push_back(volume_);
  }
}

Vec3 Region::draw(Rng& rng, bool& full) const {
  const double u = rng.uniform() * volume_;
  auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  if (it == cdf_.end()) --it;  // u rounded up to the total
  const Cell& c = cells_[static_cast<std::size_t>(it - cdf_.begin())];
  full = c.full;
  const Vec3 t(rng.uniform(), rng.uniform(), rng.uniform());
  return c.box.min() + c.box.sizes().cwiseProduct(t);
}

}  // namespace ramiform::sample_detail
