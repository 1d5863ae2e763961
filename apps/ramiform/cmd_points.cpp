// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform reconstruct POINTS -o MESH`: a point cloud or a mesh to an MPU implicit, meshed by
// marching cubes (docs/reconstruction.md).
// `ramiform particles INPUT -o PARTICLES`: particles spread evenly over any surface
// (docs/particles.md). Their INPUT and options: surface_input.h.

#include <iostream>
#include <string>

#include "commands.h"
#include "common.h"
#include "mesh_job.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/particles/surface_particles.h"
#include "ramiform/script/script.h"
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
};

int run_reconstruct(ReconstructArgs& args) {
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
    std::cerr << "ramiform: warning: the mesh has " << report.components << " pieces"
              << (report.watertight ? "" : " and is not closed") << '\n';
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
  c->add_option("-o,--out", a->out_path, "output mesh (.ply, .obj, .off, .glb)")->required();
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
  add_common_options(*c, a->common);
  c->callback([a, &action] { action = [a] { return run_reconstruct(*a); }; });
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
