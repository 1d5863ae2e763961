// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/radius_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/skeleton/generate.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

using SparseRow = Eigen::SparseMatrix<double, Eigen::RowMajor>;

const SkeletonFieldOptions kConvolution{};  // Cauchy convolution, c = 1, iso 1

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Samples of a report whose edge's mean requested radius lies in [lo, hi).
std::vector<double> errors_in_class(const RadiusErrorReport& rep, const Skeleton& s, double lo,
                                    double hi) {
  std::vector<double> out;
  for (std::size_t i = 0; i < rep.errors.size(); ++i) {
    const auto& e = s.edges[rep.sample_edge[i]];
    const double r = 0.5 * (s.nodes[e[0]].radius + s.nodes[e[1]].radius);
    if (r >= lo && r < hi) out.push_back(rep.errors[i]);
  }
  return out;
}

// The fit's last least-squares problem written out independently from its parts: dense
// N = F^T Omega F + mu diag(D), b = F^T Omega (T - o) + mu D, D_i = sum_j omega_j F_ji^2.
struct DenseProblem {
  Eigen::MatrixXd N;
  Eigen::VectorXd b;
};
DenseProblem dense_problem(const RadiusFitSystem& sys, const RadiusFitResult& r, double mu) {
  const Eigen::MatrixXd F = Eigen::MatrixXd(sys.matrix);
  const Eigen::Index m = F.rows();
  Eigen::VectorXd omega(m), target(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    omega[j] = r.row_weight[static_cast<std::size_t>(j)];
    target[j] = sys.iso - r.row_offset[static_cast<std::size_t>(j)];
  }
  DenseProblem p;
  p.N = F.transpose() * omega.asDiagonal() * F;
  p.b = F.transpose() * omega.asDiagonal() * target;
  for (Eigen::Index i = 0; i < F.cols(); ++i) {
    const double d = (omega.array() * F.col(i).array().square()).sum();
    p.N(i, i) += mu * d;
    p.b[i] += mu * d;
  }
  return p;
}

// KKT conditions of that problem (relative to the diagonal, as documented); returns the number
// of weights held at 0.
int expect_kkt(const RadiusFitSystem& sys, const RadiusFitResult& r, const RadiusFitOptions& o) {
  const DenseProblem p = dense_problem(sys, r, o.regularization);
  const Eigen::Map<const Eigen::VectorXd> w(r.weights.data(),
                                            static_cast<Eigen::Index>(r.weights.size()));
  const Eigen::VectorXd g = p.N * w - p.b;
  // The independent N sums in another order: allow rounding on top of the tolerance.
  const double tol = 10 * o.kkt_tolerance;
  // The bounded problem w >= min_weight has the same conditions with the bound in place of 0.
  const double low = o.min_weight;
  int zeros = 0;
  for (Eigen::Index i = 0; i < w.size(); ++i) {
    EXPECT_GE(w[i], low) << "edge " << i;
    if (p.N(i, i) == 0) {
      EXPECT_EQ(w[i], 1.0) << "edge " << i << " has no data and keeps weight 1";
      continue;
    }
    if (w[i] > low) {
      EXPECT_LE(std::abs(g[i]), tol * p.N(i, i)) << "edge " << i << " w " << w[i];
    } else {
      ++zeros;
      EXPECT_GE(g[i], -tol * p.N(i, i)) << "edge " << i << " at the bound";
    }
  }
  return zeros;
}

// Y-fork plus a thin rod inside the upper trunk: the rod's own constraint points all lie inside
// the trunk's tube (skipped), and the trunk's points there already have enough field, so its
// weight goes to 0 (measured; nearer the free root end it would fill the pulled-in end).
Skeleton fork_with_hidden_rod() {
  Skeleton s = test::y_fork();
  const auto base = static_cast<std::uint32_t>(s.nodes.size());
  s.nodes.push_back({Vec3(0, 0, 6), 0.25});
  s.nodes.push_back({Vec3(0, 0, 8), 0.25});
  s.edges.push_back({base, base + 1});
  return s;
}

// A smaller tree with root radius about 1 and tips 0.02 (pipe exponent 1.6 over ~128 tips).
Skeleton small_tree(std::size_t segments, std::uint64_t seed = 3) {
  BranchingTreeOptions o;
  o.segments = segments;
  o.seed = seed;
  o.tip_radius = 0.02;
  o.pipe_exponent = 1.6;
  return branching_tree(o);
}

// ---------------------------------------------------------------------------------------------

TEST(RadiusFit, MatrixIsTheFieldAndTheIntegral) {
  // Every entry against an independent composite Simpson quadrature of
  // lambda_i * integral 1/(1 + s^2 |p - q|^2)^2 dq, with s = c/r and
  // lambda = 2 c iso (1 + c^2)^(3/2) / (pi r) from docs/fields.md (c = 1, iso = 1).
  const Skeleton s = test::y_fork();
  RadiusFitOptions o;
  o.near_level = 0;  // keep every contribution
  const RadiusFitSystem sys = build_radius_fit_system(s, kConvolution, o);
  ASSERT_EQ(sys.matrix.cols(), 3);
  ASSERT_EQ(sys.points.size(), static_cast<std::size_t>(sys.matrix.rows()));
  ASSERT_GT(sys.points.size(), 50u);
  const Eigen::MatrixXd F = Eigen::MatrixXd(sys.matrix);
  for (std::size_t j = 0; j < sys.points.size(); ++j) {
    for (int i = 0; i < 3; ++i) {
      const auto& na = s.nodes[s.edges[static_cast<std::size_t>(i)][0]];
      const auto& nb = s.nodes[s.edges[static_cast<std::size_t>(i)][1]];
      const double r = 0.5 * (na.radius + nb.radius);
      const double sw = 1 / r;
      const double lambda = 2 * std::pow(2.0, 1.5) / (std::numbers::pi * r);
      const int n = 4000;
      const double len = (nb.position - na.position).norm();
      double sum = 0;
      for (int k = 0; k <= n; ++k) {
        const Vec3 q = na.position + (nb.position - na.position) * (static_cast<double>(k) / n);
        const double d2 = (sys.points[j] - q).squaredNorm();
        const double kern = 1 / ((1 + sw * sw * d2) * (1 + sw * sw * d2));
        sum += (k == 0 || k == n ? 1 : (k % 2 == 1 ? 4 : 2)) * kern;
      }
      const double expected = lambda * sum * len / (3.0 * n);
      EXPECT_NEAR(F(static_cast<Eigen::Index>(j), i), expected, 1e-9 * expected)
          << "point " << j << " edge " << i;
    }
  }
  // Sum_i w_i F_ji is the field with weights w (no point lies in a fade band here).
  Rng rng(5);
  for (int trial = 0; trial < 3; ++trial) {
    std::vector<double> w(3, 1.0);
    if (trial > 0) {
      for (double& x : w) x = rng.uniform(0.3, 1.7);
    }
    const FieldPtr f = make_skeleton_field(s, kConvolution, w);
    std::vector<double> v(sys.points.size());
    f->evaluate(sys.points, v);
    const Eigen::VectorXd model = F * Eigen::Map<const Eigen::VectorXd>(w.data(), 3);
    for (std::size_t j = 0; j < v.size(); ++j) {
      EXPECT_NEAR(model[static_cast<Eigen::Index>(j)], v[j], 1e-12 * v[j])
          << "trial " << trial << " point " << j;
    }
  }
}

TEST(RadiusFit, ConstraintPointsLieOnTheRequestedSurface) {
  // Each kept point is at its edge's interpolated radius (station circles) or at a node radius
  // from a node (node circles), and outside every other edge's requested tube.
  const Skeleton s = test::y_fork();
  const RadiusFitSystem sys = build_radius_fit_system(s, kConvolution);
  ASSERT_EQ(sys.point_edge.size(), sys.points.size());
  for (std::size_t j = 0; j < sys.points.size(); ++j) {
    const auto& e = s.edges[sys.point_edge[j]];
    const Vec3 a = s.nodes[e[0]].position, b = s.nodes[e[1]].position;
    long double t = 0;
    const double d = test::brute_distance(sys.points[j], a, b, &t);
    const double r = (1 - static_cast<double>(t)) * s.nodes[e[0]].radius +
                     static_cast<double>(t) * s.nodes[e[1]].radius;
    const bool on_station = std::abs(d - r) < 1e-9 * r;
    const bool on_node = std::abs((sys.points[j] - a).norm() - s.nodes[e[0]].radius) < 1e-9 ||
                         std::abs((sys.points[j] - b).norm() - s.nodes[e[1]].radius) < 1e-9;
    EXPECT_TRUE(on_station || on_node) << "point " << j;
    for (std::size_t k = 0; k < s.edges.size(); ++k) {
      if (k == sys.point_edge[j]) continue;
      const Vec3 c = s.nodes[s.edges[k][0]].position, dd = s.nodes[s.edges[k][1]].position;
      long double tk = 0;
      const double dist = test::brute_distance(sys.points[j], c, dd, &tk);
      const double rk = (1 - static_cast<double>(tk)) * s.nodes[s.edges[k][0]].radius +
                        static_cast<double>(tk) * s.nodes[s.edges[k][1]].radius;
      EXPECT_GE(dist, rk * (1 - 1e-3) - 1e-9) << "point " << j << " inside edge " << k;
    }
  }
  // 3 edges x 3 stations x 6 points, plus the joint's circles that stay outside the branches
  // (the tips, degree 1, get none by default).
  EXPECT_GE(sys.points.size(), 54u);
  EXPECT_LT(sys.points.size(), 54u + 3 * 6);
}

TEST(RadiusFit, LongSegmentKeepsWeightOne) {
  const Skeleton s = test::single_segment(Vec3(0, 0, 0), Vec3(0, 0, 40), 1.0, 1.0);
  const RadiusFitResult r = fit_edge_weights(s, kConvolution);
  ASSERT_EQ(r.weights.size(), 1u);
  EXPECT_TRUE(r.converged);
  // Measured 1.0013: the free ends pull the end stations in a little, and the fit feeds them.
  EXPECT_NEAR(r.weights[0], 1.0, 0.005);
  const RadiusErrorReport rep =
      measure_radius_error(*make_skeleton_field(s, kConvolution, r.weights), s);
  EXPECT_EQ(rep.samples, 32u);
  EXPECT_LT(rep.median, 0.003);  // measured 0.14 % (unit weight: 0.15 %)
  EXPECT_LT(rep.max, 0.005);     // measured 0.20 % (unit weight: 0.29 %), 5 radii from the ends
}

TEST(RadiusFit, YForkFittedFarBelowUnfitted) {
  const Skeleton fork = test::y_fork();
  // Unfitted, unsplit: junction swell, free ends and the taper (one kernel width per edge).
  const RadiusErrorReport plain =
      measure_radius_error(*make_skeleton_field(fork, kConvolution), fork);
  // Split into pieces (<= 4 radii, <= 10 % taper), unfitted and fitted, measured against the
  // original fork's requested radii.
  const SplitSkeleton split = split_edges(fork);
  const RadiusErrorReport unit =
      measure_radius_error(*make_skeleton_field(split.skeleton, kConvolution), fork);
  const RadiusFitResult r = fit_edge_weights(split.skeleton, kConvolution);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.residual_rms, r.unit_residual_rms);
  const RadiusErrorReport fitted =
      measure_radius_error(*make_skeleton_field(split.skeleton, kConvolution, r.weights), fork);
  EXPECT_EQ(fitted.samples + fitted.skipped, 3u * 4 * 8);
  // Measured: plain median 6.1 % (p90 17 %, max 22 %); split, unit weights 1.35 % (p90 10.5 %,
  // max 76 %: webbing at the joint); split and fitted 0.93 % (p90 5.0 %, max 37 %).
  EXPECT_GT(plain.median, 0.05);
  EXPECT_LT(fitted.median, 0.012);
  EXPECT_LT(fitted.median, unit.median);
  EXPECT_LT(fitted.median, 0.2 * plain.median);
  EXPECT_LT(fitted.p90, 0.6 * unit.p90);
  EXPECT_LT(fitted.max, 0.6 * unit.max);
  EXPECT_LT(fitted.mean, 0.6 * unit.mean);
}

TEST(RadiusFit, BranchingTreeTrunkAndTwigs) {
  // Radii from about 1 at the root down to 0.02 at the tips.
  const Skeleton tree = small_tree(1000);
  double rmax = 0, rmin = 1e9;
  for (const auto& n : tree.nodes) {
    rmax = std::max(rmax, n.radius);
    rmin = std::min(rmin, n.radius);
  }
  ASSERT_GT(rmax, 0.9);
  ASSERT_NEAR(rmin, 0.02, 1e-12);
  const SplitSkeleton split = split_edges(tree);
  const RadiusFitResult r = fit_edge_weights(split.skeleton, kConvolution);
  EXPECT_TRUE(r.converged);
  const RadiusErrorReport unit =
      measure_radius_error(*make_skeleton_field(split.skeleton, kConvolution), tree);
  const RadiusErrorReport fitted =
      measure_radius_error(*make_skeleton_field(split.skeleton, kConvolution, r.weights), tree);
  const double trunk_unit = median_of(errors_in_class(unit, tree, 0.3, 10));
  const double trunk = median_of(errors_in_class(fitted, tree, 0.3, 10));
  const double twig_unit = median_of(errors_in_class(unit, tree, 0, 0.04));
  const double twig = median_of(errors_in_class(fitted, tree, 0, 0.04));
  ASSERT_GT(errors_in_class(fitted, tree, 0.3, 10).size(), 100u);
  ASSERT_GT(errors_in_class(fitted, tree, 0, 0.04).size(), 1000u);
  // Measured (1000 edges -> 4988 pieces): trunk (r >= 0.3) median 21.7 % unfitted -> 2.2 %,
  // twigs (r < 0.04) 1.73 % -> 0.97 %; overall median 2.5 % -> 0.97 %, p90 21 % -> 5.9 %.
  EXPECT_LT(trunk, 0.03);
  EXPECT_LT(twig, 0.013);
  EXPECT_LT(trunk, 0.2 * trunk_unit);
  EXPECT_LT(twig, 0.7 * twig_unit);
  EXPECT_LT(fitted.median, 0.013);
  EXPECT_LT(fitted.p90, 0.4 * unit.p90);
}

TEST(RadiusFit, KktConditionsHoldDenseAndSparse) {
  const Skeleton s = fork_with_hidden_rod();
  // Plain NNLS (no floor, no coverage repair) and the default floor of 0.25: the hidden rod
  // only adds field where the trunk already has enough, so it sits on the bound either way.
  for (const double floor : {0.0, 0.25}) {
    for (const NnlsSolver solver : {NnlsSolver::kDense, NnlsSolver::kSparse}) {
      RadiusFitOptions o;
      o.solver = solver;
      o.min_weight = floor;
      o.coverage_margin = 0;  // the repair runs after the solve and would move the weights
      const RadiusFitSystem sys = build_radius_fit_system(s, kConvolution, o);
      const RadiusFitResult r = solve_radius_fit(sys, o);
      EXPECT_TRUE(r.converged);
      EXPECT_LE(r.kkt_violation, o.kkt_tolerance);
      ASSERT_EQ(r.row_weight.size(), sys.points.size());
      const int zeros = expect_kkt(sys, r, o);
      EXPECT_EQ(r.weights[3], floor) << "the hidden rod sits on the bound";
      EXPECT_GE(zeros, 1);
    }
  }
  // A larger problem through the sparse solver (the default for this size).
  const Skeleton tree = split_edges(small_tree(60)).skeleton;
  ASSERT_GT(tree.edges.size(), 200u);
  RadiusFitOptions o;
  o.coverage_margin = 0;
  const RadiusFitSystem sys = build_radius_fit_system(tree, kConvolution, o);
  const RadiusFitResult r = solve_radius_fit(sys, o);
  EXPECT_TRUE(r.converged);
  expect_kkt(sys, r, o);
}

// The coverage repair: with the default options every point of the skeleton ends inside the
// fitted surface with the margin, and no weight is below the floor.
TEST(RadiusFit, FittedSurfaceCoversTheSkeleton) {
  const Skeleton tree = split_edges(small_tree(60)).skeleton;
  const RadiusFitOptions o;
  const RadiusFitResult r = fit_edge_weights(tree, kConvolution, o);
  EXPECT_TRUE(r.covered);
  for (const double w : r.weights) EXPECT_GE(w, o.min_weight);
  const FieldPtr f = make_skeleton_field(tree, kConvolution, r.weights);
  std::vector<Vec3> samples;
  for (const auto& e : tree.edges) {
    for (int k = 0; k <= 8; ++k) {
      const double t = k / 8.0;
      samples.push_back((1 - t) * tree.nodes[e[0]].position + t * tree.nodes[e[1]].position);
    }
  }
  std::vector<double> values(samples.size());
  f->evaluate(samples, values);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    EXPECT_GT(values[i], f->iso()) << "sample " << i << " of edge " << i / 9;
  }
}

TEST(RadiusFit, SparseMatchesDenseLawsonHanson) {
  for (const Skeleton& s : {fork_with_hidden_rod(), split_edges(small_tree(25)).skeleton}) {
    RadiusFitOptions dense, sparse;
    dense.solver = NnlsSolver::kDense;
    sparse.solver = NnlsSolver::kSparse;
    const RadiusFitSystem sys = build_radius_fit_system(s, kConvolution, dense);
    const RadiusFitResult a = solve_radius_fit(sys, dense);
    const RadiusFitResult b = solve_radius_fit(sys, sparse);
    ASSERT_EQ(a.weights.size(), b.weights.size());
    EXPECT_TRUE(a.converged);
    EXPECT_TRUE(b.converged);
    for (std::size_t i = 0; i < a.weights.size(); ++i) {
      EXPECT_NEAR(a.weights[i], b.weights[i], 1e-8) << "edge " << i << " of " << a.weights.size();
      EXPECT_EQ(a.weights[i] == 0, b.weights[i] == 0) << "edge " << i;
    }
    EXPECT_NEAR(a.residual_rms, b.residual_rms, 1e-10);
  }
}

TEST(RadiusFit, IdenticalForAnyThreadCount) {
  const Skeleton tree = split_edges(small_tree(200)).skeleton;
  Context one(1), two(2), all(0);
  const RadiusFitResult a = fit_edge_weights(tree, kConvolution, {}, &one);
  const RadiusFitResult b = fit_edge_weights(tree, kConvolution, {}, &two);
  const RadiusFitResult c = fit_edge_weights(tree, kConvolution, {}, &all);
  EXPECT_EQ(a.weights, b.weights);
  EXPECT_EQ(a.weights, c.weights);
  EXPECT_EQ(a.residual_rms, b.residual_rms);
}

TEST(RadiusFit, PlainLeastSquaresAndFarFieldRounds) {
  // Without the Huber weights (robust_threshold 0) the rows keep weight 1; the far-field offset
  // is then the only thing the rounds change. The last round's model F w + o (far part at the
  // previous round's weights) is the field of the fitted weights at the points, nearly.
  const Skeleton tree = split_edges(small_tree(60)).skeleton;
  RadiusFitOptions o;
  o.robust_threshold = 0;
  const RadiusFitSystem sys = build_radius_fit_system(tree, kConvolution, o);
  const RadiusFitResult r = solve_radius_fit(sys, o);
  EXPECT_TRUE(r.converged);
  for (const double omega : r.row_weight) EXPECT_EQ(omega, 1.0);
  expect_kkt(sys, r, o);
  // The far part is small (contributions below near_level * iso each; measured at most 0.0036).
  double worst = 0;
  for (const double off : r.row_offset) worst = std::max(worst, std::abs(off));
  EXPECT_LT(worst, 0.02 * sys.iso);
  EXPECT_GT(worst, 0.0);
  const FieldPtr f = make_skeleton_field(tree, kConvolution, r.weights);
  std::vector<double> v(sys.points.size());
  f->evaluate(sys.points, v);
  const Eigen::VectorXd model =
      sys.matrix * Eigen::Map<const Eigen::VectorXd>(r.weights.data(),
                                                     static_cast<Eigen::Index>(r.weights.size()));
  double gap = 0;
  for (std::size_t j = 0; j < v.size(); ++j) {
    gap = std::max(gap, std::abs(model[static_cast<Eigen::Index>(j)] + r.row_offset[j] - v[j]));
  }
  EXPECT_LT(gap, 1e-8 * sys.iso);  // measured 1.2e-12: the rounds reach their fixed point
}

TEST(RadiusFit, NearFarSplitBarelyMovesTheWeights) {
  // near_level 0 keeps every contribution in F: the exact NNLS of the full field. The default
  // (1e-3) holds the far part at the previous round's weights; measured weight differences
  // 1e-4 (529 pieces) to 2e-3 (1807 pieces).
  const Skeleton tree = split_edges(small_tree(60)).skeleton;
  RadiusFitOptions exact;
  exact.near_level = 0;
  const RadiusFitResult a = fit_edge_weights(tree, kConvolution, exact);
  const RadiusFitResult b = fit_edge_weights(tree, kConvolution);
  EXPECT_GT(a.nonzeros, b.nonzeros * 3 / 2);
  ASSERT_EQ(a.weights.size(), b.weights.size());
  for (std::size_t i = 0; i < a.weights.size(); ++i)
    EXPECT_NEAR(a.weights[i], b.weights[i], 2e-3) << "edge " << i;
  EXPECT_NEAR(a.residual_rms, b.residual_rms, 1e-4);
}

TEST(RadiusFit, Validation) {
  const Skeleton s = test::y_fork();
  auto bad = [&](auto change) {
    RadiusFitOptions o;
    change(o);
    EXPECT_THROW((void)fit_edge_weights(s, kConvolution, o), InvalidArgument);
  };
  bad([](RadiusFitOptions& o) { o.stations_per_edge = 0; });
  bad([](RadiusFitOptions& o) { o.points_per_circle = 2; });
  bad([](RadiusFitOptions& o) { o.regularization = -1; });
  bad([](RadiusFitOptions& o) { o.kkt_tolerance = 0; });
  bad([](RadiusFitOptions& o) { o.robust_threshold = std::nan(""); });
  bad([](RadiusFitOptions& o) { o.outer_rounds = -1; });
  bad([](RadiusFitOptions& o) { o.near_level = 1; });
  bad([](RadiusFitOptions& o) { o.max_iterations = -2; });
  SkeletonFieldOptions distance;
  distance.surface = SurfaceKind::kDistance;
  distance.kernel = Kernel{KernelKind::kWyvill, 0.0};
  EXPECT_THROW((void)fit_edge_weights(s, distance), InvalidArgument);
  Skeleton broken = s;
  broken.nodes[1].radius = -1;
  EXPECT_THROW((void)fit_edge_weights(broken, kConvolution), InputError);
  RadiusErrorOptions m;
  m.search_factor = 1;
  EXPECT_THROW((void)measure_radius_error(*make_skeleton_field(s), s, m), InvalidArgument);
  m = {};
  m.directions = 0;
  EXPECT_THROW((void)measure_radius_error(*make_skeleton_field(s), s, m), InvalidArgument);
  EdgeSplitOptions e;
  e.max_taper = 1;
  EXPECT_THROW((void)split_edges(s, e), InvalidArgument);
  e = {};
  e.max_length = 0;
  EXPECT_THROW((void)split_edges(s, e), InvalidArgument);
}

TEST(RadiusFit, Cancellation) {
  const Skeleton s = test::y_fork();
  Context ctx;
  ctx.cancel();
  EXPECT_THROW((void)fit_edge_weights(s, kConvolution, {}, &ctx), Cancelled);
  EXPECT_THROW((void)measure_radius_error(*make_skeleton_field(s), s, {}, &ctx), Cancelled);
}

TEST(RadiusFit, EmptyEdgeSetAndUnseenEdges) {
  // A lone node: no edges, no unknowns.
  Skeleton point;
  point.nodes.push_back({Vec3(0, 0, 0), 1.0});
  const RadiusFitResult r = fit_edge_weights(point, kConvolution);
  EXPECT_TRUE(r.weights.empty());
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(measure_radius_error(*make_skeleton_field(point), point).samples, 0u);
}

// ---------------------------------------------------------------------------------------------

TEST(SplitEdges, PiecesFollowTheLimits) {
  const Skeleton tree = small_tree(80);
  EdgeSplitOptions o;
  o.max_length = 3.0;
  o.max_taper = 0.08;
  const SplitSkeleton split = split_edges(tree, o);
  const Skeleton& s = split.skeleton;
  validate(s);
  ASSERT_EQ(split.edge_origin.size(), s.edges.size());
  // Original nodes keep their indices and values.
  for (std::size_t i = 0; i < tree.nodes.size(); ++i) {
    EXPECT_EQ(s.nodes[i].position, tree.nodes[i].position);
    EXPECT_EQ(s.nodes[i].radius, tree.nodes[i].radius);
  }
  std::vector<double> length(tree.edges.size(), 0.0);
  for (std::size_t k = 0; k < s.edges.size(); ++k) {
    const auto& e = s.edges[k];
    const auto& a = s.nodes[e[0]];
    const auto& b = s.nodes[e[1]];
    const double len = (b.position - a.position).norm();
    EXPECT_LE(len, o.max_length * 0.5 * (a.radius + b.radius) * (1 + 1e-9)) << "piece " << k;
    EXPECT_LE(std::abs(a.radius - b.radius) / std::max(a.radius, b.radius), o.max_taper + 1e-9)
        << "piece " << k;
    // Each piece lies on its original edge, with the linearly interpolated radius.
    const auto& orig = tree.edges[split.edge_origin[k]];
    const Vec3 p0 = tree.nodes[orig[0]].position, p1 = tree.nodes[orig[1]].position;
    for (const auto* n : {&a, &b}) {
      long double t = 0;
      EXPECT_LT(test::brute_distance(n->position, p0, p1, &t), 1e-9);
      const double r = (1 - static_cast<double>(t)) * tree.nodes[orig[0]].radius +
                       static_cast<double>(t) * tree.nodes[orig[1]].radius;
      EXPECT_NEAR(n->radius, r, 1e-9 * r);
    }
    length[split.edge_origin[k]] += len;
  }
  for (std::size_t e = 0; e < tree.edges.size(); ++e) {
    const double len =
        (tree.nodes[tree.edges[e][1]].position - tree.nodes[tree.edges[e][0]].position).norm();
    EXPECT_NEAR(length[e], len, 1e-9 * len) << "edge " << e;
  }
  EXPECT_GT(s.edges.size(), 2 * tree.edges.size());
  // Connectivity is unchanged: still one component, still a tree.
  EXPECT_EQ(connected_components(s).count, 1u);
  EXPECT_EQ(s.edges.size() + 1, s.nodes.size());
  // A short, untapered edge stays whole.
  const Skeleton one = test::single_segment(Vec3(0, 0, 0), Vec3(0, 0, 3), 1.0, 1.0);
  EXPECT_EQ(split_edges(one).skeleton.edges.size(), 1u);
  EXPECT_EQ(split_edges(test::single_segment(Vec3(0, 0, 0), Vec3(0, 0, 10), 1.0, 1.0))
                .skeleton.edges.size(),
            3u);
}

// ---------------------------------------------------------------------------------------------

TEST(MeasureRadiusError, ExactOnADistanceSurface) {
  // A lone Wyvill distance segment has its surface at exactly the node radius (R = r / x_iso):
  // the measured error is the root-finding tolerance only; a field built from radii 1.2 times
  // the requested ones measures exactly +20 %.
  SkeletonFieldOptions wyvill;
  wyvill.surface = SurfaceKind::kDistance;
  wyvill.kernel = Kernel{KernelKind::kWyvill, 0.0};
  const Skeleton s = test::single_segment(Vec3(1, 2, 3), Vec3(4, -2, 9), 0.7, 0.7);
  const RadiusErrorReport exact = measure_radius_error(*make_skeleton_field(s, wyvill), s);
  EXPECT_EQ(exact.samples, 32u);
  EXPECT_EQ(exact.skipped, 0u);
  EXPECT_LT(exact.max, 1e-8);
  Skeleton fat = s;
  for (auto& n : fat.nodes) n.radius *= 1.2;
  const RadiusErrorReport more = measure_radius_error(*make_skeleton_field(fat, wyvill), s);
  for (std::size_t i = 0; i < more.samples; ++i) EXPECT_NEAR(more.signed_errors[i], 0.2, 1e-8);
  EXPECT_NEAR(more.median, 0.2, 1e-8);
  EXPECT_NEAR(more.max, 0.2, 1e-8);
  EXPECT_NEAR(more.edge_error[0], 0.2, 1e-8);
  // Thinner than requested, bracketed inward.
  Skeleton thin = s;
  for (auto& n : thin.nodes) n.radius *= 0.55;
  const RadiusErrorReport less = measure_radius_error(*make_skeleton_field(thin, wyvill), s);
  EXPECT_NEAR(less.median, 0.45, 1e-8);
  for (std::size_t i = 0; i < less.samples; ++i) EXPECT_NEAR(less.signed_errors[i], -0.45, 1e-8);
  // A field that is outside everywhere near the skeleton measures radius 0 (error 1), and one
  // that is inside out to the search radius measures the search radius.
  const Skeleton far = test::single_segment(Vec3(100, 0, 0), Vec3(100, 0, 5), 0.7, 0.7);
  EXPECT_DOUBLE_EQ(measure_radius_error(*make_skeleton_field(far, wyvill), s).median, 1.0);
  Skeleton huge = s;
  for (auto& n : huge.nodes) n.radius *= 10;
  EXPECT_DOUBLE_EQ(measure_radius_error(*make_skeleton_field(huge, wyvill), s).max, 3.0);
}

TEST(MeasureRadiusError, SkipsRaysIntoOtherBranches) {
  // Two parallel rods 3 radii apart (gap 1 radius between the requested tubes): the rays
  // between them enter the other tube within min_gap = 1.5 radii and are skipped; with
  // min_gap 0.5 they are measured.
  Skeleton s;
  s.nodes = {
      {Vec3(0, 0, 0), 1.0}, {Vec3(0, 0, 20), 1.0}, {Vec3(3, 0, 0), 1.0}, {Vec3(3, 0, 20), 1.0}};
  s.edges = {{0, 1}, {2, 3}};
  SkeletonFieldOptions wyvill;
  wyvill.surface = SurfaceKind::kDistance;
  wyvill.kernel = Kernel{KernelKind::kWyvill, 0.0};
  const FieldPtr f = make_skeleton_field(s, wyvill);
  RadiusErrorOptions o;
  o.min_gap = 1.5;
  const RadiusErrorReport strict = measure_radius_error(*f, s, o);
  o.min_gap = 0.5;
  const RadiusErrorReport loose = measure_radius_error(*f, s, o);
  EXPECT_GT(strict.skipped, 0u);
  EXPECT_EQ(strict.samples + strict.skipped, 64u);
  EXPECT_LT(loose.skipped, strict.skipped);
  // Wyvill's support is 2 radii: the rods do not touch each other's surface.
  EXPECT_LT(strict.max, 1e-8);
  EXPECT_LT(loose.max, 1e-8);
}

}  // namespace
}  // namespace ramiform
