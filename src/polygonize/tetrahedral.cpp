// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Skeleton-bounded tetrahedral polygonization after Zhu, Guo & Jin 2013, "Efficient
// polygonization of tree trunks modeled by convolution surfaces", §3–5; the header describes
// the steps, and each step lives in its own file (tetrahedral_*.h). Differences from the paper,
// and why:
// - Delaunay tetrahedralization of the bounding point set (delaunay.h) replaces TetGen (GPL); the
//   region is the set of Delaunay tetrahedra near the skeleton instead of a meshed polyhedron.
// - Holes are detected and closed (step 5) instead of hoped away with auxiliary points only.
// - Subdivision skips region tetrahedra whose field bound excludes the iso value.
// - The skeleton's own points join the bounding set, so that the lattice samples the inside
//   even at levels 0 and 1.
// - The field is evaluated once per distinct lattice point (the paper evaluates per region
//   tetrahedron), and the needle cleanup the paper lacks keeps every skeleton node inside.

#include "ramiform/polygonize/tetrahedral.h"

#include <algorithm>
#include <chrono>

#include "polygonize/tetrahedral_checks.h"
#include "polygonize/tetrahedral_cleanup.h"
#include "polygonize/tetrahedral_extract.h"
#include "polygonize/tetrahedral_lattice.h"
#include "polygonize/tetrahedral_mesh.h"
#include "polygonize/tetrahedral_points.h"
#include "polygonize/tetrahedral_region.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

// Seconds per stage, for the stats.
class StageClock {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Step 1, then the tetrahedralization of step 2; `node_points` gets the index of every node's
// own point.
detail::tets::Tetrahedralization tetrahedralize_bounding_points(
    const Field& field, const Skeleton& skeleton, const TetrahedralOptions& options, Context* ctx,
    StageClock& clock, TetrahedralStats& st, std::vector<std::uint32_t>& node_points) {
  detail::tets::BoundingPoints set = detail::tets::bounding_points(skeleton, options, ctx, &field);
  detail::tets::check_memory(set.points.size(), options, ctx);
  const std::size_t real_points = set.points.size();
  std::vector<Vec3> points = detail::tets::jitter_and_enclose(set, skeleton);
  st.polyhedron_points = real_points;
  st.gap_points = set.gap_points;
  st.crotch_points = set.crotch_points;
  st.seconds_polyhedron = clock.lap();
  check_cancel(ctx);
  detail::tets::Tetrahedralization tz =
      detail::tets::tetrahedralize(std::move(points), real_points, set.axis_pairs, ctx, st);
  st.seconds_tetrahedralize = clock.lap();
  check_cancel(ctx);
  node_points = std::move(set.node_points);
  return tz;
}

// Step 2, second half: the region.
std::vector<char> region_of(const Skeleton& skeleton, const detail::tets::Tetrahedralization& tz,
                            const std::vector<std::uint32_t>& node_points,
                            const TetrahedralOptions& options, Context* ctx, StageClock& clock,
                            TetrahedralStats& st) {
  std::vector<char> keep = detail::tets::initial_region(skeleton, tz, node_points, options, ctx);
  st.region_tets = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1));
  st.seconds_region = clock.lap();
  return keep;
}

}  // namespace

TriMesh polygonize_tetrahedral(const Field& field, const Skeleton& skeleton,
                               const TetrahedralOptions& options, Context* ctx,
                               TetrahedralStats* stats_out) {
  detail::tets::validate_options(options);
  validate(skeleton);
  detail::tets::validate_resolution(skeleton, options);
  TetrahedralStats st;
  StageClock clock;
  std::vector<std::uint32_t> node_points;
  const detail::tets::Tetrahedralization tz =
      tetrahedralize_bounding_points(field, skeleton, options, ctx, clock, st, node_points);
  std::vector<char> keep = region_of(skeleton, tz, node_points, options, ctx, clock, st);
  detail::tets::Lattice lattice(tz, options.levels);
  detail::tets::Extraction extraction =
      detail::tets::extract_surface(field, tz, keep, lattice, options, ctx, st);
  st.seconds_subdivide = clock.lap();
  TriMesh mesh =
      detail::tets::assemble_mesh(field, std::move(extraction), lattice, options, ctx, st);
  st.seconds_extract = clock.lap();
  detail::tets::clean_up(mesh, skeleton, options, ctx, st);
  st.seconds_cleanup = clock.lap();
  if (stats_out != nullptr) *stats_out = st;
  return mesh;
}

}  // namespace ramiform
