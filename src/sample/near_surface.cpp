// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Points outside and near the surface, iso - epsilon < f < iso (Kochhar 2010, Application of
// implicit methods to the interactive modeling of trees, M.Sc. thesis, University of Calgary,
// §6.2): projection by default, or the thesis's rejection with its two speed-ups, the field
// cache (§6.2.2) and Lane's grid (§6.2.3).
#include <algorithm>
#include <optional>

#include "ramiform/sample/point_sets.h"
#include "sample/common.h"
#include "sample/dart.h"
#include "sample/field_cache.h"
#include "sample/lane.h"
#include "sample/option_checks.h"
#include "sample/projection.h"
#include "sample/region.h"

namespace ramiform {

using namespace sample_detail;

namespace {

/// True when no field bound on the six slabs between `g` and a box grown from it by `far`
/// exceeds `floor_value`.
bool slabs_clear(const Field& field, const Aabb& g, const Vec3& far, double floor_value) {
  const Aabb big(g.min() - far, g.max() + far);
  for (int a = 0; a < 3; ++a) {
    for (int side = 0; side < 2; ++side) {
      Aabb slab = big;
      if (side == 0) {
        slab.max()[a] = g.min()[a];
      } else {
        slab.min()[a] = g.max()[a];
      }
      if (!(field.bound(slab).hi <= floor_value)) return false;
    }
  }
  return true;
}

/// The box holding every point with f > iso - epsilon: bounds() grown in eighths of its
/// diagonal until the field's bound on the six slabs from the box out to a far box is
/// <= iso - epsilon (one diagonal when eight steps do not suffice).
Aabb band_box(const Field& field, double epsilon) {
  const Aabb b = field.bounds();
  if (b.isEmpty()) return b;
  check_box(b, "sample_near_surface");
  const double diag = std::max(b.sizes().norm(), 1e-300);
  const double floor_value = field.iso() - epsilon;
  const Vec3 far = Vec3::Constant(1000.0 * diag);
  for (int step = 0; step <= 8; ++step) {
    Aabb g = b;
    const Vec3 grow = Vec3::Constant(step * diag / 8.0);
    g.min() -= grow;
    g.max() += grow;
    if (slabs_clear(field, g, far, floor_value)) return g;
  }
  Aabb g = b;
  g.min() -= Vec3::Constant(diag);
  g.max() += Vec3::Constant(diag);
  return g;
}

PointSet near_by_projection(const Field& field, const NearSurfaceOptions& options, const Aabb& box,
                            const Target& band, std::uint64_t seed, Context* ctx, SampleStats& st) {
  if (options.count == 0) return {};
  ProjectSpec spec;
  spec.band = band;
  spec.max_step = box.isEmpty() ? 0.0 : box.sizes().maxCoeff() / kRegionBand;
  spec.width = options.project_width > 0.0
                   ? options.project_width
                   : automatic_project_width(field, box, band, spec.max_step, seed, ctx);
  spec.min_distance = options.min_distance;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  const Region region(field, box, wide_band(band, spec.width), kRegionBand, ctx, kProjectTop);
  return run_project(field, region, box, spec, seed, ctx, st);
}

PointSet near_by_lane_grid(const Field& field, const NearSurfaceOptions& options, const Aabb& box,
                           const Target& band, const FieldCache* cache, std::uint64_t seed,
                           Context* ctx, SampleStats& st) {
  LaneSpec spec;
  spec.target = band;
  if (options.min_distance > 0.0) spec.kernel = LaneKernel::disk(options.min_distance);
  spec.grid = options.grid;
  spec.prune = options.prune;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  spec.cache = cache;
  return run_lane(field, box, spec, seed, ctx, st);
}

PointSet near_by_rejection(const Field& field, const NearSurfaceOptions& options, const Aabb& box,
                           const Target& band, const FieldCache* cache, std::uint64_t seed,
                           Context* ctx, SampleStats& st) {
  const Region region(field, box, band, options.prune ? kRegionBand : 0, ctx);
  DartSpec spec;
  spec.target = band;
  spec.min_distance = options.min_distance;
  spec.count = options.count;
  spec.max_attempts = attempt_budget(options.max_attempts, options.count);
  spec.cache = cache;
  return run_dart(field, region, box, spec, seed, ctx, st);
}

}  // namespace

PointSet sample_near_surface(const Field& field, const NearSurfaceOptions& options,
                             std::uint64_t seed, Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_near_surface");
  check_point_memory(options.count, ctx, "sample_near_surface");
  StatsScope scope(&field, stats);
  const Aabb box = options.box.isEmpty() ? band_box(field, options.epsilon) : options.box;
  check_box(box, "sample_near_surface");
  const Target band{field.iso() - options.epsilon, field.iso()};
  std::optional<FieldCache> cache;
  if (options.use_cache && !box.isEmpty() && box.sizes().maxCoeff() > 0.0) {
    const double cell =
        options.cache_cell > 0.0 ? options.cache_cell : box.sizes().maxCoeff() / 64.0;
    cache.emplace(field, box, cell, band, options.cache_tolerance, ctx);
  }
  const FieldCache* cache_ptr = cache ? &*cache : nullptr;
  // Projection changes the distribution slightly; the cache and Lane's grid (and prune = false)
  // are the thesis's rejection variants, kept as they were.
  const bool project = options.method == NearSurfaceOptions::Method::kProject &&
                       !options.use_cache && !options.use_lane_grid && options.prune;
  PointSet out;
  if (project) {
    out = near_by_projection(field, options, box, band, seed, ctx, scope.stats);
  } else if (options.use_lane_grid) {
    out = near_by_lane_grid(field, options, box, band, cache_ptr, seed, ctx, scope.stats);
  } else {
    out = near_by_rejection(field, options, box, band, cache_ptr, seed, ctx, scope.stats);
  }
  scope.stats.points = out.size();
  return out;
}

}  // namespace ramiform
