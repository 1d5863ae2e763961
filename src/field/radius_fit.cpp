// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Solving a radius fit: the rounds of regularized NNLS (solve_radius_fit; the file comment of
// radius_fit.h) on the system of radius_fit_system.cpp, then the coverage repair.
#include "ramiform/field/radius_fit.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "field/radius_fit_detail.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/nnls.h"
#include "ramiform/core/parallel.h"

namespace ramiform {
namespace {

using SparseCol = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using SparseRow = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using detail::check_at_least;

// Columns of the normal matrix per parallel chunk.
constexpr std::size_t kColumnGrain = 64;

// Column-major CSC pieces (lower triangle) of a chunk of columns of N.
struct ColumnChunk {
  std::vector<int> count, rows;
  std::vector<double> vals;
};

// The inputs of the normal equations of one round.
struct WeightedRows {
  const SparseRow& F;
  const SparseCol& Fc;  // F, column-major
  const Eigen::VectorXd& omega;
  const Eigen::VectorXd& target;
  double mu;
};

// Column i of N = F^T diag(omega) F + mu diag(|F_i|^2_omega) (its lower part) into cc, and b_i,
// D_i into p. acc and touched are zero-filled scratch of n entries, left zero-filled; list is
// empty scratch. Every entry is summed over the rows in ascending order.
void normal_column(const WeightedRows& in, int i, NnlsProblem& p, ColumnChunk& cc,
                   std::vector<double>& acc, std::vector<char>& touched, std::vector<int>& list) {
  const SparseRow& F = in.F;
  double b = 0;
  for (SparseCol::InnerIterator it(in.Fc, i); it; ++it) {
    const auto j = static_cast<int>(it.row());
    const double a = in.omega[j] * it.value();
    b += a * in.target[j];
    const int* cols = F.innerIndexPtr() + F.outerIndexPtr()[j];
    const double* vals = F.valuePtr() + F.outerIndexPtr()[j];
    const int len = F.outerIndexPtr()[j + 1] - F.outerIndexPtr()[j];
    for (int q = static_cast<int>(std::lower_bound(cols, cols + len, i) - cols); q < len; ++q) {
      const auto k = static_cast<std::size_t>(cols[q]);
      if (touched[k] == 0) {
        touched[k] = 1;
        list.push_back(cols[q]);
      }
      acc[k] += a * vals[q];
    }
  }
  // Every column stores its diagonal (0 for an edge no constraint sees), so that the pivoting
  // solver can factorize one fixed pattern.
  if (touched[static_cast<std::size_t>(i)] == 0) list.push_back(i);
  std::sort(list.begin(), list.end());
  const double d = acc[static_cast<std::size_t>(i)];
  p.diagonal[i] = d;
  p.rhs[i] = b + in.mu * d;
  for (const int k : list) {
    double v = acc[static_cast<std::size_t>(k)];
    if (k == i) v += in.mu * d;
    cc.rows.push_back(k);
    cc.vals.push_back(v);
    acc[static_cast<std::size_t>(k)] = 0;
    touched[static_cast<std::size_t>(k)] = 0;
  }
  cc.count.push_back(static_cast<int>(list.size()));
  list.clear();
}

// N = F^T diag(omega) F + mu diag(|F_i|^2_omega), b = F^T omega t + mu |F_i|^2_omega, column by
// column in parallel; the result is the same for any thread count. The KKT scale of unknown i
// is N_ii (0 for an edge no constraint sees: it does not take part).
NnlsProblem normal_equations(const WeightedRows& in, const Context* ctx) {
  const auto n = static_cast<int>(in.F.cols());
  NnlsProblem p;
  p.rhs = Eigen::VectorXd::Zero(n);
  p.diagonal = Eigen::VectorXd::Zero(n);
  const std::size_t chunk_count = (static_cast<std::size_t>(n) + kColumnGrain - 1) / kColumnGrain;
  std::vector<ColumnChunk> chunks(chunk_count);
  parallel::for_each(
      chunk_count, 1,
      [&](std::size_t ci) {
        std::vector<double> acc(static_cast<std::size_t>(n), 0.0);
        std::vector<char> touched(static_cast<std::size_t>(n), 0);
        std::vector<int> list;
        const int begin = static_cast<int>(ci * kColumnGrain);
        const int end = std::min(n, begin + static_cast<int>(kColumnGrain));
        for (int i = begin; i < end; ++i) normal_column(in, i, p, chunks[ci], acc, touched, list);
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
  p.diagonal *= 1 + in.mu;
  return p;
}

// The state of a fit across its rounds.
class FitRounds {
 public:
  FitRounds(const RadiusFitSystem& system, const RadiusFitOptions& options, Context* ctx)
      : system_(system),
        options_(options),
        ctx_(ctx),
        F_(system.matrix),
        Fc_(system.matrix),
        n_(static_cast<int>(F_.cols())),
        m_(F_.rows()),
        T_(system.iso),
        w_(Eigen::VectorXd::Ones(n_)),  // edges without data keep 1
        omega_(Eigen::VectorXd::Ones(m_)),
        offset_(Eigen::VectorXd::Zero(m_)),
        f_(static_cast<std::size_t>(m_)) {}

  // The field itself at the constraint points, with the current weights, into f_.
  void evaluate_field() {
    const FieldPtr field =
        make_skeleton_field(system_.skeleton, system_.field_options,
                            std::span<const double>(w_.data(), static_cast<std::size_t>(n_)));
    field->evaluate(system_.points, f_, {}, ctx_);
  }

  // rms of (f - T) / T over the constraint points.
  [[nodiscard]] double rms() const {
    double sum = 0;
    for (const double v : f_) sum += (v - T_) * (v - T_);
    return m_ > 0 ? std::sqrt(sum / static_cast<double>(m_)) / T_ : 0.0;
  }

  // What F (the near part) does not hold becomes a fixed offset per row; after the first
  // round, with robust_threshold > 0, rows whose residual exceeds the threshold get Huber
  // weight threshold / |residual|.
  void update_rows(int round) {
    const Eigen::VectorXd near = F_ * w_;
    for (Eigen::Index j = 0; j < m_; ++j) {
      const double fj = f_[static_cast<std::size_t>(j)];
      offset_[j] = fj - near[j];
      if (round > 0 && options_.robust_threshold > 0) {
        const double r = std::abs(fj - T_) / T_;
        omega_[j] = r <= options_.robust_threshold ? 1.0 : options_.robust_threshold / r;
      }
    }
  }

  // This round's NNLS, bounded below by l = min_weight: for v = w - l >= 0, with the target
  // lowered by F l and the regularization pulling v toward 1 - l.
  [[nodiscard]] NnlsProblem round_problem() const {
    const double low = options_.min_weight;
    const double mu = options_.regularization;
    const Eigen::VectorXd floor_near = F_ * Eigen::VectorXd::Constant(n_, low);
    const Eigen::VectorXd target = Eigen::VectorXd::Constant(m_, T_) - offset_ - floor_near;
    NnlsProblem p = normal_equations({F_, Fc_, omega_, target, mu}, ctx_);
    for (int i = 0; i < n_; ++i) p.rhs[i] -= mu * low * p.diagonal[i] / (1 + mu);
    return p;
  }

  // Solves this round's problem, warm-started (the sparse solver begins with the previous
  // round's positive weights free), into w_.
  void solve(RadiusFitResult& result) {
    const double low = options_.min_weight;
    const NnlsProblem p = round_problem();
    const Eigen::VectorXd start = (w_.array() - low).max(0.0).matrix();
    const NnlsOptions nnls{options_.kkt_tolerance, options_.max_iterations};
    const NnlsResult outcome = use_dense() ? solve_nnls_active_set(p, start, nnls, ctx_)
                                           : solve_nnls_block_pivoting(p, start, nnls, ctx_);
    result.iterations += outcome.iterations;
    result.kkt_violation = nnls_kkt_violation(p, outcome.x);
    w_ = (outcome.x.array() + low).matrix();
  }

  // The weights and the last round's rows into result.
  void finish(RadiusFitResult& result) {
    result.weights.assign(w_.data(), w_.data() + n_);
    result.row_offset.assign(offset_.data(), offset_.data() + m_);
    result.row_weight.assign(omega_.data(), omega_.data() + m_);
    evaluate_field();
    result.residual_rms = rms();
  }

  Eigen::VectorXd& weights() { return w_; }

 private:
  [[nodiscard]] bool use_dense() const {
    return options_.solver == NnlsSolver::kDense ||
           (options_.solver == NnlsSolver::kAuto &&
            static_cast<std::size_t>(n_) <= options_.dense_limit);
  }

  const RadiusFitSystem& system_;
  const RadiusFitOptions& options_;
  Context* ctx_;
  const SparseRow& F_;
  const SparseCol Fc_;
  const int n_;
  const Eigen::Index m_;
  const double T_;
  Eigen::VectorXd w_, omega_, offset_;
  std::vector<double> f_;
};

}  // namespace

void RadiusFitOptions::validate() const {
  check_at_least(stations_per_edge, 1, "stations_per_edge");
  check_at_least(points_per_circle, 3, "points_per_circle");
  if (!std::isfinite(regularization) || regularization < 0) {
    throw InvalidArgument("regularization must be finite and >= 0, got " +
                          std::to_string(regularization));
  }
  if (!std::isfinite(kkt_tolerance) || kkt_tolerance <= 0) {
    throw InvalidArgument("kkt_tolerance must be finite and > 0, got " +
                          std::to_string(kkt_tolerance));
  }
  check_at_least(max_iterations, 0, "max_iterations");
  if (!std::isfinite(robust_threshold) || robust_threshold < 0) {
    throw InvalidArgument("robust_threshold must be finite and >= 0, got " +
                          std::to_string(robust_threshold));
  }
  check_at_least(outer_rounds, 0, "outer_rounds");
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

RadiusFitResult solve_radius_fit(const RadiusFitSystem& system, const RadiusFitOptions& options,
                                 Context* ctx) {
  options.validate();
  const SparseRow& F = system.matrix;
  if (static_cast<std::size_t>(F.cols()) != system.skeleton.edges.size() ||
      static_cast<std::size_t>(F.rows()) != system.points.size()) {
    throw InvalidArgument("radius fit: system matrix does not match its skeleton and points");
  }
  RadiusFitResult result;
  result.constraint_points = static_cast<std::size_t>(F.rows());
  result.nonzeros = static_cast<std::size_t>(F.nonZeros());
  FitRounds fit(system, options, ctx);
  // Every round evaluates the field with the current weights, updates the rows (far-field
  // offsets; with robust_threshold > 0 Huber weights, iteratively reweighted least squares:
  // rows whose residual exceeds the threshold, webbing between branches at a joint, tips:
  // errors no weight removes, stop dictating the weights of everything else) and solves again.
  for (int round = 0; round <= options.outer_rounds; ++round) {
    check_cancel(ctx);
    if (ctx != nullptr)
      ctx->report("radius fit: solve", static_cast<double>(round) / (options.outer_rounds + 1));
    fit.evaluate_field();
    if (round == 0) result.unit_residual_rms = fit.rms();
    fit.update_rows(round);
    fit.solve(result);
  }
  result.converged = result.kkt_violation <= options.kkt_tolerance;
  detail::cover_skeleton(system, options, fit.weights(), result, ctx);
  fit.finish(result);
  if (ctx != nullptr) ctx->report("radius fit: solve", 1);
  return result;
}

RadiusFitResult fit_edge_weights(const Skeleton& skeleton,
                                 const SkeletonFieldOptions& field_options,
                                 const RadiusFitOptions& options, Context* ctx) {
  const RadiusFitSystem system = build_radius_fit_system(skeleton, field_options, options, ctx);
  return solve_radius_fit(system, options, ctx);
}

}  // namespace ramiform
