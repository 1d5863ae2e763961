// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform demo [--out DIR]`: the whole pipeline on the built-in scene examples/demo.rf — a
// crown modeled in the scene language, points, a grown tree with pipe-model radii, and its
// tetrahedral mesh.

#include <chrono>
#include <filesystem>
#include <iostream>
#include <regex>
#include <string>

#include "commands.h"
#include "common.h"
#include "demo_scene.h"
#include "ramiform/core/errors.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/script/script.h"

namespace ramiform::cli {
namespace {

// The grow command's cleanup clause (ramiform::cleanup_summary) as numbers for stats.json;
// null when the message has none (the clause's format is pinned by the CLI tests).
nlohmann::json cleanup_stats(const std::string& message) {
  static const std::regex clause(
      R"(cleanup: (\d+) nodes moved, (\d+) removed \((\d+) kinks, (\d+) stubs pruned\); )"
      R"(turn at chain nodes p50/p90/max ([0-9.]+)/([0-9.]+)/([0-9.]+) deg -> )"
      R"(([0-9.]+)/([0-9.]+)/([0-9.]+) deg; tip branches shorter than ([0-9.]+) steps )"
      R"((\d+) of (\d+) \(([0-9.]+) %\) -> (\d+) of (\d+) \(([0-9.]+) %\))");
  std::smatch m;
  if (!std::regex_search(message, m, clause)) return nullptr;
  auto integer = [&](int k) { return std::stoll(m[k].str()); };
  auto real = [&](int k) { return std::stod(m[k].str()); };
  auto shape = [&](int turn, int tips) {
    return nlohmann::json{{"turn_p50_deg", real(turn)},
                          {"turn_p90_deg", real(turn + 1)},
                          {"turn_max_deg", real(turn + 2)},
                          {"short_tip_branches", integer(tips)},
                          {"tip_branches", integer(tips + 1)},
                          {"short_tip_percent", real(tips + 2)}};
  };
  return {{"nodes_moved", integer(1)}, {"nodes_removed", integer(2)},
          {"kinks_removed", integer(3)}, {"stubs_pruned", integer(4)},
          {"short_steps", real(11)},     {"before", shape(5, 12)},
          {"after", shape(8, 15)}};
}

struct DemoArgs {
  std::string out_dir = "out";
  int levels = 1;  ///< the base mesh's levels (examples/demo.rf's `param levels`)
  double tolerance = ToleranceOptions{}.tolerance;  ///< examples/demo.rf's `param tolerance`
  int points = 2500;
  std::uint64_t seed = ScriptOptions{}.seed;
  CommonOptions common;
};

int run_demo(const DemoArgs& args) {
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(args.out_dir, ec);
  if (ec) throw Failure("cannot create the output directory '" + args.out_dir + "': " + ec.message());
  ScriptOptions options;
  options.out_dir = args.out_dir;
  options.seed = args.seed;
  options.params = {{"levels", std::to_string(args.levels)},
                    {"tolerance", format_number(args.tolerance)},
                    {"points", std::to_string(args.points)}};
  ScriptSession session(options, &scope.context());
  nlohmann::json commands = nlohmann::json::array();
  std::vector<std::string> reports;
  const std::string text = kDemoScene;
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::string> written;
  try {
    std::size_t line_no = 1;
    for (std::size_t at = 0; at <= text.size(); ++line_no) {
      std::size_t end = text.find('\n', at);
      if (end == std::string::npos) end = text.size();
      const auto t0 = std::chrono::steady_clock::now();
      const CommandResult r =
          session.execute_line(std::string_view(text).substr(at, end - at), "demo.rf", line_no);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!r.command.empty()) {
        commands.push_back({{"line", line_no},
                            {"command", r.command},
                            {"result", r.message},
                            {"seconds", seconds}});
        if (r.command == "grow") commands.back()["cleanup"] = cleanup_stats(r.message);
        if (r.command == "grow" || r.command == "point_set_thin" || r.command == "point_set_gen" ||
            r.command.rfind("save_", 0) == 0) {
          reports.push_back(r.message);
        }
      }
      at = end + 1;
    }
    written = session.commit();
  } catch (...) {
    session.discard();
    throw;
  }
  nlohmann::json stats;
  stats["seconds"] =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  stats["commands"] = commands;
  // The grown tree's branch cleanup (examples/demo.rf: smooth= and prune= of `grow`).
  for (const nlohmann::json& c : commands)
    if (c["command"] == "grow" && c.contains("cleanup")) stats["grow_cleanup"] = c["cleanup"];
  stats["outputs"] = written;
  stats["seed"] = args.seed;
  const std::string stats_path = (fs::path(args.out_dir) / "stats.json").string();
  write_stats(stats_path, stats);
  write_stats(args.common.stats_path, stats);
  std::cout << "ramiform demo: crown (scene language) -> points -> space colonization -> "
               "pipe-model radii -> "
               "tetrahedral mesh\n";
  for (const std::string& r : reports) std::cout << "  " << r << '\n';
  std::cout << "files in " << args.out_dir << ":";
  for (const std::string& w : written) std::cout << ' ' << fs::path(w).filename().string();
  std::cout << " stats.json\n(the scene is examples/demo.rf; run it yourself with: ramiform run "
               "examples/demo.rf --out DIR)\n";
  return 0;
}

}  // namespace

void register_demo(CLI::App& root, Action& action) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* c = root.add_subcommand(
      "demo",
      "Run the whole pipeline on the built-in scene (examples/demo.rf): model a crown, fill it "
      "with points, grow a tree, mesh it, draw it; writes crown.ply, points.txt, skeleton.json, "
      "tree.ply, tree.glb, tree.svg and stats.json into --out.");
  c->add_option("--out", args->out_dir, "output directory (created if missing)")
      ->capture_default_str();
  // The demo's own default (a quick run); the range is the polygonizer's.
  c->add_option("--levels", args->levels,
                with_default("tets: 1:8 subdivision levels of the tree's base mesh", args->levels,
                             TetrahedralOptions::kMinLevels, TetrahedralOptions::kMaxLevels))
      ->check(CLI::Range(TetrahedralOptions::kMinLevels, TetrahedralOptions::kMaxLevels));
  c->add_option("--tolerance", args->tolerance,
                with_default("tets: the tree mesh's deviation p99, relative to the local radius",
                             args->tolerance, ToleranceOptions::kMinTolerance,
                             ToleranceOptions::kMaxTolerance))
      ->check(CLI::Range(ToleranceOptions::kMinTolerance, ToleranceOptions::kMaxTolerance));
  c->add_option("--points", args->points, "attraction points in the crown")
      ->check(CLI::Range(10, 10'000'000))
      ->capture_default_str();
  c->add_option("--seed", args->seed, "random seed")->capture_default_str();
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_demo(*args); }; });
}

}  // namespace ramiform::cli
