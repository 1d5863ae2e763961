// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The memory budget (core/memory.h): size parsing, byte formatting, the budget's source and the
// refusal with its estimate.

#include "ramiform/core/memory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

TEST(MemorySize, ReadsDecimalAndBinaryUnits) {
  EXPECT_EQ(parse_memory_size("4096"), 4096U);
  EXPECT_EQ(parse_memory_size("512M"), 512000000U);
  EXPECT_EQ(parse_memory_size("8G"), 8000000000U);
  EXPECT_EQ(parse_memory_size("8gb"), 8000000000U);
  EXPECT_EQ(parse_memory_size("2GiB"), 2147483648U);
  EXPECT_EQ(parse_memory_size("1.5Gi"), 1610612736U);
  EXPECT_EQ(parse_memory_size("3k"), 3000U);
  EXPECT_EQ(parse_memory_size("1Ti"), 1099511627776U);
  EXPECT_EQ(parse_memory_size("2e9"), 2000000000U);
  EXPECT_EQ(parse_memory_size("100B"), 100U);
}

TEST(MemorySize, RefusesWhatIsNotASize) {
  for (const char* bad :
       {"", "G", "-1G", "0", "0.5", "1X", "1GG", "nan", "inf", "1e30", "1 G", "12MiBs", "G8"}) {
    EXPECT_FALSE(parse_memory_size(bad).has_value()) << bad;
  }
}

TEST(MemorySize, FormatsWithThreeSignificantDigits) {
  EXPECT_EQ(format_bytes(512), "512 B");
  EXPECT_EQ(format_bytes(3.2e6), "3.2 MB");
  EXPECT_EQ(format_bytes(90.2529e9), "90.3 GB");
  EXPECT_EQ(format_bytes(1e3), "1 kB");
  EXPECT_EQ(format_bytes(std::numeric_limits<double>::infinity()), "an unbounded amount");
}

TEST(MemoryBudget, ContextOverridesTheMachine) {
  Context ctx;
  EXPECT_EQ(ctx.max_memory(), 0U);
  EXPECT_EQ(memory_budget(&ctx), available_memory());
  ctx.set_max_memory(123456);
  EXPECT_EQ(memory_budget(&ctx), 123456U);
  EXPECT_EQ(memory_budget(nullptr), available_memory());
  // Linux has /proc/meminfo: the available memory is known, positive and at most physical.
  EXPECT_GT(available_memory(), 0U);
}

TEST(MemoryBudget, RefusesAboveTheBudgetWithTheEstimate) {
  Context ctx;
  ctx.set_max_memory(1000000);
  EXPECT_NO_THROW(check_memory(&ctx, 1e6, "a job"));
  try {
    check_memory(&ctx, 2.5e6, "a job of 7 parts", "use fewer parts");
    ADD_FAILURE() << "2.5 MB within a 1 MB budget";
  } catch (const ResourceLimit& e) {
    EXPECT_EQ(std::string(e.what()),
              "a job of 7 parts need at least 2.5 MB of memory, more than the budget of 1 MB "
              "(the max_memory set for this run); use fewer parts");
    EXPECT_EQ(e.needed(), 2.5e6);
    EXPECT_EQ(e.budget(), 1e6);
  }
  // A ResourceLimit is an InvalidArgument (exit 2 in the CLI), and an unbounded need never fits.
  EXPECT_THROW(check_memory(&ctx, std::numeric_limits<double>::infinity(), "x"), InvalidArgument);
  EXPECT_THROW(check_memory(&ctx, std::nan(""), "x"), ResourceLimit);
  // Without a set budget the machine's available memory is the limit.
  EXPECT_NO_THROW(check_memory(nullptr, 1e6, "a small job"));
  try {
    check_memory(nullptr, 1e18, "an exabyte job");
    ADD_FAILURE() << "an exabyte was accepted";
  } catch (const ResourceLimit& e) {
    EXPECT_NE(std::string(e.what()).find("(the memory this machine has available now)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ramiform
