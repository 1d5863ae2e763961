// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Curve and surface skeleton commands: `deform`, `bezier`, `patch`, `superquadric` (Rigaudière,
// Gesquière & Faudot, "Shape Modelling with Skeleton based Implicit Primitives", §3.2–4.3).

#include <cmath>
#include <numbers>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/field/surface_skeleton.h"
#include "ramiform/io/points_io.h"
#include "session.h"

namespace ramiform::script {
namespace {

const std::vector<std::string> kDeformKinds = {"identity", "squared-cosine", "flat", "wave",
                                               "linear",   "bezier"};

// Runs `build`, turning the library's InvalidArgument into an error at the command.
template <class Build>
auto checked(const Call& c, Build&& build) {
  try {
    return build();
  } catch (const InvalidArgument& e) {
    c.fail(e.what());
  }
}

CommandResult run_deform(Call& c) {
  if (c.count() < 2) c.expect_count(2, 2, "NAME KIND [VALUES ...]");
  const std::string name = c.new_name(0);
  const Token& kind = c.arg(1);
  std::string text = kind.text;
  for (std::size_t i = 2; i < c.count(); ++i) {
    text += (i == 2 ? ":" : ",") + format_shortest(c.number(i, "value " + std::to_string(i - 1)));
  }
  Deformation d;
  try {
    d = parse_deformation(text);
  } catch (const InvalidArgument& e) {
    c.fail(kind, e.what());
  }
  Object o;
  o.kind = ObjectKind::kDeformation;
  o.deformation = d;
  o.summary = "deformation def(t) = " + format_deformation(d);
  c.define(name, std::move(o));
  return defined(c, name);
}

// Inner control points of `bezier`: positional X,Y,Z arguments from `first` on.
std::vector<Vec3> points_from(const Call& c, std::size_t first) {
  std::vector<Vec3> points;
  for (std::size_t i = first; i < c.count(); ++i) {
    points.push_back(c.parse_vec3(c.arg(i), "control point " + std::to_string(i - first)));
  }
  return points;
}

std::vector<double> numbers_option(const Call& c, const std::string& key) {
  std::vector<double> out;
  const Token* t = c.option_token(key);
  if (t == nullptr) return out;
  std::size_t start = 0;
  while (start <= t->text.size()) {
    const std::size_t comma = std::min(t->text.find(',', start), t->text.size());
    Token item{t->text.substr(start, comma - start), t->column + start};
    out.push_back(c.parse_number(item, key));
    start = comma + 1;
  }
  return out;
}

CommandResult run_bezier(Call& c) {
  if (c.count() < 3) c.expect_count(3, 17, "NAME X0,Y0,Z0 X1,Y1,Z1 [X2,Y2,Z2 ...]");
  const std::string name = c.new_name(0);
  BezierCurve curve;
  curve.controls = points_from(c, 1);
  curve.radii = numbers_option(c, "radii");
  const double radius = c.option_positive("radius", 0.25);
  if (!curve.radii.empty() && c.has_option("radius")) {
    c.fail(*c.option_token("radius"), "give radius= or radii=, not both");
  }
  const Deformation def = deformation_option(c, "def");
  const TieRule tie =
      c.option_word("tie", "first", {"first", "last"}) == "last" ? TieRule::kLast : TieRule::kFirst;
  const DistancePrimitiveOptions options = primitive_options(c);
  FieldPtr f = checked(c, [&] { return make_bezier_field(curve, radius, def, tie, options); });
  std::string summary = "Bezier curve skeleton, degree " +
                        std::to_string(curve.controls.size() - 1) + ", radius " +
                        (curve.radii.empty() ? format_number(radius) : "per control point");
  if (def.kind != Deformation::Kind::kIdentity) summary += ", def " + format_deformation(def);
  c.define(name, shape(std::move(f), summary));
  return defined(c, name);
}

SubdivisionOptions subdivision_options(const Call& c) {
  SubdivisionOptions o;
  o.epsilon_degrees = c.option_positive("epsilon", o.epsilon_degrees);
  if (o.epsilon_degrees > 90) {
    c.fail(*c.option_token("epsilon"),
           "epsilon must be in (0, 90] degrees, got " + format_number(o.epsilon_degrees));
  }
  o.max_depth = c.option_integer("depth", o.max_depth, 0, 10);
  if (c.has_option("max_error")) o.max_error = c.option_positive("max_error", 1.0);
  return o;
}

// The surface skeleton shape shared by `patch` and `superquadric`.
CommandResult define_surface(Call& c, const std::string& name,
                             std::shared_ptr<const ParametricSurface> surface,
                             const std::string& what) {
  const SubdivisionOptions sub = subdivision_options(c);
  const double radius = c.option_positive("radius", 0.1);
  const Deformation du = deformation_option(c, "def_u");
  const Deformation dv = deformation_option(c, "def_v");
  const DistancePrimitiveOptions options = primitive_options(c);
  auto skeleton = checked(
      c, [&] { return std::make_shared<const SurfaceSkeleton>(std::move(surface), sub); });
  const std::string summary =
      what + " skeleton, " + std::to_string(skeleton->patch_count()) + " sub-patches (depth " +
      std::to_string(skeleton->depth_reached()) + "), radius " + format_number(radius) +
      (skeleton->error_is_estimate() ? ", error about " : ", error at most ") +
      format_number(skeleton->error_bound());
  FieldPtr f =
      checked(c, [&] { return make_surface_skeleton_field(skeleton, radius, du, dv, options); });
  c.define(name, shape(std::move(f), summary));
  return defined(c, name);
}

CommandResult run_patch(Call& c) {
  if (c.count() != 2 && c.count() != 17) c.expect_count(2, 2, "NAME FILE or NAME P00 ... P33");
  const std::string name = c.new_name(0);
  BicubicPatch patch;
  if (c.count() == 17) {
    const std::vector<Vec3> points = points_from(c, 1);
    for (std::size_t i = 0; i < 16; ++i) patch.controls[i] = points[i];
  } else {
    const PointSet points = read_points(c.input_path(1));
    if (points.size() != 16) {
      c.fail(c.arg(1), "a bicubic patch needs 16 control points (4 rows of 4), the file has " +
                           std::to_string(points.size()));
    }
    for (std::size_t i = 0; i < 16; ++i) patch.controls[i] = points.positions[i];
  }
  auto surface = checked(c, [&] { return make_patch_surface(patch); });
  return define_surface(c, name, std::move(surface), "bicubic patch");
}

CommandResult run_superquadric(Call& c) {
  if (c.count() != 1 && c.count() != 2 && c.count() != 4)
    c.expect_count(1, 1, "NAME [A | A1 A2 A3]");
  const std::string name = c.new_name(0);
  Superquadric q;
  if (c.count() == 2) q.radii = Vec3::Constant(c.positive(1, "size"));
  if (c.count() == 4) q.radii = {c.positive(1, "a1"), c.positive(2, "a2"), c.positive(3, "a3")};
  q.e1 = c.option_positive("e1", q.e1);
  q.e2 = c.option_positive("e2", q.e2);
  q.center = c.option_vec3("center", q.center);
  auto surface = checked(c, [&] { return make_superquadric_surface(q); });
  return define_surface(c, name, std::move(surface),
                        "superquadric (e1 " + format_number(q.e1) + ", e2 " +
                            format_number(q.e2) + ")");
}

}  // namespace

Deformation deformation_option(const Call& c, const std::string& key) {
  const Token* t = c.option_token(key);
  if (t == nullptr) return {};
  const auto& objects = c.session().objects;
  const auto it = objects.find(t->text);
  if (it != objects.end() && it->second.kind == ObjectKind::kDeformation) {
    return it->second.deformation;
  }
  try {
    return parse_deformation(t->text);
  } catch (const InvalidArgument& e) {
    c.fail(*t, std::string(e.what()) + "; or name a deformation made by `deform`");
  }
}

void add_skeletal_commands(std::vector<CommandSpec>& out) {
  const std::string def_help =
      "def=D names a `deform` object or gives one inline (squared-cosine:S, flat:N, wave:A,W, "
      "linear:V0,V1,..., bezier:B0,B1,...)";
  out.push_back(
      {"deform",
       "deform NAME KIND [VALUES ...]",
       "A deformation function def(t) over [0, 1] that multiplies the distance to a skeleton "
       "(Rigaudière et al. §3.2): the skin's thickness at t is radius / def(t). KIND: "
       "identity; squared-cosine [S] (thickness S at the ends, default 0.25, 1 in the middle); "
       "flat [N] (a cylinder with flat ends, exponent N, default 8); wave A [W] (1 / (1 + A "
       "cos(2 pi W t))); linear V0 V1 ... (piecewise linear through the values); bezier B0 "
       "... (a Bezier function). Use it as def=NAME (def_u=, def_v= on surfaces).",
       "deform spindle squared-cosine 0.2",
       {},
       run_deform,
       {}});
  out.push_back(
      {"bezier",
       "bezier NAME X0,Y0,Z0 X1,Y1,Z1 [X2,Y2,Z2 ...] [radius=R | radii=R0,R1,...] [def=D] "
       "[tie=first|last] [kernel=K] [weight=W]",
       "A Bezier-curve skeleton of any degree up to 15 (one more point than the degree), "
       "skinned at `radius` (default 0.25) or at radii per control point; the distance is "
       "exact (root isolation, Rigaudière et al. §3.4). " +
           def_help +
           ". tie=last takes the largest t where two projections are equally near (default "
           "the smallest).",
       "bezier tail 0,0,0 1,0,1 2,0,0 3,0,0.5 radius=0.2 def=squared-cosine:0.3",
       {"radius", "radii", "def", "tie", "kernel", "weight"},
       run_bezier,
       {}});
  out.push_back(
      {"patch",
       "patch NAME FILE | NAME P00 P01 ... P33 [radius=R] [def_u=D] [def_v=D] [epsilon=DEG] "
       "[depth=N] [max_error=E] [kernel=K] [weight=W]",
       "A bicubic Bezier patch skeleton (16 control points, row by row along u, as X,Y,Z "
       "arguments or a points file) skinned at `radius` (default 0.1). The patch is subdivided "
       "where the derivatives along a side turn by more than `epsilon` degrees (default 10), "
       "at most `depth` times (default 6), and the distance is taken to the flat sub-patches "
       "(Rigaudière et al. §4.1); max_error=E also splits a sub-patch whose error bound "
       "exceeds E (model units), which the angle test alone misses; def_u and def_v deform "
       "the thickness over u and v.",
       "patch leaf data/leaf_patch.txt radius=0.05",
       {"radius", "def_u", "def_v", "epsilon", "depth", "max_error", "kernel", "weight"},
       run_patch,
       {}});
  out.push_back(
      {"superquadric",
       "superquadric NAME [A | A1 A2 A3] [e1=E] [e2=E] [center=X,Y,Z] [radius=R] [def_u=D] "
       "[def_v=D] [epsilon=DEG] [depth=N] [max_error=E] [kernel=K] [weight=W]",
       "Barr's superquadric ellipsoid (half-axes A1 A2 A3, default 1; exponents e1, e2, "
       "default 1) as a surface skeleton: a shell of thickness 2 radius (default 0.1) around "
       "it, subdivided as `patch` is (Rigaudière et al. §4.2).",
       "superquadric shell 1 1 0.6 e1=0.3 e2=0.3 radius=0.08",
       {"e1", "e2", "center", "radius", "def_u", "def_v", "epsilon", "depth", "max_error", "kernel",
        "weight"},
       run_superquadric,
       {}});
}

}  // namespace ramiform::script
