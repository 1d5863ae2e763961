// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Non-negative least squares on normal equations: the x >= 0 that minimizes
///   q(x) = 1/2 x^T N x - b^T x,
/// N symmetric positive semi-definite (n x n). With N = A^T A and b = A^T y this is
/// min_{x >= 0} |A x - y|^2; a ridge term mu |x - x0|^2_D adds mu D to N and mu D x0 to b. The
/// minimizer is characterized by the KKT conditions with the gradient g = N x - b:
///   x_i >= 0,  g_i >= 0 where x_i = 0,  g_i = 0 where x_i > 0,
/// which the solvers test scaled per unknown, g_i / d_i against a tolerance (with d_i = N_ii the
/// scaled gradient is the change of x_i that a single coordinate step would make).
///
/// Two solvers with the same stopping rule:
/// - solve_nnls_active_set(): Lawson & Hanson 1974, *Solving Least Squares Problems*
///   (Prentice-Hall), ch. 23, §3 (Algorithm NNLS), on dense normal equations in the
///   cross-product form of Bro & De Jong 1997, "A fast non-negativity-constrained least squares
///   algorithm" (J. Chemometrics 11). O(n^2) memory: small problems.
/// - solve_nnls_block_pivoting(): block principal pivoting, Kim & Park 2011, "Fast nonnegative
///   matrix factorization: an active-set-like method and comparisons" (SIAM J. Sci. Comput. 33),
///   after Júdice & Pires 1994, "A block principal pivoting algorithm for large-scale strictly
///   monotone linear complementarity problems" (Computers & Operations Research 21), with a
///   sparse LDL^T of the free block: large sparse problems (N positive definite).

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "ramiform/core/context.h"

namespace ramiform {

/// A problem min_{x >= 0} 1/2 x^T N x - b^T x (see the file comment).
struct NnlsProblem {
  /// N (n x n, symmetric positive semi-definite): its lower triangle, column-major. Every
  /// column stores its diagonal entry (an explicit 0 where N_ii = 0): the block pivoting solver
  /// factorizes this one pattern at every step.
  Eigen::SparseMatrix<double, Eigen::ColMajor, int> lower;
  Eigen::VectorXd rhs;  ///< b, one entry per unknown
  /// Per unknown, the scale d_i > 0 of its KKT test (usually N_ii). An unknown with d_i <= 0
  /// does not take part (its row and column of N must be zero, e.g. a zero column of A): it
  /// keeps its start value and is not tested.
  Eigen::VectorXd diagonal;

  /// N x (x: one entry per unknown).
  [[nodiscard]] Eigen::VectorXd times(const Eigen::VectorXd& x) const;
  /// True when unknown i takes part (diagonal[i] > 0).
  [[nodiscard]] bool is_free(Eigen::Index i) const { return diagonal[i] > 0; }
};

/// Stopping rule of the NNLS solvers; validated at entry (InvalidArgument naming the option).
struct NnlsOptions {
  /// KKT tolerance (dimensionless, > 0): on the scaled gradient g_i / d_i (file comment).
  double tolerance = 1e-9;
  /// Largest number of iterations (>= 0; 0 = 3 n + 10): active-set changes (inner steps
  /// included) or pivoting steps.
  int max_iterations = 0;
};

/// A solver's outcome. When the iteration limit stopped it, `x` is the last feasible iterate
/// (every entry >= 0 but those of the unknowns that do not take part, which keep their start).
struct NnlsResult {
  Eigen::VectorXd x;   ///< one entry per unknown
  int iterations = 0;  ///< iterations made (see NnlsOptions::max_iterations)
};

/// Lawson–Hanson active set (file comment). Starts from x = 0 on the unknowns that take part
/// (`start` gives the others' values). Throws InvalidArgument when the sizes of `lower`,
/// `rhs`, `diagonal` and `start` disagree or an option is out of range, Cancelled through `ctx`
/// (checked once per iteration).
[[nodiscard]] NnlsResult solve_nnls_active_set(const NnlsProblem& problem,
                                               const Eigen::VectorXd& start,
                                               const NnlsOptions& options = {},
                                               const Context* ctx = nullptr);

/// Block principal pivoting (file comment), warm-started with the free set {i : start_i > 0}.
/// Exchanges every infeasible unknown at once while that shrinks the infeasible set, else, after
/// three steps that do not, only the largest infeasible index (Murty's single exchange, which
/// terminates). The free block of N must be positive definite; where a factorization fails the
/// solver stops with its last iterate (nnls_kkt_violation() then reports the failure). Throws
/// as solve_nnls_active_set(), and InvalidArgument when a column of `lower` lacks its diagonal.
[[nodiscard]] NnlsResult solve_nnls_block_pivoting(const NnlsProblem& problem,
                                                   const Eigen::VectorXd& start,
                                                   const NnlsOptions& options = {},
                                                   const Context* ctx = nullptr);

/// The largest scaled KKT violation of x over the unknowns that take part: |g_i| / d_i where
/// x_i > 0, -g_i / d_i where x_i = 0 (0 when g_i >= 0), +infinity when some x_i < 0. x solves the
/// problem to tolerance tol when this is <= tol. `x` has one entry per unknown.
[[nodiscard]] double nnls_kkt_violation(const NnlsProblem& problem, const Eigen::VectorXd& x);

}  // namespace ramiform
