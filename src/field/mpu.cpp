// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/mpu.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include "field/mpu_rays.h"
#include "field/point_kdtree.h"
#include "field/pointwise_field.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"

namespace ramiform {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();
// λ of Ohtake §3: the support ball grows by this fraction until it holds N_min points.
constexpr double kGrowth = 0.1;
// The root cube's edge is the points' longest box side times this (a margin on every side).
constexpr double kRootScale = 1.1;
// Weight of a normal (slope or gradient) equation relative to a position equation.
constexpr double kNormalWeight = 0.5;
// Larger balls are fitted on an evenly strided subset of this many points (the error is still
// measured on every point); coarse cells hold most of the cloud and are subdivided anyway.
constexpr std::size_t kMaxFitPoints = 384;
// Sharp features: every normal of a cluster within this angle of the cluster's mean, and the
// means of two clusters more than twice as far apart.
const double kClusterCos = std::cos(20.0 * std::numbers::pi / 180.0);
const double kSeparationCos = std::cos(40.0 * std::numbers::pi / 180.0);
// Fewest points per cluster of a piecewise fit.
constexpr std::size_t kMinClusterPoints = 4;
// Relative ridge added to the normal equations (they are well conditioned in ball units).
constexpr double kRidge = 1e-12;
// The field is clipped to the points' box padded by this fraction of its diagonal (inside the
// root cube: kClipMargin sqrt(3) < (kRootScale - 1) / 2).
constexpr double kClipMargin = 0.02;
// Background weight (s / (kBackgroundReach * root edge))^3 at distance s outside the root cube.
constexpr double kBackgroundReach = 0.25;
// Neighbours that must agree on the side of an auxiliary point (Ohtake §3).
constexpr std::size_t kAuxiliaryNeighbours = 6;
// Levels of box subdivision used to shrink bounds() to where the field may be inside.
constexpr int kBoundsLevels = 4;

// Quadratic B-spline b(t) (support |t| < 3/2) and its derivative.
double bspline(double t) {
  if (t < 0.5) return 0.75 - t * t;
  if (t < 1.5) return 0.5 * (1.5 - t) * (1.5 - t);
  return 0.0;
}
double bspline_derivative(double t) {
  if (t < 0.5) return -2 * t;
  if (t < 1.5) return -(1.5 - t);
  return 0.0;
}

// Q(d) = d^T A d + b.d + c with d = x - centre, model units; negative inside.
struct Quadric {
  Mat3 A = Mat3::Zero();
  Vec3 b = Vec3::Zero();
  double c = 0;

  [[nodiscard]] double value(const Vec3& d) const { return d.dot(A * d) + b.dot(d) + c; }
  [[nodiscard]] Vec3 gradient(const Vec3& d) const { return 2 * (A * d) + b; }
  // Range over the box m ± h (m, h relative to the centre): the centred form
  // Q(m) + grad Q(m).e + e^T A e with e in [-h, h].
  [[nodiscard]] Interval bound(const Vec3& m, const Vec3& h) const {
    const double q = value(m);
    const Vec3 g = gradient(m);
    double lo = q - g.cwiseAbs().dot(h);
    double hi = q + g.cwiseAbs().dot(h);
    for (int k = 0; k < 3; ++k) {
      const double t = A(k, k) * h[k] * h[k];
      (t < 0 ? lo : hi) += t;
      for (int l = k + 1; l < 3; ++l) {
        const double s = 2 * std::abs(A(k, l)) * h[k] * h[l];
        lo -= s;
        hi += s;
      }
    }
    return {lo, hi};
  }
};

enum class FitKind : std::uint8_t { kGeneral, kBivariate, kSharp, kPointDistance };

// A leaf's local function: one quadric, or the max (convex) / min (concave) of 2 or 3.
struct LocalFit {
  FitKind kind = FitKind::kGeneral;
  int pieces = 1;
  bool use_max = true;
  std::array<Quadric, 3> q;
  // kPointDistance: sign * |x - point| (point relative to the centre), sign = +-1.
  Vec3 point = Vec3::Zero();
  double sign = 1;

  [[nodiscard]] double value(const Vec3& d, Vec3* grad) const {
    if (kind == FitKind::kPointDistance) {
      const Vec3 e = d - point;
      const double r = e.norm();
      if (grad != nullptr) *grad = r > 0 ? Vec3((sign / r) * e) : Vec3::Zero();
      return sign * r;
    }
    int best = 0;
    double v = q[0].value(d);
    for (int i = 1; i < pieces; ++i) {
      const double w = q[static_cast<std::size_t>(i)].value(d);
      if (use_max ? w > v : w < v) {
        v = w;
        best = i;
      }
    }
    if (grad != nullptr) *grad = q[static_cast<std::size_t>(best)].gradient(d);
    return v;
  }
  [[nodiscard]] Interval bound(const Vec3& m, const Vec3& h) const {
    if (kind == FitKind::kPointDistance) {
      const Aabb box(m - h - point, m + h - point);  // the box relative to the point
      const double lo = std::sqrt(squared_distance(box, Vec3::Zero()));
      const double hi = max_distance(box, Vec3::Zero());
      return sign > 0 ? Interval{lo, hi} : Interval{-hi, -lo};
    }
    Interval r = q[0].bound(m, h);
    for (int i = 1; i < pieces; ++i) {
      const Interval s = q[static_cast<std::size_t>(i)].bound(m, h);
      r = use_max ? Interval{std::max(r.lo, s.lo), std::max(r.hi, s.hi)}
                  : Interval{std::min(r.lo, s.lo), std::min(r.hi, s.hi)};
    }
    return r;
  }
};

struct Leaf {
  Vec3 centre;
  double radius = 0;  // support radius R (after growth)
  LocalFit fit;
};

struct Node {
  Aabb box;
  int depth = 0;
  std::int32_t first_child = -1;  // 8 consecutive nodes, child index x + 2 y + 4 z
  std::int32_t leaf = -1;         // index into leaves_ when a leaf
  Aabb reach;                     // union of the subtree's support boxes
};

// The points of a support ball with their weights, in ball units (d / R).
struct Ball {
  std::vector<std::uint32_t> index;
  std::vector<double> weight;
};

// ---- local fits ------------------------------------------------------------------------------

// An orthonormal frame (e1, e2, n) around the unit vector n.
void frame(const Vec3& n, Vec3& e1, Vec3& e2) {
  const Vec3 a = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  e1 = a.cross(n).normalized();
  e2 = n.cross(e1);
}

template <int N>
bool solve(Eigen::Matrix<double, N, N>& M, const Eigen::Matrix<double, N, 1>& rhs,
           Eigen::Matrix<double, N, 1>& x) {
  M.template triangularView<Eigen::Lower>() = M.transpose();
  const double ridge = kRidge * std::max(M.trace(), std::numeric_limits<double>::min());
  M.diagonal().array() += ridge;
  const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(M);
  if (ldlt.info() != Eigen::Success) return false;
  x = ldlt.solve(rhs);
  if (!x.allFinite()) return false;
  // Reject (near-)singular systems: the fit is then not determined by the data.
  const auto d = ldlt.vectorD();
  return d.minCoeff() > 1e-10 * d.maxCoeff();
}

// Bivariate quadratic w = h(u, v) over the plane through `centre` with normal `n`, fitted to
// the positions and the slopes of the points `subset` of the ball (radius R).
bool fit_bivariate(const std::vector<Vec3>& pos, const std::vector<Vec3>& nrm, const Ball& ball,
                   const std::vector<std::size_t>& subset, const Vec3& centre, double R,
                   const Vec3& n, Quadric& out) {
  Vec3 e1, e2;
  frame(n, e1, e2);
  Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
  auto add = [&](const Eigen::Matrix<double, 6, 1>& row, double target, double w) {
    M.template selfadjointView<Eigen::Upper>().rankUpdate(row, w);
    rhs += (w * target) * row;
  };
  for (const std::size_t k : subset) {
    const std::uint32_t i = ball.index[k];
    const double w = ball.weight[k];
    if (!(w > 0)) continue;
    const Vec3 d = (pos[i] - centre) / R;
    const double u = e1.dot(d), v = e2.dot(d), h = n.dot(d);
    Eigen::Matrix<double, 6, 1> row;
    row << u * u, u * v, v * v, u, v, 1;
    add(row, h, w);
    // Slopes: grad(w - h) ∥ normal, i.e. n_w h_u + n_u = 0 and n_w h_v + n_v = 0.
    const Vec3& m = nrm[i];
    const double nu = e1.dot(m), nv = e2.dot(m), nw = n.dot(m);
    const double ws = kNormalWeight * kNormalWeight * w;
    row << nw * 2 * u, nw * v, 0, nw, 0, 0;
    add(row, -nu, ws);
    row << 0, nw * u, nw * 2 * v, 0, nw, 0;
    add(row, -nv, ws);
  }
  Eigen::Matrix<double, 6, 1> x;
  if (!solve<6>(M, rhs, x)) return false;
  // Q(d) = n.d - h(e1.d, e2.d) in model units: h_model(u, v) = R h(u / R, v / R).
  const double a = x[0] / R, b = x[1] / R, c = x[2] / R;
  out.A = -(a * e1 * e1.transpose() + 0.5 * b * (e1 * e2.transpose() + e2 * e1.transpose()) +
            c * e2 * e2.transpose());
  out.b = n - x[3] * e1 - x[4] * e2;
  out.c = -R * x[5];
  return true;
}

// General quadric fitted to Q(p_i) = 0 and grad Q(p_i) = n_i.
bool fit_general(const std::vector<Vec3>& pos, const std::vector<Vec3>& nrm, const Ball& ball,
                 const std::vector<std::size_t>& subset, const Vec3& centre, double R,
                 Quadric& out) {
  using Vec10 = Eigen::Matrix<double, 10, 1>;
  Eigen::Matrix<double, 10, 10> M = Eigen::Matrix<double, 10, 10>::Zero();
  Vec10 rhs = Vec10::Zero();
  for (const std::size_t k : subset) {
    const std::uint32_t i = ball.index[k];
    const double w = ball.weight[k];
    if (!(w > 0)) continue;
    const Vec3 s = (pos[i] - centre) / R;
    const double x = s.x(), y = s.y(), z = s.z();
    Vec10 row;
    row << x * x, y * y, z * z, x * y, y * z, z * x, x, y, z, 1;
    M.selfadjointView<Eigen::Upper>().rankUpdate(row, w);
    const double ws = kNormalWeight * kNormalWeight * w;
    const Vec3& m = nrm[i];
    row << 2 * x, 0, 0, y, 0, z, 1, 0, 0, 0;
    M.selfadjointView<Eigen::Upper>().rankUpdate(row, ws);
    rhs += (ws * m.x()) * row;
    row << 0, 2 * y, 0, x, z, 0, 0, 1, 0, 0;
    M.selfadjointView<Eigen::Upper>().rankUpdate(row, ws);
    rhs += (ws * m.y()) * row;
    row << 0, 0, 2 * z, 0, y, x, 0, 0, 1, 0;
    M.selfadjointView<Eigen::Upper>().rankUpdate(row, ws);
    rhs += (ws * m.z()) * row;
  }
  Vec10 c;
  if (!solve<10>(M, rhs, c)) return false;
  // Q(d) = R q(d / R).
  Mat3 A;
  A << c[0], 0.5 * c[3], 0.5 * c[5], 0.5 * c[3], c[1], 0.5 * c[4], 0.5 * c[5], 0.5 * c[4], c[2];
  out.A = A / R;
  out.b = Vec3(c[6], c[7], c[8]);
  out.c = R * c[9];
  return true;
}

// The plane through the weighted centroid with normal n (the last resort).
Quadric plane(const std::vector<Vec3>& pos, const Ball& ball, const Vec3& centre, const Vec3& n) {
  Vec3 sum = Vec3::Zero();
  double total = 0;
  for (std::size_t k = 0; k < ball.index.size(); ++k) {
    const double w = ball.weight[k] + 1e-6;
    sum += w * pos[ball.index[k]];
    total += w;
  }
  Quadric q;
  q.b = n;
  q.c = -n.dot(sum / total - centre);
  return q;
}

// Groups unit normals into `k` clusters (2 or 3) by seeded k-means; true when every cluster is
// tight, the means are well apart and each cluster has enough points.
bool cluster_normals(const std::vector<Vec3>& normals, const Vec3& mean, int k,
                     std::vector<int>& label, std::array<Vec3, 3>& centre) {
  const std::size_t n = normals.size();
  auto farthest = [&](auto&& score) {
    std::size_t best = 0;
    double best_score = kInf;
    for (std::size_t i = 0; i < n; ++i) {
      const double s = score(normals[i]);
      if (s < best_score) {
        best_score = s;
        best = i;
      }
    }
    return normals[best];
  };
  centre[0] = farthest([&](const Vec3& m) { return m.dot(mean); });
  centre[1] = farthest([&](const Vec3& m) { return m.dot(centre[0]); });
  if (k == 3) {
    centre[2] =
        farthest([&](const Vec3& m) { return std::max(m.dot(centre[0]), m.dot(centre[1])); });
  }
  label.assign(n, 0);
  for (int iteration = 0; iteration < 4; ++iteration) {
    std::array<Vec3, 3> sum{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    for (std::size_t i = 0; i < n; ++i) {
      int best = 0;
      for (int c = 1; c < k; ++c) {
        if (normals[i].dot(centre[static_cast<std::size_t>(c)]) >
            normals[i].dot(centre[static_cast<std::size_t>(best)]))
          best = c;
      }
      label[i] = best;
      sum[static_cast<std::size_t>(best)] += normals[i];
    }
    for (int c = 0; c < k; ++c) {
      const double len = sum[static_cast<std::size_t>(c)].norm();
      if (!(len > 0)) return false;
      centre[static_cast<std::size_t>(c)] = sum[static_cast<std::size_t>(c)] / len;
    }
  }
  std::array<std::size_t, 3> count{0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<std::size_t>(label[i]);
    ++count[c];
    if (normals[i].dot(centre[c]) < kClusterCos) return false;
  }
  for (int a = 0; a < k; ++a) {
    if (count[static_cast<std::size_t>(a)] < kMinClusterPoints) return false;
    for (int b = a + 1; b < k; ++b) {
      if (centre[static_cast<std::size_t>(a)].dot(centre[static_cast<std::size_t>(b)]) >
          kSeparationCos)
        return false;
    }
  }
  return true;
}

struct CellFit {
  LocalFit fit;
  double radius = 0;  // support radius α d
  double error = 0;
  std::size_t initial_count = 0;  // points in the ball of radius α d
  bool consistent = true;         // the fit passed the auxiliary-point check
  bool fallback = false;          // failed it as a sparse cell: replaced
};

class Fitter {
 public:
  Fitter(const std::vector<Vec3>& pos, const std::vector<Vec3>& nrm,
         const detail::PointKdTree& tree, const MpuOptions& options)
      : pos_(pos), nrm_(nrm), tree_(tree), options_(options) {}

  [[nodiscard]] CellFit fit(const Aabb& cell) const {
    CellFit out;
    const Vec3 centre = cell.center();
    double R = options_.support * cell.diagonal().norm();
    std::vector<std::pair<std::uint32_t, double>> found;
    tree_.within_by_index(centre, R, found);
    out.initial_count = found.size();
    const auto need = static_cast<std::size_t>(options_.min_points);
    if (found.size() < need) {
      // Grow R by λ steps past the N_min-th nearest point (then check: the search is open).
      std::vector<std::pair<std::uint32_t, double>> nearest;
      tree_.nearest(centre, need, nearest);
      const double reach = std::sqrt(nearest.back().second);
      while (R <= reach) R += kGrowth * R;
      tree_.within_by_index(centre, R, found);
      while (found.size() < need) {
        R += kGrowth * R;
        tree_.within_by_index(centre, R, found);
      }
    }
    // The support stays α d: the ball is grown only to fit (Ohtake grows the support too).
    // A grown support reaches far from its cell, where the local function extrapolates (a
    // concave patch's paraboloid is negative all around it): spurious inside regions, and
    // slow evaluation.
    const double support = options_.support * cell.diagonal().norm();
    out.radius = support;
    Ball ball;
    ball.index.reserve(found.size());
    ball.weight.reserve(found.size());
    // Ball order: by index (sums follow the input order, whatever the tree's traversal).
    for (const auto& [i, d2] : found) {
      ball.index.push_back(i);
      ball.weight.push_back(bspline(1.5 * std::sqrt(d2) / R));
    }
    std::vector<std::size_t> subset;
    const std::size_t n = ball.index.size();
    const std::size_t stride = (n + kMaxFitPoints - 1) / kMaxFitPoints;
    for (std::size_t k = 0; k < n; k += stride) subset.push_back(k);

    Vec3 mean = Vec3::Zero();
    for (const std::size_t k : subset) mean += (ball.weight[k] + 1e-6) * nrm_[ball.index[k]];
    const double mean_len = mean.norm();
    double min_cos = -1;
    if (mean_len > 0) {
      mean /= mean_len;
      min_cos = 1;
      for (const std::size_t i : ball.index) min_cos = std::min(min_cos, nrm_[i].dot(mean));
    } else {
      mean = nrm_[ball.index.front()];
    }
    bool done = false;
    if (options_.sharp_features && n >= 2 * need && min_cos < kClusterCos) {
      done = fit_sharp(ball, subset, centre, R, mean, out.fit);
    }
    if (!done && min_cos > 0 &&
        fit_bivariate(pos_, nrm_, ball, subset, centre, R, mean, out.fit.q[0])) {
      out.fit.kind = FitKind::kBivariate;
      done = true;
    }
    if (!done) {
      out.fit.kind = FitKind::kGeneral;
      if (!fit_general(pos_, nrm_, ball, subset, centre, R, out.fit.q[0]))
        out.fit.q[0] = plane(pos_, ball, centre, mean);
    }
    // Ohtake's auxiliary points, as a check: at the cell's centre (and, for a general quadric,
    // its corners) the 6 nearest points' tangent planes agreeing on a side give the side the
    // fit must have there. A sparse cell (fewer than N_min points within α d: it will not be
    // subdivided) that fails gets the nearest point's tangent plane (its sign is right at the
    // centre); another cell is subdivided when it can be. Sparse cells are checked at their
    // corners too: most leaves are sparse or empty, and away from the points a quadric's sign
    // is least certain.
    bool valid = consistent_at(out.fit, centre, centre);
    const bool sparse = out.initial_count < need;  // a leaf whatever its error
    if (valid && (out.fit.kind == FitKind::kGeneral || sparse)) {
      for (int c = 0; c < 8 && valid; ++c)
        valid = consistent_at(out.fit, centre, cell.corner(static_cast<Aabb::CornerType>(c)));
    }
    if (!valid && sparse) {
      std::vector<std::pair<std::uint32_t, double>> nearest;
      tree_.nearest(centre, kAuxiliaryNeighbours, nearest);
      const std::uint32_t j = nearest.front().first;
      out.fit = LocalFit{};
      out.fallback = true;
      if (out.initial_count == 0) {
        // No point in the support: the distance to the nearest point, on the side most of the
        // nearest tangent planes give (no zero in the support, unlike a tangent plane, which
        // extrapolated sideways cuts through it, e.g. a hoof's sole beside the hoof).
        int outside = 0;
        for (const auto& [i, d2] : nearest) outside += nrm_[i].dot(centre - pos_[i]) > 0 ? 1 : -1;
        if (outside == 0) outside = nrm_[j].dot(centre - pos_[j]) > 0 ? 1 : -1;
        out.fit.kind = FitKind::kPointDistance;
        out.fit.point = pos_[j] - centre;
        out.fit.sign = outside > 0 ? 1.0 : -1.0;
      } else {
        out.fit.q[0].b = nrm_[j];
        out.fit.q[0].c = -nrm_[j].dot(pos_[j] - centre);
      }
      valid = true;
    }
    out.consistent = valid;
    // Taubin's first-order distance at every point of the ball within the support.
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t i = ball.index[k];
      if (!((pos_[i] - centre).squaredNorm() < support * support)) continue;
      Vec3 g;
      const double v = out.fit.value(pos_[i] - centre, &g);
      out.error = std::max(out.error, std::abs(v) / std::max(g.norm(), 1e-12));
    }
    return out;
  }

 private:
  bool fit_sharp(const Ball& ball, const std::vector<std::size_t>& subset, const Vec3& centre,
                 double R, const Vec3& mean, LocalFit& out) const {
    std::vector<Vec3> normals;
    normals.reserve(subset.size());
    for (const std::size_t k : subset) normals.push_back(nrm_[ball.index[k]]);
    std::vector<int> label;
    std::array<Vec3, 3> axis;
    int pieces = 0;
    for (const int k : {2, 3}) {
      if (cluster_normals(normals, mean, k, label, axis)) {
        pieces = k;
        break;
      }
    }
    if (pieces == 0) return false;
    std::array<std::vector<std::size_t>, 3> members;
    for (std::size_t j = 0; j < subset.size(); ++j)
      members[static_cast<std::size_t>(label[j])].push_back(subset[j]);
    for (int c = 0; c < pieces; ++c) {
      const auto cu = static_cast<std::size_t>(c);
      if (!fit_bivariate(pos_, nrm_, ball, members[cu], centre, R, axis[cu], out.q[cu]))
        return false;
    }
    // Convex when each piece's points lie inside (Q < 0) every other piece on average.
    int convex = 0, concave = 0;
    for (int a = 0; a < pieces; ++a) {
      for (int b = 0; b < pieces; ++b) {
        if (a == b) continue;
        double sum = 0;
        for (const std::size_t k : members[static_cast<std::size_t>(b)])
          sum += out.q[static_cast<std::size_t>(a)].value(pos_[ball.index[k]] - centre);
        (sum < 0 ? convex : concave) += 1;
      }
    }
    if (convex != 0 && concave != 0) return false;  // mixed corner: a general quadric instead
    out.kind = FitKind::kSharp;
    out.pieces = pieces;
    out.use_max = concave == 0;
    return true;
  }

  // False when the 6 nearest points all put q on one side of their tangent planes and the fit
  // puts it on the other.
  [[nodiscard]] bool consistent_at(const LocalFit& fit, const Vec3& centre, const Vec3& q) const {
    std::vector<std::pair<std::uint32_t, double>> nearest;
    tree_.nearest(q, kAuxiliaryNeighbours, nearest);
    int outside = 0, inside = 0;
    for (const auto& [j, d2] : nearest) (nrm_[j].dot(q - pos_[j]) > 0 ? outside : inside) += 1;
    if (outside != 0 && inside != 0) return true;  // not a valid auxiliary point
    const double v = fit.value(q - centre, nullptr);
    return outside != 0 ? v > 0 : v < 0;
  }

  const std::vector<Vec3>& pos_;
  const std::vector<Vec3>& nrm_;
  const detail::PointKdTree& tree_;
  const MpuOptions& options_;
};

// ---- the field -------------------------------------------------------------------------------

class MpuField final : public detail::PointwiseField {
 public:
  MpuField(double iso, std::vector<Node> nodes, std::vector<Leaf> leaves,
           std::vector<MpuCell> cells, const Aabb& root, const Aabb& clip, std::size_t point_count,
           const MpuStats& stats, const Context* ctx)
      : PointwiseField(iso),
        nodes_(std::move(nodes)),
        leaves_(std::move(leaves)),
        cells_(std::move(cells)),
        root_(root),
        clip_(clip),
        background_reach_(kBackgroundReach * root.sizes().maxCoeff()),
        point_count_(point_count),
        stats_(stats) {
    support_.reserve(leaves_.size());
    for (const Leaf& leaf : leaves_) support_.push_back({leaf.centre, leaf.radius * leaf.radius});
    build_near_lists(ctx);
    build_status(ctx);
    bounds_ = inside_box();
  }

  Interval bound(const Aabb& box) const override {
    if (box.isEmpty()) return {iso(), iso()};
    if (!box.min().allFinite() || !box.max().allFinite()) return {-kInf, iso()};
    const Interval native = native_bound(box);
    return {iso() - native.hi, iso() - native.lo};
  }

  Aabb bounds() const override { return bounds_; }

  std::string describe() const override {
    return "MPU implicit, " + std::to_string(point_count_) + " points, " +
           std::to_string(leaves_.size()) + " leaves (" + std::to_string(stats_.general_quadrics) +
           " quadrics, " + std::to_string(stats_.bivariate) + " bivariate, " +
           std::to_string(stats_.sharp) + " sharp)";
  }

  [[nodiscard]] const std::vector<MpuCell>& cells() const { return cells_; }

 protected:
  double at(const Vec3& p, Vec3* grad) const override {
    Vec3 g = Vec3::Zero();
    const double f = native(p, grad != nullptr ? &g : nullptr);
    if (grad != nullptr) *grad = -g;
    return iso() - f;
  }

 private:
  // f_mpu(p) (negative inside) and its gradient.
  double native(const Vec3& p, Vec3* grad) const {
    double sw = 0, swq = 0;
    Vec3 gsw = Vec3::Zero(), gswq = Vec3::Zero();
    auto add = [&](const Leaf& leaf) {
      const Vec3 d = p - leaf.centre;
      const double r2 = d.squaredNorm();
      if (!(r2 < leaf.radius * leaf.radius)) return;
      const double r = std::sqrt(r2);
      const double t = 1.5 * r / leaf.radius;
      const double w = bspline(t);
      if (!(w > 0)) return;
      Vec3 gq;
      const double q = leaf.fit.value(d, grad != nullptr ? &gq : nullptr);
      sw += w;
      swq += w * q;
      if (grad != nullptr) {
        const Vec3 gw =
            r > 0 ? Vec3((bspline_derivative(t) * 1.5 / (leaf.radius * r)) * d) : Vec3::Zero();
        gsw += gw;
        gswq += gw * q + w * gq;
      }
    };
    if (root_.contains(p)) {
      // The leaf whose cell holds p lists every leaf whose support meets that cell.
      std::size_t id = 0;
      while (nodes_[id].leaf < 0) {
        const Vec3 mid = nodes_[id].box.center();
        id = static_cast<std::size_t>(nodes_[id].first_child + (p.x() >= mid.x()) +
                                      2 * (p.y() >= mid.y()) + 4 * (p.z() >= mid.z()));
      }
      const auto l = static_cast<std::size_t>(nodes_[id].leaf);
      for (std::size_t k = near_begin_[l]; k < near_begin_[l + 1]; ++k) {
        // The support test on the compact copy first (most of the list misses p).
        const Support& s = support_[near_[k]];
        if (!((p - s.centre).squaredNorm() < s.radius2)) continue;
        add(leaves_[near_[k]]);
      }
    } else {
      std::array<std::int32_t, 8 * 24> stack;  // 7 per level on the path + 8
      int top = 0;
      stack[static_cast<std::size_t>(top++)] = 0;
      while (top > 0) {
        const Node& node = nodes_[static_cast<std::size_t>(stack[static_cast<std::size_t>(--top)])];
        if (!node.reach.contains(p)) continue;
        if (node.leaf < 0) {
          for (std::int32_t c = 7; c >= 0; --c)
            stack[static_cast<std::size_t>(top++)] = node.first_child + c;
          continue;
        }
        add(leaves_[static_cast<std::size_t>(node.leaf)]);
      }
    }
    // The background: s (distance to the root cube) with weight (s / reach)^3 outside it.
    const Vec3 below = root_.min() - p, above = p - root_.max();
    const Vec3 out = below.cwiseMax(above).cwiseMax(Vec3::Zero());
    const double s = out.stableNorm();  // no overflow far away
    Vec3 gs = Vec3::Zero();
    if (s > 0) {
      for (int k = 0; k < 3; ++k)
        gs[k] = below[k] > 0 ? -below[k] / s : above[k] > 0 ? above[k] / s : 0.0;
    }
    if (!(sw > 0)) {
      // Beyond every support (the root cube is covered, so s > 0): f = s, then the clip.
      if (grad != nullptr) *grad = gs;
      return clipped(p, s, grad);
    }
    if (s > 0) {  // within some support, so s is bounded and w0 finite
      const double a = s / background_reach_;
      const double w0 = a * a * a;
      sw += w0;
      swq += w0 * s;
      if (grad != nullptr) {
        const Vec3 gw0 = (3 * a * a / background_reach_) * gs;
        gsw += gw0;
        gswq += gw0 * s + w0 * gs;
      }
    }
    const double f = swq / sw;
    if (grad != nullptr) *grad = (gswq - f * gsw) / sw;
    return clipped(p, f, grad);
  }

  // max(f, signed distance to the clip box), so that nothing outside the box is inside. An
  // exact signed distance to a surface inside a convex box never goes below the box's signed
  // distance (the surface lies between an inside point and the box's boundary), so the clip
  // only raises values that are already < 0 inside the box: the surface does not move.
  double clipped(const Vec3& p, double f, Vec3* grad) const {
    const Vec3 below = clip_.min() - p, above = p - clip_.max();
    const Vec3 out = below.cwiseMax(above).cwiseMax(Vec3::Zero());
    const double s = out.stableNorm();  // no overflow far away
    const double box = s > 0 ? s : -(p - clip_.min()).cwiseMin(clip_.max() - p).minCoeff();
    if (!(box > f)) return f;
    if (grad != nullptr) {
      if (s > 0) {
        for (int k = 0; k < 3; ++k)
          (*grad)[k] = below[k] > 0 ? -below[k] / s : above[k] > 0 ? above[k] / s : 0.0;
      } else {
        const Vec3 lo = p - clip_.min(), hi = clip_.max() - p;
        int axis = 0;
        double best = kInf, sign = 1;
        for (int k = 0; k < 3; ++k) {
          if (lo[k] < best) {
            best = lo[k];
            axis = k;
            sign = -1;
          }
          if (hi[k] < best) {
            best = hi[k];
            axis = k;
            sign = 1;
          }
        }
        *grad = sign * Vec3::Unit(axis);
      }
    }
    return box;
  }

  // [min lo_i, max hi_i] over the local functions that can contribute in the box (f_mpu is
  // a convex combination of them), each bounded over the box clipped to its support's box.
  Interval native_bound(const Aabb& box) const {
    double lo = kInf, hi = -kInf, magnitude = 0;
    std::vector<std::int32_t> stack{0};
    while (!stack.empty()) {
      const Node& node = nodes_[static_cast<std::size_t>(stack.back())];
      stack.pop_back();
      if (!node.reach.intersects(box)) continue;
      if (node.leaf < 0) {
        for (std::int32_t c = 0; c < 8; ++c) stack.push_back(node.first_child + c);
        continue;
      }
      const Leaf& leaf = leaves_[static_cast<std::size_t>(node.leaf)];
      if (!(squared_distance(box, leaf.centre) < leaf.radius * leaf.radius)) continue;
      add_leaf_bound(box, leaf, lo, hi, magnitude);
    }
    if (!root_.contains(box)) {
      const double s_lo = std::sqrt(squared_distance(box, root_));
      double s_hi = 0;
      for (int k = 0; k < 8; ++k) {
        const Vec3 c = box.corner(static_cast<Aabb::CornerType>(k));
        s_hi = std::max(s_hi, std::sqrt(squared_distance(root_, c)));
      }
      lo = std::min(lo, s_lo);
      hi = std::max(hi, s_hi);
      magnitude = std::max(magnitude, s_hi);
    }
    if (lo > hi) return {0, 0};  // cannot happen: the root cube is covered by the leaves
    return finish_bound(box, lo, hi, magnitude);
  }

  // Widens [lo, hi] (and magnitude, the largest |value|) by the bound of `leaf`'s local function
  // over the part of `box` in its support's cube.
  static void add_leaf_bound(const Aabb& box, const Leaf& leaf, double& lo, double& hi,
                             double& magnitude) {
    const Aabb clipped = box.intersection(Aabb(leaf.centre - Vec3::Constant(leaf.radius),
                                               leaf.centre + Vec3::Constant(leaf.radius)));
    const Interval iv = leaf.fit.bound(clipped.center() - leaf.centre, 0.5 * clipped.sizes());
    lo = std::min(lo, iv.lo);
    hi = std::max(hi, iv.hi);
    magnitude = std::max({magnitude, std::abs(iv.lo), std::abs(iv.hi)});
  }

  // The bound [lo, hi] of the leaves' local functions over `box` (magnitude: their largest
  // |value|), completed with the clip and the rounding slack.
  Interval finish_bound(const Aabb& box, double lo, double hi, double magnitude) const {
    // The clip max(f, signed distance to the clip box); the signed distance is 1-Lipschitz.
    const Vec3 c = box.center();
    const double half = 0.5 * box.diagonal().norm();
    const double sc = clip_.contains(c) ? -(c - clip_.min()).cwiseMin(clip_.max() - c).minCoeff()
                                        : std::sqrt(squared_distance(clip_, c));
    lo = std::max(lo, sc - half);
    hi = std::max(hi, sc + half);
    magnitude = std::max(magnitude, std::abs(sc) + half);
    // Rounding of the evaluation (a weighted mean of quadrics evaluated in double).
    const double slack = 64 * kEps * (magnitude + root_.sizes().maxCoeff());
    return {lo - slack, hi + slack};
  }

  // The bound of f_mpu (native, with the clip) over the points of `box` that lie in the cell of
  // leaf `l`: only the leaves of its near list contribute there (those of native_bound, without
  // the walk down the tree). The cell lies in the root cube: no background.
  Interval cell_bound(const Aabb& box, std::size_t l) const {
    double lo = kInf, hi = -kInf, magnitude = 0;
    for (std::size_t k = near_begin_[l]; k < near_begin_[l + 1]; ++k) {
      if (!(squared_distance(box, support_[near_[k]].centre) < support_[near_[k]].radius2))
        continue;
      add_leaf_bound(box, leaves_[near_[k]], lo, hi, magnitude);
    }
    if (lo > hi) return {-kInf, kInf};  // no support meets the box: prove nothing
    return finish_bound(box, lo, hi, magnitude);
  }

  // status_ of every node: a leaf's from cell_bound over its cell, a parent's the common status
  // of its children (children come after their parent).
  void build_status(const Context* ctx) {
    status_.assign(nodes_.size(), kUnknown);
    parallel::for_each(
        nodes_.size(), 256,
        [&](std::size_t id) {
          const Node& node = nodes_[id];
          if (node.leaf < 0) return;
          const Interval iv = cell_bound(node.box, static_cast<std::size_t>(node.leaf));
          status_[id] = iv.lo >= 0 ? kOutside : iv.hi < 0 ? kInside : kUnknown;
        },
        ctx);
    for (std::size_t id = nodes_.size(); id-- > 0;) {
      const Node& node = nodes_[id];
      if (node.leaf >= 0) continue;
      std::int8_t s = status_[static_cast<std::size_t>(node.first_child)];
      for (int c = 1; c < 8; ++c)
        if (status_[static_cast<std::size_t>(node.first_child + c)] != s) s = kUnknown;
      status_[id] = s;
    }
  }

 public:
  // detail::mpu_ray_samples (src/field/mpu_rays.h).
  std::int64_t ray_samples(const detail::RaySamples& ray, bool stop_inside,
                           std::vector<std::uint32_t>& open) const {
    open.clear();
    if (ray.count == 0) return -1;
    // Boxes are widened by a hair (the samples' rounding), and a node's run of samples by a
    // millionth of a step on each side: a sample may so be given to a neighbouring cell too, where
    // a bound proves nothing about it, but it is always given to the cell that holds it. A proof
    // of outside only drops a sample from one cell's run (the union of the runs left open is what
    // counts); a proof of inside only names a candidate, which the caller checks.
    const double hair = 1e-9 * (root_.sizes().maxCoeff() + ray.origin.cwiseAbs().maxCoeff() +
                                ray.dir.cwiseAbs().maxCoeff());
    auto widen = [&](const Aabb& b) {
      return Aabb(b.min() - Vec3::Constant(hair), b.max() + Vec3::Constant(hair));
    };
    auto slab = [&](const Aabb& b, double lo, double hi) {
      for (int k = 0; k < 3; ++k) {
        const double d = ray.dir[k], o = ray.origin[k];
        if (d == 0) {
          if (o < b.min()[k] || o > b.max()[k]) return std::pair<double, double>{1, 0};
          continue;
        }
        double t0 = (b.min()[k] - o) / d, t1 = (b.max()[k] - o) / d;
        if (t0 > t1) std::swap(t0, t1);
        lo = std::max(lo, t0);
        hi = std::min(hi, t1);
      }
      return std::pair<double, double>{lo, hi};
    };
    const double last = ray.first + static_cast<double>(ray.count - 1) * ray.step;
    // Outside the clip box the clip alone makes f_mpu ≥ 0: only the run inside it counts.
    const auto [ta, tb] = slab(widen(clip_), ray.first, last);
    if (!(ta <= tb)) return -1;
    const auto top = static_cast<double>(ray.count - 1);
    // The samples of a parameter range [a, b], widened by a millionth of a step on each side
    // (rounding in a, b and the samples' positions is some 1e-16 of the segment; a step is at
    // least 1e-6 of it, visibility.cpp).
    auto run = [&](double a, double b) {
      const double k0 = std::max(std::ceil((a - ray.first) / ray.step - 1e-6), 0.0);
      const double k1 = std::min(std::floor((b - ray.first) / ray.step + 1e-6), top);
      return std::pair<std::int64_t, std::int64_t>{static_cast<std::int64_t>(k0),
                                                   static_cast<std::int64_t>(k1)};
    };
    auto add = [&](std::int64_t k0, std::int64_t k1) {
      for (std::int64_t k = k0; k <= k1; ++k) open.push_back(static_cast<std::uint32_t>(k));
    };
    // The nodes the ray crosses, each with its parameter range: a node's range is cut at the
    // ray's crossings of its three mid planes into the ranges of the (at most 4) children met.
    struct Visit {
      std::int32_t node;
      double a, b;
    };
    std::array<Visit, 4 * 24> stack;  // at most 3 left per level on the path + 4
    int height = 0;
    stack[static_cast<std::size_t>(height++)] = {0, ta, tb};
    std::vector<std::pair<std::int64_t, std::int64_t>> runs;
    // A candidate must lie in the box the proof is about.
    auto inside_at = [&](const Aabb& where, std::int64_t k0, std::int64_t k1) -> std::int64_t {
      const std::int64_t k = k0 + (k1 - k0) / 2;
      return where.contains(detail::ray_sample(ray, static_cast<std::uint32_t>(k))) ? k : -1;
    };
    while (height > 0) {
      const Visit visit = stack[static_cast<std::size_t>(--height)];
      const auto id = static_cast<std::size_t>(visit.node);
      const std::int8_t status = status_[id];
      if (status == kOutside) continue;
      const Node& node = nodes_[id];
      const double a = visit.a, b = visit.b;
      const auto [k0, k1] = run(a, b);
      if (k0 > k1) continue;
      const Aabb box = widen(node.box);
      if (status == kInside && stop_inside) {
        const std::int64_t k = inside_at(box, k0, k1);
        if (k >= 0) return k;
      }
      if (node.leaf < 0) {
        const Vec3 mid = node.box.center();
        std::array<double, 5> cut{a, b, b, b, b};
        int cuts = 1;
        for (int k = 0; k < 3; ++k) {
          if (ray.dir[k] == 0) continue;
          const double t = (mid[k] - ray.origin[k]) / ray.dir[k];
          if (t > a && t < b) cut[static_cast<std::size_t>(cuts++)] = t;
        }
        for (int i = 2; i < cuts; ++i) {  // sort the (at most 3) crossings
          for (int j = i;
               j > 1 && cut[static_cast<std::size_t>(j)] < cut[static_cast<std::size_t>(j - 1)];
               --j)
            std::swap(cut[static_cast<std::size_t>(j)], cut[static_cast<std::size_t>(j - 1)]);
        }
        cut[static_cast<std::size_t>(cuts)] = b;
        for (int i = cuts - 1; i >= 0; --i) {
          const double u = cut[static_cast<std::size_t>(i)],
                       v = cut[static_cast<std::size_t>(i + 1)];
          const Vec3 p = ray.origin + (0.5 * (u + v)) * ray.dir;
          const std::int32_t child = node.first_child + (p.x() >= mid.x()) +
                                     2 * (p.y() >= mid.y()) + 4 * (p.z() >= mid.z());
          stack[static_cast<std::size_t>(height++)] = {child, u, v};
        }
        continue;
      }
      // A cell the surface may cross: its run of samples, halved until proven or short.
      const auto l = static_cast<std::size_t>(node.leaf);
      runs.assign(1, {k0, k1});
      while (!runs.empty()) {
        const auto [r0, r1] = runs.back();
        runs.pop_back();
        if (r1 - r0 < kDirectRun) {
          add(r0, r1);
          continue;
        }
        // The run's samples in the cell lie between the parameters pa and pb.
        const double pa = std::max(ray.first + static_cast<double>(r0) * ray.step, a);
        const double pb = std::min(ray.first + static_cast<double>(r1) * ray.step, b);
        if (!(pa <= pb)) continue;  // no sample of the run in this cell
        Aabb piece;
        piece.extend(ray.origin + pa * ray.dir);
        piece.extend(ray.origin + pb * ray.dir);
        const Interval iv = cell_bound(widen(piece), l);
        if (iv.lo >= 0) continue;
        if (iv.hi < 0 && stop_inside) {
          const std::int64_t k = inside_at(box, r0, r1);
          if (k >= 0) return k;
        }
        const std::int64_t mid = r0 + (r1 - r0) / 2;
        runs.emplace_back(mid + 1, r1);
        runs.emplace_back(r0, mid);
      }
    }
    std::sort(open.begin(), open.end());
    open.erase(std::unique(open.begin(), open.end()), open.end());
    return -1;
  }

 private:
  // For each leaf, the leaves whose support meets its cell, ascending.
  void build_near_lists(const Context* ctx) {
    std::vector<std::size_t> leaf_node(leaves_.size());
    for (std::size_t id = 0; id < nodes_.size(); ++id)
      if (nodes_[id].leaf >= 0) leaf_node[static_cast<std::size_t>(nodes_[id].leaf)] = id;
    std::vector<std::vector<std::uint32_t>> lists(leaves_.size());
    parallel::for_each(
        leaves_.size(), 64,
        [&](std::size_t l) {
          const Aabb& cell = nodes_[leaf_node[l]].box;
          std::vector<std::int32_t> stack{0};
          while (!stack.empty()) {
            const Node& node = nodes_[static_cast<std::size_t>(stack.back())];
            stack.pop_back();
            if (!node.reach.intersects(cell)) continue;
            if (node.leaf < 0) {
              for (std::int32_t c = 0; c < 8; ++c) stack.push_back(node.first_child + c);
              continue;
            }
            const Leaf& leaf = leaves_[static_cast<std::size_t>(node.leaf)];
            if (squared_distance(cell, leaf.centre) < leaf.radius * leaf.radius)
              lists[l].push_back(static_cast<std::uint32_t>(node.leaf));
          }
          std::sort(lists[l].begin(), lists[l].end());
        },
        ctx);
    near_begin_.assign(leaves_.size() + 1, 0);
    for (std::size_t l = 0; l < leaves_.size(); ++l)
      near_begin_[l + 1] = near_begin_[l] + lists[l].size();
    near_.reserve(near_begin_.back());
    for (const auto& list : lists) near_.insert(near_.end(), list.begin(), list.end());
  }

  // A box around every point where f may be > iso: the union of the boxes, down kBoundsLevels
  // subdivisions of the root's reach, whose bound allows an inside value.
  Aabb inside_box() const {
    Aabb result;
    std::vector<std::pair<Aabb, int>> stack{{nodes_.front().reach, 0}};
    while (!stack.empty()) {
      const auto [box, level] = stack.back();
      stack.pop_back();
      if (!(native_bound(box).lo < 0)) continue;
      if (level == kBoundsLevels) {
        result.extend(box);
        continue;
      }
      const Vec3 mid = box.center();
      for (int c = 0; c < 8; ++c) {
        Vec3 lo = box.min(), hi = mid;
        for (int k = 0; k < 3; ++k) {
          if ((c >> k) & 1) {
            lo[k] = mid[k];
            hi[k] = box.max()[k];
          }
        }
        stack.emplace_back(Aabb(lo, hi), level + 1);
      }
    }
    return result;
  }

  // Node status: f_mpu ≥ 0 on the whole box (outside, f ≤ iso), < 0 on the whole box (inside),
  // or neither proven.
  static constexpr std::int8_t kUnknown = 0, kOutside = 1, kInside = -1;
  // ray_samples: runs of at most this many samples are left open without a bound (a bound
  // over a cell's near list costs about as much as one or two evaluations; measured on the
  // bunny, docs/benchmarks.md: 5 against 3 or 7).
  static constexpr std::int64_t kDirectRun = 5;

  // Each leaf's support ball, compact (the near lists' loops test these first).
  struct Support {
    Vec3 centre;
    double radius2;
  };

  std::vector<Node> nodes_;
  std::vector<Leaf> leaves_;
  std::vector<Support> support_;
  std::vector<std::int8_t> status_;
  std::vector<MpuCell> cells_;
  std::vector<std::size_t> near_begin_;  // leaf l's list: near_[near_begin_[l], near_begin_[l + 1])
  std::vector<std::uint32_t> near_;
  Aabb root_;
  Aabb clip_;  // the points' box padded by kClipMargin of its diagonal
  double background_reach_;
  std::size_t point_count_;
  MpuStats stats_;
  Aabb bounds_;
};

void validate(const PointSet& points, const MpuOptions& o) {
  if (!std::isfinite(o.iso))
    throw InvalidArgument("mpu: iso must be finite, got " + format_number(o.iso));
  if (!std::isfinite(o.tolerance) || !(o.tolerance > 0))
    throw InvalidArgument("mpu: tolerance must be finite and > 0, got " +
                          format_number(o.tolerance));
  if (!std::isfinite(o.support) || !(o.support > 0.5) || o.support > 100)
    throw InvalidArgument("mpu: support must be in (0.5, 100], got " + format_number(o.support));
  if (o.min_points < 6 || o.min_points > 100000)
    throw InvalidArgument("mpu: min_points must be in 6..100000, got " +
                          std::to_string(o.min_points));
  if (o.max_depth < 0 || o.max_depth > 20)
    throw InvalidArgument("mpu: max_depth must be in 0..20, got " + std::to_string(o.max_depth));
  const std::size_t n = points.positions.size();
  if (points.normals.size() != n) {
    throw InvalidArgument("mpu: needs one normal per point, got " +
                          std::to_string(points.normals.size()) + " normals for " +
                          std::to_string(n) + " points");
  }
  if (n < static_cast<std::size_t>(o.min_points)) {
    throw InvalidArgument("mpu: needs at least min_points = " + std::to_string(o.min_points) +
                          " points, got " + std::to_string(n));
  }
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw InvalidArgument("mpu: too many points (" + std::to_string(n) + ")");
  for (std::size_t i = 0; i < n; ++i) {
    if (!points.positions[i].allFinite())
      throw InvalidArgument("mpu: point " + std::to_string(i) + " has a non-finite position");
    const Vec3& m = points.normals[i];
    if (!m.allFinite() || !(m.norm() > 0))
      throw InvalidArgument("mpu: point " + std::to_string(i) + " has a zero or non-finite normal");
  }
}

}  // namespace

FieldPtr make_mpu_field(const PointSet& points, const MpuOptions& options, MpuStats* stats,
                        const Context* ctx) {
  const auto start = std::chrono::steady_clock::now();
  validate(points, options);
  const std::vector<Vec3>& pos = points.positions;
  std::vector<Vec3> nrm(points.normals.size());
  for (std::size_t i = 0; i < nrm.size(); ++i) nrm[i] = points.normals[i].normalized();
  Aabb box;
  for (const Vec3& p : pos) box.extend(p);
  const double diagonal = box.diagonal().norm();
  if (!(diagonal > 0)) throw InvalidArgument("mpu: all points coincide");
  {
    // Points on one line say nothing about a surface around it (their normals are arbitrary):
    // refused rather than fitted to a blob.
    const Vec3 mean = box.center();
    Mat3 cov = Mat3::Zero();
    for (const Vec3& p : pos) cov.noalias() += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
    // The largest distance from the principal axis, measured directly (the middle eigenvalue
    // cannot resolve a spread below about 1e-8 of the size).
    const Vec3 axis = eig.eigenvectors().col(2);
    double across = 0;
    for (const Vec3& p : pos) {
      const Vec3 d = p - mean;
      across = std::max(across, (d - d.dot(axis) * axis).norm());
    }
    if (!(across > 1e-9 * diagonal)) {
      throw InvalidArgument("mpu: the " + std::to_string(pos.size()) +
                            " points lie on one line (the farthest is " + format_number(across) +
                            " from it, for a box diagonal of " + format_number(diagonal) +
                            "): no surface can be fitted");
    }
  }
  const double tolerance = options.tolerance * diagonal;
  const double edge = kRootScale * box.sizes().maxCoeff();
  const Aabb root(box.center() - Vec3::Constant(0.5 * edge),
                  box.center() + Vec3::Constant(0.5 * edge));

  const Aabb clip(box.min() - Vec3::Constant(kClipMargin * diagonal),
                  box.max() + Vec3::Constant(kClipMargin * diagonal));
  const detail::PointKdTree tree(pos);
  const Fitter fitter(pos, nrm, tree, options);

  std::vector<Node> nodes{Node{root, 0, -1, -1, Aabb()}};
  std::vector<std::vector<std::uint32_t>> members(1);  // points inside each node's cell
  members[0].resize(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) members[0][i] = static_cast<std::uint32_t>(i);
  std::vector<Leaf> leaves;
  MpuStats st;
  st.points = pos.size();

  std::size_t level_begin = 0, level_end = 1;
  while (level_begin < level_end) {
    check_cancel(ctx);
    const std::size_t count = level_end - level_begin;
    std::vector<CellFit> fits(count);
    parallel::for_each(
        count, 1, [&](std::size_t k) { fits[k] = fitter.fit(nodes[level_begin + k].box); }, ctx);
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t id = level_begin + k;
      const CellFit& cf = fits[k];
      const int depth = nodes[id].depth;
      const bool split = (cf.error > tolerance || !cf.consistent) && depth < options.max_depth &&
                         cf.initial_count >= static_cast<std::size_t>(options.min_points);
      if (!split) {
        nodes[id].leaf = static_cast<std::int32_t>(leaves.size());
        leaves.push_back({nodes[id].box.center(), cf.radius, cf.fit});
        st.depth = std::max(st.depth, depth);
        st.fit_error_max = std::max(st.fit_error_max, cf.error);
        st.fallbacks += cf.fallback ? 1 : 0;
        (cf.fit.kind == FitKind::kBivariate ? st.bivariate
         : cf.fit.kind == FitKind::kSharp   ? st.sharp
                                            : st.general_quadrics) += 1;
        continue;
      }
      const Aabb cell = nodes[id].box;
      const Vec3 mid = cell.center();
      nodes[id].first_child = static_cast<std::int32_t>(nodes.size());
      std::array<std::vector<std::uint32_t>, 8> part;
      for (const std::uint32_t i : members[id]) {
        const Vec3& p = pos[i];
        part[static_cast<std::size_t>((p.x() >= mid.x()) + 2 * (p.y() >= mid.y()) +
                                      4 * (p.z() >= mid.z()))]
            .push_back(i);
      }
      std::vector<std::uint32_t>().swap(members[id]);
      for (int c = 0; c < 8; ++c) {
        Vec3 lo = cell.min(), hi = mid;
        for (int a = 0; a < 3; ++a) {
          if ((c >> a) & 1) {
            lo[a] = mid[a];
            hi[a] = cell.max()[a];
          }
        }
        nodes.push_back(Node{Aabb(lo, hi), depth + 1, -1, -1, Aabb()});
        members.push_back(std::move(part[static_cast<std::size_t>(c)]));
      }
    }
    level_begin = level_end;
    level_end = nodes.size();
  }
  // Reach boxes bottom-up (children always come after their parent).
  for (std::size_t id = nodes.size(); id-- > 0;) {
    Node& node = nodes[id];
    if (node.leaf >= 0) {
      const Leaf& leaf = leaves[static_cast<std::size_t>(node.leaf)];
      node.reach = Aabb(leaf.centre - Vec3::Constant(leaf.radius),
                        leaf.centre + Vec3::Constant(leaf.radius));
    } else {
      node.reach = Aabb();
      for (int c = 0; c < 8; ++c)
        node.reach.extend(nodes[static_cast<std::size_t>(node.first_child + c)].reach);
    }
  }
  // The leaf cells in depth-first order.
  std::vector<MpuCell> cells;
  cells.reserve(leaves.size());
  std::vector<std::int32_t> stack{0};
  while (!stack.empty()) {
    const auto id = static_cast<std::size_t>(stack.back());
    stack.pop_back();
    if (nodes[id].leaf < 0) {
      for (std::int32_t c = 7; c >= 0; --c) stack.push_back(nodes[id].first_child + c);
      continue;
    }
    cells.push_back({nodes[id].box, nodes[id].depth, std::move(members[id])});
  }
  st.cells = nodes.size();
  st.leaves = leaves.size();
  auto field = std::make_shared<MpuField>(options.iso, std::move(nodes), std::move(leaves),
                                          std::move(cells), root, clip, pos.size(), st, ctx);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats != nullptr) *stats = st;
  return field;
}

bool detail::mpu_ray_samples(const Field& field, const RaySamples& ray, bool stop_inside,
                             std::int64_t& candidate, std::vector<std::uint32_t>& open) {
  const auto* mpu = dynamic_cast<const MpuField*>(&field);
  if (mpu == nullptr) return false;
  candidate = mpu->ray_samples(ray, stop_inside, open);
  return true;
}

std::vector<MpuCell> mpu_leaf_cells(const Field& field) {
  const auto* mpu = dynamic_cast<const MpuField*>(&field);
  return mpu != nullptr ? mpu->cells() : std::vector<MpuCell>{};
}

}  // namespace ramiform
