// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/numbers.h"

#include <charconv>
#include <cmath>
#include <system_error>

namespace ramiform {

NumberStatus parse_number(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') {
    token.remove_prefix(1);
    // from_chars would take a second sign ("+-1"); a number has one.
    if (!token.empty() && token.front() == '-') return NumberStatus::kMalformed;
  }
  if (token.empty() || token.front() == '+') return NumberStatus::kMalformed;
  if (token.size() > 1 && token.front() == '-' && token[1] == '+') return NumberStatus::kMalformed;
  const char* end = token.data() + token.size();
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(token.data(), end, v);
  if (ec == std::errc::result_out_of_range && ptr == end) {
    // libstdc++ reports underflow as out of range too; a magnitude below the smallest
    // subnormal (negative exponent) is zero, not an error.
    const std::size_t e = token.find_first_of("eE");
    if (e != std::string_view::npos && e + 1 < token.size() && token[e + 1] == '-') {
      value = token.front() == '-' ? -0.0 : 0.0;
      return NumberStatus::kOk;
    }
    return NumberStatus::kOutOfRange;
  }
  if (ec != std::errc() || ptr != end) return NumberStatus::kMalformed;
  if (!std::isfinite(v)) return NumberStatus::kNotFinite;
  value = v;
  return NumberStatus::kOk;
}

NumberStatus parse_number(std::string_view token, std::int64_t& value) {
  if (!token.empty() && token.front() == '+') {
    token.remove_prefix(1);
    if (!token.empty() && token.front() == '-') return NumberStatus::kMalformed;
  }
  if (token.empty() || token.front() == '+') return NumberStatus::kMalformed;
  const char* end = token.data() + token.size();
  std::int64_t v = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), end, v);
  if (ec == std::errc::result_out_of_range) return NumberStatus::kOutOfRange;
  if (ec != std::errc() || ptr != end) return NumberStatus::kMalformed;
  value = v;
  return NumberStatus::kOk;
}

}  // namespace ramiform
