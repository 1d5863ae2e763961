// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/memory.h"

#include <unistd.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <utility>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"

namespace ramiform {

namespace {

std::uint64_t physical_memory() {
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGE_SIZE)
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) {
    return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
  }
#endif
  return 0;
}

// MemAvailable of /proc/meminfo in bytes ("MemAvailable:   24563424 kB"), 0 when absent.
std::uint64_t meminfo_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::string unit;
  std::uint64_t kb = 0;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    if (!(fields >> key >> kb)) continue;
    if (key == "MemAvailable:") return kb * 1024;
  }
  return 0;
}

}  // namespace

std::uint64_t available_memory() {
  const std::uint64_t available = meminfo_available();
  return available > 0 ? available : physical_memory();
}

std::uint64_t memory_budget(const Context* ctx) {
  if (ctx != nullptr && ctx->max_memory() > 0) return ctx->max_memory();
  return available_memory();
}

void check_memory(const Context* ctx, double bytes, const std::string& what,
                  const std::string& advice) {
  const bool set = ctx != nullptr && ctx->max_memory() > 0;
  const std::uint64_t budget = memory_budget(ctx);
  if (budget == 0) return;
  const auto have = static_cast<double>(budget);
  if (bytes <= have) return;
  std::string message =
      what + " need at least " + format_bytes(bytes) + " of memory, more than the budget of " +
      format_bytes(have) +
      (set ? " (the max_memory set for this run)" : " (the memory this machine has available now)");
  if (!advice.empty()) message += "; " + advice;
  throw ResourceLimit(message, bytes, have);
}

std::optional<std::uint64_t> parse_memory_size(std::string_view text) {
  std::size_t end = text.size();
  while (end > 0 && std::isalpha(static_cast<unsigned char>(text[end - 1])) != 0) --end;
  std::string unit;
  for (const char c : text.substr(end)) unit += static_cast<char>(std::tolower(c));
  if (unit.size() > 1 && unit.back() == 'b') unit.pop_back();
  if (unit == "b") unit.clear();
  static constexpr std::array<std::pair<const char*, double>, 9> kUnits = {
      {{"", 1.0},
       {"k", 1e3},
       {"m", 1e6},
       {"g", 1e9},
       {"t", 1e12},
       {"ki", 1024.0},
       {"mi", 1048576.0},
       {"gi", 1073741824.0},
       {"ti", 1099511627776.0}}};
  double scale = 0;
  for (const auto& [name, factor] : kUnits) {
    if (unit == name) scale = factor;
  }
  if (scale == 0) return std::nullopt;
  double number = 0;
  if (parse_number(text.substr(0, end), number) != NumberStatus::kOk) return std::nullopt;
  const double bytes = std::floor(number * scale);
  if (!(bytes >= 1.0) || bytes > 9223372036854775808.0) return std::nullopt;
  return static_cast<std::uint64_t>(bytes);
}

std::string format_bytes(double bytes) {
  static constexpr std::array<const char*, 6> kNames = {"B", "kB", "MB", "GB", "TB", "PB"};
  std::size_t k = 0;
  double v = bytes;
  while (k + 1 < kNames.size() && std::fabs(v) >= 1000.0) {
    v /= 1000.0;
    ++k;
  }
  if (!std::isfinite(v)) return "an unbounded amount";
  char buf[32];
  std::snprintf(buf, sizeof buf, k == 0 ? "%.0f %s" : "%.3g %s", v, kNames[k]);
  return buf;
}

}  // namespace ramiform
