// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Helpers for the io tests: a unique temporary directory, file writing, byte building for
// binary PLY bodies, and catching InputError to check its file and line.

#include <gtest/gtest.h>

#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"

namespace ramiform::io_test {

namespace fs = std::filesystem;

/// A fresh directory under the system temp directory, removed with its content on destruction.
class TempDir {
 public:
  TempDir() {
    static std::atomic<unsigned> counter{0};
    const auto stamp = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = fs::temp_directory_path() /
            ("ramiform-io-test-" + std::to_string(::getpid()) + "-" +
             std::to_string(counter.fetch_add(1)) + "-" + std::to_string(stamp));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  [[nodiscard]] const fs::path& path() const { return path_; }
  [[nodiscard]] std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Names of all entries in the directory, sorted.
  [[nodiscard]] std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_))
      names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  fs::path path_;
};

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Appends the bytes of `value` in little- or big-endian order.
template <typename T>
void put(std::string& out, T value, bool big_endian) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  const bool host_big = std::endian::native == std::endian::big;
  if (big_endian != host_big) std::reverse(b, b + sizeof(T));
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

/// Runs `fn`, which must throw InputError, and returns the error (a default one on failure).
inline InputError catch_input_error(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return InputError("", 0, "wrong exception");
  }
  ADD_FAILURE() << "expected InputError, nothing was thrown";
  return InputError("", 0, "nothing thrown");
}

/// Checks that `fn` throws InputError about `file` at `line` (>0) whose message contains `text`.
#define EXPECT_INPUT_ERROR_AT(stmt, file_name, line_number, text)                          \
  do {                                                                                     \
    const ::ramiform::InputError err_ =                                                    \
        ::ramiform::io_test::catch_input_error([&] { (void)(stmt); });                     \
    EXPECT_EQ(err_.file(), file_name) << err_.what();                                      \
    EXPECT_EQ(err_.line(), static_cast<std::size_t>(line_number)) << err_.what();          \
    EXPECT_NE(std::string(err_.what()).find(file_name), std::string::npos) << err_.what(); \
    EXPECT_NE(std::string(err_.what()).find(text), std::string::npos) << err_.what();      \
  } while (0)

}  // namespace ramiform::io_test
