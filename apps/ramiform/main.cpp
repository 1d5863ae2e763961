// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// ramiform command line. Exit codes: 0 ok, 1 usage, 2 bad input, 3 failure; stopped by SIGTERM,
// SIGINT or SIGHUP it removes its staged files and dies of the signal (a shell shows 128 + N).

#include <CLI/CLI.hpp>

#include <malloc.h>
#include <signal.h>

#include <cerrno>
#include <iostream>

#include "commands.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"

namespace {

// A run stopped from outside leaves no staged file (io/atomic_file.h): the unnamed ones vanish
// with the process (so also after SIGKILL), the named ones are removed here. It then ends by the
// same signal with its default action, so the caller sees that it was interrupted.
// errno is kept as the interrupted code had it (ThreadSanitizer runs handlers deferred, so this
// one can return before the signal's default action ends the process).
void on_stop_signal(int sig) {
  const int saved_errno = errno;
  ramiform::remove_staged_files_for_signal();
  ::signal(sig, SIG_DFL);
  ::raise(sig);
  errno = saved_errno;
}

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  for (const int sig : {SIGTERM, SIGINT, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ramiform;
  install_stop_handlers();
  // The polygonizers allocate and free many large buffers. glibc serves blocks above 128 KiB by
  // mmap and returns them at once, so every reuse page-faults afresh (measured: ~14 % of a
  // tets run in the kernel's fault handler). Keep blocks up to 32 MiB on the heap and do not
  // trim it eagerly. (The command used to restart itself with glibc's transparent huge pages,
  // glibc.malloc.hugetlb=1, which helped before these settings; with them, on the 2-core VM of
  // docs/benchmarks.md, 2026-12-06, huge pages cost 0.15-0.55 s more kernel time clearing
  // 2 MiB pages than they saved: the 1,500-segment benchmark tree 2.10-2.19 s without against
  // 2.20-2.63 s with, the demo 5.45 against 5.74-5.78 s, the particle mesh of 1,000 segments
  // 3.36-3.49 against 3.52-3.62 s, archi_Tree_1 5.36-5.64 against 5.61-5.84 s.)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  CLI::App app{"ramiform: skeleton-based implicit surfaces, watertight meshes and line drawings",
               "ramiform"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "ramiform 0.1.0");
  cli::Action action;
  cli::register_mesh(app, action);
  cli::register_check(app, action);
  cli::register_eval(app, action);
  cli::register_demo(app, action);
  cli::register_convert(app, action);
  cli::register_generate(app, action);
  cli::register_run(app, action);
  cli::register_shell(app, action);
  cli::register_grow(app, action);
  cli::register_sample(app, action);
  cli::register_lsystem(app, action);
  cli::register_reconstruct(app, action);
  cli::register_particles(app, action);
  cli::register_draw(app, action);
  cli::register_studio(app, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 1;
  }
  try {
    return action ? action() : 1;
  } catch (const InputError& e) {
    std::cerr << "ramiform: error: " << e.what() << '\n';
    return 2;
  } catch (const InvalidArgument& e) {
    std::cerr << "ramiform: error: " << e.what() << '\n';
    return 2;
  } catch (const Cancelled& e) {
    std::cerr << "ramiform: cancelled\n";
    return 3;
  } catch (const std::bad_alloc&) {
    std::cerr << "ramiform: failure: out of memory\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "ramiform: failure: " << e.what() << '\n';
    return 3;
  }
}
