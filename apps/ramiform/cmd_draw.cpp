// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// `ramiform draw INPUT -o OUT.svg`: a pen-and-ink line drawing of any surface — silhouettes,
// suggestive contours and feature lines found from particles spread over it, hidden lines
// removed (docs/drawing.md; Proença, Jorge & Costa Sousa 2008).

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "commands.h"
#include "common.h"
#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"
#include "ramiform/io/drawing_io.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/lines/lines.h"
#include "surface_input.h"

namespace ramiform::cli {
namespace {

struct DrawArgs {
  SurfaceInputArgs in;
  std::string out_path;
  std::string camera;  // --camera "eye=...;target=...;up=...;fov=..."
  double azimuth = 30, elevation = 15, fov = 30;
  std::string vertical;  // --vertical y|z; default z for a skeleton, else y
  std::vector<std::string> kinds{"silhouette", "suggestive", "feature"};
  int views = 1;
  std::string polylines_path;
  std::string state_path;  // --particle-state: particles saved by `ramiform particles`
  std::string visibility = "rays";
  std::string fit = "longest";
  std::string straddle = "auto";
  LineOptions lines;
  DrawingStyle style;
  CommonOptions common;
};

// OUT for one view; "name-NNN.ext" (view index, from 000) for a turntable of several.
std::string view_path(const std::string& path, int view, int views) {
  if (views == 1 || path.empty()) return path;
  const std::filesystem::path p(path);
  char number[16];
  std::snprintf(number, sizeof number, "-%03d", view);
  return (p.parent_path() / (p.stem().string() + number + p.extension().string())).string();
}

nlohmann::json camera_json(const Camera& c) {
  return {{"eye", {c.eye.x(), c.eye.y(), c.eye.z()}},
          {"target", {c.target.x(), c.target.y(), c.target.z()}},
          {"up", {c.up.x(), c.up.y(), c.up.z()}},
          {"fov", c.fov_deg},
          {"aspect", c.aspect}};
}

int run_draw(DrawArgs& args) {
  check_output_path(args.out_path, std::array<const char*, 2>{".svg", ".png"});
  check_output_path(args.polylines_path, std::array<const char*, 1>{".json"});
  check_output_path(args.common.stats_path);
  LineOptions& lo = args.lines;
  try {
    select_line_kinds(lo, args.kinds);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(std::string("--lines: ") + e.what());
  }
  lo.visibility = visibility_from_name(args.visibility);
  lo.fit = fit_from_name(args.fit);
  lo.straddle = straddle_from_name(args.straddle);
  if (args.style.height == 0) args.style.height = args.style.width;
  args.style.suggestive.width = 0.5 * args.style.silhouette.width;
  args.style.feature.width = 0.625 * args.style.silhouette.width;
  validate(lo);
  validate(args.style);

  RunScope scope(args.common);
  Context& ctx = scope.context();
  StageTimer timer;
  SurfaceInput in = load_surface_input(args.in, ctx, timer);
  ParticleSystem system;
  ParticleStats ps;
  if (!args.state_path.empty()) {
    system = read_particles(args.state_path);
    if (system.iso != in.field->iso()) {
      throw InvalidArgument("--particle-state " + args.state_path + ": its iso value " +
                            format_number(system.iso) + " is not the surface's " +
                            format_number(in.field->iso()));
    }
    timer.lap("read_particles");
  } else {
    system = spread_particles(*in.field, args.in.particles, in.cells, in.seeds, &ps, &ctx);
    timer.lap("particles");
  }
  if (system.particles.empty()) {
    throw InvalidArgument("'" + args.in.input +
                          "': no particles reached the surface, nothing to draw");
  }
  Aabb box;
  for (const SurfaceParticle& p : system.particles) box.extend(p.position);
  const double aspect = static_cast<double>(args.style.width) / args.style.height;
  const bool z_up = args.vertical.empty() ? in.stats["input"] == "skeleton" : args.vertical == "z";
  const Camera framing = frame_box(box, args.azimuth, args.elevation, args.fov, aspect,
                                   z_up ? ViewUp::kZ : ViewUp::kY);
  const Camera camera = parse_camera(args.camera, framing);

  LineStats feature_stats;
  std::vector<Polyline> features;
  if (lo.features) features = feature_lines(*in.field, system, lo, &feature_stats, &ctx);
  timer.lap("features");

  nlohmann::json views = nlohmann::json::array();
  double line_seconds = 0;
  const std::vector<Camera> cameras = turntable(camera, args.views);
  // Every view's files are held until the last view is drawn: a failure in view k leaves no
  // drawing of the turntable on disk.
  HeldOutputs outputs;
  // The particles' k-d tree and surfel radii do not depend on the view: made once for all.
  const std::optional<ParticleLookup> lookup =
      system.particles.empty() ? std::nullopt : std::make_optional<ParticleLookup>(system);
  for (int v = 0; v < args.views; ++v) {
    LineStats ls;
    const auto start = std::chrono::steady_clock::now();
    const LineDrawing drawing = draw_lines(*in.field, system, cameras[static_cast<std::size_t>(v)],
                                           lo, &features, &ls, &ctx, lookup ? &*lookup : nullptr);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    line_seconds += seconds;
    const std::string out = view_path(args.out_path, v, args.views);
    write_drawing(outputs.add(out), drawing, args.style);
    if (!args.polylines_path.empty()) {
      write_polylines_json(outputs.add(view_path(args.polylines_path, v, args.views)), drawing);
    }
    nlohmann::json view = {{"file", out}, {"camera", camera_json(drawing.camera)}};
    // Feature lines are counted once, where feature_lines() found them; draw_lines copies them.
    for (const LineKind kind : {LineKind::kSilhouette, LineKind::kSuggestive, LineKind::kFeature}) {
      const LineStats& from = kind == LineKind::kFeature ? feature_stats : ls;
      const std::string name(line_kind_name(kind));
      view["lines"][name] = from.lines[static_cast<int>(kind)];
      view["length"][name] = from.length[static_cast<int>(kind)];
    }
    view["silhouette_seeds"] = ls.silhouette_seeds;
    view["suggestive_particles"] = ls.suggestive_particles;
    view["suggestive_clusters"] = ls.suggestive_clusters;
    view["hidden_fraction"] = ls.hidden_fraction;
    view["seconds"] = {{"silhouettes", ls.seconds_silhouettes},
                       {"suggestive", ls.seconds_suggestive},
                       {"visibility", ls.seconds_visibility},
                       {"lines", seconds}};
    views.push_back(std::move(view));
  }
  outputs.publish();
  for (int v = 0; v < args.views; ++v) {
    std::cout << "wrote " << view_path(args.out_path, v, args.views) << '\n';
  }
  timer.lap("views");

  nlohmann::json stats = std::move(in.stats);
  stats["iso"] = in.field->iso();
  if (args.state_path.empty()) {
    add_particle_stats(stats, system, ps);
  } else {
    stats["particles"] = system.particles.size();
  }
  stats["straddle_pairs"] = feature_stats.straddle_pairs;
  stats["straddle_pairs_movement"] = feature_stats.straddle_pairs_movement;
  stats["straddle_pairs_search"] = feature_stats.straddle_pairs_search;
  stats["views"] = std::move(views);
  stats["field_evals"] = in.field->evaluations();
  stats["seconds"] = timer.seconds();
  stats["seconds"]["features"] = feature_stats.seconds_features;
  stats["seconds"]["lines"] = line_seconds / args.views;  // per view
  write_stats(args.common.stats_path, stats);
  return 0;
}

}  // namespace

void register_draw(CLI::App& root, Action& action) {
  auto a = std::make_shared<DrawArgs>();
  CLI::App* c = root.add_subcommand(
      "draw",
      "A pen-and-ink line drawing of a surface: silhouettes, suggestive contours and feature "
      "lines, hidden lines removed, as SVG or PNG (docs/drawing.md).");
  add_surface_input_options(*c, a->in, "");
  c->add_option("-o,--out", a->out_path,
                "output drawing: .svg or .png (with --views N: OUT-000.svg, OUT-001.svg, ...)")
      ->required();
  c->add_option("--camera", a->camera,
                "\"eye=x,y,z;target=x,y,z;up=x,y,z;fov=deg\" (any subset; the rest frames the "
                "surface from --azimuth and --elevation)");
  c->add_option("--azimuth", a->azimuth,
                with_default("default camera: degrees about the up axis", a->azimuth));
  c->add_option("--elevation", a->elevation,
                with_default("default camera: degrees above the horizon", a->elevation, -90, 90))
      ->check(CLI::Range(-90.0, 90.0));
  c->add_option("--vertical", a->vertical,
                "default camera: the model axis that points up, y or z (default: z for a "
                "skeleton, whose trees grow along +z, else y as in scans and glTF)")
      ->check(CLI::IsMember({"y", "z"}));
  c->add_option("--fov", a->fov,
                with_default("default camera: vertical field of view, degrees", a->fov, 1, 170))
      ->check(CLI::Range(1.0, 170.0));
  c->add_option("--lines", a->kinds,
                "line kinds to draw, comma-separated (default silhouette,suggestive,feature)")
      ->delimiter(',');
  c->add_option(
       "--views", a->views,
       with_default("a turntable of this many views about the camera's up axis", a->views, 1, 3600))
      ->check(CLI::Range(1, 3600));
  c->add_option("--polylines", a->polylines_path,
                "also write the lines as JSON: camera and 3-D points with visibility");
  c->add_option("--particle-state", a->state_path,
                "particles saved by `ramiform particles` (.ply) instead of spreading new ones");
  LineOptions& l = a->lines;
  c->add_option("--k-c", l.k_c,
                with_default("silhouette particles: |v.n| below this (eq. 9)", l.k_c, 0, 1))
      ->check(CLI::Range(1e-6, 0.999));
  c->add_option("--k-e", l.k_e,
                with_default("silhouettes grow while |v.n| < k_c k_e (eq. 10)", l.k_e))
      ->check(CLI::Range(1.0, 1000.0));
  c->add_option("--chain-distance", l.chain_distance,
                with_default("silhouette pieces whose ends are this close (x delta) and run on in "
                             "similar directions are joined",
                             l.chain_distance))
      ->check(CLI::Range(0.0, 100.0));
  c->add_option("--k-d", l.k_d,
                with_default("suggestive contours: x +- k_d delta w (eqs. 4-5)", l.k_d))
      ->check(CLI::PositiveNumber);
  c->add_option("--theta-sc", l.theta_sc_deg,
                with_default("suggestive contours: least angle between n and the view, degrees "
                             "(eq. 8)",
                             l.theta_sc_deg, 0, 90))
      ->check(CLI::Range(0.0, 89.999));
  c->add_option("--t-d", l.t_d,
                with_default("suggestive contours: least delta^2 D_w kappa_r, DeCarlo et al.'s "
                             "derivative threshold (0 keeps every minimum of n.v)",
                             l.t_d))
      ->check(CLI::Range(0.0, 1000.0));
  c->add_option("--fit", a->fit,
                "suggestive contours from each cluster's MST: longest (its "
                "longest path) or trim (short branches removed); default longest")
      ->check(CLI::IsMember({"longest", "trim"}));
  c->add_option("--k-trim", l.k_trim,
                with_default("trimmed MST (fit trim): remove leaf branches of fewer particles",
                             l.k_trim, 1, 1000))
      ->check(CLI::Range(1, 1000));
  c->add_option("--k-a", l.k_a_deg,
                with_default("feature lines: normals differing by more than this, degrees "
                             "(eq. 11)",
                             l.k_a_deg, 0, 180))
      ->check(CLI::Range(0.001, 179.999));
  c->add_option("--straddle", a->straddle,
                "feature lines' straddle pairs: movement (each particle's normal before and "
                "after the simulation), search (nearby particles) or auto (movement, then search "
                "when it draws nothing) (default auto)")
      ->check(CLI::IsMember({"auto", "movement", "search"}));
  c->add_option("--visibility", a->visibility,
                "hidden lines: rays (exact, the default), surfels (the paper's disks behind the "
                "particles: faster on scans, but they hide bits of silhouettes) or none")
      ->check(CLI::IsMember({"rays", "surfels", "none"}));
  DrawingStyle& st = a->style;
  c->add_option("--width", st.width, with_default("image width, pixels", st.width, 16, 16384))
      ->check(CLI::Range(16, 16384));
  c->add_option("--height", st.height, "image height, pixels (default: the width)")
      ->check(CLI::Range(16, 16384));
  c->add_option("--stroke", st.silhouette.width,
                with_default("silhouette stroke width, pixels (suggestive contours half, feature "
                             "lines 5/8 of it)",
                             st.silhouette.width))
      ->check(CLI::Range(0.01, 100.0));
  c->add_flag("--hidden", st.show_hidden, "also draw hidden lines, grey and dashed");
  c->add_flag("--white", st.white_background, "SVG: a white background (PNG always has one)");
  add_common_options(*c, a->common);
  c->callback([a, &action] { action = [a] { return run_draw(*a); }; });
}

}  // namespace ramiform::cli
