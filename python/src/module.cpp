// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The Python module `ramiform._ramiform` (re-exported by the package `ramiform`, docs/python.md):
// skeletons, fields, the polygonizers, checks, growth, the scene language and the file formats,
// with NumPy arrays in and out.
//
// - Arrays out are read-only views of the C++ objects (no copy), kept alive by the object: a
//   Mesh's vertices, triangles, normals, uvs and labels; a Skeleton's edges, and its positions
//   and radii as strided views of its nodes.
// - Keyword defaults are read from the library's options structs, so there is one source of
//   defaults (the CLI's --help reads the same structs).
// - Long calls release the GIL and can be interrupted with Ctrl+C (`interruptible`); `threads=`
//   is the CLI's --threads (0 = all cores) and results never depend on it.
// - InputError and InvalidArgument (bad files, bad values) become ValueError with the library's
//   message (file and line included); Failure becomes RuntimeError, Cancelled KeyboardInterrupt.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "commands.h"
#include "common.h"
#include "mesh_job.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/grow/space_colonization.h"
#include "ramiform/io/drawing_io.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/particles_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/io/surface_points.h"
#include "ramiform/lines/lines.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/mesh/normals.h"
#include "ramiform/particles/surface_particles.h"
#include "ramiform/polygonize/particles.h"
#include "ramiform/script/script.h"
#include "ramiform/skeleton/from_points.h"
#include "ramiform/skeleton/generate.h"
#include "reconstruct_job.h"

namespace py = pybind11;

namespace ramiform::python {
namespace {

using cli::MeshJobOptions;
using cli::MeshJobResult;

// ---------------------------------------------------------------------------------------------
// NumPy helpers

using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Ints = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;

/// A read-only array over `data`, kept alive by `owner`.
template <typename T>
py::array view(const T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
               py::handle owner) {
  py::array a(py::dtype::of<T>(), std::move(shape), std::move(strides), data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

template <typename T>
py::array rows(const T* data, std::size_t n, std::size_t width, py::handle owner) {
  return view(data, {static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(width)},
              {static_cast<py::ssize_t>(width * sizeof(T)), static_cast<py::ssize_t>(sizeof(T))},
              owner);
}

/// The shape check every array argument gets: `what` must be (N, width) (width 0: (N,)).
void require_shape(const py::array& a, py::ssize_t width, const char* what) {
  const bool ok = width == 0 ? a.ndim() == 1 : (a.ndim() == 2 && a.shape(1) == width);
  if (!ok) {
    std::string shape = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k)
      shape += (k ? ", " : "") + std::to_string(a.shape(k));
    shape += a.ndim() == 1 ? ",)" : ")";
    throw InvalidArgument(std::string(what) + " must have shape " +
                          (width == 0 ? "(N,)" : "(N, " + std::to_string(width) + ")") + ", got " +
                          shape);
  }
}

std::vector<Vec3> to_points(const Doubles& a, const char* what) {
  require_shape(a, 3, what);
  const auto n = static_cast<std::size_t>(a.shape(0));
  std::vector<Vec3> p(n);
  const double* d = a.data();
  for (std::size_t i = 0; i < n; ++i) {
    p[i] = Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
    if (!p[i].allFinite()) {
      throw InvalidArgument(std::string(what) + "[" + std::to_string(i) + "] is not finite");
    }
  }
  return p;
}

/// Normals (count, 3), one per point or vertex (`what`, for the message).
std::vector<Vec3> to_normals(const Doubles& a, std::size_t count, const char* what) {
  std::vector<Vec3> n = to_points(a, "normals");
  if (n.size() != count) {
    throw InvalidArgument("normals has " + std::to_string(n.size()) + " rows for " +
                          std::to_string(count) + " " + what);
  }
  return n;
}

Vec3 to_vec3(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) throw InvalidArgument(std::string(what) + " must have 3 values");
  return {v[0], v[1], v[2]};
}

/// nlohmann::json to a Python object (through the json module: the figures are small).
py::object to_python(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

Context make_context(int threads) {
  if (threads < 0 || threads > Context::kMaxThreads) {
    throw InvalidArgument("threads must be 0 (all cores) to " +
                          std::to_string(Context::kMaxThreads) + ", got " +
                          std::to_string(threads));
  }
  return Context(threads);
}

/// Runs `work` without the GIL on a thread of its own while the calling thread watches for
/// Ctrl+C every 20 ms (Python runs signal handlers on the main thread only, between bytecodes,
/// so a long C++ call would otherwise hide the interrupt until it returns). On a signal the
/// context is cancelled, the work stops at its next cancellation check, and the handler's
/// exception (KeyboardInterrupt) is raised. The work's own exceptions pass through.
template <typename F>
void interruptible(Context& ctx, F&& work) {
  std::exception_ptr error;
  bool done = false;
  bool interrupted = false;
  std::mutex mutex;
  std::condition_variable finished;
  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        work();
      } catch (...) {
        error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(mutex);
      done = true;
      finished.notify_one();
    });
    std::unique_lock<std::mutex> lock(mutex);
    while (!finished.wait_for(lock, std::chrono::milliseconds(20), [&] { return done; })) {
      if (interrupted) continue;
      lock.unlock();
      {
        const py::gil_scoped_acquire acquire;
        if (PyErr_CheckSignals() != 0) interrupted = true;
      }
      if (interrupted) ctx.cancel();
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  if (error) std::rethrow_exception(error);
}

// ---------------------------------------------------------------------------------------------
// Objects

/// A mesh with the figures of the call that made it.
struct Mesh {
  TriMesh mesh;
  nlohmann::json stats = nlohmann::json::object();
};

/// A field, with the skeleton it was built from and the one a polygonizer follows.
struct FieldHandle {
  FieldPtr field;
  std::optional<Skeleton> source;  ///< the skeleton given (types, UVs and checks use it)
  std::optional<Skeleton> meshed;  ///< the skeleton the polygonizer follows (split with a fit)
  nlohmann::json fit;              ///< the radius fit's figures (null without fit_radii)
  /// surface="equipotential": its charges and lambda (`field` is its field)
  std::shared_ptr<const Equipotential> equipotential;
};

/// Per-node open-end flags from an array (N,) of 0/1 (or bools), or none: empty.
std::vector<std::uint8_t> open_end_flags(const std::optional<Ints>& flags, std::size_t nodes) {
  if (!flags) return {};
  require_shape(*flags, 0, "open_ends");
  if (static_cast<std::size_t>(flags->shape(0)) != nodes) {
    throw InvalidArgument("open_ends has " + std::to_string(flags->shape(0)) + " values for " +
                          std::to_string(nodes) + " nodes");
  }
  std::vector<std::uint8_t> out(nodes);
  for (std::size_t i = 0; i < nodes; ++i) {
    const std::int64_t v = flags->data()[i];
    if (v != 0 && v != 1) {
      throw InvalidArgument("open_ends[" + std::to_string(i) + "] must be 0 or 1, got " +
                            std::to_string(v));
    }
    out[i] = static_cast<std::uint8_t>(v);
  }
  return out;
}

Skeleton make_skeleton(const Doubles& positions, const Doubles& radii, const Ints& edges,
                       const std::optional<Ints>& types, const std::optional<Ints>& open_ends) {
  require_shape(positions, 3, "positions");
  require_shape(radii, 0, "radii");
  if (edges.size() != 0 || edges.ndim() != 1) require_shape(edges, 2, "edges");
  const auto n = static_cast<std::size_t>(positions.shape(0));
  if (static_cast<std::size_t>(radii.shape(0)) != n) {
    throw InvalidArgument("radii has " + std::to_string(radii.shape(0)) + " values for " +
                          std::to_string(n) + " positions");
  }
  Skeleton s;
  s.nodes.resize(n);
  const double* p = positions.data();
  const double* r = radii.data();
  for (std::size_t i = 0; i < n; ++i) {
    s.nodes[i].position = Vec3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    s.nodes[i].radius = r[i];
  }
  const std::size_t m = edges.ndim() == 2 ? static_cast<std::size_t>(edges.shape(0)) : 0;
  s.edges.resize(m);
  const std::int64_t* e = edges.data();
  for (std::size_t k = 0; k < m; ++k) {
    for (int j = 0; j < 2; ++j) {
      const std::int64_t v = e[2 * k + j];
      if (v < 0 || static_cast<std::size_t>(v) >= n) {
        throw InvalidArgument("edges[" + std::to_string(k) + "] refers to node " +
                              std::to_string(v) + " of " + std::to_string(n));
      }
      s.edges[k][j] = static_cast<std::uint32_t>(v);
    }
  }
  if (types) {
    require_shape(*types, 0, "types");
    if (static_cast<std::size_t>(types->shape(0)) != n) {
      throw InvalidArgument("types has " + std::to_string(types->shape(0)) + " values for " +
                            std::to_string(n) + " nodes");
    }
    s.node_types.assign(types->data(), types->data() + n);
  }
  s.open_ends = open_end_flags(open_ends, n);
  validate(s, "Skeleton");
  return s;
}

TriMesh make_mesh(const Doubles& vertices, const Ints& triangles,
                  const std::optional<Doubles>& normals) {
  TriMesh m;
  m.positions = to_points(vertices, "vertices");
  require_shape(triangles, 3, "triangles");
  const auto t = static_cast<std::size_t>(triangles.shape(0));
  m.triangles.resize(t);
  const std::int64_t* d = triangles.data();
  for (std::size_t k = 0; k < t; ++k) {
    for (int j = 0; j < 3; ++j) {
      const std::int64_t v = d[3 * k + j];
      if (v < 0 || static_cast<std::size_t>(v) >= m.positions.size()) {
        throw InvalidArgument("triangles[" + std::to_string(k) + "] refers to vertex " +
                              std::to_string(v) + " of " + std::to_string(m.positions.size()));
      }
      m.triangles[k][j] = static_cast<std::uint32_t>(v);
    }
  }
  if (normals) m.normals = to_normals(*normals, m.positions.size(), "vertices");
  return m;
}

SkeletonFieldOptions field_options(const std::string& surface, const std::string& kernel,
                                   double iso) {
  if (surface != "convolution" && surface != "distance") {
    throw InvalidArgument("surface must be 'convolution' or 'distance', got '" + surface + "'");
  }
  cli::FieldFlags flags;
  flags.surface = surface;
  flags.kernel = kernel;
  flags.iso = iso;
  return cli::field_options(flags);
}

/// The keywords of the equipotential surface (skeleton_field, mesh_skeleton); the defaults are
/// EquipotentialOptions'.
struct EquipotentialArgs {
  double alpha = EquipotentialOptions{}.alpha;
  double charge = EquipotentialOptions{}.charge;
  double charge_spacing = EquipotentialOptions{}.charge_spacing;
  double lambda = EquipotentialOptions{}.lambda;
  double lambda_scale = EquipotentialOptions{}.lambda_scale;
  bool open_ends = EquipotentialOptions{}.open_ends;
};

/// With surface "equipotential" the options of `a` in `out` (returned), else null; ValueError
/// for an equipotential keyword set with another surface, or kernel/iso with this one.
const EquipotentialOptions* equipotential_options(const std::string& surface,
                                                  const EquipotentialArgs& a,
                                                  const std::string& kernel, double iso,
                                                  EquipotentialOptions& out) {
  const EquipotentialArgs defaults;
  if (surface != "equipotential") {
    const std::pair<const char*, bool> set[] = {
        {"alpha", a.alpha != defaults.alpha},
        {"charge", a.charge != defaults.charge},
        {"charge_spacing", a.charge_spacing != defaults.charge_spacing},
        {"lambda_", a.lambda != defaults.lambda},
        {"lambda_scale", a.lambda_scale != defaults.lambda_scale},
        {"open_ends", a.open_ends != defaults.open_ends}};
    for (const auto& [name, given] : set) {
      if (given) {
        throw InvalidArgument(std::string(name) +
                              " applies to surface='equipotential' only, not to surface='" +
                              surface + "'");
      }
    }
    return nullptr;
  }
  if (!kernel.empty()) {
    throw InvalidArgument(
        "kernel applies to the convolution and distance surfaces, not to "
        "surface='equipotential' (its falloff is alpha)");
  }
  if (iso != 0.0) {
    throw InvalidArgument(
        "iso: the equipotential surface's iso value is lambda_ (times "
        "lambda_scale)");
  }
  out.alpha = a.alpha;
  out.charge = a.charge;
  out.charge_spacing = a.charge_spacing;
  out.lambda = a.lambda;
  out.lambda_scale = a.lambda_scale;
  out.open_ends = a.open_ends;
  return &out;
}

UpAxis up_axis(const std::string& up) {
  if (up != "z" && up != "y") throw InvalidArgument("up must be 'z' or 'y', got '" + up + "'");
  return up == "y" ? UpAxis::kY : UpAxis::kZ;
}

/// The polygonizer's skeleton: the one given, else the field's.
const Skeleton& meshed_skeleton(const FieldHandle& f, const Skeleton* given, const char* function) {
  if (given != nullptr) return *given;
  if (f.meshed) return *f.meshed;
  throw InvalidArgument(std::string(function) +
                        ": this field has no skeleton; pass skeleton= (the tetrahedral "
                        "polygonizer follows a skeleton)");
}

/// Normals from the field and (for a skeleton with node types) the nearest node's type, as
/// `ramiform mesh` adds them.
void finish_mesh(TriMesh& mesh, const FieldHandle& f, bool normals, Context& ctx) {
  if (normals) {
    SurfaceAttributeOptions a;
    a.normals = true;
    a.uvs = false;
    const Skeleton empty;
    add_surface_attributes(mesh, *f.field, f.source ? *f.source : empty, a, &ctx, nullptr);
  }
  if (f.source) cli::label_by_node_types(std::span<TriMesh>(&mesh, 1), *f.source, ctx);
}

Mesh polygonize(const FieldHandle& f, const Skeleton* skeleton, const MeshJobOptions& o,
                bool normals, int threads) {
  Context ctx = make_context(threads);
  Mesh out;
  interruptible(ctx, [&] {
    MeshJobResult r =
        cli::polygonize_field(*f.field, skeleton != nullptr ? *skeleton : Skeleton{}, o, ctx);
    out.mesh = std::move(r.mesh);
    out.stats = std::move(r.stats);
    finish_mesh(out.mesh, f, normals, ctx);
    out.stats["vertices"] = out.mesh.vertex_count();
    out.stats["triangles"] = out.mesh.triangle_count();
  });
  return out;
}

/// (N, 3) array copied from points.
py::array_t<double> points_array(const std::vector<Vec3>& p) {
  py::array_t<double> a({static_cast<py::ssize_t>(p.size()), py::ssize_t{3}});
  double* d = a.mutable_data();
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (int k = 0; k < 3; ++k) d[3 * i + static_cast<std::size_t>(k)] = p[i][k];
  }
  return a;
}

/// A PointSet from positions (N, 3) and optional normals (N, 3).
PointSet point_set(const Doubles& points, const std::optional<Doubles>& normals) {
  PointSet s;
  s.positions = to_points(points, "points");
  if (normals) s.normals = to_normals(*normals, s.positions.size(), "points");
  return s;
}

void bind_points(py::module_& m) {
  const SurfacePointsOptions sp;
  m.def(
      "read_surface_points",
      [](const std::string& path, std::size_t mesh_samples, std::uint64_t seed) {
        SurfacePointsOptions o;
        o.mesh_samples = mesh_samples;
        o.seed = seed;
        const SurfacePoints r = read_surface_points(path, o);
        py::object normals = py::none();
        if (r.points.has_normals()) normals = points_array(r.points.normals);
        return py::make_tuple(points_array(r.points.positions), normals);
      },
      py::arg("path"), py::kw_only(), py::arg("mesh_samples") = sp.mesh_samples,
      py::arg("seed") = sp.seed,
      "Oriented points for reconstruction: a point cloud as it is, a mesh (.ply with faces, "
      ".off, .obj) as `mesh_samples` area-weighted points with their triangles' normals. "
      "Returns (points (N, 3), normals (N, 3) or None).");
  const NormalOptions no;
  m.def(
      "orient_normals",
      [](const Doubles& points, const std::optional<Doubles>& normals, int neighbours,
         int threads) {
        NormalOptions o;
        o.neighbours = neighbours;
        const PointSet in = point_set(points, normals);
        Context ctx = make_context(threads);
        NormalReport r;
        PointSet out;
        interruptible(ctx, [&] { out = orient_normals(in, o, &r, &ctx); });
        py::dict d;
        d["estimated"] = r.estimated;
        d["flipped"] = r.flipped;
        d["components"] = r.components;
        return py::make_tuple(points_array(out.normals), d);
      },
      py::arg("points"), py::arg("normals") = py::none(), py::kw_only(),
      py::arg("neighbours") = no.neighbours, py::arg("threads") = 0,
      "Unit outward normals (N, 3) for the points: estimated (PCA over `neighbours`) when "
      "normals is None, else the given ones with the inconsistent ones flipped; and a report "
      "{'estimated', 'flipped', 'components'}.");
  const MpuOptions mo;
  m.def(
      "mpu_field",
      [](const Doubles& points, const std::optional<Doubles>& normals, double tolerance,
         double support, int min_points, int max_depth, bool sharp_features, int neighbours,
         double iso, int threads) {
        NormalOptions n;
        n.neighbours = neighbours;
        MpuOptions o;
        o.tolerance = tolerance;
        o.support = support;
        o.min_points = min_points;
        o.max_depth = max_depth;
        o.sharp_features = sharp_features;
        o.iso = iso;
        const PointSet in = point_set(points, normals);
        Context ctx = make_context(threads);
        FieldHandle f;
        interruptible(ctx, [&] {
          const PointSet oriented = orient_normals(in, n, nullptr, &ctx);
          f.field = make_mpu_field(oriented, o, nullptr, &ctx);
        });
        return f;
      },
      py::arg("points"), py::arg("normals") = py::none(), py::kw_only(),
      py::arg("tolerance") = mo.tolerance, py::arg("support") = mo.support,
      py::arg("min_points") = mo.min_points, py::arg("max_depth") = mo.max_depth,
      py::arg("sharp_features") = mo.sharp_features, py::arg("neighbours") = no.neighbours,
      py::arg("iso") = mo.iso, py::arg("threads") = 0,
      "A multi-level partition of unity implicit (Ohtake et al. 2003) through the points "
      "(N, 3), their normals oriented (or estimated when None) first; a Field like any other "
      "(docs/reconstruction.md).");
  const cli::ReconstructOptions ro;
  m.def(
      "reconstruct",
      [](const std::string& path, std::optional<std::string> out, double tolerance, double support,
         int min_points, int max_depth, bool sharp, int neighbours, std::optional<double> cell,
         int resolution, double spacing_cells, double speck_cells, std::size_t mesh_samples,
         std::uint64_t seed, int threads) {
        cli::ReconstructOptions o;
        o.mpu.tolerance = tolerance;
        o.mpu.support = support;
        o.mpu.min_points = min_points;
        o.mpu.max_depth = max_depth;
        o.mpu.sharp_features = sharp;
        o.normals.neighbours = neighbours;
        if (cell) o.cell_size = *cell;
        o.resolution = resolution;
        o.spacing_cells = spacing_cells;
        o.speck_cells = speck_cells;
        o.read.mesh_samples = mesh_samples;
        o.read.seed = seed;
        Context ctx = make_context(threads);
        Mesh result;
        interruptible(ctx, [&] {
          cli::PointSurface s = cli::build_point_surface(path, o, ctx, [](const char*) {});
          result.mesh = cli::mesh_point_surface(s, o, ctx);
          result.stats = s.stats;
          if (out) write_mesh(result.mesh, *out);
        });
        return result;
      },
      py::arg("path"), py::kw_only(), py::arg("out") = py::none(),
      py::arg("tolerance") = ro.mpu.tolerance, py::arg("support") = ro.mpu.support,
      py::arg("min_points") = ro.mpu.min_points, py::arg("max_depth") = ro.mpu.max_depth,
      py::arg("sharp") = ro.mpu.sharp_features, py::arg("neighbours") = ro.normals.neighbours,
      py::arg("cell") = py::none(), py::arg("resolution") = ro.resolution,
      py::arg("spacing_cells") = ro.spacing_cells, py::arg("speck_cells") = ro.speck_cells,
      py::arg("mesh_samples") = ro.read.mesh_samples, py::arg("seed") = ro.read.seed,
      py::arg("threads") = 0,
      "`ramiform reconstruct`: the MPU surface of a point cloud or a mesh file (options as the "
      "command's: tolerance, support, min_points, max_depth, sharp, neighbours), meshed by "
      "marching cubes at `cell` or `resolution` cells along the longest side (default "
      "`spacing_cells` point spacings), pieces below `speck_cells` cells removed; the Mesh's "
      "stats hold the same figures as --stats. Written to `out` when given.");
  const ParticleOptions po;
  m.def(
      "particles",
      [](const FieldHandle& f, std::size_t count, std::size_t per_cell, int iterations,
         std::uint64_t seed, int cell_depth, double flatness, std::optional<std::string> state,
         std::optional<std::string> previous, std::optional<std::array<double, 3>> edit_min,
         std::optional<std::array<double, 3>> edit_max, int threads) {
        ParticleOptions o;
        o.count = count;
        o.per_cell = per_cell;
        o.iterations = iterations;
        o.seed = seed;
        o.max_depth = cell_depth;
        o.flatness_deg = flatness;
        if (previous.has_value() != (edit_min.has_value() && edit_max.has_value()) ||
            edit_min.has_value() != edit_max.has_value()) {
          throw InvalidArgument(
              "previous= (saved particles) goes with edit_min= and edit_max= (the box the edit "
              "stayed in)");
        }
        Context ctx = make_context(threads);
        ParticleSystem sys;
        ParticleStats st;
        interruptible(ctx, [&] {
          if (previous) {
            // Local regeneration (paper §3): only the particles near the edit box move.
            const ParticleSystem before = read_particles(*previous);
            if (before.iso != f.field->iso()) {
              throw InvalidArgument("previous=" + *previous + ": the saved particles lie on iso " +
                                    format_number(before.iso) + ", the field's surface is iso " +
                                    format_number(f.field->iso()));
            }
            const Aabb box(Vec3((*edit_min)[0], (*edit_min)[1], (*edit_min)[2]),
                           Vec3((*edit_max)[0], (*edit_max)[1], (*edit_max)[2]));
            sys = regenerate_particles(*f.field, before, box, o, &st, &ctx);
          } else {
            sys = spread_particles(*f.field, o, field_cells(*f.field), {}, &st, &ctx);
          }
          if (state) write_particles(sys, *state);
        });
        const std::size_t n = sys.particles.size();
        py::array_t<double> pos({static_cast<py::ssize_t>(n), py::ssize_t{3}});
        py::array_t<double> nor({static_cast<py::ssize_t>(n), py::ssize_t{3}});
        py::array_t<double> delta(static_cast<py::ssize_t>(n));
        for (std::size_t i = 0; i < n; ++i) {
          for (int k = 0; k < 3; ++k) {
            pos.mutable_data()[3 * i + static_cast<std::size_t>(k)] = sys.particles[i].position[k];
            nor.mutable_data()[3 * i + static_cast<std::size_t>(k)] = sys.particles[i].normal[k];
          }
          delta.mutable_data()[i] = sys.particles[i].delta;
        }
        py::dict d;
        d["positions"] = pos;
        d["normals"] = nor;
        d["delta"] = delta;
        py::dict stats;
        stats["particles"] = st.particles;
        stats["cells"] = st.cells;
        stats["kept"] = st.kept;
        stats["iterations"] = st.iterations;
        stats["residual_max"] = st.residual_max;
        stats["spacing_cv"] = st.spacing_cv;
        d["stats"] = stats;
        return d;
      },
      py::arg("field"), py::kw_only(), py::arg("count") = po.count,
      py::arg("per_cell") = po.per_cell, py::arg("iterations") = po.iterations,
      py::arg("seed") = po.seed, py::arg("cell_depth") = po.max_depth,
      py::arg("flatness") = po.flatness_deg, py::arg("state") = py::none(),
      py::arg("previous") = py::none(), py::arg("edit_min") = py::none(),
      py::arg("edit_max") = py::none(), py::arg("threads") = 0,
      "Particles spread evenly over the field's surface (docs/particles.md): about `count` in "
      "all, or `per_cell` per cell of an MPU field's octree or of adaptive cells. `state` saves "
      "them (particle-state PLY, for draw(particle_state=...) and later regeneration); "
      "`previous` (a saved state) with `edit_min`, `edit_max` regenerates only the particles "
      "near that box after an edit of the field confined to it (paper §3). Returns "
      "{'positions' (K, 3), 'normals' (K, 3), 'delta' (K,), 'stats'}.");
  const LineOptions lo;
  const DrawingStyle ds;
  m.def(
      "draw",
      [](const FieldHandle& f, std::optional<std::string> out, std::optional<std::string> camera,
         double azimuth, double elevation, const std::string& vertical, double fov,
         const std::vector<std::string>& kinds, std::size_t count, std::uint64_t seed,
         const std::string& visibility, const std::string& fit, double k_c, double k_e, double k_d,
         double theta_sc, double k_a, int k_trim, int width, int height, bool hidden,
         std::optional<std::string> polylines, std::optional<std::string> particle_state,
         std::size_t per_cell, int iterations, int cell_depth, double flatness, int threads,
         const std::string& straddle, double t_d) {
        LineOptions o;
        try {
          select_line_kinds(o, kinds);
        } catch (const InvalidArgument& e) {
          throw InvalidArgument(std::string("lines: ") + e.what());
        }
        if (vertical != "y" && vertical != "z") {
          throw InvalidArgument("vertical must be y or z, got '" + vertical + "'");
        }
        o.visibility = visibility_from_name(visibility);
        o.fit = fit_from_name(fit);
        o.straddle = straddle_from_name(straddle);
        o.k_c = k_c;
        o.k_e = k_e;
        o.k_d = k_d;
        o.theta_sc_deg = theta_sc;
        o.t_d = t_d;
        o.k_a_deg = k_a;
        o.k_trim = k_trim;
        validate(o);
        DrawingStyle style;
        style.width = width;
        style.height = height > 0 ? height : width;
        style.show_hidden = hidden;
        validate(style);
        ParticleOptions po;
        po.count = count;
        po.seed = seed;
        po.per_cell = per_cell;
        po.iterations = iterations;
        po.max_depth = cell_depth;
        po.flatness_deg = flatness;
        Context ctx = make_context(threads);
        LineDrawing drawing;
        LineStats ls;
        std::size_t particles = 0;
        interruptible(ctx, [&] {
          ParticleSystem sys;
          if (particle_state) {
            // Saved by particles(state=...) or `ramiform particles --state`: not spread again.
            sys = read_particles(*particle_state);
            if (sys.iso != f.field->iso()) {
              throw InvalidArgument("particle_state=" + *particle_state +
                                    ": the saved particles lie on iso " + format_number(sys.iso) +
                                    ", the field's surface is iso " +
                                    format_number(f.field->iso()));
            }
          } else {
            sys = spread_particles(*f.field, po, field_cells(*f.field), {}, nullptr, &ctx);
          }
          particles = sys.particles.size();
          if (sys.particles.empty()) throw InvalidArgument("no particles reached the surface");
          Aabb box;
          for (const SurfaceParticle& p : sys.particles) box.extend(p.position);
          const Camera framing = frame_box(box, azimuth, elevation, fov,
                                           static_cast<double>(style.width) / style.height,
                                           vertical == "z" ? ViewUp::kZ : ViewUp::kY);
          const Camera cam = camera ? parse_camera(*camera, framing) : framing;
          drawing = draw_lines(*f.field, sys, cam, o, nullptr, &ls, &ctx);
          if (out) write_drawing(*out, drawing, style);
          if (polylines) write_polylines_json(*polylines, drawing);
        });
        py::list lines;
        for (const Polyline& l : drawing.lines) {
          py::dict d;
          d["kind"] = std::string(line_kind_name(l.kind));
          d["closed"] = l.closed;
          const auto n = static_cast<py::ssize_t>(l.points.size());
          py::array_t<double> pts({n, py::ssize_t{3}});
          py::array_t<bool> vis(n);
          for (std::size_t i = 0; i < l.points.size(); ++i) {
            for (int k = 0; k < 3; ++k) {
              pts.mutable_data()[3 * i + static_cast<std::size_t>(k)] = l.points[i][k];
            }
            vis.mutable_data()[i] = l.visible.empty() || l.visible[i] != 0;
          }
          d["points"] = pts;
          d["visible"] = vis;
          lines.append(d);
        }
        const Camera& c = drawing.camera;
        py::dict cam;
        cam["eye"] = std::vector<double>{c.eye.x(), c.eye.y(), c.eye.z()};
        cam["target"] = std::vector<double>{c.target.x(), c.target.y(), c.target.z()};
        cam["up"] = std::vector<double>{c.up.x(), c.up.y(), c.up.z()};
        cam["fov"] = c.fov_deg;
        cam["aspect"] = c.aspect;
        py::dict stats;
        stats["particles"] = particles;
        stats["silhouette_seeds"] = ls.silhouette_seeds;
        stats["suggestive_particles"] = ls.suggestive_particles;
        stats["straddle_pairs"] = ls.straddle_pairs;
        stats["straddle_pairs_movement"] = ls.straddle_pairs_movement;
        stats["straddle_pairs_search"] = ls.straddle_pairs_search;
        stats["hidden_fraction"] = ls.hidden_fraction;
        for (int k = 0; k < 3; ++k) {
          stats[py::str(std::string("lines_") +
                        std::string(line_kind_name(static_cast<LineKind>(k))))] = ls.lines[k];
        }
        py::dict d;
        d["camera"] = cam;
        d["lines"] = lines;
        d["stats"] = stats;
        return d;
      },
      py::arg("field"), py::kw_only(), py::arg("out") = py::none(), py::arg("camera") = py::none(),
      py::arg("azimuth") = 30.0, py::arg("elevation") = 15.0, py::arg("vertical") = "y",
      py::arg("fov") = 30.0,
      py::arg("lines") = std::vector<std::string>{"silhouette", "suggestive", "feature"},
      py::arg("count") = 10000, py::arg("seed") = 1, py::arg("visibility") = "rays",
      py::arg("fit") = "longest", py::arg("k_c") = lo.k_c, py::arg("k_e") = lo.k_e,
      py::arg("k_d") = lo.k_d, py::arg("theta_sc") = lo.theta_sc_deg, py::arg("k_a") = lo.k_a_deg,
      py::arg("k_trim") = lo.k_trim, py::arg("width") = ds.width, py::arg("height") = 0,
      py::arg("hidden") = false, py::arg("polylines") = py::none(),
      py::arg("particle_state") = py::none(), py::arg("per_cell") = po.per_cell,
      py::arg("iterations") = po.iterations, py::arg("cell_depth") = po.max_depth,
      py::arg("flatness") = po.flatness_deg, py::arg("threads") = 0, py::arg("straddle") = "auto",
      py::arg("t_d") = lo.t_d,
      "`ramiform draw` on a field (docs/drawing.md): silhouettes, suggestive contours and "
      "feature lines from `count` particles (spread with per_cell, iterations, cell_depth, "
      "flatness as particles() does) or from the saved `particle_state`, hidden lines "
      "classified. `camera` is the command's "
      "text (\"eye=x,y,z;target=...;up=...;fov=deg\", any subset), else the surface is framed from "
      "`azimuth` and `elevation` about the `vertical` axis (\"y\" or \"z\"). Writes `out` (.svg or "
      ".png) and `polylines` (.json) when given. "
      "`straddle` (\"auto\", \"movement\" or \"search\") chooses where feature lines start. "
      "Returns {'camera', 'lines': [{'kind', 'closed', 'points' (K, 3), 'visible' (K,)}], "
      "'stats'}.");
}

// ---------------------------------------------------------------------------------------------

void translate_errors() {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const InvalidArgument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const Cancelled& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const Failure& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
}

void bind_skeleton(py::module_& m) {
  py::class_<Skeleton>(m, "Skeleton",
                       "A line skeleton: nodes with positions and radii, edges between them, and "
                       "optional per-node types (SWC).")
      .def(py::init(&make_skeleton), py::arg("positions"), py::arg("radii"), py::arg("edges"),
           py::arg("types") = py::none(), py::kw_only(), py::arg("open_ends") = py::none(),
           "positions (N, 3) float, radii (N,) > 0, edges (M, 2) node indices, types (N,) int or "
           "None, open_ends (N,) 0/1 or None (1: the leaf's end is open for the equipotential "
           "surface). Validated: ValueError names the bad element.")
      .def_property_readonly(
          "positions",
          [](py::object self) {
            const auto& s = self.cast<const Skeleton&>();
            return view(s.nodes.empty() ? nullptr : s.nodes[0].position.data(),
                        {static_cast<py::ssize_t>(s.nodes.size()), 3},
                        {sizeof(SkeletonNode), sizeof(double)}, self);
          },
          "(N, 3) float64, a read-only view")
      .def_property_readonly(
          "radii",
          [](py::object self) {
            const auto& s = self.cast<const Skeleton&>();
            return view(s.nodes.empty() ? nullptr : &s.nodes[0].radius,
                        {static_cast<py::ssize_t>(s.nodes.size())}, {sizeof(SkeletonNode)}, self);
          },
          "(N,) float64, a read-only view")
      .def_property_readonly(
          "edges",
          [](py::object self) {
            const auto& s = self.cast<const Skeleton&>();
            return rows(s.edges.empty() ? nullptr : s.edges[0].data(), s.edges.size(), 2, self);
          },
          "(M, 2) uint32, a read-only view")
      .def_property_readonly(
          "types",
          [](py::object self) -> py::object {
            const auto& s = self.cast<const Skeleton&>();
            if (s.node_types.empty()) return py::none();
            return view(s.node_types.data(), {static_cast<py::ssize_t>(s.node_types.size())},
                        {sizeof(std::int32_t)}, self);
          },
          "(N,) int32 node types (SWC), or None")
      .def_property(
          "open_ends",
          [](py::object self) -> py::object {
            const auto& s = self.cast<const Skeleton&>();
            if (s.open_ends.empty()) return py::none();
            return view(s.open_ends.data(), {static_cast<py::ssize_t>(s.open_ends.size())},
                        {sizeof(std::uint8_t)}, self);
          },
          [](Skeleton& s, const std::optional<Ints>& flags) {
            std::vector<std::uint8_t> f = open_end_flags(flags, s.nodes.size());
            s.open_ends = std::move(f);
          },
          "(N,) uint8 open-end flags (1: a leaf whose end is open, skeleton JSON's "
          "\"end\": \"open\"), or None (every end closed); settable with an (N,) array or None")
      .def("__len__", [](const Skeleton& s) { return s.nodes.size(); })
      .def_property_readonly("node_count", [](const Skeleton& s) { return s.nodes.size(); })
      .def_property_readonly("edge_count", [](const Skeleton& s) { return s.edges.size(); })
      .def(
          "components", [](const Skeleton& s) { return connected_components(s).count; },
          "the number of connected parts")
      .def("__repr__", [](const Skeleton& s) {
        return "<ramiform.Skeleton " + std::to_string(s.nodes.size()) + " nodes, " +
               std::to_string(s.edges.size()) + " edges>";
      });

  const BranchingTreeOptions bt;
  m.def(
      "branching_tree",
      [](std::size_t segments, std::uint64_t seed, double trunk_length, double length_ratio,
         double branch_angle_deg, double jitter_deg, double tip_radius, double pipe_exponent) {
        BranchingTreeOptions o;
        o.segments = segments;
        o.seed = seed;
        o.trunk_length = trunk_length;
        o.length_ratio = length_ratio;
        o.branch_angle_deg = branch_angle_deg;
        o.jitter_deg = jitter_deg;
        o.tip_radius = tip_radius;
        o.pipe_exponent = pipe_exponent;
        py::gil_scoped_release release;
        return branching_tree(o);
      },
      py::kw_only(), py::arg("segments") = bt.segments, py::arg("seed") = bt.seed,
      py::arg("trunk_length") = bt.trunk_length, py::arg("length_ratio") = bt.length_ratio,
      py::arg("branch_angle_deg") = bt.branch_angle_deg, py::arg("jitter_deg") = bt.jitter_deg,
      py::arg("tip_radius") = bt.tip_radius, py::arg("pipe_exponent") = bt.pipe_exponent,
      "A procedural binary branching tree with pipe-model radii (`ramiform generate`).");
  m.def(
      "read_skeleton",
      [](const std::string& path, double obj_radius, bool soma_regions, bool keep_curves) {
        SkeletonReadOptions o;
        o.obj_radius = obj_radius;
        o.swc.soma_regions = soma_regions;
        o.keep_curves = keep_curves;
        py::gil_scoped_release release;
        return read_skeleton(path, o);
      },
      py::arg("path"), py::kw_only(), py::arg("obj_radius") = SkeletonReadOptions{}.obj_radius,
      py::arg("soma_regions") = SwcReadOptions{}.soma_regions, py::arg("keep_curves") = false,
      "Reads a skeleton: .json, .ply, .obj (obj_radius), TreeQSM .txt/.mat-text, SimpleForest "
      ".csv, SWC .swc (soma_regions: somata as closed regions, docs/formats.md). Curved JSON "
      "edges are straightened into short segments unless keep_curves (for "
      "skeleton_distances).");
  const TreeFromPointsOptions tf;
  m.def(
      "tree_from_points",
      [](const Doubles& points, const std::string& up, double bin, double min_radius,
         double pipe_exponent, std::size_t min_branch_points, double straight_tolerance) {
        TreeFromPointsOptions o;
        if (up != "z" && up != "y")
          throw InvalidArgument("up must be 'z' or 'y', got '" + up + "'");
        o.up_axis = up == "y" ? 1 : 2;
        o.bin_width = bin;
        o.min_radius = min_radius;
        o.pipe_exponent = pipe_exponent;
        o.min_branch_points = min_branch_points;
        o.straight_tolerance = straight_tolerance;
        const std::vector<Vec3> p = to_points(points, "points");
        py::gil_scoped_release release;
        return tree_from_points(p, o);
      },
      py::arg("points"), py::kw_only(), py::arg("up") = "z", py::arg("bin") = tf.bin_width,
      py::arg("min_radius") = tf.min_radius, py::arg("pipe_exponent") = tf.pipe_exponent,
      py::arg("min_branch_points") = tf.min_branch_points,
      py::arg("straight_tolerance") = tf.straight_tolerance,
      "The branching skeleton of a laser-scanned tree's point cloud (N, 3) by geodesic level "
      "sets (`ramiform reconstruct --tree`, docs/reconstruction.md): bin 0 means 6 median point "
      "spacings, min_radius 0 half the median spacing. Node 0 is the root.");
  m.def(
      "write_skeleton",
      [](const std::string& path, const Skeleton& s) {
        py::gil_scoped_release release;
        write_skeleton(s, path);
      },
      py::arg("path"), py::arg("skeleton"), "Writes a skeleton (.json or .ply), atomically.");
}

void bind_mesh(py::module_& m) {
  py::class_<Mesh>(m, "Mesh",
                   "A triangle mesh: vertices (V, 3), triangles (T, 3) uint32 counter-clockwise "
                   "from outside, optional normals (V, 3), uvs (V, 2), labels (V,); `stats` holds "
                   "the figures of the call that made it.")
      .def(py::init([](const Doubles& v, const Ints& t, const std::optional<Doubles>& n) {
             return Mesh{make_mesh(v, t, n), nlohmann::json::object()};
           }),
           py::arg("vertices"), py::arg("triangles"), py::arg("normals") = py::none())
      .def_property_readonly("vertices",
                             [](py::object self) {
                               const TriMesh& t = self.cast<const Mesh&>().mesh;
                               return rows(t.positions.empty() ? nullptr : t.positions[0].data(),
                                           t.positions.size(), 3, self);
                             })
      .def_property_readonly("triangles",
                             [](py::object self) {
                               const TriMesh& t = self.cast<const Mesh&>().mesh;
                               return rows(t.triangles.empty() ? nullptr : t.triangles[0].data(),
                                           t.triangles.size(), 3, self);
                             })
      .def_property_readonly("normals",
                             [](py::object self) -> py::object {
                               const TriMesh& t = self.cast<const Mesh&>().mesh;
                               if (t.normals.empty()) return py::none();
                               return rows(t.normals[0].data(), t.normals.size(), 3, self);
                             })
      .def_property_readonly("uvs",
                             [](py::object self) -> py::object {
                               const TriMesh& t = self.cast<const Mesh&>().mesh;
                               if (t.uvs.empty()) return py::none();
                               return rows(t.uvs[0].data(), t.uvs.size(), 2, self);
                             })
      .def_property_readonly(
          "labels",
          [](py::object self) -> py::object {
            const TriMesh& t = self.cast<const Mesh&>().mesh;
            if (t.vertex_labels.empty()) return py::none();
            return view(t.vertex_labels.data(), {static_cast<py::ssize_t>(t.vertex_labels.size())},
                        {sizeof(std::int32_t)}, self);
          },
          "per-vertex labels (the SWC type of the nearest node), or None")
      .def_property_readonly("stats", [](const Mesh& m) { return to_python(m.stats); })
      .def_property_readonly("vertex_count", [](const Mesh& m) { return m.mesh.vertex_count(); })
      .def_property_readonly("triangle_count",
                             [](const Mesh& m) { return m.mesh.triangle_count(); })
      .def("__repr__", [](const Mesh& m) {
        return "<ramiform.Mesh " + std::to_string(m.mesh.vertex_count()) + " vertices, " +
               std::to_string(m.mesh.triangle_count()) + " triangles>";
      });

  m.def(
      "read_mesh",
      [](const std::string& path) {
        py::gil_scoped_release release;
        return Mesh{read_mesh(path), nlohmann::json::object()};
      },
      py::arg("path"), "Reads a .ply, .obj or .off mesh.");
  m.def(
      "write_mesh",
      [](const std::string& path, const Mesh& mesh, const std::string& up, bool normals, bool uvs) {
        MeshWriteOptions o;
        o.up = up_axis(up);
        o.normals = normals;
        o.uvs = uvs;
        py::gil_scoped_release release;
        write_mesh(mesh.mesh, path, o);
      },
      py::arg("path"), py::arg("mesh"), py::kw_only(), py::arg("up") = "z",
      py::arg("normals") = MeshWriteOptions{}.normals, py::arg("uvs") = MeshWriteOptions{}.uvs,
      "Writes .ply (binary), .obj, .off or .glb by the extension, atomically, as `ramiform mesh` "
      "does (up: the up axis of .ply/.obj/.off, 'z' or 'y'; a .glb is always +Y up).");
  m.def(
      "check",
      [](const Mesh& mesh, const Skeleton* skeleton, const FieldHandle* field, std::size_t samples,
         std::uint64_t seed, int threads) {
        Context ctx = make_context(threads);
        nlohmann::json j;
        interruptible(ctx, [&] {
          j = cli::check_json(mesh.mesh, skeleton, ctx);
          if (field) {
            DeviationOptions o;
            o.samples = samples;
            o.seed = seed;
            const Skeleton* s = field->meshed ? &*field->meshed : nullptr;
            const DeviationReport d = measure_deviation(mesh.mesh, *field->field, s, o, &ctx);
            cli::put_deviation_summary(j, "deviation_", d.samples);
            cli::put_deviation_summary(j, "vertex_deviation_", d.vertices);
          }
        });
        return to_python(j);
      },
      py::arg("mesh"), py::kw_only(), py::arg("skeleton") = py::none(),
      py::arg("field") = py::none(), py::arg("samples") = DeviationOptions{}.samples,
      py::arg("seed") = DeviationOptions{}.seed, py::arg("threads") = 0,
      "The figures of `ramiform check --json`: watertight, oriented, manifold, components, "
      "euler, angles; with skeleton= the share of its nodes inside (skeleton_nodes_inside); with "
      "field= the deviation from the field's surface relative to the local radius.");
  m.def(
      "read_points",
      [](const std::string& path) {
        PointSet p;
        {
          py::gil_scoped_release release;
          p = read_points(path);
        }
        py::array_t<double> pos({static_cast<py::ssize_t>(p.positions.size()), py::ssize_t{3}});
        std::memcpy(pos.mutable_data(), p.positions.data(), p.positions.size() * sizeof(Vec3));
        if (p.normals.empty()) return py::make_tuple(pos, py::none());
        py::array_t<double> nor({static_cast<py::ssize_t>(p.normals.size()), py::ssize_t{3}});
        std::memcpy(nor.mutable_data(), p.normals.data(), p.normals.size() * sizeof(Vec3));
        return py::make_tuple(pos, nor);
      },
      py::arg("path"),
      "Reads points (\"x y z [nx ny nz]\" text or PLY): (positions, normals or None).");
}

void bind_field(py::module_& m) {
  const SkeletonFieldOptions fo;
  py::class_<FieldHandle>(m, "Field", "An implicit surface f(p) = iso; inside where f > iso.")
      .def_property_readonly("iso", [](const FieldHandle& f) { return f.field->iso(); })
      .def_property_readonly(
          "bounds",
          [](const FieldHandle& f) {
            const Aabb b = f.field->bounds();
            return py::make_tuple(std::vector<double>{b.min().x(), b.min().y(), b.min().z()},
                                  std::vector<double>{b.max().x(), b.max().y(), b.max().z()});
          },
          "(min, max) corners of a box holding the whole surface")
      .def_property_readonly(
          "skeleton",
          [](const FieldHandle& f) -> py::object {
            if (!f.meshed) return py::none();
            return py::cast(*f.meshed);
          },
          "the skeleton a polygonizer follows (split by fit_radii), or None")
      .def_property_readonly(
          "fit", [](const FieldHandle& f) { return to_python(f.fit); },
          "the radius fit's figures, or None")
      .def_property_readonly(
          "charges",
          [](py::object self) -> py::object {
            const auto& f = self.cast<const FieldHandle&>();
            if (!f.equipotential) return py::none();
            const ChargeSet& c = f.equipotential->charges;
            py::dict d;
            d["positions"] = rows(c.positions.empty() ? nullptr : c.positions[0].data(),
                                  c.positions.size(), 3, self);
            d["values"] = view(c.values.data(), {static_cast<py::ssize_t>(c.values.size())},
                               {sizeof(double)}, self);
            d["edge_values"] =
                view(c.edge_values.data(), {static_cast<py::ssize_t>(c.edge_values.size())},
                     {sizeof(double)}, self);
            d["alpha"] = c.alpha;
            return d;
          },
          "surface='equipotential': {'positions': (K, 3), 'values': (K,), 'edge_values': (M,), "
          "'alpha'} (read-only views), else None; the iso value `iso` is lambda")
      .def_property_readonly("evaluations",
                             [](const FieldHandle& f) { return f.field->evaluations(); })
      .def(
          "evaluate",
          [](const FieldHandle& f, const Doubles& points, bool gradients,
             int threads) -> py::object {
            const std::vector<Vec3> p = to_points(points, "points");
            Context ctx = make_context(threads);
            py::array_t<double> values(static_cast<py::ssize_t>(p.size()));
            py::array_t<double> grads;
            std::span<Vec3> g;
            if (gradients) {
              grads = py::array_t<double>({static_cast<py::ssize_t>(p.size()), py::ssize_t{3}});
              g = std::span<Vec3>(reinterpret_cast<Vec3*>(grads.mutable_data()), p.size());
            }
            std::span<double> v(values.mutable_data(), p.size());
            interruptible(ctx, [&] { f.field->evaluate(p, v, g, &ctx); });
            if (gradients) return py::make_tuple(values, grads);
            return values;
          },
          py::arg("points"), py::kw_only(), py::arg("gradients") = false, py::arg("threads") = 0,
          "values (K,) at points (K, 3); with gradients=True (values, gradients (K, 3))")
      .def("__repr__",
           [](const FieldHandle& f) { return "<ramiform.Field " + f.field->describe() + ">"; });

  const EquipotentialArgs ea;
  m.def(
      "skeleton_field",
      [](const Skeleton& s, const std::string& surface, const std::string& kernel, double iso,
         bool fit_radii, double alpha, double charge, double charge_spacing, double lambda,
         double lambda_scale, bool open_ends, int threads) {
        EquipotentialOptions eo;
        const EquipotentialOptions* equipotential = equipotential_options(
            surface, {alpha, charge, charge_spacing, lambda, lambda_scale, open_ends}, kernel, iso,
            eo);
        const SkeletonFieldOptions o =
            equipotential != nullptr ? SkeletonFieldOptions{} : field_options(surface, kernel, iso);
        Context ctx = make_context(threads);
        FieldHandle f;
        interruptible(ctx, [&] {
          cli::StageTimer timer;
          cli::SkeletonSurface surf =
              cli::build_surface(s, o, fit_radii, timer, ctx, equipotential);
          f.field = surf.field;
          f.source = s;
          f.meshed = std::move(surf.skeleton);
          f.fit = std::move(surf.fit_stats);
          f.equipotential = std::move(surf.equipotential);
        });
        return f;
      },
      py::arg("skeleton"), py::kw_only(), py::arg("surface") = "convolution",
      py::arg("kernel") = "", py::arg("iso") = fo.iso, py::arg("fit_radii") = false,
      py::arg("alpha") = ea.alpha, py::arg("charge") = ea.charge,
      py::arg("charge_spacing") = ea.charge_spacing, py::arg("lambda_") = ea.lambda,
      py::arg("lambda_scale") = ea.lambda_scale, py::arg("open_ends") = ea.open_ends,
      py::arg("threads") = 0,
      "The implicit surface of a skeleton, as `ramiform mesh` builds it: surface 'convolution' "
      "(Cauchy kernel, the default), 'distance' or 'equipotential' (point charges along the "
      "skeleton, Gruber & Wallner 2014: potential q / r^(alpha - 1), surface at lambda); kernel "
      "as --kernel ('' = the surface's default); iso 0 = the kernel's; fit_radii: split edges "
      "and fit weights (convolution) or fit one charge value per edge (equipotential) so the "
      "surface passes through the radii. Equipotential only, as the CLI's --alpha, --charge, "
      "--charge-spacing, --lambda, --lambda-scale, --open-ends: alpha (2-16), charge (0 = per "
      "edge from the radii), charge_spacing (0 = half the smaller node radius), lambda_ (0 = "
      "estimated by eq. 2), lambda_scale, open_ends (every leaf open; Skeleton.open_ends opens "
      "single leaves).");
}

// The curve and surface skeletons of Rigaudière, Gesquière & Faudot (field/anisotropic.h).
DistancePrimitiveOptions primitive_options(const std::string& kernel, double weight) {
  DistancePrimitiveOptions o;
  o.kernel = parse_kernel(kernel);
  o.weight = weight;
  return o;
}

FieldHandle handle(FieldPtr f) {
  FieldHandle h;
  h.field = std::move(f);
  return h;
}

void bind_skeletal(py::module_& m) {
  const char* deform_doc =
      " Deformations (def, def_u, def_v) as the scene language writes them: 'identity', "
      "'squared-cosine:S', 'flat:N', 'wave:A,W', 'linear:V0,V1,...', 'bezier:B0,...' "
      "(docs/skeletal.md); kernel 'wyvill' (default), 'metaball' (Murakami), 'blinn[:B]', "
      "'inverse-power[:alpha]'.";
  m.def(
      "segment_field",
      [](const std::vector<double>& a, const std::vector<double>& b, double radius,
         const std::string& def, const std::string& kernel, double weight) {
        return handle(make_anisotropic_segment_field(to_vec3(a, "a"), to_vec3(b, "b"), radius,
                                                     parse_deformation(def),
                                                     primitive_options(kernel, weight)));
      },
      py::arg("a"), py::arg("b"), py::kw_only(), py::arg("radius") = 0.3,
      py::arg("def_") = "identity", py::arg("kernel") = "wyvill", py::arg("weight") = 1.0,
      (std::string("An anisotropic segment skeleton a -> b: thickness radius / def(t) (§3.2).") +
       deform_doc)
          .c_str());
  m.def(
      "bezier_field",
      [](const Doubles& controls, double radius, const std::optional<std::vector<double>>& radii,
         const std::string& def, const std::string& tie, const std::string& kernel, double weight) {
        BezierCurve c;
        c.controls = to_points(controls, "controls");
        if (radii) c.radii = *radii;
        if (tie != "first" && tie != "last") {
          throw InvalidArgument("tie must be 'first' or 'last', got '" + tie + "'");
        }
        return handle(make_bezier_field(c, radius, parse_deformation(def),
                                        tie == "last" ? TieRule::kLast : TieRule::kFirst,
                                        primitive_options(kernel, weight)));
      },
      py::arg("controls"), py::kw_only(), py::arg("radius") = 0.25, py::arg("radii") = py::none(),
      py::arg("def_") = "identity", py::arg("tie") = "first", py::arg("kernel") = "wyvill",
      py::arg("weight") = 1.0,
      (std::string("A Bezier-curve skeleton through controls (K, 3), degree K - 1 <= 15, skinned "
                   "at radius or at radii per control point; exact distance by root isolation "
                   "(§3.3-3.5); tie 'first'/'last' picks the smallest/largest t among equally "
                   "near projections.") +
       deform_doc)
          .c_str());
  auto surface_field = [](std::shared_ptr<const ParametricSurface> surface, double radius,
                          const std::string& def_u, const std::string& def_v, double epsilon,
                          int depth, double max_error, const std::string& kernel, double weight) {
    SubdivisionOptions sub;
    sub.epsilon_degrees = epsilon;
    sub.max_depth = depth;
    sub.max_error = max_error;
    auto skeleton = std::make_shared<const SurfaceSkeleton>(std::move(surface), sub);
    return handle(make_surface_skeleton_field(skeleton, radius, parse_deformation(def_u),
                                              parse_deformation(def_v),
                                              primitive_options(kernel, weight)));
  };
  const SubdivisionOptions sub;
  m.def(
      "patch_field",
      [surface_field](const Doubles& controls, double radius, const std::string& def_u,
                      const std::string& def_v, double epsilon, int depth, double max_error,
                      const std::string& kernel, double weight) {
        const std::vector<Vec3> p = to_points(controls, "controls");
        if (p.size() != 16) {
          throw InvalidArgument("controls must be 16 points (4 rows of 4), got " +
                                std::to_string(p.size()));
        }
        BicubicPatch patch;
        std::copy(p.begin(), p.end(), patch.controls.begin());
        return surface_field(make_patch_surface(patch), radius, def_u, def_v, epsilon, depth,
                             max_error, kernel, weight);
      },
      py::arg("controls"), py::kw_only(), py::arg("radius") = 0.1, py::arg("def_u") = "identity",
      py::arg("def_v") = "identity", py::arg("epsilon") = sub.epsilon_degrees,
      py::arg("depth") = sub.max_depth, py::arg("max_error") = sub.max_error,
      py::arg("kernel") = "wyvill", py::arg("weight") = 1.0,
      (std::string(
           "A bicubic Bezier patch skeleton (controls (16, 3), b_ij at row 4 i + j) "
           "subdivided where a side's derivatives turn by more than epsilon degrees, at "
           "most depth times (§4.1), and while a sub-patch's error bound exceeds max_error (0: "
           "off), skinned at radius.") +
       deform_doc)
          .c_str());
  m.def(
      "superquadric_field",
      [surface_field](const std::vector<double>& radii, double e1, double e2,
                      const std::vector<double>& center, double radius, const std::string& def_u,
                      const std::string& def_v, double epsilon, int depth, double max_error,
                      const std::string& kernel, double weight) {
        Superquadric q;
        q.radii = to_vec3(radii, "radii");
        q.center = to_vec3(center, "center");
        q.e1 = e1;
        q.e2 = e2;
        return surface_field(make_superquadric_surface(q), radius, def_u, def_v, epsilon, depth,
                             max_error, kernel, weight);
      },
      py::kw_only(), py::arg("radii") = std::vector<double>{1, 1, 1}, py::arg("e1") = 1.0,
      py::arg("e2") = 1.0, py::arg("center") = std::vector<double>{0, 0, 0},
      py::arg("radius") = 0.1, py::arg("def_u") = "identity", py::arg("def_v") = "identity",
      py::arg("epsilon") = sub.epsilon_degrees, py::arg("depth") = sub.max_depth,
      py::arg("max_error") = sub.max_error, py::arg("kernel") = "wyvill", py::arg("weight") = 1.0,
      (std::string("Barr's superquadric ellipsoid (half-axes radii, exponents e1, e2) as a "
                   "surface skeleton: a shell of thickness 2 radius (§4.2).") +
       deform_doc)
          .c_str());
  m.def(
      "skeleton_distances",
      [](const Skeleton& s, const Doubles& points, const std::string& tie, int threads) {
        const std::vector<Vec3> p = to_points(points, "points");
        if (tie != "first" && tie != "last") {
          throw InvalidArgument("tie must be 'first' or 'last', got '" + tie + "'");
        }
        Context ctx = make_context(threads);
        std::vector<SkeletonDistance> d;
        interruptible(ctx, [&] {
          d = skeleton_distances(s, p, tie == "last" ? TieRule::kLast : TieRule::kFirst, &ctx);
        });
        const auto n = static_cast<py::ssize_t>(d.size());
        py::array_t<double> distance(n), t(n);
        py::array_t<std::int64_t> edge(n), node(n);
        for (py::ssize_t i = 0; i < n; ++i) {
          const SkeletonDistance& r = d[static_cast<std::size_t>(i)];
          distance.mutable_at(i) = r.distance;
          t.mutable_at(i) = r.t;
          edge.mutable_at(i) = r.is_edge ? static_cast<std::int64_t>(r.index) : -1;
          node.mutable_at(i) = r.is_edge ? -1 : static_cast<std::int64_t>(r.index);
        }
        py::dict out;
        out["distance"] = distance;
        out["edge"] = edge;
        out["node"] = node;
        out["t"] = t;
        return out;
      },
      py::arg("skeleton"), py::arg("points"), py::kw_only(), py::arg("tie") = "first",
      py::arg("threads") = 0,
      "The nearest skeleton element of each point (K, 3), as `ramiform eval --distance`: "
      "{'distance', 'edge' (-1 for a node), 'node' (-1 for an edge), 't'} arrays. Curved edges "
      "(read_skeleton(path, keep_curves=True)) exactly, by root isolation.");
}

void bind_polygonizers(py::module_& m) {
  const ToleranceOptions tol;
  const TetrahedralOptions tets;
  const MarchingCubesOptions mc;
  m.def(
      "polygonize_tets",
      [](const FieldHandle& f, const Skeleton* skeleton, std::optional<double> tolerance,
         int levels, double section_scale, bool cleanup, std::size_t max_triangles,
         std::size_t deviation_samples, bool normals, int threads) {
        MeshJobOptions o;
        o.method = "tets";
        o.tets.levels = levels;
        o.tets.section_scale = section_scale;
        o.tets.cleanup = cleanup;
        o.to_tolerance = tolerance.has_value();
        if (tolerance) o.tolerance.tolerance = *tolerance;
        o.tolerance.max_triangles = max_triangles;
        o.tolerance.samples = deviation_samples;
        const Skeleton& s = meshed_skeleton(f, skeleton, "polygonize_tets");
        return polygonize(f, &s, o, normals, threads);
      },
      py::arg("field"), py::arg("skeleton") = py::none(), py::kw_only(),
      py::arg("tolerance") = tol.tolerance, py::arg("levels") = tol.tets.levels,
      py::arg("section_scale") = tets.section_scale, py::arg("cleanup") = tets.cleanup,
      py::arg("max_triangles") = tol.max_triangles, py::arg("deviation_samples") = tol.samples,
      py::arg("normals") = true, py::arg("threads") = 0,
      "The skeleton-bounded tetrahedral polygonizer (Zhu, Guo & Jin 2013): watertight, every "
      "branch kept. With a tolerance (deviation p99 relative to the local radius) the base mesh "
      "at `levels` is refined until it holds (`ramiform mesh --tolerance`); tolerance=None "
      "meshes at exactly `levels`, unrefined (`ramiform mesh --levels`). The skeleton defaults "
      "to the field's. normals: the field's exact outward normals.");
  m.def(
      "marching_cubes",
      [](const FieldHandle& f, std::optional<double> cell, int resolution, bool normals,
         int threads) {
        MeshJobOptions o;
        o.method = "mc";
        if (cell) {
          if (!(*cell > 0) || !std::isfinite(*cell)) throw InvalidArgument("cell must be > 0");
          o.mc.cell_size = *cell;
        }
        o.mc.resolution = resolution;
        return polygonize(f, nullptr, o, normals, threads);
      },
      py::arg("field"), py::kw_only(), py::arg("cell") = py::none(),
      py::arg("resolution") = mc.resolution, py::arg("normals") = true, py::arg("threads") = 0,
      "Marching cubes over the field's bounds (pruned by its bound): a cell edge length, or "
      "`resolution` cells along the longest side.");
  const ParticleMeshOptions pm;
  const EquipotentialArgs ea;
  m.def(
      "mesh_skeleton",
      [](const Skeleton& s, std::optional<std::string> out, const std::string& method,
         std::optional<double> tolerance, std::optional<int> levels, double section_scale,
         bool fit_radii, std::optional<std::string> surface, const std::string& kernel, double iso,
         double alpha, double charge, double charge_spacing, double lambda, double lambda_scale,
         bool open_ends, int n_circ, int n_sphere, double placement_radius, double delta,
         int max_iterations, int relax, const std::string& up, bool normals, std::optional<bool> uv,
         int threads) {
        MeshJobOptions o;
        o.method = method;
        if (method != "tets" && method != "mc" && method != "particles") {
          throw InvalidArgument("method must be 'tets', 'mc' or 'particles', got '" + method + "'");
        }
        ParticleMeshOptions& p = o.particles;
        const std::pair<const char*, bool> particle_set[] = {
            {"n_circ", n_circ != p.n_circ},
            {"n_sphere", n_sphere != p.n_sphere},
            {"placement_radius", placement_radius != p.placement_radius},
            {"delta", delta != p.delta},
            {"max_iterations", max_iterations != p.max_iterations},
            {"relax", relax != p.relax}};
        if (method != "particles") {
          for (const auto& [name, given] : particle_set) {
            if (given) {
              throw InvalidArgument(std::string(name) + " applies to method='particles' only");
            }
          }
        } else if (tolerance || levels || section_scale != o.tets.section_scale) {
          throw InvalidArgument("method='particles' takes no tolerance, levels or section_scale");
        }
        p.n_circ = n_circ;
        p.n_sphere = n_sphere;
        p.placement_radius = placement_radius;
        p.delta = delta;
        p.max_iterations = max_iterations;
        p.relax = relax;
        o.to_tolerance = tolerance.has_value() || !levels.has_value();
        if (tolerance) o.tolerance.tolerance = *tolerance;
        o.tets.levels = levels.value_or(o.tolerance.tets.levels);
        o.tets.section_scale = section_scale;
        o.fit_radii = fit_radii;
        o.write.up = up_axis(up);
        o.write.normals = normals;
        if (uv) o.uv = *uv ? 1 : 0;
        // The particle mesher's surface is the equipotential one unless another is asked for
        // (as `ramiform mesh --method particles`).
        const std::string kind =
            surface.value_or(method == "particles" ? "equipotential" : "convolution");
        EquipotentialOptions eo;
        const EquipotentialOptions* equipotential = equipotential_options(
            kind, {alpha, charge, charge_spacing, lambda, lambda_scale, open_ends}, kernel, iso,
            eo);
        const SkeletonFieldOptions fo =
            equipotential != nullptr ? SkeletonFieldOptions{} : field_options(kind, kernel, iso);
        const std::string path = out.value_or("");
        if (!path.empty()) cli::check_output_path(path, cli::kMeshFormats);
        Context ctx = make_context(threads);
        Mesh result;
        interruptible(ctx, [&] {
          cli::StageTimer timer;
          MeshJobResult r = cli::mesh_skeleton(s, fo, o, path, timer, ctx, equipotential);
          result.mesh = std::move(r.mesh);
          result.stats = std::move(r.stats);
        });
        if (method == "particles") {
          const auto particles = result.stats.value("particles", std::size_t{0});
          const auto converged = result.stats.value("converged", std::size_t{0});
          if (converged < particles) {
            const std::string message =
                "mesh_skeleton: " + std::to_string(particles - converged) + " of " +
                std::to_string(particles) + " particles did not reach the surface within delta " +
                format_number(delta) + " after " +
                std::to_string(result.stats.value("iterations", 0)) +
                " iterations (stats['unconverged'] lists them); raise max_iterations";
            if (PyErr_WarnEx(PyExc_RuntimeWarning, message.c_str(), 1) != 0) {
              throw py::error_already_set();
            }
          }
        }
        return result;
      },
      py::arg("skeleton"), py::arg("out") = py::none(), py::kw_only(), py::arg("method") = "tets",
      py::arg("tolerance") = py::none(), py::arg("levels") = py::none(),
      py::arg("section_scale") = tets.section_scale, py::arg("fit_radii") = false,
      py::arg("surface") = py::none(), py::arg("kernel") = "", py::arg("iso") = 0.0,
      py::arg("alpha") = ea.alpha, py::arg("charge") = ea.charge,
      py::arg("charge_spacing") = ea.charge_spacing, py::arg("lambda_") = ea.lambda,
      py::arg("lambda_scale") = ea.lambda_scale, py::arg("open_ends") = ea.open_ends,
      py::arg("n_circ") = pm.n_circ, py::arg("n_sphere") = pm.n_sphere,
      py::arg("placement_radius") = pm.placement_radius, py::arg("delta") = pm.delta,
      py::arg("max_iterations") = pm.max_iterations, py::arg("relax") = pm.relax,
      py::arg("up") = "z", py::arg("normals") = true, py::arg("uv") = py::none(),
      py::arg("threads") = 0,
      "`ramiform mesh` in one call: field, polygonizer, normals, UVs (uv=None: by the output's "
      "format), SWC labels, checks; writes `out` when given (byte-identical to the CLI with the "
      "same options) and returns the mesh with the --stats figures in `stats`. tolerance and "
      "levels as the CLI's --tolerance and --levels (levels alone: the uniform mesher). "
      "method='particles' is `--method particles` (Gruber & Wallner 2014) with n_circ, "
      "n_sphere, placement_radius (0 = per edge its mean node radius), delta, max_iterations "
      "and relax as --n-circ ... --relax; its stats add particles, converged, unconverged, "
      "iterations, open_loops and radius_error_*, and a RuntimeWarning says when a particle did "
      "not converge (the CLI exits 3). surface None is 'convolution', or 'equipotential' with "
      "method='particles'; the equipotential keywords (alpha, charge, charge_spacing, lambda_, "
      "lambda_scale, open_ends) are skeleton_field's, and its stats add charges, lambda and "
      "alpha.");
}

/// `ramiform mesh WORDS...` in this process (ramiform.mesh_file builds the words from keywords):
/// parsed by the CLI's own parser, so options, defaults, checks and files are the CLI's. An
/// unknown option raises TypeError, a bad value ValueError (both "mesh_file(): ..."); each
/// warning the command prints becomes a RuntimeWarning. Returns the --stats figures.
py::object mesh_command(const std::vector<std::string>& words) {
  std::ostringstream out, err;
  nlohmann::json stats;
  std::string parse_error;
  bool unknown_option = false;
  {
    py::gil_scoped_release release;
    try {
      stats = cli::run_mesh_command(words, out, err);
    } catch (const CLI::ExtrasError& e) {
      parse_error = e.what();
      unknown_option = true;
    } catch (const CLI::ParseError& e) {
      parse_error = e.what();
    }
  }
  if (!parse_error.empty()) {
    const std::string message = "mesh_file(): " + parse_error;
    if (unknown_option) throw py::type_error(message);
    throw py::value_error(message);
  }
  std::istringstream lines(err.str());
  for (std::string line; std::getline(lines, line);) {
    const std::string prefix = "ramiform: warning: ";
    if (line.rfind(prefix, 0) == 0) line = line.substr(prefix.size());
    if (!line.empty() && PyErr_WarnEx(PyExc_RuntimeWarning, line.c_str(), 1) != 0) {
      throw py::error_already_set();
    }
  }
  return to_python(stats);
}

void bind_grow_and_script(py::module_& m) {
  m.def("_mesh_command", &mesh_command, py::arg("words"),
        "`ramiform mesh WORDS...` in this process; use ramiform.mesh_file.");
  const ColonizationOptions g;
  m.def(
      "grow",
      [](const Doubles& points, double step, double influence, double kill,
         const std::optional<Doubles>& roots, const std::vector<double>& direction,
         const std::vector<double>& tropism, int max_iterations, double tip_radius,
         double pipe_exponent, int smooth_iterations, double max_turn_deg, double prune_steps,
         int threads) {
        const std::vector<Vec3> p = to_points(points, "points");
        ColonizationOptions o;
        o.step = step;
        o.influence = influence;
        o.kill = kill;
        if (roots) o.roots = to_points(*roots, "roots");
        o.direction = to_vec3(direction, "direction");
        o.tropism = to_vec3(tropism, "tropism");
        o.max_iterations = max_iterations;
        o.tip_radius = tip_radius;
        o.pipe_exponent = pipe_exponent;
        o.smooth_iterations = smooth_iterations;
        o.max_turn_deg = max_turn_deg;
        o.prune_steps = prune_steps;
        Context ctx = make_context(threads);
        ColonizationResult r;
        interruptible(ctx, [&] { r = grow_space_colonization(p, o, &ctx); });
        if (r.skeleton.edge_count() == 0) {
          throw InvalidArgument("grow: no branch grew: " + no_branch_reason(r, p, o));
        }
        if (r.stalled) {
          PyErr_WarnEx(
              PyExc_RuntimeWarning,
              ("grow: " + std::to_string(r.points_reached) + " of " +
               std::to_string(r.points_total) + " attraction points reached: " + r.stall_reason)
                  .c_str(),
              1);
        }
        return std::move(r.skeleton);
      },
      py::arg("points"), py::kw_only(), py::arg("step") = g.step,
      py::arg("influence") = g.influence, py::arg("kill") = g.kill, py::arg("roots") = py::none(),
      py::arg("direction") = std::vector<double>{g.direction.x(), g.direction.y(), g.direction.z()},
      py::arg("tropism") = std::vector<double>{g.tropism.x(), g.tropism.y(), g.tropism.z()},
      py::arg("max_iterations") = g.max_iterations, py::arg("tip_radius") = g.tip_radius,
      py::arg("pipe_exponent") = g.pipe_exponent,
      py::arg("smooth_iterations") = g.smooth_iterations, py::arg("max_turn_deg") = g.max_turn_deg,
      py::arg("prune_steps") = g.prune_steps, py::arg("threads") = 0,
      "Space colonization (Runions et al. 2007) towards attraction points (K, 3) from roots "
      "(R, 3; default the origin), with pipe-model radii; a RuntimeWarning when some points "
      "were never reached.");
  m.def(
      "run_script",
      [](const std::string& text, const std::string& out, const std::string& input_dir,
         const std::map<std::string, std::string>& params, std::uint64_t seed, bool allow_any_path,
         int threads, bool draft) {
        ScriptOptions o;
        o.draft = draft;
        o.out_dir = out;
        o.input_dir = input_dir;
        o.params = params;
        o.seed = seed;
        o.allow_any_path = allow_any_path;
        Context ctx = make_context(threads);
        std::vector<CommandResult> results;
        std::vector<std::string> written;
        interruptible(ctx, [&] {
          ScriptSession session(o, &ctx);
          try {
            results = session.run_text(text, "<script>");
            written = session.commit();
          } catch (...) {
            session.discard();
            throw;
          }
        });
        std::vector<std::string> reports;
        for (const CommandResult& r : results) {
          if (r.is_report) reports.push_back(r.message);
        }
        py::dict d;
        d["outputs"] = written;
        d["reports"] = reports;
        return d;
      },
      py::arg("text"), py::kw_only(), py::arg("out") = ScriptOptions{}.out_dir,
      py::arg("input_dir") = "", py::arg("params") = std::map<std::string, std::string>{},
      py::arg("seed") = ScriptOptions{}.seed, py::arg("allow_any_path") = false,
      py::arg("threads") = 0, py::arg("draft") = false,
      "Runs a scene-language script (docs/language.md) as `ramiform run` does: outputs under "
      "`out` (written only when the whole script succeeds), params as --set, draft=True as "
      "`--draft` (coarse meshes, no drawings). Returns "
      "{'outputs': paths written, 'reports': the lines `ramiform run` prints}.");
}

}  // namespace
}  // namespace ramiform::python

PYBIND11_MODULE(_ramiform, m) {
  using namespace ramiform::python;
  m.doc() = "ramiform: skeleton-based implicit surfaces, watertight tree and neuron meshes";
  translate_errors();
  bind_skeleton(m);
  bind_mesh(m);
  bind_field(m);
  bind_skeletal(m);
  bind_polygonizers(m);
  bind_grow_and_script(m);
  bind_points(m);
}
