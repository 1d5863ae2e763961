// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform studio [SCRIPT] [--port N] [--out DIR] [--listen ADDR] [--run-timeout S]
// [--memory-budget SIZE] [--threads N]`: the modeler and viewer in the browser
// (docs/studio_api.md). The script editor beside the 3-D view is the thesis's modeler (Kochhar
// 2010, "Application of implicit methods to the interactive modeling of trees" (M.Sc. thesis),
// §4.1).

#include <signal.h>

#include <iostream>
#include <optional>
#include <string>

#include "commands.h"
#include "common.h"
#include "demo_scene.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "studio/server.h"

namespace ramiform::cli {
namespace {

int run_studio(const studio::StudioOptions& options) {
  // SIGINT and SIGTERM end the server cleanly (exit 0): they are blocked in every thread (the
  // server's threads inherit the mask) and taken here by sigwait.
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGINT);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  studio::StudioServer server(options);
  server.start();
  // The one line that names the token; nothing else ever logs it.
  std::cout << "ramiform studio: " << server.url() << std::endl;
  int sig = 0;
  sigwait(&stop, &sig);
  server.stop();
  return 0;
}

}  // namespace

void register_studio(CLI::App& root, Action& action) {
  auto options = std::make_shared<studio::StudioOptions>();
  CLI::App* c = root.add_subcommand(
      "studio",
      "The modeler and viewer in the browser: serves a script editor, a 3-D view and line "
      "drawings on 127.0.0.1 and prints the URL with its access token (docs/studio_api.md). "
      "Runs until SIGINT or SIGTERM.");
  c->add_option(
      "SCRIPT", options->script_path,
      "the script shown first (default: the demo crown made for editing, examples/studio.rf)");
  c->add_option("--port", options->port, with_default("TCP port; 0 = any free port", options->port))
      ->check(CLI::Range(0, 65535));
  c->add_option("--out", options->out_dir,
                "directory of the runs' outputs, OUT/runs/rN/, created if missing (default "
                "./studio-out)");
  c->add_option("--listen", options->listen,
                "address to listen on (default 127.0.0.1; another one exposes the server, still "
                "behind its token)");
  c->add_option("--run-timeout", options->run_timeout,
                with_default("seconds a run may take before it is stopped", options->run_timeout))
      ->check(CLI::PositiveNumber);
  c->add_option_function<std::string>(
       "--memory-budget",
       [options](const std::string& text) {
         const std::optional<std::uint64_t> bytes = parse_memory_size(text);
         if (!bytes) {
           throw CLI::ValidationError("--memory-budget",
                                      "expected a size such as 512M, 8G or "
                                      "2GiB, got '" +
                                          text + "'");
         }
         options->max_memory = *bytes;
       },
       "memory budget of each run: a step whose estimated peak exceeds it fails the run; e.g. "
       "512M, 8G, 2GiB (default: the memory available when the step starts)")
      ->type_name("SIZE");
  c->add_option("--threads", options->threads,
                with_default("worker threads of each run (0 = all cores)", options->threads))
      ->check(CLI::Range(0, Context::kMaxThreads));
  c->callback([options, &action] {
    action = [options] {
      studio::StudioOptions o = *options;
      o.demo_script = kStudioScene;
      o.version = "ramiform " RAMIFORM_VERSION;
      return run_studio(o);
    };
  });
}

}  // namespace ramiform::cli
