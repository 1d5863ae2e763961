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

void append_shortest(std::string& out, double value) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, static_cast<std::size_t>(r.ptr - buf));
}

std::string format_shortest(double value) {
  std::string out;
  append_shortest(out, value);
  return out;
}

namespace {

// format_shortest, but whole numbers below 2^53 in plain digits ("10000000", not "1e+07"),
// as a reader of a help text expects them; both read back exactly.
std::string shown(double value) {
  if (!(std::abs(value) < 9007199254740992.0 && value == std::trunc(value))) {
    return format_shortest(value);
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed);
  return std::string(buf, static_cast<std::size_t>(r.ptr - buf));
}

}  // namespace

std::string default_text(double value) { return " (default " + shown(value) + ")"; }

std::string default_text(double value, double min, double max) {
  return " (default " + shown(value) + ", " + shown(min) + "\u2013" + shown(max) + ")";
}

std::string range_text(double min, double max) {
  return "[" + shown(min) + ", " + shown(max) + "]";
}

}  // namespace ramiform
