// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The one number parser: exact values, every refusal, and independence from the C locale.

#include "ramiform/core/numbers.h"

#include <gtest/gtest.h>

#include <clocale>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "ramiform/core/random.h"

namespace ramiform {
namespace {

NumberStatus status_of(std::string_view token) {
  double v = 0;
  return parse_number(token, v);
}

double value_of(std::string_view token) {
  double v = -12345;
  EXPECT_EQ(parse_number(token, v), NumberStatus::kOk) << token;
  return v;
}

TEST(ParseNumber, DecimalValuesAreExact) {
  EXPECT_EQ(value_of("0"), 0.0);
  EXPECT_EQ(value_of("1.5"), 1.5);
  EXPECT_EQ(value_of("+2.25"), 2.25);
  EXPECT_EQ(value_of("-3e2"), -300.0);
  EXPECT_EQ(value_of("1E-3"), 0.001);
  EXPECT_EQ(value_of(".5"), 0.5);
  EXPECT_EQ(value_of("5."), 5.0);
  // Shortest round-trip texts read back as the same double.
  EXPECT_EQ(value_of("0.1"), 0.1);
  EXPECT_EQ(value_of("1.7976931348623157e308"), std::numeric_limits<double>::max());
  EXPECT_EQ(value_of("5e-324"), std::numeric_limits<double>::denorm_min());
}

TEST(ParseNumber, UnderflowIsSignedZero) {
  const double p = value_of("1e-400");
  const double n = value_of("-1e-400");
  EXPECT_EQ(p, 0.0);
  EXPECT_EQ(n, 0.0);
  EXPECT_FALSE(std::signbit(p));
  EXPECT_TRUE(std::signbit(n));
}

TEST(ParseNumber, Refusals) {
  for (const char* t : {"", "+", "-", "++1", "+-1", "-+1", "1,5", "1.5x", " 1", "1 ", "0x10", "e5",
                        "1e", "--1", "abc"}) {
    EXPECT_EQ(status_of(t), NumberStatus::kMalformed) << "'" << t << "'";
  }
  for (const char* t : {"nan", "NaN", "inf", "-inf", "infinity"}) {
    EXPECT_EQ(status_of(t), NumberStatus::kNotFinite) << t;
  }
  EXPECT_EQ(status_of("1e400"), NumberStatus::kOutOfRange);
  EXPECT_EQ(status_of("-1e400"), NumberStatus::kOutOfRange);
}

TEST(ParseNumber, ValueUntouchedOnFailure) {
  double v = 7;
  EXPECT_NE(parse_number("1.5x", v), NumberStatus::kOk);
  EXPECT_EQ(v, 7);
  std::int64_t i = 7;
  EXPECT_NE(parse_number("9223372036854775808", i), NumberStatus::kOk);
  EXPECT_EQ(i, 7);
}

TEST(ParseNumber, Integers) {
  std::int64_t v = 0;
  EXPECT_EQ(parse_number("+42", v), NumberStatus::kOk);
  EXPECT_EQ(v, 42);
  EXPECT_EQ(parse_number("-9223372036854775808", v), NumberStatus::kOk);
  EXPECT_EQ(v, std::numeric_limits<std::int64_t>::min());
  EXPECT_EQ(parse_number("9223372036854775808", v), NumberStatus::kOutOfRange);
  for (const char* t : {"", "+", "1.0", "1e3", "++1", "+-1", "-+1", "0x1", "12a"}) {
    EXPECT_EQ(parse_number(t, v), NumberStatus::kMalformed) << t;
  }
}

TEST(FormatShortest, ReadsBackExactly) {
  Rng rng(5);
  for (int i = 0; i < 2000; ++i) {
    const double v = std::ldexp(rng.uniform(-1, 1), static_cast<int>(rng.below(200)) - 100);
    double back = 0;
    ASSERT_EQ(parse_number(format_shortest(v), back), NumberStatus::kOk);
    EXPECT_EQ(back, v);
  }
  EXPECT_EQ(format_shortest(0.1), "0.1");
  EXPECT_EQ(format_shortest(2.5), "2.5");
  std::string out = "x=";
  append_shortest(out, 1e-9);
  EXPECT_EQ(out, "x=1e-09");
}

TEST(DefaultText, StatesDefaultsAndRangesAsHelpAndDocsDo) {
  EXPECT_EQ(default_text(0.02), " (default 0.02)");
  EXPECT_EQ(default_text(3, 0, 6), " (default 3, 0\u20136)");
  EXPECT_EQ(default_text(1000, 1, 10000000), " (default 1000, 1\u201310000000)");
  EXPECT_EQ(range_text(2, 1000), "[2, 1000]");
  EXPECT_EQ(range_text(0.001, 1), "[0.001, 1]");
  EXPECT_EQ(range_text(1, 1048576), "[1, 1048576]");
}

// A locale whose decimal separator is a comma does not change what is read (std::stod would).
TEST(ParseNumber, LocaleIndependent) {
  const char* previous = std::setlocale(LC_NUMERIC, nullptr);
  const std::string saved = previous != nullptr ? previous : "C";
  bool switched = false;
  for (const char* name : {"de_DE.UTF-8", "fr_FR.UTF-8", "de_DE", "fr_FR"}) {
    if (std::setlocale(LC_NUMERIC, name) != nullptr) {
      switched = true;
      break;
    }
  }
  EXPECT_EQ(value_of("1.25"), 1.25);
  EXPECT_EQ(status_of("1,25"), NumberStatus::kMalformed);
  std::setlocale(LC_NUMERIC, saved.c_str());
  if (!switched) GTEST_SKIP() << "no comma-decimal locale installed; checked in the C locale only";
}

}  // namespace
}  // namespace ramiform
