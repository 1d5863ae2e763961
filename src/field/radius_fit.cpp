// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/radius_fit.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>

#include "field/bvh.h"
#include "field/cutoff.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using SparseCol = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using SparseRow = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
// The field's own cut-off (skeleton_field.cpp), so the fitted values are the field's.
using detail::cauchy_segment_reach;
using detail::fade_of;
using tol::kSupportMargin;

// A point counts as inside another edge's requested tube only when it is deeper than this
// fraction of that tube's radius: circles of a straight chain's shared node lie exactly on both
// tubes, and rounding must not decide whether they are kept.
constexpr double kInsideMargin = 1e-3;
// Points per parallel chunk when building rows and checking tubes.
constexpr std::size_t kRowGrain = 512;

// One edge as the convolution field sees it.
struct EdgeGeometry {
  Vec3 a, b, u, e1, e2;  // end points, unit direction, unit frame perpendicular to u
  double len = 0, ra = 1, rb = 1;
};

Vec3 perpendicular(const Vec3& d) {
  const Vec3 helper = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return d.cross(helper).normalized();
}

std::vector<EdgeGeometry> edge_geometry(const Skeleton& skeleton) {
  std::vector<EdgeGeometry> out(skeleton.edges.size());
  for (std::size_t e = 0; e < out.size(); ++e) {
    EdgeGeometry& g = out[e];
    const auto& na = skeleton.nodes[skeleton.edges[e][0]];
    const auto& nb = skeleton.nodes[skeleton.edges[e][1]];
    g.a = na.position;
    g.b = nb.position;
    g.ra = na.radius;
    g.rb = nb.radius;
    g.len = (g.b - g.a).norm();
    g.u = (g.b - g.a) / g.len;  // validate() rejects zero-length edges
    g.e1 = perpendicular(g.u);
    g.e2 = g.u.cross(g.e1);
  }
  return out;
}

// The requested shape: the union of the tubes {p : d(p, segment) < r(t*)}, t* the closest
// point parameter (clamped, so the tube ends in spheres of the node radii).
class TubeIndex {
 public:
  explicit TubeIndex(const std::vector<EdgeGeometry>& edges) : edges_(edges) {
    std::vector<Aabb> boxes(edges.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
      Aabb box;
      box.extend(edges[e].a);
      box.extend(edges[e].b);
      const double r = std::max(edges[e].ra, edges[e].rb);
      box.min().array() -= r;
      box.max().array() += r;
      boxes[e] = box;
    }
    bvh_ = detail::BoxBvh(std::move(boxes));
  }

  // Edges whose tube box meets `box`, appended to ids (unordered).
  void query(const Aabb& box, std::vector<std::uint32_t>& ids) const { bvh_.query(box, ids); }

  // True when p is deeper than kInsideMargin inside the requested tube of edge e.
  bool inside(const Vec3& p, std::uint32_t e) const {
    const EdgeGeometry& g = edges_[e];
    const double t = std::clamp((p - g.a).dot(g.u) / g.len, 0.0, 1.0);
    const double r = (1 - t) * g.ra + t * g.rb;
    return (p - (g.a + t * g.len * g.u)).norm() < r * (1 - kInsideMargin);
  }

  // True when p is deeper than kInsideMargin inside the requested tube of an edge other than
  // `own`.
  bool inside_other(const Vec3& p, std::uint32_t own, std::vector<std::uint32_t>& ids) const {
    ids.clear();
    bvh_.query(Aabb(p, p), ids);
    for (const std::uint32_t e : ids) {
      if (e != own && inside(p, e)) return true;
    }
    return false;
  }

 private:
  const std::vector<EdgeGeometry>& edges_;
  detail::BoxBvh bvh_;
};

// One edge's primitive at unit weight, with lambda, s and the cut-off exactly as
// skeleton_field.cpp builds them (so that sum_i w_i F(j, i) is the field with weights w, up to
// the fade window, whose width grows with the weight).
struct EdgePrimitive {
  double s = 1, lambda = 1, inv_cut = 0;
  double near2 = 0;  // squared distance within which the contribution is "near"
};

// Row-major CSR pieces of a chunk of rows.
struct RowChunk {
  std::vector<int> count;
  std::vector<int> cols;
  std::vector<double> vals;
};

void check_positive_int(int v, int min, const std::string& what) {
  if (v < min)
    throw InvalidArgument(what + " must be >= " + std::to_string(min) + ", got " +
                          std::to_string(v));
}

// ---------------------------------------------------------------------------------------------
// NNLS on normal equations: min 1/2 w^T N w - b^T w subject to w >= 0.

struct NnlsProblem {
  SparseCol lower;            // N, lower triangle (column-major)
  Eigen::VectorXd rhs;        // b
  Eigen::VectorXd diagonal;   // N_ii
  std::vector<char> is_free;  // the unknown takes part (N_ii > 0); the others keep their value

  [[nodiscard]] Eigen::VectorXd times(const Eigen::VectorXd& x) const {
    return lower.selfadjointView<Eigen::Lower>() * x;
  }
  [[nodiscard]] bool free(Eigen::Index i) const {
    return is_free[static_cast<std::size_t>(i)] != 0;
  }
};

// N = F^T diag(omega) F + mu diag(|F_i|^2_omega), b = F^T omega t + mu |F_i|^2_omega, column by
// column in parallel; every entry is summed over the rows in ascending order, so the result is
// the same for any thread count.
NnlsProblem normal_equations(const SparseRow& F, const SparseCol& Fc, const Eigen::VectorXd& omega,
                             const Eigen::VectorXd& target, double mu, const Context* ctx) {
  const auto n = static_cast<int>(F.cols());
  NnlsProblem p;
  p.rhs = Eigen::VectorXd::Zero(n);
  p.diagonal = Eigen::VectorXd::Zero(n);
  p.is_free.assign(static_cast<std::size_t>(n), 0);
  constexpr std::size_t kColumnGrain = 64;
  const std::size_t chunk_count = (static_cast<std::size_t>(n) + kColumnGrain - 1) / kColumnGrain;
  struct ColumnChunk {
    std::vector<int> count, rows;
    std::vector<double> vals;
  };
  std::vector<ColumnChunk> chunks(chunk_count);
  parallel::for_each(
      chunk_count, 1,
      [&](std::size_t ci) {
        ColumnChunk& cc = chunks[ci];
        std::vector<double> acc(static_cast<std::size_t>(n), 0.0);
        std::vector<char> touched(static_cast<std::size_t>(n), 0);
        std::vector<int> list;
        const int begin = static_cast<int>(ci * kColumnGrain);
        const int end = std::min(n, begin + static_cast<int>(kColumnGrain));
        for (int i = begin; i < end; ++i) {
          double b = 0;
          for (SparseCol::InnerIterator it(Fc, i); it; ++it) {
            const auto j = static_cast<int>(it.row());
            const double a = omega[j] * it.value();
            b += a * target[j];
            const int* cols = F.innerIndexPtr() + F.outerIndexPtr()[j];
            const double* vals = F.valuePtr() + F.outerIndexPtr()[j];
            const int len = F.outerIndexPtr()[j + 1] - F.outerIndexPtr()[j];
            for (int q = static_cast<int>(std::lower_bound(cols, cols + len, i) - cols); q < len;
                 ++q) {
              const auto k = static_cast<std::size_t>(cols[q]);
              if (touched[k] == 0) {
                touched[k] = 1;
                list.push_back(cols[q]);
              }
              acc[k] += a * vals[q];
            }
          }
          // Every column stores its diagonal (0 for an edge no constraint sees), so that the
          // pivoting solver can factorize one fixed pattern.
          if (touched[static_cast<std::size_t>(i)] == 0) list.push_back(i);
          std::sort(list.begin(), list.end());
          const double d = acc[static_cast<std::size_t>(i)];
          p.diagonal[i] = d;
          p.rhs[i] = b + mu * d;
          if (d > 0) p.is_free[static_cast<std::size_t>(i)] = 1;
          for (const int k : list) {
            double v = acc[static_cast<std::size_t>(k)];
            if (k == i) v += mu * d;
            cc.rows.push_back(k);
            cc.vals.push_back(v);
            acc[static_cast<std::size_t>(k)] = 0;
            touched[static_cast<std::size_t>(k)] = 0;
          }
          cc.count.push_back(static_cast<int>(list.size()));
          list.clear();
        }
      },
      ctx);
  std::size_t nnz = 0;
  for (const auto& cc : chunks) nnz += cc.vals.size();
  p.lower.resize(n, n);
  p.lower.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = p.lower.outerIndexPtr();
  outer[0] = 0;
  std::size_t at = 0;
  int col = 0;
  for (const auto& cc : chunks) {
    std::copy(cc.rows.begin(), cc.rows.end(), p.lower.innerIndexPtr() + at);
    std::copy(cc.vals.begin(), cc.vals.end(), p.lower.valuePtr() + at);
    at += cc.vals.size();
    for (const int c : cc.count) {
      outer[col + 1] = outer[col] + c;
      ++col;
    }
  }
  p.diagonal *= 1 + mu;
  return p;
}

// Largest scaled KKT violation of w (infinite for a negative weight).
double kkt_violation(const NnlsProblem& p, const Eigen::VectorXd& w) {
  const Eigen::VectorXd g = p.times(w) - p.rhs;
  double worst = 0;
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    if (!p.free(i)) continue;
    const double scaled = g[i] / p.diagonal[i];
    if (w[i] < 0) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, w[i] > 0 ? std::abs(scaled) : -scaled);
  }
  return worst;
}

struct NnlsOutcome {
  Eigen::VectorXd w;
  int iterations = 0;
};

// Lawson–Hanson active set on dense normal equations (Bro & De Jong's cross-product form).
// Unknowns that do not take part (zero columns of F) keep their start value; their rows and
// columns of N are zero.
NnlsOutcome lawson_hanson(const NnlsProblem& p, const Eigen::VectorXd& start, double tol,
                          int max_iterations, const Context* ctx) {
  const Eigen::MatrixXd N = Eigen::MatrixXd(SparseCol(p.lower.selfadjointView<Eigen::Lower>()));
  const Eigen::Index n = N.rows();
  NnlsOutcome out;
  out.w = start;
  std::vector<char> passive(static_cast<std::size_t>(n), 0);
  auto in_p = [&](Eigen::Index i) { return passive[static_cast<std::size_t>(i)] != 0; };
  for (Eigen::Index i = 0; i < n; ++i) {
    if (p.free(i)) out.w[i] = 0;
  }
  // z = the minimizer over the passive set, the other free unknowns held at 0.
  auto solve_passive = [&](Eigen::VectorXd& z) {
    std::vector<Eigen::Index> idx;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (in_p(i)) idx.push_back(i);
    }
    const auto k = static_cast<Eigen::Index>(idx.size());
    Eigen::MatrixXd A(k, k);
    Eigen::VectorXd r(k);
    for (Eigen::Index x = 0; x < k; ++x) {
      r[x] = p.rhs[idx[x]];
      for (Eigen::Index y = 0; y < k; ++y) A(x, y) = N(idx[x], idx[y]);
    }
    const Eigen::VectorXd sol = A.ldlt().solve(r);
    z = out.w;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (p.free(i)) z[i] = 0;
    }
    for (Eigen::Index x = 0; x < k; ++x) z[idx[x]] = sol[x];
  };
  while (out.iterations < max_iterations) {
    check_cancel(ctx);
    // Negative gradient; the free, non-passive unknown that most wants to grow enters.
    const Eigen::VectorXd g = p.rhs - N * out.w;
    Eigen::Index best = -1;
    double best_value = tol;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!p.free(i) || in_p(i)) continue;
      const double scaled = g[i] / p.diagonal[i];
      if (scaled > best_value) {
        best_value = scaled;
        best = i;
      }
    }
    if (best < 0) break;
    passive[static_cast<std::size_t>(best)] = 1;
    ++out.iterations;
    // Inner loop: step toward the passive-set solution until it is feasible; the unknowns that
    // the step drives to 0 leave the passive set.
    Eigen::VectorXd z;
    for (;;) {
      solve_passive(z);
      double alpha = 1;
      Eigen::Index blocking = -1;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (in_p(i) && z[i] <= 0) {
          const double a = out.w[i] / (out.w[i] - z[i]);
          if (blocking < 0 || a < alpha) {
            alpha = a;
            blocking = i;
          }
        }
      }
      if (blocking < 0) break;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (!in_p(i)) continue;
        out.w[i] += alpha * (z[i] - out.w[i]);
        if (i == blocking || out.w[i] <= 0) {
          out.w[i] = 0;
          passive[static_cast<std::size_t>(i)] = 0;
        }
      }
      if (++out.iterations >= max_iterations) return out;
    }
    out.w = z;
  }
  return out;
}

// Block principal pivoting (Kim & Park 2011, after Júdice & Pires 1994) with a sparse LDL^T.
// Starts from the free set {start > 0}, exchanges every infeasible unknown at once while that
// shrinks the infeasible set, and falls back to Murty's single exchange of the largest
// infeasible index after three steps that do not (which terminates). The unknowns held at 0
// keep their rows and columns in the matrix as unit rows (zero off the diagonal), so every
// step factorizes the same pattern: the fill-reducing ordering is computed once.
NnlsOutcome block_pivoting(const NnlsProblem& p, const Eigen::VectorXd& start, double tol,
                           int max_iterations, const Context* ctx) {
  const auto n = static_cast<int>(p.rhs.size());
  NnlsOutcome out;
  out.w = start;
  std::vector<char> in_f(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; ++i) in_f[static_cast<std::size_t>(i)] = p.free(i) && start[i] > 0 ? 1 : 0;
  auto is_in_f = [&](Eigen::Index i) { return in_f[static_cast<std::size_t>(i)] != 0; };
  int backup = 3;
  std::size_t best_infeasible = static_cast<std::size_t>(n) + 1;
  Eigen::SimplicialLDLT<SparseCol, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  SparseCol work = p.lower;
  ldlt.analyzePattern(work);
  while (out.iterations < max_iterations) {
    check_cancel(ctx);
    ++out.iterations;
    // The free block, with unit rows for the others.
    const double* src = p.lower.valuePtr();
    double* dst = work.valuePtr();
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    for (int c = 0; c < n; ++c) {
      const bool keep_col = is_in_f(c);
      if (keep_col) r[c] = p.rhs[c];
      for (int q = work.outerIndexPtr()[c]; q < work.outerIndexPtr()[c + 1]; ++q) {
        const int row = work.innerIndexPtr()[q];
        dst[q] = row == c ? (keep_col ? src[q] : 1.0) : (keep_col && is_in_f(row) ? src[q] : 0.0);
      }
    }
    ldlt.factorize(work);
    if (ldlt.info() != Eigen::Success) break;  // not positive definite: the KKT check reports it
    Eigen::VectorXd x = ldlt.solve(r);
    x += ldlt.solve(r - work.selfadjointView<Eigen::Lower>() * x);  // one step of refinement
    for (int i = 0; i < n; ++i) {
      if (!p.free(i))
        x[i] = start[i];  // edges without data keep their value
      else if (!is_in_f(i))
        x[i] = 0;
    }
    const Eigen::VectorXd y = p.times(x) - p.rhs;
    std::vector<int> infeasible;
    for (int i = 0; i < n; ++i) {
      if (!p.free(i)) continue;
      if (is_in_f(i) ? x[i] < 0 : y[i] < -tol * p.diagonal[i]) infeasible.push_back(i);
    }
    // The projection of x is the feasible iterate returned if the limit stops the pivoting.
    out.w = x.cwiseMax(0.0);
    if (infeasible.empty()) return out;
    if (infeasible.size() < best_infeasible) {
      best_infeasible = infeasible.size();
      backup = 3;
    } else if (backup > 0) {
      --backup;
    } else {
      infeasible = {infeasible.back()};
    }
    for (const int i : infeasible) in_f[static_cast<std::size_t>(i)] ^= 1;
  }
  return out;
}

}  // namespace

void RadiusFitOptions::validate() const {
  check_positive_int(stations_per_edge, 1, "stations_per_edge");
  check_positive_int(points_per_circle, 3, "points_per_circle");
  if (!std::isfinite(regularization) || regularization < 0) {
    throw InvalidArgument("regularization must be finite and >= 0, got " +
                          std::to_string(regularization));
  }
  if (!std::isfinite(kkt_tolerance) || kkt_tolerance <= 0) {
    throw InvalidArgument("kkt_tolerance must be finite and > 0, got " +
                          std::to_string(kkt_tolerance));
  }
  check_positive_int(max_iterations, 0, "max_iterations");
  if (!std::isfinite(robust_threshold) || robust_threshold < 0) {
    throw InvalidArgument("robust_threshold must be finite and >= 0, got " +
                          std::to_string(robust_threshold));
  }
  check_positive_int(outer_rounds, 0, "outer_rounds");
  if (!std::isfinite(coverage_margin) || coverage_margin < 0) {
    throw InvalidArgument("coverage_margin must be finite and >= 0, got " +
                          std::to_string(coverage_margin));
  }
  if (!std::isfinite(min_weight) || min_weight < 0 || min_weight >= 1) {
    throw InvalidArgument("min_weight must be in [0, 1), got " + std::to_string(min_weight));
  }
  if (!std::isfinite(near_level) || near_level < 0 || near_level >= 1) {
    throw InvalidArgument("near_level must be in [0, 1), got " + std::to_string(near_level));
  }
}

RadiusFitSystem build_radius_fit_system(const Skeleton& skeleton,
                                        const SkeletonFieldOptions& field_options,
                                        const RadiusFitOptions& options, Context* ctx) {
  options.validate();
  const SkeletonFieldOptions fo = field_options.resolved();
  if (fo.surface != SurfaceKind::kConvolution) {
    throw InvalidArgument("radius fit: needs a convolution surface (the Cauchy kernel)");
  }
  validate(skeleton);
  const std::vector<EdgeGeometry> edges = edge_geometry(skeleton);
  const std::size_t n = edges.size();
  RadiusFitSystem sys;
  sys.iso = fo.iso;
  sys.skeleton = skeleton;
  sys.field_options = fo;
  if (ctx != nullptr) ctx->report("radius fit: constraints", 0);

  // Candidate points: station circles, then node circles, edge by edge (a fixed order).
  const int stations = options.stations_per_edge;
  const int per_circle = options.points_per_circle;
  const std::vector<std::uint32_t> degree = degrees(skeleton);
  std::vector<Vec3> candidates;
  std::vector<std::uint32_t> owner;
  auto add_circle = [&](const EdgeGeometry& g, std::uint32_t e, const Vec3& centre, double r,
                        double phase) {
    for (int m = 0; m < per_circle; ++m) {
      const double angle = 2 * std::numbers::pi * (m + phase) / per_circle;
      candidates.push_back(centre + r * (std::cos(angle) * g.e1 + std::sin(angle) * g.e2));
      owner.push_back(e);
    }
  };
  for (std::size_t e = 0; e < n; ++e) {
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
  // Drop candidates inside another edge's requested tube.
  const TubeIndex tubes(edges);
  std::vector<char> keep(candidates.size(), 0);
  parallel::for_chunks(
      candidates.size(), kRowGrain,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t> ids;
        for (std::size_t j = begin; j < end; ++j)
          keep[j] = tubes.inside_other(candidates[j], owner[j], ids) ? 0 : 1;
      },
      ctx);
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    if (keep[j] != 0) {
      sys.points.push_back(candidates[j]);
      sys.point_edge.push_back(owner[j]);
    }
  }
  if (ctx != nullptr) ctx->report("radius fit: matrix", 0);

  // The primitives, as skeleton_field.cpp builds them at unit weight.
  const double c = fo.kernel.shape();
  const double floor_value = tol::kKernelCutoff * fo.iso;
  const double near_value = std::max(options.near_level, tol::kKernelCutoff) * fo.iso;
  std::vector<EdgePrimitive> prims(n);
  std::vector<Aabb> supports(n);
  for (std::size_t e = 0; e < n; ++e) {
    const EdgeGeometry& g = edges[e];
    EdgePrimitive& pr = prims[e];
    const double r = 0.5 * (g.ra + g.rb);
    pr.s = c / r;
    pr.lambda = 2 * c * fo.iso * std::pow(1 + c * c, 1.5) / (std::numbers::pi * r);
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
    supports[e] = box;
  }
  const detail::BoxBvh bvh(supports);

  // Rows in fixed chunks (in parallel), each row's columns ascending.
  const std::size_t m = sys.points.size();
  const std::size_t chunk_count = (m + kRowGrain - 1) / kRowGrain;
  std::vector<RowChunk> chunks(chunk_count);
  parallel::for_each(
      chunk_count, 1,
      [&](std::size_t ci) {
        RowChunk& rc = chunks[ci];
        std::vector<std::uint32_t> ids;
        const std::size_t begin = ci * kRowGrain;
        const std::size_t end = std::min(m, begin + kRowGrain);
        for (std::size_t j = begin; j < end; ++j) {
          const Vec3& p = sys.points[j];
          ids.clear();
          bvh.query(Aabb(p, p), ids);
          std::sort(ids.begin(), ids.end());
          int count = 0;
          for (const std::uint32_t e : ids) {
            const EdgeGeometry& g = edges[e];
            const EdgePrimitive& pr = prims[e];
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
      },
      ctx);
  std::size_t nnz = 0;
  for (const RowChunk& rc : chunks) nnz += rc.vals.size();
  sys.matrix.resize(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(n));
  sys.matrix.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = sys.matrix.outerIndexPtr();
  int* inner = sys.matrix.innerIndexPtr();
  double* values = sys.matrix.valuePtr();
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
  return sys;
}

namespace {

// The skeleton coverage repair of RadiusFitOptions::coverage_margin: samples every half radius
// along every edge (ends included), raises the weights of edges with a sample below the level.
void cover_skeleton(const RadiusFitSystem& system, const RadiusFitOptions& options,
                    Eigen::VectorXd& w, RadiusFitResult& result, Context* ctx) {
  if (options.coverage_margin <= 0) return;
  constexpr int kRounds = 12;
  constexpr double kRaise = 1.25;
  const Skeleton& s = system.skeleton;
  std::vector<Vec3> samples;
  std::vector<std::uint32_t> sample_edge;
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    const auto& a = s.nodes[s.edges[e][0]];
    const auto& b = s.nodes[s.edges[e][1]];
    const double len = (b.position - a.position).norm();
    const int k = std::max(1, static_cast<int>(std::ceil(len / (0.5 * std::min(a.radius, b.radius)))));
    for (int i = 0; i <= k; ++i) {
      const double t = static_cast<double>(i) / k;
      samples.push_back((1 - t) * a.position + t * b.position);
      sample_edge.push_back(e);
    }
  }
  const double level = (1 + options.coverage_margin) * system.iso;
  std::vector<double> f(samples.size());
  std::vector<char> raised(s.edges.size(), 0);
  const auto n = static_cast<std::size_t>(w.size());
  for (int round = 0;; ++round) {
    check_cancel(ctx);
    const FieldPtr field = make_skeleton_field(s, system.field_options,
                                               std::span<const double>(w.data(), n));
    field->evaluate(samples, f);
    std::vector<char> low(s.edges.size(), 0);
    bool any = false;
    for (std::size_t j = 0; j < samples.size(); ++j) {
      if (f[j] < level) low[sample_edge[j]] = 1, any = true;
    }
    if (!any) break;
    if (round == kRounds) {
      result.covered = false;
      break;
    }
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
      if (low[e] == 0) continue;
      w[static_cast<Eigen::Index>(e)] = std::max(w[static_cast<Eigen::Index>(e)] * kRaise, 0.25);
      raised[e] = 1;
    }
    result.coverage_rounds = round + 1;
  }
  result.coverage_raised = static_cast<std::size_t>(std::count(raised.begin(), raised.end(), 1));
}

}  // namespace

RadiusFitResult solve_radius_fit(const RadiusFitSystem& system, const RadiusFitOptions& options,
                                 Context* ctx) {
  options.validate();
  const SparseRow& F = system.matrix;
  const auto n = static_cast<int>(F.cols());
  const Eigen::Index m = F.rows();
  const double T = system.iso;
  if (static_cast<std::size_t>(n) != system.skeleton.edges.size() ||
      static_cast<std::size_t>(m) != system.points.size()) {
    throw InvalidArgument("radius fit: system matrix does not match its skeleton and points");
  }
  RadiusFitResult result;
  result.constraint_points = static_cast<std::size_t>(m);
  result.nonzeros = static_cast<std::size_t>(F.nonZeros());
  const SparseCol Fc(F);
  const bool dense =
      options.solver == NnlsSolver::kDense ||
      (options.solver == NnlsSolver::kAuto && static_cast<std::size_t>(n) <= options.dense_limit);
  const int max_iterations = options.max_iterations > 0 ? options.max_iterations : 3 * n + 10;
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);  // edges without data keep 1
  Eigen::VectorXd omega = Eigen::VectorXd::Ones(m);
  Eigen::VectorXd offset = Eigen::VectorXd::Zero(m);
  // The field itself at the constraint points, with weights w.
  std::vector<double> f(static_cast<std::size_t>(m));
  auto evaluate_field = [&](const Eigen::VectorXd& weights) {
    const FieldPtr field =
        make_skeleton_field(system.skeleton, system.field_options,
                            std::span<const double>(weights.data(), static_cast<std::size_t>(n)));
    field->evaluate(system.points, f);
  };
  auto rms = [&]() {
    double sum = 0;
    for (const double v : f) sum += (v - T) * (v - T);
    return m > 0 ? std::sqrt(sum / static_cast<double>(m)) / T : 0.0;
  };
  // Every round evaluates the field with the current weights; what F (the near part) does not
  // hold becomes a fixed offset per row, and with robust_threshold > 0 the rows are reweighted
  // for Huber's loss (iteratively reweighted least squares): rows whose residual exceeds the
  // threshold (webbing between branches at a joint, tips: errors no weight removes) get weight
  // threshold / |residual|, so they stop dictating the weights of everything else.
  for (int round = 0; round <= options.outer_rounds; ++round) {
    check_cancel(ctx);
    if (ctx != nullptr)
      ctx->report("radius fit: solve", static_cast<double>(round) / (options.outer_rounds + 1));
    evaluate_field(w);
    if (round == 0) result.unit_residual_rms = rms();
    const Eigen::VectorXd near = F * w;
    for (Eigen::Index j = 0; j < m; ++j) {
      const double fj = f[static_cast<std::size_t>(j)];
      offset[j] = fj - near[j];
      if (round > 0 && options.robust_threshold > 0) {
        const double r = std::abs(fj - T) / T;
        omega[j] = r <= options.robust_threshold ? 1.0 : options.robust_threshold / r;
      }
    }
    // Bounded below by l = min_weight: solve for v = w - l >= 0, with the target lowered by
    // F l and the regularization pulling v toward 1 - l.
    const double low = options.min_weight;
    const Eigen::VectorXd floor_near = F * Eigen::VectorXd::Constant(n, low);
    NnlsProblem p = normal_equations(F, Fc, omega,
                                     Eigen::VectorXd::Constant(m, T) - offset - floor_near,
                                     options.regularization, ctx);
    for (int i = 0; i < n; ++i) {
      p.rhs[i] -= options.regularization * low * p.diagonal[i] / (1 + options.regularization);
    }
    // Warm start: the sparse solver begins with the previous round's positive weights free.
    const Eigen::VectorXd start = (w.array() - low).max(0.0).matrix();
    const NnlsOutcome outcome =
        dense ? lawson_hanson(p, start, options.kkt_tolerance, max_iterations, ctx)
              : block_pivoting(p, start, options.kkt_tolerance, max_iterations, ctx);
    result.iterations += outcome.iterations;
    result.kkt_violation = kkt_violation(p, outcome.w);
    w = (outcome.w.array() + low).matrix();
  }
  result.converged = result.kkt_violation <= options.kkt_tolerance;
  cover_skeleton(system, options, w, result, ctx);
  result.weights.assign(w.data(), w.data() + n);
  result.row_offset.assign(offset.data(), offset.data() + m);
  result.row_weight.assign(omega.data(), omega.data() + m);
  evaluate_field(w);
  result.residual_rms = rms();
  if (ctx != nullptr) ctx->report("radius fit: solve", 1);
  return result;
}

RadiusFitResult fit_edge_weights(const Skeleton& skeleton,
                                 const SkeletonFieldOptions& field_options,
                                 const RadiusFitOptions& options, Context* ctx) {
  const RadiusFitSystem system = build_radius_fit_system(skeleton, field_options, options, ctx);
  return solve_radius_fit(system, options, ctx);
}

// ---------------------------------------------------------------------------------------------

SplitSkeleton split_edges(const Skeleton& skeleton, const EdgeSplitOptions& options) {
  if (!std::isfinite(options.max_length) || options.max_length <= 0) {
    throw InvalidArgument("max_length must be finite and > 0, got " +
                          std::to_string(options.max_length));
  }
  if (!(options.max_taper > 0 && options.max_taper < 1)) {
    throw InvalidArgument("max_taper must be in (0, 1), got " + std::to_string(options.max_taper));
  }
  check_positive_int(options.max_pieces, 1, "max_pieces");
  validate(skeleton);
  SplitSkeleton out;
  out.skeleton.nodes = skeleton.nodes;
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto [ia, ib] = skeleton.edges[e];
    const SkeletonNode& na = skeleton.nodes[ia];
    const SkeletonNode& nb = skeleton.nodes[ib];
    const double len = (nb.position - na.position).norm();
    // Split radii in geometric progression r_k = r_a q^k, q = (r_b / r_a)^(1/k): along a
    // linear taper every piece then has the same taper 1 - min(q, 1/q) and the same ratio of
    // length to mean radius, len 2 |q - 1| / ((q + 1) |r_b - r_a|) (len / r without taper).
    // The smallest k that meets both limits:
    const double ratio = std::max(na.radius, nb.radius) / std::min(na.radius, nb.radius);
    const bool tapered = ratio > 1 + 1e-12;
    auto length_ratio = [&](int k) {
      if (!tapered) return len / (k * na.radius);
      const double q = std::pow(nb.radius / na.radius, 1.0 / k);
      return len * 2 * std::abs(q - 1) / ((q + 1) * std::abs(nb.radius - na.radius));
    };
    int pieces =
        tapered
            ? static_cast<int>(std::ceil(std::log(ratio) / -std::log1p(-options.max_taper) - 1e-9))
            : 1;
    pieces = std::max(pieces, 1);
    while (pieces < options.max_pieces && length_ratio(pieces) > options.max_length) ++pieces;
    pieces = std::min(pieces, options.max_pieces);
    std::uint32_t prev = ia;
    for (int k = 1; k < pieces; ++k) {
      double t = static_cast<double>(k) / pieces;
      if (tapered) {
        const double r = na.radius * std::pow(nb.radius / na.radius, t);
        t = (r - na.radius) / (nb.radius - na.radius);
      }
      out.skeleton.nodes.push_back(
          {(1 - t) * na.position + t * nb.position, (1 - t) * na.radius + t * nb.radius});
      const auto node = static_cast<std::uint32_t>(out.skeleton.nodes.size() - 1);
      out.skeleton.edges.push_back({prev, node});
      out.edge_origin.push_back(static_cast<std::uint32_t>(e));
      prev = node;
    }
    out.skeleton.edges.push_back({prev, ib});
    out.edge_origin.push_back(static_cast<std::uint32_t>(e));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------

RadiusErrorReport measure_radius_error(const Field& field, const Skeleton& skeleton,
                                       const RadiusErrorOptions& options, Context* ctx) {
  check_positive_int(options.stations_per_edge, 1, "stations_per_edge");
  check_positive_int(options.directions, 1, "directions");
  if (!std::isfinite(options.search_factor) || options.search_factor <= 1) {
    throw InvalidArgument("search_factor must be finite and > 1, got " +
                          std::to_string(options.search_factor));
  }
  if (!std::isfinite(options.min_gap) || options.min_gap < 0) {
    throw InvalidArgument("min_gap must be finite and >= 0, got " +
                          std::to_string(options.min_gap));
  }
  validate(skeleton);
  const std::vector<EdgeGeometry> edges = edge_geometry(skeleton);
  const TubeIndex tubes(edges);
  const double T = field.iso();

  // The rays: origin on the edge, unit direction, requested radius, and how far out (in
  // requested radii) the surface is searched.
  struct Ray {
    Vec3 origin, dir;
    double radius;
    std::uint32_t edge;
    double limit;
  };
  std::vector<Ray> candidates;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const EdgeGeometry& g = edges[e];
    for (int k = 0; k < options.stations_per_edge; ++k) {
      const double t = (k + 0.5) / options.stations_per_edge;
      const Vec3 o = g.a + t * g.len * g.u;
      const double r = (1 - t) * g.ra + t * g.rb;
      for (int d = 0; d < options.directions; ++d) {
        // Offset from the fit's angles (0, 1/2 and 1/4 of a step) so samples fall between them.
        const double angle = 2 * std::numbers::pi * (d + 0.37 + 0.5 * (k % 2)) / options.directions;
        candidates.push_back({o, std::cos(angle) * g.e1 + std::sin(angle) * g.e2, r,
                              static_cast<std::uint32_t>(e), options.search_factor});
      }
    }
  }
  // Keep a ray when its requested surface point is outside every other tube; limit its search
  // to where it enters another tube (marched in steps of 1/16 radius), and drop it when that
  // entry is less than min_gap radii beyond the requested surface.
  std::vector<char> keep(candidates.size(), 0);
  parallel::for_chunks(
      candidates.size(), kRowGrain,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t> ids;
        constexpr int kStepsPerRadius = 16;
        for (std::size_t j = begin; j < end; ++j) {
          Ray& ray = candidates[j];
          if (tubes.inside_other(ray.origin + ray.radius * ray.dir, ray.edge, ids)) continue;
          ids.clear();
          Aabb box;
          box.extend(ray.origin + ray.radius * ray.dir);
          box.extend(ray.origin + options.search_factor * ray.radius * ray.dir);
          tubes.query(box, ids);
          std::sort(ids.begin(), ids.end());
          const int steps =
              static_cast<int>(std::ceil((options.search_factor - 1) * kStepsPerRadius));
          for (int q = 1; q <= steps; ++q) {
            const double factor =
                std::min(options.search_factor, 1.0 + static_cast<double>(q) / kStepsPerRadius);
            const Vec3 p = ray.origin + factor * ray.radius * ray.dir;
            bool entered = false;
            for (const std::uint32_t e : ids)
              entered = entered || (e != ray.edge && tubes.inside(p, e));
            if (entered) {
              ray.limit = factor;
              break;
            }
          }
          keep[j] = ray.limit - 1 >= options.min_gap ? 1 : 0;
        }
      },
      ctx);
  std::vector<Ray> rays;
  RadiusErrorReport report;
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    if (keep[j] != 0) rays.push_back(candidates[j]);
  }
  report.skipped = candidates.size() - rays.size();
  const std::size_t count = rays.size();

  // Bracketing, one batch per step: f on the skeleton (must be inside) and at the requested
  // radius, then outward over a grid of radius multiples up to the ray's limit while f > iso,
  // or inward while f <= iso. The result brackets the crossing nearest the requested radius.
  const std::vector<double> outward{1.1, 1.25, 1.5,  2.0,  2.5,  3.0, 4.0,
                                    6.0, 8.0,  12.0, 16.0, 24.0, 32.0};
  const std::vector<double> inward{0.9, 0.8, 0.65, 0.5, 0.3};
  std::vector<double> lo(count, 0), hi(count, 0), f_lo(count, 0), f_hi(count, 0),
      measured(count, -1);
  std::vector<int> step_of(count, 0);
  std::vector<Vec3> pts;
  std::vector<double> vals;
  auto evaluate = [&](const std::vector<std::size_t>& which, const std::vector<double>& factor) {
    pts.resize(which.size());
    vals.resize(which.size());
    for (std::size_t k = 0; k < which.size(); ++k) {
      const Ray& ray = rays[which[k]];
      pts[k] = ray.origin + factor[k] * ray.radius * ray.dir;
    }
    field.evaluate(pts, vals);
  };
  std::vector<std::size_t> all(count);
  for (std::size_t i = 0; i < count; ++i) all[i] = i;
  std::vector<double> factor(count, 0.0);
  evaluate(all, factor);
  std::vector<std::size_t> up, down;
  for (std::size_t i = 0; i < count; ++i) {
    if (vals[i] <= T) {
      measured[i] = 0;  // the skeleton itself is outside
    } else {
      lo[i] = 0;
      f_lo[i] = vals[i] - T;
    }
  }
  {
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < count; ++i) {
      if (measured[i] < 0) which.push_back(i);
    }
    evaluate(which, std::vector<double>(which.size(), 1.0));
    for (std::size_t k = 0; k < which.size(); ++k) {
      const std::size_t i = which[k];
      if (vals[k] > T) {
        lo[i] = rays[i].radius;
        f_lo[i] = vals[k] - T;
        up.push_back(i);
      } else {
        hi[i] = rays[i].radius;
        f_hi[i] = vals[k] - T;
        down.push_back(i);
      }
    }
  }
  while (!up.empty() || !down.empty()) {
    check_cancel(ctx);
    std::vector<std::size_t> which;
    std::vector<double> f;
    for (const std::size_t i : up) {
      which.push_back(i);
      const std::size_t s = static_cast<std::size_t>(step_of[i]);
      f.push_back(s < outward.size() ? std::min(outward[s], rays[i].limit) : rays[i].limit);
    }
    for (const std::size_t i : down) {
      which.push_back(i);
      f.push_back(inward[static_cast<std::size_t>(step_of[i])]);
    }
    evaluate(which, f);
    std::vector<std::size_t> next_up, next_down;
    for (std::size_t k = 0; k < which.size(); ++k) {
      const std::size_t i = which[k];
      const bool going_up = k < up.size();
      const double rho = f[k] * rays[i].radius;
      ++step_of[i];
      if (vals[k] > T) {
        lo[i] = rho;
        f_lo[i] = vals[k] - T;
        if (going_up) {
          if (f[k] >= rays[i].limit)
            measured[i] = rho;  // no crossing before the limit
          else
            next_up.push_back(i);
        }
      } else {
        hi[i] = rho;
        f_hi[i] = vals[k] - T;
        if (!going_up) {
          if (static_cast<std::size_t>(step_of[i]) < inward.size()) next_down.push_back(i);
          // else: bracketed by the skeleton point (lo = 0)
        }
      }
    }
    up.swap(next_up);
    down.swap(next_down);
  }
  // Illinois refinement of every bracketed ray, one batch per iteration.
  std::vector<std::size_t> active;
  for (std::size_t i = 0; i < count; ++i) {
    if (measured[i] < 0) active.push_back(i);
  }
  std::vector<int> side(count, 0);  // which end was kept last (-1 lo, +1 hi)
  constexpr int kMaxRefine = 100;
  constexpr double kRelativeWidth = 1e-9;
  for (int it = 0; it < kMaxRefine && !active.empty(); ++it) {
    check_cancel(ctx);
    std::vector<double> x(active.size());
    for (std::size_t k = 0; k < active.size(); ++k) {
      const std::size_t i = active[k];
      double xi = hi[i] - f_hi[i] * (hi[i] - lo[i]) / (f_hi[i] - f_lo[i]);
      if (!(xi > lo[i] && xi < hi[i])) xi = 0.5 * (lo[i] + hi[i]);
      x[k] = xi / rays[i].radius;
    }
    evaluate(active, x);
    std::vector<std::size_t> next;
    for (std::size_t k = 0; k < active.size(); ++k) {
      const std::size_t i = active[k];
      const double rho = x[k] * rays[i].radius;
      const double fx = vals[k] - T;
      if (fx > 0) {
        lo[i] = rho;
        f_lo[i] = fx;
        if (side[i] == -1) f_hi[i] *= 0.5;
        side[i] = -1;
      } else {
        hi[i] = rho;
        f_hi[i] = fx;
        if (side[i] == 1) f_lo[i] *= 0.5;
        side[i] = 1;
      }
      if (fx == 0 || hi[i] - lo[i] <= kRelativeWidth * rays[i].radius) {
        measured[i] = fx == 0 ? rho : 0.5 * (lo[i] + hi[i]);
      } else {
        next.push_back(i);
      }
    }
    active.swap(next);
  }
  for (const std::size_t i : active) measured[i] = 0.5 * (lo[i] + hi[i]);

  report.edge_error.assign(edges.size(), std::numeric_limits<double>::quiet_NaN());
  report.errors.resize(count);
  report.signed_errors.resize(count);
  report.sample_edge.resize(count);
  double sum = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double err = std::abs(measured[i] - rays[i].radius) / rays[i].radius;
    report.errors[i] = err;
    report.signed_errors[i] = (measured[i] - rays[i].radius) / rays[i].radius;
    report.sample_edge[i] = rays[i].edge;
    double& edge = report.edge_error[rays[i].edge];
    edge = std::isnan(edge) ? err : std::max(edge, err);
    report.max = std::max(report.max, err);
    sum += err;
  }
  report.samples = count;
  if (count > 0) {
    report.mean = sum / static_cast<double>(count);
    std::vector<double> sorted = report.errors;
    const std::size_t mid = count / 2;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid),
                     sorted.end());
    report.median = sorted[mid];
    const auto p90 = static_cast<std::size_t>(std::floor(0.9 * static_cast<double>(count - 1)));
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(p90),
                     sorted.end());
    report.p90 = sorted[p90];
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(mid),
                     sorted.end());
    if (count % 2 == 0) {
      report.median = 0.5 * (report.median +
                             *std::max_element(sorted.begin(),
                                               sorted.begin() + static_cast<std::ptrdiff_t>(mid)));
    }
  }
  return report;
}

}  // namespace ramiform
