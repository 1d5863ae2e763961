// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the vectorized inner loop of skeleton fields (Highway, runtime dispatch). One call
// adds the contributions of a list of primitives to a chunk of points stored as padded SoA.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ramiform::detail {

/// How a primitive's contribution is computed (one mode per field).
enum class PrimitiveMode : int {
  kWyvill = 0,        ///< w k(y), y = d^2 / R^2, compact
  kBlinn = 1,         ///< w exp(-B y) * fade(y / y_cut)
  kMetaball = 2,      ///< w metaball(sqrt(y)), compact
  kInversePower = 3,  ///< w y^(-(alpha-1)/2) * fade(y / y_cut)
  kCauchyPoint = 4,   ///< w / (1 + y)^2 * fade(y / y_cut), y = s^2 d^2 (R = 1/s)
  kCauchySegment = 5, ///< w * closed-form segment integral * fade(d^2 / D^2)
};

/// Structure-of-arrays primitive table. Segment i runs from a_i along the unit direction u_i for
/// length len_i (len 0: a point). Distance modes use R(t) = r0_i + t * dr_i (t in [0, len]).
struct PrimitiveTable {
  std::vector<double> ax, ay, az, ux, uy, uz, len;
  std::vector<double> r0, dr;      ///< radius of influence at a, and its slope per unit length
  std::vector<double> weight;      ///< total multiplier (weight * lambda)
  std::vector<double> s;           ///< Cauchy width s (segments)
  std::vector<double> inv_cut;     ///< 1 / cutoff: in y units (distance modes) or 1/D^2 (segments)

  [[nodiscard]] std::size_t size() const { return ax.size(); }
};

/// Per-field constants of the mode.
struct ModeParams {
  PrimitiveMode mode = PrimitiveMode::kWyvill;
  double shape = 0.0;  ///< Blinn B, inverse-power alpha
  bool fades = false;  ///< apply the C1 fade-out window (infinite kernels)
};

/// Padded SoA chunk of points and accumulators; capacity kChunk (a multiple of every vector width).
inline constexpr std::size_t kChunk = 128;
struct alignas(64) Chunk {
  double px[kChunk], py[kChunk], pz[kChunk];
  double value[kChunk], gx[kChunk], gy[kChunk], gz[kChunk];
  std::size_t padded = 0;  ///< lanes prepared (multiple of 16, <= kChunk), copies of point 0
  std::size_t count = 0;   ///< the real points, the first `count` lanes (<= padded)
};

/// Adds primitives `ids[0..count)` (in that order) to the chunk's accumulators, values always,
/// gradients when `with_gradient`.
void accumulate(const PrimitiveTable& table, const ModeParams& mode, const std::uint32_t* ids,
                std::size_t count, Chunk& chunk, bool with_gradient);

/// The Highway target (an HWY_* bit) that accumulate() dispatches to now: the best one the CPU
/// supports, or the one a test forced with hwy::SetSupportedTargetsForTest.
[[nodiscard]] std::int64_t dispatched_target();

}  // namespace ramiform::detail
