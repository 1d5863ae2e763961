// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Session commands: parameters, meshing and evaluation outputs, inspection and help, and the
// point-set commands that arrive with a later stage (they fail with a clear message).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "ramiform/core/errors.h"
#include "ramiform/io/atomic_file.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/mesh/normals.h"
#include "ramiform/polygonize/lod.h"
#include "ramiform/polygonize/marching_cubes.h"
#include "ramiform/polygonize/particles.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "session.h"

namespace ramiform::script {
namespace {

/// Most points the `deviation` command samples on a mesh.
constexpr int kMaxDeviationSamples = 10'000'000;

// The ranges ParticleMeshOptions documents and polygonize_particles checks (polygonize/
// particles.h), checked here too so that the error points at the token.
constexpr int kMinCirc = 3, kMaxCirc = 4096;
constexpr int kMinSphere = 4, kMaxSphere = 65536;
constexpr int kMaxParticleIterations = 100'000;
constexpr int kMaxRelax = 100;

const std::vector<std::string> kParticleKeys = {"n_circ", "n_sphere",       "placement_radius",
                                                "delta",  "max_iterations", "relax"};
const std::vector<std::string> kMcKeys = {"cell", "resolution"};
const std::vector<std::string> kTetsKeys = {"levels", "section_scale", "tolerance", "lod",
                                            "lod_budget"};

// Fails at the first of `keys` given: they apply to `method` only.
void refuse(const Call& c, const std::vector<std::string>& keys, const std::string& method) {
  for (const std::string& key : keys) {
    if (const Token* t = c.option_token(key)) c.fail(*t, key + "= applies to method=" + method);
  }
}

std::string count_text(std::size_t n);

// save_mesh method=particles: the particle mesher of Gruber & Wallner 2014 around the shape's
// skeleton; at the charges of an equipotential surface, else rings at the default spacing and
// the skeleton file's open ends. Fails when a particle did not reach the surface.
TriMesh particle_mesh(const Call& c, const Object& obj, std::string& how, std::size_t& open_loops) {
  using P = ParticleMeshOptions;
  P o;
  o.n_circ = c.option_integer("n_circ", o.n_circ, kMinCirc, kMaxCirc);
  o.n_sphere = c.option_integer("n_sphere", o.n_sphere, kMinSphere, kMaxSphere);
  o.placement_radius = c.option_positive("placement_radius", o.placement_radius);
  o.delta = c.option_number("delta", o.delta);
  if (!(o.delta > 0 && o.delta < 1)) {
    c.fail(*c.option_token("delta"), "delta must be in (0, 1) (relative to the iso value), got " +
                                         c.option_token("delta")->text);
  }
  o.max_iterations =
      c.option_integer("max_iterations", o.max_iterations, 1, kMaxParticleIterations);
  o.relax = c.option_integer("relax", o.relax, 0, kMaxRelax);
  ParticleMeshStats st;
  TriMesh mesh;
  const Skeleton& skeleton = *obj.skeleton;
  if (obj.equipotential) {
    mesh = polygonize_particles(*obj.equipotential, skeleton, o, c.session().ctx, &st);
  } else {
    mesh =
        polygonize_particles(*obj.field, skeleton, {}, skeleton.open_ends, o, c.session().ctx, &st);
  }
  if (st.converged < st.particles) {
    std::string which;
    for (std::size_t k = 0; k < st.unconverged.size() && k < 10; ++k) {
      which += (k > 0 ? " " : "") + std::to_string(st.unconverged[k]);
    }
    const std::size_t left = st.particles - st.converged;
    c.fail(count_text(left) + " of " + count_text(st.particles) +
           " particles did not reach the surface within delta " + format_number(o.delta) +
           " after " + std::to_string(st.iterations) + " iterations (particles " + which +
           (left > 10 ? " ..." : "") + "); raise max_iterations= (now " +
           std::to_string(o.max_iterations) + ") or delta=; nothing was written");
  }
  how = "particles: " + count_text(st.particles) + " particles, " + count_text(st.converged) +
        " converged, " + std::to_string(st.iterations) + " iterations" +
        (st.inverted_triangles > 0
             ? ", " + count_text(st.inverted_triangles) +
                   " triangles folded (facing into the surface; method=tets has no folds)"
             : std::string()) +
        (st.nodes_outside > 0 ? ", " + count_text(st.nodes_outside) +
                                    " skeleton nodes outside the mesh, under a fold (method=tets "
                                    "keeps every node inside)"
                              : std::string());
  open_loops = st.open_loops;
  return mesh;
}

CommandResult run_param(Call& c) {
  c.expect_count(2, 2, "NAME VALUE");
  const std::string name = c.arg(0).text;
  const bool ok = !name.empty() && std::isdigit(static_cast<unsigned char>(name[0])) == 0 &&
                  std::all_of(name.begin(), name.end(), [](char ch) {
                    return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '_';
                  });
  if (!ok) c.fail(c.arg(0), "'" + name + "' is not a valid parameter name (letters, digits, '_')");
  auto& s = c.session();
  if (s.declared.count(name) != 0) c.fail(c.arg(0), "parameter '" + name + "' is declared twice");
  s.declared.insert(name);
  const auto set = s.options.params.find(name);
  const std::string value = set != s.options.params.end() ? set->second : c.arg(1).text;
  if (value.size() > kMaxParameterBytes - std::min(s.param_bytes, kMaxParameterBytes)) {
    c.fail(c.arg(1), "the parameters' values would hold more than " +
                         std::to_string(kMaxParameterBytes) + " bytes (kMaxParameterBytes)");
  }
  s.param_bytes += value.size();
  s.params[name] = value;
  // The message shows a long value's start only: results are kept for the whole run.
  const std::string head =
      value.size() > kMaxSummary ? value.substr(0, kMaxSummary) + "..." : value;
  ScriptParam info{name, value, std::nullopt, std::nullopt, std::nullopt};
  const auto range_option = [&c](const std::string& key) -> std::optional<double> {
    if (!c.has_option(key)) return std::nullopt;
    return c.option_number(key, 0);  // finite, or an error at the token
  };
  info.min = range_option("min");
  info.max = range_option("max");
  info.step = range_option("step");
  if (info.step && !(*info.step > 0)) {
    c.fail(*c.option_token("step"), "step must be > 0, got " + c.option_token("step")->text);
  }
  if (info.min && info.max && *info.min > *info.max) {
    c.fail(*c.option_token("max"), "max must be >= min (" + format_number(*info.min) + "), got " +
                                       c.option_token("max")->text);
  }
  s.param_list.push_back(std::move(info));
  return {c.spec().name,
          name + " = " + head + (set != s.options.params.end() ? " (from --set)" : ""),
          false,
          {},
          {}};
}

std::string count_text(std::size_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3)
    s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

std::string lower_extension(const std::string& file) {
  const std::size_t dot = file.rfind('.');
  std::string e = dot == std::string::npos ? "" : file.substr(dot);
  for (char& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

// The levels of lod= (tolerances) or lod_budget= (triangle counts), finest first.
std::vector<LodLevel> lod_option(const Call& c) {
  const Token* tol = c.option_token("lod");
  const Token* budget = c.option_token("lod_budget");
  if (tol != nullptr && budget != nullptr) c.fail(*budget, "give lod= or lod_budget=, not both");
  const Token* t = tol != nullptr ? tol : budget;
  std::vector<LodLevel> levels;
  if (t == nullptr) return levels;
  std::size_t at = 0;
  while (at <= t->text.size()) {
    std::size_t end = t->text.find(',', at);
    if (end == std::string::npos) end = t->text.size();
    Token part = *t;
    part.text = t->text.substr(at, end - at);
    const double v = c.parse_number(part, tol != nullptr ? "tolerance" : "triangle budget");
    LodLevel l;
    if (tol != nullptr) {
      l.tolerance = v;
    } else {
      if (!(v >= 1 && v <= 4e9 && v == std::floor(v))) {
        c.fail(*t, "lod_budget= takes triangle counts (positive whole numbers), got '" + part.text +
                       "'");
      }
      l.max_triangles = static_cast<std::size_t>(v);
    }
    levels.push_back(l);
    at = end + 1;
  }
  return levels;
}

// save_mesh NAME FILE [FILE ...]: one polygonization, written in every format asked for.
CommandResult run_save_mesh(Call& c) {
  c.expect_count(2, 9, "NAME FILE [FILE ...]");
  const Object& obj = c.object(0, ObjectKind::kShape);
  // Levels of detail come from the tolerance mesher: lod= makes tets the default method.
  const bool lod_given = c.has_option("lod") || c.has_option("lod_budget");
  const std::string method =
      c.option_word("method", lod_given ? "tets" : "mc", {"mc", "tets", "particles"});
  for (std::size_t i = 1; i < c.count(); ++i) {
    const std::string ext = lower_extension(c.arg(i).text);
    if (ext != ".ply" && ext != ".obj" && ext != ".off" && ext != ".glb") {
      c.fail(c.arg(i), "mesh files end in .ply, .obj, .off or .glb, got '" + c.arg(i).text + "'");
    }
  }
  const std::vector<LodLevel> lods = lod_option(c);
  MeshWriteOptions write;
  write.up = c.option_word("up", "z", {"z", "y"}) == "y" ? UpAxis::kY : UpAxis::kZ;
  write.normals = c.option_word("normals", "yes", {"yes", "no"}) == "yes";
  const std::string uv = c.option_word("uv", "auto", {"auto", "yes", "no"});
  if (uv == "yes" && !obj.skeleton) {
    c.fail(*c.option_token("uv"),
           "bark UVs follow a skeleton: uv=yes needs a shape made by skeleton, grow or lsystem");
  }
  TriMesh mesh;
  std::vector<TriMesh> levels;
  bool sent = false;  // on_mesh already has the mesh (polygonize_to_tolerance's on_pass)
  std::string how;
  std::size_t open_loops = 0;  // method=particles: boundary loops at open ends
  if (method != "particles") refuse(c, kParticleKeys, "particles");
  if (method == "particles") {
    if (!obj.skeleton) {
      c.fail(c.arg(0),
             "method=particles needs a shape made by skeleton, grow or lsystem (unchanged "
             "since); use method=mc");
    }
    refuse(c, kMcKeys, "mc");
    refuse(c, kTetsKeys, "tets");
    mesh = particle_mesh(c, obj, how, open_loops);
  } else if (method == "tets") {
    if (!obj.skeleton) {
      c.fail(c.arg(0),
             "method=tets needs a shape made by skeleton, grow or lsystem (unchanged since); use "
             "method=mc");
    }
    refuse(c, kMcKeys, "mc");
    using Tets = TetrahedralOptions;
    using Tol = ToleranceOptions;
    Tol t;
    Tets& o = t.tets;
    o.levels = c.option_integer("levels", o.levels, Tets::kMinLevels, Tets::kMaxLevels);
    o.section_scale = c.option_number("section_scale", o.section_scale);
    if (!(o.section_scale >= Tets::kMinSectionScale && o.section_scale <= Tets::kMaxSectionScale)) {
      c.fail(*c.option_token("section_scale"),
             "section_scale= must be in " +
                 range_text(Tets::kMinSectionScale, Tets::kMaxSectionScale));
    }
    t.tolerance = c.option_number("tolerance", t.tolerance);
    if (!(t.tolerance >= Tol::kMinTolerance && t.tolerance <= Tol::kMaxTolerance)) {
      c.fail(*c.option_token("tolerance"),
             "tolerance= must be in " + range_text(Tol::kMinTolerance, Tol::kMaxTolerance));
    }
    // levels= alone: the paper's uniform levels, unrefined; otherwise refined to the tolerance.
    if (!lods.empty() && !c.session().options.draft) {
      if (c.has_option("levels") && !c.has_option("tolerance")) {
        c.fail(*c.option_token("levels"),
               "lod= needs the tolerance mesher: give tolerance= with levels=, or no levels=");
      }
      try {
        levels = polygonize_lods(*obj.field, *obj.skeleton, t, lods, c.session().ctx);
      } catch (const InvalidArgument& e) {
        c.fail(*c.option_token(c.has_option("lod") ? "lod" : "lod_budget"), e.what());
      }
      how = "tets, " + std::to_string(levels.size()) + " levels of detail";
    } else if (c.session().options.draft ||
               (c.has_option("levels") && !c.has_option("tolerance"))) {
      if (c.session().options.draft) o.levels = 0;
      mesh = polygonize_tetrahedral(*obj.field, *obj.skeleton, o, c.session().ctx);
      how = "tets, " + std::to_string(o.levels) + " levels" +
            (c.session().options.draft ? " (draft)" : "");
    } else {
      ToleranceStats st;
      // The mesh goes to on_mesh before its deviation is measured (a tenth of the time); a
      // second pass, when the measure asks for one, sends its mesh again.
      if (c.session().options.on_mesh) {
        t.on_pass = [&](const TriMesh& m) { c.session().options.on_mesh(c.arg(0).text, m); };
      }
      mesh = polygonize_to_tolerance(*obj.field, *obj.skeleton, t, c.session().ctx, &st);
      sent = t.on_pass != nullptr;
      how = "tets to tolerance " + format_number(t.tolerance) + ": deviation p99 " +
            format_number(st.deviation.samples.p99) + ", max " +
            format_number(st.deviation.samples.max) + " of the local radius" +
            (st.reached ? "" : " (NOT reached)");
    }
  } else {
    refuse(c, kTetsKeys, "tets");
    if (c.has_option("cell") && c.has_option("resolution")) {
      c.fail(*c.option_token("resolution"), "give cell= or resolution=, not both");
    }
    const Aabb box = obj.field->bounds();
    if (box.isEmpty()) c.fail(c.arg(0), "'" + c.arg(0).text + "' has no inside: nothing to mesh");
    if (!box.min().allFinite() || !box.max().allFinite()) {
      c.fail(c.arg(0), "'" + c.arg(0).text +
                           "' is unbounded (a plane?); intersect it with a bounded shape first");
    }
    using Mc = MarchingCubesOptions;
    Mc o;
    o.cell_size = c.option_positive("cell", o.cell_size);
    o.resolution =
        c.option_integer("resolution", o.resolution, Mc::kMinResolution, Mc::kMaxResolution);
    if (c.session().options.draft) {
      // The cell a draft allows: the box's longest side over kDraftResolution.
      const double coarsest = box.sizes().maxCoeff() / kDraftResolution;
      if (o.cell_size > 0.0) o.cell_size = std::max(o.cell_size, coarsest);
      o.resolution = std::min(o.resolution, kDraftResolution);
    }
    mesh = marching_cubes(*obj.field, o, c.session().ctx);
    how = (o.cell_size > 0 ? "mc, cell " + format_number(o.cell_size)
                           : "mc, resolution " + std::to_string(o.resolution)) +
          (c.session().options.draft ? " (draft)" : "");
  }
  if (levels.empty()) levels.push_back(std::move(mesh));
  if (levels[0].triangles.empty() && !c.session().options.draft) {
    // Nothing to write: say why instead of saving an empty file (ramiform mesh exits 3 here). A
    // draft's coarse grid may miss what the full run finds: it goes on.
    c.fail(c.arg(0), "the mesh of '" + c.arg(0).text + "' (" + how +
                         ") is empty: the polygonizer found no surface, the field stays below "
                         "its iso value everywhere it looked (a shape thinner than the cells: "
                         "give a smaller cell=; a skeleton's edges much shorter than their "
                         "radius: give its skeleton line surface=distance)");
  }
  if (c.session().options.on_mesh && !sent) c.session().options.on_mesh(c.arg(0).text, levels[0]);
  // Each file gets normals (unless normals=no) and, by its format (uv=auto: .glb and .obj) or
  // as uv= says, bark UVs; the two variants are made once each.
  std::vector<TriMesh> plain, textured;
  const auto variant = [&](bool with_uvs) -> const std::vector<TriMesh>& {
    std::vector<TriMesh>& v = with_uvs ? textured : plain;
    if (v.empty()) {
      SurfaceAttributeOptions a;
      a.normals = write.normals;
      a.uvs = with_uvs && static_cast<bool>(obj.skeleton);
      for (const TriMesh& m : levels) {
        v.push_back(m);
        if (obj.skeleton) {
          add_surface_attributes(v.back(), *obj.field, *obj.skeleton, a, c.session().ctx);
        } else if (write.normals) {
          set_normals_from_field(v.back(), *obj.field, c.session().ctx);
        }
      }
    }
    return v;
  };
  const MeshReport report = check_mesh(levels[0]);
  std::string files;
  for (std::size_t i = 1; i < c.count(); ++i) {
    const std::string ext = lower_extension(c.arg(i).text);
    const bool with_uvs = uv == "yes" || (uv == "auto" && (ext == ".glb" || ext == ".obj"));
    const std::vector<TriMesh>& out = variant(with_uvs);
    MeshWriteOptions w = write;
    w.uvs = with_uvs;
    const std::vector<std::string> names = lod_paths(c.arg(i).text, out.size());
    if (names.size() == 1) {
      write_mesh_lods(out, c.output_path(i), w);
    } else {
      for (std::size_t k = 0; k < out.size(); ++k) {
        write_mesh(out[k], c.output_path(c.arg(i), names[k]), w);
      }
    }
    for (std::size_t k = 0; k < names.size(); ++k) files += (files.empty() ? "" : ", ") + names[k];
  }
  std::string counts = count_text(report.triangles) + " triangles";
  if (levels.size() > 1) {
    counts = "levels of detail of";
    for (std::size_t k = 0; k < levels.size(); ++k) {
      counts += (k > 0 ? ", " : " ") + count_text(levels[k].triangle_count());
    }
    counts += " triangles";
  }
  std::string closed =
      report.watertight && report.oriented && report.manifold ? "watertight" : "NOT watertight";
  // Open ends asked for: the boundary is one loop per open end, by construction.
  if (open_loops > 0 && report.oriented && report.manifold) {
    closed = "open at " + std::to_string(open_loops) + " end(s) as asked (" +
             count_text(report.boundary_edges) + " boundary edges), otherwise manifold";
  }
  CommandResult result{c.spec().name,
                       files + ": " + counts + " (" + how + "), " + closed + ", " +
                           std::to_string(report.components) + " component(s)",
                       true,
                       {},
                       {}};
  result.facts = {{"vertices", static_cast<double>(levels[0].vertex_count())},
                  {"triangles", static_cast<double>(report.triangles)},
                  {"components", static_cast<double>(report.components)},
                  {"boundary_edges", static_cast<double>(report.boundary_edges)},
                  {"watertight", report.watertight && report.oriented && report.manifold ? 1 : 0}};
  result.shape = c.arg(0).text;
  return result;
}

// deviation NAME MESH: how far a mesh lies from a shape's surface (mesh/deviation.h).
CommandResult run_deviation(Call& c) {
  c.expect_count(2, 2, "NAME MESH");
  const Object& obj = c.object(0, ObjectKind::kShape);
  DeviationOptions o;
  o.samples = static_cast<std::size_t>(
      c.option_integer("samples", static_cast<int>(o.samples), 0, kMaxDeviationSamples));
  o.seed = static_cast<std::uint64_t>(
      c.option_integer("seed", static_cast<int>(o.seed), 0, std::numeric_limits<int>::max()));
  const TriMesh mesh = read_mesh(c.written_or_input_path(1));
  const Skeleton* skeleton = obj.skeleton ? &*obj.skeleton : nullptr;
  const DeviationReport r = measure_deviation(mesh, *obj.field, skeleton, o, c.session().ctx);
  auto figures = [&](const DeviationSummary& d) {
    if (r.relative) {
      return "p50 " + format_number(d.p50) + ", p99 " + format_number(d.p99) + ", max " +
             format_number(d.max);
    }
    return "p50 " + format_number(d.abs_p50) + ", p99 " + format_number(d.abs_p99) + ", max " +
           format_number(d.abs_max);
  };
  std::string text = c.arg(1).text + " against " + c.arg(0).text + ": deviation " +
                     figures(r.samples) + (r.relative ? " of the local radius" : " model units") +
                     " over " + count_text(r.samples.points) + " points on the mesh; vertices " +
                     figures(r.vertices) + " over " + count_text(r.vertices.points);
  const std::size_t unresolved = r.samples.unresolved + r.vertices.unresolved;
  if (unresolved > 0) {
    text += "; " + count_text(unresolved) + " point(s) without surface within the search distance";
  }
  return {c.spec().name, text, true, {}, {}};
}

std::string value_line(const Field& f, const Vec3& p) {
  const double v = f.value(p);
  char buf[160];
  std::snprintf(buf, sizeof buf, "f(%s) = %.17g (%s, iso %g)", format_vec3(p).c_str(), v,
                v > f.iso() ? "inside" : "outside", f.iso());
  return buf;
}

CommandResult run_eval(Call& c) {
  c.expect_count(4, 4, "NAME X Y Z");
  const Object& obj = c.object(0, ObjectKind::kShape);
  const Vec3 p(c.number(1, "x"), c.number(2, "y"), c.number(3, "z"));
  return {c.spec().name, value_line(*obj.field, p), true, {}, {}};
}

CommandResult run_eval_points(Call& c) {
  c.expect_count(3, 3, "NAME POINTS OUT");
  const Object& obj = c.object(0, ObjectKind::kShape);
  const PointSet points = read_points(c.input_path(1));
  std::vector<double> values(points.size());
  obj.field->evaluate(points.positions, values, {}, c.session().ctx);
  const std::string path = c.output_path(2);
  write_file_atomically(path, [&](std::ostream& out) {
    char buf[64];
    for (double v : values) {
      std::snprintf(buf, sizeof buf, "%.17g\n", v);
      out << buf;
    }
  });
  std::size_t inside = 0;
  for (double v : values) inside += v > obj.field->iso() ? 1 : 0;
  return {c.spec().name,
          c.arg(2).text + ": " + std::to_string(values.size()) + " values, " +
              std::to_string(inside) + " inside",
          true,
          {},
          {}};
}

CommandResult run_info(Call& c) {
  c.expect_count(1, 1, "NAME");
  const auto it = c.session().objects.find(c.arg(0).text);
  if (it == c.session().objects.end()) (void)c.object(0, ObjectKind::kShape);  // throws with a hint
  const Object& o = it->second;
  std::string text = c.arg(0).text + ": " + summary_text(o);
  if (o.kind == ObjectKind::kShape) {
    const Aabb b = o.field->bounds();
    text += "; iso " + format_number(o.field->iso());
    if (!b.isEmpty()) text += "; bounds " + format_vec3(b.min()) + " to " + format_vec3(b.max());
  }
  return {c.spec().name, text, true, {}, {}};
}

CommandResult run_list(Call& c) {
  c.expect_count(0, 0, "no arguments");
  std::string text;
  std::size_t listed = 0;
  for (const auto& [name, o] : c.session().objects) {
    if (listed++ == kMaxListed) {
      text += "\n... and " + std::to_string(c.session().objects.size() - kMaxListed) + " more";
      break;
    }
    text += (text.empty() ? "" : "\n") + name + " (" + kind_name(o.kind) + "): " + summary_text(o);
  }
  if (text.empty()) text = "no objects yet";
  return {c.spec().name, text, true, {}, {}};
}

CommandResult run_help(Call& c) {
  c.expect_count(0, 1, "[COMMAND]");
  if (c.count() == 1) {
    try {
      return {c.spec().name, ScriptSession::command_help(c.arg(0).text), true, {}, {}};
    } catch (const InvalidArgument& e) {
      c.fail(c.arg(0), e.what());
    }
  }
  std::string text = "commands (help COMMAND for details):";
  for (const std::string& name : ScriptSession::command_names()) {
    text += "\n  " + command_table().at(name)->synopsis;
  }
  return {c.spec().name, text, true, {}, {}};
}

}  // namespace

void add_output_commands(std::vector<CommandSpec>& out) {
  using Mc = MarchingCubesOptions;
  using Tets = TetrahedralOptions;
  using Tol = ToleranceOptions;
  const Mc mc;
  const Tets tets;
  const Tol tol;
  const ParticleMeshOptions pm;
  out.push_back(
      {"param",
       "param NAME VALUE [min=A] [max=B] [step=S]",
       "Declares a parameter with a default VALUE; `ramiform run --set NAME=V` overrides it. "
       "Later arguments use it as $NAME or ${NAME}. `min`, `max` and `step` (numbers, step > 0, "
       "min <= max) give the range of the slider `ramiform studio` shows for it; they change "
       "nothing else.",
       "param r 2 min=0.5 max=4 step=0.1\nsphere s $r",
       {"min", "max", "step"},
       run_param,
       {}});
  out.push_back(
      {"save_mesh",
       "save_mesh NAME FILE [FILE ...] [resolution=N | cell=H] [method=mc|tets|particles] "
       "[tolerance=T] [levels=N] [section_scale=S] [lod=T1,T2,... | lod_budget=N1,N2,...] "
       "[n_circ=N] [n_sphere=N] [placement_radius=R] [delta=D] [max_iterations=N] [relax=N] "
       "[up=z|y] [normals=yes|no] [uv=auto|yes|no]",
       "Polygonizes a shape once and writes it to every FILE (.ply, .obj, .off, .glb) inside the "
       "output directory: marching cubes over the shape's bounds, `resolution` cells along the "
       "longest side" +
           default_text(mc.resolution, Mc::kMinResolution, Mc::kMaxResolution) +
           " or cells of size `cell`; or, for a shape made by skeleton, grow or lsystem, the "
           "skeleton-bounded tetrahedral polygonizer refined until the deviation p99 is at most "
           "`tolerance` local radii" +
           default_text(tol.tolerance, Tol::kMinTolerance, Tol::kMaxTolerance) +
           " (the message gives the measured p99 and max), from a base mesh of `levels` "
           "subdivisions" +
           default_text(tol.tets.levels, Tets::kMinLevels, Tets::kMaxLevels) +
           " and cross-section squares `section_scale` radii wide" +
           default_text(tets.section_scale, Tets::kMinSectionScale, Tets::kMaxSectionScale) +
           "; `levels` without `tolerance` gives the paper's uniform levels, unrefined. "
           "`lod` (tolerances, finest first, e.g. lod=0.05,0.15,0.4) or `lod_budget` (triangle "
           "counts, e.g. lod_budget=1000000,300000,100000) makes levels of detail with the "
           "tolerance mesher (method=tets is then the default): a .glb holds them all (nodes LOD0, "
           "LOD1, ..., MSFT_lod), another "
           "format gets one file per level (t.lod0.ply, t.lod1.ply, ...). method=particles "
           "(for a shape made by skeleton, grow or lsystem; Gruber & Wallner 2014) places "
           "`n_circ`" +
           default_text(pm.n_circ, kMinCirc, kMaxCirc) +
           " particles on rings around every edge (at the charges of an equipotential surface, "
           "else every half the smaller node radius) and `n_sphere`" +
           default_text(pm.n_sphere, kMinSphere, kMaxSphere) +
           " on a sphere at every junction, rings of radius `placement_radius` (default per edge "
           "its mean node radius), joins them by the skeleton's structure and moves them onto "
           "the surface by Newton steps until |f - iso| <= `delta`" +
           default_text(pm.delta) + " times the iso value, for at most `max_iterations`" +
           default_text(pm.max_iterations, 1, kMaxParticleIterations) + " rounds, then `relax`" +
           default_text(pm.relax, 0, kMaxRelax) +
           " rounds of tangential relaxation; the message gives the particles, how many "
           "converged and the iterations, and the command fails (nothing is written) when a "
           "particle did not converge. Files get the field's "
           "normals (`normals`=yes|no, default yes) and bark UVs along the skeleton (`uv`="
           "auto|yes|no; auto: for .glb and .obj); `up`=z|y is the up axis of .ply, .obj and "
           ".off files (default z; a .glb is always +Y up).",
       "save_mesh s3 s3.ply resolution=128",
       {"resolution", "cell", "method", "tolerance", "levels", "section_scale", "lod", "lod_budget",
        "n_circ", "n_sphere", "placement_radius", "delta", "max_iterations", "relax", "up",
        "normals", "uv"},
       run_save_mesh,
       {}});
  out.push_back(
      {"deviation",
       "deviation NAME MESH [samples=N] [seed=S]",
       "Measures how far MESH (a mesh file, or one this script saved under that name) lies from "
       "the surface of shape NAME, as `ramiform check --deviation` does: `samples` "
       "area-weighted points on the mesh (default " +
           std::to_string(DeviationOptions{}.samples) + ", 0–" +
           std::to_string(kMaxDeviationSamples) +
           ", seed `seed`) and every vertex are "
           "projected onto the surface. For a shape made by skeleton, grow or lsystem the "
           "distances are relative to the local skeleton radius, otherwise in model units.",
       "deviation t t.ply samples=50000",
       {"samples", "seed"},
       run_deviation,
       {}});
  out.push_back({"eval",
                 "eval NAME X Y Z",
                 "Prints the field value at a point and whether it is inside.",
                 "eval s3 0 0 0",
                 {},
                 run_eval,
                 {}});
  out.push_back(
      {"eval_points",
       "eval_points NAME POINTS OUT",
       "Evaluates a shape at every point of POINTS ('x y z' per line, or .ply) and writes one "
       "value per line to OUT.",
       "eval_points s3 probe.txt values.txt",
       {},
       run_eval_points,
       {}});
  out.push_back({"info",
                 "info NAME",
                 "Describes an object: what it is, its iso value and bounds.",
                 "info s3",
                 {},
                 run_info,
                 {}});
  out.push_back({"list", "list", "Lists every named object.", "list", {}, run_list, {}});
  out.push_back({"help",
                 "help [COMMAND]",
                 "Lists the commands, or describes one.",
                 "help skin",
                 {},
                 run_help,
                 {}});
}

}  // namespace ramiform::script
