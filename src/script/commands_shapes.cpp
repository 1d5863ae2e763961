// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Shape commands: primitives (Kochhar 2010, "Application of implicit methods to the interactive
// modeling of trees" (M.Sc. thesis), §3.2), BlobTree operators (§3.3), transforms and Barr's
// deformations (§4.1), skeletons from files and variational (RBF) surfaces.

#include <cmath>
#include <fstream>
#include <numbers>
#include <string_view>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/primitives.h"
#include "ramiform/field/rbf.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/field/warps.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/mesh_field.h"
#include "ramiform/skeleton/from_points.h"
#include "session.h"

namespace ramiform::script {
namespace {

const std::vector<std::string> kKernelNames = {"wyvill", "blinn", "metaball", "power",
                                               "inverse-power"};

Kernel kernel_option(const Call& call) {
  const Token* t = call.option_token("kernel");
  if (t == nullptr) return Kernel{KernelKind::kWyvill, 0.0};
  Kernel k;
  try {
    k = parse_kernel(t->text);
    k.validate();
  } catch (const InvalidArgument& e) {
    call.fail(*t, e.what());
  }
  if (k.kind == KernelKind::kCauchy) {
    call.fail(
        *t,
        "the Cauchy kernel makes convolution surfaces; primitives are distance surfaces "
        "(use wyvill, blinn, metaball or power), or load a skeleton with surface=convolution");
  }
  return k;
}

SkeletonFieldOptions distance_options(const Call& call) {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kDistance;
  o.kernel = kernel_option(call);
  if (call.has_option("weight"))
    call.fail(*call.option_token("weight"), "weight is not supported here");
  return o;
}

// Reads three positional numbers starting at `first` as a vector.
Vec3 vec_args(const Call& call, std::size_t first, const std::string& what) {
  return {call.number(first, what + " x"), call.number(first + 1, what + " y"),
          call.number(first + 2, what + " z")};
}

const std::vector<std::string> kPrimitiveOptions = {"center", "kernel", "weight"};

std::vector<std::string> with(std::vector<std::string> base,
                              std::initializer_list<std::string> more) {
  base.insert(base.end(), more);
  return base;
}

CommandResult run_sphere(Call& c) {
  c.expect_count(1, 2, "NAME [RADIUS]");
  const std::string name = c.new_name(0);
  const double r = c.count() > 1 ? c.positive(1, "radius") : 1.0;
  const Vec3 center = c.option_vec3("center", Vec3::Zero());
  c.define(name, shape(make_point_field(center, r, distance_options(c)),
                       "sphere, radius " + format_number(r) + " at " + format_vec3(center)));
  return defined(c, name);
}

CommandResult run_line(Call& c) {
  if (c.count() != 1 && c.count() != 7) c.expect_count(1, 1, "NAME or NAME X0 Y0 Z0 X1 Y1 Z1");
  const std::string name = c.new_name(0);
  Vec3 a(0, 0, -1.5);
  Vec3 b(0, 0, 1.5);
  if (c.count() == 7) {
    a = vec_args(c, 1, "start");
    b = vec_args(c, 4, "end");
  }
  const double r = c.option_positive("radius", 0.3);
  const double r_end = c.option_positive("radius_end", r);
  if (c.has_option("def")) {
    const Deformation def = deformation_option(c, "def");
    if (r_end != r) c.fail(*c.option_token("radius_end"), "radius_end does not apply with def=");
    FieldPtr f;
    try {
      f = make_anisotropic_segment_field(a, b, r, def, primitive_options(c));
    } catch (const InvalidArgument& e) {
      c.fail(e.what());
    }
    c.define(name, shape(std::move(f), "anisotropic line segment " + format_vec3(a) + " to " +
                                           format_vec3(b) + ", radius " + format_number(r) +
                                           ", def " + format_deformation(def)));
    return defined(c, name);
  }
  c.define(name, shape(make_segment_field(a, r, b, r_end, distance_options(c)),
                       "line segment " + format_vec3(a) + " to " + format_vec3(b) + ", radius " +
                           format_number(r) + (r_end != r ? " to " + format_number(r_end) : "")));
  return defined(c, name);
}

CommandResult run_circle(Call& c) {
  c.expect_count(1, 2, "NAME [RADIUS]");
  const std::string name = c.new_name(0);
  const double R = c.count() > 1 ? c.positive(1, "radius") : 1.0;
  const double t = c.option_positive("thickness", 0.25);
  const Vec3 center = c.option_vec3("center", Vec3::Zero());
  const Vec3 normal = c.option_vec3("normal", Vec3::UnitZ());
  c.define(name,
           shape(make_circle_field(center, normal, R, t, primitive_options(c)),
                 "torus, circle radius " + format_number(R) + ", thickness " + format_number(t)));
  return defined(c, name);
}

CommandResult run_box(Call& c) {
  if (c.count() != 1 && c.count() != 2 && c.count() != 4)
    c.expect_count(1, 1, "NAME [SIZE | SX SY SZ]");
  const std::string name = c.new_name(0);
  Vec3 size = Vec3::Ones();
  if (c.count() == 2) size = Vec3::Constant(c.positive(1, "size"));
  if (c.count() == 4)
    size = {c.positive(1, "size x"), c.positive(2, "size y"), c.positive(3, "size z")};
  const double rounding = c.option_positive("rounding", 0.05 * size.minCoeff());
  const Vec3 center = c.option_vec3("center", Vec3::Zero());
  c.define(name, shape(make_box_field(center, size / 2, rounding, primitive_options(c)),
                       "box " + format_vec3(size) + " at " + format_vec3(center) + ", rounding " +
                           format_number(rounding)));
  return defined(c, name);
}

CommandResult run_cylinder(Call& c) {
  if (c.count() != 1 && c.count() != 3) c.expect_count(1, 1, "NAME [RADIUS HEIGHT]");
  const std::string name = c.new_name(0);
  const double r = c.count() == 3 ? c.positive(1, "radius") : 0.5;
  const double h = c.count() == 3 ? c.positive(2, "height") : 1.0;
  const double rounding = c.option_positive("rounding", 0.05 * std::min(r, h));
  const Vec3 center = c.option_vec3("center", Vec3::Zero());
  const Vec3 a = center - Vec3(0, 0, h / 2);
  const Vec3 b = center + Vec3(0, 0, h / 2);
  c.define(name, shape(make_cylinder_field(a, b, r, rounding, primitive_options(c)),
                       "cylinder, radius " + format_number(r) + ", height " + format_number(h) +
                           " along z at " + format_vec3(center)));
  return defined(c, name);
}

CommandResult run_cone(Call& c) {
  if (c.count() != 1 && c.count() != 3) c.expect_count(1, 1, "NAME [RADIUS HEIGHT]");
  const std::string name = c.new_name(0);
  const double r = c.count() == 3 ? c.positive(1, "radius") : 0.5;
  const double h = c.count() == 3 ? c.positive(2, "height") : 1.0;
  const double top = c.option_number("top", 0.0);
  if (top < 0) c.fail(*c.option_token("top"), "top must be >= 0");
  const double rounding = c.option_positive("rounding", 0.05 * std::min(r, h));
  const Vec3 center = c.option_vec3("center", Vec3::Zero());
  c.define(name, shape(make_cone_field(center - Vec3(0, 0, h / 2), r, center + Vec3(0, 0, h / 2),
                                       top, rounding, primitive_options(c)),
                       "cone, radius " + format_number(r) + " to " + format_number(top) +
                           ", height " + format_number(h) + " along z"));
  return defined(c, name);
}

CommandResult run_plane(Call& c) {
  if (c.count() != 1 && c.count() != 4) c.expect_count(1, 1, "NAME [NX NY NZ]");
  const std::string name = c.new_name(0);
  const Vec3 n = c.count() == 4 ? vec_args(c, 1, "normal") : Vec3::UnitZ();
  const Vec3 point = c.option_vec3("point", Vec3::Zero());
  const double falloff = c.option_positive("falloff", 0.1);
  c.define(name, shape(make_plane_field(point, n, falloff, primitive_options(c)),
                       "half-space behind the plane through " + format_vec3(point) +
                           " with normal " + format_vec3(n) + " (unbounded)"));
  return defined(c, name);
}

// Defines NAME (argument 0) as the surface of `skeleton` with the surface= options of the
// `skeleton` command; `summary` starts the object's summary.
CommandResult define_skeleton_shape(Call& c, Skeleton skeleton, std::string summary) {
  const std::string name = c.new_name(0);
  const std::string surface =
      c.option_word("surface", "distance", {"distance", "convolution", "equipotential"});
  const std::optional<EquipotentialRequest> equipotential =
      equipotential_request(c, surface == "equipotential", surface);
  SkeletonFieldOptions o;
  if (surface == "convolution" || surface == "equipotential") {
    o.surface = SurfaceKind::kConvolution;
    o.kernel = Kernel{KernelKind::kCauchy, 0.0};
    if (const Token* t = c.option_token("kernel")) {
      c.fail(*t, surface == "convolution"
                     ? "convolution surfaces use the Cauchy kernel; kernel= applies to "
                       "surface=distance"
                     : "kernel= applies to surface=distance; the equipotential surface's "
                       "falloff is alpha=");
    }
  } else {
    o = distance_options(c);
  }
  summary += ", " + std::to_string(skeleton.nodes.size()) + " nodes, " +
             std::to_string(skeleton.edges.size()) + " edges";
  Object obj;
  if (equipotential) {
    obj = shape(nullptr, "");
    obj.equipotential = build_equipotential(c, skeleton, *equipotential, summary);
    obj.field = obj.equipotential->field;
  } else {
    obj = shape(make_skeleton_field(skeleton, o), "");
    summary += ", " + surface + " surface";
  }
  obj.summary = std::move(summary);
  obj.skeleton = std::move(skeleton);
  c.define(name, std::move(obj));
  return defined(c, name);
}

CommandResult run_skeleton(Call& c) {
  c.expect_count(2, 2, "NAME FILE");
  (void)c.new_name(0);
  const std::string path = c.input_path(1);
  return define_skeleton_shape(c, read_skeleton(path), "skeleton from " + c.arg(1).text);
}

// tree_from_points NAME FILE [bin=W] [up=z|y] [min_radius=R] [surface options of `skeleton`]
CommandResult run_tree_from_points(Call& c) {
  c.expect_count(2, 2, "NAME FILE");
  (void)c.new_name(0);
  const std::string path = c.input_path(1);
  TreeFromPointsOptions o;
  o.up_axis = c.option_word("up", "z", {"z", "y"}) == "y" ? 1 : 2;
  o.bin_width = c.option_positive("bin", 0.0);
  o.min_radius = c.option_positive("min_radius", 0.0);
  const PointSet cloud = read_points(path);
  TreeFromPointsReport report;
  Skeleton skeleton = tree_from_points(cloud.positions, o, &report);
  return define_skeleton_shape(
      c, std::move(skeleton),
      "tree skeleton from " + std::to_string(report.points) + " points of " + c.arg(1).text + " (" +
          std::to_string(report.tips) + " tips, " + std::to_string(report.bridges) + " bridges)");
}

CommandResult run_mesh_shape(Call& c) {
  c.expect_count(2, 2, "NAME FILE");
  const std::string name = c.new_name(0);
  const TriMesh mesh = read_mesh(c.input_path(1));
  c.define(name,
           shape(make_mesh_field(mesh), "closed mesh from " + c.arg(1).text + ", " +
                                            std::to_string(mesh.triangles.size()) + " triangles"));
  return defined(c, name);
}

// blend / union / intersect: INPUT INPUT... OUT
CommandResult run_nary(Call& c, const std::string& op) {
  if (c.count() < 3) c.expect_count(3, 1000000, "at least two inputs and an output name");
  const std::string out = c.new_name(c.count() - 1);
  std::vector<FieldPtr> kids;
  std::string names;
  for (std::size_t i = 0; i + 1 < c.count(); ++i) {
    kids.push_back(c.object(i, ObjectKind::kShape).field);
    names += (i > 0 ? ", " : "") + c.arg(i).text;
  }
  FieldPtr f;
  if (op == "blend") {
    for (std::size_t i = 1; i < kids.size(); ++i) {
      if (kids[i]->iso() != kids[0]->iso()) {
        c.fail(c.arg(i), "cannot blend '" + shown(c.arg(i).text) + "' (iso " +
                             format_number(kids[i]->iso()) + ") with '" + shown(c.arg(0).text) +
                             "' (iso " + format_number(kids[0]->iso()) +
                             "): a sum blend needs equal iso values; use union instead");
      }
    }
    f = make_sum(std::move(kids));
  } else if (op == "union") {
    f = make_union(std::move(kids));
  } else {
    f = make_intersection(std::move(kids));
  }
  c.define(out, shape(f, op + " of " + names));
  return defined(c, out);
}

CommandResult run_diff(Call& c) {
  c.expect_count(3, 3, "A B OUT");
  const std::string out = c.new_name(2);
  c.define(out, shape(make_difference(c.object(0, ObjectKind::kShape).field,
                                      c.object(1, ObjectKind::kShape).field),
                      c.arg(0).text + " minus " + c.arg(1).text));
  return defined(c, out);
}

CommandResult run_copy(Call& c) {
  c.expect_count(2, 2, "SOURCE NEW");
  const auto it = c.session().objects.find(c.arg(0).text);
  if (it == c.session().objects.end()) (void)c.object(0, ObjectKind::kShape);  // throws with a hint
  const std::string out = c.new_name(1);
  Object copy = c.session().objects.at(c.arg(0).text);
  c.define(out, std::move(copy));
  return defined(c, out);
}

// Rebinds NAME to its transformed shape; earlier uses of NAME keep the old node.
CommandResult rebind(Call& c, FieldPtr field, const std::string& what) {
  const std::string name = c.arg(0).text;
  Object& obj = c.session().objects.at(name);
  obj.field = std::move(field);
  obj.skeleton.reset();
  obj.equipotential.reset();
  // The summary keeps the first transforms while it has room and counts the rest, so that a
  // long chain of transforms does not grow it (and every result that copies it) without limit.
  if (obj.more_transforms == 0 && obj.summary.size() + 2 + what.size() <= kMaxSummary) {
    obj.summary += ", " + what;
  } else {
    ++obj.more_transforms;
  }
  return defined(c, name);
}

CommandResult run_translate(Call& c) {
  c.expect_count(4, 4, "NAME X Y Z");
  const FieldPtr f = c.object(0, ObjectKind::kShape).field;
  const Vec3 t = vec_args(c, 1, "offset");
  Affine3 m = Affine3::Identity();
  m.translate(t);
  return rebind(c, make_transform(f, m), "translated by " + format_vec3(t));
}

Vec3 axis_arg(const Call& c, std::size_t i) {
  const std::string& a = c.arg(i).text;
  if (a == "x" || a == "X") return Vec3::UnitX();
  if (a == "y" || a == "Y") return Vec3::UnitY();
  if (a == "z" || a == "Z") return Vec3::UnitZ();
  const Vec3 v = c.parse_vec3(c.arg(i), "axis (x, y, z or X,Y,Z)");
  if (!(v.norm() > 0)) c.fail(c.arg(i), "axis must not be zero");
  return v.normalized();
}

CommandResult run_rotate(Call& c) {
  c.expect_count(3, 3, "NAME AXIS DEGREES");
  const FieldPtr f = c.object(0, ObjectKind::kShape).field;
  const Vec3 axis = axis_arg(c, 1);
  const double deg = c.number(2, "angle in degrees");
  const Vec3 center = c.option_vec3("center", Vec3::Zero());
  Affine3 m = Affine3::Identity();
  m.translate(center);
  m.rotate(pm::rotation(deg * std::numbers::pi / 180.0, axis));
  m.translate(-center);
  return rebind(c, make_transform(f, m),
                "rotated " + format_number(deg) + " degrees about " + format_vec3(axis));
}

CommandResult run_scale(Call& c) {
  if (c.count() != 2 && c.count() != 4) c.expect_count(2, 2, "NAME S or NAME SX SY SZ");
  const FieldPtr f = c.object(0, ObjectKind::kShape).field;
  const Vec3 s = c.count() == 2 ? Vec3::Constant(c.positive(1, "scale"))
                                : Vec3(c.positive(1, "scale x"), c.positive(2, "scale y"),
                                       c.positive(3, "scale z"));
  const Vec3 center = c.option_vec3("center", Vec3::Zero());
  Affine3 m = Affine3::Identity();
  m.translate(center);
  m.scale(s);
  m.translate(-center);
  return rebind(c, make_transform(f, m), "scaled by " + format_vec3(s));
}

int axis_option(const Call& c) {
  const std::string a = c.option_word("axis", "z", {"x", "y", "z"});
  return a == "x" ? 0 : a == "y" ? 1 : 2;
}

CommandResult run_taper(Call& c) {
  c.expect_count(2, 2, "NAME SCALE_END");
  const FieldPtr f = c.object(0, ObjectKind::kShape).field;
  TaperOptions o;
  o.axis = axis_option(c);
  o.scale_end = c.positive(1, "scale at the end");
  o.scale_start = c.option_positive("scale_start", o.scale_start);
  const Aabb box = f->bounds();
  o.start = c.option_number("start", box.isEmpty() ? 0.0 : box.min()[o.axis]);
  o.end = c.option_number("end", box.isEmpty() ? 1.0 : box.max()[o.axis]);
  return rebind(c, make_taper(f, o), "tapered to " + format_number(o.scale_end));
}

CommandResult run_twist(Call& c) {
  c.expect_count(2, 2, "NAME DEGREES_PER_UNIT");
  const FieldPtr f = c.object(0, ObjectKind::kShape).field;
  TwistOptions o;
  o.axis = axis_option(c);
  o.rate = c.number(1, "twist rate in degrees per unit length") * std::numbers::pi / 180.0;
  o.origin = c.option_number("origin", 0.0);
  return rebind(c, make_twist(f, o), "twisted " + c.arg(1).text + " degrees per unit");
}

CommandResult run_bend(Call& c) {
  c.expect_count(2, 2, "NAME RATE");
  const FieldPtr f = c.object(0, ObjectKind::kShape).field;
  BendOptions o;
  o.rate = c.number(1, "bend rate (1 / radius of curvature)");
  const Aabb box = f->bounds();
  o.min = c.option_number("min", box.isEmpty() ? -1.0 : box.min().y());
  o.max = c.option_number("max", box.isEmpty() ? 1.0 : box.max().y());
  o.center = c.option_number("center", 0.5 * (o.min + o.max));
  return rebind(c, make_bend(f, o), "bent at rate " + c.arg(1).text);
}

constexpr const char* kBlanks = " \t\r\v\f";  // what separates numbers on a line

// RBF constraints: "x y z value" or "x y z nx ny nz" per line.
CommandResult run_rbf(Call& c) {
  c.expect_count(2, 2, "NAME FILE");
  const std::string name = c.new_name(0);
  const std::string path = c.input_path(1);
  const double offset = c.option_positive("offset", 0.05);
  std::ifstream in(path);
  std::vector<RbfConstraint> values;
  std::vector<Vec3> points;
  std::vector<Vec3> normals;
  std::string text;
  std::size_t line_no = 0;
  while (std::getline(in, text)) {
    ++line_no;
    const std::size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::vector<double> v;
    for (std::size_t at = text.find_first_not_of(kBlanks); at != std::string::npos;) {
      const std::size_t end = text.find_first_of(kBlanks, at);
      const std::string_view word = std::string_view(text).substr(at, end - at);
      double x = 0;
      if (parse_number(word, x) != NumberStatus::kOk) {
        throw InputError(path, line_no, "expected a finite number, got '" + shown(word) + "'");
      }
      v.push_back(x);
      at = end == std::string::npos ? end : text.find_first_not_of(kBlanks, end);
    }
    if (v.empty()) continue;
    if (v.size() == 4) {
      values.push_back({Vec3(v[0], v[1], v[2]), v[3]});
    } else if (v.size() == 6) {
      points.emplace_back(v[0], v[1], v[2]);
      normals.emplace_back(v[3], v[4], v[5]);
    } else {
      throw InputError(path, line_no,
                       "expected 'x y z value' or 'x y z nx ny nz', got " +
                           std::to_string(v.size()) + " numbers");
    }
  }
  if (!normals.empty()) {
    const auto more = rbf_constraints_from_normals(points, normals, offset);
    values.insert(values.end(), more.begin(), more.end());
  }
  c.define(name, shape(make_rbf_field(values), "variational surface through " +
                                                   std::to_string(values.size()) + " constraints"));
  return defined(c, name);
}

}  // namespace

Object shape(FieldPtr field, std::string summary) {
  Object o;
  o.kind = ObjectKind::kShape;
  o.field = std::move(field);
  o.summary = std::move(summary);
  return o;
}

CommandResult defined(const Call& call, const std::string& name) {
  return {call.spec().name, name + ": " + summary_text(call.session().objects.at(name)), false};
}

DistancePrimitiveOptions primitive_options(const Call& call) {
  DistancePrimitiveOptions o;
  o.kernel = kernel_option(call);
  o.weight = call.option_positive("weight", o.weight);
  return o;
}

void add_shape_commands(std::vector<CommandSpec>& out) {
  const std::vector<std::string> prim = kPrimitiveOptions;
  std::vector<std::string> skeleton_options = {"surface", "kernel"};
  skeleton_options.insert(skeleton_options.end(), equipotential_keys().begin(),
                          equipotential_keys().end());
  out.push_back(
      {"sphere",
       "sphere NAME [RADIUS] [center=X,Y,Z] [kernel=K]",
       "A point primitive: distance surface around a point, surface at RADIUS (default 1).",
       "sphere s 2 center=0,0,1",
       {"center", "kernel"},
       run_sphere,
       {"point"}});
  out.push_back(
      {"line",
       "line NAME [X0 Y0 Z0 X1 Y1 Z1] [radius=R] [radius_end=R1] [def=D] [kernel=K] "
       "[weight=W]",
       "A line-segment primitive (default from 0,0,-1.5 to 0,0,1.5, radius 0.3); the radius "
       "may change linearly to radius_end. def=D (a `deform` name or inline, e.g. "
       "squared-cosine:0.3 or flat:8) makes it anisotropic (Rigaudière et al. §3.2): thickness "
       "radius / def(t) along the segment; weight=W applies then.",
       "line arm 0 0 0 2 0 0 radius=0.2",
       {"radius", "radius_end", "def", "kernel", "weight"},
       run_line,
       {"segment"}});
  out.push_back(
      {"circle",
       "circle NAME [RADIUS] [thickness=T] [center=X,Y,Z] [normal=X,Y,Z] [kernel=K] [weight=W]",
       "A torus: distance surface around a circle of RADIUS (default 1) in the plane normal "
       "to `normal` (default z), tube radius `thickness` (default 0.25).",
       "circle wheel 0.5 thickness=0.1 normal=0,1,0",
       with(prim, {"thickness", "normal"}),
       run_circle,
       {"torus"}});
  out.push_back({"box",
                 "box NAME [SIZE | SX SY SZ] [center=X,Y,Z] [rounding=R] [kernel=K] [weight=W]",
                 "A box of the given full size (default 1) with edges rounded by `rounding` "
                 "(default 5 % of the smallest side).",
                 "box body 4 1.5 1 rounding=0.1",
                 with(prim, {"rounding"}),
                 run_box,
                 {}});
  out.push_back(
      {"cylinder",
       "cylinder NAME [RADIUS HEIGHT] [center=X,Y,Z] [rounding=R] [kernel=K] [weight=W]",
       "A solid cylinder along z (default radius 0.5, height 1) centred at `center`, edges "
       "rounded by `rounding`.",
       "cylinder chimney 0.3 1.2 center=1,0,1",
       with(prim, {"rounding"}),
       run_cylinder,
       {}});
  out.push_back(
      {"cone",
       "cone NAME [RADIUS HEIGHT] [top=R] [center=X,Y,Z] [rounding=R] [kernel=K] [weight=W]",
       "A solid (truncated) cone along z: RADIUS at the bottom, `top` (default 0) at the top.",
       "cone roof 1 0.8 top=0.2",
       with(prim, {"top", "rounding"}),
       run_cone,
       {}});
  out.push_back(
      {"plane",
       "plane NAME [NX NY NZ] [point=X,Y,Z] [falloff=F] [kernel=K] [weight=W]",
       "The half-space behind a plane (inside is opposite the normal, default z). Unbounded: "
       "use it in intersections and differences.",
       "plane ground 0 0 1 point=0,0,-0.5",
       {"point", "falloff", "kernel", "weight"},
       run_plane,
       {}});
  out.push_back(
      {"skeleton",
       "skeleton NAME FILE [surface=distance|convolution|equipotential] [kernel=K] [alpha=A] "
       "[charge=Q] [charge_spacing=D] [lambda=L] [lambda_scale=S] [open_ends=yes|no] "
       "[fit_radii=yes|no]",
       "A line skeleton read from a file (.json, .ply, .obj, TreeQSM .txt, SimpleForest .csv), "
       "as a distance surface (Wyvill by default), a Cauchy convolution surface or an "
       "equipotential surface. " +
           equipotential_help() +
           "; these options apply to surface=equipotential only. save_mesh method=particles "
           "meshes it with particles placed at the charges.",
       "skeleton tree fork.json surface=convolution",
       skeleton_options,
       run_skeleton,
       {}});
  std::vector<std::string> tree_options = {"bin", "up", "min_radius"};
  tree_options.insert(tree_options.end(), skeleton_options.begin(), skeleton_options.end());
  out.push_back(
      {"tree_from_points",
       "tree_from_points NAME FILE [bin=W] [up=z|y] [min_radius=R] [surface=...] (and the "
       "surface options of `skeleton`)",
       "The branching skeleton of a laser-scanned tree's point cloud (.xyz/.txt 'x y z' lines "
       "or .ply) by geodesic level sets (Xu, Gossett & Chen 2007; docs/reconstruction.md), as a "
       "skeleton shape: `bin` is the level-set width (default 6 median point spacings), `up` "
       "the up axis (default z), `min_radius` the smallest radius (default half the median "
       "spacing).",
       "tree_from_points tree data/tree_cloud.xyz bin=0.08 surface=convolution",
       tree_options,
       run_tree_from_points,
       {}});
  out.push_back(
      {"mesh_shape",
       "mesh_shape NAME FILE",
       "A closed triangle mesh (.ply, .obj, .off) as a shape: inside where its winding number "
       "exceeds 0.5. Use it in CSG, as an obstacle (grow ... avoid=NAME) or to sample.",
       "mesh_shape cube data/cube.obj",
       {},
       run_mesh_shape,
       {"mesh"}});
  out.push_back({"blend",
                 "blend A B [C ...] OUT",
                 "Sum blend of shapes (Wyvill's BlobTree '+'): smooth joins.",
                 "blend body wheel car",
                 {},
                 [](Call& c) { return run_nary(c, "blend"); },
                 {"sum"}});
  out.push_back({"union",
                 "union A B [C ...] OUT",
                 "CSG union (max of the fields).",
                 "union a b ab",
                 {},
                 [](Call& c) { return run_nary(c, "union"); },
                 {}});
  out.push_back({"intersect",
                 "intersect A B [C ...] OUT",
                 "CSG intersection (min of the fields).",
                 "intersect a b both",
                 {},
                 [](Call& c) { return run_nary(c, "intersection"); },
                 {"intersection"}});
  out.push_back({"diff",
                 "diff A B OUT",
                 "CSG difference: inside A and not inside B (the thesis's 'diff').",
                 "diff s1 s2 s3",
                 {},
                 run_diff,
                 {"difference"}});
  out.push_back({"copy",
                 "copy SOURCE NEW",
                 "A new name for an object, so that later changes to SOURCE "
                 "(translate, scale, ...) leave NEW as it was.",
                 "copy wheel wheel2",
                 {},
                 run_copy,
                 {}});
  out.push_back({"translate",
                 "translate NAME X Y Z",
                 "Moves a shape (NAME now names the moved shape).",
                 "translate s 0 0 2",
                 {},
                 run_translate,
                 {"move"}});
  out.push_back(
      {"rotate",
       "rotate NAME AXIS DEGREES [center=X,Y,Z]",
       "Rotates a shape about an axis (x, y, z or X,Y,Z) through `center` (default origin).",
       "rotate s x 90",
       {"center"},
       run_rotate,
       {}});
  out.push_back({"scale",
                 "scale NAME S | NAME SX SY SZ [center=X,Y,Z]",
                 "Scales a shape, uniformly or per axis, about `center` (default origin).",
                 "scale s 50 80 50",
                 {"center"},
                 run_scale,
                 {}});
  out.push_back(
      {"taper",
       "taper NAME SCALE_END [axis=x|y|z] [start=T0] [end=T1] [scale_start=S0]",
       "Barr's taper: the two other coordinates scale linearly from scale_start (default 1) "
       "at `start` to SCALE_END at `end` along `axis` (defaults: z, the shape's extent).",
       "taper trunk 0.5",
       {"axis", "start", "end", "scale_start"},
       run_taper,
       {}});
  out.push_back(
      {"twist",
       "twist NAME DEGREES_PER_UNIT [axis=x|y|z] [origin=T]",
       "Barr's twist about `axis` (default z): rotation grows by DEGREES_PER_UNIT per unit "
       "along the axis from `origin`.",
       "twist column 90",
       {"axis", "origin"},
       run_twist,
       {}});
  out.push_back({"bend",
                 "bend NAME RATE [min=Y0] [max=Y1] [center=YC]",
                 "Barr's bend of the y axis toward z with curvature RATE (1 / radius) over y in "
                 "[min, max] (default the shape's extent), centred at `center`.",
                 "bend beam 0.5",
                 {"min", "max", "center"},
                 run_bend,
                 {}});
  out.push_back(
      {"rbf",
       "rbf NAME FILE [offset=D]",
       "A variational implicit surface (Turk and O'Brien) interpolating the constraints of "
       "FILE: lines 'x y z value' (value > 0 inside, 0 on the surface) or 'x y z nx ny nz' "
       "(a surface point with its outward normal; an inside constraint is put `offset` "
       "(default 0.05) behind it).",
       "rbf blob blob_points.txt",
       {"offset"},
       run_rbf,
       {"variational"}});
}

}  // namespace ramiform::script
