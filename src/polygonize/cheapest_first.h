// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the order in which refinement spares edges (refine.cpp, RefineOptions::spare_area).

#include <cstdint>
#include <utility>
#include <vector>

namespace ramiform::detail {

/// Orders `cost` ((cost, edge) pairs, costs finite and >= 0, edges distinct) ascending as far as
/// a walk needs it that takes items in that order while each fits in what is left of `budget`
/// (subtracting it) and stops at the first that does not: the result is a prefix of the fully
/// sorted list that holds that item, or the whole sorted list. The smallest items are picked out
/// by selection, their number growing until they add up to more than twice the budget (so the
/// walk stops among them), and only they are sorted.
void cheapest_first(std::vector<std::pair<double, std::uint32_t>>& cost, double budget);

}  // namespace ramiform::detail
