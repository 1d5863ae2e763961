// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int err) { return err != 0 ? std::string(": ") + std::strerror(err) : ""; }

[[noreturn]] void fail(const std::string& path, const std::string& problem, int err) {
  throw Failure("cannot write '" + path + "': " + problem + errno_text(err));
}

// Creates the temporary file exclusively (O_EXCL), so two writers never share one; mode 0666
// lets the process umask decide the final permissions, as for any ordinary new file.
fs::path create_temporary(const std::string& path, const fs::path& dir, const std::string& name) {
  static std::atomic<unsigned> counter{0};
  const auto stamp =
      static_cast<unsigned long long>(std::chrono::steady_clock::now().time_since_epoch().count());
  for (int attempt = 0; attempt < 100; ++attempt) {
    char suffix[96];
    std::snprintf(suffix, sizeof suffix, ".tmp-%ld-%u-%llx", static_cast<long>(::getpid()),
                  counter.fetch_add(1), stamp + static_cast<unsigned long long>(attempt));
    fs::path candidate = dir / ("." + name + suffix);
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      return candidate;
    }
    if (errno != EEXIST)
      fail(path, "cannot create a temporary file in '" + dir.string() + "'", errno);
  }
  fail(path, "cannot find a free temporary file name in '" + dir.string() + "'", 0);
}

// The staged-file registry: fixed slots, claimed by compare-and-swap, so that a signal handler
// can walk it without locks or allocation. State: 0 free, 1 being written, 2 registered.
struct StagedSlot {
  std::atomic<int> state{0};
  char path[kMaxStagedPath + 1] = {};
};
StagedSlot staged_slots[kMaxStagedFiles];

void remove_quietly(const fs::path& p) {
  std::error_code ec;
  fs::remove(p, ec);
}

// Flushes the file's data to the device so the rename never publishes an empty file after a
// crash. A file system that cannot sync (EINVAL, e.g. some pseudo file systems) is not an error.
int sync_file(const fs::path& p) {
  const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  int err = 0;
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) err = errno;
  ::close(fd);
  return err;
}

}  // namespace

void register_staged_file(const std::string& path) {
  if (path.size() > static_cast<std::size_t>(kMaxStagedPath)) return;
  for (StagedSlot& slot : staged_slots) {
    int expected = 0;
    if (!slot.state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) continue;
    std::memcpy(slot.path, path.c_str(), path.size() + 1);
    slot.state.store(2, std::memory_order_release);
    return;
  }
}

void unregister_staged_file(const std::string& path) {
  for (StagedSlot& slot : staged_slots) {
    if (slot.state.load(std::memory_order_acquire) != 2 || path != slot.path) continue;
    int expected = 2;
    if (slot.state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
      slot.path[0] = '\0';
      slot.state.store(0, std::memory_order_release);
      return;
    }
  }
}

void remove_staged_files_for_signal() noexcept {
  for (StagedSlot& slot : staged_slots) {
    int expected = 2;
    if (slot.state.compare_exchange_strong(expected, 1, std::memory_order_acq_rel)) {
      ::unlink(slot.path);
      slot.path[0] = '\0';
      slot.state.store(0, std::memory_order_release);
    }
  }
}

void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer, FileMode mode) {
  if (path.empty()) fail(path, "the path is empty", 0);
  const fs::path target(path);
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..") fail(path, "the path names no file", 0);
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    fail(path, "directory '" + dir.string() + "' does not exist", 0);
  }
  if (fs::is_directory(target, ec)) fail(path, "it is a directory", 0);

  const fs::path tmp = create_temporary(path, dir, name);
  register_staged_file(tmp.string());
  try {
    std::ios::openmode flags = std::ios::out | std::ios::trunc;
    if (mode == FileMode::kBinary) flags |= std::ios::binary;
    std::ofstream out(tmp, flags);
    if (!out) fail(path, "cannot open temporary file '" + tmp.string() + "'", errno);
    writer(out);
    errno = 0;
    out.flush();
    if (!out) fail(path, "write error", errno);
    out.close();
    if (out.fail()) fail(path, "write error while closing", errno);
    if (const int err = sync_file(tmp); err != 0) fail(path, "cannot sync", err);
    if (::rename(tmp.c_str(), target.c_str()) != 0)
      fail(path, "cannot rename temporary file", errno);
  } catch (...) {
    remove_quietly(tmp);
    unregister_staged_file(tmp.string());
    throw;
  }
  unregister_staged_file(tmp.string());
}

}  // namespace ramiform
