// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// A run stopped by SIGTERM or SIGINT while outputs are staged leaves nothing in its output
// directory and dies of the signal (so the caller sees it was interrupted).

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "cli/cli_run.h"

extern char** environ;

namespace ramiform::test {
namespace {

namespace fs = std::filesystem;

// A script that stages a small mesh, then works for many seconds before it would publish it.
constexpr const char* kSlowScript =
    "sphere s 1\n"
    "save_mesh s s.ply resolution=16\n"
    "sphere crown 10\n"
    "point_set_gen crown uniform count=20000000\n"
    "save_point_set crown pts.txt\n";

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    (void)e;
    ++n;
  }
  return n;
}

class KillSafety : public CliDirTest {
 protected:
  void stop_with(int sig) const;
};

void KillSafety::stop_with(int sig) const {
  const std::string script = write("slow.rf", kSlowScript);
  const fs::path out = path("out");
  fs::create_directories(out);
  std::vector<std::string> args = {RAMIFORM_BINARY, "run",        script,
                                   "--out",         out.string(), "--quiet"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ), 0);
  // Wait until the first output is staged (at most 60 s), then stop the run.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (entries(out) == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GT(entries(out), 0u) << "the script staged nothing";
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(::kill(pid, sig), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run finished before the signal; status " << status;
  EXPECT_EQ(WTERMSIG(status), sig);
  std::string left;
  for (const auto& e : fs::directory_iterator(out)) left += e.path().filename().string() + " ";
  EXPECT_EQ(entries(out), 0u) << "left behind: " << left;
}

TEST_F(KillSafety, SigtermLeavesNothingBehind) { stop_with(SIGTERM); }
TEST_F(KillSafety, SigintLeavesNothingBehind) { stop_with(SIGINT); }

}  // namespace
}  // namespace ramiform::test
