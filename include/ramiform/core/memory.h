// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The memory budget of long operations. An operation whose memory grows with its options (the
/// tetrahedral polygonizer's levels, a marching-cubes grid, a point count, a growth grid)
/// estimates its peak before it allocates and refuses a run that cannot fit with
/// `ResourceLimit` (an InvalidArgument: exit code 2 in the CLI), instead of being killed by the
/// system after minutes of work. The budget is `Context::max_memory()` when the caller set one,
/// else the memory this machine has available at the time of the check.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ramiform/core/context.h"

namespace ramiform {

/// Bytes a new allocation can get now: `MemAvailable` of /proc/meminfo on Linux, the physical
/// memory elsewhere; 0 when unknown.
[[nodiscard]] std::uint64_t available_memory();

/// The budget in bytes: `ctx->max_memory()` when non-null and non-zero, else
/// available_memory(); 0 means unknown (no check).
[[nodiscard]] std::uint64_t memory_budget(const Context* ctx);

/// Throws ResourceLimit when `bytes`, an estimate of the operation's peak memory (a lower bound:
/// the operation needs at least this much), exceeds memory_budget(ctx). The message is
/// "WHAT need at least N GB of memory, more than the budget of M GB (SOURCE); ADVICE", where
/// SOURCE says where the budget came from. A non-finite `bytes` always exceeds the budget.
void check_memory(const Context* ctx, double bytes, const std::string& what,
                  const std::string& advice = "");

/// A size such as "512M", "8G", "1.5GiB", "2e9" or "4096" (bytes). K, M, G, T are powers of
/// 1000 and Ki, Mi, Gi, Ti of 1024; an optional trailing "B" is ignored; case-insensitive.
/// nullopt for anything else, for sizes below 1 byte and above 2^63.
[[nodiscard]] std::optional<std::uint64_t> parse_memory_size(std::string_view text);

/// A byte count for messages: "512 B", "3.2 MB", "90.3 GB" (three significant digits, powers
/// of 1000).
[[nodiscard]] std::string format_bytes(double bytes);

}  // namespace ramiform
