// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Oriented point clouds for the MPU and normal tests: analytic shapes with exact normals and
// signed distances, and the shared models (skipped when ../shared is absent).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/geometry.h"
#include "ramiform/core/random.h"
#include "ramiform/io/mesh_io.h"
#include "ramiform/io/points_io.h"
#include "ramiform/mesh/surface_points.h"
#include "support/fixtures.h"

namespace ramiform::test {

/// n points on the sphere of radius r around c (Fibonacci lattice), exact outward normals.
inline PointSet sphere_cloud(int n, double r = 1.0, const Vec3& c = Vec3::Zero()) {
  PointSet s;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n;
    const double q = std::sqrt(1 - z * z);
    const Vec3 u(q * std::cos(golden * i), q * std::sin(golden * i), z);
    s.positions.push_back(c + r * u);
    s.normals.push_back(u);
  }
  return s;
}

/// Signed distance to the sphere (> 0 outside).
inline double sphere_distance(const Vec3& p, double r = 1.0, const Vec3& c = Vec3::Zero()) {
  return (p - c).norm() - r;
}

constexpr double kTorusMajor = 1.0;
constexpr double kTorusMinor = 0.4;

/// n area-uniform random points on the torus around the z axis (major radius 1, minor 0.4),
/// exact outward normals.
inline PointSet torus_cloud(int n, std::uint64_t seed) {
  Rng rng(seed);
  PointSet s;
  while (static_cast<int>(s.size()) < n) {
    const double phi = rng.uniform(0, 2 * std::numbers::pi);
    const double theta = rng.uniform(0, 2 * std::numbers::pi);
    // Area element (R + r cos θ): accept with probability proportional to it.
    if (rng.uniform() * (kTorusMajor + kTorusMinor) > kTorusMajor + kTorusMinor * std::cos(theta))
      continue;
    const Vec3 n3(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi),
                  std::sin(theta));
    const Vec3 ring(kTorusMajor * std::cos(phi), kTorusMajor * std::sin(phi), 0);
    s.positions.push_back(ring + kTorusMinor * n3);
    s.normals.push_back(n3);
  }
  return s;
}

/// Signed distance to the torus (> 0 outside).
inline double torus_distance(const Vec3& p) {
  const double q = std::hypot(p.x(), p.y()) - kTorusMajor;
  return std::hypot(q, p.z()) - kTorusMinor;
}

/// The shared models directory, or "" when absent.
inline std::filesystem::path models_dir() {
  const auto dir = shared_data_dir() / "models";
  std::error_code ec;
  return std::filesystem::is_directory(dir, ec) ? dir : std::filesystem::path();
}

/// `n` area-weighted points on a mesh file with their face normals (seeded).
inline PointSet sample_mesh(const std::filesystem::path& file, int n, std::uint64_t seed) {
  const TriMesh mesh = read_mesh(file.string());
  const MeshAreaSampler sampler(mesh);
  Rng rng(seed);
  PointSet s;
  for (int i = 0; i < n; ++i) {
    const MeshPoint mp = sampler.draw(rng);
    const auto& t = mesh.triangles[mp.triangle];
    const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
    const Vec3 normal = (b - a).cross(c - a);
    if (!(normal.norm() > 0)) continue;
    s.positions.push_back(sampler.position(mp));
    s.normals.push_back(normal.normalized());
  }
  return s;
}

/// Runs `fn` and expects an InvalidArgument whose message contains `text`.
inline void expect_invalid_argument(const std::function<void()>& fn, const std::string& text) {
  try {
    fn();
    ADD_FAILURE() << "no exception, expected one naming '" << text << "'";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

/// The points' bounding-box diagonal.
inline double diagonal(const PointSet& s) {
  Aabb b;
  for (const auto& p : s.positions) b.extend(p);
  return b.diagonal().norm();
}

}  // namespace ramiform::test

/// Loads a shared model as an oriented point cloud into `cloud`, or skips the test.
#define RAMIFORM_LOAD_MODEL_OR_SKIP(name, mesh_samples, cloud)                           \
  do {                                                                                   \
    const auto dir_ = ::ramiform::test::models_dir();                                    \
    if (dir_.empty())                                                                    \
      GTEST_SKIP() << "shared models not found (" << ::ramiform::test::shared_data_dir() \
                   << "/models): a clone without ../shared skips the model tests";       \
    const std::filesystem::path file_ = dir_ / (name);                                   \
    const std::string ext_ = file_.extension().string();                                 \
    (cloud) = ext_ == ".xyz" || ext_ == ".pwn"                                           \
                  ? ::ramiform::read_points(file_.string())                              \
                  : ::ramiform::test::sample_mesh(file_, (mesh_samples), 7);             \
  } while (false)
