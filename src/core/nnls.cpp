// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/nnls.h"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using SparseCol = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// Block pivoting steps that may fail to shrink the infeasible set before the single exchange.
constexpr int kBackupSteps = 3;

void check_problem(const NnlsProblem& p, const Eigen::VectorXd& start, const NnlsOptions& o,
                   const char* solver) {
  const Eigen::Index n = p.rhs.size();
  if (p.lower.rows() != n || p.lower.cols() != n || p.diagonal.size() != n || start.size() != n) {
    throw InvalidArgument(std::string(solver) + ": N is " + std::to_string(p.lower.rows()) + " x " +
                          std::to_string(p.lower.cols()) + ", b, diagonal and start have " +
                          std::to_string(n) + ", " + std::to_string(p.diagonal.size()) + " and " +
                          std::to_string(start.size()) + " entries; all must be n");
  }
  if (!std::isfinite(o.tolerance) || o.tolerance <= 0) {
    throw InvalidArgument(std::string(solver) + ": tolerance must be finite and > 0, got " +
                          format_number(o.tolerance));
  }
  if (o.max_iterations < 0) {
    throw InvalidArgument(std::string(solver) + ": max_iterations must be >= 0, got " +
                          std::to_string(o.max_iterations));
  }
}

int iteration_limit(const NnlsOptions& o, Eigen::Index n) {
  return o.max_iterations > 0 ? o.max_iterations : 3 * static_cast<int>(n) + 10;
}

// ---------------------------------------------------------------------------------------------
// Lawson–Hanson on dense normal equations. The unknowns that do not take part keep their start
// value; their rows and columns of N are zero.

class ActiveSet {
 public:
  ActiveSet(const NnlsProblem& p, const Eigen::VectorXd& start)
      : p_(p),
        N_(Eigen::MatrixXd(SparseCol(p.lower.selfadjointView<Eigen::Lower>()))),
        n_(N_.rows()),
        passive_(static_cast<std::size_t>(n_), 0) {
    out_.x = start;
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (p_.is_free(i)) out_.x[i] = 0;
    }
  }

  NnlsResult run(double tol, int max_iterations, const Context* ctx) {
    while (out_.iterations < max_iterations) {
      check_cancel(ctx);
      const Eigen::Index best = entering(tol);
      if (best < 0) break;
      passive_[static_cast<std::size_t>(best)] = 1;
      ++out_.iterations;
      Eigen::VectorXd z;
      if (!step_to_feasible(z, max_iterations)) return out_;
      out_.x = z;
    }
    return out_;
  }

 private:
  [[nodiscard]] bool in_p(Eigen::Index i) const {
    return passive_[static_cast<std::size_t>(i)] != 0;
  }

  // The free unknown outside the passive set whose scaled negative gradient is largest and
  // above tol (it most wants to grow), or -1.
  [[nodiscard]] Eigen::Index entering(double tol) const {
    const Eigen::VectorXd g = p_.rhs - N_ * out_.x;
    Eigen::Index best = -1;
    double best_value = tol;
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (!p_.is_free(i) || in_p(i)) continue;
      const double scaled = g[i] / p_.diagonal[i];
      if (scaled > best_value) {
        best_value = scaled;
        best = i;
      }
    }
    return best;
  }

  // z = the minimizer over the passive set, the other free unknowns held at 0.
  void solve_passive(Eigen::VectorXd& z) const {
    std::vector<Eigen::Index> idx;
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (in_p(i)) idx.push_back(i);
    }
    const auto k = static_cast<Eigen::Index>(idx.size());
    Eigen::MatrixXd A(k, k);
    Eigen::VectorXd r(k);
    for (Eigen::Index x = 0; x < k; ++x) {
      r[x] = p_.rhs[idx[x]];
      for (Eigen::Index y = 0; y < k; ++y) A(x, y) = N_(idx[x], idx[y]);
    }
    const Eigen::VectorXd sol = A.ldlt().solve(r);
    z = out_.x;
    for (Eigen::Index i = 0; i < n_; ++i) {
      if (p_.is_free(i)) z[i] = 0;
    }
    for (Eigen::Index x = 0; x < k; ++x) z[idx[x]] = sol[x];
  }

  // The inner loop: steps toward the passive-set solution z until it is feasible; the unknowns
  // that a step drives to 0 leave the passive set. False when the iteration limit stopped it
  // (x is then the last feasible iterate).
  bool step_to_feasible(Eigen::VectorXd& z, int max_iterations) {
    for (;;) {
      solve_passive(z);
      double alpha = 1;
      Eigen::Index blocking = -1;
      for (Eigen::Index i = 0; i < n_; ++i) {
        if (in_p(i) && z[i] <= 0) {
          const double a = out_.x[i] / (out_.x[i] - z[i]);
          if (blocking < 0 || a < alpha) {
            alpha = a;
            blocking = i;
          }
        }
      }
      if (blocking < 0) return true;
      for (Eigen::Index i = 0; i < n_; ++i) {
        if (!in_p(i)) continue;
        out_.x[i] += alpha * (z[i] - out_.x[i]);
        if (i == blocking || out_.x[i] <= 0) {
          out_.x[i] = 0;
          passive_[static_cast<std::size_t>(i)] = 0;
        }
      }
      if (++out_.iterations >= max_iterations) return false;
    }
  }

  const NnlsProblem& p_;
  const Eigen::MatrixXd N_;
  const Eigen::Index n_;
  std::vector<char> passive_;
  NnlsResult out_;
};

// ---------------------------------------------------------------------------------------------
// Block principal pivoting. The unknowns held at 0 keep their rows and columns in the matrix as
// unit rows (zero off the diagonal), so every step factorizes the same pattern: the
// fill-reducing ordering is computed once.

class BlockPivoting {
 public:
  BlockPivoting(const NnlsProblem& p, const Eigen::VectorXd& start)
      : p_(p),
        start_(start),
        n_(static_cast<int>(p.rhs.size())),
        in_f_(static_cast<std::size_t>(n_), 0),
        work_(p.lower) {
    for (int i = 0; i < n_; ++i)
      in_f_[static_cast<std::size_t>(i)] = p_.is_free(i) && start[i] > 0 ? 1 : 0;
    ldlt_.analyzePattern(work_);
  }

  NnlsResult run(double tol, int max_iterations, const Context* ctx) {
    NnlsResult out;
    out.x = start_;
    int backup = kBackupSteps;
    std::size_t best_infeasible = static_cast<std::size_t>(n_) + 1;
    while (out.iterations < max_iterations) {
      check_cancel(ctx);
      ++out.iterations;
      const Eigen::VectorXd r = free_block();
      ldlt_.factorize(work_);
      if (ldlt_.info() != Eigen::Success) break;  // not positive definite: the KKT check says so
      const Eigen::VectorXd x = solve_free_block(r);
      std::vector<int> infeasible = infeasible_set(x, tol);
      // The projection of x is the feasible iterate returned if the limit stops the pivoting.
      out.x = x.cwiseMax(0.0);
      if (infeasible.empty()) return out;
      if (infeasible.size() < best_infeasible) {
        best_infeasible = infeasible.size();
        backup = kBackupSteps;
      } else if (backup > 0) {
        --backup;
      } else {
        infeasible = {infeasible.back()};
      }
      for (const int i : infeasible) in_f_[static_cast<std::size_t>(i)] ^= 1;
    }
    return out;
  }

 private:
  [[nodiscard]] bool is_in_f(Eigen::Index i) const {
    return in_f_[static_cast<std::size_t>(i)] != 0;
  }

  // Writes the free block of N into work_, with unit rows for the others; returns its b.
  Eigen::VectorXd free_block() {
    const double* src = p_.lower.valuePtr();
    double* dst = work_.valuePtr();
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n_);
    for (int c = 0; c < n_; ++c) {
      const bool keep_col = is_in_f(c);
      if (keep_col) r[c] = p_.rhs[c];
      for (int q = work_.outerIndexPtr()[c]; q < work_.outerIndexPtr()[c + 1]; ++q) {
        const int row = work_.innerIndexPtr()[q];
        dst[q] = row == c ? (keep_col ? src[q] : 1.0) : (keep_col && is_in_f(row) ? src[q] : 0.0);
      }
    }
    return r;
  }

  // The solution of the factorized free block (one step of iterative refinement), with the
  // unknowns outside it at 0 and those that do not take part at their start value.
  [[nodiscard]] Eigen::VectorXd solve_free_block(const Eigen::VectorXd& r) const {
    Eigen::VectorXd x = ldlt_.solve(r);
    x += ldlt_.solve(r - work_.selfadjointView<Eigen::Lower>() * x);
    for (int i = 0; i < n_; ++i) {
      if (!p_.is_free(i))
        x[i] = start_[i];
      else if (!is_in_f(i))
        x[i] = 0;
    }
    return x;
  }

  // The free unknowns that are negative and the held ones whose gradient wants them to grow.
  [[nodiscard]] std::vector<int> infeasible_set(const Eigen::VectorXd& x, double tol) const {
    const Eigen::VectorXd y = p_.times(x) - p_.rhs;
    std::vector<int> infeasible;
    for (int i = 0; i < n_; ++i) {
      if (!p_.is_free(i)) continue;
      if (is_in_f(i) ? x[i] < 0 : y[i] < -tol * p_.diagonal[i]) infeasible.push_back(i);
    }
    return infeasible;
  }

  const NnlsProblem& p_;
  const Eigen::VectorXd& start_;
  const int n_;
  std::vector<char> in_f_;
  SparseCol work_;
  Eigen::SimplicialLDLT<SparseCol, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_;
};

void check_diagonal_stored(const NnlsProblem& p) {
  for (Eigen::Index c = 0; c < p.lower.outerSize(); ++c) {
    bool found = false;
    for (SparseCol::InnerIterator it(p.lower, c); it && !found; ++it) found = it.row() == c;
    if (!found) {
      throw InvalidArgument("solve_nnls_block_pivoting: column " + std::to_string(c) +
                            " of N stores no diagonal entry");
    }
  }
}

}  // namespace

Eigen::VectorXd NnlsProblem::times(const Eigen::VectorXd& x) const {
  return lower.selfadjointView<Eigen::Lower>() * x;
}

NnlsResult solve_nnls_active_set(const NnlsProblem& problem, const Eigen::VectorXd& start,
                                 const NnlsOptions& options, const Context* ctx) {
  check_problem(problem, start, options, "solve_nnls_active_set");
  ActiveSet solver(problem, start);
  return solver.run(options.tolerance, iteration_limit(options, problem.rhs.size()), ctx);
}

NnlsResult solve_nnls_block_pivoting(const NnlsProblem& problem, const Eigen::VectorXd& start,
                                     const NnlsOptions& options, const Context* ctx) {
  check_problem(problem, start, options, "solve_nnls_block_pivoting");
  check_diagonal_stored(problem);
  BlockPivoting solver(problem, start);
  return solver.run(options.tolerance, iteration_limit(options, problem.rhs.size()), ctx);
}

double nnls_kkt_violation(const NnlsProblem& problem, const Eigen::VectorXd& x) {
  if (x.size() != problem.rhs.size()) {
    throw InvalidArgument("nnls_kkt_violation: x has " + std::to_string(x.size()) +
                          " entries, the problem " + std::to_string(problem.rhs.size()));
  }
  const Eigen::VectorXd g = problem.times(x) - problem.rhs;
  double worst = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (!problem.is_free(i)) continue;
    const double scaled = g[i] / problem.diagonal[i];
    if (x[i] < 0) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, x[i] > 0 ? std::abs(scaled) : -scaled);
  }
  return worst;
}

}  // namespace ramiform
