// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// A seeded random number generator that yields the same numbers on every platform and
/// compiler: xoshiro256** seeded through SplitMix64, with its own integer-to-real conversions
/// (the standard library's distributions are implementation-defined and are not used).

#include <cstdint>

namespace ramiform {

/// Deterministic random numbers. Copyable; a copy continues the same sequence independently.
class Rng {
 public:
  /// Seeds the generator; equal seeds give equal sequences everywhere.
  explicit Rng(std::uint64_t seed = 0);

  /// Next raw 64-bit value.
  std::uint64_t next_u64();
  /// Uniform double in [0, 1) with 53 random bits.
  double uniform();
  /// Uniform double in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n); `n` must be > 0 (unbiased, Lemire's method).
  std::uint64_t below(std::uint64_t n);
  /// Standard normal sample (Marsaglia's polar method; uses std::log and std::sqrt).
  double normal();

  /// An independent generator for sub-stream `index` (e.g. one per parallel chunk), so results
  /// do not depend on how work is split among threads.
  [[nodiscard]] Rng split(std::uint64_t index) const;

 private:
  std::uint64_t s_[4];
};

}  // namespace ramiform
