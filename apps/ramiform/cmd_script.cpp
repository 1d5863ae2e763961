// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform run SCRIPT [--out DIR] [--seed N] [--set name=value ...] [--allow-any-path]`
// `ramiform shell [--out DIR] [--seed N] [--allow-any-path]`

#include <unistd.h>

#include <iostream>
#include <string>
#include <vector>

#include "commands.h"
#include "common.h"
#include "ramiform/core/errors.h"
#include "ramiform/script/script.h"

namespace ramiform::cli {
namespace {

struct ScriptArgs {
  std::string script;
  std::string out_dir = ScriptOptions{}.out_dir;
  std::uint64_t seed = ScriptOptions{}.seed;
  std::vector<std::string> sets;
  bool allow_any_path = false;
  bool draft = false;
  bool quiet = false;
  CommonOptions common;
};

ScriptOptions script_options(const ScriptArgs& args) {
  ScriptOptions o;
  o.out_dir = args.out_dir;
  o.seed = args.seed;
  o.allow_any_path = args.allow_any_path;
  o.draft = args.draft;
  for (const std::string& s : args.sets) {
    const std::size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw InvalidArgument("--set expects name=value, got '" + s + "'");
    }
    const std::string name = s.substr(0, eq);
    if (o.params.count(name) != 0) throw InvalidArgument("--set " + name + " given twice");
    o.params[name] = s.substr(eq + 1);
  }
  return o;
}

int run_run(const ScriptArgs& args) {
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  const ScriptOptions options = script_options(args);
  ScriptSession session(options, &scope.context());
  std::vector<CommandResult> results;
  std::vector<std::string> written;
  try {
    results = session.run_file(args.script);
    written = session.commit();
  } catch (...) {
    session.discard();
    throw;
  }
  timer.lap("run");
  if (!args.quiet) {
    for (const CommandResult& r : results) {
      if (r.is_report && !r.message.empty()) std::cout << r.message << '\n';
    }
  }
  nlohmann::json stats;
  stats["seconds"] = timer.seconds();
  stats["commands"] = results.size();
  stats["outputs"] = written;
  write_stats(args.common.stats_path, stats);
  return 0;
}

// The interactive command editor (Kochhar 2010, "Application of implicit methods to the interactive
// modeling of trees" (M.Sc. thesis), §4.1): one command per line, each result reported; an error is
// reported and the session goes on. Outputs are committed after every successful command.
int run_shell(const ScriptArgs& args) {
  RunScope scope(args.common);
  ScriptSession session(script_options(args), &scope.context());
  const bool interactive = isatty(STDIN_FILENO) != 0;
  if (interactive)
    std::cout << "ramiform shell: 'help' lists the commands, 'quit' or Ctrl-D ends.\n";
  std::string line;
  std::size_t line_no = 0;
  int errors = 0;
  for (;;) {
    if (interactive) std::cout << "rf> " << std::flush;
    if (!std::getline(std::cin, line)) break;
    ++line_no;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first != std::string::npos) {
      const std::string word = line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
      if (word == "quit" || word == "exit") break;
    }
    try {
      const CommandResult r = session.execute_line(line, "<shell>", line_no);
      session.commit();
      if (!r.message.empty()) std::cout << r.message << '\n';
    } catch (const InputError& e) {
      session.discard();
      ++errors;
      std::cout << "error: " << e.what() << '\n';
    } catch (const InvalidArgument& e) {
      session.discard();
      ++errors;
      std::cout << "error: " << e.what() << '\n';
    }
    std::cout << std::flush;
  }
  if (interactive) std::cout << '\n';
  return errors > 0 && !interactive ? 2 : 0;
}

void add_session_options(CLI::App& c, ScriptArgs& args) {
  c.add_option("--out", args.out_dir, "directory the script's outputs go to (must exist)")
      ->capture_default_str();
  c.add_option("--seed", args.seed,
               with_default("seed of every random choice", static_cast<double>(args.seed)));
  c.add_flag("--allow-any-path", args.allow_any_path, "let outputs be written outside --out");
  c.add_flag("--draft", args.draft,
             "a quick preview: save_mesh meshes coarsely (tets at levels 0, mc at resolution 48 at "
             "most), draw writes nothing");
}

}  // namespace

void register_run(CLI::App& root, Action& action) {
  auto args = std::make_shared<ScriptArgs>();
  CLI::App* c = root.add_subcommand(
      "run",
      "Run a scene script (.rf, see docs/language.md); outputs are written only when the "
      "whole script succeeds.");
  c->add_option("SCRIPT", args->script, "the script file")->required();
  add_session_options(*c, *args);
  c->add_option("--set", args->sets, "override a parameter declared with 'param': name=value")
      ->allow_extra_args(false);
  c->add_flag("--quiet", args->quiet, "do not print the results of eval, save_mesh, info, ...");
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_run(*args); }; });
}

void register_shell(CLI::App& root, Action& action) {
  auto args = std::make_shared<ScriptArgs>();
  CLI::App* c = root.add_subcommand(
      "shell",
      "The interactive command editor: type scene-language commands, one per line; each "
      "result is reported. Reading from a pipe, it exits with 2 if any command failed.");
  add_session_options(*c, *args);
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_shell(*args); }; });
}

}  // namespace ramiform::cli
