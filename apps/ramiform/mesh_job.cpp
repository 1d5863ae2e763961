// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "mesh_job.h"

#include "ramiform/io/mesh_io.h"
#include "ramiform/polygonize/marching_cubes.h"

namespace ramiform::cli {

MeshJobResult mesh_skeleton(const Skeleton& skeleton, const SkeletonFieldOptions& field_options,
                            const MeshJobOptions& options, const std::string& out_path,
                            StageTimer& timer, Context& ctx) {
  const FieldPtr field = make_skeleton_field(skeleton, field_options);
  timer.lap("field");
  MarchingCubesOptions mc;
  mc.cell_size = options.cell_size;
  mc.resolution = options.resolution;
  MarchingCubesStats mc_stats;
  MeshJobResult r;
  r.mesh = marching_cubes(*field, mc, &ctx, &mc_stats);
  timer.lap("polygonize");
  r.report = check_mesh(r.mesh, &ctx);
  timer.lap("check");
  write_mesh(r.mesh, out_path);
  timer.lap("write");
  r.stats["method"] = "mc";
  r.stats["vertices"] = r.mesh.vertex_count();
  r.stats["triangles"] = r.mesh.triangle_count();
  r.stats["field_evals"] = field->evaluations();
  r.stats["cell_size"] = mc_stats.cell_size;
  r.stats["cells"] = mc_stats.cells_total;
  r.stats["cells_skipped_by_bound"] = mc_stats.cells_skipped;
  r.stats["crossing_edges"] = mc_stats.crossing_edges;
  r.stats["watertight"] = r.report.watertight;
  r.stats["oriented"] = r.report.oriented;
  r.stats["manifold"] = r.report.manifold;
  r.stats["components"] = r.report.components;
  r.stats["skeleton_components"] = connected_components(skeleton).count;
  r.stats["min_angle_deg"] = r.report.min_angle_deg;
  r.stats["median_angle_deg"] = r.report.median_angle_deg;
  return r;
}

}  // namespace ramiform::cli
