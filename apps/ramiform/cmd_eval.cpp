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

// Writes `count` lines to stdout at once, line i made by row(i, buffer, size) (an snprintf).
template <class Row>
void print_rows(std::size_t count, std::size_t bytes_per_row, Row&& row) {
  std::string out;
  out.reserve(count * bytes_per_row);
  char line[128];
  for (std::size_t i = 0; i < count; ++i) {
    const int n = row(i, line, sizeof line);
    out.append(line, static_cast<std::size_t>(n));
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
}

// --distance: the nearest skeleton element of each point, curved edges exact.
int run_distance(const EvalArgs& args, RunScope& scope, StageTimer& timer) {
  SkeletonReadOptions read = read_options(args.field);
  read.keep_curves = true;
  const Skeleton skeleton = read_skeleton(args.skeleton_path, read);
  const PointSet points = read_points(args.points_path);
  timer.lap("read");
  const std::vector<SkeletonDistance> d =
      skeleton_distances(skeleton, points.positions,
                         args.tie == "last" ? TieRule::kLast : TieRule::kFirst, &scope.context());
  timer.lap("distance");
  print_rows(d.size(), 48, [&](std::size_t i, char* line, std::size_t size) {
    return std::snprintf(line, size, "%.17g %s %u %.17g\n", d[i].distance,
                         d[i].is_edge ? "edge" : "node", d[i].index, d[i].t);
  });
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
  if (args.distance) return run_distance(args, scope, timer);
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
  print_rows(points.size(), args.gradient ? 96 : 26,
             [&](std::size_t i, char* line, std::size_t size) {
               if (!args.gradient) return std::snprintf(line, size, "%.17g\n", values[i]);
               return std::snprintf(line, size, "%.17g %.17g %.17g %.17g\n", values[i],
                                    gradients[i].x(), gradients[i].y(), gradients[i].z());
             });
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
