// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// ramiform command line. Exit codes: 0 ok, 1 usage, 2 bad input, 3 failure.

#include <CLI/CLI.hpp>

#include <malloc.h>

#include <iostream>

#include "commands.h"
#include "ramiform/core/errors.h"

int main(int argc, char** argv) {
  using namespace ramiform;
  // The polygonizers allocate and free many large buffers. glibc serves blocks above 128 KiB by
  // mmap and returns them at once, so every reuse page-faults afresh (measured: ~14 % of a
  // tets run in the kernel's fault handler). Keep blocks up to 32 MiB on the heap and do not
  // trim it eagerly.
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
