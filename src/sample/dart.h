// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: dart throwing — candidates uniform in the candidate region,
/// kept when their field value is in the target set, with an optional acceptance density and
/// minimum distance (rejection sampling of Kochhar 2010, *Application of implicit methods to the
/// interactive modeling of trees*, M.Sc. thesis, University of Calgary, §5.1, §6.1, §6.2.1).

#include <cstddef>
#include <cstdint>
#include <functional>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/sample/point_sets.h"
#include "sample/common.h"
#include "sample/field_cache.h"
#include "sample/region.h"

namespace ramiform::sample_detail {

/// What one dart-throwing run keeps and when it stops.
struct DartSpec {
  Target target;
  std::function<double(double)> density;  ///< acceptance probability given f; empty = 1
  double min_distance = 0.0;              ///< 0: no minimum distance (model units)
  std::size_t count = 0;                  ///< points wanted
  std::size_t max_attempts = 0;           ///< candidate budget
  std::size_t max_failures = 0;       ///< consecutive too-close candidates that saturate; 0 = never
  const FieldCache* cache = nullptr;  ///< optional §6.2.2 cache; not owned
  std::uint64_t stream = 0;           ///< sub-stream index of the candidate blocks
};

/// Up to spec.count points from `region` (a pruning of `box`), accepted in candidate order;
/// updates st.attempts and st.saturated.
[[nodiscard]] PointSet run_dart(const Field& field, const Region& region, const Aabb& box,
                                const DartSpec& spec, std::uint64_t seed, Context* ctx,
                                SampleStats& st);

/// The volume of {f in target} estimated from the region's volume and the share of 8192 pilot
/// candidates (stream "pilot" of `seed`) that fall in the target. 0 for an empty region.
[[nodiscard]] double estimate_volume(const Field& field, const Region& region, const Target& target,
                                     std::uint64_t seed, Context* ctx);

}  // namespace ramiform::sample_detail
