// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/field_cache.h"

#include <algorithm>
#include <cmath>

namespace ramiform::sample_detail {

FieldCache::FieldCache(const Field& field, const Aabb& box, double cell, const Target& target,
                       const double tolerance, const Context* ctx)
    : grid_(box, cell), target_(target), tolerance_(tolerance) {
  const std::vector<Leaf> leaves = find_cubes(field, target, ctx);
  cubes_.resize(leaves.size());
  index_.reserve(leaves.size() * 2);
  for (std::size_t c = 0; c < leaves.size(); ++c) {
    index_.emplace(leaves[c].key, static_cast<std::uint32_t>(c));
    cubes_[c].full = leaves[c].full;
  }
  fill_corners(field, leaves, ctx);
}

std::vector<FieldCache::Leaf> FieldCache::find_cubes(const Field& field, const Target& target,
                                                     const Context* ctx) const {
  const auto parts = descend<Leaf>(
      field, grid_, target,
      [&](const IndexBox& b, CellClass c, std::vector<Leaf>& o) {
        for_each_voxel(b, [&](std::int64_t i, std::int64_t j, std::int64_t k) {
          o.push_back({grid_.index(i, j, k), c == CellClass::kFull});
        });
      },
      ctx);
  std::vector<Leaf> leaves;
  for (const auto& p : parts) leaves.insert(leaves.end(), p.begin(), p.end());
  return leaves;
}

void FieldCache::fill_corners(const Field& field, const std::vector<Leaf>& leaves,
                              const Context* ctx) {
  // Corners are shared between cubes: give each distinct corner one slot, so that it is
  // evaluated once.
  std::unordered_map<std::size_t, std::uint32_t> corner_slot;
  std::vector<Vec3> corner_points;
  const auto nx = static_cast<std::size_t>(grid_.n[0]);
  const auto ny = static_cast<std::size_t>(grid_.n[1]);
  std::vector<std::array<std::uint32_t, 8>> slots(leaves.size());
  for (std::size_t c = 0; c < leaves.size(); ++c) {
    if (leaves[c].full) continue;
    const std::size_t key = leaves[c].key;
    const std::size_t i = key % nx, j = (key / nx) % ny, k = key / (nx * ny);
    for (int v = 0; v < 8; ++v) {
      const std::size_t ci = i + (v & 1), cj = j + ((v >> 1) & 1), ck = k + ((v >> 2) & 1);
      const std::size_t ckey = ci + (nx + 1) * (cj + (ny + 1) * ck);
      auto [it, inserted] =
          corner_slot.emplace(ckey, static_cast<std::uint32_t>(corner_points.size()));
      if (inserted) {
        corner_points.push_back(grid_.origin + grid_.h * Vec3(double(ci), double(cj), double(ck)));
      }
      slots[c][static_cast<std::size_t>(v)] = it->second;
    }
  }
  std::vector<double> corner_values;
  evaluate_parallel(field, corner_points, corner_values, nullptr, ctx);
  for (std::size_t c = 0; c < cubes_.size(); ++c) {
    if (cubes_[c].full) continue;
    double lo = kInf, hi = -kInf;
    for (std::size_t v = 0; v < 8; ++v) {
      const double value = corner_values[slots[c][v]];
      cubes_[c].corner[v] = value;
      lo = std::min(lo, value);
      hi = std::max(hi, value);
    }
    // Trilinear interpolation misses the field by more where the corners differ more.
    cubes_[c].slack =
        tolerance_ > 0.0 ? tolerance_ : std::max(target_.hi - target_.lo, 0.25 * (hi - lo));
  }
}

double FieldCache::interpolate(const Cube& cube, const Vec3& t) {
  const auto& v = cube.corner;
  const double x00 = v[0] + t.x() * (v[1] - v[0]);
  const double x10 = v[2] + t.x() * (v[3] - v[2]);
  const double x01 = v[4] + t.x() * (v[5] - v[4]);
  const double x11 = v[6] + t.x() * (v[7] - v[6]);
  const double y0 = x00 + t.y() * (x10 - x00);
  const double y1 = x01 + t.y() * (x11 - x01);
  return y0 + t.z() * (y1 - y0);
}

FieldCache::Verdict FieldCache::classify(const Vec3& p) const {
  std::array<std::int64_t, 3> c{};
  Vec3 t;
  for (int a = 0; a < 3; ++a) {
    const double x = (p[a] - grid_.origin[a]) / grid_.h;
    c[a] = static_cast<std::int64_t>(std::floor(x));
    if (c[a] < 0 || c[a] >= grid_.n[a]) {
      if (c[a] == grid_.n[a] && x <= double(grid_.n[a])) {
        c[a] = grid_.n[a] - 1;  // a point on the far face
      } else {
        return Verdict::kReject;
      }
    }
    t[a] = std::clamp(x - double(c[a]), 0.0, 1.0);
  }
  const auto it = index_.find(grid_.index(c[0], c[1], c[2]));
  if (it == index_.end()) return Verdict::kReject;  // no target point can be in this cube
  const Cube& cube = cubes_[it->second];
  if (cube.full) return Verdict::kAccept;
  const double f = interpolate(cube, t);
  return (f > target_.lo - cube.slack && f < target_.hi + cube.slack) ? Verdict::kEvaluate
                                                                      : Verdict::kReject;
}

bool FieldCache::overlaps(const Aabb& box) const {
  std::array<std::int64_t, 3> lo{}, hi{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max<std::int64_t>(
        0, static_cast<std::int64_t>(std::floor((box.min()[a] - grid_.origin[a]) / grid_.h)));
    hi[a] = std::min<std::int64_t>(
        grid_.n[a] - 1,
        static_cast<std::int64_t>(std::floor((box.max()[a] - grid_.origin[a]) / grid_.h)));
    if (lo[a] > hi[a]) return false;
  }
  for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
      for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        if (index_.count(grid_.index(i, j, k)) != 0) return true;
      }
    }
  }
  return false;
}

}  // namespace ramiform::sample_detail
