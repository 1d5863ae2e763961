// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Shared test fixtures: skeletons every stage tests on (Y-fork, helix, random tree, single
/// segment), unique temporary directories and the location of the shared data files. All
/// randomness flows through ramiform::Rng, so every fixture is identical on every platform.

#include <cstdint>
#include <filesystem>
#include <string>

#include "ramiform/core/types.h"
#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

// RAMIFORM_TEST_SANITIZED is defined when the tests are built with AddressSanitizer or
// ThreadSanitizer (GCC's __SANITIZE_*__, clang's __has_feature), for tests that scale down or
// skip work that takes minutes under them.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define RAMIFORM_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define RAMIFORM_TEST_SANITIZED 1
#endif
#endif

namespace ramiform::test {

/// A Y-shaped fork: node 0 at the origin (radius `trunk_radius`), a vertical trunk of length
/// 10 * trunk_radius to node 1 (radius 0.8 * trunk_radius), and two branches from node 1 to the
/// tips 2 and 3 (radius 0.5 * trunk_radius) at (-+6, 0, 18) * trunk_radius, in the xz plane.
/// Edges {0,1}, {1,2}, {1,3}. Passes validate().
[[nodiscard]] Skeleton y_fork(double trunk_radius = 1.0);

/// A helical polyline of `segments` edges (segments + 1 nodes, node i joined to i + 1) around the
/// z axis starting at (coil, 0, 0), 12 segments per turn. Every node has tube radius `radius`;
/// the coil radius is 5 * radius and the pitch 8 * radius per turn, so neighbouring turns are
/// 6 radii apart (their tubes never touch). `segments` >= 1.
[[nodiscard]] Skeleton helix(int segments, double radius = 1.0);

/// A random branching tree of `nodes` nodes (>= 1) grown upward from a root at the origin of
/// radius 1: every new node attaches to a uniformly chosen existing node, offset by a random
/// direction with positive z component, at a length of 3..6 times the parent's radius; its
/// radius is 0.80..0.95 times the parent's (never below 0.05). Edges are (parent, child), in
/// order of creation (edge i creates node i + 1). Built with ramiform::Rng(seed); passes
/// validate().
[[nodiscard]] Skeleton random_tree(std::uint64_t seed, int nodes);

/// `s` with every edge cut into `pieces` edges, the new nodes on the edge with a linear taper
/// of the radius (as a scanned cylinder model's fine chains are). New nodes come after `s`'s.
[[nodiscard]] Skeleton subdivided(const Skeleton& s, int pieces);

/// The generated tree with 4 mm twigs of docs/benchmarks.md with `segments` edges:
/// branching_tree with tip_radius 0.004, trunk_length 1 and seed 1 (what `ramiform generate
/// --segments N --tip-radius 0.004 --trunk-length 1 --seed 1` writes).
[[nodiscard]] Skeleton twig_tree(std::size_t segments);

/// The Wyvill distance surface of `s` (what `ramiform mesh --surface distance` meshes).
[[nodiscard]] FieldPtr wyvill_distance_field(const Skeleton& s);

/// One segment from `a` (radius `ra`) to `b` (radius `rb`).
[[nodiscard]] Skeleton single_segment(const Vec3& a = Vec3(0, 0, 0), const Vec3& b = Vec3(0, 0, 10),
                                      double ra = 1.0, double rb = 1.0);

/// A new, unique, empty directory named after `name` under $RAMIFORM_TEST_TMP (when set) or
/// the system temporary directory. The caller may remove it; nothing removes it automatically.
[[nodiscard]] std::filesystem::path temp_dir(const std::string& name);

/// The shared data directory (`<source_dir>/../shared/data`) for a given source directory.
[[nodiscard]] std::filesystem::path shared_data_dir(const std::filesystem::path& source_dir);

#ifdef RAMIFORM_SOURCE_DIR
// Defined only in test programs (which get RAMIFORM_SOURCE_DIR from CMake); the support library
// itself never sees these, so there is one definition per program.

/// The shared data directory of this source tree: RAMIFORM_SOURCE_DIR "/../shared/data".
[[nodiscard]] inline std::filesystem::path shared_data_dir() {
  return shared_data_dir(std::filesystem::path(RAMIFORM_SOURCE_DIR));
}

/// True when the shared data directory exists (tests that need it skip otherwise).
[[nodiscard]] inline bool shared_data_available() {
  std::error_code ec;
  return std::filesystem::is_directory(shared_data_dir(), ec);
}
#endif

}  // namespace ramiform::test
