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
