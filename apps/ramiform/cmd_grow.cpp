// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform grow --points FILE ... -o TREE.json`, `ramiform sample SCRIPT NAME --dist KIND ...`,
// `ramiform lsystem EXAMPLE|FILE -o TREE.json`.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "commands.h"
#include "common.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/grow/branch_cleanup.h"
#include "ramiform/grow/lsystem.h"
#include "ramiform/grow/space_colonization.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/sample/point_sets.h"
#include "ramiform/sample/props.h"
#include "ramiform/script/script.h"

namespace ramiform::cli {
namespace {

// "X,Y,Z" -> vector (InvalidArgument naming the flag otherwise).
Vec3 parse_vec3(const std::string& text, const std::string& flag) {
  Vec3 v;
  std::string_view rest = text;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = rest.find(',');
    const bool last = k == 2;
    if (last != (comma == std::string_view::npos) ||
        parse_number(rest.substr(0, comma), v[k]) != NumberStatus::kOk) {
      throw InvalidArgument(flag + " expects X,Y,Z (three numbers), got '" + text + "'");
    }
    if (!last) rest.remove_prefix(comma + 1);
  }
  return v;
}

// The text parse_vec3 reads back as `v`, for the defaults in --help.
std::string vec3_text(const Vec3& v) {
  return format_shortest(v.x()) + "," + format_shortest(v.y()) + "," + format_shortest(v.z());
}

nlohmann::json shape_json(const BranchShape& s) {
  return {{"chain_nodes", s.chain_nodes},
          {"turn_p50_deg", s.turn_p50_deg},
          {"turn_p90_deg", s.turn_p90_deg},
          {"turn_max_deg", s.turn_max_deg},
          {"tip_branches", s.tip_branches},
          {"short_tip_branches", s.short_tip_branches},
          {"short_tip_share", s.short_share()}};
}

nlohmann::json cleanup_json(const BranchCleanupReport& r) {
  return {{"nodes_moved", r.nodes_moved},
          {"nodes_removed", r.nodes_removed},
          {"kinks_removed", r.kinks_removed},
          {"stubs_pruned", r.stubs_pruned},
          {"rounds", r.rounds},
          {"short_steps", kShortTipSteps},
          {"before", shape_json(r.before)},
          {"after", shape_json(r.after)}};
}

struct GrowArgs {
  std::string points_path;
  std::string out_path;
  ColonizationOptions options;
  std::string root = vec3_text(options.roots.front());
  std::string direction = vec3_text(options.direction);
  std::string tropism = vec3_text(options.tropism);
  std::uint64_t seed = 0;
  CommonOptions common;
};

int run_grow(const GrowArgs& args) {
  // Growth can take minutes: a path that cannot be written is refused before it.
  check_output_path(args.out_path, kSkeletonFormats);
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  const PointSet points = read_points(args.points_path);
  timer.lap("read");
  ColonizationOptions o = args.options;
  o.roots = {parse_vec3(args.root, "--root")};
  o.direction = parse_vec3(args.direction, "--direction");
  o.tropism = parse_vec3(args.tropism, "--tropism");
  const ColonizationResult r = grow_space_colonization(points.positions, o, &scope.context());
  timer.lap("grow");
  if (r.skeleton.edge_count() == 0) {
    const std::string advice = r.stalled ? std::string()
                                         : "; move --root away from the points or use a "
                                           "smaller --kill";
    throw InvalidArgument("grew no branch from " + args.points_path + ": " +
                          no_branch_reason(r, points.positions, o) + advice);
  }
  write_skeleton(r.skeleton, args.out_path);
  timer.lap("write");
  nlohmann::json stats;
  stats["nodes"] = r.skeleton.node_count();
  stats["iterations"] = r.iterations;
  stats["points_reached"] = r.points_reached;
  stats["points_total"] = r.points_total;
  stats["stalled"] = r.stalled;
  stats["stall_reason"] = r.stall_reason;
  stats["cleanup"] = cleanup_json(r.cleanup);
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  std::cout << "wrote " << args.out_path << ": " << r.skeleton.node_count() << " nodes, "
            << r.iterations << " iterations, " << r.points_reached << " of " << r.points_total
            << " points reached"
            << (r.stalled ? "; stopped early: " + r.stall_reason : std::string()) << "; "
            << cleanup_summary(r.cleanup, format_number(kShortTipSteps) + " steps") << '\n';
  return 0;
}

struct SampleArgs {
  std::string script;
  std::string name;
  std::string dist;
  std::string props_path;
  std::size_t count = 0;
  std::string out_path;
  std::uint64_t seed = ScriptOptions{}.seed;
  std::vector<std::string> sets;
  CommonOptions common;
};

// Runs the script (its outputs are discarded: only the named shape is used), then samples.
int run_sample(const SampleArgs& args) {
  check_output_path(args.out_path);  // any extension: text, or .ply
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  ScriptOptions so;
  so.seed = args.seed;
  so.allow_any_path = true;  // -o names the output explicitly
  for (const std::string& s : args.sets) {
    const std::size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InvalidArgument("--set expects name=value, got '" + s + "'");
    so.params[s.substr(0, eq)] = s.substr(eq + 1);
  }
  ScriptSession session(so, &scope.context());
  session.run_file(args.script);
  session.discard();
  timer.lap("script");
  std::string line = "point_set_gen " + args.name + " " + args.dist;
  // Command-line paths are relative to the working directory, not to the script.
  if (!args.props_path.empty())
    line += " \"" + std::filesystem::absolute(args.props_path).string() + "\"";
  if (args.count > 0) line += " count=" + std::to_string(args.count);
  line += " name=__sample";
  session.execute_line(line, "<sample>", 1);
  timer.lap("sample");
  session.execute_line(
      "save_point_set \"" + std::filesystem::absolute(args.out_path).string() + "\" __sample",
      "<sample>", 2);
  // Outputs of the session are relative to its out_dir "."; commit moves the staged file.
  const std::vector<std::string> written = session.commit();
  timer.lap("write");
  nlohmann::json stats;
  stats["seconds"] = timer.seconds();
  stats["outputs"] = written;
  write_stats(args.common.stats_path, stats);
  std::cout << "wrote " << args.out_path << '\n';
  return 0;
}

struct LSystemArgs {
  std::string source;
  std::string out_path;
  LSystemOptions options;
  std::string radii = "width";
  bool list = false;
  CommonOptions common;
};

int run_lsystem(const LSystemArgs& args) {
  if (args.list || args.source.empty()) {
    for (const auto& [name, text] : lsystem_examples()) std::cout << name << '\n';
    if (args.source.empty() && !args.list)
      throw InvalidArgument("give an example name or a file (--list lists them)");
    return 0;
  }
  if (args.out_path.empty()) throw InvalidArgument("-o TREE.json is required");
  check_output_path(args.out_path, kSkeletonFormats);
  RunScope scope(args.common);
  std::string text;
  std::string source = args.source;
  for (const auto& [name, body] : lsystem_examples()) {
    if (name == args.source) text = body;
  }
  if (text.empty()) {
    std::ifstream in(args.source);
    if (!in)
      throw InputError(args.source, 0, "not an L-system example name and not a readable file");
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  LSystemOptions o = args.options;
  o.radius = args.radii == "pipe" ? LSystemRadius::kPipe : LSystemRadius::kWidth;
  const Skeleton skeleton = lsystem_skeleton(text, source, o, &scope.context());
  if (skeleton.edge_count() == 0)
    throw InvalidArgument(args.source + ": the L-system draws no segment");
  write_skeleton(skeleton, args.out_path);
  std::cout << "wrote " << args.out_path << ": " << skeleton.node_count() << " nodes, "
            << skeleton.edge_count() << " edges\n";
  return 0;
}

}  // namespace

void register_grow(CLI::App& root, Action& action) {
  auto a = std::make_shared<GrowArgs>();
  CLI::App* c = root.add_subcommand(
      "grow",
      "Grow a tree skeleton toward attraction points by space colonization (Runions et al. 2007), "
      "with pipe-model radii; writes skeleton JSON (docs/growth.md).");
  c->add_option("--points", a->points_path, "attraction points: 'x y z' per line, or .ply")
      ->required();
  c->add_option("-o,--out", a->out_path, "output skeleton (.json, .ply, .obj)")->required();
  ColonizationOptions& o = a->options;
  c->add_option("--step", o.step, with_default("node spacing D", o.step));
  c->add_option("--influence", o.influence, with_default("influence distance d_i", o.influence));
  c->add_option("--kill", o.kill, with_default("kill distance d_k", o.kill));
  c->add_option("--root", a->root, "trunk start X,Y,Z")->capture_default_str();
  c->add_option("--direction", a->direction, "initial trunk direction X,Y,Z")
      ->capture_default_str();
  c->add_option("--tropism", a->tropism, "tropism vector added to each growth direction")
      ->capture_default_str();
  c->add_option("--max-iterations", o.max_iterations,
                with_default("iteration limit", o.max_iterations));
  c->add_option("--tip-radius", o.tip_radius,
                with_default("pipe model: radius of every tip", o.tip_radius));
  // The range is checked by the library (bad input, exit 2), not by CLI11.
  c->add_option(
      "--pipe-exponent", o.pipe_exponent,
      with_default("pipe model exponent n", o.pipe_exponent, ColonizationOptions::kMinPipeExponent,
                   ColonizationOptions::kMaxPipeExponent));
  // The ranges are checked by the library (bad input, exit 2), not by CLI11.
  c->add_option("--smooth", o.smooth_iterations,
                with_default("branch cleanup: Laplacian passes along unbranched chains",
                             o.smooth_iterations, 0, BranchCleanupOptions::kMaxSmoothIterations));
  c->add_option("--max-turn", o.max_turn_deg,
                with_default("branch cleanup, with --smooth: remove chain nodes turning more "
                             "(degrees)",
                             o.max_turn_deg));
  c->add_option("--prune", o.prune_steps,
                with_default("branch cleanup: remove tip branches of at most this many steps",
                             o.prune_steps));
  c->add_option("--seed", a->seed, "accepted for symmetry: growth itself makes no random choice");
  add_common_options(*c, a->common);
  c->callback([a, &action] { action = [a] { return run_grow(*a); }; });
}

void register_sample(CLI::App& root, Action& action) {
  auto a = std::make_shared<SampleArgs>();
  CLI::App* c = root.add_subcommand(
      "sample",
      "Sample a named shape of a scene script with a point distribution (docs/sampling.md).");
  c->add_option("SCRIPT", a->script, "the scene script (.rf)")->required();
  c->add_option("NAME", a->name, "the shape to sample")->required();
  c->add_option(
       "--dist", a->dist,
       "distribution: " +
           [] {
             std::string s;
             for (const std::string& n : distribution_names()) s += (s.empty() ? "" : ", ") + n;
             return s;
           }())
      ->required();
  c->add_option("--props", a->props_path, "a .props file of 'key = value' parameters");
  c->add_option("--count", a->count, "number of points (overrides the props' count)");
  c->add_option("-o,--out", a->out_path, "output points ('x y z' text, or .ply)")->required();
  c->add_option("--seed", a->seed, "random seed")->capture_default_str();
  c->add_option("--set", a->sets, "override a script parameter: name=value");
  add_common_options(*c, a->common);
  c->callback([a, &action] { action = [a] { return run_sample(*a); }; });
}

void register_lsystem(CLI::App& root, Action& action) {
  auto a = std::make_shared<LSystemArgs>();
  CLI::App* c = root.add_subcommand(
      "lsystem",
      "Derive a bracketed parametric L-system and write its turtle skeleton (docs/growth.md).");
  c->add_option("SOURCE", a->source, "a built-in example name (--list) or an L-system file");
  c->add_option("-o,--out", a->out_path, "output skeleton (.json, .ply, .obj)");
  c->add_flag("--list", a->list, "list the built-in examples");
  LSystemOptions& o = a->options;
  c->add_option("--iterations", o.iterations,
                with_default("derivation steps", o.iterations, 0, LSystemOptions::kMaxIterations))
      ->check(CLI::Range(0, LSystemOptions::kMaxIterations));
  c->add_option("--angle", o.angle_deg, with_default("default turn angle, degrees", o.angle_deg));
  c->add_option("--step", o.step, with_default("default segment length", o.step));
  c->add_option("--width", o.width, with_default("initial width", o.width));
  c->add_option("--radii", a->radii, "node radii from the turtle width or the pipe model")
      ->check(CLI::IsMember({"width", "pipe"}))
      ->capture_default_str();
  add_common_options(*c, a->common);
  c->callback([a, &action] { action = [a] { return run_lsystem(*a); }; });
}

}  // namespace ramiform::cli
