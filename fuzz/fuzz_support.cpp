// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "fuzz_support.h"

#include <unistd.h>

#include <cstdlib>
#include <system_error>

namespace ramiform::fuzz {

namespace fs = std::filesystem;

namespace {

void remove_scratch() {
  std::error_code ec;
  fs::remove_all(scratch_dir(), ec);
}

}  // namespace

const fs::path& scratch_dir() {
  // Never destroyed: the atexit handler that removes it runs after static destructors.
  static const fs::path* const dir = [] {
    std::error_code ec;
    // A file written and read back on every execution: on a disk-backed /tmp the block writes
    // cost ten times the harness itself (measured: 1.8 k against 25 k executions per second for
    // curve2), so without an explicit TMPDIR the scratch goes to the RAM-backed /dev/shm.
    fs::path base;
    const char* tmpdir = std::getenv("TMPDIR");
    if ((tmpdir == nullptr || *tmpdir == '\0') && ::access("/dev/shm", W_OK | X_OK) == 0) {
      base = "/dev/shm";
    } else {
      base = fs::temp_directory_path(ec);
      if (ec) base = "/tmp";
    }
    fs::path d = base / ("ramiform-fuzz-" + std::to_string(::getpid()));
    fs::remove_all(d, ec);
    fs::create_directories(d, ec);
    if (ec) {
      std::fprintf(stderr, "fuzz: cannot create %s: %s\n", d.c_str(), ec.message().c_str());
      std::abort();
    }
    auto* kept = new fs::path(std::move(d));
    std::atexit(remove_scratch);
    return kept;
  }();
  return *dir;
}

bool verbose() {
  static const bool on = std::getenv("RAMIFORM_FUZZ_VERBOSE") != nullptr;
  return on;
}

void write_file(const fs::path& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  bool ok = f != nullptr && (size == 0 || std::fwrite(data, 1, size, f) == size);
  if (f != nullptr && std::fclose(f) != 0) ok = false;
  if (!ok) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}

void finding(const std::string& what) {
  std::fprintf(stderr, "ramiform fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace ramiform::fuzz
