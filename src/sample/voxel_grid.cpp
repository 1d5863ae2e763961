// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/voxel_grid.h"

namespace ramiform::sample_detail {

std::vector<IndexBox> octants(const IndexBox& b) {
  std::array<std::array<std::int64_t, 3>, 3> cuts{};  // lo, mid, hi per axis
  for (int a = 0; a < 3; ++a) {
    cuts[a] = {b.lo[a], b.lo[a] + (b.hi[a] - b.lo[a] + 1) / 2, b.hi[a]};
  }
  std::vector<IndexBox> children;
  children.reserve(8);
  for (int z = 0; z < 2; ++z) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 2; ++x) {
        IndexBox child{{cuts[0][x], cuts[1][y], cuts[2][z]},
                       {cuts[0][x + 1], cuts[1][y + 1], cuts[2][z + 1]}};
        // An extent of one voxel has an empty upper half.
        if (child.lo[0] < child.hi[0] && child.lo[1] < child.hi[1] && child.lo[2] < child.hi[2]) {
          children.push_back(child);
        }
      }
    }
  }
  return children;
}

IndexBox top_block(const VoxelGrid& grid, const std::array<std::int64_t, 3>& blocks, std::size_t t,
                   std::int64_t top) {
  const auto bx = static_cast<std::int64_t>(t) % blocks[0];
  const auto by = (static_cast<std::int64_t>(t) / blocks[0]) % blocks[1];
  const auto bz = static_cast<std::int64_t>(t) / (blocks[0] * blocks[1]);
  return IndexBox{{bx * top, by * top, bz * top},
                  {std::min(grid.n[0], (bx + 1) * top), std::min(grid.n[1], (by + 1) * top),
                   std::min(grid.n[2], (bz + 1) * top)}};
}

IndexBox neighbourhood(const VoxelGrid& grid, std::int64_t ci, std::int64_t cj, std::int64_t ck,
                       std::int64_t r) {
  IndexBox b{};
  const std::array<std::int64_t, 3> c{ci, cj, ck};
  for (int a = 0; a < 3; ++a) {
    b.lo[a] = std::max<std::int64_t>(0, c[a] - r);
    b.hi[a] = std::min(grid.n[a] - 1, c[a] + r) + 1;
  }
  return b;
}

}  // namespace ramiform::sample_detail
