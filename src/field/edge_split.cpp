// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Splitting edges into pieces one weight each can follow (split_edges of radius_fit.h).
#include <algorithm>
#include <cmath>
#include <string>

#include "field/radius_fit_detail.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/field/radius_fit.h"

namespace ramiform {
namespace {

// Radii whose ratio is within this of 1 count as an untapered edge.
constexpr double kUntapered = 1e-12;
// Slack of the taper's piece count against rounding up an exact whole number.
constexpr double kCountSlack = 1e-9;

void check(const EdgeSplitOptions& options) {
  if (!std::isfinite(options.max_length) || options.max_length <= 0) {
    throw InvalidArgument("max_length must be finite and > 0, got " +
                          std::to_string(options.max_length));
  }
  if (!(options.max_taper > 0 && options.max_taper < 1)) {
    throw InvalidArgument("max_taper must be in (0, 1), got " + std::to_string(options.max_taper));
  }
  detail::check_at_least(options.max_pieces, 1, "max_pieces");
}

double radius_ratio(const SkeletonNode& na, const SkeletonNode& nb) {
  return std::max(na.radius, nb.radius) / std::min(na.radius, nb.radius);
}

bool is_tapered(const SkeletonNode& na, const SkeletonNode& nb) {
  return radius_ratio(na, nb) > 1 + kUntapered;
}

// Split radii in geometric progression r_k = r_a q^k, q = (r_b / r_a)^(1/k): along a linear
// taper every piece then has the same taper 1 - min(q, 1/q) and the same ratio of length to
// mean radius, len 2 |q - 1| / ((q + 1) |r_b - r_a|) (len / r without taper). The smallest k
// that meets both limits (at most max_pieces).
int piece_count(const SkeletonNode& na, const SkeletonNode& nb, double len,
                const EdgeSplitOptions& options) {
  const double ratio = radius_ratio(na, nb);
  const bool tapered = is_tapered(na, nb);
  auto length_ratio = [&](int k) {
    if (!tapered) return len / (k * na.radius);
    const double q = pm::pow(nb.radius / na.radius, 1.0 / k);
    return len * 2 * std::abs(q - 1) / ((q + 1) * std::abs(nb.radius - na.radius));
  };
  int pieces = tapered ? static_cast<int>(std::ceil(
                             pm::log(ratio) / -pm::log1p(-options.max_taper) - kCountSlack))
                       : 1;
  pieces = std::max(pieces, 1);
  while (pieces < options.max_pieces && length_ratio(pieces) > options.max_length) ++pieces;
  return std::min(pieces, options.max_pieces);
}

}  // namespace

SplitSkeleton split_edges(const Skeleton& skeleton, const EdgeSplitOptions& options) {
  check(options);
  validate(skeleton);
  SplitSkeleton out;
  out.skeleton.nodes = skeleton.nodes;
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    const auto [ia, ib] = skeleton.edges[e];
    const SkeletonNode& na = skeleton.nodes[ia];
    const SkeletonNode& nb = skeleton.nodes[ib];
    const int pieces = piece_count(na, nb, (nb.position - na.position).norm(), options);
    const bool tapered = is_tapered(na, nb);
    std::uint32_t prev = ia;
    for (int k = 1; k < pieces; ++k) {
      double t = static_cast<double>(k) / pieces;
      if (tapered) {  // the node where the radius has changed by the k-th power of q
        const double r = na.radius * pm::pow(nb.radius / na.radius, t);
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

}  // namespace ramiform
