// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// LaneKernel: the radial kernels of Lane and Prusinkiewicz's method (Kochhar 2010, Application
// of implicit methods to the interactive modeling of trees, M.Sc. thesis, University of Calgary,
// §5.2.2, Figures 5.7 and 5.9) and their text form.
#include <algorithm>
#include <cmath>
#include <string_view>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/sample/point_sets.h"

namespace ramiform {

namespace {

/// The words of `text`, separated by commas or ASCII whitespace (a fixed set, so the split
/// never depends on the locale).
std::vector<std::string_view> kernel_words(std::string_view text) {
  constexpr std::string_view kSeparators = " \t\n\v\f\r,";
  std::vector<std::string_view> words;
  std::size_t pos = text.find_first_not_of(kSeparators);
  while (pos != std::string_view::npos) {
    const std::size_t end = std::min(text.find_first_of(kSeparators, pos), text.size());
    words.push_back(text.substr(pos, end - pos));
    pos = text.find_first_not_of(kSeparators, end);
  }
  return words;
}

/// The numbers after the kind; InvalidArgument naming the first word that is not one.
std::vector<double> kernel_numbers(const std::vector<std::string_view>& words) {
  std::vector<double> v;
  for (std::size_t i = 1; i < words.size(); ++i) {
    double x = 0.0;
    if (parse_number(words[i], x) != NumberStatus::kOk) {
      throw InvalidArgument("kernel: '" + std::string(words[i]) + "' is not a finite number");
    }
    v.push_back(x);
  }
  return v;
}

LaneKernel table_kernel(const std::vector<double>& v) {
  if (v.empty() || v.size() % 2 != 0) {
    throw InvalidArgument("kernel 'table' takes (distance, factor) pairs");
  }
  LaneKernel k;
  for (std::size_t i = 0; i < v.size(); i += 2) k.table.emplace_back(v[i], v[i + 1]);
  k.validate();
  return k;
}

}  // namespace

LaneKernel LaneKernel::disk(double radius) {
  LaneKernel k;
  k.table = {{0.0, 0.0}, {radius, 0.0}, {radius, 1.0}};
  k.validate();
  return k;
}

LaneKernel LaneKernel::ring(double zero_radius, double ring_radius, double factor) {
  LaneKernel k;
  k.table = {{0.0, 0.0},
             {zero_radius, 0.0},
             {zero_radius, factor},
             {ring_radius, factor},
             {ring_radius, 1.0}};
  k.validate();
  return k;
}

LaneKernel LaneKernel::parse(const std::string& text) {
  const std::vector<std::string_view> words = kernel_words(text);
  const std::string kind = words.empty() ? std::string() : std::string(words.front());
  const std::vector<double> v = kernel_numbers(words);
  const auto need = [&](std::size_t n) {
    if (v.size() != n) {
      throw InvalidArgument("kernel '" + kind + "' takes " + std::to_string(n) + " numbers, got " +
                            std::to_string(v.size()));
    }
  };
  if (kind == "none") {
    need(0);
    return {};
  }
  if (kind == "disk") {
    need(1);
    return disk(v[0]);
  }
  if (kind == "ring") {
    need(3);
    return ring(v[0], v[1], v[2]);
  }
  if (kind == "table") return table_kernel(v);
  throw InvalidArgument("unknown kernel '" + kind + "' (valid: none, disk R, ring R0 R1 F, " +
                        "table d0 f0 d1 f1 ...)");
}

void LaneKernel::validate() const {
  for (std::size_t i = 0; i < table.size(); ++i) {
    const auto [d, f] = table[i];
    const std::string where = "kernel pair " + std::to_string(i) + " (" + format_number(d) + ", " +
                              format_number(f) + ")";
    if (!std::isfinite(d) || !std::isfinite(f)) throw InvalidArgument(where + ": not finite");
    if (f < 0.0) throw InvalidArgument(where + ": factor must be >= 0");
    if (i == 0 && d != 0.0) throw InvalidArgument(where + ": the first distance must be 0");
    if (i > 0 && d < table[i - 1].first) {
      throw InvalidArgument(where + ": distances must not decrease");
    }
  }
}

double LaneKernel::factor(double d) const {
  if (table.empty() || d >= table.back().first) return 1.0;
  // The last pair whose distance is <= d (at a step the later factor applies).
  const auto it = std::upper_bound(table.begin(), table.end(), d,
                                   [](double x, const auto& pr) { return x < pr.first; });
  const auto& a = *(it - 1);
  const auto& b = *it;
  if (b.first <= a.first) return b.second;
  return a.second + (b.second - a.second) * (d - a.first) / (b.first - a.first);
}

double LaneKernel::zero_radius() const {
  // The kernel is 0 from distance 0 up to the end of its leading run of zero factors.
  double z = 0.0;
  for (std::size_t i = 0; i + 1 < table.size(); ++i) {
    if (table[i].second == 0.0 && table[i + 1].second == 0.0) {
      z = table[i + 1].first;
    } else {
      break;
    }
  }
  return z;
}

double LaneKernel::reach() const { return table.empty() ? 0.0 : table.back().first; }

}  // namespace ramiform
