// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// `ramiform mesh SKELETON [-o OUT] --method mc [--cell H | --resolution N] [--kernel ...]`

#include <algorithm>
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "common.h"
#include "mesh_job.h"
#include "ramiform/core/errors.h"

namespace ramiform::cli {
namespace {

struct MeshArgs {
  std::string skeleton_path;
  std::string out_path;
  MeshJobOptions job;
  FieldFlags field;
  CommonOptions common;
  std::vector<double> lod_values;       ///< --lod
  bool lod_budget = false;              ///< --lod-budget
  std::ostream* out = &std::cout;       ///< the "wrote ..." line
  std::ostream* err = &std::cerr;       ///< warnings
  nlohmann::json* stats_out = nullptr;  ///< when not null, receives the --stats figures
};

int run_mesh(MeshArgs& args) {
  RunScope scope(args.common);
  StageTimer timer;
  const SkeletonFieldOptions options = field_options(args.field);
  if (args.out_path.empty()) {
    args.out_path = std::filesystem::path(args.skeleton_path).stem().string() + ".ply";
  }
  check_output_path(args.out_path, kMeshFormats);
  for (const std::string& p : lod_paths(args.out_path, args.job.lods.size())) check_output_path(p);
  check_output_path(args.common.stats_path);
  const Skeleton skeleton = read_skeleton(args.skeleton_path, read_options(args.field));
  timer.lap("read");
  const MeshJobResult result = mesh_skeleton(skeleton, options, args.job, args.out_path, timer,
                                             scope.context(), equipotential_options(args.field));
  nlohmann::json stats = result.stats;
  stats["seconds"] = timer.seconds();
  write_stats(args.common.stats_path, stats);
  if (args.stats_out != nullptr) *args.stats_out = stats;
  std::ostream& out = *args.out;
  std::ostream& err = *args.err;
  out << "wrote " << args.out_path << ": " << result.mesh.vertex_count() << " vertices, "
      << result.mesh.triangle_count() << " triangles"
      << (result.report.watertight ? ", watertight" : ", NOT watertight");
  if (!result.lod_triangles.empty()) {
    out << "; " << result.lod_triangles.size() << " levels of detail:";
    for (std::size_t k = 0; k < result.lod_triangles.size(); ++k) {
      out << (k > 0 ? "," : "") << " LOD" << k << " " << result.lod_triangles[k];
    }
    out << " triangles";
    if (result.written.size() > 1) out << " (" << result.written.size() << " files)";
  }
  out << '\n';
  if (result.mesh.triangle_count() == 0) {
    err << "ramiform: failure: " << args.out_path
        << ": the mesh is empty: the polygonizer found no surface, the field stays below its iso "
           "value everywhere it looked (a convolution surface hardly forms around edges much "
           "shorter than their radius: --surface distance skins every edge at its radius; "
           "--method mc misses a surface thinner than its cells: give a smaller --cell)\n";
    return 3;
  }
  // A coarse lattice (levels 0 and 1, or a coarse mc cell) can let a thin branch fall apart;
  // say so instead of leaving it to a later check.
  const auto components = stats.value("components", std::size_t{0});
  const auto expected = stats.value("skeleton_components", std::size_t{0});
  if (components > expected) {
    err << "ramiform: warning: " << args.out_path << " has " << components << " components for "
        << expected << " connected skeleton part(s): branches thinner than the lattice came apart ("
        << (args.job.method == "mc" ? "use a smaller --cell" : "use more --levels") << ")\n";
  }
  if (const auto folded = stats.value("inverted_triangles", std::size_t{0}); folded > 0) {
    err << "ramiform: warning: " << args.out_path << ": " << folded << " of "
        << stats.value("triangles", std::size_t{0})
        << " triangles face into the surface: the particle mesh folds over itself where "
           "the surface's shape departs from the skeleton's (branches not joined in the "
           "skeleton that merge, or sharp bends along runs of edges shorter than their radius; "
           "--method tets meshes the same surface without folds)\n";
  }
  if (const auto outside = stats.value("nodes_outside", std::size_t{0}); outside > 0) {
    err << "ramiform: warning: " << args.out_path << ": " << outside
        << " skeleton node(s) lie outside the particle mesh (at";
    std::size_t shown = 0;
    for (const auto& q : stats["outside_nodes"]) {
      if (shown++ == 5) break;
      err << " (" << format_number(q[0].get<double>()) << ", " << format_number(q[1].get<double>())
          << ", " << format_number(q[2].get<double>()) << ")";
    }
    err << (outside > 5 ? " ..." : "")
        << "): a fold where branches not joined in the skeleton merge covers them (--method tets "
           "keeps every node inside)\n";
  }
  if (args.job.method == "particles" &&
      stats.value("converged", std::size_t{0}) < stats.value("particles", std::size_t{0})) {
    const std::size_t left =
        stats.value("particles", std::size_t{0}) - stats.value("converged", std::size_t{0});
    err << "ramiform: failure: " << args.out_path << ": " << left << " of "
        << stats.value("particles", std::size_t{0})
        << " particles did not reach the surface within --delta " << args.job.particles.delta
        << " after " << stats.value("iterations", 0) << " iterations (particles";
    std::size_t shown = 0;
    for (const auto& i : stats["unconverged"]) {
      if (shown++ == 10) break;
      err << ' ' << i.get<std::uint32_t>();
    }
    err << (left > 10 ? " ..." : "") << "; the mesh was written; raise --max-iterations)\n";
    return 3;
  }
  if (args.job.method == "tets" && args.job.to_tolerance &&
      !stats.value("tolerance_reached", true)) {
    err << "ramiform: warning: " << args.out_path << ": deviation p99 "
        << stats.value("deviation_p99", 0.0) << " is above --tolerance "
        << args.job.tolerance.tolerance << " (refinement stopped: "
        << (stats["refine"].value("budget_reached", false) ? "triangle budget" : "passes used up")
        << ")\n";
  }
  return 0;
}

std::shared_ptr<MeshArgs> add_mesh(CLI::App& root, Action& action) {
  auto args = std::make_shared<MeshArgs>();
  CLI::App* c = root.add_subcommand(
      "mesh", "Mesh the implicit surface of a skeleton (convolution surface by default).");
  c->add_option("SKELETON", args->skeleton_path,
                "skeleton file (.json, .ply, .obj, .txt TreeQSM, .csv SimpleForest, .swc)")
      ->required();
  c->add_option("-o,--output", args->out_path,
                "output mesh (.ply binary, .obj, .off or .glb); default SKELETON's name .ply");
  c->add_option("--method", args->job.method,
                "polygonizer: tets (skeleton-bounded tetrahedra, default), mc (uniform marching "
                "cubes over the field's bounds) or particles (particles moved onto the surface "
                "and joined by the skeleton's structure; Gruber & Wallner 2014; the surface "
                "defaults to equipotential)")
      ->check(CLI::IsMember({"tets", "mc", "particles"}));
  TetrahedralOptions& tets = args->job.tets;
  tets.levels = args->job.tolerance.tets.levels;
  ToleranceOptions& tol = args->job.tolerance;
  auto* tolerance =
      c->add_option("--tolerance", tol.tolerance,
                    with_default("tets: the deviation p99 to reach, relative to the local "
                                 "radius",
                                 tol.tolerance, ToleranceOptions::kMinTolerance,
                                 ToleranceOptions::kMaxTolerance) +
                        "; the base mesh at --levels is refined where it is farther from the "
                        "surface, then measured (deviation_p99 in --stats)")
          ->check(CLI::Range(ToleranceOptions::kMinTolerance, ToleranceOptions::kMaxTolerance));
  auto* max_triangles =
      c->add_option("--max-triangles", tol.max_triangles,
                    with_default("tets: the refinement's triangle budget", tol.max_triangles) +
                        "; a smaller --max-memory lowers it (256 bytes per triangle), and "
                        "refinement stops before a round that would exceed it")
          ->check(CLI::PositiveNumber);
  auto* samples =
      c->add_option("--deviation-samples", tol.samples,
                    with_default("tets: points of each deviation measure of the tolerance "
                                 "mesher",
                                 tol.samples) +
                        " (at least 100)")
          ->check(CLI::Range(std::size_t{100}, std::size_t{100'000'000}));
  c->add_option("--levels", tets.levels,
                with_default("tets: 1:8 subdivision levels of the base mesh", tets.levels,
                             TetrahedralOptions::kMinLevels, TetrahedralOptions::kMaxLevels) +
                    "; --levels without --tolerance meshes at exactly these levels, unrefined "
                    "(the paper's uniform method)")
      ->check(CLI::Range(TetrahedralOptions::kMinLevels, TetrahedralOptions::kMaxLevels));
  c->add_option(
       "--section-scale", tets.section_scale,
       with_default("tets: cross-section square edge / radius", tets.section_scale,
                    TetrahedralOptions::kMinSectionScale, TetrahedralOptions::kMaxSectionScale) +
           "; 3 is the paper's 3R. 2.6 gives level 1 eight-sided instead of four-sided "
           "branch sections (docs/polygonize.md)")
      ->check(
          CLI::Range(TetrahedralOptions::kMinSectionScale, TetrahedralOptions::kMaxSectionScale));
  c->add_flag("!--no-cleanup", tets.cleanup,
              "tets: skip the needle cleanup pass (edge collapses of short edges)");
  c->add_flag("--fit-radii", args->job.fit_radii,
              "convolution surface: split long/tapered edges and fit one weight per piece by "
              "non-negative least squares so the surface passes through the nodes' radii; "
              "equipotential surface: fit one charge value per edge the same way; adds "
              "radius_error_* to --stats");
  c->add_flag("--radius-error", args->job.radius_error,
              "measure the surface's radius error against the skeleton's radii (in --stats)");
  add_output_options(*c, args->job);
  auto* lod =
      c->add_option("--lod", args->lod_values,
                    "tets: levels of detail, finest first: deviation tolerances (e.g. "
                    "0.05,0.15,0.4), or with --lod-budget triangle budgets (e.g. "
                    "1000000,300000,100000); each level is a watertight mesh of the same field. "
                    "-o tree.glb writes one file with nodes LOD0, LOD1, ... (MSFT_lod); another "
                    "format one file per level: tree.lod0.ply, tree.lod1.ply, ...")
          ->delimiter(',');
  c->add_flag("--lod-budget", args->lod_budget,
              "read the --lod values as triangle budgets: each level is the finest mesh within "
              "its budget");
  ParticleMeshOptions& pm = args->job.particles;
  std::vector<CLI::Option*> particle_options;
  particle_options.push_back(
      c->add_option(
           "--n-circ", pm.n_circ,
           with_default("particles: particles on each ring around an edge", pm.n_circ, 3, 4096))
          ->check(CLI::Range(3, 4096)));
  particle_options.push_back(
      c->add_option("--n-sphere", pm.n_sphere,
                    with_default("particles: particles on each junction sphere before removal",
                                 pm.n_sphere, 4, 65536))
          ->check(CLI::Range(4, 65536)));
  particle_options.push_back(
      c->add_option("--placement-radius", pm.placement_radius,
                    "particles: the placement radius R of the rings (model units); default per "
                    "edge " +
                        format_number(pm.placement_factor) + " times its mean node radius")
          ->check(CLI::PositiveNumber));
  particle_options.push_back(
      c->add_option("--delta", pm.delta,
                    with_default("particles: a particle has converged when |f - lambda| <= "
                                 "delta * lambda",
                                 pm.delta))
          ->check(CLI::Range(1e-12, 0.5)));
  particle_options.push_back(
      c->add_option("--max-iterations", pm.max_iterations,
                    with_default("particles: movement iterations at most (then exit 3 naming the "
                                 "particles that did not converge)",
                                 pm.max_iterations))
          ->check(CLI::Range(1, 100000)));
  particle_options.push_back(
      c->add_option("--relax", pm.relax,
                    with_default("particles: rounds of tangential relaxation after convergence "
                                 "(0: the paper's method alone)",
                                 pm.relax, 0, 100))
          ->check(CLI::Range(0, 100)));
  MarchingCubesOptions& mc = args->job.mc;
  auto* cell = c->add_option("--cell", mc.cell_size, "mc: cell edge length (model units)")
                   ->check(CLI::PositiveNumber);
  auto* res = c->add_option("--resolution", mc.resolution,
                            with_default("mc: cells along the longest side of the surface's box",
                                         mc.resolution, MarchingCubesOptions::kMinResolution,
                                         MarchingCubesOptions::kMaxResolution))
                  ->check(CLI::Range(MarchingCubesOptions::kMinResolution,
                                     MarchingCubesOptions::kMaxResolution));
  cell->excludes(res);
  auto* levels = c->get_option("--levels");
  auto* scale = c->get_option("--section-scale");
  add_field_options(*c, args->field);
  add_common_options(*c, args->common);
  c->callback([args, cell, res, levels, scale, tolerance, max_triangles, samples, lod,
               particle_options, &action] {
    if (args->job.method != "particles") {
      for (CLI::Option* o : particle_options) {
        if (o->count() > 0) {
          throw CLI::ValidationError(o->get_name(), "applies to --method particles only");
        }
      }
    } else {
      if (!args->field.surface_given) args->field.surface = "equipotential";
      if (levels->count() > 0 || scale->count() > 0 || tolerance->count() > 0 ||
          cell->count() > 0 || res->count() > 0 || lod->count() > 0) {
        throw CLI::ValidationError("--method particles",
                                   "takes no --levels, --section-scale, --tolerance, --cell, "
                                   "--resolution or --lod");
      }
    }
    // Equipotential options without the equipotential surface, or --kernel/--iso with it, are
    // a usage error like the other misplaced options (exit 1), not bad input.
    try {
      (void)equipotential_options(args->field);
    } catch (const InvalidArgument& e) {
      throw CLI::ValidationError(e.what());
    }
    // As in the scene language: the fitted charges scale with lambda, so --lambda-scale would
    // change the numbers and not the surface.
    if (args->field.surface == "equipotential" && args->job.fit_radii &&
        args->field.equipotential.lambda_scale != EquipotentialOptions{}.lambda_scale) {
      throw CLI::ValidationError("--lambda-scale",
                                 "does not change the surface with --fit-radii (the fitted "
                                 "charges scale with lambda)");
    }
    if (args->job.method == "tets" && (cell->count() > 0 || res->count() > 0)) {
      throw CLI::ValidationError(cell->count() > 0 ? "--cell" : "--resolution",
                                 "applies to --method mc only (the default method is tets)");
    }
    if (args->job.method == "mc" &&
        (levels->count() > 0 || scale->count() > 0 || tolerance->count() > 0)) {
      throw CLI::ValidationError(levels->count() > 0
                                     ? "--levels"
                                     : (scale->count() > 0 ? "--section-scale" : "--tolerance"),
                                 "applies to --method tets only");
    }
    args->job.to_tolerance = tolerance->count() > 0 || levels->count() == 0;
    for (const CLI::Option* o : {max_triangles, samples}) {
      if (o->count() > 0 && (args->job.method != "tets" || !args->job.to_tolerance)) {
        throw CLI::ValidationError(o->get_name(),
                                   "applies to the tolerance mesher only (--method tets without "
                                   "--levels alone)");
      }
    }
    if (lod->count() > 0) {
      if (args->job.method != "tets" || !args->job.to_tolerance) {
        throw CLI::ValidationError("--lod",
                                   "applies to the tolerance mesher only (--method tets without "
                                   "--levels alone)");
      }
      try {
        args->job.lods = lod_levels(args->lod_values, args->lod_budget);
        validate_lod_levels(args->job.lods);
      } catch (const InvalidArgument& e) {
        throw CLI::ValidationError("--lod", e.what());
      }
    } else if (args->lod_budget) {
      throw CLI::ValidationError("--lod-budget", "needs --lod");
    }
    action = [args] { return run_mesh(*args); };
  });
  return args;
}

}  // namespace

void register_mesh(CLI::App& root, Action& action) { add_mesh(root, action); }

nlohmann::json run_mesh_command(const std::vector<std::string>& args, std::ostream& out,
                                std::ostream& err) {
  CLI::App root{"ramiform", "ramiform"};
  root.require_subcommand(1);
  Action action;
  const std::shared_ptr<MeshArgs> mesh = add_mesh(root, action);
  std::vector<std::string> words{"mesh"};
  words.insert(words.end(), args.begin(), args.end());
  std::reverse(words.begin(), words.end());  // CLI11 takes the arguments last to first
  root.parse(words);
  nlohmann::json stats;
  mesh->out = &out;
  mesh->err = &err;
  mesh->stats_out = &stats;
  if (action) action();
  return stats;
}

}  // namespace ramiform::cli
