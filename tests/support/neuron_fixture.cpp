// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "support/neuron_fixture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "ramiform/core/random.h"
#include "ramiform/core/types.h"

namespace ramiform::test {
namespace {

constexpr double kTipRadius = 0.2;     // um, the thinnest neurite
constexpr double kStep = 2.0;          // um between samples along a neurite (+- 25 %)
constexpr double kBranchTaper = 0.85;  // radius at a branch's end / at its start
constexpr double kDaughter = 0.7;      // daughter radius / parent's end radius at a fork

struct Sample {
  int id = 0;
  int type = 0;
  Vec3 p = Vec3::Zero();
  double r = 0;
  int parent = -1;
};

Vec3 random_unit(Rng& rng) {
  while (true) {
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const double n = v.norm();
    if (n > 0.1 && n <= 1.0) return v / n;
  }
}

// Branches of a subtree whose first branch starts at radius r0 (the radii are deterministic).
int branch_count(double r0) {
  const double child = r0 * kBranchTaper * kDaughter;
  if (child < 1.25 * kTipRadius) return 1;
  return 1 + 2 * branch_count(child);
}

class Grower {
 public:
  Grower(Rng& rng, std::vector<Sample>& out, int steps) : rng_(rng), out_(out), steps_(steps) {}

  // Grows a branch of `steps_` samples from the sample `parent` at `from`, then forks.
  void branch(int parent, Vec3 from, Vec3 dir, double r0, int type, int steps = 0) {
    if (steps == 0) steps = steps_;
    const double child = r0 * kBranchTaper * kDaughter;
    const bool terminal = child < 1.25 * kTipRadius;
    const double r1 = terminal ? kTipRadius : r0 * kBranchTaper;
    Vec3 p = from;
    for (int k = 1; k <= steps; ++k) {
      const Vec3 outward = p.norm() > 0 ? Vec3(p / p.norm()) : dir;
      dir = (dir + 0.25 * random_unit(rng_) + 0.1 * outward).normalized();
      p += kStep * rng_.uniform(0.75, 1.25) * dir;
      const double t = static_cast<double>(k) / steps;
      parent = add(type, p, (1 - t) * r0 + t * r1, parent);
    }
    if (terminal) return;
    const Vec3 side = dir.cross(random_unit(rng_)).normalized();
    const double angle = rng_.uniform(25, 40) * std::numbers::pi / 180;
    for (const double s : {1.0, -1.0}) {
      const Vec3 d = (std::cos(angle) * dir + s * std::sin(angle) * side).normalized();
      branch(parent, p, d, child, type);
    }
  }

  int add(int type, const Vec3& p, double r, int parent) {
    Sample s;
    s.id = static_cast<int>(out_.size()) + 1;
    s.type = type;
    s.p = p;
    s.r = r;
    s.parent = parent;
    out_.push_back(s);
    return s.id;
  }

 private:
  Rng& rng_;
  std::vector<Sample>& out_;
  int steps_;
};

double rounded(double v) { return std::round(v * 100.0) / 100.0; }

}  // namespace

std::string neuron_swc(const NeuronOptions& o, NeuronFacts* facts) {
  if (o.dendrites < 1 || o.dendrites > 12 || o.target_samples < 200 || !(o.soma_radius >= 1) ||
      o.extra_trees < 0) {
    throw std::invalid_argument("neuron_swc: dendrites " + std::to_string(o.dendrites) +
                                " (1..12), target_samples " + std::to_string(o.target_samples) +
                                " (>= 200), soma_radius " + std::to_string(o.soma_radius) +
                                " (>= 1), extra_trees " + std::to_string(o.extra_trees) +
                                " (>= 0)");
  }
  Rng rng(o.seed);
  std::vector<Sample> s;
  const double R = o.soma_radius;
  Grower grow(rng, s, 1);

  // The soma.
  switch (o.soma) {
    case NeuronSoma::kSinglePoint:
      grow.add(1, Vec3::Zero(), R, -1);
      break;
    case NeuronSoma::kThreePoint:
      grow.add(1, Vec3::Zero(), R, -1);
      grow.add(1, Vec3(0, -R, 0), R, 1);
      grow.add(1, Vec3(0, R, 0), R, 1);
      break;
    case NeuronSoma::kContour:
      for (int k = 0; k < 16; ++k) {
        const double a = 2 * std::numbers::pi * k / 16;
        grow.add(1, Vec3(R * std::cos(a), R * std::sin(a), 0), 0.5, k == 0 ? -1 : k);
      }
      break;
    case NeuronSoma::kCylinders:
      for (int k = 0; k < 7; ++k) {
        const double z = -R + 2 * R * k / 6;
        grow.add(1, Vec3(0, 0, z), R * std::sqrt(1 - 0.8 * (z / R) * (z / R)), k == 0 ? -1 : k);
      }
      break;
  }
  const int soma_samples = static_cast<int>(s.size());
  const auto soma_parent = [&](const Vec3& p) {
    int best = 1;
    for (int k = 0; k < soma_samples; ++k) {
      if ((s[k].p - p).norm() < (s[best - 1].p - p).norm()) best = k + 1;
    }
    return best;
  };

  // Primary directions: a Fibonacci sphere with jitter; the axon leaves downward (-z).
  std::vector<Vec3> dirs;
  std::vector<double> r0s;
  int branches = 0;
  for (int d = 0; d < o.dendrites; ++d) {
    const double zf = 1 - 2 * (d + 0.5) / o.dendrites;
    const double z = 0.2 + 0.75 * zf;  // keep clear of the axon's direction
    const double phi = d * std::numbers::pi * (3 - std::sqrt(5.0));
    const double rho = std::sqrt(std::max(0.0, 1 - z * z));
    dirs.push_back(
        (Vec3(rho * std::cos(phi), rho * std::sin(phi), z) + 0.1 * random_unit(rng)).normalized());
    r0s.push_back(d == 0 ? 1.6 : rng.uniform(0.9, 1.3));
    branches += branch_count(r0s.back());
  }
  const int axon_steps = std::max(10, o.target_samples / 10);
  const int collateral_steps = std::max(4, axon_steps / 5);
  const int steps =
      std::max(3, (o.target_samples - axon_steps - 2 * collateral_steps) / std::max(1, branches));
  Grower g(rng, s, steps);
  for (int d = 0; d < o.dendrites; ++d) {
    const Vec3 start = (R + 1.5) * dirs[d];
    const int first = g.add(d == 0 ? 4 : 3, start, r0s[d], soma_parent(start));
    g.branch(first, start, dirs[d], r0s[d], d == 0 ? 4 : 3);
  }
  // The axon: a long thin process straight down with two collaterals.
  {
    Vec3 dir(0, 0, -1);
    Vec3 p = Vec3(0, 0, -(R + 1.5));
    int parent = g.add(2, p, 0.6, soma_parent(p));
    for (int k = 1; k <= axon_steps; ++k) {
      dir = (dir + 0.1 * random_unit(rng) + Vec3(0, 0, -0.05)).normalized();
      p += kStep * dir;
      parent = g.add(2, p, 0.6 - 0.3 * k / axon_steps, parent);
      if (k == axon_steps / 3 || k == 2 * axon_steps / 3) {
        const Vec3 side = dir.cross(random_unit(rng)).normalized();
        g.branch(parent, p, (dir + 1.5 * side).normalized(), 0.35, 2, collateral_steps);
      }
    }
  }
  // Unconnected fragments far from the neuron (a root each, no soma).
  double extent = 0;
  for (const Sample& x : s) extent = std::max(extent, x.p.norm());
  for (int t = 0; t < o.extra_trees; ++t) {
    Vec3 p(extent + 40.0 + 30.0 * t, 0, 0);
    int parent = g.add(3, p, 0.5, -1);
    for (int k = 1; k <= 10; ++k) {
      p += Vec3(0, kStep, 0.3 * k);
      parent = g.add(3, p, 0.5 - 0.025 * k, parent);
    }
  }

  std::vector<std::size_t> order(s.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  if (o.shuffle) {
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
  }
  std::string text =
      "# generated neuron (ramiform tests/support/neuron_fixture.cpp)\n"
      "# units: micrometres\n"
      "# index type x y z radius parent\n";
  char line[160];
  NeuronFacts f;
  f.min_radius = 1e9;
  for (const std::size_t i : order) {
    const Sample& x = s[i];
    const double r = std::max(kTipRadius, rounded(x.r));
    std::snprintf(line, sizeof line, "%d %d %.2f %.2f %.2f %.2f %d\n", x.id, x.type, x.p.x(),
                  x.p.y(), x.p.z(), r, x.parent);
    text += line;
    f.roots += x.parent == -1 ? 1 : 0;
    if (x.type != 1) {
      f.min_radius = std::min(f.min_radius, r);
      f.max_neurite_radius = std::max(f.max_neurite_radius, r);
    }
  }
  f.samples = static_cast<int>(s.size());
  f.soma_samples = soma_samples;
  if (facts != nullptr) *facts = f;
  return text;
}

}  // namespace ramiform::test
