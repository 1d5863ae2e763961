// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/skeleton/generate.h"

#include <cmath>
#include <deque>
#include <numbers>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw InvalidArgument("branching_tree: " + what);
}

// A unit vector perpendicular to `d`.
Vec3 perpendicular(const Vec3& d) {
  const Vec3 helper = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return d.cross(helper).normalized();
}

}  // namespace

Skeleton branching_tree(const BranchingTreeOptions& o) {
  using O = BranchingTreeOptions;
  check(o.segments >= O::kMinSegments && o.segments <= O::kMaxSegments,
        "segments must be in " + range_text(O::kMinSegments, O::kMaxSegments));
  check(std::isfinite(o.trunk_length) && o.trunk_length > 0, "trunk_length must be > 0");
  check(o.length_ratio >= O::kMinLengthRatio && o.length_ratio <= O::kMaxLengthRatio,
        "length_ratio must be in " + range_text(O::kMinLengthRatio, O::kMaxLengthRatio));
  check(std::isfinite(o.branch_angle_deg) && o.branch_angle_deg >= 0 &&
            o.branch_angle_deg < O::kMaxBranchAngleDeg,
        "branch_angle_deg must be in [0, " + format_number(O::kMaxBranchAngleDeg) + ")");
  check(std::isfinite(o.jitter_deg) && o.jitter_deg >= 0 && o.jitter_deg <= O::kMaxJitterDeg,
        "jitter_deg must be in [0, " + format_number(O::kMaxJitterDeg) + "]");
  check(std::isfinite(o.tip_radius) && o.tip_radius > 0, "tip_radius must be > 0");
  check(o.pipe_exponent >= O::kMinPipeExponent && o.pipe_exponent <= O::kMaxPipeExponent,
        "pipe_exponent must be in " + range_text(O::kMinPipeExponent, O::kMaxPipeExponent));

  const double deg = std::numbers::pi / 180;
  Rng rng(o.seed);
  Skeleton s;
  s.nodes.push_back({Vec3::Zero(), o.tip_radius});
  std::vector<std::uint32_t> parent{UINT32_MAX};
  struct Bud {
    std::uint32_t node;
    Vec3 direction;
    double length;
  };
  std::deque<Bud> buds{{0, Vec3::UnitZ(), o.trunk_length}};
  while (s.edges.size() < o.segments) {
    const Bud bud = buds.front();
    buds.pop_front();
    // Jitter the direction by a small random rotation.
    const Vec3 axis = pm::rotation(rng.uniform(0, 2 * std::numbers::pi), bud.direction) *
                      perpendicular(bud.direction);
    const Vec3 dir = (pm::rotation(o.jitter_deg * deg * rng.uniform(), axis) * bud.direction).normalized();
    const auto node = static_cast<std::uint32_t>(s.nodes.size());
    s.nodes.push_back({s.nodes[bud.node].position + bud.length * dir, o.tip_radius});
    s.edges.push_back({bud.node, node});
    parent.push_back(bud.node);
    const Vec3 fork_axis = pm::rotation(rng.uniform(0, 2 * std::numbers::pi), dir) * perpendicular(dir);
    for (const double side : {-1.0, 1.0}) {
      const Vec3 child = (pm::rotation(side * o.branch_angle_deg * deg, fork_axis) * dir).normalized();
      buds.push_back({node, child, bud.length * o.length_ratio});
    }
  }
  // Pipe model from the tips down: nodes are created after their parents, so a reverse sweep
  // sees every child before its parent.
  std::vector<double> sum(s.nodes.size(), 0.0);
  for (std::size_t i = s.nodes.size(); i-- > 0;) {
    const double r = sum[i] > 0 ? pm::pow(sum[i], 1 / o.pipe_exponent) : o.tip_radius;
    s.nodes[i].radius = r;
    if (parent[i] != UINT32_MAX) sum[parent[i]] += pm::pow(r, o.pipe_exponent);
  }
  return s;
}

}  // namespace ramiform
