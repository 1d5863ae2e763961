// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// The scene language's `draw`: a pen-and-ink line drawing of a shape (lines/, io/drawing_io.h).

#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/io/drawing_io.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"
#include "session.h"

namespace ramiform::script {
namespace {

LineOptions line_options(const Call& c) {
  LineOptions o;
  if (c.has_option("lines")) {
    const Token& t = *c.option_token("lines");
    std::vector<std::string> kinds;
    std::string_view rest = t.text;
    for (std::size_t comma = rest.find(','); true; comma = rest.find(',')) {
      kinds.emplace_back(rest.substr(0, comma));
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
    try {
      select_line_kinds(o, kinds);
    } catch (const InvalidArgument& e) {
      c.fail(t, e.what());
    }
  }
  o.k_c = c.option_positive("k_c", o.k_c);
  o.k_e = c.option_positive("k_e", o.k_e);
  o.k_d = c.option_positive("k_d", o.k_d);
  o.theta_sc_deg = c.option_number("theta_sc", o.theta_sc_deg);
  o.t_d = c.option_number("t_d", o.t_d);
  o.k_a_deg = c.option_positive("k_a", o.k_a_deg);
  o.k_trim = c.option_integer("k_trim", o.k_trim, 1, 1000);
  o.fit = fit_from_name(c.option_word("fit", "longest", {"longest", "trim"}));
  o.straddle =
      straddle_from_name(c.option_word("straddle", "auto", {"auto", "movement", "search"}));
  o.visibility =
      visibility_from_name(c.option_word("visibility", "rays", {"rays", "surfels", "none"}));
  try {
    validate(o);
  } catch (const InvalidArgument& e) {
    c.fail(e.what());
  }
  return o;
}

CommandResult run_draw(Call& c) {
  c.expect_count(2, 2, "SHAPE FILE");
  const Object& object = c.object(0, ObjectKind::kShape);
  const Field& field = *object.field;
  const LineOptions lo = line_options(c);
  DrawingStyle style;
  style.width = c.option_integer("width", style.width, 16, 16384);
  style.height = c.option_integer("height", style.width, 16, 16384);
  style.show_hidden = c.option_word("hidden", "no", {"yes", "no"}) == "yes";
  if (c.session().options.draft) {
    return {"draw", c.arg(1).text + ": not drawn (draft run)", true};
  }

  // The particles: saved ones (`particles SHAPE state=FILE` earlier, or an input file), else
  // spread here with the `particles` command's options (count 10,000 unless per_cell is given).
  ParticleSystem system;
  if (c.has_option("state")) {
    for (const char* key : {"count", "per_cell", "iterations", "cell_depth", "flatness", "seed"}) {
      if (c.has_option(key)) {
        c.fail(*c.option_token(key),
               std::string(key) + "= spreads new particles; state= reuses saved ones");
      }
    }
    system = saved_particles(c, *c.option_token("state"), field.iso());
  } else {
    const ParticleOptions po =
        particle_options(c, c.has_option("per_cell") ? 0 : 10000, c.arg(0).text + "/draw");
    system = spread_particles(field, po, field_cells(field), {}, nullptr, c.session().ctx);
  }
  if (system.particles.empty()) c.fail(c.arg(0), "no particles reached the surface of the shape");
  Aabb box;
  for (const SurfaceParticle& p : system.particles) box.extend(p.position);
  const bool z_up = c.option_word("vertical", "y", {"y", "z"}) == "z";
  Camera camera =
      frame_box(box, c.option_number("azimuth", 30), c.option_number("elevation", 15),
                c.option_number("fov", 30), static_cast<double>(style.width) / style.height,
                z_up ? ViewUp::kZ : ViewUp::kY);
  camera.eye = c.option_vec3("eye", camera.eye);
  camera.target = c.option_vec3("target", camera.target);
  camera.up = c.option_vec3("up", camera.up);
  try {
    validate(camera);
  } catch (const InvalidArgument& e) {
    c.fail(e.what());
  }
  LineStats ls;
  const LineDrawing drawing = draw_lines(field, system, camera, lo, nullptr, &ls, c.session().ctx);
  const std::string& file = c.arg(1).text;
  const std::string path = c.output_path(1);
  try {
    write_drawing(path, drawing, style);
  } catch (const InvalidArgument& e) {
    c.fail(c.arg(1), e.what());
  }
  if (c.has_option("polylines")) {
    const Token& t = *c.option_token("polylines");
    write_polylines_json(c.output_path(t, t.text), drawing);
  }
  return {c.spec().name,
          file + ": " + std::to_string(ls.lines[0]) + " silhouettes, " +
              std::to_string(ls.lines[1]) + " suggestive contours, " + std::to_string(ls.lines[2]) +
              " feature lines of " + c.arg(0).text + " (" +
              std::to_string(system.particles.size()) + " particles, " +
              format_number(100 * ls.hidden_fraction) + " % hidden)",
          true};
}

}  // namespace

void add_draw_commands(std::vector<CommandSpec>& out) {
  out.push_back(
      {"draw",
       "draw SHAPE FILE [lines=silhouette,suggestive,feature] [azimuth=A] [elevation=E] [fov=F] "
       "[vertical=y|z] "
       "[eye=X,Y,Z] [target=X,Y,Z] [up=X,Y,Z] [count=N] [per_cell=K] [iterations=I] "
       "[cell_depth=D] [flatness=DEG] [state=STATE.ply] [visibility=rays|surfels|none] "
       "[fit=longest|trim] [straddle=auto|movement|search] [k_c=K] [k_e=K] [k_d=K] "
       "[theta_sc=DEG] [t_d=T] [k_a=DEG] [k_trim=N] "
       "[width=PX] [height=PX] [hidden=yes|no] [polylines=FILE.json] [seed=S]",
       "A pen-and-ink line drawing of SHAPE written to FILE (.svg or .png): silhouettes, "
       "suggestive contours and feature lines found from particles spread over the surface "
       "(options as for `particles`; 10,000 by default) or saved by `particles ... state=FILE` "
       "and reused with state=FILE, hidden lines removed (Proença et al. 2008; docs/drawing.md). "
       "The camera frames "
       "the shape from `azimuth` and `elevation` (about the `vertical` axis) unless "
       "eye/target/up are given.",
       "sphere a 1\nsphere b 0.7 center=1.1,0,0\nblend a b ab\ndraw ab ab.svg count=3000",
       {"lines",    "azimuth",  "elevation",  "vertical", "fov",        "eye",
        "target",   "up",       "count",      "per_cell", "iterations", "cell_depth",
        "flatness", "state",    "visibility", "fit",      "k_c",        "k_e",
        "k_d",      "theta_sc", "t_d",        "k_a",      "k_trim",     "width",
        "height",   "hidden",   "polylines",  "seed",     "straddle"},
       run_draw,
       {}});
}

}  // namespace ramiform::script
