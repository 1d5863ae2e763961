// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/rbf.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = std::numeric_limits<double>::epsilon();
// Positions whose root-mean-square distance from their best-fitting plane is below this
// fraction of the bounding-box diagonal are coplanar: the linear part is then undetermined.
constexpr double kCoplanar = 1e-9;
// Reciprocal condition number below which the system counts as numerically singular.
constexpr double kSingularRcond = 1e-15;
// Points per parallel evaluation chunk.
constexpr std::size_t kGrain = 256;

// Signed distance to the box (> 0 inside) and its gradient.
double signed_box_distance(const Aabb& box, const Vec3& p, Vec3* gradient) {
  const Vec3 below = box.min() - p;
  const Vec3 above = p - box.max();
  const Vec3 out = below.cwiseMax(above).cwiseMax(Vec3::Zero());
  const double d = out.norm();
  if (d > 0) {
    if (gradient != nullptr) {
      for (int k = 0; k < 3; ++k)
        (*gradient)[k] = below[k] > 0 ? below[k] / d : above[k] > 0 ? -above[k] / d : 0.0;
    }
    return -d;
  }
  double best = kInf;
  int axis = 0;
  double sign = 1;
  for (int k = 0; k < 3; ++k) {
    if (-below[k] < best) {
      best = -below[k];
      axis = k;
      sign = 1;
    }
    if (-above[k] < best) {
      best = -above[k];
      axis = k;
      sign = -1;
    }
  }
  if (gradient != nullptr) *gradient = sign * Vec3::Unit(axis);
  return best;
}

class RbfField final : public Field {
 public:
  RbfField(double iso, std::vector<Vec3> centres, Eigen::VectorXd weights, double c0,
           const Vec3& linear, const Vec3& origin, double scale, const Aabb& clip, double kappa)
      : Field(iso),
        centres_(std::move(centres)),
        weights_(std::move(weights)),
        c0_(c0),
        linear_(linear),
        origin_(origin),
        scale_(scale),
        clip_(clip),
        kappa_(kappa) {}

  Interval bound(const Aabb& box) const override {
    if (box.isEmpty()) return {iso(), iso()};
    // The largest value of the clip term anywhere: iso + kappa * (half the smallest box side).
    const double cap_max = iso() + kappa_ * 0.5 * clip_.diagonal().minCoeff();
    if (!box.min().allFinite() || !box.max().allFinite())
      return {-kInf, cap_max * (1 + 1e-12) + 1e-300};
    const Vec3 c = box.center();
    const double half = 0.5 * box.diagonal().norm();
    // f_rbf over the box: the centre value ± half diagonal × a bound of |grad f_rbf|, where
    // |grad |x - c_j|^3| = 3 |x - c_j|^2 <= 3 (|centre - c_j| + h)^2 (normalized units).
    const Vec3 x = (c - origin_) / scale_;
    const double h = half / scale_;
    double value = c0_ + linear_.dot(x);
    double grad_bound = linear_.norm();
    double magnitude = std::abs(c0_) + linear_.norm() * (x.norm() + h);
    for (std::size_t j = 0; j < centres_.size(); ++j) {
      const double r = (x - centres_[j]).norm();
      const double aw = std::abs(weights_[static_cast<Eigen::Index>(j)]);
      value += weights_[static_cast<Eigen::Index>(j)] * r * r * r;
      const double rh = r + h;
      grad_bound += 3 * aw * rh * rh;
      magnitude += aw * rh * rh * rh;
    }
    // Rounding of the sums (here and in the evaluation) grows with the number of terms.
    const double rounding = 4 * kEps * static_cast<double>(centres_.size() + 8) * magnitude;
    const double lo_rbf = value - h * grad_bound - rounding;
    const double hi_rbf = value + h * grad_bound + rounding;
    // The clip term iso + kappa s: s is 1-Lipschitz.
    const double sc = signed_box_distance(clip_, c, nullptr);
    const double cap_slack = 1e-12 * (std::abs(iso()) + kappa_ * (std::abs(sc) + half));
    const double lo_cap = iso() + kappa_ * (sc - half) - cap_slack;
    const double hi_cap = iso() + kappa_ * (sc + half) + cap_slack;
    return {std::min(lo_rbf, lo_cap), std::min(hi_rbf, hi_cap)};
  }

  Aabb bounds() const override { return clip_; }

  std::string describe() const override {
    return "variational implicit surface (cubic RBF), " + std::to_string(centres_.size()) +
           " constraints, iso " + format_number(iso()) + ", clipped to a box of diagonal " +
           format_number(clip_.diagonal().norm());
  }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    const bool with_gradient = !gradients.empty();
    auto run = [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const Vec3 x = (points[i] - origin_) / scale_;
        double v = c0_ + linear_.dot(x);
        Vec3 g = linear_;
        for (std::size_t j = 0; j < centres_.size(); ++j) {
          const Vec3 d = x - centres_[j];
          const double r = d.norm();
          const double w = weights_[static_cast<Eigen::Index>(j)];
          v += w * r * r * r;
          if (with_gradient) g += (3 * w * r) * d;
        }
        Vec3 cap_gradient;
        const double cap = iso() + kappa_ * signed_box_distance(clip_, points[i], &cap_gradient);
        if (cap < v) {
          values[i] = cap;
          if (with_gradient) gradients[i] = kappa_ * cap_gradient;
        } else {
          values[i] = v;
          if (with_gradient) gradients[i] = g / scale_;
        }
      }
    };
    if (points.size() > kGrain && centres_.size() >= 32) {
      parallel::for_chunks(points.size(), kGrain, run, ctx);
    } else {
      run(0, points.size());
    }
  }

 private:
  std::vector<Vec3> centres_;  // normalized: (position - origin) / scale
  Eigen::VectorXd weights_;
  double c0_;
  Vec3 linear_;
  Vec3 origin_;
  double scale_;
  Aabb clip_;
  double kappa_;
};

}  // namespace

FieldPtr make_rbf_field(std::span<const RbfConstraint> constraints, const RbfOptions& options) {
  if (!std::isfinite(options.iso))
    throw InvalidArgument("rbf: iso must be finite, got " + format_number(options.iso));
  if (!std::isfinite(options.margin) || options.margin <= 0) {
    throw InvalidArgument("rbf: margin must be finite and > 0, got " +
                          format_number(options.margin));
  }
  const std::size_t n = constraints.size();
  if (n < 4) {
    throw InvalidArgument("rbf: needs at least 4 constraints at non-coplanar positions, got " +
                          std::to_string(n));
  }
  Aabb box;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& c = constraints[i];
    if (!c.position.allFinite() || !std::isfinite(c.value)) {
      throw InvalidArgument("rbf: constraint " + std::to_string(i) + " is not finite (position " +
                            format_number(c.position.x()) + " " + format_number(c.position.y()) +
                            " " + format_number(c.position.z()) + ", value " +
                            format_number(c.value) + ")");
    }
    box.extend(c.position);
  }
  const double diagonal = box.diagonal().norm();
  if (!(diagonal > 0)) throw InvalidArgument("rbf: all constraint positions coincide");
  // Solve in normalized coordinates (centred, unit diagonal) for a scale-free conditioning.
  const Vec3 origin = box.center();
  const double scale = diagonal;
  std::vector<Vec3> centres(n);
  for (std::size_t i = 0; i < n; ++i) centres[i] = (constraints[i].position - origin) / scale;

  Vec3 mean = Vec3::Zero();
  for (const auto& c : centres) mean += c;
  mean /= static_cast<double>(n);
  Mat3 covariance = Mat3::Zero();
  for (const auto& c : centres) covariance += (c - mean) * (c - mean).transpose();
  covariance /= static_cast<double>(n);
  const double smallest = Eigen::SelfAdjointEigenSolver<Mat3>(covariance).eigenvalues()[0];
  if (!(std::sqrt(std::max(smallest, 0.0)) > kCoplanar)) {
    throw InvalidArgument("rbf: the " + std::to_string(n) +
                          " constraint positions are coplanar (a cubic RBF with a linear term "
                          "needs 4 non-coplanar points)");
  }

  const auto m = static_cast<Eigen::Index>(n + 4);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  for (std::size_t i = 0; i < n; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    for (std::size_t j = 0; j < i; ++j) {
      const double r = (centres[i] - centres[j]).norm();
      if (!(r > tol::kCoincident)) {
        throw InvalidArgument("rbf: constraints " + std::to_string(j) + " and " +
                              std::to_string(i) + " are at the same position (" +
                              format_number(constraints[i].position.x()) + " " +
                              format_number(constraints[i].position.y()) + " " +
                              format_number(constraints[i].position.z()) + ")");
      }
      M(ii, static_cast<Eigen::Index>(j)) = M(static_cast<Eigen::Index>(j), ii) = r * r * r;
    }
    M(ii, static_cast<Eigen::Index>(n)) = M(static_cast<Eigen::Index>(n), ii) = 1;
    for (int k = 0; k < 3; ++k) {
      const auto col = static_cast<Eigen::Index>(n + 1 + k);
      M(ii, col) = M(col, ii) = centres[i][k];
    }
    rhs[ii] = constraints[i].value;
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(M);
  Eigen::VectorXd solution = lu.solve(rhs);
  solution += lu.solve(rhs - M * solution);  // one step of iterative refinement
  const double rcond = lu.rcond();
  if (!solution.allFinite() || !(rcond > kSingularRcond)) {
    throw InvalidArgument(
        "rbf: the interpolation system is numerically singular (reciprocal "
        "condition " +
        format_number(rcond) +
        "); check for (near-)duplicate or coplanar "
        "constraint positions");
  }

  const Aabb clip(box.min() - Vec3::Constant(options.margin * diagonal),
                  box.max() + Vec3::Constant(options.margin * diagonal));
  // The clip slope: iso + kappa s(c_i) >= h_i at every constraint, with a factor 2 to spare.
  double spread = 0;
  double kappa = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double excess = constraints[i].value - options.iso;
    spread = std::max(spread, std::abs(excess));
    if (excess > 0) {
      kappa = std::max(kappa, excess / signed_box_distance(clip, constraints[i].position, nullptr));
    }
  }
  kappa = 2 * std::max({kappa, spread / diagonal, std::numeric_limits<double>::min()});

  const Eigen::VectorXd weights = solution.head(static_cast<Eigen::Index>(n));
  const auto ni = static_cast<Eigen::Index>(n);
  const Vec3 linear(solution[ni + 1], solution[ni + 2], solution[ni + 3]);
  return std::make_shared<RbfField>(options.iso, std::move(centres), weights, solution[ni], linear,
                                    origin, scale, clip, kappa);
}

std::vector<RbfConstraint> rbf_constraints_from_normals(std::span<const Vec3> points,
                                                        std::span<const Vec3> normals,
                                                        double offset, double iso) {
  if (points.size() != normals.size()) {
    throw InvalidArgument("rbf normal constraints: " + std::to_string(normals.size()) +
                          " normals for " + std::to_string(points.size()) + " points");
  }
  if (!std::isfinite(offset) || offset <= 0) {
    throw InvalidArgument("rbf normal constraints: offset must be finite and > 0, got " +
                          format_number(offset));
  }
  if (!std::isfinite(iso))
    throw InvalidArgument("rbf normal constraints: iso must be finite, got " + format_number(iso));
  std::vector<RbfConstraint> out;
  out.reserve(2 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double len = normals[i].norm();
    if (!points[i].allFinite() || !normals[i].allFinite() || !(len > 0)) {
      throw InvalidArgument("rbf normal constraints: point " + std::to_string(i) +
                            " has a non-finite position or a zero / non-finite normal");
    }
    out.push_back({points[i], iso});
    out.push_back({points[i] - (offset / len) * normals[i], iso + 1});
  }
  return out;
}

}  // namespace ramiform
