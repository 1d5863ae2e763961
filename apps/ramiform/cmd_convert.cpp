// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform convert IN OUT.json [--obj-radius R]`

#include <cstdio>
#include <string>

#include "commands.h"
#include "common.h"
#include "ramiform/io/qsm_io.h"

namespace ramiform::cli {
namespace {

struct ConvertArgs {
  std::string in_path;
  std::string out_path;
  double obj_radius = 0.0;
  CommonOptions common;
};

int run_convert(const ConvertArgs& args) {
  check_output_path(args.out_path, kSkeletonFormats);
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  QsmImportReport qsm;
  SkeletonReadOptions options;
  options.obj_radius = args.obj_radius;
  options.qsm_report = &qsm;
  options.keep_curves = true;  // JSON keeps curved edges; PLY and OBJ get them straightened
  const Skeleton skeleton = read_skeleton(args.in_path, options);
  timer.lap("read");
  write_skeleton(skeleton, args.out_path);
  timer.lap("write");
  const SkeletonComponents components = connected_components(skeleton);

  nlohmann::json stats;
  stats["nodes"] = skeleton.node_count();
  stats["edges"] = skeleton.edge_count();
  stats["components"] = components.count;
  std::printf("wrote %s: %zu nodes, %zu edges, %u component%s\n", args.out_path.c_str(),
              skeleton.node_count(), skeleton.edge_count(), components.count,
              components.count == 1 ? "" : "s");
  if (qsm.cylinders > 0) {
    std::printf(
        "cylinders %zu: %zu tiny merged, %zu parent splits, %zu connectors, %zu reattached, "
        "%zu duplicates\n",
        qsm.cylinders, qsm.merged_tiny, qsm.split_parents, qsm.connectors, qsm.reattached,
        qsm.duplicates);
    stats["cylinders"] = qsm.cylinders;
    stats["merged_tiny"] = qsm.merged_tiny;
    stats["split_parents"] = qsm.split_parents;
    stats["connectors"] = qsm.connectors;
    stats["reattached"] = qsm.reattached;
    stats["duplicates"] = qsm.duplicates;
  }
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  return 0;
}

}  // namespace

void register_convert(CLI::App& root, Action& action) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* c = root.add_subcommand(
      "convert",
      "Convert a skeleton or a tree cylinder model (TreeQSM .txt, SimpleForest .csv) "
      "to a skeleton file (.json; also .ply, .obj) and print its size and the "
      "cylinder import report.");
  c->add_option("IN", args->in_path,
                "skeleton (.json, .ply, .obj), cylinder model (.txt TreeQSM, .csv SimpleForest) or SWC "
                "neuron (.swc)")
      ->required();
  c->add_option("OUT", args->out_path, "output skeleton: .json (or .ply, .obj)")->required();
  c->add_option("--obj-radius", args->obj_radius,
                "radius of every node of an OBJ skeleton (OBJ files carry no radius)")
      ->check(CLI::PositiveNumber);
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_convert(*args); }; });
}

}  // namespace ramiform::cli
