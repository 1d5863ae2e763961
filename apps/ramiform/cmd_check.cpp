// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform check MESH [--skeleton SKELETON] [--json]`

#include <cstdio>
#include <iostream>

#include "commands.h"
#include "common.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/winding.h"

namespace ramiform::cli {
namespace {

struct CheckArgs {
  std::string mesh_path;
  std::string skeleton_path;
  bool json = false;
  double obj_radius = 0.0;
  CommonOptions common;
};

int run_check(const CheckArgs& args) {
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  const TriMesh mesh = read_mesh(args.mesh_path);
  timer.lap("read");
  const MeshReport r = check_mesh(mesh, &scope.context());
  timer.lap("check");
  nlohmann::json j;
  j["vertices"] = r.vertices;
  j["triangles"] = r.triangles;
  j["watertight"] = r.watertight;
  j["oriented"] = r.oriented;
  j["manifold"] = r.manifold;
  j["components"] = r.components;
  j["euler"] = r.euler;
  j["min_angle_deg"] = r.min_angle_deg;
  j["median_angle_deg"] = r.median_angle_deg;
  std::size_t inside = 0, nodes = 0;
  if (!args.skeleton_path.empty()) {
    SkeletonReadOptions ro;
    ro.obj_radius = args.obj_radius;
    const Skeleton skeleton = read_skeleton(args.skeleton_path, ro);
    std::vector<Vec3> points;
    points.reserve(skeleton.nodes.size());
    for (const auto& n : skeleton.nodes) points.push_back(n.position);
    const auto flags = points_inside(mesh, points, &scope.context());
    for (const char f : flags) inside += f != 0 ? 1 : 0;
    nodes = points.size();
    j["skeleton_nodes_inside"] = nodes == 0 ? 0.0 : static_cast<double>(inside) / static_cast<double>(nodes);
    timer.lap("inside");
  }
  if (args.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    auto yes = [](bool b) { return b ? "yes" : "NO"; };
    std::printf("mesh        %s\n", args.mesh_path.c_str());
    std::printf("vertices    %zu\ntriangles   %zu\n", r.vertices, r.triangles);
    std::printf("watertight  %s (%zu boundary, %zu non-manifold edges)\n", yes(r.watertight),
                r.boundary_edges, r.nonmanifold_edges);
    std::printf("oriented    %s (%zu misoriented edges)\n", yes(r.oriented), r.misoriented_edges);
    std::printf("manifold    %s (%zu non-manifold vertices, %zu degenerate triangles)\n",
                yes(r.manifold), r.nonmanifold_vertices, r.degenerate_triangles);
    std::printf("components  %zu\neuler       %lld\n", r.components, r.euler);
    std::printf("angles      min %.3f deg, median %.3f deg\n", r.min_angle_deg, r.median_angle_deg);
    if (!args.skeleton_path.empty()) {
      std::printf("skeleton    %zu of %zu nodes inside\n", inside, nodes);
    }
  }
  nlohmann::json stats = j;
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  return 0;
}

}  // namespace

void register_check(CLI::App& root, Action& action) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* c = root.add_subcommand(
      "check", "Check a mesh: watertight, oriented, manifold, components, Euler characteristic, "
               "triangle angles; optionally which skeleton nodes lie inside (generalized winding "
               "number). Exit 0 even when a check fails.");
  c->add_option("MESH", args->mesh_path, "mesh file (.ply, .obj, .off)")->required();
  c->add_option("--skeleton", args->skeleton_path,
                "skeleton whose nodes must lie inside (reports skeleton_nodes_inside, 0..1)");
  c->add_flag("--json", args->json, "print the report as JSON");
  c->add_option("--obj-radius", args->obj_radius, "node radius for an OBJ skeleton")
      ->check(CLI::PositiveNumber);
  add_common_options(*c, args->common);
  c->callback([args, &action] { action = [args] { return run_check(*args); }; });
}

}  // namespace ramiform::cli
