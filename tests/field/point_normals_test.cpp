// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/point_normals.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "field/point_cloud_fixtures.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/mpu.h"

namespace ramiform {
namespace {

// Counts normals that point against the reference, and the largest angle (degrees) between the
// lines they span.
struct Agreement {
  std::size_t against = 0;
  double worst_deg = 0;
};
Agreement compare(const std::vector<Vec3>& got, const std::vector<Vec3>& reference) {
  Agreement a;
  for (std::size_t i = 0; i < got.size(); ++i) {
    const Vec3 r = reference[i].normalized();
    EXPECT_NEAR(got[i].norm(), 1.0, 1e-12);
    const double c = got[i].dot(r);
    if (c < 0) ++a.against;
    a.worst_deg = std::max(
        a.worst_deg, std::atan2(got[i].cross(r).norm(), std::abs(c)) * 180 / std::numbers::pi);
  }
  return a;
}

PointSet flip_some(const PointSet& s, double fraction, std::uint64_t seed, std::size_t* count) {
  PointSet out = s;
  Rng rng(seed);
  *count = 0;
  for (auto& n : out.normals) {
    if (rng.uniform() < fraction) {
      n = -2.5 * n;  // flipped, and not unit: the result must be normalized
      ++*count;
    }
  }
  return out;
}

TEST(PointNormals, EstimatesOutwardNormalsOfAnalyticShapes) {
  const PointSet sphere = test::sphere_cloud(2000);
  const PointSet torus = test::torus_cloud(6000, 21);
  for (const PointSet* s : {&sphere, &torus}) {
    PointSet bare = *s;
    bare.normals.clear();
    NormalReport report;
    const PointSet out = orient_normals(bare, {}, &report);
    EXPECT_EQ(out.positions, s->positions);
    EXPECT_EQ(report.estimated, s->size());
    EXPECT_EQ(report.flipped, 0u);
    EXPECT_EQ(report.components, 1u);
    const Agreement a = compare(out.normals, s->normals);
    EXPECT_EQ(a.against, 0u);
    EXPECT_LT(a.worst_deg, 12.0);
  }
}

TEST(PointNormals, FlipsInconsistentNormalsBack) {
  const PointSet torus = test::torus_cloud(5000, 22);
  for (const double fraction : {0.2, 1.0}) {
    std::size_t flipped = 0;
    const PointSet bad = flip_some(torus, fraction, 23, &flipped);
    NormalReport report;
    const PointSet out = orient_normals(bad, {}, &report);
    EXPECT_EQ(report.estimated, 0u);
    EXPECT_EQ(report.flipped, flipped) << fraction;
    const Agreement a = compare(out.normals, torus.normals);
    EXPECT_EQ(a.against, 0u) << fraction;
    EXPECT_LT(a.worst_deg, 1e-12) << fraction;  // given normals keep their direction
  }
}

TEST(PointNormals, ThinPlateKeepsBothSides) {
  // A 2 x 2 x 0.04 plate: neighbours reach across it, where the two sides' normals are opposite
  // (Hoppe's plain n_i . n_j would carry the orientation across and flip one side).
  Rng rng(25);
  PointSet plate;
  const Vec3 half(1, 1, 0.02);
  while (plate.size() < 6000) {
    const Vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.02, 0.02));
    // Area-uniform over the six faces: pick a face with probability proportional to its area.
    const double areas[3] = {0.04 * 2, 0.04 * 2, 4};
    double pick = rng.uniform(0, 2 * (areas[0] + areas[1] + areas[2]));
    int axis = 0;
    while (pick >= 2 * areas[axis]) pick -= 2 * areas[axis++];
    const double side = pick < areas[axis] ? -1.0 : 1.0;
    Vec3 q = p;
    q[axis] = side * half[axis];
    plate.positions.push_back(q);
    plate.normals.push_back(side * Vec3::Unit(axis));
  }
  std::size_t flipped = 0;
  const PointSet bad = flip_some(plate, 0.2, 26, &flipped);
  NormalReport report;
  const PointSet out = orient_normals(bad, {}, &report);
  EXPECT_EQ(report.flipped, flipped);
  EXPECT_EQ(compare(out.normals, plate.normals).against, 0u);
}

TEST(PointNormals, OrientsEachComponent) {
  PointSet two = test::sphere_cloud(600, 1.0, Vec3(-3, 0, 0));
  const PointSet b = test::sphere_cloud(900, 0.5, Vec3(4, 1, 0));
  two.positions.insert(two.positions.end(), b.positions.begin(), b.positions.end());
  two.normals.insert(two.normals.end(), b.normals.begin(), b.normals.end());
  const PointSet reference = two;
  for (std::size_t i = 600; i < two.size(); ++i) two.normals[i] = -two.normals[i];
  NormalReport report;
  const PointSet out = orient_normals(two, {}, &report);
  EXPECT_EQ(report.components, 2u);
  EXPECT_EQ(report.flipped, 900u);
  EXPECT_EQ(compare(out.normals, reference.normals).against, 0u);
}

TEST(PointNormals, SameResultOnOneAndTwoThreads) {
  PointSet bare = test::torus_cloud(4000, 24);
  bare.normals.clear();
  const Context one(1), two(2);
  const PointSet a = orient_normals(bare, {}, nullptr, &one);
  const PointSet b = orient_normals(bare, {}, nullptr, &two);
  EXPECT_EQ(a.normals, b.normals);
}

TEST(PointNormals, RejectsBadInput) {
  const auto& expect_throw_with = test::expect_invalid_argument;
  const PointSet good = test::sphere_cloud(50);
  PointSet zero = good;
  zero.normals[9] = Vec3::Zero();
  expect_throw_with([&] { (void)orient_normals(zero); }, "point 9 has a zero or non-finite normal");
  PointSet nan = good;
  nan.normals[4].z() = std::nan("");
  expect_throw_with([&] { (void)orient_normals(nan); }, "point 4");
  PointSet inf = good;
  inf.positions[0].y() = -std::numeric_limits<double>::infinity();
  inf.normals.clear();
  expect_throw_with([&] { (void)orient_normals(inf); }, "point 0 has a non-finite position");
  PointSet mismatched = good;
  mismatched.normals.resize(10);
  expect_throw_with([&] { (void)orient_normals(mismatched); }, "10 normals for 50 points");
  NormalOptions o;
  o.neighbours = 2;
  expect_throw_with([&] { (void)orient_normals(good, o); }, "neighbours");
  PointSet two;
  two.positions = {Vec3::Zero(), Vec3::UnitX()};
  expect_throw_with([&] { (void)orient_normals(two); }, "at least 3 points");
}

// ---- the kitten: normals removed, 20 % flipped, all flipped -------------------------------------

// Sign agreement of two fields at points just off the surface, and the mean difference of their
// first-order distances there.
void expect_same_surface(const Field& a, const Field& b, const PointSet& cloud, double diag,
                         const std::string& what) {
  Rng rng(31);
  std::vector<Vec3> pts;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3 n = cloud.normals[i].normalized();
    pts.push_back(cloud.positions[i] + rng.uniform(-0.01, 0.01) * diag * n);
  }
  std::vector<double> va(pts.size()), vb(pts.size());
  std::vector<Vec3> ga(pts.size()), gb(pts.size());
  a.evaluate(pts, va, ga);
  b.evaluate(pts, vb, gb);
  std::size_t agree = 0;
  double difference = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    agree += (va[i] > a.iso()) == (vb[i] > b.iso()) ? 1 : 0;
    difference += std::abs((va[i] - a.iso()) / ga[i].norm() - (vb[i] - b.iso()) / gb[i].norm());
  }
  EXPECT_GE(static_cast<double>(agree), 0.99 * static_cast<double>(pts.size())) << what;
  EXPECT_LT(difference / static_cast<double>(pts.size()), 1e-3 * diag) << what;
}

TEST(PointNormals, KittenWithoutNormalsGivesTheSameSurface) {
  PointSet kitten;
  RAMIFORM_LOAD_MODEL_OR_SKIP("kitten.xyz", 0, kitten);
  const double diag = test::diagonal(kitten);
  const FieldPtr reference = make_mpu_field(kitten);

  PointSet bare = kitten;
  bare.normals.clear();
  NormalReport report;
  const PointSet estimated = orient_normals(bare, {}, &report);
  EXPECT_EQ(report.estimated, kitten.size());
  EXPECT_EQ(report.components, 1u);
  const Agreement a = compare(estimated.normals, kitten.normals);
  EXPECT_LT(static_cast<double>(a.against), 0.005 * static_cast<double>(kitten.size()));
  expect_same_surface(*reference, *make_mpu_field(estimated), kitten, diag, "estimated normals");

  for (const double fraction : {0.2, 1.0}) {
    std::size_t flipped = 0;
    const PointSet bad = flip_some(kitten, fraction, 32, &flipped);
    const PointSet fixed = orient_normals(bad, {}, &report);
    EXPECT_NEAR(static_cast<double>(report.flipped), static_cast<double>(flipped),
                0.005 * static_cast<double>(kitten.size()))
        << fraction;
    EXPECT_LT(static_cast<double>(compare(fixed.normals, kitten.normals).against),
              0.005 * static_cast<double>(kitten.size()))
        << fraction;
    expect_same_surface(*reference, *make_mpu_field(fixed), kitten, diag,
                        std::to_string(fraction) + " flipped");
  }
}

}  // namespace
}  // namespace ramiform
