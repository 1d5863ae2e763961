// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Numbers in props values and Lane kernels go through the one number parser (core/numbers.h):
// the values it reads and the messages of what it rejects.
#include <gtest/gtest.h>

#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/sample/point_sets.h"
#include "ramiform/sample/props.h"

namespace ramiform {
namespace {

std::string kernel_error(const std::string& text) {
  try {
    (void)LaneKernel::parse(text);
  } catch (const InvalidArgument& e) {
    return e.what();
  }
  return "";
}

TEST(SampleParsing, KernelWordsSplitAtCommasAndWhitespace) {
  const LaneKernel disk = LaneKernel::parse(" disk\t0.25 ");
  EXPECT_EQ(disk.table, LaneKernel::disk(0.25).table);
  const LaneKernel ring = LaneKernel::parse("ring 0.1,0.3 , 2.5");
  EXPECT_EQ(ring.table, LaneKernel::ring(0.1, 0.3, 2.5).table);
  const LaneKernel table = LaneKernel::parse("table 0 0\n0.2 0.5 0.4 1");
  ASSERT_EQ(table.table.size(), 3U);
  EXPECT_EQ(table.table[1], std::make_pair(0.2, 0.5));
  EXPECT_TRUE(LaneKernel::parse("none").table.empty());
  EXPECT_EQ(LaneKernel::parse("disk 2.5e-1").table, LaneKernel::disk(0.25).table);
  EXPECT_EQ(LaneKernel::parse("disk +0.25").table, LaneKernel::disk(0.25).table);
}

TEST(SampleParsing, KernelRejectsWhatIsNotAFiniteNumber) {
  for (const std::string word :
       {"abc", "nan", "inf", "-inf", "1e999", "0.5x", "0x1p-2", "--1", "+-1", "++1"}) {
    SCOPED_TRACE(word);
    EXPECT_EQ(kernel_error("disk " + word), "kernel: '" + word + "' is not a finite number");
  }
  EXPECT_EQ(kernel_error("disk 1,"), "");  // a trailing comma only separates
  EXPECT_EQ(kernel_error("disk 0.1 0.2"), "kernel 'disk' takes 1 numbers, got 2");
  EXPECT_EQ(kernel_error("table 0 0 1"), "kernel 'table' takes (distance, factor) pairs");
  EXPECT_NE(kernel_error("").find("unknown kernel ''"), std::string::npos);
  EXPECT_NE(kernel_error("blob 1").find("unknown kernel 'blob'"), std::string::npos);
}

std::string props_error(const std::string& text, const std::string& distribution) {
  const Props props = parse_props(text, "p.props");
  try {
    (void)distribution_keys(distribution);
    const PropsReader in(props, distribution_keys(distribution), "distribution");
    (void)in.number("min_distance", 0.0);
    (void)in.count("count", 0);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SampleParsing, PropsNumbersAndCountsUseTheOneParser) {
  const Props props = parse_props(
      "min_distance = 2.5e-1\nmax_failures = +12\nmax_attempts = 0\ncount = 7\n", "p.props");
  const PropsReader in(props, distribution_keys("poisson"), "distribution 'poisson'");
  EXPECT_EQ(in.number("min_distance", 1.0), 0.25);
  EXPECT_EQ(in.count("max_failures", 0), 12U);
  EXPECT_EQ(in.count("max_attempts", 5), 0U);
  EXPECT_EQ(in.count("count", 0), 7U);
  EXPECT_EQ(in.number("absent", 3.5), 3.5);
  EXPECT_EQ(in.count("absent", 9), 9U);
  const Props tiny = parse_props("min_distance = 1e-400\n", "p.props");
  EXPECT_EQ(PropsReader(tiny, {"min_distance"}, "x").number("min_distance", 1.0), 0.0);
}

TEST(SampleParsing, PropsRejectionsKeepTheirMessages) {
  for (const std::string value : {"abc", "nan", "inf", "1e999", "1.5.2", "--1", "1 2"}) {
    SCOPED_TRACE(value);
    const std::string msg = props_error("min_distance = " + value + "\n", "poisson");
    EXPECT_NE(msg.find("min_distance = " + value + ": expected a finite number"), std::string::npos)
        << msg;
  }
  for (const std::string value : {"-1", "1.5", "abc", "1e3", "99999999999999999999", "+-3"}) {
    SCOPED_TRACE(value);
    const std::string msg = props_error("count = " + value + "\n", "poisson");
    EXPECT_NE(msg.find("count = " + value + ": expected a non-negative integer"), std::string::npos)
        << msg;
  }
}

}  // namespace
}  // namespace ramiform
