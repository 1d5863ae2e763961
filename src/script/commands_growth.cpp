// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Point-set and growth commands: the thesis's point_set_* commands (Kochhar 2010, "Application of
// implicit methods to the interactive modeling of trees" (M.Sc. thesis), §7.0.1, §7.1), space
// colonization (§2.5, chapter 7) and L-systems as skeleton sources.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/grow/branch_cleanup.h"
#include "ramiform/grow/lsystem.h"
#include "ramiform/grow/space_colonization.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/sample/point_sets.h"
#include "ramiform/sample/props.h"
#include "session.h"

namespace ramiform::script {

// A seed per named random choice: the session seed mixed with the name (FNV-1a), so that two
// point sets of one script differ and each stays the same when other commands change.
std::uint64_t seed_for(const Call& c, const std::string& name) {
  if (c.has_option("seed")) {
    const double v = c.option_number("seed", 0);
    if (v < 0 || v != std::floor(v) || v > 9.0e15)
      c.fail(*c.option_token("seed"), "seed must be an integer >= 0");
    return static_cast<std::uint64_t>(v);
  }
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : name) h = (h ^ ch) * 1099511628211ull;
  return c.session().options.seed ^ h;
}

namespace {

const PointSet& point_set(const Call& c, const Token& token) {
  const auto& sets = c.session().point_sets;
  const auto it = sets.find(token.text);
  if (it == sets.end()) {
    std::vector<std::string> known;
    for (const auto& [name, p] : sets) known.push_back(name);
    const std::string best = closest_name(token.text, known);
    c.fail(token, "no point set '" + shown(token.text) + "'" +
                      (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                      (known.empty() ? "; make one with point_set_gen or load_point_set" : ""));
  }
  return it->second;
}

CommandResult stored(Call& c, const std::string& name, PointSet points, const std::string& what) {
  const std::size_t n = points.size();
  c.session().point_sets[name] = std::move(points);
  c.session().current_points = name;
  return {c.spec().name, "point set " + name + ": " + std::to_string(n) + " points" + what, false};
}

CommandResult run_point_set_gen(Call& c) {
  c.expect_count(2, 3, "SHAPE DISTRIBUTION [PROPS]");
  const Object& shape = c.object(0, ObjectKind::kShape);
  const Token& dist = c.arg(1);
  const std::vector<std::string> names = distribution_names();
  if (std::find(names.begin(), names.end(), dist.text) == names.end()) {
    const std::string best = closest_name(dist.text, names);
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    c.fail(dist, "unknown distribution '" + shown(dist.text) + "'" +
                     (best.empty() ? "" : " (did you mean '" + best + "'?)") + "; known: " + list);
  }
  Props props;
  props.source = "<none>";
  if (c.count() == 3) props = read_props(c.input_path(2));
  const std::string name = c.has_option("name") ? c.option_token("name")->text : c.arg(0).text;
  const int count = c.option_integer("count", 0, 0, 100'000'000);
  SampleStats stats;
  PointSet points = generate_points(*shape.field, dist.text, props, seed_for(c, name),
                                    static_cast<std::size_t>(count), c.session().ctx, &stats);
  return stored(
      c, name, std::move(points),
      " (" + dist.text + " in " + c.arg(0).text + (stats.saturated ? ", saturated" : "") + ")");
}

CommandResult run_save_point_set(Call& c) {
  c.expect_count(1, 2, "FILE [POINTS]");
  const std::string& current = c.session().current_points;
  if (c.count() == 1 && current.empty())
    c.fail("no point set yet: make one with point_set_gen or load_point_set");
  const Token name_token = c.count() == 2 ? c.arg(1) : Token{current, c.arg(0).column};
  const PointSet& points = point_set(c, name_token);
  const std::string path = c.output_path(0);
  write_points(points, path);
  return {c.spec().name,
          c.arg(0).text + ": " + std::to_string(points.size()) + " points of " + name_token.text,
          true};
}

CommandResult run_point_set_thin(Call& c) {
  c.expect_count(3, 3, "POINTS SECONDARY PERCENT");
  const PointSet& points = point_set(c, c.arg(0));
  const Object& secondary = c.object(1, ObjectKind::kShape);
  const double percent = c.number(2, "percent");
  if (percent < 0 || percent > 100)
    c.fail(c.arg(2), "percent must lie in [0, 100], got " + c.arg(2).text);
  const std::string name = c.arg(0).text;
  const std::size_t before = points.size();
  PointSet thinned =
      thin_points(points, *secondary.field, percent, seed_for(c, name + "/thin"), c.session().ctx);
  const std::size_t removed = before - thinned.size();
  return stored(c, name, std::move(thinned),
                " (" + std::to_string(removed) + " removed inside " + c.arg(1).text + ")");
}

CommandResult run_load_point_set(Call& c) {
  c.expect_count(1, 2, "FILE [NAME]");
  const std::string name = c.count() == 2 ? c.new_name(1) : std::string("points");
  return stored(c, name, read_points(c.input_path(0)), " (from " + c.arg(0).text + ")");
}

CommandResult run_point_set_mesh(Call& c) {
  c.expect_count(2, 2, "NAME MESH");
  const std::string name = c.new_name(0);
  const TriMesh mesh = read_mesh(c.input_path(1));
  NearMeshOptions o;
  o.count = static_cast<std::size_t>(
      c.option_integer("count", static_cast<int>(o.count), 1, 100'000'000));
  o.min_offset = c.option_number("min_offset", 0.0);
  o.max_offset = c.option_number("max_offset", o.min_offset);
  return stored(c, name, sample_near_mesh(mesh, o, seed_for(c, name)),
                " (near " + c.arg(1).text + ")");
}

// surface=convolution|equipotential of grow and lsystem, with the equipotential options
// (read before the skeleton is made, so that a bad option fails first).
std::optional<EquipotentialRequest> tree_surface(const Call& c) {
  const std::string surface =
      c.option_word("surface", "convolution", {"convolution", "equipotential"});
  return equipotential_request(c, surface == "equipotential", surface);
}

Object tree_object(const Call& c, Skeleton skeleton, std::string summary,
                   const std::optional<EquipotentialRequest>& equipotential) {
  Object o;
  o.kind = ObjectKind::kShape;
  if (equipotential) {
    o.equipotential = build_equipotential(c, skeleton, *equipotential, summary);
    o.field = o.equipotential->field;
  } else {
    SkeletonFieldOptions field;  // Cauchy convolution surface: smooth forks
    o.field = make_skeleton_field(skeleton, field);
  }
  o.skeleton = std::move(skeleton);
  o.summary = std::move(summary);
  return o;
}

CommandResult run_grow(Call& c) {
  c.expect_count(3, 3, "TREE from POINTS");
  const std::string name = c.new_name(0);
  if (c.arg(1).text != "from")
    c.fail(c.arg(1), "expected the word 'from', got '" + shown(c.arg(1).text) + "'");
  const PointSet& points = point_set(c, c.arg(2));
  const std::optional<EquipotentialRequest> surface = tree_surface(c);
  ColonizationOptions o;
  o.step = c.option_positive("step", o.step);
  o.influence = c.option_positive("influence", o.influence);
  o.kill = c.option_positive("kill", o.kill);
  o.roots = {c.option_vec3("root", o.roots.front())};
  o.direction = c.option_vec3("direction", o.direction);
  o.tropism = c.option_vec3("tropism", o.tropism);
  o.max_iterations = c.option_integer("max_iterations", o.max_iterations, 0, 10'000'000);
  o.tip_radius = c.option_positive("tip_radius", o.tip_radius);
  o.pipe_exponent = c.option_number("pipe_exponent", o.pipe_exponent);
  o.smooth_iterations = c.option_integer("smooth", o.smooth_iterations, 0,
                                         BranchCleanupOptions::kMaxSmoothIterations);
  o.prune_steps = c.option_number("prune", o.prune_steps);
  if (!(std::isfinite(o.prune_steps) && o.prune_steps >= 0))
    c.fail(*c.option_token("prune"),
           "prune must be a number of growth steps >= 0, got " + c.option_token("prune")->text);
  o.max_turn_deg = c.option_number("max_turn", o.max_turn_deg);
  if (!(o.max_turn_deg > 0 && o.max_turn_deg <= 180))
    c.fail(*c.option_token("max_turn"), "max_turn must be an angle in (0, 180] degrees, got " +
                                            c.option_token("max_turn")->text);
  FieldPtr avoid;
  if (const Token* t = c.option_token("avoid")) {
    avoid = c.object_named(*t, ObjectKind::kShape).field;
    o.obstacle = avoid.get();
  }
  const ColonizationResult r = grow_space_colonization(points.positions, o, c.session().ctx);
  std::string summary = "tree grown from " + c.arg(2).text + ": " +
                        std::to_string(r.skeleton.node_count()) + " nodes, " +
                        std::to_string(r.iterations) + " iterations, " +
                        std::to_string(r.points_reached) + " of " + std::to_string(r.points_total) +
                        " points reached";
  if (r.stalled) summary += "; stopped early: " + r.stall_reason;
  if (r.skeleton.edge_count() == 0) {
    const std::string advice =
        r.stalled ? std::string() : "; move root= away from the points or use a smaller kill=";
    c.fail("grew no branch from " + shown(c.arg(2).text) + ": " +
           no_branch_reason(r, points.positions, o) + advice);
  }
  c.define(name, tree_object(c, r.skeleton, summary, surface));
  return {c.spec().name,
          name + ": " + summary_text(c.session().objects.at(name)) + "; " +
              cleanup_summary(r.cleanup, format_number(kShortTipSteps) + " steps"),
          true};
}

CommandResult run_lsystem(Call& c) {
  c.expect_count(2, 2, "TREE EXAMPLE|FILE");
  const std::string name = c.new_name(0);
  const std::optional<EquipotentialRequest> surface = tree_surface(c);
  std::string text;
  std::string source;
  for (const auto& [example, body] : lsystem_examples()) {
    if (example == c.arg(1).text) {
      text = body;
      source = "example " + example;
    }
  }
  if (text.empty()) {
    if (c.arg(1).text.find('.') == std::string::npos &&
        c.arg(1).text.find('/') == std::string::npos) {
      std::vector<std::string> known;
      for (const auto& [example, body] : lsystem_examples()) known.push_back(example);
      const std::string best = closest_name(c.arg(1).text, known);
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      c.fail(c.arg(1), "no L-system example '" + shown(c.arg(1).text) + "'" +
                           (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                           "; examples: " + list + "; or give a file path");
    }
    source = c.input_path(1);
    std::ifstream in(source);
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  LSystemOptions o;
  o.iterations = c.option_integer("iterations", o.iterations, 0, LSystemOptions::kMaxIterations);
  o.angle_deg = c.option_number("angle", o.angle_deg);
  o.step = c.option_positive("step", o.step);
  o.width = c.option_positive("width", o.width);
  const std::string radii = c.option_word("radii", "width", {"width", "pipe"});
  o.radius = radii == "pipe" ? LSystemRadius::kPipe : LSystemRadius::kWidth;
  o.tip_radius = c.option_positive("tip_radius", o.tip_radius);
  o.pipe_exponent = c.option_number("pipe_exponent", o.pipe_exponent);
  Skeleton skeleton = lsystem_skeleton(text, source, o, c.session().ctx);
  if (skeleton.edge_count() == 0)
    c.fail(c.arg(1), "the L-system draws no segment (no F) after " + std::to_string(o.iterations) +
                         " iterations");
  const std::string summary = "L-system " + c.arg(1).text + ", " + std::to_string(o.iterations) +
                              " iterations, " + std::to_string(skeleton.node_count()) + " nodes";
  c.define(name, tree_object(c, std::move(skeleton), summary, surface));
  return {c.spec().name, name + ": " + summary_text(c.session().objects.at(name)), false};
}

CommandResult run_save_skeleton(Call& c) {
  c.expect_count(2, 2, "TREE FILE");
  const Object& obj = c.object(0, ObjectKind::kShape);
  if (!obj.skeleton)
    c.fail(c.arg(0),
           "'" + shown(c.arg(0).text) + "' has no skeleton (made by grow, lsystem or skeleton)");
  const std::string path = c.output_path(1);
  write_skeleton(*obj.skeleton, path);
  return {c.spec().name,
          c.arg(1).text + ": " + std::to_string(obj.skeleton->node_count()) + " nodes, " +
              std::to_string(obj.skeleton->edge_count()) + " edges",
          true};
}

// A command's options and surface= with the equipotential options.
std::vector<std::string> with_surface(std::vector<std::string> keys) {
  keys.push_back("surface");
  keys.insert(keys.end(), equipotential_keys().begin(), equipotential_keys().end());
  return keys;
}

}  // namespace

void add_growth_commands(std::vector<CommandSpec>& out) {
  const ColonizationOptions grow;
  const LSystemOptions ls;
  out.push_back(
      {"point_set_gen",
       "point_set_gen SHAPE DISTRIBUTION [PROPS] [count=N] [name=P] [seed=S]",
       "Generates points for SHAPE (thesis §7.0.1): uniform, stratified, poisson, lane, field, "
       "boundary, near_surface, ... (docs/sampling.md); parameters come from the PROPS file "
       "('key = value' lines), count= overrides its count. The set is named after the shape "
       "(or name=P) and becomes the current point set.",
       "sphere s\nscale s 50 80 50\npoint_set_gen s poisson data/poisson.props\nsave_point_set "
       "points.txt",
       {"count", "name", "seed"},
       run_point_set_gen,
       {}});
  out.push_back(
      {"save_point_set",
       "save_point_set FILE [POINTS]",
       "Writes the current point set (or the named one): text 'x y z' per line, or binary .ply.",
       "sphere s\npoint_set_gen s uniform count=100\nsave_point_set points.txt",
       {},
       run_save_point_set,
       {}});
  out.push_back(
      {"point_set_thin",
       "point_set_thin POINTS SECONDARY PERCENT",
       "Removes PERCENT % of the points of POINTS that lie inside the shape SECONDARY "
       "(thesis §7.1).",
       "sphere crown 2\nsphere secondary 1 center=1,0,0\npoint_set_gen crown uniform count=500\n"
       "point_set_thin crown secondary 80",
       {"seed"},
       run_point_set_thin,
       {}});
  out.push_back({"load_point_set",
                 "load_point_set FILE [NAME]",
                 "Reads a point set ('x y z' per line or .ply) under NAME (default 'points').",
                 "load_point_set data/blob_points.txt blob",
                 {},
                 run_load_point_set,
                 {}});
  out.push_back(
      {"point_set_mesh",
       "point_set_mesh NAME MESH [count=N] [min_offset=A] [max_offset=B]",
       "Points near a triangle mesh (thesis §6.3): triangles by area, a uniform point in each, "
       "moved along the interpolated normal by an offset in [min_offset, max_offset].",
       "point_set_mesh shell data/cube.obj count=200 min_offset=0.05 max_offset=0.2",
       {"count", "min_offset", "max_offset", "seed"},
       run_point_set_mesh,
       {}});
  out.push_back(
      {"grow",
       "grow TREE from POINTS [step=D] [influence=DI] [kill=DK] [root=X,Y,Z] "
       "[direction=X,Y,Z] [tropism=X,Y,Z] [max_iterations=N] [tip_radius=R] [pipe_exponent=N] "
       "[avoid=SHAPE] [smooth=N] [prune=K] [max_turn=DEG] [surface=convolution|equipotential] "
       "[alpha=A ...]",
       "Space colonization (Runions et al. 2007, thesis §2.5): grows a tree from `root` toward "
       "the points in steps of `step`" +
           default_text(grow.step) + "; points within `influence`" + default_text(grow.influence) +
           " attract a node and points within `kill`" + default_text(grow.kill) +
           " die, for at most `max_iterations`" + default_text(grow.max_iterations) +
           " iterations. Then pipe-model radii: `tip_radius`" + default_text(grow.tip_radius) +
           " at the tips, exponent `pipe_exponent`" +
           default_text(grow.pipe_exponent, ColonizationOptions::kMinPipeExponent,
                        ColonizationOptions::kMaxPipeExponent) +
           ". `avoid` keeps nodes out of a shape (§7.2). Then branch cleanup (docs/growth.md): "
           "`smooth`" +
           default_text(grow.smooth_iterations, 0, BranchCleanupOptions::kMaxSmoothIterations) +
           " Laplacian passes along unbranched chains (forks, root and tips stay), removing "
           "chain nodes that still turn by more than `max_turn`" +
           default_text(grow.max_turn_deg) + " degrees, and `prune`" +
           default_text(grow.prune_steps) +
           " removes tip branches of at most that many steps (stubs); after removals the radii are "
           "recomputed. The "
           "message reports what changed and the turn angles and short tips before and after. "
           "TREE is a shape: the Cauchy convolution surface of the skeleton, or with "
           "`surface`=equipotential its equipotential surface (the options alpha=, charge=, "
           "charge_spacing=, lambda=, lambda_scale=, open_ends=, fit_radii= as for skeleton); "
           "save_mesh method=tets or method=particles meshes it, save_skeleton writes the "
           "skeleton.",
       "sphere crown 3 center=0,0,5\npoint_set_gen crown uniform count=300\n"
       "grow tree from crown step=0.4 influence=2 kill=0.8 smooth=8 prune=2\n"
       "save_skeleton tree tree.json",
       with_surface({"step", "influence", "kill", "root", "direction", "tropism", "max_iterations",
                     "tip_radius", "pipe_exponent", "avoid", "smooth", "prune", "max_turn"}),
       run_grow,
       {}});
  out.push_back(
      {"lsystem",
       "lsystem TREE EXAMPLE|FILE [iterations=N] [angle=DEG] [step=L] [width=W] [radii=width|pipe] "
       "[surface=convolution|equipotential] [alpha=A ...]",
       "A skeleton from a bracketed parametric L-system (docs/growth.md): one of the built-in "
       "examples or a file, derived `iterations`" +
           default_text(ls.iterations, 0, LSystemOptions::kMaxIterations) +
           " times; the turtle turns by `angle`" + default_text(ls.angle_deg) +
           " degrees, moves by `step`" + default_text(ls.step) + " and starts with `width`" +
           default_text(ls.width) +
           ". TREE is the Cauchy convolution surface of the skeleton, or with "
           "`surface`=equipotential its equipotential surface (options as for skeleton).",
       "lsystem plant abop_fig1_24a iterations=4\nsave_skeleton plant plant.json",
       with_surface(
           {"iterations", "angle", "step", "width", "radii", "tip_radius", "pipe_exponent"}),
       run_lsystem,
       {}});
  out.push_back(
      {"save_skeleton",
       "save_skeleton TREE FILE",
       "Writes the skeleton of a tree (grow, lsystem or skeleton) as JSON (or .ply/.obj).",
       "skeleton fork data/fork.json\nsave_skeleton fork fork_copy.json",
       {},
       run_save_skeleton,
       {}});
}

}  // namespace ramiform::script
