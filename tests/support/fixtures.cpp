// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "support/fixtures.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <stdexcept>

#include "ramiform/core/random.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/skeleton/generate.h"

namespace ramiform::test {

Skeleton y_fork(double trunk_radius) {
  const double r = trunk_radius;
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), r},
             {Vec3(0, 0, 10 * r), 0.8 * r},
             {Vec3(-6 * r, 0, 18 * r), 0.5 * r},
             {Vec3(6 * r, 0, 18 * r), 0.5 * r}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}};
  return s;
}

Skeleton helix(int segments, double radius) {
  if (segments < 1) throw std::invalid_argument("helix: segments must be >= 1");
  constexpr int kPerTurn = 12;
  const double coil = 5 * radius;
  const double pitch = 8 * radius;
  Skeleton s;
  for (int i = 0; i <= segments; ++i) {
    const double turns = static_cast<double>(i) / kPerTurn;
    const double angle = 2 * std::numbers::pi * turns;
    s.nodes.push_back({Vec3(coil * std::cos(angle), coil * std::sin(angle), pitch * turns), radius});
    if (i > 0) s.edges.push_back({static_cast<std::uint32_t>(i - 1), static_cast<std::uint32_t>(i)});
  }
  return s;
}

Skeleton random_tree(std::uint64_t seed, int nodes) {
  if (nodes < 1) throw std::invalid_argument("random_tree: nodes must be >= 1");
  Rng rng(seed);
  Skeleton s;
  s.nodes.push_back({Vec3::Zero(), 1.0});
  for (int i = 1; i < nodes; ++i) {
    const auto parent = static_cast<std::uint32_t>(rng.below(static_cast<std::uint64_t>(i)));
    const SkeletonNode& p = s.nodes[parent];
    // A random direction biased upward: z = |z| + 1 keeps it strictly positive.
    Vec3 dir(rng.normal(), rng.normal(), std::abs(rng.normal()) + 1.0);
    dir.normalize();
    const double length = rng.uniform(3.0, 6.0) * p.radius;
    const double radius = std::max(0.05, p.radius * rng.uniform(0.80, 0.95));
    s.nodes.push_back({p.position + length * dir, radius});
    s.edges.push_back({parent, static_cast<std::uint32_t>(i)});
  }
  return s;
}

Skeleton twig_tree(std::size_t segments) {
  BranchingTreeOptions o;
  o.segments = segments;
  o.tip_radius = 0.004;
  o.trunk_length = 1;
  o.seed = 1;
  return branching_tree(o);
}

FieldPtr wyvill_distance_field(const Skeleton& s) {
  SkeletonFieldOptions fo;
  fo.surface = SurfaceKind::kDistance;
  fo.kernel = Kernel{KernelKind::kWyvill, 0.0};
  return make_skeleton_field(s, fo);
}

Skeleton single_segment(const Vec3& a, const Vec3& b, double ra, double rb) {
  Skeleton s;
  s.nodes = {{a, ra}, {b, rb}};
  s.edges = {{0, 1}};
  return s;
}

std::filesystem::path temp_dir(const std::string& name) {
  static std::atomic<unsigned> counter{0};
  std::filesystem::path base;
  if (const char* env = std::getenv("RAMIFORM_TEST_TMP"); env != nullptr && *env != '\0') {
    base = env;
  } else {
    base = std::filesystem::temp_directory_path() / "ramiform-tests";
  }
  std::filesystem::create_directories(base);
  for (;;) {
    const std::filesystem::path dir =
        base / (name + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    // create_directory returns false when it already exists: try the next number.
    if (std::filesystem::create_directory(dir)) return dir;
  }
}

std::filesystem::path shared_data_dir(const std::filesystem::path& source_dir) {
  return source_dir / ".." / "shared" / "data";
}

Skeleton subdivided(const Skeleton& s, int pieces) {
  Skeleton out;
  out.nodes = s.nodes;
  for (const auto& e : s.edges) {
    std::uint32_t prev = e[0];
    for (int k = 1; k < pieces; ++k) {
      const double t = static_cast<double>(k) / pieces;
      const SkeletonNode& a = s.nodes[e[0]];
      const SkeletonNode& b = s.nodes[e[1]];
      out.nodes.push_back(
          {a.position + t * (b.position - a.position), a.radius + t * (b.radius - a.radius)});
      const auto v = static_cast<std::uint32_t>(out.nodes.size() - 1);
      out.edges.push_back({prev, v});
      prev = v;
    }
    out.edges.push_back({prev, e[1]});
  }
  return out;
}

}  // namespace ramiform::test
