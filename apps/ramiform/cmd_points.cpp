// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform reconstruct POINTS -o MESH`: a point cloud or a mesh to an MPU implicit, meshed by
// marching cubes (docs/reconstruction.md).
// `ramiform particles INPUT -o PARTICLES`: particles spread evenly over any surface
// (docs/particles.md). Their INPUT and options: surface_input.h.

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "commands.h"
#include "common.h"
#include "mesh_job.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/particles/surface_particles.h"
#include "ramiform/script/script.h"
#include "ramiform/skeleton/from_points.h"
#include "reconstruct_job.h"
#include "surface_input.h"

namespace ramiform::cli {
namespace {

struct ReconstructArgs {
  std::string input;
  std::string out_path;
  std::string points_path;  // --save-points
  ReconstructOptions options;
  std::uint64_t seed = 1;
  CommonOptions common;
  // --tree: the skeleton route (docs/reconstruction.md, "Scanned trees").
  bool tree = false;
  std::string skeleton_out;    // --skeleton-out
  std::string reference_path;  // --reference: a skeleton (QSM) to measure the cloud against
  std::string up = "z";
  TreeFromPointsOptions tree_options;
  int levels = 0;  // --levels: 0 the tolerance mesher, else plain tets at these levels
};

// The distance of every point to the surface f == iso of `field` (the surface the mesh
// approximates), searching up to 4 local radii of `skeleton` (at least `min_search`) away:
// count, unresolved, p50, p90, p99, max (nearest rank, model units).
nlohmann::json cloud_deviation(const std::vector<Vec3>& points, const Field& field,
                               const Skeleton& skeleton, double min_search, Context& ctx) {
  const std::vector<double> radii = local_radii(skeleton, points, &ctx);
  std::vector<double> d(points.size());
  std::vector<std::uint8_t> resolved(points.size(), 0);
  parallel::for_each(
      points.size(), 64,
      [&](std::size_t i) {
        const SurfaceDistance s =
            distance_to_surface(field, points[i], std::max(4.0 * radii[i], min_search));
        d[i] = s.distance;
        resolved[i] = s.resolved ? 1 : 0;
      },
      &ctx);
  std::size_t unresolved = 0;
  for (std::uint8_t r : resolved) unresolved += r == 0 ? 1 : 0;
  std::vector<double> sorted = d;
  std::sort(sorted.begin(), sorted.end());
  auto rank = [&](double q) {
    const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
    return sorted[std::min(sorted.size() - 1, k > 0 ? k - 1 : 0)];
  };
  return {{"points", points.size()}, {"unresolved", unresolved}, {"p50", rank(0.5)},
          {"p90", rank(0.9)},        {"p99", rank(0.99)},        {"max", sorted.back()}};
}

// `reconstruct --tree`: the cloud's skeleton by geodesic level sets, meshed as `mesh` meshes a
// skeleton (the default field and mesher), and the cloud's deviation from it.
int run_reconstruct_tree(ReconstructArgs& args) {
  check_output_path(args.out_path, kMeshFormats);
  check_output_path(args.skeleton_out, kSkeletonFormats);
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  Context& ctx = scope.context();
  StageTimer timer;
  const PointSet cloud = read_points(args.input);
  timer.lap("read");
  TreeFromPointsOptions to = args.tree_options;
  to.up_axis = args.up == "y" ? 1 : 2;
  TreeFromPointsReport rep;
  const Skeleton skeleton = tree_from_points(cloud.positions, to, &rep);
  timer.lap("skeleton");
  if (!args.skeleton_out.empty()) write_skeleton(skeleton, args.skeleton_out);
  nlohmann::json stats;
  stats["skeleton"] = {{"points", rep.points},
                       {"median_spacing", rep.median_spacing},
                       {"bin_width", rep.bin_width},
                       {"min_radius", rep.min_radius},
                       {"graph_edges", rep.graph_edges},
                       {"graph_parts", rep.graph_parts},
                       {"bridges", rep.bridges},
                       {"bins", rep.bins},
                       {"raw_nodes", rep.raw_nodes},
                       {"dropped_branches", rep.dropped_branches},
                       {"dropped_nodes", rep.dropped_nodes},
                       {"thinned_nodes", rep.thinned_nodes},
                       {"nodes", rep.nodes},
                       {"edges", skeleton.edges.size()},
                       {"tips", rep.tips},
                       {"forks", rep.forks},
                       {"max_geodesic", rep.max_geodesic},
                       {"root_radius", skeleton.nodes[0].radius},
                       {"seconds_graph", rep.seconds_graph},
                       {"seconds_levels", rep.seconds_levels},
                       {"seconds_radii", rep.seconds_radii}};
  if (args.out_path.empty()) {  // the skeleton alone
    stats["seconds"] = timer.seconds();
    write_stats(args.common.stats_path, stats);
    std::cout << "wrote " << args.skeleton_out << " (" << rep.nodes << " nodes, " << rep.tips
              << " tips)\n";
    return 0;
  }
  MeshJobOptions job;
  if (args.levels > 0) {
    job.to_tolerance = false;
    job.tets.levels = args.levels;
  }
  const MeshJobResult result =
      mesh_skeleton(skeleton, field_options(FieldFlags{}), job, args.out_path, timer, ctx, nullptr);
  stats["mesh"] = result.stats;
  stats["cloud_deviation"] =
      cloud_deviation(cloud.positions, *result.field, result.skeleton, rep.bin_width, ctx);
  timer.lap("cloud_deviation");
  if (!args.reference_path.empty()) {
    const Skeleton reference = read_skeleton(args.reference_path);
    StageTimer ignored;
    const SkeletonSurface surface =
        build_surface(reference, field_options(FieldFlags{}), false, ignored, ctx);
    stats["reference_deviation"] =
        cloud_deviation(cloud.positions, *surface.field, surface.skeleton, rep.bin_width, ctx);
    timer.lap("reference_deviation");
  }
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  const MeshReport& report = result.report;
  if (!report.watertight || report.components != 1) {
    std::cerr << "ramiform: warning: the mesh has " << report.components << " pieces"
              << (report.watertight ? "" : " and is not closed") << '\n';
  }
  std::cout << "wrote " << args.out_path << " (" << result.mesh.triangles.size() << " triangles, "
            << report.components << (report.components == 1 ? " piece" : " pieces")
            << (report.watertight && report.oriented && report.manifold ? ", closed" : "")
            << "; skeleton " << rep.nodes << " nodes, " << rep.tips << " tips)\n";
  return 0;
}

int run_reconstruct(ReconstructArgs& args) {
  if (args.tree) return run_reconstruct_tree(args);
  check_output_path(args.out_path, kMeshFormats);
  check_output_path(args.points_path);
  check_output_path(args.common.stats_path);
  RunScope scope(args.common);
  Context& ctx = scope.context();
  StageTimer timer;
  args.options.read.seed = args.seed;
  PointSurface surface = build_point_surface(args.input, args.options, ctx,
                                             [&timer](const char* stage) { timer.lap(stage); });
  MeshReport report;
  TriMesh mesh = mesh_point_surface(surface, args.options, ctx, &report);
  timer.lap("mesh");
  if (!args.points_path.empty()) write_points(surface.points, args.points_path);
  write_mesh(mesh, args.out_path);
  timer.lap("write");
  nlohmann::json stats = surface.stats;
  stats["field_evals"] = surface.field->evaluations();
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  const nlohmann::json& n = stats["normals"];
  if (n["estimated"].get<std::size_t>() > 0) {
    const std::size_t pieces = n["components"].get<std::size_t>();
    std::cerr << "ramiform: note: estimated " << n["estimated"] << " normals (" << pieces
              << (pieces == 1 ? " piece" : " pieces") << " of the neighbour graph)\n";
  }
  if (n["flipped"].get<std::size_t>() > 0) {
    std::cerr << "ramiform: note: flipped " << n["flipped"]
              << " normals that disagreed with their neighbours\n";
  }
  const std::size_t specks = stats["mesh"]["specks_removed"].get<std::size_t>();
  if (specks > 0) {
    std::cerr << "ramiform: note: removed " << specks << (specks == 1 ? " speck" : " specks")
              << " smaller than " << args.options.speck_cells
              << " cells (details below the grid's resolution; --speck-cells 0 keeps them)\n";
  }
  if (!report.watertight || report.components != 1) {
    // Several pieces from a cloud usually mean parts thinner than the sampling: the branches of
    // a scanned tree, which the skeleton route meshes whole (docs/reconstruction.md).
    std::cerr << "ramiform: warning: the mesh has " << report.components << " pieces"
              << (report.watertight ? "" : " and is not closed")
              << "; parts thinner than about two point spacings break up (for a scanned tree, "
                 "--tree builds its skeleton and meshes that)\n";
  }
  std::cout << "wrote " << args.out_path << " (" << mesh.triangles.size() << " triangles, "
            << report.components << (report.components == 1 ? " piece" : " pieces")
            << (report.watertight && report.oriented && report.manifold ? ", closed" : "") << ")\n";
  return 0;
}

struct ParticlesArgs {
  SurfaceInputArgs in;
  std::string out_path;
  std::string previous_path;
  std::vector<double> edit_box;
  CommonOptions common;
};

int run_particles(ParticlesArgs& args) {
  check_output_path(args.out_path);
  check_output_path(args.common.stats_path);
  if (!args.edit_box.empty() && args.previous_path.empty()) {
    throw InvalidArgument("--edit-box needs --previous (the particle state to regenerate)");
  }
  if (!args.previous_path.empty() && args.edit_box.size() != 6) {
    throw InvalidArgument("--previous needs --edit-box X0,Y0,Z0,X1,Y1,Z1");
  }
  RunScope scope(args.common);
  Context& ctx = scope.context();
  StageTimer timer;
  SurfaceInput in = load_surface_input(args.in, ctx, timer);
  ParticleStats ps;
  ParticleSystem system;
  if (!args.previous_path.empty()) {
    const ParticleSystem previous = read_particles(args.previous_path);
    const auto& b = args.edit_box;
    const Aabb box(Vec3(b[0], b[1], b[2]), Vec3(b[3], b[4], b[5]));
    if (box.isEmpty()) throw InvalidArgument("--edit-box: the minimum corner exceeds the maximum");
    timer.lap("read_previous");
    system = regenerate_particles(*in.field, previous, box, args.in.particles, &ps, &ctx);
  } else {
    system = spread_particles(*in.field, args.in.particles, in.cells, in.seeds, &ps, &ctx);
  }
  timer.lap("particles");
  const std::string ext = lower_extension(args.out_path);
  if (ext == ".ply") {
    write_particles(system, args.out_path);
  } else {
    write_points(particle_points(system), args.out_path);
  }
  timer.lap("write");
  nlohmann::json stats = std::move(in.stats);
  stats["iso"] = in.field->iso();
  add_particle_stats(stats, system, ps);
  stats["field_evals"] = in.field->evaluations();
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  std::cout << "wrote " << args.out_path << " (" << system.particles.size() << " particles)\n";
  return 0;
}

}  // namespace

void register_reconstruct(CLI::App& root, Action& action) {
  auto a = std::make_shared<ReconstructArgs>();
  CLI::App* c = root.add_subcommand(
      "reconstruct",
      "Fit an MPU implicit surface to a point cloud or a mesh and mesh it watertight by marching "
      "cubes (docs/reconstruction.md).");
  c->add_option("POINTS", a->input,
                "points ('x y z [nx ny nz]' text, .xyz, .pwn, PLY) or a mesh (.ply with faces, "
                ".off, .obj)")
      ->required();
  c->add_option("-o,--out", a->out_path,
                "output mesh (.ply, .obj, .off, .glb); with --tree it may be left out when "
                "--skeleton-out is given");
  add_mpu_options(*c, a->options);
  c->add_option("--cell-size", a->options.cell_size,
                "marching cubes cell size (default: --spacing-cells point spacings)")
      ->check(CLI::PositiveNumber);
  c->add_option("--resolution", a->options.resolution,
                "marching cubes cells along the longest side instead")
      ->check(CLI::Range(1, 4096));
  c->add_option("--spacing-cells", a->options.spacing_cells,
                with_default("default cell size in point spacings (1/sqrt of the sampling density)",
                             a->options.spacing_cells))
      ->check(CLI::PositiveNumber);
  c->add_option("--speck-cells", a->options.speck_cells,
                with_default("remove pieces smaller than this many cells (0 keeps all)",
                             a->options.speck_cells))
      ->check(CLI::Range(0.0, 1000.0));
  c->add_option("--seed", a->seed, "seed of the points drawn on a mesh input")
      ->capture_default_str();
  c->add_option("--save-points", a->points_path,
                "also write the oriented points the surface was fitted to ('x y z nx ny nz' "
                "text, or .ply): estimated and flipped normals included");
  const TreeFromPointsOptions tree_defaults;
  std::vector<CLI::Option*> tree_only;
  tree_only.push_back(c->add_flag(
      "--tree", a->tree,
      "a laser-scanned tree: build its branching skeleton by geodesic level sets (Xu et al. "
      "2007) and mesh the skeleton's surface as `ramiform mesh` does, instead of an MPU fit; "
      "the MPU and marching-cubes options do not apply"));
  tree_only.push_back(c->add_option("--skeleton-out", a->skeleton_out,
                                    "tree: also write the skeleton (.json, .ply, .obj); "
                                    "without -o only the skeleton is written"));
  tree_only.push_back(c->add_option("--bin", a->tree_options.bin_width,
                                    with_default("tree: level-set width", tree_defaults.bin_width) +
                                        "; model units, 0: --bin-spacings median point spacings")
                          ->check(CLI::NonNegativeNumber));
  tree_only.push_back(
      c->add_option("--bin-spacings", a->tree_options.bin_spacings,
                    with_default("tree: automatic --bin, spacings", tree_defaults.bin_spacings))
          ->check(CLI::Range(0.01, 1000.0)));
  tree_only.push_back(c->add_option("--up", a->up, "tree: the up axis, z or y (default z)")
                          ->check(CLI::IsMember({"z", "y"})));
  tree_only.push_back(
      c->add_option("--min-radius", a->tree_options.min_radius,
                    with_default("tree: smallest radius", tree_defaults.min_radius) +
                        "; model units, 0: half the median point spacing")
          ->check(CLI::NonNegativeNumber));
  tree_only.push_back(c->add_option("--pipe-exponent", a->tree_options.pipe_exponent,
                                    with_default("tree: pipe model exponent e",
                                                 tree_defaults.pipe_exponent, 1.0, 4.0) +
                                        "; forks keep r_parent^e >= sum r_child^e")
                          ->check(CLI::Range(1.0, 4.0)));
  tree_only.push_back(
      c->add_option("--min-branch-points", a->tree_options.min_branch_points,
                    with_default("tree: drop smaller side branches",
                                 static_cast<double>(tree_defaults.min_branch_points))));
  tree_only.push_back(
      c->add_option("--min-branch-bins", a->tree_options.min_branch_bins,
                    with_default("tree: drop shorter side branches",
                                 static_cast<double>(tree_defaults.min_branch_bins))));
  tree_only.push_back(
      c->add_option(
           "--straight-tolerance", a->tree_options.straight_tolerance,
           with_default("tree: chain thinning, radii", tree_defaults.straight_tolerance, 0.0, 1.0) +
               "; nodes this close to the line between their neighbours go, 0 keeps "
               "all")
          ->check(CLI::Range(0.0, 1.0)));
  tree_only.push_back(
      c->add_option("--levels", a->levels,
                    "tree: mesh with plain skeleton-bounded tetrahedra at this many 1:8 "
                    "subdivision levels (as `mesh --levels`; fewer triangles, faster) instead "
                    "of the tolerance mesher `mesh` uses (default 0: the tolerance mesher)")
          ->check(CLI::Range(0, TetrahedralOptions::kMaxLevels)));
  tree_only.push_back(c->add_option("--reference", a->reference_path,
                                    "tree: a skeleton or cylinder model (e.g. a QSM) of the "
                                    "same tree; --stats adds the cloud's deviation from its "
                                    "surface (reference_deviation)"));
  const std::size_t before_common = c->get_options().size();
  add_common_options(*c, a->common);
  std::vector<const CLI::Option*> common_opts;
  for (std::size_t i = before_common; i < c->get_options().size(); ++i) {
    common_opts.push_back(c->get_options()[i]);
  }
  c->callback([a, c, tree_only, common_opts, &action] {
    if (a->tree) {
      for (const CLI::Option* o : c->get_options()) {
        if (o->count() == 0 || o->get_name() == "POINTS" || o->get_name() == "--out" ||
            o->get_name() == "--help") {
          continue;
        }
        if (std::find(tree_only.begin(), tree_only.end(), o) != tree_only.end()) continue;
        if (std::find(common_opts.begin(), common_opts.end(), o) != common_opts.end()) continue;
        throw CLI::ValidationError(o->get_name(), "does not apply with --tree");
      }
      if (a->out_path.empty() && a->skeleton_out.empty()) {
        throw CLI::ValidationError("--out", "is required (or --skeleton-out with --tree)");
      }
    } else {
      for (const CLI::Option* o : tree_only) {
        if (o->count() > 0) throw CLI::ValidationError(o->get_name(), "applies with --tree only");
      }
      if (a->out_path.empty()) throw CLI::ValidationError("--out", "is required");
    }
    action = [a] { return run_reconstruct(*a); };
  });
}

void register_particles(CLI::App& root, Action& action) {
  auto a = std::make_shared<ParticlesArgs>();
  CLI::App* c = root.add_subcommand(
      "particles",
      "Spread particles evenly over a surface: of a point cloud or mesh (its MPU implicit), a "
      "skeleton, or a shape of a scene script (docs/particles.md).");
  add_surface_input_options(*c, a->in, "");
  c->add_option("-o,--out", a->out_path,
                "output: .ply (the particle state, docs/formats.md) or 'x y z nx ny nz' text")
      ->required();
  c->add_option("--previous", a->previous_path,
                "a particle state (.ply) to regenerate locally after an edit (with --edit-box)");
  c->add_option("--edit-box", a->edit_box, "X0,Y0,Z0,X1,Y1,Z1: the box the edit stayed in")
      ->delimiter(',')
      ->expected(6);
  add_common_options(*c, a->common);
  c->callback([a, &action] { action = [a] { return run_particles(*a); }; });
}

}  // namespace ramiform::cli
