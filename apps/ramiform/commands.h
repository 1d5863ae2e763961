// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// One registration function per subcommand (one file each). A subcommand stores the action to
// run after parsing in `action`; main() runs it and maps exceptions to exit codes.

#include <CLI/CLI.hpp>

#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace ramiform::cli {

using Action = std::function<int()>;

void register_mesh(CLI::App& root, Action& action);
void register_check(CLI::App& root, Action& action);
void register_eval(CLI::App& root, Action& action);
void register_demo(CLI::App& root, Action& action);
void register_convert(CLI::App& root, Action& action);
void register_generate(CLI::App& root, Action& action);
void register_run(CLI::App& root, Action& action);
void register_shell(CLI::App& root, Action& action);
void register_grow(CLI::App& root, Action& action);
void register_sample(CLI::App& root, Action& action);
void register_lsystem(CLI::App& root, Action& action);
void register_reconstruct(CLI::App& root, Action& action);
void register_particles(CLI::App& root, Action& action);
void register_draw(CLI::App& root, Action& action);
void register_studio(CLI::App& root, Action& action);

/// `ramiform mesh ARGS...` in this process (the Python module's mesh_file): the arguments are
/// parsed and checked exactly as on the command line (CLI::ParseError for a bad option), the
/// "wrote" line goes to `out` and warnings to `err`, and the --stats figures are returned
/// (whether or not --stats was given). Library exceptions (InputError, ...) pass through.
nlohmann::json run_mesh_command(const std::vector<std::string>& args, std::ostream& out,
                                std::ostream& err);

}  // namespace ramiform::cli
