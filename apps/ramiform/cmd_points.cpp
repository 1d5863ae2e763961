// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform reconstruct POINTS -o MESH`: a point cloud or a mesh to an MPU implicit, meshed by
// marching cubes (docs/reconstruction.md).
// `ramiform particles INPUT -o PARTICLES`: particles spread evenly over any surface
// (docs/particles.md).

#include <filesystem>
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

namespace ramiform::cli {
namespace {

// The options of the MPU fit and of reading the points, shared by both commands.
void add_mpu_options(CLI::App& c, ReconstructOptions& o) {
  c.add_option("--tolerance", o.mpu.tolerance,
               with_default("MPU fit tolerance ε0, a fraction of the points' bounding-box diagonal",
                            o.mpu.tolerance))
      ->check(CLI::PositiveNumber);
  c.add_option("--support", o.mpu.support,
               with_default("MPU support radius, in cell diagonals (α)", o.mpu.support))
      ->check(CLI::PositiveNumber);
  c.add_option("--min-points", o.mpu.min_points,
               with_default("fewest points a local fit uses (N_min)", o.mpu.min_points, 6, 100000))
      ->check(CLI::Range(6, 100000));
  c.add_option("--max-depth", o.mpu.max_depth,
               with_default("deepest MPU octree level", o.mpu.max_depth, 0, 20))
      ->check(CLI::Range(0, 20));
  c.add_flag(
      "--no-sharp", [&o](std::int64_t) { o.mpu.sharp_features = false; },
      "no piecewise quadrics at sharp edges and corners");
  c.add_option("--neighbours", o.normals.neighbours,
               with_default("neighbours for estimating and orienting normals", o.normals.neighbours,
                            3, 256))
      ->check(CLI::Range(3, 256));
  c.add_option(
       "--mesh-samples", o.read.mesh_samples,
       with_default("points drawn on a mesh input", static_cast<double>(o.read.mesh_samples)))
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 26));
}

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
  std::string input;
  std::string out_path;
  bool skeleton = false;
  ReconstructOptions reconstruct;
  FieldFlags field;
  ParticleOptions particles;
  std::string previous_path;
  std::vector<double> edit_box;
  CommonOptions common;
};

// INPUT is SCRIPT.rf:NAME (a shape of a scene script) when it ends in ":NAME" after ".rf".
bool split_script_input(const std::string& input, std::string& script, std::string& name) {
  const std::size_t at = input.rfind(".rf:");
  if (at == std::string::npos) return false;
  script = input.substr(0, at + 3);
  name = input.substr(at + 4);
  if (name.empty()) throw InvalidArgument("'" + input + "': the shape's name is missing after ':'");
  return true;
}

bool is_skeleton_input(const std::string& path, bool forced) {
  if (forced) return true;
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".json" || ext == ".swc";
}

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
  nlohmann::json stats;
  FieldPtr field;
  std::vector<ParticleCell> cells;
  std::vector<Vec3> seeds;
  std::string script;
  std::string name;
  if (split_script_input(args.input, script, name)) {
    ScriptOptions so;
    so.allow_any_path = true;
    ScriptSession session(so, &ctx);
    session.run_file(script);
    session.discard();  // the script's own outputs are not this command's
    field = session.shape(name);
    stats["input"] = "script";
    timer.lap("script");
  } else if (is_skeleton_input(args.input, args.skeleton)) {
    const Skeleton skeleton = read_skeleton(args.input, read_options(args.field));
    timer.lap("read");
    field = build_surface(skeleton, field_options(args.field), false, timer, ctx,
                          equipotential_options(args.field))
                .field;
    stats["input"] = "skeleton";
    timer.lap("field");
  } else {
    args.reconstruct.read.seed = args.particles.seed;
    PointSurface s = build_point_surface(args.input, args.reconstruct, ctx,
                                         [&timer](const char* stage) { timer.lap(stage); });
    field = s.field;
    for (const MpuCell& c : s.cells) cells.push_back({c.box, c.depth});
    seeds = s.points.positions;
    stats = s.stats;
    stats["input"] = "points";
  }
  ParticleStats ps;
  ParticleSystem system;
  if (!args.previous_path.empty()) {
    const ParticleSystem previous = read_particles(args.previous_path);
    const auto& b = args.edit_box;
    const Aabb box(Vec3(b[0], b[1], b[2]), Vec3(b[3], b[4], b[5]));
    if (box.isEmpty()) throw InvalidArgument("--edit-box: the minimum corner exceeds the maximum");
    timer.lap("read_previous");
    system = regenerate_particles(*field, previous, box, args.particles, &ps, &ctx);
  } else {
    system = spread_particles(*field, args.particles, cells, seeds, &ps, &ctx);
  }
  timer.lap("particles");
  std::string ext = std::filesystem::path(args.out_path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (ext == ".ply") {
    write_particles(system, args.out_path);
  } else {
    PointSet out;
    for (const SurfaceParticle& p : system.particles) {
      out.positions.push_back(p.position);
      out.normals.push_back(p.normal);
    }
    write_points(out, args.out_path);
  }
  timer.lap("write");
  stats["iso"] = field->iso();
  stats["particles"] = system.particles.size();
  stats["simulated"] = ps.particles;
  stats["kept"] = ps.kept;
  stats["dropped"] = ps.dropped;
  stats["cells"] = ps.cells;
  stats["iterations"] = ps.iterations;
  stats["residual_max"] = ps.residual_max;
  stats["spacing_cv"] = ps.spacing_cv;
  stats["particle_seconds"] = {
      {"cells", ps.seconds_cells}, {"seed", ps.seconds_seed}, {"simulate", ps.seconds_simulate}};
  stats["field_evals"] = field->evaluations();
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
  c->add_option("INPUT", a->input,
                "points or a mesh (as for reconstruct), a skeleton (.json, .swc; others with "
                "--skeleton), or SCRIPT.rf:NAME")
      ->required();
  c->add_option("-o,--out", a->out_path,
                "output: .ply (the particle state, docs/formats.md) or 'x y z nx ny nz' text")
      ->required();
  ParticleOptions& p = a->particles;
  c->add_option("--per-cell", p.per_cell,
                with_default("initial particles per leaf cell (k), on average",
                             static_cast<double>(p.per_cell), 1, 1000))
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000}));
  c->add_option("--count", p.count, "about this many particles in all (instead of --per-cell)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 26));
  c->add_option("--iterations", p.iterations,
                with_default("simulation steps", p.iterations, 0, ParticleOptions::kMaxIterations))
      ->check(CLI::Range(0, ParticleOptions::kMaxIterations));
  c->add_option("--seed", p.seed, "random seed")->capture_default_str();
  c->add_option("--cell-depth", p.max_depth,
                with_default("deepest adaptive cell (fields without an MPU octree)", p.max_depth, 0,
                             ParticleOptions::kMaxDepth))
      ->check(CLI::Range(0, ParticleOptions::kMaxDepth));
  c->add_option(
       "--flatness", p.flatness_deg,
       with_default("split a cell while its normals vary more than this, degrees", p.flatness_deg))
      ->check(CLI::Range(0.1, 180.0));
  c->add_flag("--skeleton", a->skeleton, "read INPUT as a skeleton whatever its extension");
  c->add_option("--previous", a->previous_path,
                "a particle state (.ply) to regenerate locally after an edit (with --edit-box)");
  c->add_option("--edit-box", a->edit_box, "X0,Y0,Z0,X1,Y1,Z1: the box the edit stayed in")
      ->delimiter(',')
      ->expected(6);
  add_mpu_options(*c, a->reconstruct);
  add_field_options(*c, a->field);
  add_common_options(*c, a->common);
  c->callback([a, &action] { action = [a] { return run_particles(*a); }; });
}

}  // namespace ramiform::cli
