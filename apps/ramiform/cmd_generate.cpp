// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform generate OUT.json [--segments N] [--seed S] [...]`: a procedural branching tree.

#include <cstdio>
#include <string>

#include "commands.h"
#include "common.h"
#include "ramiform/core/errors.h"
#include "ramiform/skeleton/generate.h"

namespace ramiform::cli {
namespace {

struct GenerateArgs {
  std::string out_path;
  BranchingTreeOptions tree;
  CommonOptions common;
};

int run_generate(const GenerateArgs& args) {
  check_output_path(args.out_path, kSkeletonFormats);
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  const Skeleton skeleton = branching_tree(args.tree);
  timer.lap("generate");
  write_skeleton(skeleton, args.out_path);
  timer.lap("write");
  std::printf("wrote %s: %zu nodes, %zu edges\n", args.out_path.c_str(), skeleton.node_count(),
              skeleton.edge_count());
  nlohmann::json stats;
  stats["nodes"] = skeleton.node_count();
  stats["edges"] = skeleton.edge_count();
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  return 0;
}

}  // namespace

void register_generate(CLI::App& root, Action& action) {
  auto args = std::make_shared<GenerateArgs>();
  auto& t = args->tree;
  CLI::App* c = root.add_subcommand(
      "generate",
      "Write a procedural binary branching tree with pipe-model radii (for tests and "
      "benchmarks; the same options give the same tree everywhere).");
  c->add_option("OUT", args->out_path, "output skeleton: .json (or .ply, .obj)")->required();
  using Tree = BranchingTreeOptions;
  c->add_option("--segments", t.segments,
                with_default("number of edges", static_cast<double>(t.segments),
                             static_cast<double>(Tree::kMinSegments),
                             static_cast<double>(Tree::kMaxSegments)))
      ->check(CLI::Range(Tree::kMinSegments, Tree::kMaxSegments));
  c->add_option("--seed", t.seed, with_default("random seed", static_cast<double>(t.seed)));
  c->add_option("--trunk-length", t.trunk_length,
                with_default("length of the first edge", t.trunk_length))
      ->check(CLI::PositiveNumber);
  c->add_option("--length-ratio", t.length_ratio,
                with_default("child/parent edge length", t.length_ratio, Tree::kMinLengthRatio,
                             Tree::kMaxLengthRatio))
      ->check(CLI::Range(Tree::kMinLengthRatio, Tree::kMaxLengthRatio));
  c->add_option(
       "--branch-angle", t.branch_angle_deg,
       with_default("child/parent angle, degrees, below " + format_number(Tree::kMaxBranchAngleDeg),
                    t.branch_angle_deg))
      ->check(CLI::Range(0.0, Tree::kMaxBranchAngleDeg));
  c->add_option(
       "--jitter", t.jitter_deg,
       with_default("random direction deviation, degrees", t.jitter_deg, 0.0, Tree::kMaxJitterDeg))
      ->check(CLI::Range(0.0, Tree::kMaxJitterDeg));
  c->add_option("--tip-radius", t.tip_radius, with_default("radius of every tip", t.tip_radius))
      ->check(CLI::PositiveNumber);
  c->add_option(
       "--pipe-exponent", t.pipe_exponent,
       with_default("pipe model exponent n", t.pipe_exponent,
                    BranchingTreeOptions::kMinPipeExponent, BranchingTreeOptions::kMaxPipeExponent))
      ->check(CLI::Range(BranchingTreeOptions::kMinPipeExponent,
                         BranchingTreeOptions::kMaxPipeExponent));
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_generate(*args); }; });
}

}  // namespace ramiform::cli
