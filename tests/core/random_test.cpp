// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/random.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <set>
#include <vector>

namespace ramiform {
namespace {

// An independent xoshiro256** seeded through SplitMix64 (Blackman & Vigna's reference code,
// rewritten here), to check the library's generator bit for bit.
class ReferenceXoshiro {
 public:
  explicit ReferenceXoshiro(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& s : s_) {
      x += 0x9e3779b97f4a7c15ULL;
      std::uint64_t z = x;
      z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
      z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
      s = z ^ (z >> 31);
    }
  }
  std::uint64_t next() {
    auto rotl = [](std::uint64_t v, int k) { return (v << k) | (v >> (64 - k)); };
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

 private:
  std::uint64_t s_[4];
};

TEST(Rng, FixedSeedGivesKnownSequence) {
  // Computed once by an independent Python implementation of SplitMix64 + xoshiro256**.
  const std::array<std::uint64_t, 6> seed0 = {0x99ec5f36cb75f2b4ULL, 0xbf6e1f784956452aULL,
                                              0x1a5f849d4933e6e0ULL, 0x6aa594f1262d2d2cULL,
                                              0xbba5ad4a1f842e59ULL, 0xffef8375d9ebcacaULL};
  const std::array<std::uint64_t, 6> seed42 = {0x15780b2e0c2ec716ULL, 0x6104d9866d113a7eULL,
                                               0xae17533239e499a1ULL, 0xecb8ad4703b360a1ULL,
                                               0xfde6dc7fe2ec5e64ULL, 0xc50da53101795238ULL};
  const std::array<std::uint64_t, 6> seed_deadbeef = {
      0xc5555444a74d7e83ULL, 0x65c30d37b4b16e38ULL, 0x54f773200a4efa23ULL,
      0x429aed75fb958af7ULL, 0xfb0e1dd69c255b2eULL, 0x9d6d02ec58814a27ULL};
  Rng a(0), b(42), c(0xdeadbeefULL);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(a.next_u64(), seed0[i]) << i;
    EXPECT_EQ(b.next_u64(), seed42[i]) << i;
    EXPECT_EQ(c.next_u64(), seed_deadbeef[i]) << i;
  }
  // The default seed is 0.
  Rng d;
  EXPECT_EQ(d.next_u64(), seed0[0]);
}

TEST(Rng, MatchesReferenceImplementation) {
  for (std::uint64_t seed : {0ULL, 1ULL, 7ULL, 123456789ULL, ~0ULL}) {
    Rng rng(seed);
    ReferenceXoshiro ref(seed);
    for (int i = 0; i < 10000; ++i) ASSERT_EQ(rng.next_u64(), ref.next()) << seed << " " << i;
  }
}

TEST(Rng, CopyContinuesIndependently) {
  Rng a(5);
  a.next_u64();
  Rng b = a;
  const std::uint64_t x = a.next_u64();
  EXPECT_EQ(b.next_u64(), x);
  a.next_u64();
  a.next_u64();
  ReferenceXoshiro ref(5);
  for (int i = 0; i < 2; ++i) ref.next();  // a's first value and x
  EXPECT_EQ(b.next_u64(), ref.next());
}

TEST(Rng, UniformIsTop53BitsInUnitInterval) {
  Rng rng(99);
  ReferenceXoshiro ref(99);
  double lo = 1.0, hi = 0.0, sum = 0.0;
  constexpr int kN = 200000;
  for (int i = 0; i < kN; ++i) {
    const double u = rng.uniform();
    // 53 random bits: the top 53 bits of the raw value, scaled by 2^-53.
    EXPECT_EQ(u, static_cast<double>(ref.next() >> 11) * 0x1.0p-53);
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    lo = std::min(lo, u);
    hi = std::max(hi, u);
    sum += u;
  }
  EXPECT_LT(lo, 1e-4);
  EXPECT_GT(hi, 1 - 1e-4);
  EXPECT_NEAR(sum / kN, 0.5, 0.005);
}

TEST(Rng, UniformRange) {
  Rng rng(3);
  for (int i = 0; i < 10000; ++i) {
    const double u = rng.uniform(-2.5, 7.0);
    ASSERT_GE(u, -2.5);
    ASSERT_LT(u, 7.0);
  }
}

TEST(Rng, BelowInRangeAndUnbiased) {
  for (std::uint64_t n : {1ULL, 2ULL, 3ULL, 10ULL, 1000ULL, (1ULL << 63) + 5}) {
    Rng rng(n);
    for (int i = 0; i < 2000; ++i) ASSERT_LT(rng.below(n), n);
  }
  // Chi-square on 10 bins, fixed seed: 9 degrees of freedom, 27.88 is the p = 0.001 quantile.
  Rng rng(2024);
  constexpr int kN = 100000;
  std::array<int, 10> bins{};
  for (int i = 0; i < kN; ++i) ++bins[rng.below(10)];
  double chi2 = 0;
  for (int c : bins) {
    const double e = kN / 10.0;
    chi2 += (c - e) * (c - e) / e;
  }
  EXPECT_LT(chi2, 27.88);
  // n = 3 * 2^62 - the case where a modulo reduction would be strongly biased (the lower third
  // would get twice the mass): check the three thirds are equally likely.
  const std::uint64_t big = 3ULL << 62;
  std::array<int, 3> thirds{};
  Rng rng2(77);
  for (int i = 0; i < 30000; ++i) ++thirds[rng2.below(big) / (1ULL << 62)];
  for (int c : thirds) EXPECT_NEAR(c, 10000, 500);
}

TEST(Rng, NormalHasUnitMoments) {
  Rng rng(8);
  constexpr int kN = 200000;
  double s1 = 0, s2 = 0;
  for (int i = 0; i < kN; ++i) {
    const double x = rng.normal();
    ASSERT_TRUE(std::isfinite(x));
    s1 += x;
    s2 += x * x;
  }
  EXPECT_NEAR(s1 / kN, 0.0, 0.01);
  EXPECT_NEAR(s2 / kN, 1.0, 0.02);
}

TEST(Rng, SplitStreamsDifferAndAreDeterministic) {
  const Rng parent(11);
  Rng parent_copy = parent;
  std::set<std::uint64_t> firsts;
  std::vector<std::vector<std::uint64_t>> streams;
  for (std::uint64_t k = 0; k < 16; ++k) {
    Rng s = parent.split(k);
    std::vector<std::uint64_t> v;
    for (int i = 0; i < 8; ++i) v.push_back(s.next_u64());
    firsts.insert(v[0]);
    streams.push_back(v);
  }
  EXPECT_EQ(firsts.size(), 16U);
  for (std::size_t a = 0; a < streams.size(); ++a) {
    for (std::size_t b = a + 1; b < streams.size(); ++b) EXPECT_NE(streams[a], streams[b]);
  }
  // Deterministic, and split() does not advance the parent.
  Rng again = parent.split(3);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(again.next_u64(), streams[3][i]);
  Rng p2 = parent;
  EXPECT_EQ(p2.next_u64(), parent_copy.next_u64());
  // A sub-stream is not the parent's own stream.
  Rng p3 = parent;
  Rng s0 = parent.split(0);
  EXPECT_NE(p3.next_u64(), s0.next_u64());
  // Different parents give different sub-streams for the same index.
  EXPECT_NE(Rng(1).split(0).next_u64(), Rng(2).split(0).next_u64());
}

}  // namespace
}  // namespace ramiform
