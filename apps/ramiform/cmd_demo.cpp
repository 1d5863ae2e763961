// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform demo [--out DIR]`: a built-in branching skeleton, meshed and checked.

#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>

#include "commands.h"
#include "common.h"
#include "mesh_job.h"

namespace ramiform::cli {
namespace {

struct DemoArgs {
  std::string out_dir = "out";
  int resolution = 160;
  CommonOptions common;
};

// A small tree: a trunk that forks three times, each fork turning its two children by a fixed
// angle about alternating axes, radii following the pipe model r^2 = r1^2 + r2^2.
void grow_branch(Skeleton& s, std::uint32_t parent, const Vec3& dir, double length, double radius,
                 int depth, double turn) {
  const Vec3 p = s.nodes[parent].position + length * dir;
  s.nodes.push_back({p, radius});
  const auto node = static_cast<std::uint32_t>(s.nodes.size() - 1);
  s.edges.push_back({parent, node});
  if (depth == 0) return;
  const Vec3 axis = (depth % 2 == 0 ? Vec3::UnitX() : Vec3::UnitY());
  const double child_r = radius / std::sqrt(2.0);
  for (int side = -1; side <= 1; side += 2) {
    const Vec3 d = Eigen::AngleAxisd(side * turn, axis) * dir;
    grow_branch(s, node, d.normalized(), length * 0.75, child_r, depth - 1, turn * 0.9);
  }
}

Skeleton demo_skeleton() {
  Skeleton s;
  s.nodes.push_back({Vec3(0, 0, 0), 0.45});
  grow_branch(s, 0, Vec3::UnitZ(), 3.0, 0.36, 4, std::numbers::pi / 5);
  return s;
}

int run_demo(const DemoArgs& args) {
  RunScope scope(args.common);
  StageTimer timer;
  namespace fs = std::filesystem;
  fs::create_directories(args.out_dir);
  const Skeleton skeleton = demo_skeleton();
  const std::string skeleton_path = (fs::path(args.out_dir) / "skeleton.json").string();
  const std::string mesh_path = (fs::path(args.out_dir) / "tree.ply").string();
  const std::string stats_path = (fs::path(args.out_dir) / "stats.json").string();
  write_skeleton_json(skeleton, skeleton_path);
  timer.lap("skeleton");
  MeshJobOptions job;
  job.resolution = args.resolution;
  SkeletonFieldOptions field;
  const MeshJobResult result = mesh_skeleton(skeleton, field.resolved(), job, mesh_path, timer,
                                             scope.context());
  nlohmann::json stats = result.stats;
  stats["skeleton_nodes"] = skeleton.node_count();
  stats["skeleton_edges"] = skeleton.edge_count();
  stats["seconds"] = timer.seconds();
  write_stats(stats_path, stats);
  write_stats(args.common.stats_path, stats);
  const auto& r = result.report;
  std::cout << "ramiform demo: a " << skeleton.edge_count()
            << "-segment branching skeleton as a Cauchy convolution surface, marching cubes\n"
            << "  " << skeleton_path << "  skeleton (" << skeleton.node_count() << " nodes)\n"
            << "  " << mesh_path << "  mesh (" << r.vertices << " vertices, " << r.triangles
            << " triangles; watertight " << (r.watertight ? "yes" : "NO") << ", oriented "
            << (r.oriented ? "yes" : "NO") << ", manifold " << (r.manifold ? "yes" : "NO")
            << ", " << r.components << " component(s))\n"
            << "  " << stats_path << "  timings and counts (" << result.stats["field_evals"]
            << " field evaluations)\n";
  return 0;
}

}  // namespace

void register_demo(CLI::App& root, Action& action) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* c = root.add_subcommand(
      "demo", "Run the main job on a built-in branching skeleton: mesh it, check it, and write "
              "skeleton.json, tree.ply and stats.json into --out.");
  c->add_option("--out", args->out_dir, "output directory (created if missing)");
  c->add_option("--resolution", args->resolution, "marching-cubes cells along the longest side")
      ->check(CLI::Range(8, 2048));
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_demo(*args); }; });
}

}  // namespace ramiform::cli
