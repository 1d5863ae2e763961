// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Curve commands and the curve-based surfaces of Kochhar 2010, "Application of implicit methods to
// the interactive modeling of trees" (M.Sc. thesis), §4.1–4.2: surfaces of revolution, sweeps and
// implicit skinning.

#include "ramiform/core/errors.h"
#include "ramiform/field/curves.h"
#include "ramiform/field/sweep.h"
#include "ramiform/io/curve_io.h"
#include "session.h"

namespace ramiform::script {
namespace {

const std::vector<std::string> kCurveKinds = {"polyline", "bezier", "bspline"};

CurveKind curve_kind(const Call& c, std::size_t i) {
  const Token& t = c.arg(i);
  if (t.text == "polyline") return CurveKind::kPolyline;
  if (t.text == "bezier") return CurveKind::kBezier;
  if (t.text == "bspline") return CurveKind::kBSpline;
  c.fail(t, "expected the curve kind polyline, bezier or bspline, got '" + t.text + "'" +
                (closest_name(t.text, kCurveKinds).empty()
                     ? ""
                     : " (did you mean '" + closest_name(t.text, kCurveKinds) + "'?)"));
}

// Coordinates from the positional arguments [first, count) or from file=F.
template <int Dim>
std::vector<Eigen::Matrix<double, Dim, 1>> curve_points(const Call& c, std::size_t first) {
  using V = Eigen::Matrix<double, Dim, 1>;
  std::vector<V> pts;
  if (const Token* file = c.option_token("file")) {
    if (c.count() > first)
      c.fail(c.arg(first), "give the points either inline or in file=, not both");
    const std::string path = c.input_path(*file);
    if constexpr (Dim == 2) {
      pts = read_points2(path);
    } else {
      pts = read_points3(path);
    }
    return pts;
  }
  const std::size_t n = c.count() - first;
  if (n == 0 || n % Dim != 0) {
    c.fail(n == 0 ? c.arg(first - 1) : c.arg(c.count() - 1),
           "expected " + std::string(Dim == 2 ? "X Y pairs" : "X Y Z triples") +
               " of coordinates, got " + std::to_string(n) + " number(s)");
  }
  for (std::size_t i = first; i < c.count(); i += Dim) {
    V p;
    for (int k = 0; k < Dim; ++k) p[k] = c.number(i + k, "coordinate");
    pts.push_back(p);
  }
  return pts;
}

CommandResult run_curve(Call& c) {
  if (c.count() < 2) c.expect_count(2, 2, "NAME KIND [closed] X Y ...");
  const std::string name = c.new_name(0);
  Curve2 curve;
  curve.kind = curve_kind(c, 1);
  std::size_t first = 2;
  if (c.count() > 2 && c.arg(2).text == "closed") {
    curve.closed = true;
    first = 3;
  }
  curve.points = curve_points<2>(c, first);
  validate(curve);
  Object o;
  o.kind = ObjectKind::kCurve2;
  o.curve2 = std::move(curve);
  o.summary = c.arg(1).text + (o.curve2.closed ? " closed" : "") + " 2-D curve, " +
              std::to_string(o.curve2.points.size()) + " points";
  c.define(name, std::move(o));
  return {c.spec().name, name + ": " + summary_text(c.session().objects.at(name)), false};
}

CommandResult run_path(Call& c) {
  if (c.count() < 2) c.expect_count(2, 2, "NAME KIND X Y Z ...");
  const std::string name = c.new_name(0);
  Curve3 curve;
  curve.kind = curve_kind(c, 1);
  curve.points = curve_points<3>(c, 2);
  validate(curve);
  Object o;
  o.kind = ObjectKind::kCurve3;
  o.curve3 = std::move(curve);
  o.summary = c.arg(1).text + " 3-D path, " + std::to_string(o.curve3.points.size()) + " points";
  c.define(name, std::move(o));
  return {c.spec().name, name + ": " + summary_text(c.session().objects.at(name)), false};
}

CurveSurfaceOptions surface_options(const Call& c) {
  CurveSurfaceOptions o;
  o.radius = c.option_positive("radius", o.radius);
  if (const Token* t = c.option_token("kernel")) {
    try {
      o.kernel = parse_kernel(t->text);
      o.kernel.validate();
    } catch (const InvalidArgument& e) {
      c.fail(*t, e.what());
    }
  }
  o.weight = c.option_positive("weight", o.weight);
  return o;
}

CommandResult shape_result(Call& c, const std::string& name, FieldPtr field, std::string summary) {
  Object o;
  o.kind = ObjectKind::kShape;
  o.field = std::move(field);
  o.summary = std::move(summary);
  c.define(name, std::move(o));
  return {c.spec().name, name + ": " + summary_text(c.session().objects.at(name)), false};
}

CommandResult run_revolve(Call& c) {
  c.expect_count(2, 2, "NAME PROFILE");
  const std::string name = c.new_name(0);
  const Curve2& profile = c.object(1, ObjectKind::kCurve2).curve2;
  return shape_result(c, name, make_revolution_field(profile, surface_options(c)),
                      "surface of revolution of " + c.arg(1).text + " about z");
}

CommandResult run_sweep(Call& c) {
  c.expect_count(3, 3, "NAME SECTION PATH");
  const std::string name = c.new_name(0);
  const Curve2& section = c.object(1, ObjectKind::kCurve2).curve2;
  const Curve3& path = c.object(2, ObjectKind::kCurve3).curve3;
  return shape_result(c, name, make_sweep_field(path, section, surface_options(c)),
                      "sweep of " + c.arg(1).text + " along " + c.arg(2).text);
}

CommandResult run_skin(Call& c) {
  if (c.count() < 3) c.expect_count(3, 3, "NAME PATH SECTION@S ...");
  const std::string name = c.new_name(0);
  const Curve3& path = c.object(1, ObjectKind::kCurve3).curve3;
  std::vector<SkinSection> sections;
  for (std::size_t i = 2; i < c.count(); ++i) {
    const Token& t = c.arg(i);
    const std::size_t at = t.text.rfind('@');
    if (at == std::string::npos || at == 0) {
      c.fail(t,
             "expected SECTION@S (a 2-D curve name and its arc-length parameter in [0, 1]), got '" +
                 t.text + "'");
    }
    const Token curve_name{t.text.substr(0, at), t.column};
    const Token s_token{t.text.substr(at + 1), t.column + at + 1};
    const double s = c.parse_number(s_token, "section parameter");
    if (s < 0 || s > 1)
      c.fail(s_token, "section parameter must lie in [0, 1], got " + s_token.text);
    sections.push_back({c.object_named(curve_name, ObjectKind::kCurve2).curve2, s});
  }
  SkinOptions o;
  o.surface = surface_options(c);
  const std::string interp = c.option_word("interp", "linear", {"linear", "quadratic", "cubic"});
  o.interpolation = interp == "linear"      ? SkinInterpolation::kLinear
                    : interp == "quadratic" ? SkinInterpolation::kQuadratic
                                            : SkinInterpolation::kCubic;
  const std::size_t n = sections.size();
  return shape_result(c, name, make_skin_field(path, std::move(sections), o),
                      "skinned surface along " + c.arg(1).text + ", " + std::to_string(n) +
                          " sections, " + interp + " interpolation");
}

}  // namespace

void add_curve_commands(std::vector<CommandSpec>& out) {
  const std::vector<std::string> surf = {"radius", "kernel", "weight"};
  out.push_back(
      {"curve",
       "curve NAME polyline|bezier|bspline [closed] X Y X Y ... | file=F",
       "A planar (2-D) curve for profiles and cross-sections: a polyline, one Bezier curve "
       "through its control points' hull, or a cubic B-spline. `closed` makes it bound a "
       "filled region. The points may come from a file ('x y' per line).",
       "curve square polyline closed -1 -1 1 -1 1 1 -1 1",
       {"file"},
       run_curve,
       {"curve2d"}});
  out.push_back({"path",
                 "path NAME polyline|bezier|bspline X Y Z ... | file=F",
                 "A 3-D path curve for sweeps and skinning ('x y z' per line in a file).",
                 "path up polyline 0 0 0 0 0 1",
                 {"file"},
                 run_path,
                 {"curve3d"}});
  out.push_back({"revolve",
                 "revolve NAME PROFILE [radius=R] [kernel=K] [weight=W]",
                 "Surface of revolution: the 2-D PROFILE (x = distance from the axis, y = height) "
                 "turned about the z axis; a closed profile is a filled region. The surface lies "
                 "`radius` (default 0.1) from the profile.",
                 "revolve vase outline radius=0.05",
                 surf,
                 run_revolve,
                 {"revolution"}});
  out.push_back({"sweep",
                 "sweep NAME SECTION PATH [radius=R] [kernel=K] [weight=W]",
                 "Sweep surface: the 2-D SECTION carried along PATH in rotation-minimizing frames.",
                 "sweep pipe ring bend_path radius=0.02",
                 surf,
                 run_sweep,
                 {}});
  out.push_back(
      {"skin",
       "skin NAME PATH SECTION@S [SECTION@S ...] [interp=linear|quadratic|cubic] [radius=R]",
       "Implicit skinning (thesis §4.2): 2-D sections attached to normalized arc-length "
       "parameters S of PATH; the distance field is interpolated between them. Several "
       "sections at one S are united (the table of Figure 4.10).",
       "skin table up leg1@0 leg2@0 leg3@0 leg4@0 top@1",
       {"radius", "kernel", "weight", "interp"},
       run_skin,
       {}});
}

}  // namespace ramiform::script
