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
#include <map>
#include <mutex>
#include <system_error>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

namespace fs = std::filesystem;

std::string errno_text(int err) { return err != 0 ? std::string(": ") + std::strerror(err) : ""; }

[[noreturn]] void fail(const std::string& path, const std::string& problem, int err) {
  throw Failure("cannot write '" + path + "': " + problem + errno_text(err));
}

// "." + name + ".tmp-PID-COUNTER-STAMP" in `dir`: a different name on every call in this
// process; another process's file of that name makes O_EXCL or linkat fail with EEXIST.
fs::path temporary_name(const fs::path& dir, const std::string& name, int attempt) {
  static std::atomic<unsigned> counter{0};
  const auto stamp =
      static_cast<unsigned long long>(std::chrono::steady_clock::now().time_since_epoch().count());
  char suffix[96];
  std::snprintf(suffix, sizeof suffix, ".tmp-%ld-%u-%llx", static_cast<long>(::getpid()),
                counter.fetch_add(1), stamp + static_cast<unsigned long long>(attempt));
  return dir / ("." + name + suffix);
}

// Creates the temporary file exclusively (O_EXCL), so two writers never share one; mode 0666
// lets the process umask decide the final permissions, as for any ordinary new file.
fs::path create_temporary(const std::string& path, const fs::path& dir, const std::string& name) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    fs::path candidate = temporary_name(dir, name, attempt);
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

// Flushes the file's data to the device so that publishing never shows an empty file after a
// crash. A file system that cannot sync (EINVAL, e.g. some pseudo file systems) is not an error.
int sync_fd(int fd) {
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) return errno;
  return 0;
}

int sync_file(const fs::path& p) {
  const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  const int err = sync_fd(fd);
  ::close(fd);
  return err;
}

std::ios::openmode open_flags(FileMode mode) {
  std::ios::openmode flags = std::ios::out | std::ios::trunc;
  if (mode == FileMode::kBinary) flags |= std::ios::binary;
  return flags;
}

// Runs `writer` and checks that every byte reached the file.
void write_stream(const std::string& path, std::ofstream& out,
                  const std::function<void(std::ostream&)>& writer) {
  writer(out);
  errno = 0;
  out.flush();
  if (!out) fail(path, "write error", errno);
  out.close();
  if (out.fail()) fail(path, "write error while closing", errno);
}

// An owned file descriptor.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  [[nodiscard]] int get() const { return fd_; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }

 private:
  int fd_;
};

// Unnamed files (Linux O_TMPFILE): the content is written to a file that has no name in any
// directory until it is complete, and is then linked under its name (linkat through
// /proc/self/fd). A process killed while writing, SIGKILL included, leaves nothing behind: the
// kernel frees the unnamed file with the process's last descriptor of it.

std::string proc_fd_path(int fd) { return "/proc/self/fd/" + std::to_string(fd); }

// An unnamed file in `dir`, open for writing, or -1 when the system or the file system has no
// O_TMPFILE (EOPNOTSUPP; EISDIR on kernels before 3.11; EINVAL) or it fails for another reason
// (the named temporary file then reports that error). Mode 0666: the umask decides the final
// permissions, as for the named temporary file.
int open_unnamed(const fs::path& dir) {
#if defined(__linux__) && defined(O_TMPFILE)
  return ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
#else
  (void)dir;
  return -1;
#endif
}

// Links the complete unnamed file `fd` under `target`, replacing an existing target atomically:
// directly when the target does not exist, else under a temporary name that is renamed over it
// (linkat never replaces a file). Only that temporary name, for the moment between link and
// rename, can outlive a SIGKILL; it is registered, so a stop signal removes it. `path` names
// the output in messages.
void link_unnamed(const std::string& path, int fd, const fs::path& target) {
  const std::string source = proc_fd_path(fd);
  if (::linkat(AT_FDCWD, source.c_str(), AT_FDCWD, target.c_str(), AT_SYMLINK_FOLLOW) == 0) return;
  if (errno != EEXIST) fail(path, "cannot link the written file", errno);
  const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string name = target.filename().string();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path tmp = temporary_name(dir, name, attempt);
    register_staged_file(tmp.string());
    if (::linkat(AT_FDCWD, source.c_str(), AT_FDCWD, tmp.c_str(), AT_SYMLINK_FOLLOW) != 0) {
      const int err = errno;
      unregister_staged_file(tmp.string());
      if (err == EEXIST) continue;
      fail(path, "cannot link the written file", err);
    }
    if (::rename(tmp.c_str(), target.c_str()) != 0) {
      const int err = errno;
      ::unlink(tmp.c_str());
      unregister_staged_file(tmp.string());
      fail(path, "cannot rename temporary file", err);
    }
    unregister_staged_file(tmp.string());
    return;
  }
  fail(path, "cannot find a free temporary file name in '" + dir.string() + "'", 0);
}

// Held files (hold_file): by path, under one lock.
struct HeldFile {
  int fd = -1;           // the content last written, in an unnamed file; -1: none or named
  bool written = false;  // a write completed: its content is under fd, or (fd < 0) the path
  bool shown = false;    // fd is also linked under the path (show_held_file)
};

std::mutex held_mutex;

std::map<std::string, HeldFile>& held_files() {
  static auto* files = new std::map<std::string, HeldFile>();  // never destroyed: used to exit
  return *files;
}

// Forgets the content `held` had: closes its unnamed file, removes its name. Lock held.
void clear_held(const std::string& path, HeldFile& held) noexcept {
  if (held.written && (held.fd < 0 || held.shown)) ::unlink(path.c_str());
  if (held.fd >= 0) ::close(held.fd);
  held = HeldFile{};
}

// Whether `path` is held and, if so, whether its next content may be an unnamed file (at most
// kMaxStagedFiles held files keep a descriptor open).
struct HeldState {
  bool held = false;
  bool unnamed_allowed = true;
};

HeldState held_state(const std::string& path) {
  const std::lock_guard lock(held_mutex);
  const auto& files = held_files();
  if (files.count(path) == 0) return {};
  int open_fds = 0;
  for (const auto& [p, h] : files) open_fds += h.fd >= 0 ? 1 : 0;
  return {true, open_fds < kMaxStagedFiles};
}

// Records a completed write of held `path`: the unnamed file `fd`, or (fd < 0) the file now
// under `path` itself.
void keep_held(const std::string& path, int fd) {
  const std::lock_guard lock(held_mutex);
  auto& files = held_files();
  const auto it = files.find(path);
  if (it == files.end()) {  // dropped while it was written
    if (fd >= 0) {
      ::close(fd);
    } else {
      ::unlink(path.c_str());
    }
    return;
  }
  HeldFile& held = it->second;
  if (fd >= 0) {
    clear_held(path, held);
  } else {  // the rename replaced whatever was under the path
    if (held.fd >= 0) ::close(held.fd);
  }
  held = {fd, true, false};
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
  const HeldState state = held_state(path);

  if (state.unnamed_allowed) {
    Fd unnamed(open_unnamed(dir));
    if (unnamed.get() >= 0) {
      // A second descriptor of the same file for the stream (its buffering, seeking and error
      // states are std::ofstream's); fails only without /proc, and then so would linkat.
      std::ofstream out(proc_fd_path(unnamed.get()), open_flags(mode));
      if (out) {
        write_stream(path, out, writer);
        if (const int err = sync_fd(unnamed.get()); err != 0) fail(path, "cannot sync", err);
        if (state.held) {
          keep_held(path, unnamed.release());
        } else {
          link_unnamed(path, unnamed.get(), target);
        }
        return;
      }
    }
  }

  const fs::path tmp = create_temporary(path, dir, name);
  register_staged_file(tmp.string());
  try {
    std::ofstream out(tmp, open_flags(mode));
    if (!out) fail(path, "cannot open temporary file '" + tmp.string() + "'", errno);
    write_stream(path, out, writer);
    if (const int err = sync_file(tmp); err != 0) fail(path, "cannot sync", err);
    if (::rename(tmp.c_str(), target.c_str()) != 0)
      fail(path, "cannot rename temporary file", errno);
  } catch (...) {
    remove_quietly(tmp);
    unregister_staged_file(tmp.string());
    throw;
  }
  unregister_staged_file(tmp.string());
  if (state.held) keep_held(path, -1);
}

void hold_file(const std::string& path) {
  const std::lock_guard lock(held_mutex);
  if (held_files().try_emplace(path).second) register_staged_file(path);
}

void publish_held_file(const std::string& path, const std::string& target) {
  const std::lock_guard lock(held_mutex);
  auto& files = held_files();
  const auto it = files.find(path);
  if (it == files.end() || !it->second.written) {
    throw Failure("cannot move '" + path + "' to '" + target + "': nothing was written");
  }
  HeldFile& held = it->second;
  if (held.fd >= 0) {
    link_unnamed(target, held.fd, fs::path(target));
    if (held.shown) ::unlink(path.c_str());
    ::close(held.fd);
  } else if (::rename(path.c_str(), target.c_str()) != 0) {
    const int err = errno;
    throw Failure("cannot move '" + path + "' to '" + target + "'" + errno_text(err));
  }
  files.erase(it);
  unregister_staged_file(path);
}

void drop_held_file(const std::string& path) noexcept {
  {
    const std::lock_guard lock(held_mutex);
    auto& files = held_files();
    const auto it = files.find(path);
    if (it == files.end()) return;
    clear_held(path, it->second);
    files.erase(it);
  }
  unregister_staged_file(path);
}

void show_held_file(const std::string& path) {
  const std::lock_guard lock(held_mutex);
  auto& files = held_files();
  const auto it = files.find(path);
  if (it == files.end() || it->second.fd < 0 || it->second.shown) return;
  // A copy, not a link: an unnamed file that was linked once and unlinked again can never be
  // linked again (the kernel clears I_LINKABLE), so the held file itself keeps no name until it
  // is published. A leftover file under the private staging name is replaced.
  std::error_code ec;
  fs::copy_file(proc_fd_path(it->second.fd), path, fs::copy_options::overwrite_existing, ec);
  if (ec) {
    remove_quietly(path);
    throw Failure("cannot read back '" + path + "': " + ec.message());
  }
  it->second.shown = true;
}

void hide_held_file(const std::string& path) noexcept {
  const std::lock_guard lock(held_mutex);
  auto& files = held_files();
  const auto it = files.find(path);
  if (it == files.end() || it->second.fd < 0 || !it->second.shown) return;
  ::unlink(path.c_str());
  it->second.shown = false;
}

HeldOutputs::~HeldOutputs() {
  for (const auto& [staged, target] : outputs_) drop_held_file(staged);
}

std::string HeldOutputs::add(const std::string& target) {
  for (const auto& [staged, t] : outputs_) {
    if (t == target) return staged;
  }
  const std::filesystem::path path(target);
  const std::filesystem::path staged =
      path.parent_path() /
      (".rf-held-" + std::to_string(outputs_.size()) + "-" + path.filename().string());
  hold_file(staged.string());
  outputs_.emplace_back(staged.string(), target);
  return staged.string();
}

void HeldOutputs::publish() {
  while (!outputs_.empty()) {
    const auto& [staged, target] = outputs_.front();
    publish_held_file(staged, target);
    outputs_.erase(outputs_.begin());
  }
}

}  // namespace ramiform
