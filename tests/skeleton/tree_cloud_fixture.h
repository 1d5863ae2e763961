// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// A synthetic laser-scanned tree: points on the open cylinder (cone frustum) surfaces of a known
// branching skeleton, with radial noise and uneven density, and the exact answers to compare a
// reconstructed skeleton with (tips, distance to the true skeleton, radius there).

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "ramiform/core/random.h"
#include "ramiform/core/types.h"

namespace ramiform::test {

struct TrueSegment {
  Vec3 a, b;
  double ra, rb;
};

struct SyntheticTree {
  std::vector<TrueSegment> segments;
  std::vector<Vec3> tips;
  std::vector<Vec3> points;

  /// Closest point parameter, distance and interpolated radius of the nearest segment.
  struct Near {
    std::size_t segment = 0;
    double t = 0.0, distance = std::numeric_limits<double>::infinity(), radius = 0.0;
  };
  [[nodiscard]] Near nearest(const Vec3& p) const {
    Near best;
    for (std::size_t s = 0; s < segments.size(); ++s) {
      const TrueSegment& g = segments[s];
      const Vec3 d = g.b - g.a;
      const double t = std::clamp((p - g.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      const double dist = (p - (g.a + t * d)).norm();
      if (dist < best.distance) best = {s, t, dist, (1 - t) * g.ra + t * g.rb};
    }
    return best;
  }
};

/// The tree: a trunk (radius 0.15 to 0.11) forking at 2.0 into two limbs, a side branch off
/// the trunk at 1.2 and a twig off one limb; 4 tips. Points are drawn uniformly on each
/// frustum's side at `per_area` points per unit area, thinned by a smooth density factor in
/// [0.35, 1] (uneven density), moved radially by normal noise of `noise` times the local
/// radius; points inside another segment's frustum (the joins) are left out, as a scanner does
/// not see them.
inline SyntheticTree synthetic_tree(double per_area = 4000.0, double noise = 0.03,
                                    std::uint64_t seed = 7) {
  SyntheticTree t;
  const Vec3 base(0, 0, 0), fork(0, 0, 2.0), side0(0, 0, 1.2);
  const Vec3 limb_a(0.9, 0.1, 3.3), limb_b(-0.7, 0.4, 3.1), side1(0.8, -0.6, 1.9);
  const Vec3 twig0 = fork + 0.55 * (limb_a - fork), twig1(0.3, 0.7, 3.2);
  t.segments = {{base, fork, 0.15, 0.11},
                {fork, limb_a, 0.085, 0.045},
                {fork, limb_b, 0.08, 0.045},
                {side0, side1, 0.06, 0.035},
                {twig0, twig1, 0.04, 0.03}};
  t.tips = {limb_a, limb_b, side1, twig1};
  Rng rng(seed);
  for (std::size_t s = 0; s < t.segments.size(); ++s) {
    const TrueSegment& g = t.segments[s];
    const Vec3 axis = (g.b - g.a).normalized();
    const Vec3 u = axis.unitOrthogonal();
    const Vec3 v = axis.cross(u);
    const double len = (g.b - g.a).norm();
    const double area = std::numbers::pi * (g.ra + g.rb) * len;
    const auto count = static_cast<std::size_t>(area * per_area);
    for (std::size_t i = 0; i < count; ++i) {
      const double h = rng.uniform();
      const double phi = rng.uniform(0.0, 2 * std::numbers::pi);
      const double r = (1 - h) * g.ra + h * g.rb;
      const double rr = r * (1.0 + noise * rng.normal());
      const Vec3 p = g.a + h * len * axis + rr * (std::cos(phi) * u + std::sin(phi) * v);
      // Uneven density: denser on one side and varying with height.
      const double keep = 0.35 + 0.65 * (0.5 + 0.25 * std::sin(3.0 * p.z()) + 0.25 * std::cos(phi));
      if (rng.uniform() > keep) continue;
      bool hidden = false;
      for (std::size_t o = 0; o < t.segments.size() && !hidden; ++o) {
        if (o == s) continue;
        const TrueSegment& q = t.segments[o];
        const Vec3 d = q.b - q.a;
        const double tt = (p - q.a).dot(d) / d.squaredNorm();
        if (tt < 0.0 || tt > 1.0) continue;
        hidden = (p - (q.a + tt * d)).norm() < 0.97 * ((1 - tt) * q.ra + tt * q.rb);
      }
      if (!hidden) t.points.push_back(p);
    }
  }
  return t;
}

}  // namespace ramiform::test
