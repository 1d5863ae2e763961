// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// A scene-language test with its own empty directory (input and output), removed afterwards.

#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/script/script.h"
#include "support/fixtures.h"

namespace ramiform::test {

class ScriptDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = temp_dir(std::string(info->test_suite_name()) + "-" + info->name());
    options_.out_dir = dir_.string();
    options_.input_dir = dir_.string();
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Entries in the test's directory.
  [[nodiscard]] std::size_t files() const {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir_),
                                                  std::filesystem::directory_iterator()));
  }
  /// The InputError a script raises (fails the test if it runs).
  InputError error_of(const std::string& text) {
    ScriptSession s(options_);
    try {
      s.run_text(text, "t.rf");
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "script ran without error:\n" << text;
    return InputError("", 0, "none");
  }

  std::filesystem::path dir_;
  ScriptOptions options_;
};

}  // namespace ramiform::test
