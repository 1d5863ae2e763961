// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Samples along a ray through an MPU field (internal; used by the lines/ stage's kRays
// visibility, src/lines/visibility.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "ramiform/core/types.h"
#include "ramiform/field/field.h"

namespace ramiform::detail {

/// Evenly spaced samples of a ray: sample k (k < count) is ray_sample(ray, k).
struct RaySamples {
  Vec3 origin = Vec3::Zero();
  Vec3 dir = Vec3::Zero();
  double first = 0;  ///< parameter of sample 0
  double step = 0;   ///< parameter increment between samples (> 0)
  std::uint32_t count = 0;
};

/// Sample k of the ray. The field and its callers both compute the samples through this
/// function, so that they are the same points to the last bit.
inline Vec3 ray_sample(const RaySamples& ray, std::uint32_t k) {
  return ray.origin + (ray.first + static_cast<double>(k) * ray.step) * ray.dir;
}

/// Which samples of `ray` may be inside an MPU field (f > iso), by the field's interval
/// bounds: false when `field` is not an MPU field (make_mpu_field), nothing done. Otherwise
/// `open` receives, ascending and without repeats, every sample the bounds do not prove outside
/// (f ≤ iso); when `stop_inside` is set and the bounds prove some sample inside, the search
/// stops there and `candidate` is that sample (`open` is then incomplete), else candidate = -1.
/// A candidate is proven inside up to rounding in the bounds, so a caller that needs certainty
/// evaluates it, and calls again with stop_inside unset in the (never observed) case it is not.
/// The search walks the octree cells the ray crosses: whole subtrees proven outside (bounds of
/// each leaf cell, computed once with the field) are skipped at once; in the other leaf cells the
/// samples are bounded in halving runs over the local functions of that cell only.
bool mpu_ray_samples(const Field& field, const RaySamples& ray, bool stop_inside,
                     std::int64_t& candidate, std::vector<std::uint32_t>& open);

}  // namespace ramiform::detail
