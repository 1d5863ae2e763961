// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform eval SKELETON --points FILE [--gradient | --distance [--tie first|last]]`

#include <cstdio>
#include <string>

#include "commands.h"
#include "common.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/io/points_io.h"

namespace ramiform::cli {
namespace {

struct EvalArgs {
  std::string skeleton_path;
  std::string points_path;
  bool gradient = false;
  bool distance = false;
  std::string tie = "first";
  FieldFlags field;
  CommonOptions common;
};

// --distance: the nearest skeleton element of each point, curved edges exact.
int run_distance(const EvalArgs& args) {
  RunScope scope(args.common);
  StageTimer timer;
  SkeletonReadOptions read = read_options(args.field);
  read.keep_curves = true;
  const Skeleton skeleton = read_skeleton(args.skeleton_path, read);
  const PointSet points = read_points(args.points_path);
  timer.lap("read");
  const std::vector<SkeletonDistance> d =
      skeleton_distances(skeleton, points.positions,
                         args.tie == "last" ? TieRule::kLast : TieRule::kFirst, &scope.context());
  timer.lap("distance");
  std::string out;
  out.reserve(points.size() * 48);
  char line[128];
  for (const SkeletonDistance& r : d) {
    const int n = std::snprintf(line, sizeof line, "%.17g %s %u %.17g\n", r.distance,
                                r.is_edge ? "edge" : "node", r.index, r.t);
    out.append(line, static_cast<std::size_t>(n));
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  timer.lap("print");
  nlohmann::json stats;
  stats["seconds"] = timer.seconds();
  stats["points"] = points.size();
  stats["edges"] = skeleton.edges.size();
  std::size_t curved = 0;
  for (const EdgeCurve& c : skeleton.curves) curved += c.controls.empty() ? 0 : 1;
  stats["curved_edges"] = curved;
  write_stats(args.common.stats_path, stats);
  return 0;
}

int run_eval(const EvalArgs& args) {
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  if (args.distance) return run_distance(args);
  const SkeletonFieldOptions options = field_options(args.field);
  const Skeleton skeleton = read_skeleton(args.skeleton_path, read_options(args.field));
  const PointSet points = read_points(args.points_path);
  timer.lap("read");
  const EquipotentialOptions* eq = equipotential_options(args.field);
  const FieldPtr field = eq != nullptr ? make_equipotential(skeleton, *eq).field
                                       : make_skeleton_field(skeleton, options);
  timer.lap("field");
  std::vector<double> values(points.size());
  std::vector<Vec3> gradients(args.gradient ? points.size() : 0);
  field->evaluate(points.positions, values, gradients, &scope.context());
  timer.lap("evaluate");
  std::string out;
  out.reserve(points.size() * (args.gradient ? 96 : 26));
  char line[128];
  for (std::size_t i = 0; i < points.size(); ++i) {
    int n = 0;
    if (args.gradient) {
      n = std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g\n", values[i], gradients[i].x(),
                        gradients[i].y(), gradients[i].z());
    } else {
      n = std::snprintf(line, sizeof line, "%.17g\n", values[i]);
    }
    out.append(line, static_cast<std::size_t>(n));
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  timer.lap("print");
  nlohmann::json stats;
  stats["seconds"] = timer.seconds();
  stats["points"] = points.size();
  stats["field_evals"] = field->evaluations();
  stats["iso"] = field->iso();
  write_stats(args.common.stats_path, stats);
  return 0;
}

}  // namespace

void register_eval(CLI::App& root, Action& action) {
  auto args = std::make_shared<EvalArgs>();
  CLI::App* c = root.add_subcommand(
      "eval",
      "Print the field value of a skeleton's surface at each point, one line each "
      "(inside where value > iso); with --gradient also the gradient; with --distance the "
      "distance to the nearest skeleton element instead.");
  c->add_option("SKELETON", args->skeleton_path,
                "skeleton file (.json, .ply, .obj, .txt TreeQSM, .csv SimpleForest, .swc)")
      ->required();
  c->add_option("--points", args->points_path, "points: text 'x y z [nx ny nz]' per line, or .ply")
      ->required();
  auto* gradient =
      c->add_flag("--gradient", args->gradient, "also print the gradient: 'value gx gy gz'");
  auto* distance = c->add_flag(
      "--distance", args->distance,
      "print instead the distance to the nearest skeleton element and where it is: 'distance "
      "edge E t' (t in [0, 1] from the edge's first node; curved edges exactly, by root "
      "isolation) or 'distance node N 0' for a node without edges");
  distance->excludes(gradient);
  c->add_option("--tie", args->tie,
                "--distance: where two points of a curved edge are equally near, take the "
                "smallest t (first, default) or the largest (last)")
      ->check(CLI::IsMember({"first", "last"}));
  add_field_options(*c, args->field);
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_eval(*args); }; });
}

}  // namespace ramiform::cli
