// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The one number parser of every text format, the scene language and the command line:
/// `std::from_chars`, so it never depends on the locale. Each caller adds its own message (file
/// and line, script line and column, or option name) from the status.

#include <cstdint>
#include <string>
#include <string_view>

namespace ramiform {

/// Outcome of strict number parsing.
enum class NumberStatus {
  kOk,          ///< the whole token is a number
  kMalformed,   ///< not a number, or trailing characters
  kNotFinite,   ///< "nan", "inf" and the like
  kOutOfRange,  ///< too large in magnitude for the type
};

/// Parses the whole token as a decimal floating-point number: an optional leading '+' (not
/// "+-", "++" or "-+"), digits with an optional fraction and exponent. A magnitude below the
/// smallest subnormal reads as (signed) zero; overflow gives kOutOfRange; NaN and infinities
/// give kNotFinite. `value` is set only when the result is kOk.
[[nodiscard]] NumberStatus parse_number(std::string_view token, double& value);

/// Parses the whole token as a decimal integer (an optional leading '+' is accepted).
[[nodiscard]] NumberStatus parse_number(std::string_view token, std::int64_t& value);

/// Appends the shortest decimal text that parse_number reads back as exactly `value`.
void append_shortest(std::string& out, double value);
/// The shortest decimal text that parse_number reads back as exactly `value` ("0.1", "1e-09").
[[nodiscard]] std::string format_shortest(double value);

/// How help texts and messages state an option's default and range, the same in `--help`,
/// the scene language's `help` and the docs: " (default D)", " (default D, MIN–MAX)" and
/// "[MIN, MAX]", every number in its shortest exact form (whole numbers below 2^53 in plain
/// digits: "10000000", not "1e+07").
[[nodiscard]] std::string default_text(double value);
[[nodiscard]] std::string default_text(double value, double min, double max);
[[nodiscard]] std::string range_text(double min, double max);

}  // namespace ramiform
