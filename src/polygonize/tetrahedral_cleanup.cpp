// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/tetrahedral_cleanup.h"

#include <algorithm>

#include "polygonize/tetrahedral_mesh.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/cleanup.h"
#include "ramiform/mesh/winding.h"

namespace ramiform::detail::tets {
namespace {

// Whether component c (of `comps`, with its triangle box) encloses a skeleton node.
bool encloses_a_node(const TriMesh& mesh, const TriangleComponents& comps, std::uint32_t c,
                     const Skeleton& skeleton, Context* ctx) {
  TriMesh part;
  part.positions = mesh.positions;
  Aabb box;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (comps.label[t] != c) continue;
    part.triangles.push_back(mesh.triangles[t]);
    for (const std::uint32_t v : mesh.triangles[t]) box.extend(mesh.positions[v]);
  }
  std::vector<Vec3> nodes;
  for (const auto& n : skeleton.nodes) {
    if (box.contains(n.position)) nodes.push_back(n.position);
  }
  const std::vector<char> in =
      nodes.empty() ? std::vector<char>{} : points_inside(part, nodes, ctx);
  return std::find(in.begin(), in.end(), 1) != in.end();
}

// Removes the small components (each under 1 % of the triangles) that enclose no skeleton
// node: blobs where the field rises above the iso value away from the skeleton, mostly next to
// fitted joints. Returns how many were removed.
std::size_t drop_strays(TriMesh& mesh, const Skeleton& skeleton, Context* ctx) {
  const TriangleComponents comps = triangle_components(mesh);
  if (comps.count <= 1) return 0;
  std::vector<std::size_t> size(comps.count, 0);
  for (const std::uint32_t l : comps.label) ++size[l];
  std::vector<char> keep(comps.count, 1);
  std::size_t dropped = 0;
  for (std::uint32_t c = 0; c < comps.count; ++c) {
    if (100 * size[c] >= mesh.triangles.size()) continue;
    check_cancel(ctx);  // each test copies the mesh's positions
    if (!encloses_a_node(mesh, comps, c, skeleton, ctx)) {
      keep[c] = 0;
      ++dropped;
    }
  }
  if (dropped == 0) return 0;
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (keep[comps.label[t]] != 0) tris.push_back(mesh.triangles[t]);
  }
  mesh.triangles = std::move(tris);
  renumber_by_first_use(mesh);  // drops the vertices of the removed components
  return dropped;
}

// Coarse levels make thin tubes of few triangles, where a collapse could cut across the axis:
// no collapse or flip may move a skeleton node out of the mesh.
void clean_needles_keeping_nodes(TriMesh& mesh, const Skeleton& skeleton, Context* ctx,
                                 TetrahedralStats& st) {
  NeedleCleanupStats cs;
  NeedleCleanupOptions co;
  co.measure_after = false;  // the caller's mesh check measures the result
  std::vector<Vec3> nodes;
  nodes.reserve(skeleton.nodes.size());
  for (const auto& n : skeleton.nodes) nodes.push_back(n.position);
  co.keep_sides = nodes;
  clean_needles(mesh, co, &cs, ctx);
  st.collapsed_edges = cs.collapsed_edges;
  st.min_angle_before = cs.min_angle_before;
  st.median_angle_before = cs.median_angle_before;
}

}  // namespace

void clean_up(TriMesh& mesh, const Skeleton& skeleton, const TetrahedralOptions& options,
              Context* ctx, TetrahedralStats& st) {
  if (options.cleanup) clean_needles_keeping_nodes(mesh, skeleton, ctx, st);
  check_cancel(ctx);
  if (options.drop_strays) st.stray_components = drop_strays(mesh, skeleton, ctx);
}

}  // namespace ramiform::detail::tets
