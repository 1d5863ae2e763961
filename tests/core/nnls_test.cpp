// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The NNLS solvers (core/nnls.h) against solutions found independently: every active set of
// small random problems enumerated by brute force.

#include "ramiform/core/nnls.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using SparseCol = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// min |A x - y|^2 as normal equations (N = A^T A, b = A^T y, d = diag N), every lower entry
// stored.
NnlsProblem normal_form(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  const Eigen::MatrixXd N = A.transpose() * A;
  NnlsProblem p;
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index c = 0; c < N.cols(); ++c) {
    for (Eigen::Index r = c; r < N.rows(); ++r) entries.emplace_back(r, c, N(r, c));
  }
  p.lower.resize(N.rows(), N.cols());
  p.lower.setFromTriplets(entries.begin(), entries.end());
  p.rhs = A.transpose() * y;
  p.diagonal = N.diagonal();
  return p;
}

// The exact NNLS solution of a full-column-rank A: over every subset S, the least-squares
// solution on the columns S (the others 0); the optimum is the feasible one (x_S >= 0) of least
// residual. Independent of both solvers.
Eigen::VectorXd brute_force(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  const auto n = static_cast<int>(A.cols());
  Eigen::VectorXd best = Eigen::VectorXd::Zero(n);
  double best_residual = y.squaredNorm();
  for (std::uint32_t mask = 1; mask < (1u << n); ++mask) {
    std::vector<int> cols;
    for (int i = 0; i < n; ++i) {
      if ((mask >> i) & 1u) cols.push_back(i);
    }
    Eigen::MatrixXd As(A.rows(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t k = 0; k < cols.size(); ++k)
      As.col(static_cast<Eigen::Index>(k)) = A.col(cols[k]);
    const Eigen::VectorXd xs = As.colPivHouseholderQr().solve(y);
    if (xs.minCoeff() < 0) continue;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < cols.size(); ++k) x[cols[k]] = xs[static_cast<Eigen::Index>(k)];
    const double residual = (A * x - y).squaredNorm();
    if (residual < best_residual) {
      best_residual = residual;
      best = x;
    }
  }
  return best;
}

// The KKT conditions of min |A x - y|^2, x >= 0, with w = A^T (y - A x): x >= 0, w <= tol where
// x = 0, |w| <= tol where x > 0.
void expect_kkt(const Eigen::MatrixXd& A, const Eigen::VectorXd& y, const Eigen::VectorXd& x,
                double tol) {
  const Eigen::VectorXd w = A.transpose() * (y - A * x);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    EXPECT_GE(x[i], 0.0) << "unknown " << i;
    if (x[i] > 0)
      EXPECT_LE(std::abs(w[i]), tol) << "unknown " << i;
    else
      EXPECT_LE(w[i], tol) << "unknown " << i;
  }
}

struct Random {
  std::mt19937_64 engine;
  explicit Random(std::uint64_t seed) : engine(seed) {}
  double normal() { return std::normal_distribution<double>(0.0, 1.0)(engine); }
  Eigen::MatrixXd matrix(Eigen::Index rows, Eigen::Index cols) {
    Eigen::MatrixXd m(rows, cols);
    for (Eigen::Index c = 0; c < cols; ++c) {
      for (Eigen::Index r = 0; r < rows; ++r) m(r, c) = normal();
    }
    return m;
  }
};

TEST(Nnls, BothSolversMatchTheBruteForceOptimumOnRandomProblems) {
  Random rng(20260);
  int with_zeros = 0, with_positives = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 6;
    const Eigen::MatrixXd A = rng.matrix(n + 4, n);
    const Eigen::VectorXd y = rng.matrix(n + 4, 1);
    const Eigen::VectorXd exact = brute_force(A, y);
    const NnlsProblem p = normal_form(A, y);
    const NnlsOptions o{1e-12, 0};
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    // Warm starts of the pivoting solver: none, everything free, the answer's support.
    const Eigen::VectorXd all = Eigen::VectorXd::Ones(n);
    for (const NnlsResult& r :
         {solve_nnls_active_set(p, zero, o), solve_nnls_block_pivoting(p, zero, o),
          solve_nnls_block_pivoting(p, all, o), solve_nnls_block_pivoting(p, exact, o)}) {
      ASSERT_EQ(r.x.size(), n);
      EXPECT_LE((r.x - exact).norm(), 1e-9 * (1 + exact.norm())) << "trial " << trial;
      expect_kkt(A, y, r.x, 1e-9 * (1 + p.rhs.norm()));
      EXPECT_LE(nnls_kkt_violation(p, r.x), 1e-9);
      EXPECT_LE(r.iterations, 3 * n + 10);
    }
    for (Eigen::Index i = 0; i < n; ++i) (exact[i] > 0 ? with_positives : with_zeros) += 1;
  }
  // The problems exercise both sides of the complementarity.
  EXPECT_GT(with_zeros, 100);
  EXPECT_GT(with_positives, 100);
}

TEST(Nnls, UnconstrainedOptimumWhenItIsPositive) {
  // A x = y solvable with x > 0: the NNLS solution is that x, to rounding.
  const Eigen::MatrixXd A = (Eigen::MatrixXd(3, 2) << 2, 0, 1, 1, 0, 3).finished();
  const Eigen::VectorXd x_true = (Eigen::VectorXd(2) << 0.5, 2.0).finished();
  const NnlsProblem p = normal_form(A, A * x_true);
  const NnlsOptions o{1e-12, 0};
  EXPECT_LE((solve_nnls_active_set(p, Eigen::VectorXd::Zero(2), o).x - x_true).norm(), 1e-12);
  EXPECT_LE((solve_nnls_block_pivoting(p, Eigen::VectorXd::Zero(2), o).x - x_true).norm(), 1e-12);
}

TEST(Nnls, DegenerateProblems) {
  const NnlsOptions o{1e-12, 0};
  // b <= 0: every unknown would rather be negative, x = 0 (with no iteration of the active set,
  // one pivoting step that finds the empty free set feasible).
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(3, 3);
  const Eigen::VectorXd y = (Eigen::VectorXd(3) << -1, -2, 0).finished();
  const NnlsProblem p = normal_form(A, y);
  const NnlsResult a = solve_nnls_active_set(p, Eigen::VectorXd::Zero(3), o);
  EXPECT_EQ(a.x, Eigen::VectorXd::Zero(3));
  EXPECT_EQ(a.iterations, 0);
  const NnlsResult b = solve_nnls_block_pivoting(p, Eigen::VectorXd::Ones(3), o);
  EXPECT_EQ(b.x, Eigen::VectorXd::Zero(3));
  EXPECT_EQ(nnls_kkt_violation(p, b.x), 0.0);
  // No unknowns at all.
  const NnlsProblem empty = normal_form(Eigen::MatrixXd(2, 0), Eigen::VectorXd::Ones(2));
  EXPECT_EQ(solve_nnls_active_set(empty, Eigen::VectorXd(0), o).x.size(), 0);
  EXPECT_EQ(solve_nnls_block_pivoting(empty, Eigen::VectorXd(0), o).x.size(), 0);
  EXPECT_EQ(nnls_kkt_violation(empty, Eigen::VectorXd(0)), 0.0);
}

TEST(Nnls, UnknownsThatDoNotTakePartKeepTheirStart) {
  // Column 1 of A is zero: N's row and column 1 are zero (the diagonal stored as 0), so x_1
  // keeps its start value and the others solve the problem without it.
  Random rng(7);
  Eigen::MatrixXd A = rng.matrix(6, 3);
  A.col(1).setZero();
  const Eigen::VectorXd y = rng.matrix(6, 1);
  const NnlsProblem p = normal_form(A, y);
  ASSERT_FALSE(p.is_free(1));
  Eigen::MatrixXd A02(6, 2);
  A02 << A.col(0), A.col(2);
  const Eigen::VectorXd exact = brute_force(A02, y);
  const Eigen::VectorXd start = (Eigen::VectorXd(3) << 0.3, 7.5, 0.2).finished();
  const NnlsOptions o{1e-12, 0};
  for (const NnlsResult& r :
       {solve_nnls_active_set(p, start, o), solve_nnls_block_pivoting(p, start, o)}) {
    EXPECT_EQ(r.x[1], 7.5);
    EXPECT_NEAR(r.x[0], exact[0], 1e-10);
    EXPECT_NEAR(r.x[2], exact[1], 1e-10);
    EXPECT_LE(nnls_kkt_violation(p, r.x), 1e-9);
  }
}

TEST(Nnls, IterationLimitReturnsAFeasibleIterate) {
  Random rng(11);
  const Eigen::MatrixXd A = rng.matrix(12, 8);
  const Eigen::VectorXd y = rng.matrix(12, 1);
  const NnlsProblem p = normal_form(A, y);
  const NnlsOptions one{1e-12, 1};
  for (const NnlsResult& r : {solve_nnls_active_set(p, Eigen::VectorXd::Zero(8), one),
                              solve_nnls_block_pivoting(p, Eigen::VectorXd::Zero(8), one)}) {
    EXPECT_EQ(r.iterations, 1);
    EXPECT_GE(r.x.minCoeff(), 0.0);
  }
  // 0 means 3 n + 10: enough for these problems.
  const NnlsResult full = solve_nnls_active_set(p, Eigen::VectorXd::Zero(8), {1e-12, 0});
  EXPECT_LE(full.iterations, 3 * 8 + 10);
  EXPECT_LE((full.x - brute_force(A, y)).norm(), 1e-9);
}

TEST(Nnls, KktViolationMeasuresTheScaledGradient) {
  // N = diag(2, 4), b = (2, -4): the optimum is x = (1, 0), gradient N x - b = (0, 4).
  NnlsProblem p = normal_form((Eigen::MatrixXd(2, 2) << std::sqrt(2.0), 0, 0, 2).finished(),
                              (Eigen::VectorXd(2) << std::sqrt(2.0), -2).finished());
  EXPECT_NEAR(nnls_kkt_violation(p, (Eigen::VectorXd(2) << 1, 0).finished()), 0.0, 1e-15);
  // x_0 = 1.5: gradient 1 on a positive unknown, scaled by N_00 = 2.
  EXPECT_NEAR(nnls_kkt_violation(p, (Eigen::VectorXd(2) << 1.5, 0).finished()), 0.5, 1e-15);
  // x_0 = 0: the gradient -2 wants it to grow (scaled: 1).
  EXPECT_NEAR(nnls_kkt_violation(p, (Eigen::VectorXd(2) << 0, 0).finished()), 1.0, 1e-15);
  EXPECT_EQ(nnls_kkt_violation(p, (Eigen::VectorXd(2) << 1, -1e-30).finished()),
            std::numeric_limits<double>::infinity());
}

TEST(Nnls, ChecksItsArguments) {
  const NnlsProblem p = normal_form(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Ones(2));
  const Eigen::VectorXd start = Eigen::VectorXd::Zero(2);
  EXPECT_THROW((void)solve_nnls_active_set(p, Eigen::VectorXd::Zero(3)), InvalidArgument);
  EXPECT_THROW((void)solve_nnls_block_pivoting(p, Eigen::VectorXd::Zero(1)), InvalidArgument);
  EXPECT_THROW((void)solve_nnls_active_set(p, start, {0.0, 0}), InvalidArgument);
  EXPECT_THROW((void)solve_nnls_active_set(p, start, {std::nan(""), 0}), InvalidArgument);
  EXPECT_THROW((void)solve_nnls_block_pivoting(p, start, {1e-9, -1}), InvalidArgument);
  EXPECT_THROW((void)nnls_kkt_violation(p, Eigen::VectorXd::Zero(3)), InvalidArgument);
  NnlsProblem wrong_diagonal = p;
  wrong_diagonal.diagonal = Eigen::VectorXd::Ones(3);
  EXPECT_THROW((void)solve_nnls_active_set(wrong_diagonal, start), InvalidArgument);
  // The pivoting solver factorizes one pattern: every column must store its diagonal.
  NnlsProblem no_diagonal = p;
  no_diagonal.lower.coeffRef(1, 1) = 0;
  no_diagonal.lower.prune(0.0);
  EXPECT_THROW((void)solve_nnls_block_pivoting(no_diagonal, start), InvalidArgument);
}

TEST(Nnls, CancelledThroughTheContext) {
  const NnlsProblem p = normal_form(Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Ones(2));
  Context ctx;
  ctx.cancel();
  EXPECT_THROW((void)solve_nnls_active_set(p, Eigen::VectorXd::Zero(2), {}, &ctx), Cancelled);
  EXPECT_THROW((void)solve_nnls_block_pivoting(p, Eigen::VectorXd::Zero(2), {}, &ctx), Cancelled);
}

}  // namespace
}  // namespace ramiform
