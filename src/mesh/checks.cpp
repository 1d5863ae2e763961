// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/checks.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <string>

#include "core/union_find.h"
#include "mesh/mesh_indices.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {

namespace detail {

void check_triangle_indices(const TriMesh& mesh, const char* who) {
  const std::size_t n = mesh.positions.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= n) {
        throw InvalidArgument(std::string(who) + ": triangle " + std::to_string(t) +
                              " refers to vertex " + std::to_string(v) + " of " +
                              std::to_string(n));
      }
    }
  }
}

}  // namespace detail

namespace {

constexpr std::size_t kGrain = 4096;

bool has_repeated_index(const std::array<std::uint32_t, 3>& t) {
  return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
}

/// Compressed vertex -> incident triangles (each triangle listed once per distinct vertex).
struct VertexTriangles {
  std::vector<std::size_t> offset;  // size V + 1
  std::vector<std::uint32_t> tri;
};

VertexTriangles vertex_triangles(const TriMesh& mesh) {
  VertexTriangles vt;
  const std::size_t nv = mesh.positions.size();
  vt.offset.assign(nv + 1, 0);
  for (const auto& t : mesh.triangles) {
    ++vt.offset[t[0] + 1];
    if (t[1] != t[0]) ++vt.offset[t[1] + 1];
    if (t[2] != t[0] && t[2] != t[1]) ++vt.offset[t[2] + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) vt.offset[v + 1] += vt.offset[v];
  vt.tri.resize(vt.offset[nv]);
  std::vector<std::size_t> fill(vt.offset.begin(), vt.offset.end() - 1);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const auto id = static_cast<std::uint32_t>(i);
    vt.tri[fill[t[0]]++] = id;
    if (t[1] != t[0]) vt.tri[fill[t[1]]++] = id;
    if (t[2] != t[0] && t[2] != t[1]) vt.tri[fill[t[2]]++] = id;
  }
  return vt;
}

struct EdgeCounts {
  std::size_t edges = 0;
  std::size_t boundary = 0;
  std::size_t nonmanifold = 0;
  std::size_t misoriented = 0;
};

/// Counts edges from per-vertex lists of (other vertex, direction) for the edges whose smaller
/// endpoint is that vertex.
EdgeCounts count_edges(const TriMesh& mesh, const Context* ctx) {
  const std::size_t nv = mesh.positions.size();
  std::vector<std::size_t> offset(nv + 1, 0);
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k];
      const std::uint32_t b = t[(k + 1) % 3];
      if (a != b) ++offset[std::min(a, b) + 1];
    }
  }
  for (std::size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
  // entry = other vertex * 2 + direction (0: from the smaller index to the larger)
  std::vector<std::uint64_t> entry(offset[nv]);
  {
    std::vector<std::size_t> fill(offset.begin(), offset.end() - 1);
    for (const auto& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = t[k];
        const std::uint32_t b = t[(k + 1) % 3];
        if (a == b) continue;
        const std::uint32_t lo = std::min(a, b);
        const std::uint32_t hi = std::max(a, b);
        entry[fill[lo]++] = static_cast<std::uint64_t>(hi) * 2 + (a < b ? 0 : 1);
      }
    }
  }
  return parallel::reduce(
      nv, kGrain, EdgeCounts{},
      [&](std::size_t vb, std::size_t ve) {
        EdgeCounts c;
        for (std::size_t v = vb; v < ve; ++v) {
          auto* first = entry.data() + offset[v];
          auto* last = entry.data() + offset[v + 1];
          std::sort(first, last);
          for (auto* it = first; it != last;) {
            const std::uint64_t other = *it >> 1;
            std::size_t forward = 0;
            std::size_t backward = 0;
            for (; it != last && (*it >> 1) == other; ++it) ((*it & 1) == 0 ? forward : backward)++;
            const std::size_t uses = forward + backward;
            ++c.edges;
            if (uses == 1) ++c.boundary;
            if (uses > 2) ++c.nonmanifold;
            if (forward > 1 || backward > 1) ++c.misoriented;
          }
        }
        return c;
      },
      [](EdgeCounts a, const EdgeCounts& b) {
        a.edges += b.edges;
        a.boundary += b.boundary;
        a.nonmanifold += b.nonmanifold;
        a.misoriented += b.misoriented;
        return a;
      },
      ctx);
}

/// True when the link of vertex v (the opposite edges of its triangles) is connected: the
/// triangles around v form one fan or disk.
bool link_is_connected(const TriMesh& mesh, const VertexTriangles& vt, std::uint32_t v,
                       std::vector<std::uint32_t>& verts, std::vector<std::uint32_t>& parent) {
  const std::size_t b = vt.offset[v];
  const std::size_t e = vt.offset[v + 1];
  if (e - b <= 1) return true;
  verts.clear();
  for (std::size_t i = b; i < e; ++i) {
    for (const std::uint32_t w : mesh.triangles[vt.tri[i]])
      if (w != v) verts.push_back(w);
  }
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  parent.resize(verts.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  auto local = [&](std::uint32_t w) {
    return static_cast<std::uint32_t>(std::lower_bound(verts.begin(), verts.end(), w) -
                                      verts.begin());
  };
  std::size_t groups = verts.size();
  for (std::size_t i = b; i < e; ++i) {
    const auto& t = mesh.triangles[vt.tri[i]];
    std::uint32_t pair[2];
    int n = 0;
    for (const std::uint32_t w : t)
      if (w != v && n < 2) pair[n++] = w;
    if (n < 2) continue;
    const std::uint32_t x = find(local(pair[0]));
    const std::uint32_t y = find(local(pair[1]));
    if (x != y) {
      parent[std::max(x, y)] = std::min(x, y);
      --groups;
    }
  }
  return groups == 1;
}

/// The three corner angles of triangle t in radians; all 0 for a zero-area triangle.
std::array<double, 3> corner_angles(const TriMesh& mesh, const std::array<std::uint32_t, 3>& t,
                                    bool& zero_area) {
  const Vec3& a = mesh.positions[t[0]];
  const Vec3& b = mesh.positions[t[1]];
  const Vec3& c = mesh.positions[t[2]];
  const Vec3 ab = b - a;
  const Vec3 bc = c - b;
  const Vec3 ca = a - c;
  const double longest2 = std::max({ab.squaredNorm(), bc.squaredNorm(), ca.squaredNorm()});
  const double cross = ab.cross(-ca).norm();
  zero_area = has_repeated_index(t) || !(cross > tol::kCoincident * longest2);
  if (zero_area) return {0.0, 0.0, 0.0};
  auto angle = [cross](const Vec3& u, const Vec3& v) { return pm::atan2(cross, u.dot(v)); };
  return {angle(ab, -ca), angle(bc, -ab), angle(ca, -bc)};
}

}  // namespace

TriMesh welded_topology(const TriMesh& mesh) {
  detail::check_triangle_indices(mesh, "welded_topology");
  TriMesh w;
  w.positions = mesh.positions;
  w.triangles = mesh.triangles;
  if (mesh.welded.empty()) return w;
  const std::size_t n = mesh.positions.size();
  if (mesh.welded.size() != n) {
    throw InvalidArgument("welded_topology: " + std::to_string(mesh.welded.size()) +
                          " welded entries for " + std::to_string(n) + " vertices");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t o = mesh.welded[i];
    if (o > i || mesh.welded[o] != o) {
      throw InvalidArgument("welded_topology: vertex " + std::to_string(i) +
                            " is welded to " + std::to_string(o) +
                            ", which is not an original vertex before it");
    }
  }
  for (auto& t : w.triangles) {
    for (std::uint32_t& v : t) v = mesh.welded[v];
  }
  return w;
}

void weld_coincident(TriMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
  const auto less = [&](std::uint32_t a, std::uint32_t b) {
    const Vec3& p = mesh.positions[a];
    const Vec3& q = mesh.positions[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  mesh.welded.assign(n, 0);
  for (std::size_t k = 0; k < n;) {
    std::size_t e = k + 1;
    while (e < n && mesh.positions[order[e]] == mesh.positions[order[k]]) ++e;
    for (std::size_t j = k; j < e; ++j) mesh.welded[order[j]] = order[k];  // smallest index
    k = e;
  }
}

MeshReport check_mesh(const TriMesh& mesh, Context* ctx) {
  detail::check_triangle_indices(mesh, "check_mesh");
  if (!mesh.welded.empty()) {
    // A textured mesh: check the surface, through its seam copies.
    MeshReport r = check_mesh(welded_topology(mesh), ctx);
    r.vertices = mesh.positions.size();
    return r;
  }
  MeshReport r;
  r.vertices = mesh.positions.size();
  r.triangles = mesh.triangles.size();
  if (ctx != nullptr) ctx->report("check mesh", 0.0);

  const EdgeCounts ec = count_edges(mesh, ctx);
  r.edges = ec.edges;
  r.boundary_edges = ec.boundary;
  r.nonmanifold_edges = ec.nonmanifold;
  r.misoriented_edges = ec.misoriented;
  for (const auto& t : mesh.triangles)
    if (has_repeated_index(t)) ++r.degenerate_triangles;

  const VertexTriangles vt = vertex_triangles(mesh);
  std::size_t used = 0;
  for (std::size_t v = 0; v < r.vertices; ++v)
    if (vt.offset[v + 1] > vt.offset[v]) ++used;
  r.nonmanifold_vertices = parallel::reduce(
      r.vertices, kGrain, std::size_t{0},
      [&](std::size_t b, std::size_t e) {
        std::vector<std::uint32_t> verts;
        std::vector<std::uint32_t> parent;
        std::size_t bad = 0;
        for (std::size_t v = b; v < e; ++v)
          if (!link_is_connected(mesh, vt, static_cast<std::uint32_t>(v), verts, parent)) ++bad;
        return bad;
      },
      [](std::size_t a, std::size_t b) { return a + b; }, ctx);

  r.watertight = r.triangles > 0 && r.boundary_edges == 0 && r.nonmanifold_edges == 0;
  r.oriented = r.misoriented_edges == 0;
  r.manifold =
      r.nonmanifold_edges == 0 && r.nonmanifold_vertices == 0 && r.degenerate_triangles == 0;
  r.components = triangle_components(mesh).count;
  r.euler = static_cast<long long>(used) - static_cast<long long>(r.edges) +
            static_cast<long long>(r.triangles);

  if (r.triangles > 0) {
    std::vector<double> angles(3 * r.triangles);
    r.zero_area_triangles = parallel::reduce(
        r.triangles, kGrain, std::size_t{0},
        [&](std::size_t b, std::size_t e) {
          std::size_t zero = 0;
          for (std::size_t t = b; t < e; ++t) {
            bool z = false;
            const auto a = corner_angles(mesh, mesh.triangles[t], z);
            if (z) ++zero;
            for (int k = 0; k < 3; ++k) angles[3 * t + k] = a[k] * (180.0 / std::numbers::pi);
          }
          return zero;
        },
        [](std::size_t a, std::size_t b) { return a + b; }, ctx);
    r.min_angle_deg = *std::min_element(angles.begin(), angles.end());
    for (std::size_t t = 0; t < r.triangles; ++t) {
      const double m = std::min({angles[3 * t], angles[3 * t + 1], angles[3 * t + 2]});
      if (m < 10.0) ++r.triangles_below_10_deg;
      if (m < 1.0) ++r.triangles_below_1_deg;
    }
    const std::size_t n = angles.size();
    const auto mid = angles.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(angles.begin(), mid, angles.end());
    double median = *mid;
    if (n % 2 == 0) median = 0.5 * (median + *std::max_element(angles.begin(), mid));
    r.median_angle_deg = median;
  }
  if (ctx != nullptr) ctx->report("check mesh", 1.0);
  return r;
}

TriangleComponents triangle_components(const TriMesh& mesh) {
  detail::check_triangle_indices(mesh, "triangle_components");
  detail::UnionFind uf(mesh.positions.size());
  for (const auto& t : mesh.triangles) {
    uf.unite(t[0], t[1]);
    uf.unite(t[0], t[2]);
  }
  TriangleComponents out;
  out.label.resize(mesh.triangles.size());
  constexpr std::uint32_t kUnset = ~0u;
  std::vector<std::uint32_t> root_label(mesh.positions.size(), kUnset);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const std::uint32_t root = uf.find(mesh.triangles[i][0]);
    if (root_label[root] == kUnset) root_label[root] = out.count++;
    out.label[i] = root_label[root];
  }
  return out;
}

double signed_volume(const TriMesh& mesh) {
  detail::check_triangle_indices(mesh, "signed_volume");
  if (mesh.triangles.empty()) return 0.0;
  // Relative to a point near the mesh, so far-away meshes do not lose precision.
  const Vec3 o = mesh.positions[mesh.triangles[0][0]];
  double six_v = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.positions[t[0]] - o;
    const Vec3 b = mesh.positions[t[1]] - o;
    const Vec3 c = mesh.positions[t[2]] - o;
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

double surface_area(const TriMesh& mesh) {
  detail::check_triangle_indices(mesh, "surface_area");
  double twice = 0.0;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.positions[t[0]];
    twice += (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a).norm();
  }
  return 0.5 * twice;
}

}  // namespace ramiform
