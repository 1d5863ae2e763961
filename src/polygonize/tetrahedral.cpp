// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Skeleton-bounded tetrahedral polygonization after Zhu, Guo & Jin 2013 (`003` §3–5); the
// header describes the steps. Differences from the paper, and why:
// - Delaunay tetrahedralization of the bounding point set (Qhull) replaces TetGen (GPL); the
//   region is the set of Delaunay tetrahedra near the skeleton instead of a meshed polyhedron.
// - Holes are detected and closed (step 3) instead of hoped away with auxiliary points only.
// - Subdivision skips tetrahedra whose field bound excludes the iso value.

#include "ramiform/polygonize/tetrahedral.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "field/bvh.h"
#include "polygonize/edge_roots.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/random.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace ramiform {
namespace {

using Clock = std::chrono::steady_clock;
using Tet = std::array<std::uint32_t, 4>;
using TetPoints = std::array<Vec3, 4>;
constexpr std::uint32_t kNone = UINT32_MAX;

double seconds_since(Clock::time_point& t) {
  const auto now = Clock::now();
  const double s = std::chrono::duration<double>(now - t).count();
  t = now;
  return s;
}

void validate_options(const TetrahedralOptions& o) {
  auto fail = [](const std::string& m) { throw InvalidArgument("TetrahedralOptions." + m); };
  if (o.levels < 0 || o.levels > 6) fail("levels must be in [0, 6], got " + std::to_string(o.levels));
  if (!(o.section_scale >= 2.0) || !std::isfinite(o.section_scale)) {
    fail("section_scale must be >= 2, got " + std::to_string(o.section_scale));
  }
  if (!(o.station_spacing > 0.0) || !std::isfinite(o.station_spacing)) {
    fail("station_spacing must be > 0, got " + std::to_string(o.station_spacing));
  }
  if (o.root_steps < 0 || o.root_steps > 64) fail("root_steps must be in [0, 64]");
  if (o.max_growth_rounds < 0) fail("max_growth_rounds must be >= 0");
}

// Two unit vectors completing d to an orthonormal frame.
void frame(const Vec3& d, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(d.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = d.cross(helper).normalized();
  e2 = d.cross(e1).normalized();
}

// ---------------------------------------------------------------------------------------------
// Step 1: the bounding point set (§3.1 and the auxiliary points of §5).
struct PointSetBuilder {
  std::vector<Vec3> points;

  void square(const Vec3& c, const Vec3& d, double half) {
    Vec3 e1, e2;
    frame(d, e1, e2);
    for (const double a : {-1.0, 1.0}) {
      for (const double b : {-1.0, 1.0}) points.push_back(c + half * (a * e1 + b * e2));
    }
  }
};

std::vector<Vec3> bounding_points(const Skeleton& s, const TetrahedralOptions& o) {
  PointSetBuilder pb;
  const std::size_t n = s.nodes.size();
  std::vector<std::vector<std::uint32_t>> adjacent(n);
  for (const auto& e : s.edges) {
    adjacent[e[0]].push_back(e[1]);
    adjacent[e[1]].push_back(e[0]);
  }
  const double half_scale = 0.5 * o.section_scale;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3& p = s.nodes[i].position;
    const double r = s.nodes[i].radius;
    const double half = half_scale * r;
    const auto& adj = adjacent[i];
    if (adj.empty()) {  // isolated node: a cube
      for (int c = 0; c < 8; ++c) {
        pb.points.push_back(p + half * Vec3((c & 1) ? 1 : -1, (c & 2) ? 1 : -1, (c & 4) ? 1 : -1));
      }
      continue;
    }
    // Section direction: incident edge directions aligned with the first one, summed.
    const Vec3 u0 = (s.nodes[adj[0]].position - p).normalized();
    Vec3 d = Vec3::Zero();
    for (const std::uint32_t j : adj) {
      const Vec3 u = (s.nodes[j].position - p).normalized();
      d += u.dot(u0) >= 0 ? u : Vec3(-u);
    }
    d = d.norm() > 1e-12 ? Vec3(d.normalized()) : u0;
    pb.square(p, d, half);
    if (adj.size() == 1) {  // tip: a second square and a cap point beyond it
      const Vec3 out = -u0;
      pb.square(p + out * half, out, half);
      pb.points.push_back(p + out * (2 * half));
    }
    if (adj.size() >= 3) {
      // §5: an auxiliary point on each side of the plane of every pair of branches, at the
      // mean length of the two edges (capped at the section size).
      for (std::size_t a = 0; a < adj.size(); ++a) {
        for (std::size_t b = a + 1; b < adj.size(); ++b) {
          const Vec3 ua = s.nodes[adj[a]].position - p;
          const Vec3 ub = s.nodes[adj[b]].position - p;
          const Vec3 nrm = ua.cross(ub);
          if (nrm.norm() <= 1e-12 * ua.norm() * ub.norm()) continue;
          const double len = std::min(0.5 * (ua.norm() + ub.norm()), 2 * half);
          pb.points.push_back(p + len * nrm.normalized());
          pb.points.push_back(p - len * nrm.normalized());
        }
      }
    }
  }
  // Intermediate stations along long edges.
  for (const auto& e : s.edges) {
    const auto& na = s.nodes[e[0]];
    const auto& nb = s.nodes[e[1]];
    const Vec3 d = nb.position - na.position;
    const double len = d.norm();
    const double r_mean = 0.5 * (na.radius + nb.radius);
    const int stations = static_cast<int>(std::ceil(len / (o.station_spacing * r_mean))) - 1;
    for (int k = 1; k <= stations; ++k) {
      const double t = static_cast<double>(k) / (stations + 1);
      pb.square(na.position + t * d, d / len, half_scale * ((1 - t) * na.radius + t * nb.radius));
    }
  }
  return pb.points;
}

// ---------------------------------------------------------------------------------------------
// Step 2: Delaunay tetrahedralization through Qhull (reentrant API).
std::vector<Tet> delaunay(const std::vector<Vec3>& points) {
  std::vector<coordT> coords(points.size() * 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    for (int k = 0; k < 3; ++k) coords[3 * i + k] = points[i][k];
  }
  char* message = nullptr;
  std::size_t message_size = 0;
  FILE* err = open_memstream(&message, &message_size);
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, err);
  char flags[] = "qhull d Qbb Qt";
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False, flags,
                                nullptr, err);
  std::vector<Tet> tets;
  if (code == 0) {
    facetT* facet = nullptr;
    vertexT* vertex = nullptr;
    vertexT** vertexp = nullptr;
    FORALLfacets {
      if (facet->upperdelaunay) continue;
      Tet t{};
      int k = 0;
      FOREACHvertex_(facet->vertices) {
        if (k < 4) t[k] = static_cast<std::uint32_t>(qh_pointid(qh, vertex->point));
        ++k;
      }
      if (k == 4) tets.push_back(t);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(err);
  std::string text = message != nullptr ? std::string(message, message_size) : std::string();
  std::free(message);
  if (code != 0) throw Failure("tetrahedralization failed (qhull code " + std::to_string(code) + "): " + text.substr(0, 400));
  // Qhull's facet order depends on its internals only (no threads); sort for a canonical order.
  for (auto& t : tets) std::sort(t.begin(), t.end());
  std::sort(tets.begin(), tets.end());
  return tets;
}

// Face adjacency: neighbor[4 * t + k] is the tetrahedron across the face opposite vertex k.
std::vector<std::uint32_t> face_neighbors(const std::vector<Tet>& tets) {
  struct Face {
    std::array<std::uint32_t, 3> v;
    std::uint32_t slot;  // 4 * tet + k
    bool operator<(const Face& o) const { return v < o.v || (v == o.v && slot < o.slot); }
  };
  std::vector<Face> faces;
  faces.reserve(tets.size() * 4);
  for (std::uint32_t t = 0; t < tets.size(); ++t) {
    for (int k = 0; k < 4; ++k) {
      Face f;
      int m = 0;
      for (int j = 0; j < 4; ++j) {
        if (j != k) f.v[m++] = tets[t][j];
      }
      std::sort(f.v.begin(), f.v.end());
      f.slot = 4 * t + static_cast<std::uint32_t>(k);
      faces.push_back(f);
    }
  }
  tbb::parallel_sort(faces.begin(), faces.end());
  std::vector<std::uint32_t> neighbor(tets.size() * 4, kNone);
  for (std::size_t i = 0; i + 1 < faces.size(); ++i) {
    if (faces[i].v == faces[i + 1].v) {
      neighbor[faces[i].slot] = faces[i + 1].slot / 4;
      neighbor[faces[i + 1].slot] = faces[i].slot / 4;
      ++i;
    }
  }
  return neighbor;
}

Aabb box_of(const Vec3& a, const Vec3& b, const Vec3& c) {
  Aabb box;
  box.extend(a);
  box.extend(b);
  box.extend(c);
  return box;
}

Aabb box_of(const TetPoints& t) {
  Aabb box = box_of(t[0], t[1], t[2]);
  box.extend(t[3]);
  return box;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b, double& t) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Step 3 (first half): tetrahedra near the skeleton, and those holding a node.
std::vector<char> initial_region(const Skeleton& s, const std::vector<Vec3>& pts,
                                 const std::vector<Tet>& tets, std::size_t real_points,
                                 const TetrahedralOptions& o, const Context* ctx) {
  const double reach = 0.5 * o.section_scale * std::sqrt(2.0) * 1.05;
  std::vector<Aabb> capsules;
  std::vector<std::array<std::uint32_t, 2>> capsule_nodes;
  for (const auto& e : s.edges) capsule_nodes.push_back(e);
  std::vector<char> has_edge(s.nodes.size(), 0);
  for (const auto& e : s.edges) has_edge[e[0]] = has_edge[e[1]] = 1;
  for (std::uint32_t i = 0; i < s.nodes.size(); ++i) {
    if (has_edge[i] == 0) capsule_nodes.push_back({i, i});
  }
  for (const auto& c : capsule_nodes) {
    const auto& a = s.nodes[c[0]];
    const auto& b = s.nodes[c[1]];
    const double grow = reach * std::max(a.radius, b.radius);
    Aabb box;
    box.extend(a.position);
    box.extend(b.position);
    box.min().array() -= grow;
    box.max().array() += grow;
    capsules.push_back(box);
  }
  const detail::BoxBvh capsule_bvh(capsules);
  std::vector<char> keep(tets.size(), 0);
  parallel::for_chunks(
      tets.size(), 4096,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t> ids;
        for (std::size_t t = begin; t < end; ++t) {
          const Tet& tet = tets[t];
          if (tet[3] >= real_points) continue;  // touches the far box (ids are sorted)
          const Vec3 c = 0.25 * (pts[tet[0]] + pts[tet[1]] + pts[tet[2]] + pts[tet[3]]);
          ids.clear();
          capsule_bvh.query(Aabb(c, c), ids);
          for (const std::uint32_t k : ids) {
            const auto& a = s.nodes[capsule_nodes[k][0]];
            const auto& b = s.nodes[capsule_nodes[k][1]];
            double u = 0;
            const double d = segment_distance(c, a.position, b.position, u);
            if (d <= reach * ((1 - u) * a.radius + u * b.radius)) {
              keep[t] = 1;
              break;
            }
          }
        }
      },
      ctx);
  // Every node must lie in a kept tetrahedron.
  std::vector<Aabb> tet_boxes(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    tet_boxes[t] = box_of(TetPoints{pts[tets[t][0]], pts[tets[t][1]], pts[tets[t][2]], pts[tets[t][3]]});
  }
  const detail::BoxBvh tet_bvh(std::move(tet_boxes));
  std::vector<std::uint32_t> ids;
  for (const auto& node : s.nodes) {
    ids.clear();
    tet_bvh.query(Aabb(node.position, node.position), ids);
    for (const std::uint32_t t : ids) {
      const Vec3 a = pts[tets[t][0]];
      Mat3 m;
      m.col(0) = pts[tets[t][1]] - a;
      m.col(1) = pts[tets[t][2]] - a;
      m.col(2) = pts[tets[t][3]] - a;
      const Vec3 l = m.colPivHouseholderQr().solve(node.position - a);
      const double eps = 1e-9;
      if (l.minCoeff() >= -eps && l.sum() <= 1 + eps) keep[t] = 1;
    }
  }
  return keep;
}

// Step 3 (second half): grow the region until no boundary face may be crossed by the surface.
void close_holes(const Field& field, const std::vector<Vec3>& pts, const std::vector<Tet>& tets,
                 const std::vector<std::uint32_t>& neighbor, std::vector<char>& keep,
                 const TetrahedralOptions& o, const Context* ctx, TetrahedralStats& st) {
  const double iso = field.iso();
  std::vector<std::uint32_t> frontier;
  for (std::uint32_t t = 0; t < tets.size(); ++t) {
    if (keep[t] != 0) frontier.push_back(t);
  }
  while (!frontier.empty()) {
    if (st.growth_rounds >= o.max_growth_rounds) {
      st.holes_left = true;
      break;
    }
    // Per frontier tetrahedron: which neighbours must join (deterministic: fixed chunks,
    // results merged in order).
    std::vector<std::vector<std::uint32_t>> add(frontier.size());
    std::vector<char> hull_hit(frontier.size(), 0);
    parallel::for_chunks(
        frontier.size(), 256,
        [&](std::size_t begin, std::size_t end) {
          for (std::size_t i = begin; i < end; ++i) {
            const std::uint32_t t = frontier[i];
            for (int k = 0; k < 4; ++k) {
              const std::uint32_t nb = neighbor[4 * t + k];
              if (nb != kNone && keep[nb] != 0) continue;
              Vec3 v[3];
              int m = 0;
              for (int j = 0; j < 4; ++j) {
                if (j != k) v[m++] = pts[tets[t][j]];
              }
              if (field.bound(box_of(v[0], v[1], v[2])).hi <= iso) continue;  // surely outside
              if (nb == kNone) {
                hull_hit[i] = 1;
              } else {
                add[i].push_back(nb);
              }
            }
          }
        },
        ctx);
    std::vector<std::uint32_t> next;
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      if (hull_hit[i] != 0) st.holes_left = true;
      for (const std::uint32_t nb : add[i]) {
        if (keep[nb] == 0) {
          keep[nb] = 1;
          next.push_back(nb);
        }
      }
    }
    st.grown_tets += next.size();
    if (!next.empty()) ++st.growth_rounds;
    frontier = std::move(next);
  }
}

// ---------------------------------------------------------------------------------------------
// Step 4: 1:8 subdivision, Figure 4: the four corner tetrahedra, then the octahedron of the six
// edge midpoints split along its shortest diagonal (m1m6, m2m5 or m3m4) into the four
// tetrahedra around it. Appends the eight children of `t` to `out`.
void split_1_to_8(const TetPoints& t, std::vector<TetPoints>& out) {
  const Vec3& v1 = t[0];
  const Vec3& v2 = t[1];
  const Vec3& v3 = t[2];
  const Vec3& v4 = t[3];
  // 0.5 * (a + b) is symmetric in a and b, so both neighbours of a face compute bit-identical
  // midpoints: the subdivision stays conforming across tetrahedra.
  const Vec3 m1 = 0.5 * (v1 + v2), m2 = 0.5 * (v1 + v3), m3 = 0.5 * (v1 + v4);
  const Vec3 m4 = 0.5 * (v2 + v3), m5 = 0.5 * (v2 + v4), m6 = 0.5 * (v3 + v4);
  out.push_back({v1, m1, m2, m3});
  out.push_back({v2, m1, m4, m5});
  out.push_back({v3, m2, m4, m6});
  out.push_back({v4, m3, m5, m6});
  const double d16 = (m1 - m6).squaredNorm(), d25 = (m2 - m5).squaredNorm(), d34 = (m3 - m4).squaredNorm();
  const Vec3* a = nullptr;
  const Vec3* b = nullptr;
  std::array<const Vec3*, 4> ring{};  // the other four midpoints, in cyclic order
  if (d16 <= d25 && d16 <= d34) {
    a = &m1, b = &m6, ring = {&m2, &m4, &m5, &m3};
  } else if (d25 <= d34) {
    a = &m2, b = &m5, ring = {&m1, &m3, &m6, &m4};
  } else {
    a = &m3, b = &m4, ring = {&m1, &m2, &m6, &m5};
  }
  for (int k = 0; k < 4; ++k) out.push_back({*a, *b, *ring[k], *ring[(k + 1) % 4]});
}

struct PointLess {
  bool operator()(const Vec3& p, const Vec3& q) const {
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    return p.z() < q.z();
  }
};

}  // namespace

TriMesh polygonize_tetrahedral(const Field& field, const Skeleton& skeleton,
                               const TetrahedralOptions& options, Context* ctx,
                               TetrahedralStats* stats_out) {
  validate_options(options);
  validate(skeleton);
  TetrahedralStats st;
  auto clock = Clock::now();

  // 1. Bounding points, jittered by a tiny deterministic amount so that Delaunay sees no
  //    cospherical sets (the squares are), plus a far box so the hull lies far outside.
  std::vector<Vec3> pts = bounding_points(skeleton, options);
  Rng rng(0x7e7a);
  const Aabb skel_box = bounding_box(skeleton);
  const double scale = skel_box.diagonal().norm();
  for (auto& p : pts) {
    p += 1e-7 * scale * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
  }
  const std::size_t real_points = pts.size();
  {
    const Vec3 c = skel_box.center();
    const Vec3 h = 0.5 * skel_box.diagonal() + Vec3::Constant(0.5 * scale);
    for (int k = 0; k < 8; ++k) {
      pts.push_back(c + Vec3((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z()));
    }
  }
  st.polyhedron_points = real_points;
  st.seconds_polyhedron = seconds_since(clock);
  check_cancel(ctx);

  // 2. Delaunay tetrahedralization and face adjacency.
  const std::vector<Tet> tets = delaunay(pts);
  const std::vector<std::uint32_t> neighbor = face_neighbors(tets);
  st.delaunay_tets = tets.size();
  st.seconds_tetrahedralize = seconds_since(clock);
  check_cancel(ctx);

  // 3. Region and hole closing.
  std::vector<char> keep = initial_region(skeleton, pts, tets, real_points, options, ctx);
  st.region_tets = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1));
  close_holes(field, pts, tets, neighbor, keep, options, ctx, st);
  std::vector<std::uint32_t> region;
  for (std::uint32_t t = 0; t < tets.size(); ++t) {
    if (keep[t] != 0) region.push_back(t);
  }
  st.seconds_region = seconds_since(clock);

  // 4 + 5a. Level by level (the paper's data-parallel kernels): the field at the unique corners
  //    of the level in one batch; a tetrahedron whose corners disagree surely holds surface, one
  //    whose corners agree is kept only if its field bound straddles the iso value; kept ones are
  //    split 1:8 for the next level. A pruned tetrahedron creates no vertex on its faces, so the
  //    leaves stay conforming wherever the surface is.
  const double iso = field.iso();
  std::vector<TetPoints> leaves;
  leaves.reserve(region.size());
  for (const std::uint32_t t : region) leaves.push_back({pts[tets[t][0]], pts[tets[t][1]], pts[tets[t][2]], pts[tets[t][3]]});
  std::vector<Vec3> verts;
  std::vector<double> values;
  std::vector<Tet> leaf_ids;
  for (int level = 0;; ++level) {
    // Unique corners (exact positions) and their values.
    verts.clear();
    verts.reserve(leaves.size() * 4);
    for (const auto& l : leaves) verts.insert(verts.end(), l.begin(), l.end());
    tbb::parallel_sort(verts.begin(), verts.end(), PointLess());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    leaf_ids.assign(leaves.size(), Tet{});
    parallel::for_chunks(
        leaves.size(), 4096,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) {
            for (int k = 0; k < 4; ++k) {
              leaf_ids[i][k] = static_cast<std::uint32_t>(
                  std::lower_bound(verts.begin(), verts.end(), leaves[i][k], PointLess()) - verts.begin());
            }
          }
        },
        ctx);
    values.assign(verts.size(), 0.0);
    field.evaluate(verts, values);
    st.vertices_evaluated += verts.size();
    // Which tetrahedra may hold surface.
    std::vector<char> hold(leaves.size(), 0);
    parallel::for_chunks(
        leaves.size(), 1024,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t i = b; i < e; ++i) {
            int in = 0;
            for (int k = 0; k < 4; ++k) in += values[leaf_ids[i][k]] > iso ? 1 : 0;
            // A leaf whose corners agree emits nothing; above the leaves, such a tetrahedron is
            // split only if its bound says the surface may pass between its corners.
            const bool mixed = in > 0 && in < 4;
            hold[i] = mixed || (level < options.levels && field.bound(box_of(leaves[i])).straddles(iso)) ? 1 : 0;
          }
        },
        ctx);
    if (level == options.levels) {
      // Keep the holding leaves; vertex ids stay valid (verts is not compacted).
      std::size_t w = 0;
      for (std::size_t i = 0; i < leaves.size(); ++i) {
        if (hold[i] != 0) {
          leaves[w] = leaves[i];
          leaf_ids[w] = leaf_ids[i];
          ++w;
        }
      }
      leaves.resize(w);
      leaf_ids.resize(w);
      break;
    }
    std::vector<TetPoints> next;
    next.reserve(8 * static_cast<std::size_t>(std::count(hold.begin(), hold.end(), 1)));
    for (std::size_t i = 0; i < leaves.size(); ++i) {
      if (hold[i] != 0) split_1_to_8(leaves[i], next);
    }
    leaves = std::move(next);
    check_cancel(ctx);
  }
  st.leaf_tets = leaves.size();
  st.seconds_subdivide = seconds_since(clock);
  st.seconds_field = 0;  // included in seconds_subdivide: values are computed per level

  // 5b. Marching tetrahedra: per-leaf triangle counts, prefix sum, crossing edges.
  auto inside = [&](std::uint32_t v) { return values[v] > iso; };
  std::vector<std::size_t> tri_count(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    int in = 0;
    for (int k = 0; k < 4; ++k) in += inside(leaf_ids[i][k]) ? 1 : 0;
    tri_count[i] = in == 0 || in == 4 ? 0 : (in == 2 ? 2 : 1);
  }
  std::vector<std::size_t> tri_offset = tri_count;
  const std::size_t total_tris = parallel::exclusive_scan(tri_offset);
  // Crossing edges as (inside vertex, outside vertex) keys.
  std::vector<std::uint64_t> edge_keys;
  edge_keys.reserve(total_tris * 2);
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    if (tri_count[i] == 0) continue;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const std::uint32_t va = leaf_ids[i][a], vb = leaf_ids[i][b];
        if (inside(va) != inside(vb)) {
          const std::uint32_t vin = inside(va) ? va : vb;
          const std::uint32_t vout = inside(va) ? vb : va;
          edge_keys.push_back((std::uint64_t{vin} << 32U) | vout);
        }
      }
    }
  }
  tbb::parallel_sort(edge_keys.begin(), edge_keys.end());
  edge_keys.erase(std::unique(edge_keys.begin(), edge_keys.end()), edge_keys.end());
  auto edge_index = [&](std::uint32_t va, std::uint32_t vb) {
    const std::uint32_t vin = inside(va) ? va : vb;
    const std::uint32_t vout = inside(va) ? vb : va;
    const std::uint64_t key = (std::uint64_t{vin} << 32U) | vout;
    return static_cast<std::uint32_t>(std::lower_bound(edge_keys.begin(), edge_keys.end(), key) - edge_keys.begin());
  };
  // Vertices on the surface.
  std::vector<Vec3> ea(edge_keys.size()), eb(edge_keys.size());
  std::vector<double> fa(edge_keys.size()), fb(edge_keys.size());
  for (std::size_t e = 0; e < edge_keys.size(); ++e) {
    const auto vin = static_cast<std::uint32_t>(edge_keys[e] >> 32U);
    const auto vout = static_cast<std::uint32_t>(edge_keys[e] & 0xffffffffU);
    ea[e] = verts[vin];
    eb[e] = verts[vout];
    fa[e] = values[vin];
    fb[e] = values[vout];
  }
  TriMesh mesh;
  mesh.positions = detail::find_edge_roots(field, ea, eb, std::move(fa), std::move(fb),
                                           options.root_steps, st.root_evaluations);
  st.crossing_edges = mesh.positions.size();
  // Triangles, oriented with the normal pointing from the inside corners to the outside ones
  // (decided on the edge midpoints, which always span a proper cross-section of the leaf).
  mesh.triangles.resize(total_tris);
  parallel::for_chunks(
      leaves.size(), 4096,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          if (tri_count[i] == 0) continue;
          const Tet& t = leaf_ids[i];
          std::array<int, 4> ins{}, outs{};
          int ni = 0, no = 0;
          for (int k = 0; k < 4; ++k) {
            if (inside(t[k])) {
              ins[ni++] = k;
            } else {
              outs[no++] = k;
            }
          }
          Vec3 in_mean = Vec3::Zero(), out_mean = Vec3::Zero();
          for (int k = 0; k < ni; ++k) in_mean += leaves[i][ins[k]] / ni;
          for (int k = 0; k < no; ++k) out_mean += leaves[i][outs[k]] / no;
          const Vec3 outward = out_mean - in_mean;
          auto mid = [&](int a, int c) { return 0.5 * (leaves[i][a] + leaves[i][c]); };
          std::size_t w = tri_offset[i];
          if (ni == 1 || no == 1) {
            const bool one_in = ni == 1;
            const int apex = one_in ? ins[0] : outs[0];
            const std::array<int, 3> others = one_in ? std::array<int, 3>{outs[0], outs[1], outs[2]}
                                                     : std::array<int, 3>{ins[0], ins[1], ins[2]};
            std::array<std::uint32_t, 3> tri{};
            std::array<Vec3, 3> m;
            for (int k = 0; k < 3; ++k) {
              tri[k] = edge_index(t[apex], t[others[k]]);
              m[k] = mid(apex, others[k]);
            }
            if ((m[1] - m[0]).cross(m[2] - m[0]).dot(outward) < 0) std::swap(tri[1], tri[2]);
            mesh.triangles[w] = tri;
          } else {
            // Quad around the four crossing edges, in cyclic order.
            const int a = ins[0], c = ins[1], p = outs[0], q = outs[1];
            std::array<std::uint32_t, 4> quad = {edge_index(t[a], t[p]), edge_index(t[a], t[q]),
                                                 edge_index(t[c], t[q]), edge_index(t[c], t[p])};
            std::array<Vec3, 4> m = {mid(a, p), mid(a, q), mid(c, q), mid(c, p)};
            if ((m[1] - m[0]).cross(m[2] - m[0]).dot(outward) < 0) {
              std::swap(quad[1], quad[3]);
              std::swap(m[1], m[3]);
            }
            // Split along the shorter diagonal of the placed vertices.
            const double d02 = (mesh.positions[quad[0]] - mesh.positions[quad[2]]).squaredNorm();
            const double d13 = (mesh.positions[quad[1]] - mesh.positions[quad[3]]).squaredNorm();
            if (d02 <= d13) {
              mesh.triangles[w] = {quad[0], quad[1], quad[2]};
              mesh.triangles[w + 1] = {quad[0], quad[2], quad[3]};
            } else {
              mesh.triangles[w] = {quad[1], quad[2], quad[3]};
              mesh.triangles[w + 1] = {quad[1], quad[3], quad[0]};
            }
          }
        }
      },
      ctx);
  st.seconds_extract = seconds_since(clock);
  if (stats_out != nullptr) *stats_out = st;
  return mesh;
}

}  // namespace ramiform
