// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// A run stopped while outputs are staged leaves nothing in its output directory: SIGTERM and
// SIGINT remove the named staged files and the run dies of the signal (so the caller sees it was
// interrupted); SIGKILL leaves no output and, where Linux has O_TMPFILE, no staged file either,
// because staged files have no name until they are published (io/atomic_file.h).

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cli/cli_run.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"

extern char** environ;

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A script that stages a small mesh, then works for many seconds before it would publish it.
constexpr const char* kSlowScript =
    "sphere s 1\n"
    "save_mesh s s.ply resolution=16\n"
    "sphere crown 10\n"
    "point_set_gen crown uniform count=20000000\n"
    "save_point_set crown pts.txt\n";

// A script with two outputs, the second one large, and more work before it would publish them.
constexpr const char* kTwoOutputScript =
    "sphere s 1\n"
    "save_mesh s a.ply resolution=16\n"
    "sphere crown 10\n"
    "point_set_gen crown uniform count=2000000\n"
    "save_point_set pts.txt crown\n"
    "point_set_gen crown uniform count=20000000\n"
    "save_point_set more.txt crown\n";

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

std::string listing(const fs::path& dir) {
  std::string text;
  for (const std::string& name : names_in(dir)) text += name + " ";
  return text;
}

// True when files in `dir` can be written unnamed (O_TMPFILE), as write_file_atomically does.
bool has_unnamed_files(const fs::path& dir) {
#ifdef O_TMPFILE
  const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
  if (fd < 0) return false;
  ::close(fd);
  return true;
#else
  (void)dir;
  return false;
#endif
}

// The distinct files in `dir` (named or unnamed: "DIR/#123 (deleted)") that process `pid` has
// open, from /proc/PID/fd.
std::set<std::string> files_open_in(pid_t pid, const fs::path& dir) {
  const std::string prefix = fs::canonical(dir).string() + "/";
  std::set<std::string> open;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
    const fs::path target = fs::read_symlink(e.path(), ec);
    if (!ec && target.string().rfind(prefix, 0) == 0) open.insert(target.string());
  }
  return open;
}

// The size of the largest file in `dir` that process `pid` has open (0 when none is).
std::uintmax_t largest_open_in(pid_t pid, const fs::path& dir) {
  const std::string prefix = fs::canonical(dir).string() + "/";
  std::uintmax_t largest = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
    const fs::path target = fs::read_symlink(e.path(), ec);
    if (ec || target.string().rfind(prefix, 0) != 0) continue;
    struct stat st {};
    if (::stat(e.path().c_str(), &st) == 0) {
      largest = std::max(largest, static_cast<std::uintmax_t>(st.st_size));
    }
  }
  return largest;
}

pid_t spawn(std::vector<std::string> args) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  return pid;
}

class KillSafety : public CliDirTest {
 protected:
  // Starts `args`, waits (at most 60 s) until the run has `files` files in `out` open or
  // present (it is writing or holding its outputs) and, with `min_bytes` > 0, one of the files
  // it has open there holds at least that many bytes (it is in the middle of writing), waits
  // `delay` more, then sends `sig` and checks that the run died of it.
  void stop_when_staged(std::vector<std::string> args, const fs::path& out, std::size_t files,
                        int sig, std::chrono::milliseconds delay,
                        std::uintmax_t min_bytes = 0) const;
  // kSlowScript stopped by `sig` once its first output is staged leaves nothing behind.
  void stop_slow_script_with(int sig) const;
};

void KillSafety::stop_when_staged(std::vector<std::string> args, const fs::path& out,
                                  std::size_t files, int sig, std::chrono::milliseconds delay,
                                  std::uintmax_t min_bytes) const {
  const pid_t pid = spawn(std::move(args));
  ASSERT_GT(pid, 0) << "cannot start " << RAMIFORM_BINARY;
  const auto deadline = Clock::now() + std::chrono::seconds(60);
  bool staged = false;
  int status = 0;
  while (!staged && Clock::now() < deadline) {
    staged = files_open_in(pid, out).size() >= files || names_in(out).size() >= files;
    if (staged && min_bytes > 0) staged = largest_open_in(pid, out) >= min_bytes;
    if (!staged) {
      ASSERT_EQ(::waitpid(pid, &status, WNOHANG), 0) << "the run ended first; status " << status;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  if (!staged) ::kill(pid, SIGKILL);
  std::this_thread::sleep_for(delay);
  ASSERT_EQ(::kill(pid, sig), 0);
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(staged) << "the run staged fewer than " << files << " files in 60 s";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run finished before the signal; status " << status;
  EXPECT_EQ(WTERMSIG(status), sig);
}

void KillSafety::stop_slow_script_with(int sig) const {
  const std::string script = write("slow.rf", kSlowScript);
  const fs::path out = path("out");
  fs::create_directories(out);
  stop_when_staged({RAMIFORM_BINARY, "run", script, "--out", out.string(), "--quiet"}, out, 1, sig,
                   std::chrono::milliseconds(100));
  EXPECT_TRUE(names_in(out).empty()) << "left behind: " << listing(out);
}

TEST_F(KillSafety, SigtermLeavesNothingBehind) { stop_slow_script_with(SIGTERM); }
TEST_F(KillSafety, SigintLeavesNothingBehind) { stop_slow_script_with(SIGINT); }
TEST_F(KillSafety, SigkillOfAScriptWithStagedOutputsLeavesNothingWhereLinuxAllows) {
  const fs::path out = path("out");
  fs::create_directories(out);
  if (!has_unnamed_files(out)) GTEST_SKIP() << "no O_TMPFILE on this file system";
  stop_slow_script_with(SIGKILL);
}

// `generate` writes a 240 MB skeleton; SIGKILL while it writes (just after the file is opened,
// and once 16 MB of it are written: a fixed delay is not "later" on a fast disk, where the whole
// file can be written in 300 ms) leaves no output and no staged file, and an existing output
// stays as it was.
TEST_F(KillSafety, SigkillWhileWritingLeavesNoOutputAndNoStagedFile) {
  for (const int mid_write : {0, 1}) {
    for (const bool existing : {false, true}) {
      const fs::path out = path("out-" + std::to_string(mid_write) + (existing ? "-old" : ""));
      fs::create_directories(out);
      const fs::path tree = out / "tree.json";
      if (existing) std::ofstream(tree) << "old";
      stop_when_staged({RAMIFORM_BINARY, "generate", "--segments", "2000000", tree.string()}, out,
                       1, SIGKILL, std::chrono::milliseconds(0),
                       mid_write != 0 ? std::uintmax_t{16} << 20 : 0);
      const std::vector<std::string> left = names_in(out);
      if (existing) {
        EXPECT_EQ(read_file(tree.string()), "old") << "mid-write " << mid_write;
      } else {
        EXPECT_FALSE(fs::exists(tree)) << "mid-write " << mid_write;
      }
      if (has_unnamed_files(out)) {
        EXPECT_EQ(left.size(), existing ? 1u : 0u)
            << "mid-write " << mid_write << ", left behind: " << listing(out);
      } else {
        for (const std::string& name : left) {
          EXPECT_TRUE(name == "tree.json" || name.rfind(".tree.json.tmp-", 0) == 0) << name;
        }
      }
    }
  }
}

// `ramiform run` holds both outputs of a script unnamed until the script succeeded: SIGKILL
// while the second is written, or while both wait to be published, leaves nothing.
TEST_F(KillSafety, SigkillOfAScriptWithTwoOutputsLeavesNothing) {
  const std::string script = write("two.rf", kTwoOutputScript);
  for (const int delay_ms : {0, 1000}) {
    const fs::path out = path("out-" + std::to_string(delay_ms));
    fs::create_directories(out);
    if (!has_unnamed_files(out)) GTEST_SKIP() << "no O_TMPFILE on this file system";
    stop_when_staged({RAMIFORM_BINARY, "run", script, "--out", out.string(), "--quiet"}, out, 2,
                     SIGKILL, std::chrono::milliseconds(delay_ms));
    EXPECT_TRUE(names_in(out).empty())
        << "delay " << delay_ms << " ms, left behind: " << listing(out);
  }
}

// The library itself, in a child process: SIGKILL at a known moment (inside the writer, after
// it has written a megabyte) leaves nothing; held files are unnamed until published.
class AtomicPublish : public CliDirTest {
 protected:
  // Forks a child that runs `work` with a pipe end to write one byte to when it is ready to be
  // killed; kills it then and waits for it.
  template <class Work>
  void kill_child_when_ready(Work work) const {
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      ::close(ready[0]);
      work(ready[1]);
      ::_exit(1);  // not reached: work ends by being killed
    }
    ::close(ready[1]);
    char byte = 0;
    ASSERT_EQ(::read(ready[0], &byte, 1), 1) << "the child died before it was ready";
    ::close(ready[0]);
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(WTERMSIG(status), SIGKILL);
  }
};

// A writer that writes a megabyte, tells the parent, and waits to be killed.
auto blocking_writer(int ready) {
  return [ready](std::ostream& out) {
    out << std::string(1 << 20, 'x');
    out.flush();
    const char byte = 1;
    if (::write(ready, &byte, 1) != 1) ::_exit(2);
    for (;;) ::pause();
  };
}

TEST_F(AtomicPublish, SigkillInsideTheWriterLeavesNoFile) {
  if (!has_unnamed_files(dir_)) GTEST_SKIP() << "no O_TMPFILE on this file system";
  const std::string target = path("out.txt");
  kill_child_when_ready([&](int ready) { write_file_atomically(target, blocking_writer(ready)); });
  EXPECT_TRUE(names_in(dir_).empty()) << "left behind: " << listing(dir_);
}

TEST_F(AtomicPublish, SigkillWithHeldFilesLeavesNoFile) {
  if (!has_unnamed_files(dir_)) GTEST_SKIP() << "no O_TMPFILE on this file system";
  const std::string first = path(".rf-staged-0-a.txt");
  const std::string second = path(".rf-staged-1-b.txt");
  kill_child_when_ready([&](int ready) {
    hold_file(first);
    write_file_atomically(first, [](std::ostream& out) { out << "first"; });
    hold_file(second);
    write_file_atomically(second, blocking_writer(ready));
  });
  EXPECT_TRUE(names_in(dir_).empty()) << "left behind: " << listing(dir_);
}

TEST_F(AtomicPublish, HeldFilesAreUnnamedUntilPublishedAndGetTheUmaskMode) {
  const mode_t old_mask = ::umask(027);
  const bool unnamed = has_unnamed_files(dir_);
  const std::string staged = path(".rf-staged-0-a.txt");
  const std::string target = path("a.txt");
  std::ofstream(target) << "old";
  ::chmod(target.c_str(), 0600);
  hold_file(staged);
  write_file_atomically(staged, [](std::ostream& out) { out << "first"; });
  write_file_atomically(staged, [](std::ostream& out) { out << "second"; });  // last wins
  EXPECT_EQ(names_in(dir_).size(), unnamed ? 1u : 2u) << listing(dir_);
  show_held_file(staged);  // readable under the staging name, for a later command
  EXPECT_EQ(read_file(staged), "second");
  hide_held_file(staged);
  EXPECT_EQ(fs::exists(staged), !unnamed);
  publish_held_file(staged, target);  // replaces the existing target
  EXPECT_EQ(read_file(target), "second");
  EXPECT_EQ(names_in(dir_), std::vector<std::string>{"a.txt"});
  struct stat st {};
  ASSERT_EQ(::stat(target.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);  // a new file's mode: 0666 minus the umask

  const std::string fresh = path("b.txt");  // published without a temporary name
  write_file_atomically(fresh, [](std::ostream& out) { out << "b"; });
  ASSERT_EQ(::stat(fresh.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);

  hold_file(staged);
  write_file_atomically(staged, [](std::ostream& out) { out << "dropped"; });
  drop_held_file(staged);
  EXPECT_THROW(publish_held_file(staged, target), Failure);
  EXPECT_EQ(names_in(dir_).size(), 2u) << listing(dir_);
  EXPECT_EQ(read_file(target), "second");
  ::umask(old_mask);
}

}  // namespace
}  // namespace ramiform::test
