// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <algorithm>
#include <cmath>

#include "particles/particle_common.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/field/mpu.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform {
namespace particles_detail {

Aabb root_cube(const Field& field) {
  const Aabb b = field.bounds();
  if (b.isEmpty()) return b;
  if (!is_finite(b.min()) || !is_finite(b.max())) {
    throw InvalidArgument("adaptive_cells: the field's bounds() are not finite (" +
                          field.describe() + "); pass the cells explicitly");
  }
  const Vec3 c = b.center();
  // A margin of 5 % keeps the surface off the root's faces, where probes see only one side.
  const double half = std::max(0.525 * b.sizes().maxCoeff(), 1e-9 * (1.0 + c.norm()));
  return Aabb(c - Vec3::Constant(half), c + Vec3::Constant(half));
}

std::vector<ParticleCell> octree_cells(const Field& field, const ParticleOptions& options,
                                       int min_depth, const Aabb& root, const Aabb& region,
                                       std::vector<CellProbe>* probes, const Context* ctx,
                                       std::size_t max_leaves) {
  std::vector<ParticleCell> leaves;
  if (probes) probes->clear();
  if (root.isEmpty()) return leaves;
  const double iso = field.iso();
  min_depth = std::min(min_depth, options.max_depth);
  std::vector<Aabb> level{root};
  for (int depth = 0; !level.empty(); ++depth) {
    check_cancel(ctx);
    if (ctx != nullptr) {
      ctx->report("particles: cells", static_cast<double>(depth) / (options.max_depth + 1));
    }
    // Keep the cells the surface may cross and that meet the region.
    std::vector<char> keep(level.size(), 0);
    parallel::for_each(
        level.size(), 16,
        [&](std::size_t i) {
          keep[i] = static_cast<char>((region.isEmpty() || level[i].intersects(region)) &&
                                      field.bound(level[i]).straddles(iso));
        },
        ctx);
    std::vector<Aabb> kept;
    for (std::size_t i = 0; i < level.size(); ++i) {
      if (keep[i]) kept.push_back(level[i]);
    }
    std::vector<char> split(kept.size(), 0);
    std::vector<CellProbe> pr;
    if (depth < min_depth) {
      split.assign(kept.size(), 1);
    } else {
      pr = probe_cells(field, kept, ctx);
      std::size_t splitting = 0;
      for (std::size_t i = 0; i < kept.size(); ++i) {
        if (!pr[i].meets()) continue;
        const bool curved =
            pr[i].near_count < kMinFlatProbes || pr[i].spread_deg > options.flatness_deg;
        split[i] = static_cast<char>(depth < options.max_depth && curved);
        splitting += split[i] != 0;
      }
      // A split surface cell has about four surface children. Where that would make more
      // leaves than `max_leaves` (twice the particles asked for), the cells stay as they are:
      // most smaller ones would hold no particle (a thin tree's twigs are curved at every
      // depth, so they would otherwise be split down to max_depth).
      if (max_leaves > 0 && leaves.size() + 4 * splitting > max_leaves) {
        std::fill(split.begin(), split.end(), 0);
      }
      for (std::size_t i = 0; i < kept.size(); ++i) {
        if (!pr[i].meets() || split[i]) continue;
        leaves.push_back({kept[i], depth});
        if (probes) probes->push_back(std::move(pr[i]));
      }
    }
    std::vector<Aabb> children;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (!split[i]) continue;
      const Vec3 lo = kept[i].min(), mid = kept[i].center(), hi = kept[i].max();
      for (int k = 0; k < 8; ++k) {
        const Vec3 a((k & 1) ? mid.x() : lo.x(), (k & 2) ? mid.y() : lo.y(),
                     (k & 4) ? mid.z() : lo.z());
        const Vec3 b((k & 1) ? hi.x() : mid.x(), (k & 2) ? hi.y() : mid.y(),
                     (k & 4) ? hi.z() : mid.z());
        children.emplace_back(a, b);
      }
    }
    level.swap(children);
  }
  return leaves;
}

}  // namespace particles_detail

std::vector<ParticleCell> adaptive_cells(const Field& field, const ParticleOptions& options,
                                         const Context* ctx) {
  particles_detail::validate(options, "adaptive_cells");
  return particles_detail::octree_cells(field, options, particles_detail::kMinDepth,
                                        particles_detail::root_cube(field), Aabb(), nullptr, ctx);
}

std::vector<ParticleCell> field_cells(const Field& field) {
  std::vector<ParticleCell> cells;
  for (const MpuCell& m : mpu_leaf_cells(field)) cells.push_back({m.box, m.depth});
  return cells;
}

PointSet particle_points(const ParticleSystem& system) {
  PointSet points;
  points.positions.reserve(system.particles.size());
  points.normals.reserve(system.particles.size());
  for (const SurfaceParticle& p : system.particles) {
    points.positions.push_back(p.position);
    points.normals.push_back(p.normal);
  }
  return points;
}

}  // namespace ramiform
