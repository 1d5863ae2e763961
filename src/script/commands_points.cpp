// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Scene commands over point clouds: `mpu` (an MPU implicit fitted to a point cloud or a mesh,
// field/mpu.h) and `particles` (particles spread over a shape, particles/surface_particles.h).

#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/field/mpu.h"
#include "ramiform/field/point_normals.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/io/surface_points.h"
#include "ramiform/particles/surface_particles.h"
#include "session.h"

namespace ramiform::script {
namespace {

CommandResult run_mpu(Call& c) {
  c.expect_count(2, 2, "NAME FILE");
  const std::string name = c.new_name(0);
  const std::string path = c.input_path(1);
  SurfacePointsOptions read;
  read.mesh_samples = static_cast<std::size_t>(
      c.option_integer("samples", static_cast<int>(read.mesh_samples), 1, 1 << 26));
  read.seed = seed_for(c, name);
  NormalOptions normals;
  normals.neighbours = c.option_integer("neighbours", normals.neighbours, 3, 256);
  MpuOptions o;
  o.tolerance = c.option_positive("tolerance", o.tolerance);
  o.support = c.option_positive("support", o.support);
  o.min_points = c.option_integer("min_points", o.min_points, 6, 100000);
  o.max_depth = c.option_integer("max_depth", o.max_depth, 0, 20);
  o.sharp_features = c.option_word("sharp", "on", {"on", "off"}) == "on";
  o.iso = c.option_number("iso", o.iso);
  const SurfacePoints in = read_surface_points(path, read);
  NormalReport nr;
  const PointSet points = orient_normals(in.points, normals, &nr, c.session().ctx);
  MpuStats st;
  FieldPtr field = make_mpu_field(points, o, &st, c.session().ctx);
  std::string summary = "MPU implicit of " + std::to_string(points.size()) + " points" +
                        (in.mesh_triangles > 0 ? " drawn on a mesh" : "") + ", " +
                        std::to_string(st.leaves) + " leaves";
  if (nr.estimated > 0) summary += ", " + std::to_string(nr.estimated) + " normals estimated";
  if (nr.flipped > 0) summary += ", " + std::to_string(nr.flipped) + " normals flipped";
  c.define(name, shape(std::move(field), summary));
  return defined(c, name);
}

}  // namespace

ParticleOptions particle_options(const Call& c, std::size_t default_count,
                                 const std::string& seed_name) {
  ParticleOptions o;
  o.per_cell =
      static_cast<std::size_t>(c.option_integer("per_cell", static_cast<int>(o.per_cell), 1, 1000));
  o.count = static_cast<std::size_t>(
      c.option_integer("count", static_cast<int>(default_count), 0, 1 << 26));
  o.iterations = c.option_integer("iterations", o.iterations, 0, ParticleOptions::kMaxIterations);
  o.max_depth = c.option_integer("cell_depth", o.max_depth, 0, ParticleOptions::kMaxDepth);
  o.flatness_deg = c.option_positive("flatness", o.flatness_deg);
  o.seed = seed_for(c, seed_name);
  return o;
}

ParticleSystem saved_particles(const Call& c, const Token& token, double iso) {
  const std::string path = c.written_or_input_path(token);  // fails at the token if missing
  ParticleSystem system;
  try {
    system = read_particles(path);
  } catch (const InputError& e) {
    c.fail(token, e.what());
  }
  if (system.iso != iso) {
    c.fail(token, "the saved particles lie on iso " + format_number(system.iso) +
                      ", the shape's surface is iso " + format_number(iso));
  }
  return system;
}

namespace {

CommandResult run_particles(Call& c) {
  c.expect_count(1, 1, "SHAPE");
  const Object& object = c.object(0, ObjectKind::kShape);
  const std::string name = c.has_option("name") ? c.option_token("name")->text : c.arg(0).text;
  const ParticleOptions o = particle_options(c, 0, name);
  // An MPU shape brings its octree leaves (the paper's cells); any other shape gets adaptive
  // cells from its bound.
  ParticleStats st;
  ParticleSystem system;
  if (c.has_option("previous")) {
    // Local regeneration (paper §3): only the particles near the edit box move.
    const Token& prev = *c.option_token("previous");
    if (!c.has_option("edit_min") || !c.has_option("edit_max")) {
      c.fail(prev,
             "previous= needs edit_min=X,Y,Z and edit_max=X,Y,Z (the box the edit stayed in)");
    }
    const Aabb box(c.option_vec3("edit_min", Vec3::Zero()),
                   c.option_vec3("edit_max", Vec3::Zero()));
    if (box.isEmpty()) c.fail(*c.option_token("edit_max"), "edit_max is below edit_min");
    const ParticleSystem previous = saved_particles(c, prev, object.field->iso());
    system = regenerate_particles(*object.field, previous, box, o, &st, c.session().ctx);
  } else {
    if (c.has_option("edit_min") || c.has_option("edit_max")) {
      c.fail("edit_min= and edit_max= need previous=STATE.ply (the particles to regenerate)");
    }
    system =
        spread_particles(*object.field, o, field_cells(*object.field), {}, &st, c.session().ctx);
  }
  PointSet points = particle_points(system);
  const std::size_t n = points.size();
  c.session().point_sets[name] = std::move(points);
  c.session().current_points = name;
  if (c.has_option("state")) {
    const Token& t = *c.option_token("state");
    write_particles(system, c.output_path(t, t.text));
  }
  return {c.spec().name,
          "point set " + name + ": " + std::to_string(n) + " particles on " + c.arg(0).text + " (" +
              std::to_string(st.cells) + " cells, spacing CV " + format_number(st.spacing_cv) + ")",
          false};
}

}  // namespace

void add_point_commands(std::vector<CommandSpec>& out) {
  out.push_back(
      {"mpu",
       "mpu NAME FILE [tolerance=E] [support=A] [min_points=N] [max_depth=D] [sharp=on|off] "
       "[neighbours=K] [samples=N] [seed=S] [iso=V]",
       "A multi-level partition of unity implicit (Ohtake et al. 2003) fitted to FILE: points "
       "('x y z [nx ny nz]' text, .xyz, .pwn, PLY) or a mesh (.ply with faces, .off, .obj; "
       "`samples` points drawn on it). Missing normals are estimated and every normal is "
       "oriented outward (docs/reconstruction.md). The shape is a signed distance (iso 0): "
       "union, intersection and difference combine it with any other.",
       "mpu pebble data/pebble.xyz\nsphere ball 0.5 center=1.2,0,0\nunion pebble ball both",
       {"tolerance", "support", "min_points", "max_depth", "sharp", "neighbours", "samples", "seed",
        "iso"},
       run_mpu,
       {}});
  out.push_back(
      {"particles",
       "particles SHAPE [count=N] [per_cell=K] [iterations=I] [cell_depth=D] [flatness=DEG] "
       "[seed=S] [name=P] [state=FILE.ply] [previous=STATE.ply edit_min=X,Y,Z edit_max=X,Y,Z]",
       "Spreads particles evenly over the surface of SHAPE (Witkin and Heckbert; Proenca et "
       "al. 2008 §4): K per cell of the shape's MPU octree or of adaptive cells, repelled "
       "within their radius and held on the surface, `iterations` steps (docs/particles.md). "
       "The particles become the point set P (positions and normals; save_point_set writes "
       "them); state= also writes the whole particle state. With previous= (a state saved "
       "before an edit of SHAPE confined to the box edit_min..edit_max) only the particles near "
       "the box are regenerated; the rest keep their exact positions (§3).",
       "sphere s 1\nparticles s count=2000\nsave_point_set particles.ply",
       {"count", "per_cell", "iterations", "cell_depth", "flatness", "seed", "name", "state",
        "previous", "edit_min", "edit_max"},
       run_particles,
       {}});
}

}  // namespace ramiform::script
