// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "mesh_job.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numeric>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/field/radius_fit.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/mesh/normals.h"
#include "ramiform/mesh/winding.h"

namespace ramiform::cli {
namespace {

// Nearest skeleton node to a point by the distance to the node's sphere, |p - x_i| - r_i (a
// point on a 10 um soma belongs to the soma, not to the 1 um dendrite node 3 um away): a k-d
// tree whose boxes also keep their largest radius, so that dist(p, box) - max radius bounds
// every node below. Ties go to the smaller node index, so the answer is unique.
class NearestNode {
 public:
  explicit NearestNode(const Skeleton& s) : s_(s), order_(s.nodes.size()) {
    std::iota(order_.begin(), order_.end(), 0U);
    if (!order_.empty()) build(0, order_.size());
  }

  [[nodiscard]] std::uint32_t find(const Vec3& p) const {
    Best best;
    if (!tree_.empty()) search(0, p, best);
    return best.node;
  }

 private:
  struct Box {
    Aabb box;
    double max_radius = 0;
    std::size_t begin = 0, end = 0;
    std::size_t left = 0, right = 0;  // children (0 = leaf)
  };
  struct Best {
    double d = std::numeric_limits<double>::infinity();
    std::uint32_t node = 0;
  };
  static constexpr std::size_t kLeaf = 8;

  std::size_t build(std::size_t begin, std::size_t end) {
    const std::size_t id = tree_.size();
    tree_.emplace_back();
    Box b;
    b.begin = begin;
    b.end = end;
    for (std::size_t k = begin; k < end; ++k) {
      b.box.extend(s_.nodes[order_[k]].position);
      b.max_radius = std::max(b.max_radius, s_.nodes[order_[k]].radius);
    }
    if (end - begin > kLeaf) {
      int axis = 0;
      b.box.diagonal().maxCoeff(&axis);
      const std::size_t mid = begin + (end - begin) / 2;
      std::nth_element(order_.begin() + static_cast<std::ptrdiff_t>(begin),
                       order_.begin() + static_cast<std::ptrdiff_t>(mid),
                       order_.begin() + static_cast<std::ptrdiff_t>(end),
                       [&](std::uint32_t a, std::uint32_t c) {
                         const double pa = s_.nodes[a].position[axis];
                         const double pc = s_.nodes[c].position[axis];
                         return pa < pc || (pa == pc && a < c);
                       });
      b.left = build(begin, mid);
      b.right = build(mid, end);
    }
    tree_[id] = b;
    return id;
  }

  void search(std::size_t id, const Vec3& p, Best& best) const {
    const Box& b = tree_[id];
    const double reach = b.box.exteriorDistance(p) - b.max_radius;
    if (reach > best.d) return;
    if (b.left == 0) {
      for (std::size_t k = b.begin; k < b.end; ++k) {
        const std::uint32_t i = order_[k];
        const double d = (p - s_.nodes[i].position).norm() - s_.nodes[i].radius;
        if (d < best.d || (d == best.d && i < best.node)) best = {d, i};
      }
      return;
    }
    const double dl = tree_[b.left].box.exteriorDistance(p);
    const double dr = tree_[b.right].box.exteriorDistance(p);
    search(dl <= dr ? b.left : b.right, p, best);
    search(dl <= dr ? b.right : b.left, p, best);
  }

  const Skeleton& s_;
  std::vector<std::uint32_t> order_;
  std::vector<Box> tree_;
};

// One label per vertex: the type of the node nearest to it (NearestNode). Seam copies share
// their original's position and so its label.
std::vector<std::int32_t> nearest_node_types(const TriMesh& mesh, const Skeleton& skeleton,
                                             const NearestNode& nearest, Context& ctx) {
  std::vector<std::int32_t> labels(mesh.positions.size());
  parallel::for_each(
      mesh.positions.size(), 4096,
      [&](std::size_t v) { labels[v] = skeleton.node_types[nearest.find(mesh.positions[v])]; },
      &ctx);
  return labels;
}

void polygonize_mc(const Field& field, const MeshJobOptions& options, Context& ctx,
                   MeshJobResult& r) {
  MarchingCubesStats st;
  r.mesh = marching_cubes(field, options.mc, &ctx, &st);
  r.stats["cell_size"] = st.cell_size;
  r.stats["cells"] = st.cells_total;
  r.stats["cells_skipped_by_bound"] = st.cells_skipped;
  r.stats["crossing_edges"] = st.crossing_edges;
}

void put_tets_stats(const TetrahedralOptions& o, const TetrahedralStats& st, MeshJobResult& r) {
  r.stats["levels"] = o.levels;
  r.stats["section_scale"] = o.section_scale;
  r.stats["polyhedron_points"] = st.polyhedron_points;
  r.stats["axis_points_added"] = st.axis_points_added;
  r.stats["gap_points"] = st.gap_points;
  r.stats["crotch_points"] = st.crotch_points;
  r.stats["axis_edges_missing"] = st.axis_edges_missing;
  r.stats["delaunay_tets"] = st.delaunay_tets;
  r.stats["region_tets"] = st.region_tets;
  r.stats["grown_tets"] = st.grown_tets;
  r.stats["growth_rounds"] = st.growth_rounds;
  r.stats["holes_left"] = st.holes_left;
  r.stats["leaf_tets"] = st.leaf_tets;
  r.stats["vertices_evaluated"] = st.vertices_evaluated;
  r.stats["crossing_edges"] = st.crossing_edges;
  r.stats["skipped_tets"] = st.skipped_tets;
  r.stats["stray_components_removed"] = st.stray_components;
  if (o.cleanup) {
    r.stats["cleanup_collapsed_edges"] = st.collapsed_edges;
    r.stats["min_angle_deg_before_cleanup"] = st.min_angle_before;
    r.stats["median_angle_deg_before_cleanup"] = st.median_angle_before;
  }
  r.stats["root_evaluations"] = st.root_evaluations;
  r.stats["tets_seconds"] = {
      {"polyhedron", st.seconds_polyhedron}, {"tetrahedralize", st.seconds_tetrahedralize},
      {"region", st.seconds_region},         {"subdivide", st.seconds_subdivide},
      {"extract", st.seconds_extract},       {"cleanup", st.seconds_cleanup}};
}

void polygonize_tets(const Field& field, const Skeleton& skeleton, const MeshJobOptions& options,
                     Context& ctx, MeshJobResult& r) {
  if (!options.to_tolerance) {
    TetrahedralStats st;
    r.mesh = polygonize_tetrahedral(field, skeleton, options.tets, &ctx, &st);
    put_tets_stats(options.tets, st, r);
    return;
  }
  ToleranceOptions o = options.tolerance;
  o.tets = options.tets;
  ToleranceStats st;
  r.mesh = polygonize_to_tolerance(field, skeleton, o, &ctx, &st);
  put_tets_stats(o.tets, st.tets, r);
  const DeviationSummary& d = st.deviation.samples;
  r.stats["tolerance"] = o.tolerance;
  r.stats["tolerance_reached"] = st.reached;
  r.stats["refine"] = {{"passes", st.passes},
                       {"rounds", st.refine.rounds},
                       {"split_edges", st.refine.split_edges},
                       {"flat_splits", st.refine.flat_splits},
                       {"unprojected", st.refine.unprojected},
                       {"reverted", st.refine.reverted},
                       {"halfway", st.refine.halfway},
                       {"reprojected", st.refine.reprojected},
                       {"inherited", st.refine.inherited},
                       {"spared", st.refine.spared},
                       {"triangles_before", st.refine.triangles_before},
                       {"triangles_after", st.refine.triangles_after},
                       {"edge_tolerance", st.edge_tolerance},
                       {"budget_reached", st.refine.budget_reached}};
  r.stats["improve"] = {{"rounds", st.improve.rounds},
                        {"flips", st.improve.flips},
                        {"collapses", st.improve.collapses},
                        {"clusters", st.improve.clusters},
                        {"relaxed", st.improve.relaxed},
                        {"triangles_before", st.improve.triangles_before},
                        {"triangles_after", st.improve.triangles_after},
                        {"below_10_deg_before", st.improve.below_10_deg_before},
                        {"below_10_deg_after", st.improve.below_10_deg_after},
                        {"below_1_deg_before", st.improve.below_1_deg_before},
                        {"below_1_deg_after", st.improve.below_1_deg_after},
                        {"min_angle_deg_before", st.improve.min_angle_deg_before},
                        {"min_angle_deg_after", st.improve.min_angle_deg_after}};
  r.stats["tolerance_seconds"] = {{"tets", st.seconds_tets},
                                  {"refine", st.seconds_refine},
                                  {"improve", st.seconds_improve},
                                  {"measure", st.seconds_measure}};
  r.stats["deviation_p50"] = d.p50;
  r.stats["deviation_p99"] = d.p99;
  r.stats["deviation_max"] = d.max;
  r.stats["deviation_samples"] = d.points;
  r.stats["deviation_unresolved"] = d.unresolved;
}

}  // namespace

MeshJobResult polygonize_field(const Field& field, const Skeleton& skeleton,
                               const MeshJobOptions& options, Context& ctx) {
  MeshJobResult r;
  if (options.method == "mc") {
    polygonize_mc(field, options, ctx, r);
  } else {
    polygonize_tets(field, skeleton, options, ctx, r);
  }
  r.stats["method"] = options.method;
  return r;
}

void label_by_node_types(std::span<TriMesh> meshes, const Skeleton& skeleton, Context& ctx) {
  if (skeleton.node_types.empty()) return;
  const NearestNode nearest(skeleton);
  for (TriMesh& m : meshes) m.vertex_labels = nearest_node_types(m, skeleton, nearest, ctx);
}

nlohmann::json check_json(const TriMesh& mesh, const Skeleton* skeleton, Context& ctx,
                          MeshReport* report) {
  const MeshReport r = check_mesh(mesh, &ctx);
  if (report != nullptr) *report = r;
  nlohmann::json j;
  j["vertices"] = r.vertices;
  j["triangles"] = r.triangles;
  j["watertight"] = r.watertight;
  j["oriented"] = r.oriented;
  j["manifold"] = r.manifold;
  j["components"] = r.components;
  j["euler"] = r.euler;
  j["min_angle_deg"] = r.min_angle_deg;
  j["median_angle_deg"] = r.median_angle_deg;
  j["triangles_below_10_deg"] = share(r.triangles_below_10_deg, r.triangles);
  j["triangles_below_1_deg"] = share(r.triangles_below_1_deg, r.triangles);
  j["boundary_edges"] = r.boundary_edges;
  j["nonmanifold_edges"] = r.nonmanifold_edges;
  j["misoriented_edges"] = r.misoriented_edges;
  j["nonmanifold_vertices"] = r.nonmanifold_vertices;
  j["degenerate_triangles"] = r.degenerate_triangles;
  if (skeleton != nullptr) {
    std::vector<Vec3> points;
    points.reserve(skeleton->nodes.size());
    for (const auto& n : skeleton->nodes) points.push_back(n.position);
    const auto flags = points_inside(mesh, points, &ctx);
    const auto inside = static_cast<std::size_t>(std::count(flags.begin(), flags.end(), char{1}));
    j["skeleton_nodes"] = points.size();
    j["skeleton_nodes_inside_count"] = inside;
    j["skeleton_nodes_inside"] =
        points.empty() ? 0.0 : static_cast<double>(inside) / static_cast<double>(points.size());
  }
  return j;
}

void put_deviation_summary(nlohmann::json& j, const std::string& prefix,
                           const DeviationSummary& s) {
  j[prefix + "points"] = s.points;
  j[prefix + "unresolved"] = s.unresolved;
  j[prefix + "p50"] = s.p50;
  j[prefix + "p99"] = s.p99;
  j[prefix + "max"] = s.max;
  j[prefix + "abs_p50"] = s.abs_p50;
  j[prefix + "abs_p99"] = s.abs_p99;
  j[prefix + "abs_max"] = s.abs_max;
  j[prefix + "worst"] = {s.worst.x(), s.worst.y(), s.worst.z()};
}

SkeletonSurface build_surface(const Skeleton& skeleton, const SkeletonFieldOptions& field_options,
                              bool fit_radii, StageTimer& timer, Context& ctx,
                              const EquipotentialOptions* equipotential) {
  if (equipotential != nullptr) {
    // Gruber & Wallner 2014 §3.2-3.4; with fit_radii the charge values are fitted by NNLS so
    // that the surface passes through the requested radii (fit_charges, lambda fixed).
    if (fit_radii && equipotential->lambda_scale != EquipotentialOptions{}.lambda_scale) {
      throw InvalidArgument(
          "lambda_scale does not change the surface with fit_radii (the fitted charges scale "
          "with lambda)");
    }
    SkeletonSurface s;
    s.skeleton = skeleton;
    auto eq = std::make_shared<Equipotential>(make_equipotential(skeleton, *equipotential));
    if (fit_radii) {
      const ChargeFitResult fit =
          fit_charges(eq->charges, skeleton, eq->lambda, {}, equipotential->theta, &ctx);
      set_edge_charges(eq->charges, fit.edge_values);
      eq->field = make_equipotential_field(eq->charges, eq->lambda, equipotential->theta);
      s.fit_stats = {{"edges", skeleton.edge_count()},
                     {"samples", fit.samples},
                     {"rounds", fit.rounds},
                     {"sweeps", fit.sweeps},
                     {"residual_rms", fit.residual_rms},
                     {"residual_max", fit.residual_max},
                     {"charges_at_floor", fit.active}};
      timer.lap("fit");
    }
    s.field = eq->field;
    s.equipotential = std::move(eq);
    return s;
  }
  // With fit_radii the surface is the convolution surface of the split skeleton with fitted
  // per-piece weights (Zhu, Guo & Jin 2013, "Efficient polygonization of tree trunks modeled by
  // convolution surfaces", §2.2.2); the polygonizer follows the split skeleton too.
  SkeletonSurface s;
  std::vector<double> weights;
  if (fit_radii) {
    if (field_options.surface != SurfaceKind::kConvolution) {
      throw InvalidArgument("--fit-radii needs a convolution surface (--surface convolution)");
    }
    SplitSkeleton split = split_edges(skeleton);
    const RadiusFitResult fit = fit_edge_weights(split.skeleton, field_options, {}, &ctx);
    s.skeleton = std::move(split.skeleton);
    weights = fit.weights;
    s.fit_stats = {{"edges", s.skeleton.edge_count()},
                   {"constraint_points", fit.constraint_points},
                   {"residual_rms", fit.residual_rms},
                   {"unit_residual_rms", fit.unit_residual_rms},
                   {"converged", fit.converged},
                   {"coverage_rounds", fit.coverage_rounds},
                   {"coverage_raised", fit.coverage_raised},
                   {"covered", fit.covered}};
    timer.lap("fit");
  } else {
    s.skeleton = skeleton;
  }
  s.field = make_skeleton_field(s.skeleton, field_options, weights);
  return s;
}

void add_output_options(CLI::App& app, MeshJobOptions& options) {
  app.add_option_function<std::string>(
         "--up",
         [&options](const std::string& v) {
           options.write.up = v == "y" ? UpAxis::kY : UpAxis::kZ;
         },
         "up axis of a .ply, .obj or .off file: z (the library's coordinates, default) or y "
         "(rotated: x, z, -y); a .glb is always +Y up as glTF requires")
      ->check(CLI::IsMember({"z", "y"}));
  app.add_flag("!--no-normals", options.write.normals,
               "write no vertex normals (by default every format but .off gets the field's exact "
               "outward normals)");
  app.add_flag_function(
      "--uv,!--no-uv", [&options](std::int64_t n) { options.uv = n > 0 ? 1 : 0; },
      "bark texture coordinates along the branches (u around, v along in units of the local "
      "circumference) and tangents: on by default for .glb and .obj, off for .ply (its seam "
      "copies open the vertex indices) and .off (no UVs)");
  app.add_option_function<std::vector<double>>(
         "--uv-facing",
         [&options](const std::vector<double>& v) { options.bark.facing = Vec3(v[0], v[1], v[2]); },
         "X,Y,Z: each branch's texture seam lies on the side facing away from this direction "
         "(default 0,-1,0: hidden from a viewer on -Y)")
      ->expected(3)
      ->delimiter(',');
}

std::vector<LodLevel> lod_levels(const std::vector<double>& values, bool budgets) {
  std::vector<LodLevel> levels;
  for (const double v : values) {
    LodLevel l;
    if (budgets) {
      if (!(v >= 1 && v <= 4e9 && v == std::floor(v))) {
        throw InvalidArgument("--lod with --lod-budget: " + format_number(v) +
                              " is not a triangle count (a positive whole number)");
      }
      l.max_triangles = static_cast<std::size_t>(v);
    } else {
      l.tolerance = v;
    }
    levels.push_back(l);
  }
  return levels;
}

bool wants_uvs(const MeshJobOptions& options, const std::string& path) {
  if (options.uv >= 0) return options.uv > 0;
  const std::string ext = lower_extension(path);
  return ext == ".glb" || ext == ".obj";
}

nlohmann::json uv_stats(const BarkUvStats& st) {
  return {{"branches", st.branches},
          {"seam_edges", st.seam_edges},
          {"wrap_seam_edges", st.wrap_seam_edges},
          {"fork_seam_edges", st.fork_seam_edges},
          {"split_vertices", st.split_vertices},
          {"stretch_p50", st.stretch_p50},
          {"stretch_within_10_percent", st.within_10_percent}};
}

MeshJobResult mesh_skeleton(const Skeleton& skeleton, const SkeletonFieldOptions& field_options,
                            const MeshJobOptions& options, const std::string& out_path,
                            StageTimer& timer, Context& ctx,
                            const EquipotentialOptions* equipotential) {
  MeshJobResult r;
  SkeletonSurface surface =
      build_surface(skeleton, field_options, options.fit_radii, timer, ctx, equipotential);
  if (options.fit_radii) r.stats["fit"] = surface.fit_stats;
  if (surface.equipotential) {
    r.stats["surface"] = "equipotential";
    r.stats["charges"] = surface.equipotential->charges.positions.size();
    r.stats["lambda"] = surface.equipotential->lambda;
    r.stats["alpha"] = surface.equipotential->charges.alpha;
  }
  const Skeleton& meshed = surface.skeleton;
  const FieldPtr field = surface.field;
  timer.lap("field");
  std::vector<TriMesh> levels;
  if (!options.lods.empty()) {
    if (options.method != "tets" || !options.to_tolerance) {
      throw InvalidArgument(
          "--lod needs the tolerance mesher (--method tets without --levels alone)");
    }
    ToleranceOptions o = options.tolerance;
    o.tets = options.tets;
    std::vector<LodStats> st;
    levels = polygonize_lods(*field, meshed, o, options.lods, &ctx, &st);
    nlohmann::json lods = nlohmann::json::array();
    for (std::size_t k = 0; k < st.size(); ++k) {
      const DeviationSummary& d = st[k].mesher.deviation.samples;
      lods.push_back({{"level", k},
                      {"triangles", st[k].triangles},
                      {"tolerance", st[k].tolerance},
                      {"base_levels", st[k].levels},
                      {"attempts", st[k].attempts},
                      {"tolerance_reached", st[k].mesher.reached},
                      {"deviation_p99", d.p99},
                      {"deviation_max", d.max},
                      {"coarsened_from", st[k].coarsened_from},
                      {"collapsed", st[k].collapsed},
                      {"seconds_coarsen", st[k].seconds_coarsen}});
      r.lod_triangles.push_back(st[k].triangles);
    }
    r.stats["lods"] = lods;
    r.mesh = levels[0];
  } else if (options.method == "particles") {
    ParticleMeshStats st;
    if (surface.equipotential) {
      r.mesh = polygonize_particles(*surface.equipotential, meshed, options.particles, &ctx, &st);
    } else {
      r.mesh =
          polygonize_particles(*field, meshed, {}, meshed.open_ends, options.particles, &ctx, &st);
    }
    nlohmann::json unconverged = nlohmann::json::array();
    for (const std::uint32_t i : st.unconverged) unconverged.push_back(i);
    r.stats["particles"] = st.particles;
    r.stats["converged"] = st.converged;
    r.stats["unconverged"] = unconverged;
    r.stats["iterations"] = st.iterations;
    r.stats["open_loops"] = st.open_loops;
    r.stats["fallback_junctions"] = st.fallback_junctions;
    r.stats["inverted_triangles"] = st.inverted_triangles;
    r.stats["joined_branches"] = st.joined_branches;
    r.stats["repaired_nodes"] = st.repaired_nodes;
    r.stats["nodes_outside"] = st.nodes_outside;
    nlohmann::json outside_at = nlohmann::json::array();
    for (const std::uint32_t i : st.outside_nodes) {
      const Vec3& q = meshed.nodes[i].position;
      outside_at.push_back({q.x(), q.y(), q.z()});
    }
    r.stats["outside_nodes"] = outside_at;
    r.stats["unrelaxed"] = st.unrelaxed;
    r.stats["seconds_layout"] = st.seconds_layout;
    r.stats["seconds_move"] = st.seconds_move;
    r.stats["seconds_relax"] = st.seconds_relax;
  } else {
    MeshJobResult p = polygonize_field(*field, meshed, options, ctx);
    r.mesh = std::move(p.mesh);
    r.stats.update(p.stats);
  }
  timer.lap("polygonize");
  const std::uint64_t evals = field->evaluations();
  if (options.fit_radii || options.radius_error || options.method == "particles") {
    const RadiusErrorReport e = measure_radius_error(*field, skeleton, {}, &ctx);
    r.stats["radius_error_median"] = e.median;
    r.stats["radius_error_p90"] = e.p90;
    r.stats["radius_error_max"] = e.max;
    r.stats["radius_error_samples"] = e.samples;
    timer.lap("radius_error");
  }
  SurfaceAttributeOptions attributes;
  attributes.normals = options.write.normals;
  attributes.uvs = wants_uvs(options, out_path);
  attributes.bark = options.bark;
  if (levels.empty()) levels.push_back(std::move(r.mesh));
  for (std::size_t k = 0; k < levels.size(); ++k) {
    BarkUvStats uv;
    add_surface_attributes(levels[k], *field, skeleton, attributes, &ctx, &uv);
    if (attributes.uvs && k == 0) r.stats["uv"] = uv_stats(uv);
  }
  // The input skeleton's types (SWC), not the split one's: splitting keeps no types.
  label_by_node_types(levels, skeleton, ctx);
  timer.lap("attributes");
  r.mesh = levels[0];
  r.report = check_mesh(r.mesh, &ctx);
  if (!options.lods.empty()) {
    for (std::size_t k = 0; k < levels.size(); ++k) {
      const MeshReport lr = k == 0 ? r.report : check_mesh(levels[k], &ctx);
      nlohmann::json& l = r.stats["lods"][k];
      l["watertight"] = lr.watertight;
      l["oriented"] = lr.oriented;
      l["manifold"] = lr.manifold;
      l["components"] = lr.components;
    }
  }
  timer.lap("check");
  MeshWriteOptions write = options.write;
  write.uvs = attributes.uvs;
  if (!out_path.empty()) r.written = write_mesh_lods(levels, out_path, write);
  timer.lap("write");
  r.stats["method"] = options.method;
  r.stats["vertices"] = r.mesh.vertex_count();
  r.stats["triangles"] = r.mesh.triangle_count();
  r.stats["field_evals"] = evals;
  r.stats["watertight"] = r.report.watertight;
  r.stats["oriented"] = r.report.oriented;
  r.stats["manifold"] = r.report.manifold;
  r.stats["components"] = r.report.components;
  r.stats["skeleton_components"] = connected_components(skeleton).count;
  r.stats["min_angle_deg"] = r.report.min_angle_deg;
  r.stats["median_angle_deg"] = r.report.median_angle_deg;
  r.stats["triangles_below_10_deg"] = share(r.report.triangles_below_10_deg, r.report.triangles);
  r.stats["triangles_below_1_deg"] = share(r.report.triangles_below_1_deg, r.report.triangles);
  r.field = field;
  r.skeleton = meshed;
  return r;
}

}  // namespace ramiform::cli
