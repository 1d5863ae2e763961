// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The inside samplers, each a thin set-up of one of the engines: dart throwing (sample/dart.h)
// or Lane's method (sample/lane.h). Stratified sampling, the near-surface band, meshes,
// thinning and the props entry point have files of their own.
#include "ramiform/core/portable_math.h"
#include "ramiform/sample/point_sets.h"

#include <cmath>

#include "sample/common.h"
#include "sample/dart.h"
#include "sample/lane.h"
#include "sample/option_checks.h"
#include "sample/region.h"

namespace ramiform {

using namespace sample_detail;

namespace {

/// The dart-throwing spec of an inside sampler: the target f > iso and the attempt budget.
DartSpec inside_spec(const Field& field, std::size_t count, std::size_t max_attempts) {
  DartSpec spec;
  spec.target = inside_target(field);
  spec.count = count;
  spec.max_attempts = attempt_budget(max_attempts, count);
  return spec;
}

}  // namespace

PointSet sample_uniform(const Field& field, const UniformOptions& options, std::uint64_t seed,
                        Context* ctx, SampleStats* stats) {
  check_point_memory(options.count, ctx, "sample_uniform");
  return sample_in_bounds(field, "sample_uniform", stats, [&](const Aabb& box, SampleStats& st) {
    const DartSpec spec = inside_spec(field, options.count, options.max_attempts);
    const Region region(field, box, spec.target, kRegionInside, ctx);
    return run_dart(field, region, box, spec, seed, ctx, st);
  });
}

PointSet sample_poisson(const Field& field, const PoissonOptions& options, std::uint64_t seed,
                        Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_poisson");
  check_point_memory(options.count, ctx, "sample_poisson");
  return sample_in_bounds(field, "sample_poisson", stats, [&](const Aabb& box, SampleStats& st) {
    DartSpec spec = inside_spec(field, options.count, options.max_attempts);
    const Region region(field, box, spec.target, kRegionInside, ctx);
    double r = options.min_distance;
    if (r == 0.0 && options.count > 0) {
      // About the spacing of `count` points in the volume: dense enough to reach the count.
      r = 0.75 *
          pm::cbrt(estimate_volume(field, region, spec.target, seed, ctx) / double(options.count));
    }
    spec.min_distance = r;
    spec.max_failures = options.max_failures;
    return run_dart(field, region, box, spec, seed, ctx, st);
  });
}

PointSet sample_lane(const Field& field, const LaneOptions& options, std::uint64_t seed,
                     Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_lane");
  check_point_memory(options.count, ctx, "sample_lane");
  return sample_in_bounds(field, "sample_lane", stats, [&](const Aabb& box, SampleStats& st) {
    LaneSpec spec;
    spec.target = inside_target(field);
    spec.kernel = options.kernel;
    spec.grid = options.grid;
    spec.prune = options.prune_grid;
    spec.count = options.count;
    spec.max_attempts = attempt_budget(options.max_attempts, options.count);
    return run_lane(field, box, spec, seed, ctx, st);
  });
}

PointSet sample_field_density(const Field& field, const FieldDensityOptions& options,
                              std::uint64_t seed, Context* ctx, SampleStats* stats) {
  throw_if(check(options, field.iso()), "sample_field_density");
  check_point_memory(options.count, ctx, "sample_field_density");
  const auto body = [&](const Aabb& box, SampleStats& st) {
    DartSpec spec = inside_spec(field, options.count, options.max_attempts);
    const Region region(field, box, spec.target, kRegionInside, ctx);
    const double iso = field.iso();
    const double exponent = options.exponent;
    spec.density = [iso, exponent](double f) { return pm::pow(iso / f, exponent); };
    spec.min_distance = options.min_distance;
    return run_dart(field, region, box, spec, seed, ctx, st);
  };
  return sample_in_bounds(field, "sample_field_density", stats, body);
}

PointSet sample_boundary(const Field& field, const BoundaryOptions& options, std::uint64_t seed,
                         Context* ctx, SampleStats* stats) {
  throw_if(check(options), "sample_boundary");
  check_point_memory(options.count, ctx, "sample_boundary");
  return sample_in_bounds(field, "sample_boundary", stats, [&](const Aabb& box, SampleStats& st) {
    const double iso = field.iso();
    const double width =
        options.width > 0.0 ? options.width : (iso != 0.0 ? 0.2 * std::abs(iso) : 0.2);
    DartSpec spec = inside_spec(field, options.count, options.max_attempts);
    if (options.interior_density > 0.0) {
      const double edge = iso + width;
      const double interior = options.interior_density;
      spec.density = [edge, interior](double f) { return f < edge ? 1.0 : interior; };
    } else {
      spec.target = Target{iso, iso + width};  // the layer alone: prune the deep inside too
    }
    const Region region(field, box, spec.target, kRegionBand, ctx);
    spec.min_distance = options.min_distance;
    return run_dart(field, region, box, spec, seed, ctx, st);
  });
}

}  // namespace ramiform
