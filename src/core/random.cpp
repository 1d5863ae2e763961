// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/random.h"

#include <cmath>

#include "ramiform/core/portable_math.h"

namespace ramiform {
namespace {

std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30U)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27U)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31U);
}

std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

// Full 64x64 -> 128-bit product in portable C++: returns the high word, stores the low word.
std::uint64_t mul_128(std::uint64_t a, std::uint64_t b, std::uint64_t& low) {
  const std::uint64_t a_lo = a & 0xffffffffULL, a_hi = a >> 32U;
  const std::uint64_t b_lo = b & 0xffffffffULL, b_hi = b >> 32U;
  const std::uint64_t ll = a_lo * b_lo;
  const std::uint64_t lh = a_lo * b_hi;
  const std::uint64_t hl = a_hi * b_lo;
  const std::uint64_t hh = a_hi * b_hi;
  const std::uint64_t mid = (ll >> 32U) + (lh & 0xffffffffULL) + (hl & 0xffffffffULL);
  low = (mid << 32U) | (ll & 0xffffffffULL);
  return hh + (lh >> 32U) + (hl >> 32U) + (mid >> 32U);
}

}  // namespace

Rng::Rng(std::uint64_t seed) {
  std::uint64_t x = seed;
  for (auto& s : s_) s = splitmix64(x);
}

std::uint64_t Rng::next_u64() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17U;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

double Rng::uniform() { return static_cast<double>(next_u64() >> 11U) * 0x1.0p-53; }

std::uint64_t Rng::below(std::uint64_t n) {
  // Lemire's nearly divisionless method with rejection, exact for every n.
  std::uint64_t low = 0;
  std::uint64_t high = mul_128(next_u64(), n, low);
  if (low < n) {
    const std::uint64_t threshold = (0 - n) % n;
    while (low < threshold) high = mul_128(next_u64(), n, low);
  }
  return high;
}

double Rng::normal() {
  for (;;) {
    const double u = 2.0 * uniform() - 1.0;
    const double v = 2.0 * uniform() - 1.0;
    const double s = u * u + v * v;
    if (s > 0.0 && s < 1.0) return u * std::sqrt(-2.0 * pm::log(s) / s);
  }
}

Rng Rng::split(std::uint64_t index) const {
  std::uint64_t x = s_[0] ^ rotl(s_[2], 13) ^ (index * 0xd1b54a32d192ed03ULL);
  Rng child(0);
  for (auto& s : child.s_) s = splitmix64(x);
  return child;
}

}  // namespace ramiform
