// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/sample/point_sets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>

#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/sample/props.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

SkeletonFieldOptions wyvill() {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kDistance;
  o.kernel = Kernel{KernelKind::kWyvill, 0.0};
  return o;
}

/// A sphere of radius `r` at `c`: Wyvill point primitive, iso 0.5, f(d) = k(d / 2r).
FieldPtr sphere(double r = 1.0, const Vec3& c = Vec3::Zero()) {
  return make_point_field(c, r, wyvill());
}

/// A blend of the Y-fork's three segments (Wyvill distance surface).
FieldPtr fork() { return make_skeleton_field(test::y_fork(1.0), wyvill()); }

std::vector<double> values_of(const Field& f, const std::vector<Vec3>& pts) {
  std::vector<double> v(pts.size());
  f.evaluate(pts, v);
  return v;
}

/// Smallest distance between any two points (brute force).
double min_pair_distance(const std::vector<Vec3>& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) best = std::min(best, (p[i] - p[j]).norm());
  }
  return best;
}

double mean_nearest_neighbour(const std::vector<Vec3>& p) {
  double sum = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (j != i) best = std::min(best, (p[i] - p[j]).norm());
    }
    sum += best;
  }
  return sum / double(p.size());
}

bool same_points(const PointSet& a, const PointSet& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a.positions[i] != b.positions[i]) return false;
  }
  return true;
}

template <class Fn>
InputError input_error(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("", 0, "");
}

void expect_inside(const Field& f, const PointSet& ps) {
  const auto v = values_of(f, ps.positions);
  for (std::size_t i = 0; i < v.size(); ++i) {
    ASSERT_GT(v[i], f.iso()) << "point " << i << " is not inside";
  }
}

TEST(SampleInside, EveryDistributionGivesExactCountInside) {
  const FieldPtr f = fork();
  const std::size_t n = 300;
  std::vector<std::pair<std::string, PointSet>> sets;
  SampleStats st;
  sets.emplace_back("uniform", sample_uniform(*f, {n, 0}, 1, nullptr, &st));
  EXPECT_EQ(st.points, n);
  EXPECT_FALSE(st.saturated);
  EXPECT_GT(st.field_evals, 0U);
  EXPECT_GE(st.attempts, n);
  sets.emplace_back("stratified", sample_stratified(*f, {n}, 1));
  PoissonOptions po;
  po.count = n;
  sets.emplace_back("poisson", sample_poisson(*f, po, 1));
  LaneOptions lo;
  lo.count = n;
  sets.emplace_back("lane", sample_lane(*f, lo, 1));
  lo.kernel = LaneKernel::disk(0.3);
  lo.prune_grid = false;
  sets.emplace_back("lane disk unpruned", sample_lane(*f, lo, 1));
  FieldDensityOptions fo;
  fo.count = n;
  sets.emplace_back("field", sample_field_density(*f, fo, 1));
  BoundaryOptions bo;
  bo.count = n;
  sets.emplace_back("boundary", sample_boundary(*f, bo, 1));
  bo.interior_density = 0.3;
  sets.emplace_back("boundary interior", sample_boundary(*f, bo, 1));
  for (const auto& [name, ps] : sets) {
    SCOPED_TRACE(name);
    EXPECT_EQ(ps.size(), n);
    expect_inside(*f, ps);
  }
}

TEST(SampleInside, UniformOctantsAndShellsMatchVolume) {
  const FieldPtr f = sphere(1.0);
  const std::size_t n = 8000;
  const PointSet ps = sample_uniform(*f, {n, 0}, 42);
  ASSERT_EQ(ps.size(), n);
  std::array<double, 8> oct{};
  std::size_t inner = 0;
  for (const auto& p : ps.positions) {
    oct[(p.x() > 0 ? 1 : 0) + (p.y() > 0 ? 2 : 0) + (p.z() > 0 ? 4 : 0)] += 1;
    if (p.norm() < 0.5) ++inner;
    ASSERT_LT(p.norm(), 1.0 + 1e-9);
  }
  double chi2 = 0;
  for (const double c : oct) chi2 += (c - n / 8.0) * (c - n / 8.0) / (n / 8.0);
  EXPECT_LT(chi2, 30.0);  // 7 degrees of freedom: p < 1e-4 beyond 27.9
  // The ball of radius 1/2 holds 1/8 of the volume: binomial sd = sqrt(n p (1-p)) ~ 29.6.
  EXPECT_NEAR(double(inner), n / 8.0, 5 * 29.6);
}

TEST(SampleInside, StratifiedIsMoreEvenThanUniform) {
  const FieldPtr f = sphere(1.0);
  const PointSet s = sample_stratified(*f, {1000}, 3);
  const PointSet u = sample_uniform(*f, {1000, 0}, 3);
  ASSERT_EQ(s.size(), 1000U);
  // Jittered grid points never cluster as tightly as independent uniform points.
  EXPECT_GT(mean_nearest_neighbour(s.positions), 1.1 * mean_nearest_neighbour(u.positions));
}

TEST(SamplePoisson, MinimumDistanceHoldsForEveryPair) {
  const FieldPtr f = fork();
  PoissonOptions o;
  o.count = 600;
  o.min_distance = 0.35;
  SampleStats st;
  const PointSet ps = sample_poisson(*f, o, 7, nullptr, &st);
  ASSERT_EQ(ps.size(), 600U);
  EXPECT_FALSE(st.saturated);
  EXPECT_GE(min_pair_distance(ps.positions), 0.35);
  expect_inside(*f, ps);
  // Automatic radius still gives a proper Poisson-disk set of the requested size.
  o.min_distance = 0;
  const PointSet auto_r = sample_poisson(*f, o, 7);
  EXPECT_EQ(auto_r.size(), 600U);
  EXPECT_GT(min_pair_distance(auto_r.positions), 0.0);
}

TEST(SamplePoisson, ReportsSaturation) {
  const FieldPtr f = sphere(1.0);
  PoissonOptions o;
  o.count = 1000;
  o.min_distance = 0.5;
  SampleStats st;
  const PointSet ps = sample_poisson(*f, o, 11, nullptr, &st);
  EXPECT_TRUE(st.saturated);
  EXPECT_LT(ps.size(), 100U);
  EXPECT_GT(ps.size(), 8U);
  EXPECT_EQ(st.points, ps.size());
  EXPECT_GE(min_pair_distance(ps.positions), 0.5);
}

TEST(SampleLane, DiskKernelKeepsDiskRadius) {
  const FieldPtr f = sphere(1.0);
  LaneOptions o;
  o.count = 400;
  o.kernel = LaneKernel::disk(0.15);
  SampleStats st;
  const PointSet ps = sample_lane(*f, o, 5, nullptr, &st);
  ASSERT_EQ(ps.size(), 400U);
  EXPECT_GE(min_pair_distance(ps.positions), 0.15);
  expect_inside(*f, ps);
}

TEST(SampleLane, RingKernelClustersAndIsKeptInside) {
  const FieldPtr f = sphere(1.0);
  LaneOptions o;
  o.count = 600;
  o.kernel = LaneKernel::ring(0.02, 0.12, 30.0);
  const PointSet ring = sample_lane(*f, o, 5);
  ASSERT_EQ(ring.size(), 600U);
  expect_inside(*f, ring);
  const PointSet uni = sample_uniform(*f, {600, 0}, 5);
  const double mr = mean_nearest_neighbour(ring.positions);
  const double mu = mean_nearest_neighbour(uni.positions);
  EXPECT_LT(mr, 0.7 * mu) << "ring " << mr << " uniform " << mu;
  EXPECT_GE(min_pair_distance(ring.positions), 0.02);
}

TEST(SampleLane, KernelTableParsingAndFactors) {
  const LaneKernel k = LaneKernel::parse("table 0 0, 1 0, 1 2, 3 1");
  EXPECT_DOUBLE_EQ(k.factor(0.5), 0.0);
  EXPECT_DOUBLE_EQ(k.factor(1.0), 2.0);
  EXPECT_DOUBLE_EQ(k.factor(2.0), 1.5);
  EXPECT_DOUBLE_EQ(k.factor(5.0), 1.0);
  EXPECT_DOUBLE_EQ(k.zero_radius(), 1.0);
  EXPECT_DOUBLE_EQ(k.reach(), 3.0);
  EXPECT_DOUBLE_EQ(LaneKernel::parse("disk 0.25").zero_radius(), 0.25);
  EXPECT_TRUE(LaneKernel::parse("none").table.empty());
  EXPECT_THROW((void)LaneKernel::parse("table 0 1 2"), InvalidArgument);
  EXPECT_THROW((void)LaneKernel::parse("table 1 0"), InvalidArgument);
  EXPECT_THROW((void)LaneKernel::parse("table 0 1 2 -1"), InvalidArgument);
  EXPECT_THROW((void)LaneKernel::parse("ring 1 2"), InvalidArgument);
  EXPECT_THROW((void)LaneKernel::parse("donut 1"), InvalidArgument);
}

TEST(SampleField, DensityIsInverselyProportionalToField) {
  const FieldPtr f = sphere(1.0);
  FieldDensityOptions o;
  o.count = 6000;
  const PointSet ps = sample_field_density(*f, o, 9);
  ASSERT_EQ(ps.size(), 6000U);
  // Expected share of the inner ball (d < 0.5): integral of d^2 / f(d) over [0, 0.5] over the
  // integral over [0, 1] (the field is radially symmetric).
  double inner_w = 0, all_w = 0;
  const int steps = 2000;
  for (int i = 0; i < steps; ++i) {
    const double d = (i + 0.5) / steps;
    const double w = d * d / f->value(Vec3(d, 0, 0));
    all_w += w;
    if (d < 0.5) inner_w += w;
  }
  const double expected = inner_w / all_w;  // about 0.074 (uniform would be 0.125)
  std::size_t inner = 0;
  for (const auto& p : ps.positions) inner += p.norm() < 0.5 ? 1 : 0;
  const double share = double(inner) / 6000.0;
  const double sd = std::sqrt(expected * (1 - expected) / 6000.0);
  EXPECT_NEAR(share, expected, 4 * sd);
  EXPECT_LT(share, 0.125 - 4 * sd);  // denser outside than a uniform set
}

TEST(SampleField, BoundaryLayerHoldsOnlyLayerPoints) {
  const FieldPtr f = fork();
  BoundaryOptions o;
  o.count = 500;
  o.width = 0.1;
  const PointSet ps = sample_boundary(*f, o, 4);
  ASSERT_EQ(ps.size(), 500U);
  for (const double v : values_of(*f, ps.positions)) {
    ASSERT_GT(v, 0.5);
    ASSERT_LT(v, 0.6);
  }
}

TEST(SampleNearSurface, EveryVariantKeepsTheBandExactly) {
  const FieldPtr f = fork();
  struct Variant {
    const char* name;
    bool cache;
    bool lane;
    double min_distance;
    bool prune;
  };
  for (const Variant v : {Variant{"plain", false, false, 0.0, true},
                          Variant{"cache", true, false, 0.0, true},
                          Variant{"lane", false, true, 0.0, true},
                          Variant{"lane+cache", true, true, 0.0, true},
                          Variant{"poisson", false, false, 0.3, true},
                          Variant{"poisson cache", true, false, 0.3, true},
                          Variant{"poisson lane", false, true, 0.3, true},
                          Variant{"unpruned", false, false, 0.0, false},
                          Variant{"unpruned lane", false, true, 0.0, false}}) {
    SCOPED_TRACE(v.name);
    NearSurfaceOptions o;
    o.count = 400;
    o.epsilon = 0.05;
    o.use_cache = v.cache;
    o.use_lane_grid = v.lane;
    o.min_distance = v.min_distance;
    o.prune = v.prune;
    SampleStats st;
    const PointSet ps = sample_near_surface(*f, o, 21, nullptr, &st);
    ASSERT_EQ(ps.size(), 400U);
    for (const double val : values_of(*f, ps.positions)) {
      ASSERT_GT(val, 0.5 - 0.05);
      ASSERT_LT(val, 0.5);
    }
    if (v.min_distance > 0) {
      EXPECT_GE(min_pair_distance(ps.positions), v.min_distance);
    }
  }
}

TEST(SampleNearSurface, CacheKeepsTheBandRoughlyUniform) {
  // With the default slack the cache must not visibly bias the set: compare the share of
  // points near the trunk (z < 8) with and without the cache.
  const FieldPtr f = fork();
  NearSurfaceOptions o;
  o.count = 3000;
  o.epsilon = 0.05;
  const PointSet plain = sample_near_surface(*f, o, 2);
  o.use_cache = true;
  const PointSet cached = sample_near_surface(*f, o, 2);
  const auto share = [](const PointSet& ps) {
    std::size_t n = 0;
    for (const auto& p : ps.positions) n += p.z() < 8 ? 1 : 0;
    return double(n) / double(ps.size());
  };
  EXPECT_NEAR(share(plain), share(cached), 0.05);
}

using Method = NearSurfaceOptions::Method;

void expect_band(const Field& f, const PointSet& ps, double epsilon) {
  const auto v = values_of(f, ps.positions);
  for (std::size_t i = 0; i < v.size(); ++i) {
    ASSERT_GT(v[i], f.iso() - epsilon) << "point " << i;
    ASSERT_LT(v[i], f.iso()) << "point " << i;
  }
}

TEST(SampleNearSurface, ProjectionKeepsBandCountAndMinimumDistance) {
  // A thin band (epsilon 0.005, about 0.005 units on the fork) with automatic and explicit
  // widths of the wider band, plain and Poisson-disk.
  const FieldPtr f = fork();
  for (const double width : {0.0, 0.05, 0.2}) {
    for (const double r : {0.0, 0.25}) {
      SCOPED_TRACE("project_width " + std::to_string(width) + " min_distance " + std::to_string(r));
      NearSurfaceOptions o;
      o.count = 500;
      o.epsilon = 0.005;
      o.project_width = width;
      o.min_distance = r;
      SampleStats st;
      const PointSet ps = sample_near_surface(*f, o, 4, nullptr, &st);
      ASSERT_EQ(ps.size(), 500U);
      EXPECT_EQ(st.points, 500U);
      EXPECT_FALSE(st.saturated);
      expect_band(*f, ps, 0.005);
      if (r > 0) {
        EXPECT_GE(min_pair_distance(ps.positions), r);
      }
    }
  }
}

TEST(SampleNearSurface, ProjectionNeedsFarFewerEvaluationsThanRejection) {
  const FieldPtr f = fork();
  NearSurfaceOptions o;
  o.count = 300;
  o.epsilon = 0.002;
  o.project_width = 0.1;
  SampleStats project, reject;
  const PointSet a = sample_near_surface(*f, o, 3, nullptr, &project);
  o.method = Method::kReject;
  const PointSet b = sample_near_surface(*f, o, 3, nullptr, &reject);
  ASSERT_EQ(a.size(), 300U);
  ASSERT_EQ(b.size(), 300U);
  expect_band(*f, a, 0.002);
  expect_band(*f, b, 0.002);
  // The wider band is 50x thicker: far more of the candidates become band points.
  EXPECT_LT(5 * project.field_evals, reject.field_evals)
      << "project " << project.field_evals << " reject " << reject.field_evals;
  EXPECT_LT(5 * project.attempts, reject.attempts);
}

TEST(SampleNearSurface, ProjectionIsUniformOverTheSphere) {
  // On a sphere, equal-height zones have equal area (Archimedes): points uniform over the
  // surface give equal counts in 10 z slabs and in the 8 octants. The band is compressed 25x.
  const FieldPtr f = sphere(1.0);
  NearSurfaceOptions o;
  o.count = 8000;
  o.epsilon = 0.002;
  o.project_width = 0.05;
  const PointSet ps = sample_near_surface(*f, o, 17);
  ASSERT_EQ(ps.size(), 8000U);
  expect_band(*f, ps, 0.002);
  std::array<double, 8> oct{};
  std::array<double, 10> slab{};
  double rmin = 10, rmax = 0;
  for (const auto& p : ps.positions) {
    oct[(p.x() > 0 ? 1 : 0) + (p.y() > 0 ? 2 : 0) + (p.z() > 0 ? 4 : 0)] += 1;
    const double r = p.norm();
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);
    slab[static_cast<std::size_t>(std::clamp(int((p.z() / r + 1.0) * 5.0), 0, 9))] += 1;
  }
  double chi_oct = 0, chi_slab = 0;
  for (const double c : oct) chi_oct += (c - 1000.0) * (c - 1000.0) / 1000.0;
  for (const double c : slab) chi_slab += (c - 800.0) * (c - 800.0) / 800.0;
  EXPECT_LT(chi_oct, 30.0);   // 7 degrees of freedom: p < 1e-4 beyond 27.9
  EXPECT_LT(chi_slab, 35.0);  // 9 degrees of freedom: p < 1e-4 beyond 33.7
  EXPECT_GT(rmin, 0.99);      // the band around r = 1 is a few thousandths thick
  EXPECT_LT(rmax, 1.01);
}

TEST(SampleNearSurface, ProjectionMatchesRejectionOnTheFork) {
  // The fork's gradient varies along its surface (blends, tips): the share of points near the
  // trunk must match rejection sampling's, which is exactly uniform in the band.
  const FieldPtr f = fork();
  NearSurfaceOptions o;
  o.count = 3000;
  o.epsilon = 0.005;
  o.project_width = 0.1;
  const PointSet project = sample_near_surface(*f, o, 5);
  o.method = Method::kReject;
  const PointSet reject = sample_near_surface(*f, o, 6);
  ASSERT_EQ(project.size(), 3000U);
  ASSERT_EQ(reject.size(), 3000U);
  const auto share = [](const PointSet& ps, double z) {
    std::size_t n = 0;
    for (const auto& p : ps.positions) n += p.z() < z ? 1 : 0;
    return double(n) / double(ps.size());
  };
  for (const double z : {4.0, 8.0, 12.0}) {
    SCOPED_TRACE(z);
    // Two binomial shares of 3000: sd of the difference <= sqrt(2 * 0.25 / 3000) = 0.013.
    EXPECT_NEAR(share(project, z), share(reject, z), 0.05);
  }
}

TEST(SampleNearSurface, ProjectionStaysInTheBoxAndReportsSaturation) {
  const FieldPtr f = sphere(1.0);
  NearSurfaceOptions o;
  o.count = 400;
  o.epsilon = 0.002;
  o.project_width = 0.05;
  o.box = Aabb(Vec3(-2, -2, 0.5), Vec3(2, 2, 2));  // only the polar cap z > 0.5
  const PointSet cap = sample_near_surface(*f, o, 8);
  ASSERT_EQ(cap.size(), 400U);
  expect_band(*f, cap, 0.002);
  for (const auto& p : cap.positions) ASSERT_TRUE(o.box.contains(p));
  // No room for 1000 points 0.5 apart on a unit sphere: saturated within the budget.
  o.box = Aabb();
  o.count = 1000;
  o.min_distance = 0.5;
  o.max_attempts = 40000;
  SampleStats st;
  const PointSet sparse = sample_near_surface(*f, o, 8, nullptr, &st);
  EXPECT_TRUE(st.saturated);
  EXPECT_LT(sparse.size(), 1000U);
  EXPECT_GT(sparse.size(), 10U);
  EXPECT_EQ(st.attempts, 40000U);
  EXPECT_GE(min_pair_distance(sparse.positions), 0.5);
  expect_band(*f, sparse, 0.002);
}

TEST(SampleNearSurface, MethodAndWidthFromProps) {
  const FieldPtr f = fork();
  const Props reject = parse_props("count = 80\nepsilon = 0.01\nmethod = reject\n", "n.props");
  const Props project =
      parse_props("count = 80\nepsilon = 0.01\nmethod = project\nproject_width = 0.1\n", "n.props");
  SampleStats sr, sp;
  const PointSet a = generate_points(*f, "near_surface", reject, 2, 0, nullptr, &sr);
  const PointSet b = generate_points(*f, "near_surface", project, 2, 0, nullptr, &sp);
  ASSERT_EQ(a.size(), 80U);
  ASSERT_EQ(b.size(), 80U);
  expect_band(*f, a, 0.01);
  expect_band(*f, b, 0.01);
  EXPECT_FALSE(same_points(a, b));
  // method = reject is the rejection sampler itself.
  NearSurfaceOptions o;
  o.count = 80;
  o.epsilon = 0.01;
  o.method = Method::kReject;
  EXPECT_TRUE(same_points(a, sample_near_surface(*f, o, 2)));
  const Props bad = parse_props("count = 5\n\nmethod = newton\n", "n.props");
  auto e = input_error([&] { (void)generate_points(*f, "near_surface", bad, 1); });
  EXPECT_EQ(e.line(), 3U);
  EXPECT_NE(std::string(e.what()).find("project or reject"), std::string::npos);
  const Props narrow = parse_props("epsilon = 0.1\nproject_width = 0.05\n", "n.props");
  e = input_error([&] { (void)generate_points(*f, "near_surface", narrow, 1); });
  EXPECT_EQ(e.line(), 2U);
  NearSurfaceOptions w;
  w.project_width = -1;
  try {
    (void)sample_near_surface(*f, w, 1);
    ADD_FAILURE() << "no throw";
  } catch (const InvalidArgument& ex) {
    EXPECT_NE(std::string(ex.what()).find("project_width"), std::string::npos);
  }
}

// ----------------------------------------------------------------------------------------------
// Near meshes.

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Ericson, Real-Time Collision Detection §5.1.5.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return (p - a).norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return (p - b).norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return (p - c).norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  }
  const double denom = 1 / (va + vb + vc);
  return (p - (a + ab * vb * denom + ac * vc * denom)).norm();
}

double mesh_distance(const TriMesh& m, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& t : m.triangles) {
    best = std::min(best, point_triangle_distance(p, m.positions[t[0]], m.positions[t[1]],
                                                  m.positions[t[2]]));
  }
  return best;
}

/// An octahedron subdivided `levels` times and projected on the unit sphere.
TriMesh icosphere(int levels) {
  TriMesh m;
  m.positions = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0),
                 Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.positions.push_back((m.positions[a] + m.positions[b]).normalized());
      const auto id = static_cast<std::uint32_t>(m.positions.size() - 1);
      mid[key] = id;
      return id;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& t : m.triangles) {
      const auto ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  return m;
}

TEST(SampleNearMesh, OffsetsStayWithinLimits) {
  const TriMesh m = icosphere(3);
  NearMeshOptions o;
  o.count = 1000;
  o.min_offset = 0.05;
  o.max_offset = 0.2;
  const PointSet ps = sample_near_mesh(m, o, 8);
  ASSERT_EQ(ps.size(), 1000U);
  ASSERT_TRUE(ps.has_normals());
  // On this convex mesh the interpolated normals stay within a few degrees of the face normals.
  for (const auto& p : ps.positions) {
    const double d = mesh_distance(m, p);
    ASSERT_LE(d, 0.2 + 1e-12);
    ASSERT_GE(d, 0.05 * 0.98);
  }
}

TEST(SampleNearMesh, FlatMeshOffsetsAreExactAndAreaWeighted) {
  // Two triangles in the plane z = 0 with areas 1/2 and 3/2.
  TriMesh m;
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(3, 0, 5), Vec3(0, 1, 5)};
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0),
                 Vec3(10, 0, 0), Vec3(13, 0, 0), Vec3(10, 1, 0)};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  NearMeshOptions o;
  o.count = 4000;
  o.min_offset = -0.1;
  o.max_offset = 0.3;
  const PointSet ps = sample_near_mesh(m, o, 3);
  std::size_t small = 0;
  for (const auto& p : ps.positions) {
    ASSERT_GE(p.z(), -0.1);
    ASSERT_LE(p.z(), 0.3);
    small += p.x() < 5 ? 1 : 0;
  }
  const double sd = std::sqrt(0.25 * 0.75 / 4000.0);
  EXPECT_NEAR(double(small) / 4000.0, 0.25, 4 * sd);
  o.min_offset = 1.0;
  EXPECT_THROW((void)sample_near_mesh(m, o, 3), InvalidArgument);
  m.triangles.push_back({0, 1, 9});
  o.min_offset = 0;
  EXPECT_THROW((void)sample_near_mesh(m, o, 3), InputError);
}

// ----------------------------------------------------------------------------------------------
// Thinning.

TEST(SampleThin, RemovesPercentOfInsidePointsOnly) {
  const FieldPtr crown = sphere(2.0);
  const FieldPtr secondary = sphere(1.0, Vec3(1, 0, 0));
  const PointSet ps = sample_uniform(*crown, {3000, 0}, 12);
  std::size_t inside = 0;
  for (const double v : values_of(*secondary, ps.positions)) inside += v > 0.5 ? 1 : 0;
  ASSERT_GT(inside, 100U);
  const PointSet thin = thin_points(ps, *secondary, 80, 1);
  const auto removed = static_cast<std::size_t>(std::floor(0.8 * double(inside) + 0.5));
  EXPECT_EQ(thin.size(), ps.size() - removed);
  std::size_t inside_after = 0;
  for (const double v : values_of(*secondary, thin.positions)) inside_after += v > 0.5 ? 1 : 0;
  EXPECT_EQ(inside_after, inside - removed);
  // Every outside point survives, in order.
  std::vector<Vec3> outside_before, outside_after;
  const auto vb = values_of(*secondary, ps.positions);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    if (vb[i] <= 0.5) outside_before.push_back(ps.positions[i]);
  }
  const auto va = values_of(*secondary, thin.positions);
  for (std::size_t i = 0; i < thin.size(); ++i) {
    if (va[i] <= 0.5) outside_after.push_back(thin.positions[i]);
  }
  EXPECT_EQ(outside_before, outside_after);
  EXPECT_TRUE(same_points(thin, thin_points(ps, *secondary, 80, 1)));
  EXPECT_FALSE(same_points(thin, thin_points(ps, *secondary, 80, 2)));
  EXPECT_EQ(thin_points(ps, *secondary, 0, 1).size(), ps.size());
  EXPECT_EQ(thin_points(ps, *secondary, 100, 1).size(), ps.size() - inside);
  EXPECT_THROW((void)thin_points(ps, *secondary, 101, 1), InvalidArgument);
}

// ----------------------------------------------------------------------------------------------
// Determinism.

TEST(SampleDeterminism, SameSeedSameThreadsIndependent) {
  const FieldPtr f = fork();
  const std::vector<std::function<PointSet(std::uint64_t, Context*)>> runs = {
      [&](std::uint64_t s, Context* c) { return sample_uniform(*f, {500, 0}, s, c); },
      [&](std::uint64_t s, Context* c) { return sample_stratified(*f, {500}, s, c); },
      [&](std::uint64_t s, Context* c) {
        PoissonOptions o;
        o.count = 500;
        return sample_poisson(*f, o, s, c);
      },
      [&](std::uint64_t s, Context* c) {
        LaneOptions o;
        o.count = 300;
        o.kernel = LaneKernel::disk(0.3);
        return sample_lane(*f, o, s, c);
      },
      [&](std::uint64_t s, Context* c) {
        NearSurfaceOptions o;
        o.count = 300;
        o.use_cache = true;
        o.min_distance = 0.2;
        return sample_near_surface(*f, o, s, c);
      },
      [&](std::uint64_t s, Context* c) {
        NearSurfaceOptions o;
        o.count = 300;
        o.use_lane_grid = true;
        o.use_cache = true;
        return sample_near_surface(*f, o, s, c);
      },
      [&](std::uint64_t s, Context* c) {  // projection (the default), automatic width
        NearSurfaceOptions o;
        o.count = 3000;
        o.epsilon = 0.003;
        return sample_near_surface(*f, o, s, c);
      },
      [&](std::uint64_t s, Context* c) {  // projection, Poisson-disk, several blocks
        NearSurfaceOptions o;
        o.count = 600;
        o.epsilon = 0.003;
        o.project_width = 0.1;
        o.min_distance = 0.2;
        return sample_near_surface(*f, o, s, c);
      },
  };
  for (std::size_t i = 0; i < runs.size(); ++i) {
    SCOPED_TRACE(i);
    Context one(1), two(2);
    const PointSet a = runs[i](5, &one);
    const PointSet b = runs[i](5, &two);
    const PointSet c = runs[i](5, nullptr);
    const PointSet d = runs[i](6, &two);
    EXPECT_TRUE(same_points(a, b));
    EXPECT_TRUE(same_points(a, c));
    EXPECT_FALSE(same_points(a, d));
  }
}

TEST(SampleDeterminism, CancelThrows) {
  const FieldPtr f = sphere(1.0);
  Context ctx;
  ctx.cancel();
  EXPECT_THROW((void)sample_uniform(*f, {100, 0}, 1, &ctx), Cancelled);
}

// ----------------------------------------------------------------------------------------------
// Props and the entry point.

TEST(SampleProps, ParsesKeysValuesAndLines) {
  const Props p = parse_props("# poisson.props\n\ncount = 250\nmin_distance=0.4  # metres\n",
                              "poisson.props");
  EXPECT_EQ(p.source, "poisson.props");
  ASSERT_EQ(p.values.size(), 2U);
  EXPECT_EQ(p.values.at("count"), std::make_pair(std::string("250"), std::size_t{3}));
  EXPECT_EQ(p.values.at("min_distance"), std::make_pair(std::string("0.4"), std::size_t{4}));
}

TEST(SampleProps, SyntaxErrorsNameFileAndLine) {
  auto e = input_error([] { (void)parse_props("count = 1\n\nmin_distance 3\n", "a.props"); });
  EXPECT_EQ(e.file(), "a.props");
  EXPECT_EQ(e.line(), 3U);
  e = input_error([] { (void)parse_props("count = 1\ncount = 2\n", "a.props"); });
  EXPECT_EQ(e.line(), 2U);
  EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos);
  e = input_error([] { (void)parse_props("count =\n", "a.props"); });
  EXPECT_EQ(e.line(), 1U);
  e = input_error([] { (void)parse_props("x y = 3\n", "a.props"); });
  EXPECT_EQ(e.line(), 1U);
  e = input_error([] { (void)read_props("/nonexistent/dir/x.props"); });
  EXPECT_EQ(e.file(), "/nonexistent/dir/x.props");
}

TEST(SampleProps, UnknownAndBadKeysNameLineAndClosestKey) {
  const FieldPtr f = sphere(1.0);
  const Props typo = parse_props("count = 10\n# r\nmin_distanse = 0.1\n", "p.props");
  auto e = input_error([&] { (void)generate_points(*f, "poisson", typo, 1); });
  EXPECT_EQ(e.file(), "p.props");
  EXPECT_EQ(e.line(), 3U);
  EXPECT_NE(std::string(e.what()).find("min_distanse"), std::string::npos);
  EXPECT_NE(std::string(e.what()).find("did you mean 'min_distance'"), std::string::npos);
  // A key of another distribution is unknown here too.
  const Props other = parse_props("epsilon = 0.1\n", "p.props");
  e = input_error([&] { (void)generate_points(*f, "uniform", other, 1); });
  EXPECT_EQ(e.line(), 1U);
  const Props bad = parse_props("count = 10\nmin_distance = abc\n", "p.props");
  e = input_error([&] { (void)generate_points(*f, "poisson", bad, 1); });
  EXPECT_EQ(e.line(), 2U);
  EXPECT_NE(std::string(e.what()).find("min_distance"), std::string::npos);
  const Props negative = parse_props("\nepsilon = -1\n", "p.props");
  e = input_error([&] { (void)generate_points(*f, "near_surface", negative, 1); });
  EXPECT_EQ(e.line(), 2U);
  const Props kernel = parse_props("kernel = ring 1\n", "p.props");
  e = input_error([&] { (void)generate_points(*f, "lane", kernel, 1); });
  EXPECT_EQ(e.line(), 1U);
  const Props flag = parse_props("cache = maybe\n", "p.props");
  e = input_error([&] { (void)generate_points(*f, "near_surface", flag, 1); });
  EXPECT_EQ(e.line(), 1U);
  try {
    (void)generate_points(*f, "poison", Props{}, 1);
    ADD_FAILURE() << "no throw";
  } catch (const InvalidArgument& ex) {
    EXPECT_NE(std::string(ex.what()).find("did you mean 'poisson'"), std::string::npos);
  }
}

TEST(SampleProps, SkipsAByteOrderMarkAndEscapesFileBytesInMessages) {
  // A UTF-8 byte order mark is not part of the first key.
  const std::string bom_bytes = "\xEF\xBB\xBF";
  const Props bom = parse_props(bom_bytes + "count = 5\r\n", "p.props");
  ASSERT_EQ(bom.values.count("count"), 1U);
  EXPECT_EQ(bom.values.at("count"), std::make_pair(std::string("5"), std::size_t{1}));
  auto e = input_error([&] { (void)parse_props(bom_bytes + "count 5\n", "p.props"); });
  EXPECT_STREQ(e.what(), "p.props:1: expected 'key = value', got 'count 5'");
  // Bytes outside printable ASCII are written as \xNN, never copied to the message.
  e = input_error([] { (void)parse_props("cou\x1b[2Jnt = 5\n", "p.props"); });
  EXPECT_STREQ(e.what(), "p.props:1: malformed key 'cou\\x1b[2Jnt'");
  e = input_error([] { (void)parse_props("\x01\xff\n", "p.props"); });
  EXPECT_STREQ(e.what(), "p.props:1: expected 'key = value', got '\\x01\\xff'");
  const FieldPtr f = sphere(1.0);
  const Props bell = parse_props("count = 5\x07\n", "p.props");
  e = input_error([&] { (void)generate_points(*f, "uniform", bell, 1); });
  EXPECT_STREQ(e.what(),
               "p.props:1: count = 5\\x07: expected a non-negative integer (distribution "
               "'uniform')");
  const std::string esc = "\x1b";
  const Props kernel = parse_props("kernel = " + esc + "disk 1\n", "p.props");
  e = input_error([&] { (void)generate_points(*f, "lane", kernel, 1); });
  const std::string what = e.what();
  EXPECT_EQ(what.find('\x1b'), std::string::npos) << what;
  EXPECT_NE(what.find("unknown kernel '\\x1bdisk"), std::string::npos) << what;
  // A long line is shortened.
  e = input_error([] { (void)parse_props(std::string(1000, 'a') + "\n", "p.props"); });
  EXPECT_STREQ(
      e.what(),
      ("p.props:1: expected 'key = value', got '" + std::string(37, 'a') + "...'").c_str());
}

TEST(SampleProps, ACountAboveTheMemoryBudgetNamesItsLine) {
  const FieldPtr f = sphere(1.0);
  Context ctx;
  ctx.set_max_memory(1'000'000);  // 1 MB: 64 bytes a point allows 15625 points
  const Props props = parse_props("# many\ncount = 4000000000000\n", "p.props");
  for (const std::string name : {"uniform", "stratified", "poisson", "near_surface"}) {
    SCOPED_TRACE(name);
    const InputError e = input_error([&] { (void)generate_points(*f, name, props, 1, 0, &ctx); });
    EXPECT_EQ(e.file(), "p.props");
    EXPECT_EQ(e.line(), 2U);
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("p.props:2: count = 4000000000000: sample_" + name +
                             ": 4000000000000 points need at least 256 TB of memory, more than "
                             "the budget of 1 MB",
                         0),
              0U)
        << what;
  }
  // A count from the caller (count_override) is not the file's: the ResourceLimit stays.
  EXPECT_THROW((void)generate_points(*f, "uniform", Props{}, 1, 4'000'000'000'000, &ctx),
               ResourceLimit);
  EXPECT_THROW((void)generate_points(*f, "uniform", props, 1, 4'000'000'000'000, &ctx),
               ResourceLimit);
}

TEST(SampleProps, GeneratePointsRunsEveryDistributionFromAFile) {
  const FieldPtr f = fork();
  const auto dir = test::temp_dir("sample_props");
  const std::string path = (dir / "near.props").string();
  {
    std::ofstream out(path);
    out << "# near the fork\ncount = 50\nepsilon = 0.02\ncache = yes\nmin_distance = 0.1\n";
  }
  const Props props = read_props(path);
  SampleStats st;
  const PointSet ps = generate_points(*f, "near_surface", props, 3, 0, nullptr, &st);
  EXPECT_EQ(ps.size(), 50U);
  EXPECT_EQ(st.points, 50U);
  for (const double v : values_of(*f, ps.positions)) {
    ASSERT_GT(v, 0.48);
    ASSERT_LT(v, 0.5);
  }
  EXPECT_EQ(generate_points(*f, "near_surface", props, 3, 20).size(), 20U);  // override
  for (const auto& name : distribution_names()) {
    SCOPED_TRACE(name);
    const PointSet q = generate_points(*f, name, Props{}, 1, 40);
    EXPECT_EQ(q.size(), 40U);
    EXPECT_FALSE(distribution_keys(name).empty());
  }
  const Props lane = parse_props("count = 60\nkernel = disk 0.4\ngrid = 32\n", "l.props");
  const PointSet l = generate_points(*f, "lane", lane, 1);
  EXPECT_EQ(l.size(), 60U);
  EXPECT_GE(min_pair_distance(l.positions), 0.4);
  std::filesystem::remove_all(dir);
}

TEST(SampleOptions, InvalidOptionsNameTheOption) {
  const FieldPtr f = sphere(1.0);
  const auto message = [](const std::function<void()>& fn) -> std::string {
    try {
      fn();
    } catch (const InvalidArgument& e) {
      return e.what();
    }
    return "";
  };
  PoissonOptions po;
  po.min_distance = -1;
  EXPECT_NE(message([&] { (void)sample_poisson(*f, po, 1); }).find("min_distance"),
            std::string::npos);
  LaneOptions lo;
  lo.grid = 1;
  EXPECT_NE(message([&] { (void)sample_lane(*f, lo, 1); }).find("grid"), std::string::npos);
  NearSurfaceOptions no;
  no.epsilon = 0;
  EXPECT_NE(message([&] { (void)sample_near_surface(*f, no, 1); }).find("epsilon"),
            std::string::npos);
  BoundaryOptions bo;
  bo.interior_density = 2;
  EXPECT_NE(message([&] { (void)sample_boundary(*f, bo, 1); }).find("interior_density"),
            std::string::npos);
  EXPECT_EQ(sample_uniform(*f, {0, 0}, 1).size(), 0U);
}

}  // namespace
}  // namespace ramiform
