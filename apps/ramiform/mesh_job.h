// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Meshing a skeleton and writing the result: shared by `mesh` and `demo`.

#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "common.h"
#include "ramiform/core/geometry.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/mesh/bark_uv.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/polygonize/lod.h"
#include "ramiform/polygonize/marching_cubes.h"
#include "ramiform/polygonize/particles.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::cli {

/// The library's options structs hold every default and range (--help prints them from there).
struct MeshJobOptions {
  /// "tets" (skeleton-bounded tetrahedra), "mc" or "particles" (equipotential particle mesher)
  std::string method = "tets";
  ParticleMeshOptions particles;  ///< --n-circ, --n-sphere, --placement-radius, --delta, ...
  MarchingCubesOptions mc;        ///< --cell, --resolution
  TetrahedralOptions tets;        ///< --levels, --section-scale, --no-cleanup
  /// tets to a deviation tolerance (--tolerance; its `tets` are taken from `tets` above)
  ToleranceOptions tolerance;
  bool to_tolerance = true;   ///< false: plain tets at `tets.levels` (--levels alone)
  bool fit_radii = false;     ///< split edges and fit per-edge weights (convolution only)
  bool radius_error = false;  ///< measure the radius error (always on with fit_radii)
  MeshWriteOptions write;     ///< --up, --no-normals (write.uvs: see `uv`)
  /// Bark texture coordinates (--uv, --no-uv): -1 by the output's format (.glb and .obj yes,
  /// .ply and .off no: a PLY file stores them on seam copies, which open its vertex indices).
  int uv = -1;
  BarkUvOptions bark;          ///< --uv-facing
  std::vector<LodLevel> lods;  ///< --lod, --lod-budget (tets to tolerance only)
};

/// Whether `options` put bark UVs into the file `path`.
[[nodiscard]] bool wants_uvs(const MeshJobOptions& options, const std::string& path);

/// --up, --no-normals, --uv, --no-uv and --uv-facing (`mesh`).
void add_output_options(CLI::App& app, MeshJobOptions& options);

/// The --lod values as levels: tolerances, or with `budgets` triangle counts (InvalidArgument
/// for a budget that is not a positive whole number).
[[nodiscard]] std::vector<LodLevel> lod_levels(const std::vector<double>& values, bool budgets);

/// The bark UV figures as --stats shows them.
[[nodiscard]] nlohmann::json uv_stats(const BarkUvStats& st);

struct MeshJobResult {
  TriMesh mesh;                            ///< the (finest) mesh written
  std::vector<std::size_t> lod_triangles;  ///< with --lod: each level's triangle count
  std::vector<std::string> written;        ///< the files written
  MeshReport report;
  nlohmann::json stats;  ///< vertices, triangles, field_evals, checks (no seconds)
  /// The field meshed (by mesh_skeleton; polygonize_field leaves it null) and the skeleton its
  /// polygonizer followed, e.g. for measuring other points against the surface.
  FieldPtr field;
  Skeleton skeleton;
};

/// The surface of a skeleton as `mesh` builds it: the field, and the skeleton the polygonizer
/// follows (with `fit_radii`, the split skeleton whose per-piece weights were fitted).
struct SkeletonSurface {
  Skeleton skeleton;
  FieldPtr field;
  nlohmann::json fit_stats;  ///< the fit's figures (null without fit_radii)
  /// With an equipotential surface: its charges and lambda (the field is `field`).
  std::shared_ptr<const Equipotential> equipotential;
};

/// Builds the field of `skeleton`: the equipotential surface when `equipotential` is set (its
/// charge values fitted to the radii with fit_radii), else the skeleton field of
/// `field_options` (fitting radii if asked: InvalidArgument unless it is a convolution
/// surface). Laps `timer` at "fit" after a fit.
SkeletonSurface build_surface(const Skeleton& skeleton, const SkeletonFieldOptions& field_options,
                              bool fit_radii, StageTimer& timer, Context& ctx,
                              const EquipotentialOptions* equipotential = nullptr);

/// Polygonizes `field` as `mesh` does with `options` (method, tets or tolerance options, mc
/// options; not fit_radii, lods or the output options): the mesh without normals, and the
/// polygonizer's figures in `stats`.
[[nodiscard]] MeshJobResult polygonize_field(const Field& field, const Skeleton& skeleton,
                                             const MeshJobOptions& options, Context& ctx);

/// Labels every vertex of each mesh with the type of the nearest node of `skeleton` (by the
/// distance to the node's sphere; ties to the smaller index). Does nothing when the skeleton has
/// no node types.
void label_by_node_types(std::span<TriMesh> meshes, const Skeleton& skeleton, Context& ctx);

/// The figures of `check` for `mesh` (check_mesh), and with `skeleton` which of its nodes lie
/// inside (generalized winding number): skeleton_nodes, skeleton_nodes_inside_count and the
/// share skeleton_nodes_inside. `report`, when given, receives check_mesh's report.
[[nodiscard]] nlohmann::json check_json(const TriMesh& mesh, const Skeleton* skeleton,
                                        Context& ctx, MeshReport* report = nullptr);

/// The deviation figures of `check --json` under `prefix` ("deviation_" for the samples,
/// "vertex_deviation_" for the vertices): points, unresolved, p50, p99, max, abs_*, worst.
void put_deviation_summary(nlohmann::json& j, const std::string& prefix, const DeviationSummary& s);

/// Builds the field (fitting radii if asked), polygonizes (every level of `options.lods`),
/// adds normals and UVs, checks and writes `out_path` (atomically; one file per level unless a
/// .glb; nothing when `out_path` is empty). Laps `timer` at "field" (and "fit"), "polygonize",
/// "check", "write". With method "particles" the stats add particles, converged, unconverged (the
/// first indices), iterations, and the radius error is always measured.
MeshJobResult mesh_skeleton(const Skeleton& skeleton, const SkeletonFieldOptions& field_options,
                            const MeshJobOptions& options, const std::string& out_path,
                            StageTimer& timer, Context& ctx,
                            const EquipotentialOptions* equipotential = nullptr);

}  // namespace ramiform::cli
