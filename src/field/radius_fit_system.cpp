// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Assembling a radius fit: the constraint points and the sparse matrix F
// (build_radius_fit_system; the file comment of radius_fit.h).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "field/bvh.h"
#include "field/cutoff.h"
#include "field/radius_fit_detail.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"
#include "ramiform/field/radius_fit.h"

namespace ramiform {
namespace {

// The field's own cut-off (skeleton_field.cpp), so the fitted values are the field's.
using detail::cauchy_segment_reach;
using detail::EdgeGeometry;
using detail::fade_of;
using detail::kRowGrain;
using tol::kSupportMargin;

// Candidate constraint points and the edge whose circle each lies on.
struct Candidates {
  std::vector<Vec3> points;
  std::vector<std::uint32_t> owner;
};

// Station circles, then node circles, edge by edge (a fixed order).
Candidates constraint_candidates(const Skeleton& skeleton, const std::vector<EdgeGeometry>& edges,
                                 const RadiusFitOptions& options) {
  const int stations = options.stations_per_edge;
  const int per_circle = options.points_per_circle;
  const std::vector<std::uint32_t> degree = degrees(skeleton);
  Candidates c;
  auto add_circle = [&](const EdgeGeometry& g, std::uint32_t e, const Vec3& centre, double r,
                        double phase) {
    for (int m = 0; m < per_circle; ++m) {
      const double angle = 2 * std::numbers::pi * (m + phase) / per_circle;
      c.points.push_back(centre + r * (pm::cos(angle) * g.e1 + pm::sin(angle) * g.e2));
      c.owner.push_back(e);
    }
  };
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const EdgeGeometry& g = edges[e];
    for (int k = 0; k < stations; ++k) {
      const double t = (k + 0.5) / stations;
      // Alternate stations are turned by half a step so the points cover more directions.
      add_circle(g, static_cast<std::uint32_t>(e), g.a + t * g.len * g.u, (1 - t) * g.ra + t * g.rb,
                 0.5 * (k % 2));
    }
    for (int end = 0; end < 2; ++end) {
      const bool tip = degree[skeleton.edges[e][end]] == 1;
      if (tip ? options.tip_circles : options.node_circles) {
        add_circle(g, static_cast<std::uint32_t>(e), end == 0 ? g.a : g.b, end == 0 ? g.ra : g.rb,
                   0.25);
      }
    }
  }
  return c;
}

// The candidates outside every other edge's requested tube become the system's points.
void keep_outside_tubes(const Candidates& c, const std::vector<EdgeGeometry>& edges,
                        RadiusFitSystem& sys, const Context* ctx) {
  const detail::TubeIndex tubes(edges);
  std::vector<char> keep(c.points.size(), 0);
  parallel::for_chunks(
      c.points.size(), kRowGrain,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t> ids;
        for (std::size_t j = begin; j < end; ++j)
          keep[j] = tubes.inside_other(c.points[j], c.owner[j], ids) ? 0 : 1;
      },
      ctx);
  for (std::size_t j = 0; j < c.points.size(); ++j) {
    if (keep[j] != 0) {
      sys.points.push_back(c.points[j]);
      sys.point_edge.push_back(c.owner[j]);
    }
  }
}

// One edge's primitive at unit weight, with lambda, s and the cut-off exactly as
// skeleton_field.cpp builds them (so that sum_i w_i F(j, i) is the field with weights w, up to
// the fade window, whose width grows with the weight).
struct EdgePrimitive {
  double s = 1, lambda = 1, inv_cut = 0;
  double near2 = 0;  // squared distance within which the contribution is "near"
};

struct Primitives {
  std::vector<EdgePrimitive> prims;
  std::vector<Aabb> supports;  // per edge, the box of its near part (empty: never near)
};

Primitives edge_primitives(const std::vector<EdgeGeometry>& edges, const SkeletonFieldOptions& fo,
                           const RadiusFitOptions& options) {
  const std::size_t n = edges.size();
  const double c = fo.kernel.shape();
  const double floor_value = tol::kKernelCutoff * fo.iso;
  const double near_value = std::max(options.near_level, tol::kKernelCutoff) * fo.iso;
  Primitives out;
  out.prims.resize(n);
  out.supports.resize(n);
  for (std::size_t e = 0; e < n; ++e) {
    const EdgeGeometry& g = edges[e];
    EdgePrimitive& pr = out.prims[e];
    const double r = 0.5 * (g.ra + g.rb);
    pr.s = c / r;
    pr.lambda = 2 * c * fo.iso * pm::pow(1 + c * c, 1.5) / (std::numbers::pi * r);
    const double reach = cauchy_segment_reach(pr.s, g.len, pr.lambda, floor_value);
    // The near part: where the edge's upper bound reaches near_level * iso.
    const double near = std::min(reach, cauchy_segment_reach(pr.s, g.len, pr.lambda, near_value));
    Aabb box;         // empty: never found
    if (reach > 0) {  // else the field drops the primitive, and so does F
      pr.inv_cut = 1 / (reach * reach);
      pr.near2 = near * near;
      box.extend(g.a);
      box.extend(g.b);
      box.min().array() -= near * (1 + kSupportMargin);
      box.max().array() += near * (1 + kSupportMargin);
    }
    out.supports[e] = box;
  }
  return out;
}

// Row-major CSR pieces of a chunk of rows.
struct RowChunk {
  std::vector<int> count;
  std::vector<int> cols;
  std::vector<double> vals;
};

// Row j of F: the near contributions at point p, columns ascending.
void append_row(const Vec3& p, const std::vector<EdgeGeometry>& edges, const Primitives& pr_all,
                const detail::BoxBvh& bvh, std::vector<std::uint32_t>& ids, RowChunk& rc) {
  ids.clear();
  bvh.query(Aabb(p, p), ids);
  std::sort(ids.begin(), ids.end());
  int count = 0;
  for (const std::uint32_t e : ids) {
    const EdgeGeometry& g = edges[e];
    const EdgePrimitive& pr = pr_all.prims[e];
    const Vec3 w = p - g.a;
    const double tc = std::clamp(w.dot(g.u), 0.0, g.len);
    const double d2 = (w - tc * g.u).squaredNorm();
    if (d2 >= pr.near2) continue;
    const double fade = fade_of(d2 * pr.inv_cut);
    if (fade <= 0) continue;
    const double v = pr.lambda * cauchy_segment_integral(p, g.a, g.b, pr.s) * fade;
    if (v <= 0) continue;
    rc.cols.push_back(static_cast<int>(e));
    rc.vals.push_back(v);
    ++count;
  }
  rc.count.push_back(count);
}

// Rows in fixed chunks (in parallel).
std::vector<RowChunk> matrix_rows(const std::vector<Vec3>& points,
                                  const std::vector<EdgeGeometry>& edges, const Primitives& prims,
                                  const Context* ctx) {
  const detail::BoxBvh bvh(prims.supports);
  const std::size_t m = points.size();
  const std::size_t chunk_count = (m + kRowGrain - 1) / kRowGrain;
  std::vector<RowChunk> chunks(chunk_count);
  parallel::for_each(
      chunk_count, 1,
      [&](std::size_t ci) {
        std::vector<std::uint32_t> ids;
        const std::size_t begin = ci * kRowGrain;
        const std::size_t end = std::min(m, begin + kRowGrain);
        for (std::size_t j = begin; j < end; ++j)
          append_row(points[j], edges, prims, bvh, ids, chunks[ci]);
      },
      ctx);
  return chunks;
}

// The chunks, in order, as the m x n matrix.
void assemble(const std::vector<RowChunk>& chunks, std::size_t m, std::size_t n,
              Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix) {
  std::size_t nnz = 0;
  for (const RowChunk& rc : chunks) nnz += rc.vals.size();
  matrix.resize(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(n));
  matrix.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = matrix.outerIndexPtr();
  int* inner = matrix.innerIndexPtr();
  double* values = matrix.valuePtr();
  std::size_t row = 0, at = 0;
  outer[0] = 0;
  for (const RowChunk& rc : chunks) {
    std::copy(rc.cols.begin(), rc.cols.end(), inner + at);
    std::copy(rc.vals.begin(), rc.vals.end(), values + at);
    at += rc.vals.size();
    for (const int cnt : rc.count) {
      outer[row + 1] = outer[row] + cnt;
      ++row;
    }
  }
}

}  // namespace

RadiusFitSystem build_radius_fit_system(const Skeleton& skeleton,
                                        const SkeletonFieldOptions& field_options,
                                        const RadiusFitOptions& options, Context* ctx) {
  options.validate();
  const SkeletonFieldOptions fo = field_options.resolved();
  if (fo.surface != SurfaceKind::kConvolution) {
    throw InvalidArgument("radius fit: needs a convolution surface (the Cauchy kernel)");
  }
  validate(skeleton);
  const std::vector<EdgeGeometry> edges = detail::edge_geometry(skeleton);
  RadiusFitSystem sys;
  sys.iso = fo.iso;
  sys.skeleton = skeleton;
  sys.field_options = fo;
  if (ctx != nullptr) ctx->report("radius fit: constraints", 0);
  keep_outside_tubes(constraint_candidates(skeleton, edges, options), edges, sys, ctx);
  if (ctx != nullptr) ctx->report("radius fit: matrix", 0);
  const Primitives prims = edge_primitives(edges, fo, options);
  assemble(matrix_rows(sys.points, edges, prims, ctx), sys.points.size(), edges.size(), sys.matrix);
  return sys;
}

}  // namespace ramiform
