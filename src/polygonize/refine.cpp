// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/refine.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "field/bvh.h"
#include "polygonize/cheapest_first.h"
#include "polygonize/in_tetrahedron.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/mesh/deviation.h"

namespace ramiform {

// (Declared in polygonize/cheapest_first.h.) The first round on the 1,500-segment benchmark
// tree sorts 58 k of its 232 k items and takes 18 k.
void detail::cheapest_first(std::vector<std::pair<double, std::uint32_t>>& cost, double budget) {
  for (std::size_t head = std::max<std::size_t>(64, cost.size() / 64);; head *= 4) {
    if (head >= cost.size()) {
      std::sort(cost.begin(), cost.end());
      return;
    }
    const auto mid = cost.begin() + static_cast<std::ptrdiff_t>(head);
    std::nth_element(cost.begin(), mid, cost.end());
    double sum = 0.0;
    for (auto it = cost.begin(); it != mid; ++it) sum += it->first;
    // Twice the budget: the walk's running subtraction rounds differently from this sum.
    if (sum > 2.0 * budget) {
      cost.resize(head);
      std::sort(cost.begin(), cost.end());
      return;
    }
  }
}

namespace {

using detail::in_tetrahedron;

constexpr std::size_t kGrain = 4096;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
/// Peak bytes per triangle of a refinement round (the mesh, its edges, the candidates' points,
/// values and gradients, the new triangles and their parents' normals: about 250).
constexpr std::size_t kBytesPerTriangle = 256;
/// An edge split at its midpoint taken onto the surface leaves two halves whose chords sag about a
/// quarter as much as the edge did (a parabola's chord of half the length); a half is assumed to
/// sag by at most this share of its parent's first-order distance, and is not evaluated again
/// when that stays within the tolerance.
constexpr double kHalfSag = 0.5;
/// A median's chord (from an edge's midpoint to the opposite corner) is assumed to sag by at
/// most this multiple of the sag the parallelogram law predicts for it (refine_round()).
constexpr double kMedianSag = 2.0;
/// A Newton step at most this long (in local radii) ends the projection of a new vertex.
constexpr double kConvergedStep = 3e-3;
/// The share of the mesh's area the first refinement pass may leave beyond the tolerance
/// (RefineOptions::spare_area): a twentieth of the 1 % a p99 leaves. Spared edges lie where a
/// split brings little area within the tolerance (thin twigs, midpoints just beyond it); on
/// archi_Tree_1 they save 6 % of the triangles, on generated trees 2-3 %, with p99 rising from
/// about 0.83-0.92 to 0.88-0.95 of the tolerance. A quarter of the 1 % saved 13 % on
/// archi_Tree_1 but left its p99 at the tolerance.
constexpr double kSpareShare = 5e-4;
// The base mesh's root finding stops at |f - iso| <= this times iso (polygonize_to_tolerance()).
constexpr double kToleranceRootValue = 1e-4;

/// Passes of reproject_off_surface() at most (each the whole way, then half way).
constexpr int kReprojectPasses = 4;

/// An allocator whose resize leaves new elements of trivial types uninitialized: the round's
/// large arrays are then first written by the parallel loops that fill them, instead of being
/// zeroed (and paged in) by one thread beforehand.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  using value_type = T;
  UninitializedAllocator() = default;
  template <class U>
  explicit UninitializedAllocator(const UninitializedAllocator<U>& /*other*/) {}
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T>
using Buffer = std::vector<T, UninitializedAllocator<T>>;

void validate(const RefineOptions& o) {
  if (!(o.edge_tolerance > 0.0) || !std::isfinite(o.edge_tolerance)) {
    throw InvalidArgument("refine: edge_tolerance must be finite and > 0, got " +
                          format_number(o.edge_tolerance));
  }
  if (!(o.min_edge_radii >= 0.0) || !std::isfinite(o.min_edge_radii)) {
    throw InvalidArgument("refine: min_edge_radii must be finite and >= 0, got " +
                          format_number(o.min_edge_radii));
  }
  if (o.max_rounds < 0) {
    throw InvalidArgument("refine: max_rounds must be >= 0, got " + std::to_string(o.max_rounds));
  }
  if (o.settle_rounds < 0) {
    throw InvalidArgument("refine: settle_rounds must be >= 0, got " +
                          std::to_string(o.settle_rounds));
  }
  if (!(o.max_turn_deg > 0.0 && o.max_turn_deg < 180.0)) {
    throw InvalidArgument("refine: max_turn_deg must be in (0, 180), got " +
                          format_number(o.max_turn_deg));
  }
  if (!(o.spare_area >= 0.0 && o.spare_area <= 0.01)) {
    throw InvalidArgument("refine: spare_area must be in [0, 0.01], got " +
                          format_number(o.spare_area));
  }
  if (!(o.max_normal_deg > 0.0 && o.max_normal_deg < 90.0)) {
    throw InvalidArgument("refine: max_normal_deg must be in (0, 90), got " +
                          format_number(o.max_normal_deg));
  }
}

/// The distinct edges of a mesh and, per triangle corner slot 3 t + k, the edge from corner k to
/// corner k + 1.
struct Edges {
  Buffer<std::array<std::uint32_t, 2>> ends;
  Buffer<std::uint32_t> of_slot;
  /// Per edge, its midpoint's first-order distance from the surface where it was evaluated,
  /// else a bound derived from the edges it came from (see refine_round), else infinity.
  Buffer<double> sag;
  /// Per edge, its midpoint's signed first-order distance (f - iso) / |grad f| where it was
  /// evaluated, else a prediction from the edges it came from (see refine_round), else NaN.
  /// Single precision: it only decides which edges to evaluate, and halves the memory.
  Buffer<float> curve;
};

Edges mesh_edges(const TriMesh& mesh) {
  // Counting sort of the corner slots by their edge's lower vertex; within a vertex's bucket
  // (a handful of slots) equal upper vertices are the same edge. Edges are numbered by lower
  // vertex, then by first slot: deterministic and linear.
  const std::size_t nv = mesh.positions.size();
  const std::size_t slots = 3 * mesh.triangles.size();
  std::vector<std::uint32_t> start(nv + 1, 0);
  auto ends_of = [&](std::size_t slot) {
    const auto& t = mesh.triangles[slot / 3];
    const std::uint32_t a = t[slot % 3], b = t[(slot % 3 + 1) % 3];
    return std::array<std::uint32_t, 2>{std::min(a, b), std::max(a, b)};
  };
  for (std::size_t s = 0; s < slots; ++s) ++start[ends_of(s)[0] + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> bucket(slots);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t s = 0; s < slots; ++s) bucket[fill[ends_of(s)[0]]++] = static_cast<std::uint32_t>(s);
  }
  Edges e;
  e.of_slot.assign(slots, 0);
  e.ends.reserve(slots / 2 + 1);
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t first_edge = e.ends.size();
    for (std::uint32_t k = start[v]; k < start[v + 1]; ++k) {
      const auto ab = ends_of(bucket[k]);
      std::size_t id = first_edge;
      while (id < e.ends.size() && e.ends[id][1] != ab[1]) ++id;
      if (id == e.ends.size()) e.ends.push_back(ab);
      e.of_slot[bucket[k]] = static_cast<std::uint32_t>(id);
    }
  }
  e.sag.assign(e.ends.size(), std::numeric_limits<double>::infinity());
  e.curve.assign(e.ends.size(), std::numeric_limits<float>::quiet_NaN());
  return e;
}

Vec3 normal_of(const TriMesh& m, const std::array<std::uint32_t, 3>& t) {
  return (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
}

/// The share of a triangle's area farther from the surface than the tolerance when one of its
/// edges, whose midpoint lies q > 1 times the tolerance from it, is left unsplit: the chord's
/// error at barycentric coordinates (u, v) of its ends is about 4 u v times the midpoint's
/// (a quadratic surface; the other edges taken as exact), and 4 u v > 1 / q on a share
/// w - 2 k ln(x2 / x1) of the triangle, k = 1 / 4q, x1,2 = (1 -+ w) / 2, w = sqrt(1 - 4 k).
double share_beyond(double q) {
  if (!(q > 1.0)) return 0.0;
  const double k = 0.25 / q;
  const double w = std::sqrt(1.0 - 4.0 * k);
  return std::max(0.0, w - 2.0 * k * std::log((1.0 + w) / (1.0 - w)));
}

/// Runs `fill(begin, end, out)` on fixed chunks of [0, n) in parallel, each appending to its own
/// list, and returns the lists joined in chunk order: what one pass over [0, n) would append.
template <class T, class Fill>
std::vector<T> gather_chunks(std::size_t n, Fill&& fill, const Context* ctx) {
  const std::size_t chunks = (n + kGrain - 1) / kGrain;
  std::vector<std::vector<T>> parts(chunks);
  parallel::for_chunks(
      n, kGrain, [&](std::size_t b, std::size_t e) { fill(b, e, parts[b / kGrain]); }, ctx);
  std::vector<std::size_t> at(chunks + 1, 0);
  for (std::size_t c = 0; c < chunks; ++c) at[c + 1] = at[c] + parts[c].size();
  std::vector<T> all(at[chunks]);
  parallel::for_chunks(
      chunks, 1,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t c = b; c < e; ++c) {
          std::copy(parts[c].begin(), parts[c].end(),
                    all.begin() + static_cast<std::ptrdiff_t>(at[c]));
        }
      },
      ctx);
  return all;
}

/// The fans (the triangles around each vertex) of the vertices that `slot` numbers 0..count - 1
/// (kNone for the others), as CSR: `start` (count + 1 offsets) into `fan`, in triangle order.
template <class Slot>
void fans_of(const TriMesh& mesh, std::size_t count, Slot&& slot, std::vector<std::size_t>& start,
             std::vector<std::uint32_t>& fan) {
  start.assign(count + 1, 0);
  for (const auto& t : mesh.triangles)
    for (const auto v : t)
      if (const std::uint32_t k = slot(v); k != kNone) ++start[k + 1];
  for (std::size_t k = 0; k < count; ++k) start[k + 1] += start[k];
  fan.resize(start[count]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (const auto v : mesh.triangles[t])
      if (const std::uint32_t k = slot(v); k != kNone) fan[fill[k]++] = t;
}

/// Whether moving vertex `vid` between `a` and `b` sweeps a skeleton node: the node lies in the
/// tetrahedron of a, b and the other two corners of a triangle of its fan (`fan[first, last)`).
/// `box` holds a, b and the fan's corners.
bool sweeps_node(const TriMesh& mesh, const std::vector<std::uint32_t>& fan, std::size_t first,
                 std::size_t last, std::uint32_t vid, const Vec3& a, const Vec3& b, const Aabb& box,
                 const Skeleton& skeleton, const detail::BoxBvh& nodes) {
  thread_local std::vector<std::uint32_t> hits;
  hits.clear();
  nodes.query(box, hits);
  for (const std::uint32_t h : hits) {
    const Vec3& p = skeleton.nodes[h].position;
    for (std::size_t f = first; f < last; ++f) {
      std::array<Vec3, 2> other;
      int k = 0;
      for (const auto v : mesh.triangles[fan[f]])
        if (v != vid) other[k++ % 2] = mesh.positions[v];
      if (in_tetrahedron(p, a, b, other[0], other[1])) return true;
    }
  }
  return false;
}

/// Newton steps along the gradient (at most 8, batched) that take each point z[i] onto the
/// surface; `first_value` and `first_grad` are the field at the starting points. ok[i] becomes 1
/// where a point converged: within 1e-7 local radii zr[i] of the surface by the first-order
/// distance, or after a step of at most kConvergedStep radii.
void newton_onto_surface(const Field& field, std::vector<Vec3>& z, const std::vector<double>& zr,
                         const Buffer<double>& first_value, const Buffer<Vec3>& first_grad,
                         std::vector<char>& ok, Context* ctx) {
  const double iso = field.iso();
  std::vector<std::uint32_t> active(z.size());
  for (std::size_t i = 0; i < z.size(); ++i) active[i] = static_cast<std::uint32_t>(i);
  Buffer<double> v;
  Buffer<Vec3> g, pts;
  for (int step = 0; step < 8 && !active.empty(); ++step) {
    v.resize(active.size());
    g.resize(active.size());
    if (step == 0) {
      parallel::for_each(
          active.size(), kGrain,
          [&](std::size_t j) {
            v[j] = first_value[active[j]];
            g[j] = first_grad[active[j]];
          },
          ctx);
    } else {
      pts.resize(active.size());
      parallel::for_each(
          active.size(), kGrain, [&](std::size_t j) { pts[j] = z[active[j]]; }, ctx);
      field.evaluate(pts, v, g, ctx);
    }
    active = gather_chunks<std::uint32_t>(
        active.size(),
        [&](std::size_t begin, std::size_t end, std::vector<std::uint32_t>& next) {
          for (std::size_t j = begin; j < end; ++j) {
            const std::uint32_t i = active[j];
            const double gg = g[j].squaredNorm();
            if (!std::isfinite(v[j]) || !(gg > 0.0) || !std::isfinite(gg)) continue;  // flat
            const double dist = std::abs(v[j] - iso) / std::sqrt(gg);
            if (dist <= 1e-7 * zr[i]) {
              ok[i] = 1;
              continue;
            }
            const Vec3 step = ((v[j] - iso) / gg) * g[j];
            z[i] -= step;
            // Newton converges quadratically: after a step this small the distance left is of
            // the order of step^2 / radius (here about 1e-5 radii), far below any tolerance,
            // and needs no further evaluation. From a midpoint 0.05 radii off the surface the
            // second step is about 0.003 radii, so most splits take one evaluation besides the
            // test's.
            if (step.norm() <= kConvergedStep * zr[i]) {
              ok[i] = 1;
              continue;
            }
            next.push_back(i);
          }
        },
        ctx);
  }
}

/// One round; returns the number of edges split (0: nothing to do or over budget). `fresh` marks
/// the vertices made by the previous round (all in the first): an edge between two older
/// vertices was measured then and not split, so only edges with a fresh end are evaluated, and
/// of those not the ones whose sag bound (from the edges they came from) is within the
/// tolerance, nor those at a vertex that `off` marks as left off the surface.
std::size_t refine_round(TriMesh& mesh, Edges& edges, std::vector<double>& vradius,
                         std::vector<char>& fresh, std::vector<char>& off, double& spare,
                         const Field& field, const Skeleton& skeleton, const detail::BoxBvh& nodes,
                         const RefineOptions& o, Context* ctx, RefineStats& st) {
  const std::size_t ne = edges.ends.size();
  const std::size_t inherited_chunks = (ne + kGrain - 1) / kGrain;
  std::vector<std::size_t> inherited(inherited_chunks, 0);
  const std::vector<std::uint32_t> candidates = gather_chunks<std::uint32_t>(
      ne,
      [&](std::size_t begin, std::size_t end, std::vector<std::uint32_t>& out) {
        for (auto e = static_cast<std::uint32_t>(begin); e < end; ++e) {
          const auto [a, b] = edges.ends[e];
          if (fresh[a] == 0 && fresh[b] == 0) continue;
          // A half of a split edge, or an edge inside a split triangle, whose bound (below) is
          // within the tolerance.
          if (edges.sag[e] <= o.edge_tolerance * std::min(vradius[a], vradius[b])) {
            ++inherited[begin / kGrain];
            continue;
          }
          // An end a split left off the surface (its move would fold the mesh or sweep a node):
          // the edge's chord cannot be brought closer by splitting it, whose new vertex would
          // meet the same fold. Splitting such edges anyway cascaded round after round around
          // forks (4 % of the triangles of archi_Tree_1) without moving the surface there.
          if (off[a] != 0 || off[b] != 0) continue;
          out.push_back(e);
        }
      },
      ctx);
  for (const std::size_t k : inherited) st.inherited += k;
  const std::size_t nc = candidates.size();
  // The candidates' midpoints and radii (an edge's radius: the smaller local radius of its end
  // points, the one whose tolerance is stricter, e.g. a twig's beside the branch it leaves),
  // indexed by candidate.
  Buffer<double> radius(nc);
  Buffer<Vec3> probe_points(nc);
  parallel::for_each(
      nc, kGrain,
      [&](std::size_t c) {
        const auto& [a, b] = edges.ends[candidates[c]];
        probe_points[c] = 0.5 * (mesh.positions[a] + mesh.positions[b]);
        radius[c] = std::min(vradius[a], vradius[b]);
      },
      ctx);
  Buffer<double> value(nc);
  Buffer<Vec3> grad(nc);
  field.evaluate(probe_points, value, grad, ctx);
  const double iso = field.iso();
  std::vector<char> split(ne, 0);
  Buffer<double> estimate(nc);
  parallel::for_each(
      nc, kGrain,
      [&](std::size_t c) {
        const std::uint32_t e = candidates[c];
        const double gn = grad[c].norm();
        estimate[c] = gn > 0.0 ? std::abs(value[c] - iso) / gn : std::numeric_limits<double>::infinity();
        edges.sag[e] = estimate[c];
        edges.curve[e] = gn > 0.0 ? static_cast<float>((value[c] - iso) / gn)
                                  : std::numeric_limits<float>::quiet_NaN();
        const double length =
            (mesh.positions[edges.ends[e][0]] - mesh.positions[edges.ends[e][1]]).norm();
        // An edge already short against the radius sags by less than the tolerance (L^2 / 8 r);
        // a midpoint still far from the surface there is not a matter of chords.
        split[e] = std::isfinite(value[c]) && estimate[c] > o.edge_tolerance * radius[c] &&
                           length > o.min_edge_radii * radius[c]
                       ? 1
                       : 0;
      },
      ctx);
  const std::size_t nt = mesh.triangles.size();
  if (spare > 0.0) {
    // The edges to split, cheapest first by the area they would leave beyond the tolerance
    // (the share of their triangles' area, ties by edge), stay unsplit while that area fits in
    // what is left of the spare area.
    Buffer<double> area(nt), around(ne);
    parallel::for_each(
        nt, kGrain,
        [&](std::size_t t) { area[t] = 0.5 * normal_of(mesh, mesh.triangles[t]).norm(); }, ctx);
    parallel::for_chunks(
        ne, kGrain,
        [&](std::size_t b, std::size_t e) {
          std::fill(around.begin() + static_cast<std::ptrdiff_t>(b),
                    around.begin() + static_cast<std::ptrdiff_t>(e), 0.0);
        },
        ctx);
    for (std::size_t t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t e = edges.of_slot[3 * t + k];
        if (split[e] != 0) around[e] += area[t];
      }
    }
    // (An edge costing more than the whole spare area is never spared: only the others are
    // sorted.)
    std::vector<std::pair<double, std::uint32_t>> cost =
        gather_chunks<std::pair<double, std::uint32_t>>(
            nc,
            [&](std::size_t begin, std::size_t end, auto& part) {
              for (std::size_t c = begin; c < end; ++c) {
                const std::uint32_t e = candidates[c];
                if (split[e] == 0) continue;
                const double beyond =
                    share_beyond(estimate[c] / (o.edge_tolerance * radius[c])) * around[e];
                if (beyond <= spare) part.emplace_back(beyond, e);
              }
            },
            ctx);
    detail::cheapest_first(cost, spare);
    for (const auto& [beyond, e] : cost) {
      if (beyond > spare) break;
      spare -= beyond;
      split[e] = 0;
      ++st.spared;
    }
  }
  // The budget: each split edge of a triangle adds one triangle.
  std::size_t added = 0;
  for (std::size_t s = 0; s < 3 * nt; ++s) added += split[edges.of_slot[s]];
  if (added == 0) return 0;
  if (nt + added > o.max_triangles) {
    st.budget_reached = true;
    return 0;
  }
  // New vertices: the split edges' midpoints, taken onto the surface by batched Newton steps.
  // Only candidates are split, and candidates ascend by edge: split_candidate[i] is the
  // candidate (the index into value and grad) of split_edges[i].
  std::vector<std::uint32_t> new_id(ne, kNone);
  std::vector<std::uint32_t> split_edges, split_candidate;
  for (std::uint32_t c = 0; c < nc; ++c) {
    const std::uint32_t e = candidates[c];
    if (split[e] != 0) {
      new_id[e] = static_cast<std::uint32_t>(mesh.positions.size() + split_edges.size());
      split_edges.push_back(e);
      split_candidate.push_back(c);
    }
  }
  const std::size_t ns = split_edges.size();
  std::vector<Vec3> z(ns), zmid(ns);
  std::vector<double> zr(ns);
  for (std::size_t i = 0; i < ns; ++i) {
    zmid[i] = z[i] = probe_points[split_candidate[i]];
    zr[i] = radius[split_candidate[i]];
  }
  std::vector<char> ok(ns, 0);
  {
    Buffer<double> v0(ns);
    Buffer<Vec3> g0(ns);
    parallel::for_each(
        ns, kGrain,
        [&](std::size_t i) {
          v0[i] = value[split_candidate[i]];
          g0[i] = grad[split_candidate[i]];
        },
        ctx);
    newton_onto_surface(field, z, zr, v0, g0, ok, ctx);
  }
  std::vector<char> moved(ns, 0);
  for (std::size_t i = 0; i < ns; ++i) {
    // A converged point not far from its midpoint (a step that jumped to another part of the
    // surface is not taken).
    moved[i] = ok[i] != 0 && (z[i] - zmid[i]).norm() <= 0.5 * zr[i] +
                                                           2.0 * estimate[split_candidate[i]]
                   ? 1
                   : 0;
    if (moved[i] == 0) {
      z[i] = zmid[i];
      ++st.unprojected;
    }
  }
  // The new triangles, each remembering its parent, and the new mesh's edges, built alongside
  // instead of sorted afresh: an unsplit edge stays one edge, a split edge becomes its two
  // halves (numbered in the old edges' order), and the edges inside a split triangle (from a new
  // vertex to the opposite corner, between new vertices, a quadrilateral's diagonal) follow in
  // triangle order; each lies inside one old triangle, so no two triangles make the same one.
  // Per triangle with c of its edges split: 1 + c new triangles, c inner edges, and a median or
  // diagonal when c is 1 or 2. Chunks of triangles count theirs, then write them from their
  // offsets in parallel, in triangle order as one pass would.
  const std::size_t chunks = (nt + kGrain - 1) / kGrain;
  std::vector<std::size_t> split_at(chunks + 1, 0), median_at(chunks + 1, 0);
  parallel::for_chunks(
      nt, kGrain,
      [&](std::size_t b, std::size_t e) {
        std::size_t splits = 0, medians = 0;
        for (std::size_t t = b; t < e; ++t) {
          int count = 0;
          for (int k = 0; k < 3; ++k) count += new_id[edges.of_slot[3 * t + k]] != kNone ? 1 : 0;
          splits += static_cast<std::size_t>(count);
          medians += count == 1 || count == 2 ? 1 : 0;
        }
        split_at[b / kGrain + 1] = splits;
        median_at[b / kGrain + 1] = medians;
      },
      ctx);
  for (std::size_t c = 0; c < chunks; ++c) {
    split_at[c + 1] += split_at[c];
    median_at[c + 1] += median_at[c];
  }
  // An old edge e becomes edge first_edge[e] (e plus the split edges before it, which ascend),
  // and a split one also the next.
  Buffer<std::uint32_t> first_edge(ne);
  const auto next_edge = static_cast<std::uint32_t>(ne + ns);
  Edges out;
  out.ends.resize(next_edge + split_at[chunks]);
  out.sag.resize(out.ends.size());
  out.curve.resize(out.ends.size());
  out.of_slot.resize(3 * (nt + added));
  parallel::for_chunks(
      ne, kGrain,
      [&](std::size_t begin, std::size_t end) {
        auto before = static_cast<std::uint32_t>(
            std::lower_bound(split_edges.begin(), split_edges.end(), begin) - split_edges.begin());
        for (std::size_t e = begin; e < end; ++e) {
          const std::uint32_t f = static_cast<std::uint32_t>(e) + before;
          first_edge[e] = f;
          const auto [a, b] = edges.ends[e];
          if (new_id[e] == kNone) {
            out.ends[f] = {a, b};
            out.sag[f] = edges.sag[e];
            out.curve[f] = edges.curve[e];
          } else {
            out.ends[f] = {a, new_id[e]};  // new vertices come after all old ones
            out.ends[f + 1] = {b, new_id[e]};
            out.sag[f] = out.sag[f + 1] = std::numeric_limits<double>::infinity();
            out.curve[f] = out.curve[f + 1] = std::numeric_limits<float>::quiet_NaN();
            ++before;
          }
        }
      },
      ctx);
  std::vector<std::array<std::uint32_t, 3>> tris(nt + added);
  Buffer<std::uint32_t> parent(nt + added);
  // A new inner edge; its sag bound comes from the old edge it is parallel to (below), kNone
  // for none.
  Buffer<std::uint32_t> inner_from(split_at[chunks]);
  // Medians and diagonals: the new edge, then the old edges of its triangle: the two from its
  // corner, then the split one whose midpoint it ends at.
  Buffer<std::array<std::uint32_t, 4>> median_of(median_at[chunks]);
  parallel::for_chunks(
      nt, kGrain,
      [&](std::size_t begin, std::size_t end) {
        std::size_t next_tri = begin + split_at[begin / kGrain];
        std::size_t next_inner = split_at[begin / kGrain];
        std::size_t next_median = median_at[begin / kGrain];
        // Triangle a, b, c with edges ab, bc, ca.
        auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t ab,
                        std::uint32_t bc, std::uint32_t ca, std::size_t t) {
          const std::size_t slot = 3 * next_tri;
          out.of_slot[slot] = ab;
          out.of_slot[slot + 1] = bc;
          out.of_slot[slot + 2] = ca;
          tris[next_tri] = {a, b, c};
          parent[next_tri++] = static_cast<std::uint32_t>(t);
        };
        auto inner = [&](std::uint32_t a, std::uint32_t b, std::uint32_t parallel) {
          const std::size_t e = next_edge + next_inner;
          out.ends[e] = {std::min(a, b), std::max(a, b)};
          out.sag[e] = std::numeric_limits<double>::infinity();
          out.curve[e] = std::numeric_limits<float>::quiet_NaN();
          inner_from[next_inner++] = parallel;
          return static_cast<std::uint32_t>(e);
        };
        auto median = [&](const std::array<std::uint32_t, 4>& m) { median_of[next_median++] = m; };
        for (std::size_t t = begin; t < end; ++t) {
          const auto& v = mesh.triangles[t];
          std::array<std::uint32_t, 3> m{}, old{};
          int count = 0;
          for (int k = 0; k < 3; ++k) {
            old[k] = edges.of_slot[3 * t + k];  // v[k] -> v[k + 1]
            m[k] = new_id[old[k]];
            count += m[k] != kNone ? 1 : 0;
          }
          // The edge of slot k whole, or the half of its split at corner `at`.
          auto whole = [&](int k) { return first_edge[old[k % 3]]; };
          auto half = [&](int k, std::uint32_t at) {
            const std::uint32_t e = old[k % 3];
            return first_edge[e] + (edges.ends[e][0] == at ? 0 : 1);
          };
          if (count == 0) {
            emit(v[0], v[1], v[2], whole(0), whole(1), whole(2), t);
          } else if (count == 3) {
            // Each joins the midpoints of two edges, parallel to the third.
            const std::uint32_t i01 = inner(m[0], m[1], old[2]);
            const std::uint32_t i12 = inner(m[1], m[2], old[0]);
            const std::uint32_t i20 = inner(m[2], m[0], old[1]);
            emit(v[0], m[0], m[2], half(0, v[0]), i20, half(2, v[0]), t);
            emit(m[0], v[1], m[1], half(0, v[1]), half(1, v[1]), i01, t);
            emit(m[1], v[2], m[2], half(1, v[2]), half(2, v[2]), i12, t);
            emit(m[0], m[1], m[2], i01, i12, i20, t);
          } else if (count == 1) {
            const int k = m[0] != kNone ? 0 : (m[1] != kNone ? 1 : 2);
            const std::uint32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
            const std::uint32_t mc = inner(m[k], c, kNone);
            median({mc, old[(k + 2) % 3], old[(k + 1) % 3], old[k]});
            emit(a, m[k], c, half(k, a), mc, whole(k + 2), t);
            emit(m[k], b, c, half(k, b), whole(k + 1), mc, t);
          } else {
            // The unsplit edge a -> b; m1 on b -> c, m2 on c -> a; cycle a, b, m1, c, m2.
            const int k = m[0] == kNone ? 0 : (m[1] == kNone ? 1 : 2);
            const std::uint32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
            const std::uint32_t m1 = m[(k + 1) % 3], m2 = m[(k + 2) % 3];
            const std::uint32_t i12 = inner(m1, m2, old[k]);
            emit(m1, c, m2, half(k + 1, c), half(k + 2, c), i12, t);
            auto pos = [&](std::uint32_t id) {
              return id < mesh.positions.size() ? mesh.positions[id]
                                                : z[id - mesh.positions.size()];
            };
            if ((pos(a) - pos(m1)).squaredNorm() <= (pos(b) - pos(m2)).squaredNorm()) {
              const std::uint32_t d = inner(a, m1, kNone);
              median({d, old[k], old[(k + 2) % 3], old[(k + 1) % 3]});
              emit(a, b, m1, whole(k), half(k + 1, b), d, t);
              emit(a, m1, m2, d, i12, half(k + 2, a), t);
            } else {
              const std::uint32_t d = inner(b, m2, kNone);
              median({d, old[k], old[(k + 1) % 3], old[(k + 2) % 3]});
              emit(a, b, m2, whole(k), d, half(k + 2, a), t);
              emit(b, m1, m2, half(k + 1, b), i12, d, t);
            }
          }
        }
      },
      ctx);
  const std::size_t nv_old = mesh.positions.size();
  mesh.positions.insert(mesh.positions.end(), z.begin(), z.end());
  fresh.assign(mesh.positions.size(), 0);
  std::fill(fresh.begin() + static_cast<std::ptrdiff_t>(nv_old), fresh.end(), 1);
  // The old triangles give the parents' normals (their corners do not move); kept rather than
  // a normal per triangle, which at 24 bytes a triangle exceeded malloc's mmap threshold on the
  // benchmark tree and was paged in afresh every round.
  const std::vector<std::array<std::uint32_t, 3>> old_triangles = std::move(mesh.triangles);
  mesh.triangles = std::move(tris);
  // The fans of the new vertices (CSR), for the checks, made by one thread while the others find
  // the new vertices' local radii (for the next round; two tasks, one after the other on one
  // thread).
  std::vector<double> new_radius;
  std::vector<std::size_t> fan_start;
  std::vector<std::uint32_t> fan;
  parallel::both([&] { new_radius = local_radii(skeleton, z, ctx); },
                 [&] {
                   fans_of(
                       mesh, ns,
                       [&](std::uint32_t v) {
                         return v >= nv_old ? static_cast<std::uint32_t>(v - nv_old) : kNone;
                       },
                       fan_start, fan);
                 },
                 ctx);
  vradius.insert(vradius.end(), new_radius.begin(), new_radius.end());
  const double cos_turn = pm::cos(o.max_turn_deg * std::numbers::pi / 180.0);
  // Revert moves, pass after pass, until no new triangle turns too far and no node is swept.
  // A pass checks the vertices whose fan changed in the pass before (at first all that moved):
  // the check depends only on the fan's positions, so the others would pass again.
  std::vector<std::uint32_t> check;
  for (std::size_t i = 0; i < ns; ++i)
    if (moved[i] != 0) check.push_back(static_cast<std::uint32_t>(i));
  // A fan that turns too far against its parents is still taken when each of its triangles
  // lies within max_normal_deg of the surface's outward normal at its centroid: the parent cut
  // across the surface (at forks, where the base mesh's triangles stand across the blend), and
  // the split brings the mesh back onto it. Taking such vertices only half way left them
  // 0.25-0.55 radii off the surface, the largest deviations of the benchmark tree.
  const double cos_normal = pm::cos(o.max_normal_deg * std::numbers::pi / 180.0);
  std::vector<char> revert(ns, 0), queued(ns, 0), turned(ns, 0);
  std::vector<Vec3> centroids;
  std::vector<double> cvalue;
  std::vector<Vec3> cgrad;
  while (!check.empty()) {
    parallel::for_each(
        check.size(), 256,
        [&](std::size_t c) {
          const std::uint32_t i = check[c];
          turned[i] = 0;
          if (moved[i] == 0) return;
          const std::uint32_t vid = static_cast<std::uint32_t>(nv_old + i);
          Aabb box(zmid[i]);
          box.extend(mesh.positions[vid]);
          for (std::size_t f = fan_start[i]; f < fan_start[i + 1]; ++f) {
            const auto& t = mesh.triangles[fan[f]];
            const Vec3 n = normal_of(mesh, t);
            const Vec3 np = normal_of(mesh, old_triangles[parent[fan[f]]]);
            const double nn = n.norm() * np.norm();
            if (!(nn > 0.0)) {
              revert[i] = 1;
              return;
            }
            if (n.dot(np) < cos_turn * nn) turned[i] = 1;
            for (const auto v : t) box.extend(mesh.positions[v]);
          }
          if (sweeps_node(mesh, fan, fan_start[i], fan_start[i + 1], vid, zmid[i],
                          mesh.positions[vid], box, skeleton, nodes)) {
            revert[i] = 1;
          }
        },
        ctx);
    centroids.clear();
    for (const std::uint32_t i : check) {
      if (revert[i] != 0 || turned[i] == 0) continue;
      for (std::size_t f = fan_start[i]; f < fan_start[i + 1]; ++f) {
        const auto& t = mesh.triangles[fan[f]];
        centroids.push_back((mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) /
                            3.0);
      }
    }
    if (!centroids.empty()) {
      cvalue.resize(centroids.size());
      cgrad.resize(centroids.size());
      field.evaluate(centroids, cvalue, cgrad, ctx);
      std::size_t k = 0;
      for (const std::uint32_t i : check) {
        if (revert[i] != 0 || turned[i] == 0) continue;
        for (std::size_t f = fan_start[i]; f < fan_start[i + 1]; ++f, ++k) {
          const Vec3 n = normal_of(mesh, mesh.triangles[fan[f]]);
          const double nn = n.norm() * cgrad[k].norm();
          if (!(nn > 0.0) || !std::isfinite(nn) || -n.dot(cgrad[k]) < cos_normal * nn) {
            revert[i] = 1;
          }
        }
      }
    }
    // A vertex sent back goes half way first, then to the midpoint; it and the new vertices of
    // its fan are checked again.
    std::vector<std::uint32_t> again;
    for (const std::uint32_t i : check) {
      if (revert[i] == 0) continue;
      revert[i] = 0;
      Vec3& p = mesh.positions[nv_old + i];
      if (moved[i] == 1) {
        moved[i] = 2;
        p = 0.5 * (p + zmid[i]);
      } else {
        moved[i] = 0;
        p = zmid[i];
        ++st.reverted;
      }
      for (std::size_t f = fan_start[i]; f < fan_start[i + 1]; ++f) {
        for (const auto v : mesh.triangles[fan[f]]) {
          if (v < nv_old || queued[v - nv_old] != 0) continue;
          queued[v - nv_old] = 1;
          again.push_back(v - static_cast<std::uint32_t>(nv_old));
        }
      }
    }
    std::sort(again.begin(), again.end());
    for (const std::uint32_t i : again) queued[i] = 0;
    check = std::move(again);
  }
  // Sag bounds of the new edges, from the final positions. Where the surface is locally a
  // quadratic form (curvature K), a chord d sags by about d^T K d / 8 in the tangent plane:
  // - a half of a split edge, a quarter of its parent's;
  // - an inner edge joining two edge midpoints is parallel to the third edge at half its length:
  //   a quarter of that edge's.
  // - a median (from a midpoint to the opposite corner; a quadrilateral's diagonal is one) of a
  //   triangle with sides u, v from that corner: by the parallelogram law, which holds for any
  //   quadratic form, definite or not (the saddles of forks), Q((u + v) / 2) =
  //   (2 Q(u) + 2 Q(v) - Q(u - v)) / 4, so its signed sag is (2 s_u + 2 s_v - s_split) / 4 from
  //   the signed sags of the triangle's three edges (`curve`, measured or predicted alike).
  //   Without the signs, a bound from the two sides alone, (sqrt s_u + sqrt s_v)^2 / 4, holds
  //   only where K is semi-definite, and at forks it let the largest deviation on the benchmark
  //   tree rise from 0.21 to 0.41 radii; so medians were all evaluated, a tenth of the field
  //   evaluations of a mesh. With the prediction (taken kMedianSag times over) the benchmark
  //   tree and the scanned and generated trees keep their triangle counts within 0.04 %, their
  //   p99 and, over 300,000 points, their largest deviation, for 8-12 % fewer evaluations.
  // Each bound is taken twice over (kHalfSag = 2 x 1/4), for the first-order distance and
  // curvature that varies; an edge at a vertex not taken onto the surface gets none.
  off.resize(mesh.positions.size(), 0);
  parallel::for_each(
      ns, kGrain,
      [&](std::size_t i) {
        if (moved[i] != 1) return;
        const std::uint32_t f = first_edge[split_edges[i]];
        const double half = kHalfSag * estimate[split_candidate[i]];
        out.sag[f] = out.sag[f + 1] = half;
        const float quarter = edges.curve[split_edges[i]] / 4;
        out.curve[f] = out.curve[f + 1] = quarter;
      },
      ctx);
  auto on_surface = [&](std::uint32_t v) { return v < nv_old || moved[v - nv_old] == 1; };
  parallel::for_each(
      inner_from.size(), kGrain,
      [&](std::size_t k) {
        const std::size_t e = next_edge + k;
        const std::uint32_t p = inner_from[k];
        if (p == kNone || !on_surface(out.ends[e][0]) || !on_surface(out.ends[e][1])) return;
        out.sag[e] = kHalfSag * edges.sag[p];
        out.curve[e] = edges.curve[p] / 4;
      },
      ctx);
  parallel::for_each(
      median_of.size(), kGrain,
      [&](std::size_t k) {
        const auto& [me, s1, s2, sp] = median_of[k];
        if (!on_surface(out.ends[me][0]) || !on_surface(out.ends[me][1])) return;
        const double c1 = edges.curve[s1], c2 = edges.curve[s2], c3 = edges.curve[sp];  // widened
        const double p = (2 * c1 + 2 * c2 - c3) / 4;
        if (std::isnan(p)) return;
        out.curve[me] = static_cast<float>(p);
        out.sag[me] = kMedianSag * std::abs(p);
      },
      ctx);
  edges = std::move(out);
  for (std::size_t i = 0; i < ns; ++i) {
    off[nv_old + i] = moved[i] == 0 ? 1 : (moved[i] == 2 ? 2 : 0);
    st.flat_splits += moved[i] == 0 ? 1 : 0;
    st.halfway += moved[i] == 2 ? 1 : 0;
  }
  return ns;
}

/// The vertices a refinement left off the surface (ascending), their fans (CSR by their index in
/// `vertices`, which `rank` gives per mesh vertex, else kNone): built once for all passes of
/// reproject_off_surface(), which moves vertices but changes no triangle.
struct OffFans {
  std::vector<std::uint32_t> vertices;
  std::vector<std::uint32_t> rank;
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> fan;
};

OffFans off_fans(const TriMesh& mesh, const std::vector<char>& off) {
  OffFans f;
  const std::size_t nv = mesh.positions.size();
  for (std::uint32_t v = 0; v < nv; ++v)
    if (off[v] != 0) f.vertices.push_back(v);
  if (f.vertices.empty()) return f;
  f.rank.assign(nv, kNone);
  for (std::uint32_t k = 0; k < f.vertices.size(); ++k) f.rank[f.vertices[k]] = k;
  fans_of(
      mesh, f.vertices.size(), [&](std::uint32_t v) { return f.rank[v]; }, f.start, f.fan);
  return f;
}

/// After the rounds: moves the vertices that splits left off the surface (`off`: at their
/// edge's midpoint or half way) `fraction` of the way onto it (1: onto it, counted in `reached`;
/// less: still off) where their fan, as the later rounds refined it around them, now lets them
/// go. A split's move is judged against the coarse triangles it was made in; a vertex left half
/// way at a fork's blend stays a spike over the surface once its neighbours were refined onto it
/// (up to 2 local radii out on generated trees), and its own edges are never split again. It
/// moves when every triangle of its fan would face outward and agree with the surface's outward
/// normal at its centroid within max_normal_deg or no worse than the fan's worst does now, no
/// centroid would lie farther from the surface (first-order) than the farthest does now, and the
/// move sweeps no skeleton node. Two vertices of one fan do not move in the same pass (the later
/// waits for the next). Returns the number of vertices moved.
std::size_t reproject_off_surface(TriMesh& mesh, std::vector<char>& off, const OffFans& fans,
                                  const std::vector<double>& vradius, const Field& field,
                                  const Skeleton& skeleton, const detail::BoxBvh& nodes,
                                  const RefineOptions& o, double fraction, std::size_t& reached,
                                  Context* ctx) {
  std::vector<std::uint32_t> pending;
  for (const std::uint32_t v : fans.vertices)
    if (off[v] != 0) pending.push_back(v);
  if (pending.empty()) return 0;
  const std::vector<std::uint32_t>& rank = fans.rank;
  const std::vector<std::size_t>& fan_start = fans.start;
  const std::vector<std::uint32_t>& fan = fans.fan;
  const double cos_normal = pm::cos(o.max_normal_deg * std::numbers::pi / 180.0);
  std::size_t moved_count = 0;
  std::vector<char> taken(fans.vertices.size(), 0);
  while (!pending.empty()) {
    // This pass: the pending vertices with no earlier pending vertex of this pass in their fan.
    std::vector<std::uint32_t> now, later;
    for (const std::uint32_t v : pending) {
      bool free = true;
      for (std::size_t f = fan_start[rank[v]]; f < fan_start[rank[v] + 1] && free; ++f)
        for (const auto u : mesh.triangles[fan[f]])
          if (u != v && rank[u] != kNone && taken[rank[u]] != 0) free = false;
      if (free) {
        now.push_back(v);
        taken[rank[v]] = 1;
      } else {
        later.push_back(v);
      }
    }
    for (const std::uint32_t v : now) taken[rank[v]] = 0;
    const std::size_t n = now.size();
    std::vector<Vec3> z(n);
    std::vector<double> zr(n);
    for (std::size_t i = 0; i < n; ++i) {
      z[i] = mesh.positions[now[i]];
      zr[i] = vradius[now[i]];
    }
    Buffer<double> v0(n);
    Buffer<Vec3> g0(n);
    field.evaluate(z, v0, g0, ctx);
    std::vector<char> ok(n, 0);
    const std::vector<Vec3> from = z;
    newton_onto_surface(field, z, zr, v0, g0, ok, ctx);
    for (std::size_t i = 0; i < n; ++i) z[i] = from[i] + fraction * (z[i] - from[i]);
    // The fans with each vertex where it is and at its target: the triangles' normals and
    // centroids for the normal test (before: entries [first[i], first[i + 1]), after: the same
    // shifted by m).
    std::vector<std::size_t> first(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      first[i + 1] = first[i] + (fan_start[rank[now[i]] + 1] - fan_start[rank[now[i]]]);
    }
    const std::size_t m = first[n];
    std::vector<Vec3> centroid(2 * m), normal(2 * m);
    parallel::for_each(
        n, 64,
        [&](std::size_t i) {
          const std::uint32_t vid = now[i];
          const double gn = g0[i].norm();
          const double est = gn > 0.0 ? std::abs(v0[i] - field.iso()) / gn : 0.0;
          if (ok[i] == 0 || (z[i] - from[i]).norm() > 0.5 * zr[i] + 2.0 * est) {
            ok[i] = 0;
            return;
          }
          Aabb box(from[i]);
          box.extend(z[i]);
          std::size_t k = first[i];
          for (std::size_t f = fan_start[rank[vid]]; f < fan_start[rank[vid] + 1]; ++f, ++k) {
            std::array<Vec3, 3> c;
            for (int j = 0; j < 3; ++j) c[j] = mesh.positions[mesh.triangles[fan[f]][j]];
            normal[k] = (c[1] - c[0]).cross(c[2] - c[0]);
            centroid[k] = (c[0] + c[1] + c[2]) / 3.0;
            for (int j = 0; j < 3; ++j) {
              if (mesh.triangles[fan[f]][j] == vid) c[j] = z[i];
              box.extend(c[j]);
            }
            normal[m + k] = (c[1] - c[0]).cross(c[2] - c[0]);
            centroid[m + k] = (c[0] + c[1] + c[2]) / 3.0;
            if (!(normal[m + k].norm() > 0.0)) ok[i] = 0;
          }
          if (ok[i] != 0 && sweeps_node(mesh, fan, fan_start[rank[vid]], fan_start[rank[vid] + 1],
                                        vid, from[i], z[i], box, skeleton, nodes)) {
            ok[i] = 0;
          }
        },
        ctx);
    Buffer<double> cvalue(centroid.size());
    Buffer<Vec3> cgrad(centroid.size());
    field.evaluate(centroid, cvalue, cgrad, ctx);
    // The cosine between a triangle's normal and the surface's outward normal at its centroid.
    auto agreement = [&](std::size_t k) {
      const double nn = normal[k].norm() * cgrad[k].norm();
      return nn > 0.0 && std::isfinite(nn) ? -normal[k].dot(cgrad[k]) / nn : -1.0;
    };
    auto distance = [&](std::size_t k) {
      const double gn = cgrad[k].norm();
      return gn > 0.0 ? std::abs(cvalue[k] - field.iso()) / gn
                      : std::numeric_limits<double>::infinity();
    };
    for (std::size_t i = 0; i < n; ++i) {
      if (ok[i] == 0) continue;
      // The fan at the target must face outward everywhere, and no worse than it does now where
      // some triangle of it strays beyond max_normal_deg (a spike's fan does: the move then
      // trades its worst triangle for a better one).
      // Nor may the fan's triangles end farther from the surface (first-order distance at
      // the centroids): a vertex left in the gap where the mesh bridges a twig's tip and the
      // branch beside it would stretch the bridge's triangles.
      double before = 1.0, after = 1.0, far_before = 0.0, far_after = 0.0;
      for (std::size_t k = first[i]; k < first[i + 1]; ++k) {
        before = std::min(before, agreement(k));
        after = std::min(after, agreement(m + k));
        far_before = std::max(far_before, distance(k));
        far_after = std::max(far_after, distance(m + k));
      }
      if (!(after > 0.0 && after >= std::min(cos_normal, before) && far_after <= far_before)) {
        continue;
      }
      mesh.positions[now[i]] = z[i];
      if (fraction == 1.0) {
        off[now[i]] = 0;
        ++reached;
      } else {
        off[now[i]] = 2;  // half way, still off the surface
      }
      ++moved_count;
    }
    pending = std::move(later);
  }
  return moved_count;
}

/// refine_round() until a round splits nothing, at most max_rounds times, counted in `st`
/// (`report`: progress through ctx).
void refine_rounds(TriMesh& mesh, Edges& edges, std::vector<double>& vradius,
                   std::vector<char>& fresh, std::vector<char>& off, double& spare,
                   const Field& field, const Skeleton& skeleton, const detail::BoxBvh& nodes,
                   const RefineOptions& o, Context* ctx, RefineStats& st, bool report) {
  for (int round = 0; round < o.max_rounds; ++round) {
    const std::size_t split =
        refine_round(mesh, edges, vradius, fresh, off, spare, field, skeleton, nodes, o, ctx, st);
    if (split == 0) break;
    ++st.rounds;
    st.split_edges += split;
    if (report && ctx != nullptr) {
      ctx->report("refine", static_cast<double>(round + 1) / o.max_rounds);
    }
  }
}

/// Rounds on the edges at `reached` (vertices a reprojection just brought onto the surface),
/// run on the submesh of their fans alone so that their cost follows the fans, not the mesh:
/// a round splits only edges with a fresh end, and every triangle at such an edge (and at the
/// new vertices' edges after it) lies inside those fans, whose outer edges are never split; the
/// refined fans then replace the old ones (the other triangles keep their order, the refined
/// ones follow; new vertices are appended).
void settle_fans(TriMesh& mesh, std::vector<double>& vradius, std::vector<char>& off,
                 const std::vector<std::uint32_t>& reached, double& spare, const Field& field,
                 const Skeleton& skeleton, const detail::BoxBvh& nodes, const RefineOptions& o,
                 Context* ctx, RefineStats& st) {
  const std::size_t nv = mesh.positions.size();
  const std::size_t nt = mesh.triangles.size();
  std::vector<char> is_reached(nv, 0);
  for (const std::uint32_t v : reached) is_reached[v] = 1;
  std::vector<char> in_fan(nt, 0);
  std::vector<std::uint32_t> local(nv, kNone), global;
  TriMesh sub;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = mesh.triangles[t];
    if (is_reached[tri[0]] == 0 && is_reached[tri[1]] == 0 && is_reached[tri[2]] == 0) continue;
    in_fan[t] = 1;
    std::array<std::uint32_t, 3> mapped{};
    for (int k = 0; k < 3; ++k) {
      if (local[tri[k]] == kNone) {
        local[tri[k]] = static_cast<std::uint32_t>(global.size());
        global.push_back(tri[k]);
        sub.positions.push_back(mesh.positions[tri[k]]);
      }
      mapped[k] = local[tri[k]];
    }
    sub.triangles.push_back(mapped);
  }
  const std::size_t fan_triangles = sub.triangles.size();
  std::vector<double> sub_radius(global.size());
  std::vector<char> sub_off(global.size()), fresh(global.size());
  for (std::size_t i = 0; i < global.size(); ++i) {
    sub_radius[i] = vradius[global[i]];
    sub_off[i] = off[global[i]];
    fresh[i] = is_reached[global[i]];
  }
  Edges edges = mesh_edges(sub);  // every sag unknown: the edges at fresh ends are evaluated
  RefineOptions so = o;
  so.max_triangles =
      o.max_triangles > nt - fan_triangles ? o.max_triangles - (nt - fan_triangles) : 0;
  refine_rounds(sub, edges, sub_radius, fresh, sub_off, spare, field, skeleton, nodes, so, ctx, st,
                false);
  // New vertices after the old ones, then the refined fans in place of the old.
  for (std::size_t i = global.size(); i < sub.positions.size(); ++i) {
    global.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
    mesh.positions.push_back(sub.positions[i]);
    vradius.push_back(sub_radius[i]);
    off.push_back(sub_off[i]);
  }
  std::size_t kept = 0;
  for (std::size_t t = 0; t < nt; ++t)
    if (in_fan[t] == 0) mesh.triangles[kept++] = mesh.triangles[t];
  mesh.triangles.resize(kept);
  for (const auto& tri : sub.triangles)
    mesh.triangles.push_back({global[tri[0]], global[tri[1]], global[tri[2]]});
}

void accumulate(ImproveStats& all, const ImproveStats& pass, bool first) {
  const ImproveStats before = all;
  all = pass;
  all.rounds += before.rounds;
  all.flips += before.flips;
  all.collapses += before.collapses;
  all.clusters += before.clusters;
  all.relaxed += before.relaxed;
  if (!first) {
    all.below_10_deg_before = before.below_10_deg_before;
    all.below_1_deg_before = before.below_1_deg_before;
    all.min_angle_deg_before = before.min_angle_deg_before;
    all.triangles_before = before.triangles_before;
  }
}

}  // namespace

void refine_to_surface(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                       const RefineOptions& options, Context* ctx, RefineStats* stats) {
  validate(options);
  if (skeleton.nodes.empty()) throw InvalidArgument("refine: the skeleton has no nodes");
  RefineStats st;
  st.triangles_before = mesh.triangles.size();
  std::vector<Aabb> boxes;
  boxes.reserve(skeleton.nodes.size());
  for (const auto& n : skeleton.nodes) boxes.emplace_back(n.position, n.position);
  const detail::BoxBvh nodes(std::move(boxes));
  mesh.normals.clear();
  // The vertices' local radii beside the mesh's edges (sequential; two tasks, one after the
  // other on one thread), which each round then keeps up to date.
  std::vector<double> vradius;
  Edges edges;
  parallel::both([&] { vradius = local_radii(skeleton, mesh.positions, ctx); },
                 [&] { edges = mesh_edges(mesh); }, ctx);
  std::vector<char> fresh(mesh.positions.size(), 1);
  // Per vertex: 1 where a split left it at its edge's midpoint, 2 half way to the surface.
  std::vector<char> off(mesh.positions.size(), 0);
  double spare = 0.0;
  if (options.spare_area > 0.0) {
    for (const auto& t : mesh.triangles) spare += 0.5 * normal_of(mesh, t).norm();
    spare *= options.spare_area;
  }
  // The memory budget caps the triangle budget: a round that would need more memory than the
  // budget allows is not started (budget_reached), rather than refused or run out of memory.
  RefineOptions o = options;
  if (const std::uint64_t budget = memory_budget(ctx); budget > 0) {
    o.max_triangles = std::min<std::size_t>(o.max_triangles, budget / kBytesPerTriangle);
  }
  refine_rounds(mesh, edges, vradius, fresh, off, spare, field, skeleton, nodes, o, ctx, st, true);
  // Then the vertices splits left off the surface that their refined neighbourhood now lets go
  // (reproject_off_surface()), in passes until one moves nothing (a vertex moved can free a
  // neighbour's move), the whole way and else half of it. Doing this after every round instead,
  // so that the next round splits the edges at the vertices moved, gave 0.2-0.5 % more
  // triangles and no smaller deviations on six generated trees. Once after all rounds it left
  // the triangles around a vertex it brought onto the surface as coarse as they were while the
  // vertex was off (none of their edges at it had been split), sagging up to 0.7 local radii
  // between corners on the surface (a twig beside a branch); so each reprojection is followed by
  // rounds on the edges at the vertices it brought onto the surface (settle_fans(), on their
  // fans alone), then another reprojection of what those left off, settle_rounds times at most
  // (+0.02-0.1 % triangles).
  for (int settle = 0; o.reproject; ++settle) {
    const OffFans fans = off_fans(mesh, off);
    if (fans.vertices.empty()) break;
    for (int pass = 0; pass < kReprojectPasses; ++pass) {
      const std::size_t moved = reproject_off_surface(mesh, off, fans, vradius, field, skeleton,
                                                      nodes, o, 1.0, st.reprojected, ctx) +
                                reproject_off_surface(mesh, off, fans, vradius, field, skeleton,
                                                      nodes, o, 0.5, st.reprojected, ctx);
      if (moved == 0) break;
    }
    if (settle >= o.settle_rounds) break;
    std::vector<std::uint32_t> reached;
    for (const std::uint32_t v : fans.vertices)
      if (off[v] == 0) reached.push_back(v);
    if (reached.empty()) break;
    settle_fans(mesh, vradius, off, reached, spare, field, skeleton, nodes, o, ctx, st);
  }
  st.triangles_after = mesh.triangles.size();
  if (stats != nullptr) *stats = st;
}

TriMesh polygonize_to_tolerance(const Field& field, const Skeleton& skeleton,
                                const ToleranceOptions& options, Context* ctx,
                                ToleranceStats* stats) {
  using O = ToleranceOptions;
  if (!(options.tolerance >= O::kMinTolerance && options.tolerance <= O::kMaxTolerance)) {
    throw InvalidArgument("tolerance must be in [" + format_number(O::kMinTolerance) + ", " +
                          format_number(O::kMaxTolerance) + "], got " +
                          format_number(options.tolerance));
  }
  if (options.samples < 100) {
    throw InvalidArgument("tolerance: samples must be >= 100, got " +
                          std::to_string(options.samples));
  }
  if (options.max_passes < 1) {
    throw InvalidArgument("tolerance: max_passes must be >= 1, got " +
                          std::to_string(options.max_passes));
  }
  {
    TriMesh none;  // the improvement's options are refused before the base mesh is made
    improve_triangles(none, field, skeleton, options.improve);
  }
  ToleranceStats st;
  using Clock = std::chrono::steady_clock;
  auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  auto t0 = Clock::now();
  TetrahedralOptions base = options.tets;
  base.crotch_points = true;  // they keep the refinement's splits in crotches on the surface
  // Vertices within |f - iso| <= 1e-4 iso: a few 1e-5 local radii off the surface, three orders
  // of magnitude below the tolerance, and below what the deviation measure resolves. The steps
  // on to the library's 1e-8 were 30 % of the base mesh's root evaluations (studio tree of
  // 4,578 nodes: 2.40 instead of 3.44 per vertex), 9 % of all the field evaluations.
  base.root_value = std::max(base.root_value, kToleranceRootValue);
  TriMesh mesh = polygonize_tetrahedral(field, skeleton, base, ctx, &st.tets);
  st.seconds_tets = since(t0);
  RefineOptions ro;
  ro.edge_tolerance = options.tolerance;
  ro.max_triangles = options.max_triangles;
  DeviationOptions dev;
  dev.samples = options.samples;
  dev.seed = options.seed;
  dev.vertices = false;
  for (int pass = 0; pass < options.max_passes; ++pass) {
    // Edges shorter than sqrt(5 T) radii are not split (0.5 at the default 0.05): such a chord
    // sags by 5 T / 8 on a surface curved like its branch, so a midpoint beyond T there sits
    // next to a fork or a vertex refinement left off the surface, which splitting does not mend.
    // The fixed quarter radius before spent 1.5 % of archi_Tree_1's triangles on them.
    ro.min_edge_radii = std::sqrt(5.0 * ro.edge_tolerance);
    ro.spare_area = pass == 0 ? kSpareShare : 0.0;
    RefineStats rs;
    t0 = Clock::now();
    refine_to_surface(mesh, field, skeleton, ro, ctx, &rs);
    st.seconds_refine += since(t0);
    st.refine.rounds += rs.rounds;
    st.refine.split_edges += rs.split_edges;
    st.refine.flat_splits += rs.flat_splits;
    st.refine.unprojected += rs.unprojected;
    st.refine.reverted += rs.reverted;
    st.refine.halfway += rs.halfway;
    st.refine.reprojected += rs.reprojected;
    st.refine.inherited += rs.inherited;
    st.refine.spared += rs.spared;
    st.refine.budget_reached = st.refine.budget_reached || rs.budget_reached;
    if (pass == 0) st.refine.triangles_before = rs.triangles_before;
    st.refine.triangles_after = rs.triangles_after;
    st.edge_tolerance = ro.edge_tolerance;
    st.passes = pass + 1;
    ImproveOptions io = options.improve;
    io.tolerance = ro.edge_tolerance;
    ImproveStats is;
    t0 = Clock::now();
    improve_triangles(mesh, field, skeleton, io, ctx, &is);
    st.seconds_improve += since(t0);
    accumulate(st.improve, is, pass == 0);
    if (options.on_pass) options.on_pass(mesh);
    t0 = Clock::now();
    st.deviation = measure_deviation(mesh, field, &skeleton, dev, ctx);
    st.seconds_measure += since(t0);
    st.reached = st.deviation.samples.p99 <= options.tolerance;
    if (st.reached || rs.budget_reached) break;
    ro.edge_tolerance *= 0.7;
  }
  if (stats != nullptr) *stats = st;
  return mesh;
}

}  // namespace ramiform
