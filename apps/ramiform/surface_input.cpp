// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "surface_input.h"


#include "ramiform/core/errors.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/script/script.h"

namespace ramiform::cli {
namespace {

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
  const std::string ext = lower_extension(path);
  return ext == ".json" || ext == ".swc";
}

}  // namespace

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

void add_surface_input_options(CLI::App& c, SurfaceInputArgs& a, const std::string& what) {
  c.add_option("INPUT", a.input,
               "points or a mesh (as for reconstruct), a skeleton (.json, .swc; others with "
               "--skeleton), or SCRIPT.rf:NAME" +
                   what)
      ->required();
  ParticleOptions& p = a.particles;
  c.add_option("--per-cell", p.per_cell,
               with_default("initial particles per leaf cell (k), on average",
                            static_cast<double>(p.per_cell), 1, 1000))
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000}));
  c.add_option("--count", p.count, "about this many particles in all (instead of --per-cell)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 26));
  c.add_option("--iterations", p.iterations,
               with_default("simulation steps", p.iterations, 0, ParticleOptions::kMaxIterations))
      ->check(CLI::Range(0, ParticleOptions::kMaxIterations));
  c.add_option("--seed", p.seed, "random seed")->capture_default_str();
  c.add_option("--cell-depth", p.max_depth,
               with_default("deepest adaptive cell (fields without an MPU octree)", p.max_depth, 0,
                            ParticleOptions::kMaxDepth))
      ->check(CLI::Range(0, ParticleOptions::kMaxDepth));
  c.add_option(
       "--flatness", p.flatness_deg,
       with_default("split a cell while its normals vary more than this, degrees", p.flatness_deg))
      ->check(CLI::Range(0.1, 180.0));
  c.add_flag("--skeleton", a.skeleton, "read INPUT as a skeleton whatever its extension");
  add_mpu_options(c, a.reconstruct);
  add_field_options(c, a.field);
}

SurfaceInput load_surface_input(SurfaceInputArgs& a, Context& ctx, StageTimer& timer) {
  SurfaceInput in;
  std::string script;
  std::string name;
  if (split_script_input(a.input, script, name)) {
    ScriptOptions so;
    so.allow_any_path = true;
    ScriptSession session(so, &ctx);
    session.run_file(script);
    session.discard();  // the script's own outputs are not this command's
    in.field = session.shape(name);
    in.cells = field_cells(*in.field);  // an MPU shape brings its octree
    in.stats["input"] = "script";
    timer.lap("script");
  } else if (is_skeleton_input(a.input, a.skeleton)) {
    const Skeleton skeleton = read_skeleton(a.input, read_options(a.field));
    timer.lap("read");
    in.field = build_surface(skeleton, field_options(a.field), false, timer, ctx,
                             equipotential_options(a.field))
                   .field;
    in.stats["input"] = "skeleton";
    timer.lap("field");
  } else {
    a.reconstruct.read.seed = a.particles.seed;
    PointSurface s = build_point_surface(a.input, a.reconstruct, ctx,
                                         [&timer](const char* stage) { timer.lap(stage); });
    in.field = s.field;
    in.cells = field_cells(*s.field);
    in.seeds = std::move(s.points.positions);
    in.stats = std::move(s.stats);
    in.stats["input"] = "points";
  }
  return in;
}

void add_particle_stats(nlohmann::json& stats, const ParticleSystem& system,
                        const ParticleStats& ps) {
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
}

}  // namespace ramiform::cli
