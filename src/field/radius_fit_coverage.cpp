// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "field/radius_fit_detail.h"
#include "ramiform/field/skeleton_field.h"

namespace ramiform::detail {
namespace {

constexpr int kRounds = 12;      // most rounds of raising
constexpr double kRaise = 1.25;  // factor per round (and weights rise to at least kLowest)
constexpr double kLowest = 0.25;

struct SkeletonSamples {
  std::vector<Vec3> points;
  std::vector<std::uint32_t> edge;  // per point, its edge
};

// Every edge sampled every half radius (of its thinner end), ends included.
SkeletonSamples sample_skeleton(const Skeleton& s) {
  SkeletonSamples out;
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    const auto& a = s.nodes[s.edges[e][0]];
    const auto& b = s.nodes[s.edges[e][1]];
    const double len = (b.position - a.position).norm();
    const int k =
        std::max(1, static_cast<int>(std::ceil(len / (0.5 * std::min(a.radius, b.radius)))));
    for (int i = 0; i <= k; ++i) {
      const double t = static_cast<double>(i) / k;
      out.points.push_back((1 - t) * a.position + t * b.position);
      out.edge.push_back(e);
    }
  }
  return out;
}

}  // namespace

void cover_skeleton(const RadiusFitSystem& system, const RadiusFitOptions& options,
                    Eigen::VectorXd& w, RadiusFitResult& result, Context* ctx) {
  if (options.coverage_margin <= 0) return;
  const Skeleton& s = system.skeleton;
  const SkeletonSamples samples = sample_skeleton(s);
  const double level = (1 + options.coverage_margin) * system.iso;
  std::vector<double> f(samples.points.size());
  std::vector<char> raised(s.edges.size(), 0);
  const auto n = static_cast<std::size_t>(w.size());
  for (int round = 0;; ++round) {
    check_cancel(ctx);
    const FieldPtr field =
        make_skeleton_field(s, system.field_options, std::span<const double>(w.data(), n));
    field->evaluate(samples.points, f, {}, ctx);
    std::vector<char> low(s.edges.size(), 0);
    bool any = false;
    for (std::size_t j = 0; j < samples.points.size(); ++j) {
      if (f[j] < level) low[samples.edge[j]] = 1, any = true;
    }
    if (!any) break;
    if (round == kRounds) {
      result.covered = false;
      break;
    }
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
      if (low[e] == 0) continue;
      w[static_cast<Eigen::Index>(e)] = std::max(w[static_cast<Eigen::Index>(e)] * kRaise, kLowest);
      raised[e] = 1;
    }
    result.coverage_rounds = round + 1;
  }
  result.coverage_raised = static_cast<std::size_t>(std::count(raised.begin(), raised.end(), 1));
}

}  // namespace ramiform::detail
