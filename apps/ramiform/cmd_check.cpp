// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform check MESH [--skeleton SKELETON] [--deviation SKELETON [field options]] [--json]`

#include <cstdio>
#include <iostream>
#include <optional>

#include "commands.h"
#include "common.h"
#include "mesh_job.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/mesh/winding.h"

namespace ramiform::cli {
namespace {

struct CheckArgs {
  std::string mesh_path;
  std::string skeleton_path;
  std::string deviation_path;  // --deviation: the skeleton whose surface the mesh approximates
  bool fit_radii = false;
  DeviationOptions deviation;
  bool json = false;
  FieldFlags field;
  CommonOptions common;
};

void print_summary(const char* what, const DeviationSummary& s) {
  std::printf("%s p50 %.4g, p99 %.4g, max %.4g of the local radius (%zu points", what, s.p50, s.p99,
              s.max, s.points);
  if (s.unresolved > 0) std::printf(", %zu unresolved", s.unresolved);
  std::printf(")\n");
}

int run_check(const CheckArgs& args) {
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  StageTimer timer;
  const TriMesh mesh = read_mesh(args.mesh_path);
  timer.lap("read");
  std::optional<Skeleton> skeleton;
  if (!args.skeleton_path.empty()) {
    SkeletonReadOptions ro;
    ro.obj_radius = args.field.obj_radius;
    skeleton = read_skeleton(args.skeleton_path, ro);
  }
  nlohmann::json j = check_json(mesh, skeleton ? &*skeleton : nullptr, scope.context());
  timer.lap("check");
  DeviationReport dev;
  if (!args.deviation_path.empty()) {
    const SkeletonFieldOptions options = field_options(args.field);
    const Skeleton skeleton = read_skeleton(args.deviation_path, read_options(args.field));
    const SkeletonSurface surface =
        build_surface(skeleton, options, args.fit_radii, timer, scope.context(),
                      equipotential_options(args.field));
    timer.lap("field");
    dev = measure_deviation(mesh, *surface.field, &surface.skeleton, args.deviation,
                            &scope.context());
    put_deviation_summary(j, "deviation_", dev.samples);
    put_deviation_summary(j, "vertex_deviation_", dev.vertices);
    timer.lap("deviation");
  }
  if (args.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    auto yes = [](bool b) { return b ? "yes" : "NO"; };
    auto n = [&j](const char* key) { return j[key].get<std::size_t>(); };
    std::printf("mesh        %s\n", args.mesh_path.c_str());
    std::printf("vertices    %zu\ntriangles   %zu\n", n("vertices"), n("triangles"));
    std::printf("watertight  %s (%zu boundary, %zu non-manifold edges)\n",
                yes(j["watertight"].get<bool>()), n("boundary_edges"), n("nonmanifold_edges"));
    std::printf("oriented    %s (%zu misoriented edges)\n", yes(j["oriented"].get<bool>()),
                n("misoriented_edges"));
    std::printf("manifold    %s (%zu non-manifold vertices, %zu degenerate triangles)\n",
                yes(j["manifold"].get<bool>()), n("nonmanifold_vertices"),
                n("degenerate_triangles"));
    std::printf("components  %zu\neuler       %lld\n", n("components"),
                j["euler"].get<long long>());
    std::printf(
        "angles      min %.3f deg, median %.3f deg; %.2f %% of triangles below 10 deg, "
        "%.2f %% below 1 deg\n",
        j["min_angle_deg"].get<double>(), j["median_angle_deg"].get<double>(),
        100.0 * j["triangles_below_10_deg"].get<double>(),
        100.0 * j["triangles_below_1_deg"].get<double>());
    if (skeleton) {
      std::printf("skeleton    %zu of %zu nodes inside\n", n("skeleton_nodes_inside_count"),
                  n("skeleton_nodes"));
    }
    if (!args.deviation_path.empty()) {
      print_summary("deviation  ", dev.samples);
      print_summary("  vertices ", dev.vertices);
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
      "check",
      "Check a mesh: watertight, oriented, manifold, components, Euler characteristic, "
      "triangle angles; optionally which skeleton nodes lie inside (generalized winding "
      "number); optionally how far the mesh lies from a skeleton's surface (deviation "
      "relative to the local radius). Exit 0 even when a check fails.");
  c->add_option("MESH", args->mesh_path, "mesh file (.ply, .obj, .off)")->required();
  c->add_option("--skeleton", args->skeleton_path,
                "skeleton whose nodes must lie inside (reports skeleton_nodes_inside, 0..1)");
  c->add_option("--deviation", args->deviation_path,
                "skeleton whose implicit surface the mesh approximates (field options as for "
                "mesh): reports deviation_p50, _p99, _max relative to the local radius, for "
                "area-weighted points and for the vertices");
  c->add_flag("--fit-radii", args->fit_radii,
              "--deviation: the surface with fitted radii, as `mesh --fit-radii` builds it");
  DeviationOptions& d = args->deviation;
  c->add_option("--samples", d.samples,
                with_default("--deviation: area-weighted points on the mesh",
                             static_cast<double>(d.samples)));
  c->add_option("--seed", d.seed,
                with_default("--deviation: seed of the points", static_cast<double>(d.seed)));
  c->add_option("--search-radii", d.search_radii,
                with_default("--deviation: how far to look for the surface, in local radii; a "
                             "point without surface that near is counted as that far "
                             "(unresolved)",
                             d.search_radii))
      ->check(CLI::PositiveNumber);
  c->add_flag("--json", args->json, "print the report as JSON");
  add_field_options(*c, args->field);
  add_common_options(*c, args->common);
  c->callback([args, c, &action] {
    if (args->deviation_path.empty()) {
      for (const char* flag : {"--fit-radii", "--samples", "--seed", "--search-radii", "--surface",
                               "--kernel", "--iso"}) {
        if (c->get_option(flag)->count() > 0) {
          throw CLI::ValidationError(flag, "applies to --deviation only");
        }
      }
    }
    action = [args] { return run_check(*args); };
  });
}

}  // namespace ramiform::cli
