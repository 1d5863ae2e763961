// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/errors.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace ramiform {
namespace {

TEST(Errors, HierarchyDerivesFromStandardExceptions) {
  static_assert(std::is_base_of_v<std::invalid_argument, InvalidArgument>);
  static_assert(std::is_base_of_v<std::runtime_error, InputError>);
  static_assert(std::is_base_of_v<std::runtime_error, Cancelled>);
  static_assert(std::is_base_of_v<std::runtime_error, Failure>);
  EXPECT_STREQ(InvalidArgument("bad radius -1").what(), "bad radius -1");
  EXPECT_STREQ(Failure("disk full").what(), "disk full");
  EXPECT_STREQ(Cancelled().what(), "cancelled");
}

TEST(Errors, InputErrorWithLine) {
  const InputError e("file", 12, "problem");
  EXPECT_STREQ(e.what(), "file:12: problem");
  EXPECT_EQ(e.file(), "file");
  EXPECT_EQ(e.line(), 12U);
  EXPECT_EQ(e.problem(), "problem");
}

TEST(Errors, InputErrorWithElement) {
  const InputError e("file", "edge", 3, "problem");
  EXPECT_STREQ(e.what(), "file: edge 3: problem");
  EXPECT_EQ(e.file(), "file");
  EXPECT_EQ(e.line(), 0U);
  // The message parts are kept: the problem names the element.
  EXPECT_NE(e.problem().find("problem"), std::string::npos);
  EXPECT_NE(e.problem().find("edge 3"), std::string::npos);
}

TEST(Errors, InputErrorWithoutLineOrFile) {
  const InputError e("tree.swc", 0, "empty file");
  EXPECT_STREQ(e.what(), "tree.swc: empty file");
  EXPECT_EQ(e.line(), 0U);
  const InputError m("", "node", 7, "radius is not finite");
  const std::string what = m.what();
  EXPECT_NE(what.find("node 7: radius is not finite"), std::string::npos) << what;
  EXPECT_TRUE(m.file().empty());
  // Catchable as std::runtime_error with the same message.
  try {
    throw InputError("a.obj", 5, "bad vertex");
  } catch (const std::runtime_error& r) {
    EXPECT_STREQ(r.what(), "a.obj:5: bad vertex");
  }
}

TEST(Errors, FormatNumberIsTheDefaultStreamText) {
  // Messages across the library used to print numbers with a default std::ostream or "%.6g";
  // format_number is both.
  for (const double v : {0.0, -0.0, 1.0, 0.004, -2.5, 1e-300, 2.5e7, 123456789.0, 1.0 / 3.0,
                         std::numeric_limits<double>::infinity(), 5e-324}) {
    std::ostringstream s;
    s << v;
    EXPECT_EQ(format_number(v), s.str()) << v;
  }
  EXPECT_EQ(format_number(0.004), "0.004");
  EXPECT_EQ(format_number(1e-300), "1e-300");
  EXPECT_EQ(format_number(2.5e7), "2.5e+07");
}

}  // namespace
}  // namespace ramiform
