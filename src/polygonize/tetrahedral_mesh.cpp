// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/tetrahedral_mesh.h"

#include <algorithm>

#include "core/bucket_order.h"
#include "polygonize/edge_roots.h"
#include "ramiform/core/parallel.h"

namespace ramiform::detail::tets {
namespace {

// Buckets (lattice points) per parallel task of unique_crossings().
constexpr std::size_t kBucketsPerChunk = std::size_t{1} << 14;

// The distinct crossing edges: their end points and values, and per record its edge.
struct CrossingEdges {
  std::vector<Vec3> inside, outside;
  std::vector<double> f_inside, f_outside;
  std::vector<std::uint32_t> edge_of;  // per record
};

// One edge per distinct pair of global lattice ids, numbered in (inside id, outside id) order:
// the records bucketed by their inside id, each small bucket ordered by the outside id.
CrossingEdges unique_crossings(const std::vector<std::uint64_t>& records, const Lattice& lattice,
                               const Context* ctx) {
  std::vector<std::uint32_t> bucket_start;
  const std::vector<std::uint32_t> by_inside = detail::bucket_order(
      records.size(), lattice.size(),
      [&](std::size_t i) { return static_cast<std::uint32_t>(records[i] >> 32U); },
      [&](std::uint32_t x, std::uint32_t y) {
        return records[x] < records[y] || (records[x] == records[y] && x < y);
      },
      ctx, &bucket_start);
  // Chunks of buckets count their distinct edges, then write them from their offsets, in
  // parallel: the numbering is that of one pass over the buckets.
  const std::size_t buckets = bucket_start.empty() ? 0 : bucket_start.size() - 1;
  const std::size_t chunks = (buckets + kBucketsPerChunk - 1) / kBucketsPerChunk;
  auto is_new = [&](std::size_t in, auto it) {
    return it == by_inside.begin() + bucket_start[in] || records[*it] != records[*(it - 1)];
  };
  std::vector<std::size_t> edge_at(chunks, 0);
  parallel::for_chunks(
      buckets, kBucketsPerChunk,
      [&](std::size_t b, std::size_t e) {
        std::size_t count = 0;
        for (std::size_t in = b; in < e; ++in) {
          const auto last = by_inside.begin() + bucket_start[in + 1];
          for (auto it = by_inside.begin() + bucket_start[in]; it != last; ++it) {
            count += is_new(in, it) ? 1 : 0;
          }
        }
        edge_at[b / kBucketsPerChunk] = count;
      },
      ctx);
  const std::size_t edges = parallel::exclusive_scan(edge_at);
  CrossingEdges ce;
  ce.edge_of.resize(records.size());
  ce.inside.resize(edges);
  ce.outside.resize(edges);
  ce.f_inside.resize(edges);
  ce.f_outside.resize(edges);
  parallel::for_chunks(
      buckets, kBucketsPerChunk,
      [&](std::size_t b, std::size_t e) {
        std::size_t next = edge_at[b / kBucketsPerChunk];
        for (std::size_t in = b; in < e; ++in) {
          const auto last = by_inside.begin() + bucket_start[in + 1];
          for (auto it = by_inside.begin() + bucket_start[in]; it != last; ++it) {
            if (is_new(in, it)) {
              const auto out = static_cast<std::uint32_t>(records[*it] & 0xffffffffU);
              ce.inside[next] = lattice.position(static_cast<std::uint32_t>(in));
              ce.outside[next] = lattice.position(out);
              ce.f_inside[next] = lattice.value(static_cast<std::uint32_t>(in));
              ce.f_outside[next] = lattice.value(out);
              ++next;
            }
            ce.edge_of[*it] = static_cast<std::uint32_t>(next - 1);
          }
        }
      },
      ctx);
  return ce;
}

// The triangles of the polygons over the placed vertices `vertex_of` (per record).
void triangulate(const std::vector<Polygon>& polygons, const std::vector<std::uint32_t>& vertex_of,
                 TriMesh& mesh, const Context* ctx) {
  std::vector<std::size_t> tri_offset(polygons.size());
  for (std::size_t i = 0; i < polygons.size(); ++i) tri_offset[i] = polygons[i].quad ? 2 : 1;
  const std::size_t total_tris = parallel::exclusive_scan(tri_offset);
  mesh.triangles.resize(total_tris);
  parallel::for_chunks(
      polygons.size(), 8192,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const Polygon& p = polygons[i];
          std::array<std::uint32_t, 4> v{};
          for (int k = 0; k < (p.quad ? 4 : 3); ++k) v[k] = vertex_of[p.record[k]];
          const std::size_t w = tri_offset[i];
          if (!p.quad) {
            mesh.triangles[w] = {v[0], v[1], v[2]};
            continue;
          }
          const double d02 = (mesh.positions[v[0]] - mesh.positions[v[2]]).squaredNorm();
          const double d13 = (mesh.positions[v[1]] - mesh.positions[v[3]]).squaredNorm();
          if (d02 <= d13) {
            mesh.triangles[w] = {v[0], v[1], v[2]};
            mesh.triangles[w + 1] = {v[0], v[2], v[3]};
          } else {
            mesh.triangles[w] = {v[1], v[2], v[3]};
            mesh.triangles[w + 1] = {v[1], v[3], v[0]};
          }
        }
      },
      ctx);
}

}  // namespace

// The crossing edges come out of their sort ordered by position along x, which scatters every
// vertex's neighbours across the array; triangles come region tetrahedron by region
// tetrahedron, so this order keeps neighbours close in memory (the cleanup and every later
// pass over the mesh run faster).
void renumber_by_first_use(TriMesh& mesh) {
  std::vector<std::uint32_t> remap(mesh.positions.size(), UINT32_MAX);
  std::vector<Vec3> positions;
  positions.reserve(mesh.positions.size());
  for (auto& t : mesh.triangles) {
    for (auto& v : t) {
      if (remap[v] == UINT32_MAX) {
        remap[v] = static_cast<std::uint32_t>(positions.size());
        positions.push_back(mesh.positions[v]);
      }
      v = remap[v];
    }
  }
  mesh.positions = std::move(positions);
}

TriMesh assemble_mesh(const Field& field, Extraction&& ex, const Lattice& lattice,
                      const TetrahedralOptions& options, const Context* ctx, TetrahedralStats& st) {
  CrossingEdges ce = unique_crossings(ex.records, lattice, ctx);
  ex.records = {};
  TriMesh mesh;
  mesh.positions =
      detail::find_edge_roots(field, ce.inside, ce.outside, std::move(ce.f_inside),
                              std::move(ce.f_outside), options.root_steps, st.root_evaluations, ctx,
                              RootStop{tol::kRootFinding, options.root_value});
  st.crossing_edges = mesh.positions.size();
  triangulate(ex.polygons, ce.edge_of, mesh, ctx);
  renumber_by_first_use(mesh);
  return mesh;
}

}  // namespace ramiform::detail::tets
