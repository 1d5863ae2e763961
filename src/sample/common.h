// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Internal to the sample stage: the pieces every sampler shares — the target set
/// {lo < f < hi}, its classification by a conservative bound, parallel field evaluation, the
/// attempt budget, box checks and the SampleStats bookkeeping.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/sample/point_sets.h"

namespace ramiform::sample_detail {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Candidates per block: the unit of random sub-streams, parallel evaluation and cancellation.
constexpr std::size_t kBlock = 2048;
/// Field evaluations per parallel chunk.
constexpr std::size_t kEvalGrain = 256;
/// Cells of the bound-pruned candidate region along the longest axis, for inside samplers.
constexpr int kRegionInside = 32;
/// Cells of the bound-pruned candidate region along the longest axis, for thin bands.
constexpr int kRegionBand = 128;

/// Values of `points` (one per point) and, when `gradients` is not null, their gradients,
/// evaluated in parallel chunks of kEvalGrain. Resizes the outputs to `points.size()`.
void evaluate_parallel(const Field& field, const std::vector<Vec3>& points,
                       std::vector<double>& values, std::vector<Vec3>* gradients,
                       const Context* ctx);

/// Throws ResourceLimit (core/memory.h) when `count` points, with their normals and the
/// samplers' bookkeeping (about 64 bytes a point), exceed the memory budget of `ctx`; `fn`
/// names the sampler in the message.
void check_point_memory(std::size_t count, const Context* ctx, const std::string& fn);

/// The open set of field values {lo < f < hi} a sampler keeps.
struct Target {
  double lo = -kInf;  ///< exclusive
  double hi = kInf;   ///< exclusive
  /// True when lo < v < hi (false for NaN).
  [[nodiscard]] bool contains(double v) const { return v > lo && v < hi; }
};

/// Inside the surface: f > iso.
[[nodiscard]] Target inside_target(const Field& field);

/// How a box relates to a target set, judged from a conservative bound of the field on it.
enum class CellClass : std::uint8_t {
  kEmpty = 0,    ///< no value of the bound is in the target
  kPartial = 1,  ///< the bound straddles a limit of the target
  kFull = 2,     ///< every value of the bound is in the target
};

/// The class of a box whose field values lie in the interval `b`.
[[nodiscard]] CellClass classify(const Interval& b, const Target& t);

/// Wall-clock seconds since construction.
struct Stopwatch {
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  /// Seconds elapsed since `start`.
  [[nodiscard]] double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
};

/// Fills SampleStats on scope exit from whichever path returns: `stats` is the sampler's
/// working copy; time and field evaluations are added at the end. `out` may be null.
class StatsScope {
 public:
  StatsScope(const Field* field, SampleStats* out);
  ~StatsScope();
  StatsScope(const StatsScope&) = delete;
  StatsScope& operator=(const StatsScope&) = delete;
  SampleStats stats;  ///< counts the sampler updates as it runs

 private:
  const Field* field_;
  SampleStats* out_;
  std::uint64_t evals0_ = 0;
  Stopwatch watch_;
};

/// Throws InvalidArgument naming `what` when a non-empty box has a non-finite corner.
void check_box(const Aabb& box, const std::string& what);

/// The bookkeeping of a sampler over the field's own bounds: checks them as the sampling box
/// (naming `fn`), runs `body(box, stats)` and records the number of points it returns, then
/// fills `*stats` (when not null) on the way out, also when `body` throws.
template <class Body>
PointSet sample_in_bounds(const Field& field, const char* fn, SampleStats* stats, Body&& body) {
  StatsScope scope(&field, stats);
  const Aabb box = field.bounds();
  check_box(box, fn);
  PointSet out = body(box, scope.stats);
  scope.stats.points = out.size();
  return out;
}

/// Throws InvalidArgument(message) unless `ok`.
void require(bool ok, const std::string& message);

/// The candidate budget: `max_attempts`, or 1000 per requested point plus a million when it is 0
/// (capped so that the product cannot overflow).
[[nodiscard]] std::size_t attempt_budget(std::size_t max_attempts, std::size_t count);

}  // namespace ramiform::sample_detail
