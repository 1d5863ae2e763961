// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Running the `ramiform` binary (RAMIFORM_BINARY, set by CMake) from the CLI tests, and a
// fixture with a fresh working directory per test.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "support/fixtures.h"

namespace ramiform::test {

/// Exit code and output of one run of the binary.
struct CliRun {
  int code = -1;    // -1 when the binary could not be started or did not exit normally
  std::string out;  // stdout and stderr together
};

/// Runs `RAMIFORM_BINARY args` through the shell (args are not quoted) and collects its output.
/// With `kill_after_seconds` > 0 the run is killed (SIGKILL, code -1) when it takes longer, so
/// that a hang fails a test instead of stalling the suite.
inline CliRun run_cli(const std::string& args, int kill_after_seconds = 0) {
  const std::string limit =
      kill_after_seconds > 0 ? "timeout -s KILL " + std::to_string(kill_after_seconds) + " " : "";
  const std::string cmd = limit + std::string(RAMIFORM_BINARY) + " " + args + " 2>&1";
  CliRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  std::size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// A JSON file (a --stats file) parsed.
inline nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

/// The bytes of a file ("" when it cannot be read).
inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// A test with its own empty directory (test::temp_dir), removed after the test.
class CliDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = temp_dir(std::string("cli-") +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  /// The path of `name` in the test's directory.
  [[nodiscard]] std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Writes `text` to `name` in the test's directory; returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  /// A small Y-fork skeleton file (trunk radius 0.5, branches 0.3); returns its path.
  [[nodiscard]] std::string y_fork() const {
    return write("fork.json",
                 R"({"nodes":[{"position":[0,0,0],"radius":0.5},{"position":[0,0,3],"radius":0.4},)"
                 R"({"position":[-1.5,0,5],"radius":0.3},{"position":[1.5,0,5],"radius":0.3}],)"
                 R"("edges":[[0,1],[1,2],[1,3]]})");
  }
  /// Number of entries in the test's directory.
  [[nodiscard]] std::size_t files_in_dir() const {
    return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir_),
                                                  std::filesystem::directory_iterator()));
  }
  std::filesystem::path dir_;
};

}  // namespace ramiform::test
