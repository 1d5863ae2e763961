// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// ramiform_bench_openvdb SKELETON VOXEL [HALF_WIDTH=3] [--out MESH] [--tets LEVELS]
//                        [--section-scale S]
//
// The OpenVDB pipeline people use instead of ramiform, measured and checked the way we check our
// own meshes: the union of the skeleton's round cones (each edge the convex hull of its two node
// spheres, radius r_a to r_b; an isolated node is its sphere) as a narrow-band level set of
// voxel size VOXEL (model units) and half width HALF_WIDTH (voxels), then
// openvdb::tools::volumeToMesh at iso 0 with no adaptivity (quads split into two triangles).
// Each stage is timed with std::chrono, best of three runs. The mesh of the last run is
// converted to a ramiform::TriMesh and checked with ramiform::check_mesh and the winding-number
// inside test of the skeleton nodes (what `ramiform check --skeleton --json` reports). Prints
// one JSON object on stdout. With --out, the converted mesh is also written (ramiform::write_mesh:
// .ply, .obj, .off), e.g. for `ramiform check MESH --skeleton SKELETON --json`.
//
// Level set: newer OpenVDB releases have tools::createLevelSetTubeComplex
// (openvdb/tools/LevelSetTubes.h; in the 12.x and 13.x documentation), which is used when the
// header exists (that branch is untested here). OpenVDB 10.0.1 (Debian bookworm's libopenvdb-dev)
// does not have it; there, `rasterize_round_cones` below builds the same grid: in every leaf
// node (8^3 voxels) touched by a cone's bounding box grown by the band, each voxel gets the
// minimum over those cones of the exact signed distance (clamped to +-HALF_WIDTH * VOXEL),
// voxels inside the band are active, voxels deeper inside are inactive at -background, and
// leaves without a value below the background are dropped; a leaf whose centre lies deeper than
// the band plus its half diagonal inside a cone becomes an inactive interior tile, and
// tools::pruneLevelSet collapses uniform interior nodes. That is the level set
// createLevelSetTubeComplex defines (exact distance to the tapered capsules, union by minimum), so
// the mesh stage sees the same input; only the level_set seconds measure our rasterizer instead of
// OpenVDB's scanline one. The JSON field "level_set_method" says which one ran.
//
// With --tets LEVELS, ramiform's tetrahedral polygonizer (default options, convolution surface,
// as `ramiform mesh SKELETON --levels LEVELS [--section-scale S]`) runs on the skeleton instead,
// under the same protocol and with the same checks (VOXEL is then ignored; --out writes its mesh). Run each pipeline in its own process:
// "first_total" is then a cold run, which on a VM can be twice the warm "total" (first-touch
// page faults measured at 0.35 GB/s on the benchmark machine; a later run reuses the freed
// pages). Both run with the allocator settings of the `ramiform` command.
//
// OpenVDB (MPL-2.0 in 10.x, Apache-2.0 in newer releases) is linked into this benchmark only,
// never into the ramiform library.

#include <openvdb/openvdb.h>
#include <openvdb/tools/Prune.h>
#include <openvdb/tools/VolumeToMesh.h>

#if __has_include(<openvdb/tools/LevelSetTubes.h>)
#include <openvdb/tools/LevelSetTubes.h>
#define RAMIFORM_BENCH_VDB_TUBES 1
#else
#define RAMIFORM_BENCH_VDB_TUBES 0
#endif

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <malloc.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "ramiform/core/geometry.h"
#include "ramiform/field/radius_fit.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/skeleton_io.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/deviation.h"
#include "ramiform/mesh/winding.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/skeleton/skeleton.h"

namespace {

using Clock = std::chrono::steady_clock;
using FloatGrid = openvdb::FloatGrid;
using FloatTree = FloatGrid::TreeType;
using LeafT = FloatTree::LeafNodeType;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// One round cone in index space (voxel units): the convex hull of the spheres (a, ra) and
/// (b, rb). Stored with ra >= rb; a cone whose smaller sphere lies inside the larger one is that
/// larger sphere (len = 0).
struct RoundCone {
  openvdb::Vec3d a, b;    // sphere centres (index space)
  double ra = 0, rb = 0;  // radii (voxels), ra >= rb
  openvdb::Vec3d u;       // unit axis a -> b (zero for a sphere)
  double len = 0;         // |b - a|, 0 for a sphere
  double sin_t = 0;       // (ra - rb) / len: sine of the half opening angle
  double cos_t = 1;       // sqrt(1 - sin_t^2)

  RoundCone(openvdb::Vec3d pa, double r_a, openvdb::Vec3d pb, double r_b) {
    if (r_b > r_a) {
      std::swap(pa, pb);
      std::swap(r_a, r_b);
    }
    a = pa;
    b = pb;
    ra = r_a;
    rb = r_b;
    const double d = (b - a).length();
    if (d <= ra - rb) {  // one sphere contains the other (or a zero-length edge)
      b = a;
      rb = ra;
      return;
    }
    len = d;
    u = (b - a) / d;
    sin_t = (ra - rb) / d;
    cos_t = std::sqrt(std::max(0.0, 1.0 - sin_t * sin_t));
  }

  /// Exact signed distance (voxels) outside; inside, negative with the exact zero set and the
  /// exact distance near the surface. In the (axial t, radial q) half plane the boundary is the
  /// circle around a, the common tangent line (unit normal n = (sin_t, cos_t)) and the circle
  /// around b; the coordinate s = t cos_t - q sin_t along the tangent line tells which part is
  /// nearest (tangent points at s = 0 and s = len cos_t).
  [[nodiscard]] double distance(const openvdb::Vec3d& p) const {
    const openvdb::Vec3d w = p - a;
    if (len == 0) return w.length() - ra;
    const double t = w.dot(u);
    const double q = std::sqrt(std::max(0.0, w.lengthSqr() - t * t));
    const double s = t * cos_t - q * sin_t;
    if (s <= 0) return std::sqrt(t * t + q * q) - ra;
    if (s >= len * cos_t) return std::sqrt((t - len) * (t - len) + q * q) - rb;
    return t * sin_t + q * cos_t - ra;
  }

  /// Index-space box of the points within `band` voxels of the cone.
  void bounds(double band, openvdb::Vec3d& lo, openvdb::Vec3d& hi) const {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(a[k] - ra, b[k] - rb) - band;
      hi[k] = std::max(a[k] + ra, b[k] + rb) + band;
    }
  }
};

struct TubeComplex {
  std::vector<openvdb::Vec3s> vertices;  // world units
  std::vector<float> radii;              // world units, one per vertex
  std::vector<openvdb::Vec2I> segments;  // edges, plus (i, i) for an isolated node
};

TubeComplex tube_complex(const ramiform::Skeleton& skeleton) {
  TubeComplex tc;
  std::vector<char> has_edge(skeleton.nodes.size(), 0);
  for (const auto& n : skeleton.nodes) {
    tc.vertices.emplace_back(static_cast<float>(n.position.x()), static_cast<float>(n.position.y()),
                             static_cast<float>(n.position.z()));
    tc.radii.push_back(static_cast<float>(n.radius));
  }
  for (const auto& e : skeleton.edges) {
    tc.segments.emplace_back(static_cast<openvdb::Int32>(e[0]), static_cast<openvdb::Int32>(e[1]));
    has_edge[e[0]] = has_edge[e[1]] = 1;
  }
  for (std::size_t i = 0; i < has_edge.size(); ++i) {
    if (has_edge[i] == 0) {
      tc.segments.emplace_back(static_cast<openvdb::Int32>(i), static_cast<openvdb::Int32>(i));
    }
  }
  return tc;
}

/// The narrow-band level set of the union of round cones without LevelSetTubes.h (see the file
/// comment). Vertices and radii are taken in double precision from the skeleton.
FloatGrid::Ptr rasterize_round_cones(const ramiform::Skeleton& skeleton, const TubeComplex& tc,
                                     double voxel, double half_width) {
  const auto background = static_cast<float>(voxel * half_width);
  FloatGrid::Ptr grid = openvdb::createLevelSet<FloatGrid>(voxel, half_width);

  std::vector<RoundCone> cones;
  cones.reserve(tc.segments.size());
  for (const auto& s : tc.segments) {
    const auto& na = skeleton.nodes[static_cast<std::size_t>(s[0])];
    const auto& nb = skeleton.nodes[static_cast<std::size_t>(s[1])];
    const openvdb::Vec3d pa(na.position.x(), na.position.y(), na.position.z());
    const openvdb::Vec3d pb(nb.position.x(), nb.position.y(), nb.position.z());
    cones.emplace_back(pa / voxel, na.radius / voxel, pb / voxel, nb.radius / voxel);
  }

  // (leaf origin, cone) pairs for every leaf a cone's grown box touches, sorted by leaf.
  struct Pair {
    openvdb::Int32 x, y, z;
    std::uint32_t cone;
  };
  constexpr int kDim = static_cast<int>(LeafT::DIM);
  auto leaf_of = [](double voxel_index) {  // origin of the leaf holding that voxel index
    return static_cast<openvdb::Int32>(std::floor(voxel_index / kDim)) * kDim;
  };
  std::vector<Pair> pairs;
  for (std::uint32_t c = 0; c < cones.size(); ++c) {
    openvdb::Vec3d lo, hi;
    cones[c].bounds(half_width, lo, hi);
    const auto x0 = leaf_of(std::ceil(lo[0])), y0 = leaf_of(std::ceil(lo[1]));
    const auto z0 = leaf_of(std::ceil(lo[2]));
    const auto x1 = leaf_of(std::floor(hi[0])), y1 = leaf_of(std::floor(hi[1]));
    const auto z1 = leaf_of(std::floor(hi[2]));
    for (auto x = x0; x <= x1; x += kDim) {
      for (auto y = y0; y <= y1; y += kDim) {
        for (auto z = z0; z <= z1; z += kDim) pairs.push_back({x, y, z, c});
      }
    }
  }
  tbb::parallel_sort(pairs.begin(), pairs.end(), [](const Pair& p, const Pair& q) {
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return p.cone < q.cone;
  });
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (i == 0 || pairs[i].x != pairs[i - 1].x || pairs[i].y != pairs[i - 1].y ||
        pairs[i].z != pairs[i - 1].z) {
      starts.push_back(i);
    }
  }
  starts.push_back(pairs.size());

  // Per leaf: a new leaf node, or a deep-interior tile (every voxel more than the band inside
  // some cone), or nothing (every voxel at least the band outside). The distance is
  // 1-Lipschitz, so its value at the leaf centre bounds it over the leaf to +-(half diagonal).
  const std::size_t groups = starts.size() - 1;
  std::vector<LeafT*> leaves(groups, nullptr);
  std::vector<char> interior(groups, 0);
  const double leaf_radius = 0.5 * (kDim - 1) * std::sqrt(3.0);
  tbb::parallel_for(std::size_t{0}, groups, [&](std::size_t g) {
    const Pair& first = pairs[starts[g]];
    const openvdb::Vec3d centre(first.x + 0.5 * (kDim - 1), first.y + 0.5 * (kDim - 1),
                                first.z + 0.5 * (kDim - 1));
    std::vector<std::uint32_t> near;
    for (std::size_t i = starts[g]; i < starts[g + 1]; ++i) {
      const double d = cones[pairs[i].cone].distance(centre);
      if (d < -(half_width + leaf_radius)) {
        interior[g] = 1;
        return;
      }
      if (d < half_width + leaf_radius) near.push_back(pairs[i].cone);
    }
    if (near.empty()) return;
    std::array<double, LeafT::SIZE> value;
    value.fill(half_width);
    for (const std::uint32_t c : near) {
      const RoundCone& cone = cones[c];
      openvdb::Vec3d lo, hi;
      cone.bounds(half_width, lo, hi);
      const int x0 = std::max(first.x, static_cast<openvdb::Int32>(std::ceil(lo[0])));
      const int y0 = std::max(first.y, static_cast<openvdb::Int32>(std::ceil(lo[1])));
      const int z0 = std::max(first.z, static_cast<openvdb::Int32>(std::ceil(lo[2])));
      const int x1 = std::min(first.x + kDim - 1, static_cast<openvdb::Int32>(std::floor(hi[0])));
      const int y1 = std::min(first.y + kDim - 1, static_cast<openvdb::Int32>(std::floor(hi[1])));
      const int z1 = std::min(first.z + kDim - 1, static_cast<openvdb::Int32>(std::floor(hi[2])));
      for (int x = x0; x <= x1; ++x) {
        for (int y = y0; y <= y1; ++y) {
          for (int z = z0; z <= z1; ++z) {
            const auto n =
                static_cast<std::size_t>(((x - first.x) << (2 * LeafT::LOG2DIM)) +
                                         ((y - first.y) << LeafT::LOG2DIM) + (z - first.z));
            value[n] = std::min(value[n], cone.distance(openvdb::Vec3d(x, y, z)));
          }
        }
      }
    }
    bool any = false;
    for (const double v : value) any = any || v < half_width;
    if (!any) return;
    auto* leaf = new LeafT(openvdb::Coord(first.x, first.y, first.z), background, false);
    for (openvdb::Index n = 0; n < LeafT::SIZE; ++n) {
      const double v = value[n];
      if (v >= half_width) continue;  // background, inactive
      if (v <= -half_width) {
        leaf->setValueOff(n, -background);
      } else {
        leaf->setValueOn(n, static_cast<float>(v * voxel));
      }
    }
    leaves[g] = leaf;
  });
  FloatTree& tree = grid->tree();
  for (std::size_t g = 0; g < groups; ++g) {
    const Pair& first = pairs[starts[g]];
    if (interior[g] != 0) {
      tree.addTile(1, openvdb::Coord(first.x, first.y, first.z), -background, false);
    } else if (leaves[g] != nullptr) {
      tree.addLeaf(leaves[g]);
    }
  }
  openvdb::tools::pruneLevelSet(tree);
  return grid;
}

FloatGrid::Ptr level_set(const ramiform::Skeleton& skeleton, const TubeComplex& tc, double voxel,
                         double half_width) {
#if RAMIFORM_BENCH_VDB_TUBES
  (void)skeleton;
  return openvdb::tools::createLevelSetTubeComplex<FloatGrid>(
      tc.vertices, tc.segments, tc.radii, static_cast<float>(voxel), static_cast<float>(half_width),
      openvdb::tools::TUBE_VERTEX_RADII);
#else
  return rasterize_round_cones(skeleton, tc, voxel, half_width);
#endif
}

struct VdbMesh {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
};

/// OpenVDB's polygons, converted. volumeToMesh lists them clockwise seen from outside (checked:
/// without the flip the signed volume of a sphere comes out negative and every skeleton node has
/// winding number -1), so each triangle and quad is reversed; a quad (a, b, c, d) becomes the
/// triangles (d, c, b) and (d, b, a).
ramiform::TriMesh to_trimesh(const VdbMesh& m) {
  ramiform::TriMesh mesh;
  mesh.positions.reserve(m.points.size());
  for (const auto& p : m.points) mesh.positions.emplace_back(p.x(), p.y(), p.z());
  mesh.triangles.reserve(m.triangles.size() + 2 * m.quads.size());
  for (const auto& t : m.triangles) mesh.triangles.push_back({t[2], t[1], t[0]});
  for (const auto& q : m.quads) {
    mesh.triangles.push_back({q[3], q[2], q[1]});
    mesh.triangles.push_back({q[3], q[1], q[0]});
  }
  return mesh;
}

/// The surface OpenVDB meshes, as a ramiform Field for the deviation measure: f = -(signed
/// distance to the union of the round cones), iso 0 (inside f > 0), gradient that of the
/// nearest cone (central differences of its exact distance). Every cone is visited at every
/// point (the measure evaluates some 10^5-10^6 points, a few seconds).
class RoundConeField final : public ramiform::Field {
 public:
  explicit RoundConeField(const ramiform::Skeleton& skeleton) : Field(0.0) {
    std::vector<char> has_edge(skeleton.nodes.size(), 0);
    auto v = [](const ramiform::Vec3& p) { return openvdb::Vec3d(p.x(), p.y(), p.z()); };
    for (const auto& e : skeleton.edges) {
      const auto& a = skeleton.nodes[e[0]];
      const auto& b = skeleton.nodes[e[1]];
      cones_.emplace_back(v(a.position), a.radius, v(b.position), b.radius);
      has_edge[e[0]] = has_edge[e[1]] = 1;
    }
    for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
      const auto& n = skeleton.nodes[i];
      if (has_edge[i] == 0) cones_.emplace_back(v(n.position), n.radius, v(n.position), n.radius);
    }
    for (const auto& n : skeleton.nodes) {
      box_.extend(n.position - ramiform::Vec3::Constant(n.radius));
      box_.extend(n.position + ramiform::Vec3::Constant(n.radius));
    }
  }
  [[nodiscard]] ramiform::Interval bound(const ramiform::Aabb& box) const override {
    // 1-Lipschitz: the value at the centre, give or take the half diagonal.
    const double c = value_at(box.center()).first;
    const double h = 0.5 * box.diagonal().norm();
    return {c - h, c + h};
  }
  [[nodiscard]] ramiform::Aabb bounds() const override { return box_; }
  [[nodiscard]] std::string describe() const override { return "union of round cones"; }

 protected:
  void do_evaluate(std::span<const ramiform::Vec3> points, std::span<double> values,
                   std::span<ramiform::Vec3> gradients, const ramiform::Context*) const override {
    tbb::parallel_for(std::size_t{0}, points.size(), [&](std::size_t i) {
      const auto [f, cone] = value_at(points[i]);
      values[i] = f;
      if (gradients.empty()) return;
      const double h = 1e-7 * std::max(1.0, points[i].norm());
      ramiform::Vec3 g;
      for (int k = 0; k < 3; ++k) {
        ramiform::Vec3 lo = points[i], hi = points[i];
        lo[k] -= h;
        hi[k] += h;
        const auto d = [&](const ramiform::Vec3& p) {
          return cones_[cone].distance(openvdb::Vec3d(p.x(), p.y(), p.z()));
        };
        g[k] = -(d(hi) - d(lo)) / (2 * h);
      }
      gradients[i] = g;
    });
  }

 private:
  /// f and the nearest cone.
  [[nodiscard]] std::pair<double, std::size_t> value_at(const ramiform::Vec3& p) const {
    const openvdb::Vec3d q(p.x(), p.y(), p.z());
    double best = std::numeric_limits<double>::infinity();
    std::size_t arg = 0;
    for (std::size_t c = 0; c < cones_.size(); ++c) {
      const double d = cones_[c].distance(q);
      if (d < best) {
        best = d;
        arg = c;
      }
    }
    return {-best, arg};
  }

  std::vector<RoundCone> cones_;
  ramiform::Aabb box_;
};

/// The deviation of `mesh` from `field`'s surface, relative to the local radius (the measure of
/// `ramiform check --deviation`: 20000 area-weighted points, seed 1), as JSON members.
std::string deviation_json(const ramiform::TriMesh& mesh, const ramiform::Field& field,
                           const ramiform::Skeleton& skeleton) {
  ramiform::DeviationOptions o;
  o.vertices = false;
  const auto t0 = Clock::now();
  const ramiform::DeviationReport r = ramiform::measure_deviation(mesh, field, &skeleton, o);
  const ramiform::MeshReport q = ramiform::check_mesh(mesh);
  char buffer[512];
  std::snprintf(buffer, sizeof buffer,
                "\"deviation_p50\": %.6g, \"deviation_p99\": %.6g, \"deviation_max\": %.6g, "
                "\"deviation_unresolved\": %zu, \"deviation_seconds\": %.3f, "
                "\"triangles_below_10_deg\": %.6g, \"triangles_below_1_deg\": %.6g",
                r.samples.p50, r.samples.p99, r.samples.max, r.samples.unresolved,
                seconds_since(t0),
                static_cast<double>(q.triangles_below_10_deg) / std::max<std::size_t>(1, q.triangles),
                static_cast<double>(q.triangles_below_1_deg) / std::max<std::size_t>(1, q.triangles));
  return buffer;
}

int usage() {
  std::fprintf(
      stderr,
      "usage: ramiform_bench_openvdb SKELETON VOXEL [HALF_WIDTH=3] [--out MESH] [--tets N]\n"
      "                              [--tolerance T] [--section-scale S] [--fit-radii]\n"
      "  SKELETON    skeleton file (.json, .ply, or a cylinder model; see "
      "docs/formats.md)\n"
      "  VOXEL       voxel size in model units (> 0)\n"
      "  HALF_WIDTH  narrow-band half width in voxels (> 0, default 3)\n"
      "  --out MESH  also write the mesh (.ply, .obj or .off)\n"
      "  --tets N    time ramiform's tetrahedral polygonizer at N levels (0..6) instead\n"
      "  --tolerance T  with --tets: refined to deviation p99 T (mesh --tolerance; N is then\n"
      "              the base mesh's levels)\n"
      "  --section-scale S  with --tets: cross-section squares S radii wide (default 3)\n"
      "  --fit-radii  with --tets: the convolution surface with fitted radii (mesh --fit-radii;\n"
      "              the split and the fit are timed with the meshing)\n");
  return 2;
}

// The checks `ramiform check --skeleton --json` reports, as the JSON members shared by both
// pipelines' results.
std::string check_json(const ramiform::TriMesh& mesh, const ramiform::Skeleton& skeleton) {
  const ramiform::MeshReport report = ramiform::check_mesh(mesh);
  std::vector<ramiform::Vec3> nodes;
  nodes.reserve(skeleton.nodes.size());
  for (const auto& n : skeleton.nodes) nodes.push_back(n.position);
  const std::vector<char> inside = ramiform::points_inside(mesh, nodes);
  std::size_t n_inside = 0;
  for (const char f : inside) n_inside += f != 0 ? 1 : 0;
  const double nodes_inside =
      nodes.empty() ? 0.0 : static_cast<double>(n_inside) / static_cast<double>(nodes.size());
  char buffer[640];
  std::snprintf(buffer, sizeof buffer,
                "\"triangles\": %zu, \"watertight\": %s, \"oriented\": %s, \"manifold\": %s, "
                "\"components\": %zu, \"nodes_inside\": %.17g, \"vertices\": %zu, "
                "\"euler\": %lld, \"boundary_edges\": %zu, \"nonmanifold_edges\": %zu, "
                "\"nonmanifold_vertices\": %zu, \"signed_volume\": %.9g",
                report.triangles, report.watertight ? "true" : "false",
                report.oriented ? "true" : "false", report.manifold ? "true" : "false",
                report.components, nodes_inside, report.vertices, report.euler,
                report.boundary_edges, report.nonmanifold_edges, report.nonmanifold_vertices,
                ramiform::signed_volume(mesh));
  return buffer;
}

// ramiform's tetrahedral polygonizer under the same protocol: `runs` runs, each building the
// field and meshing; the stage times of the best run.
// With `fit_radii` each run also splits the edges and fits their weights, as `ramiform mesh
// --fit-radii` does (the field and the polygonizer follow the split skeleton).
std::string time_tets(const ramiform::Skeleton& skeleton, int levels, double section_scale,
                      double tolerance, bool fit_radii, int runs, const std::string& out_path) {
  ramiform::TetrahedralOptions options;
  options.levels = levels;
  options.section_scale = section_scale;
  ramiform::ToleranceOptions to;
  to.tets = options;
  to.tolerance = tolerance;
  double best = std::numeric_limits<double>::infinity(), first = 0;
  ramiform::TriMesh mesh;
  ramiform::TetrahedralStats stats, best_stats;
  ramiform::ToleranceStats tstats;
  ramiform::FieldPtr field;
  ramiform::Skeleton surface_skeleton;
  for (int run = 0; run < runs; ++run) {
    mesh = {};
    const auto t0 = Clock::now();
    std::vector<double> weights;
    if (fit_radii) {
      ramiform::SplitSkeleton split = ramiform::split_edges(skeleton);
      weights = ramiform::fit_edge_weights(split.skeleton, {}).weights;
      surface_skeleton = std::move(split.skeleton);
    } else {
      surface_skeleton = skeleton;
    }
    field = ramiform::make_skeleton_field(surface_skeleton, {}, weights);
    if (tolerance > 0) {
      mesh = ramiform::polygonize_to_tolerance(*field, surface_skeleton, to, nullptr, &tstats);
      stats = tstats.tets;
    } else {
      mesh = ramiform::polygonize_tetrahedral(*field, surface_skeleton, options, nullptr, &stats);
    }
    const double seconds = seconds_since(t0);
    if (run == 0) first = seconds;
    if (seconds < best) best_stats = stats;
    best = std::min(best, seconds);
  }
  if (!out_path.empty()) ramiform::write_mesh(mesh, out_path);
  char buffer[640];
  std::snprintf(buffer, sizeof buffer,
                "{\"pipeline\": \"ramiform tets\", \"levels\": %d, \"section_scale\": %g, "
                "\"tolerance\": %g, \"fit_radii\": %s, \"seconds\": {\"total\": %.6f, "
                "\"first_total\": %.6f, \"tetrahedralize\": %.6f, \"subdivide\": %.6f, "
                "\"extract\": %.6f, \"cleanup\": %.6f}, \"runs\": %d, ",
                levels, section_scale, tolerance, fit_radii ? "true" : "false", best, first,
                best_stats.seconds_tetrahedralize, best_stats.seconds_subdivide,
                best_stats.seconds_extract, best_stats.seconds_cleanup, runs);
  return buffer + check_json(mesh, skeleton) + ", " +
         deviation_json(mesh, *field, surface_skeleton) + "}";
}

bool parse_positive(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(out) && out > 0;
}

}  // namespace

int main(int argc, char** argv) {
  // The allocator settings of the `ramiform` command (apps/ramiform/main.cpp).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  std::vector<std::string> args;
  std::string out_path;
  int tets_levels = -1;
  double section_scale = 3.0;
  double tolerance = 0.0;
  bool fit_radii = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out") {
      if (i + 1 >= argc) return usage();
      out_path = argv[++i];
    } else if (a == "--section-scale") {
      if (i + 1 >= argc || !parse_positive(argv[++i], section_scale)) return usage();
    } else if (a == "--tolerance") {
      if (i + 1 >= argc || !parse_positive(argv[++i], tolerance)) return usage();
    } else if (a == "--fit-radii") {
      fit_radii = true;
    } else if (a == "--tets") {
      if (i + 1 >= argc) return usage();
      const std::string n = argv[++i];
      if (n.size() != 1 || n[0] < '0' || n[0] > '6') return usage();
      tets_levels = n[0] - '0';
    } else {
      args.push_back(a);
    }
  }
  if (args.size() < 2 || args.size() > 3) return usage();
  double voxel = 0, half_width = 3;
  if (!parse_positive(args[1].c_str(), voxel) ||
      (args.size() == 3 && !parse_positive(args[2].c_str(), half_width))) {
    return usage();
  }
  try {
    constexpr int kRuns = 3;
    const ramiform::Skeleton skeleton = ramiform::read_skeleton(args[0]);
    if (tets_levels >= 0) {
      std::printf("%s\n", time_tets(skeleton, tets_levels, section_scale, tolerance, fit_radii,
                                    kRuns, out_path)
                              .c_str());
      return 0;
    }
    openvdb::initialize();
    const TubeComplex tc = tube_complex(skeleton);

    double best_ls = std::numeric_limits<double>::infinity();
    double best_mesh = best_ls, best_total = best_ls, first_total = 0;
    VdbMesh vdb;
    std::size_t active_voxels = 0;
    for (int run = 0; run < kRuns; ++run) {
      vdb = VdbMesh{};
      const auto t0 = Clock::now();
      FloatGrid::Ptr grid = level_set(skeleton, tc, voxel, half_width);
      const double ls = seconds_since(t0);
      const auto t1 = Clock::now();
      openvdb::tools::volumeToMesh(*grid, vdb.points, vdb.triangles, vdb.quads, 0.0);
      const double me = seconds_since(t1);
      if (run == 0) first_total = ls + me;
      best_ls = std::min(best_ls, ls);
      best_mesh = std::min(best_mesh, me);
      best_total = std::min(best_total, ls + me);
      active_voxels = static_cast<std::size_t>(grid->activeVoxelCount());
    }

    const ramiform::TriMesh mesh = to_trimesh(vdb);
    if (!out_path.empty()) ramiform::write_mesh(mesh, out_path);
    const RoundConeField cones(skeleton);
    const std::string checks = check_json(mesh, skeleton) + ", " + deviation_json(mesh, cones, skeleton);

    std::printf(
        "{\"pipeline\": \"openvdb\", \"voxel\": %.17g, \"half_width\": %.17g, \"seconds\": "
        "{\"level_set\": %.6f, "
        "\"mesh\": %.6f, \"total\": %.6f, \"first_total\": %.6f}, %s, \"quads\": %zu, "
        "\"active_voxels\": %zu, \"skeleton_nodes\": %zu, \"skeleton_edges\": %zu, "
        "\"level_set_method\": \"%s\", \"openvdb\": \"%s\", \"runs\": %d}\n",
        voxel, half_width, best_ls, best_mesh, best_total, first_total, checks.c_str(),
        vdb.quads.size(), active_voxels, skeleton.nodes.size(), skeleton.edges.size(),
        RAMIFORM_BENCH_VDB_TUBES ? "openvdb::tools::createLevelSetTubeComplex"
                                 : "exact round-cone rasterizer (this OpenVDB has no "
                                   "LevelSetTubes.h)",
        std::string(openvdb::getLibraryVersionString()).c_str(), kRuns);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ramiform_bench_openvdb: %s\n", e.what());
    return 1;
  }
  return 0;
}
