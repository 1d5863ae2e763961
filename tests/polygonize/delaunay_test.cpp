// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors

// The exact predicates against 128-bit integer determinants (exact for the small integer
// coordinates used), including configurations the floating-point filter cannot decide; and the
// Delaunay tetrahedralization: conforming (every interior face shared by two tetrahedra on
// opposite sides), positively oriented, empty circumspheres checked by brute force, volumes
// adding up to the convex hull's, duplicates dropped.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <vector>

#include "polygonize/delaunay.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"

namespace ramiform::detail {
namespace {

__extension__ using I128 = __int128;  // exact for the determinants of 20-bit coordinates
using IVec = std::array<std::int64_t, 3>;

I128 det3_int(const std::array<I128, 3>& u, const std::array<I128, 3>& v,
              const std::array<I128, 3>& w) {
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

std::array<I128, 3> sub(const IVec& a, const IVec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

int sign128(I128 x) { return (x > 0) - (x < 0); }

int orient_int(const IVec& a, const IVec& b, const IVec& c, const IVec& d) {
  return sign128(det3_int(sub(b, a), sub(c, a), sub(d, a)));
}

// Independent in-sphere sign: the power of e against the sphere, from the 4x4 system solved by
// Cramer's rule in integers. Sign of |e - o|^2 - r^2 equals -sign(det of rows (p - e, |p - e|^2))
// times the orientation; here computed directly as the 4x4 determinant by Laplace expansion.
int insphere_int(const IVec& a, const IVec& b, const IVec& c, const IVec& d, const IVec& e) {
  std::array<std::array<I128, 4>, 4> m{};
  const std::array<const IVec*, 4> p{&a, &b, &c, &d};
  for (int i = 0; i < 4; ++i) {
    const auto r = sub(*p[i], e);
    m[i] = {r[0], r[1], r[2], r[0] * r[0] + r[1] * r[1] + r[2] * r[2]};
  }
  I128 det = 0;
  for (int col = 0; col < 4; ++col) {  // expansion along the first row
    std::array<std::array<I128, 3>, 3> minor{};
    for (int i = 1; i < 4; ++i) {
      int w = 0;
      for (int j = 0; j < 4; ++j) {
        if (j != col) minor[i - 1][w++] = m[i][j];
      }
    }
    const I128 sub_det = det3_int(minor[0], minor[1], minor[2]);
    det += (col % 2 == 0 ? 1 : -1) * m[0][col] * sub_det;
  }
  // For a positively oriented (a, b, c, d) the determinant is negative inside the sphere.
  return -sign128(det) * orient_int(a, b, c, d);
}

Vec3 to_vec(const IVec& v) {
  return {static_cast<double>(v[0]), static_cast<double>(v[1]), static_cast<double>(v[2])};
}

TEST(Predicates, UnitTetrahedronSigns) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  EXPECT_EQ(orient3d(a, b, c, d), 1);
  EXPECT_EQ(orient3d(a, c, b, d), -1);
  EXPECT_EQ(orient3d(a, b, c, Vec3(0.3, 0.2, 0)), 0);
  // Circumsphere: centre (1/2, 1/2, 1/2), radius^2 3/4.
  EXPECT_EQ(insphere(a, b, c, d, Vec3(0.25, 0.25, 0.25)), 1);
  EXPECT_EQ(insphere(a, b, c, d, Vec3(2, 2, 2)), -1);
  EXPECT_EQ(insphere(a, b, c, d, Vec3(1, 1, 0)), 0);
  EXPECT_EQ(insphere(a, b, c, d, Vec3(1, 1, 1)), 0);
}

// Coplanar and nearly coplanar points with large integer coordinates: the rounded determinant
// is pure noise there, so these exercise the exact path.
TEST(Predicates, OrientMatchesIntegerArithmetic) {
  Rng rng(11);
  const std::uint64_t exact_before = exact_predicate_calls();
  auto ri = [&](double lo, double hi) {
    return static_cast<std::int64_t>(std::floor(rng.uniform(lo, hi)));
  };
  for (int trial = 0; trial < 2000; ++trial) {
    const IVec a{ri(0, 1 << 20), ri(0, 1 << 20), ri(0, 1 << 20)};
    const IVec u{ri(-(1 << 20), 1 << 20), ri(-(1 << 20), 1 << 20), ri(-(1 << 20), 1 << 20)};
    const IVec v{ri(-(1 << 20), 1 << 20), ri(-(1 << 20), 1 << 20), ri(-(1 << 20), 1 << 20)};
    const std::int64_t k = ri(-64, 64), m = ri(-64, 64);
    const IVec b{a[0] + u[0], a[1] + u[1], a[2] + u[2]};
    const IVec c{a[0] + v[0], a[1] + v[1], a[2] + v[2]};
    IVec d{a[0] + k * u[0] + m * v[0], a[1] + k * u[1] + m * v[1], a[2] + k * u[2] + m * v[2]};
    d[trial % 3] += trial % 5 - 2;  // on the plane, or one unit off it
    ASSERT_EQ(orient3d(to_vec(a), to_vec(b), to_vec(c), to_vec(d)), orient_int(a, b, c, d))
        << trial;
  }
  EXPECT_GT(exact_predicate_calls(), exact_before);
}

// Points on the sphere x^2 + y^2 + z^2 = 81 (integer solutions), shifted far from the origin,
// plus points one unit in or out: exactly cospherical sets must give 0.
TEST(Predicates, InsphereMatchesIntegerArithmetic) {
  std::vector<IVec> on;
  for (int x = -9; x <= 9; ++x) {
    for (int y = -9; y <= 9; ++y) {
      for (int z = -9; z <= 9; ++z) {
        if (x * x + y * y + z * z == 81) on.push_back({x, y, z});
      }
    }
  }
  ASSERT_GT(on.size(), 20U);
  Rng rng(5);
  const IVec shift{123457, -98765, 31415};
  auto moved = [&](IVec p) {
    for (int k = 0; k < 3; ++k) p[k] += shift[k];
    return p;
  };
  int zeros = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::array<IVec, 5> p;
    for (auto& q : p)
      q = moved(on[static_cast<std::size_t>(rng.uniform(0, static_cast<double>(on.size())))]);
    p[4][trial % 3] += trial % 3 - 1;
    if (orient_int(p[0], p[1], p[2], p[3]) == 0) continue;
    if (orient_int(p[0], p[1], p[2], p[3]) < 0) std::swap(p[0], p[1]);
    const int expected = insphere_int(p[0], p[1], p[2], p[3], p[4]);
    zeros += expected == 0 ? 1 : 0;
    ASSERT_EQ(insphere(to_vec(p[0]), to_vec(p[1]), to_vec(p[2]), to_vec(p[3]), to_vec(p[4])),
              expected)
        << trial;
  }
  EXPECT_GT(zeros, 100);
}

double volume(const std::vector<Vec3>& p, const std::array<std::uint32_t, 4>& t) {
  return (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).dot(p[t[3]] - p[t[0]]) / 6.0;
}

std::array<std::uint32_t, 3> face_of(const std::array<std::uint32_t, 4>& t, int k) {
  std::array<std::uint32_t, 3> f{};
  int m = 0;
  for (int j = 0; j < 4; ++j) {
    if (j != k) f[m++] = t[j];
  }
  return f;
}

// Conforming, non-degenerate, empty spheres, neighbours consistent with shared faces; returns
// the total volume.
double check_delaunay(const std::vector<Vec3>& p, const DelaunayResult& d,
                      bool brute_force_spheres) {
  const auto& tets = d.tets;
  EXPECT_EQ(d.neighbors.size(), 4 * tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t nb = d.neighbors[4 * t + k];
      if (nb == UINT32_MAX) continue;
      const auto f = face_of(tets[t], k);
      int back = -1;
      for (int j = 0; j < 4; ++j) {
        if (face_of(tets[nb], j) == f) back = j;
      }
      EXPECT_GE(back, 0) << "tetrahedron " << t << " face " << k;
      if (back >= 0) {
        EXPECT_EQ(d.neighbors[4 * nb + static_cast<std::size_t>(back)], t);
      }
    }
  }
  std::map<std::array<std::uint32_t, 3>, std::vector<std::uint32_t>>
      faces;  // face -> opposite corners
  double total = 0;
  for (const auto& t : tets) {
    EXPECT_TRUE(std::is_sorted(t.begin(), t.end()));
    EXPECT_NE(orient3d(p[t[0]], p[t[1]], p[t[2]], p[t[3]]), 0);
    total += std::abs(volume(p, t));
    for (int k = 0; k < 4; ++k) faces[face_of(t, k)].push_back(t[k]);
  }
  std::size_t boundary = 0;
  for (const auto& [f, opposite] : faces) {
    EXPECT_LE(opposite.size(), 2U);
    boundary += opposite.size() == 1 ? 1 : 0;
    if (opposite.size() == 2) {  // the two opposite corners lie on opposite sides of the face
      EXPECT_EQ(orient3d(p[f[0]], p[f[1]], p[f[2]], p[opposite[0]]),
                -orient3d(p[f[0]], p[f[1]], p[f[2]], p[opposite[1]]));
    }
  }
  EXPECT_EQ(
      static_cast<std::size_t>(std::count(d.neighbors.begin(), d.neighbors.end(), UINT32_MAX)),
      boundary);
  if (brute_force_spheres) {
    for (auto t : tets) {
      if (orient3d(p[t[0]], p[t[1]], p[t[2]], p[t[3]]) < 0) std::swap(t[0], t[1]);
      for (std::size_t i = 0; i < p.size(); ++i) {
        EXPECT_LE(insphere(p[t[0]], p[t[1]], p[t[2]], p[t[3]], p[i]), 0) << "point " << i;
      }
    }
  }
  return total;
}

TEST(Delaunay, RandomPointsInACube) {
  Rng rng(3);
  std::vector<Vec3> p;
  for (int c = 0; c < 8; ++c) p.emplace_back((c & 1) ? 1 : 0, (c & 2) ? 1 : 0, (c & 4) ? 1 : 0);
  for (int i = 0; i < 600; ++i)
    p.emplace_back(rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95));
  const DelaunayResult d = delaunay_tetrahedralize(p);
  EXPECT_EQ(d.duplicate_points, 0U);
  EXPECT_GT(d.tets.size(), 5 * p.size());
  const double v = check_delaunay(p, d, true);
  EXPECT_NEAR(v, 1.0, 1e-9);  // the cube's corners make the hull the cube; no hull tetrahedron lost
  // Every point is a corner of some tetrahedron.
  std::vector<char> used(p.size(), 0);
  for (const auto& t : d.tets) {
    for (const auto i : t) used[i] = 1;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), 1), static_cast<long>(p.size()));
}

// A jittered grid: nearly cospherical everywhere, the bounding sets of the polygonizer look
// like this (squares of four points along a skeleton, jittered by 1e-3 of their size).
TEST(Delaunay, JitteredGridIsConforming) {
  Rng rng(9);
  std::vector<Vec3> p;
  for (int x = 0; x < 7; ++x) {
    for (int y = 0; y < 7; ++y) {
      for (int z = 0; z < 7; ++z) {
        p.emplace_back(x + 1e-9 * rng.uniform(-1, 1), y + 1e-9 * rng.uniform(-1, 1),
                       z + 1e-9 * rng.uniform(-1, 1));
      }
    }
  }
  const DelaunayResult d = delaunay_tetrahedralize(p);
  const double v = check_delaunay(p, d, true);
  EXPECT_NEAR(v, 216.0, 1e-3);
}

TEST(Delaunay, DuplicatesAreDroppedAndTinyInputsAreEmpty) {
  std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {0.2, 0.2, 0.2}};
  const DelaunayResult d = delaunay_tetrahedralize(p);
  EXPECT_EQ(d.duplicate_points, 1U);
  EXPECT_EQ(d.tets.size(), 4U);  // the centroid-side point splits the tetrahedron in four
  EXPECT_NEAR(check_delaunay(p, d, true), 1.0 / 6.0, 1e-12);
  EXPECT_TRUE(delaunay_tetrahedralize({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).tets.empty());
}

bool has_edge(const DelaunayResult& d, std::uint32_t a, std::uint32_t b) {
  return std::any_of(d.tets.begin(), d.tets.end(), [&](const auto& t) {
    return std::count(t.begin(), t.end(), a) == 1 && std::count(t.begin(), t.end(), b) == 1;
  });
}

// A segment threaded through a ring of points close around its middle is not a Delaunay edge
// (its diametral sphere holds the ring); required, it is split at midpoints until every piece
// is an edge of the Delaunay tetrahedralization of the points plus the Steiner points.
TEST(Delaunay, RequiredEdgesAreRecoveredWithSteinerPointsOnThem) {
  Rng rng(5);
  std::vector<Vec3> p;
  for (int c = 0; c < 8; ++c) p.emplace_back((c & 1) ? 1 : 0, (c & 2) ? 1 : 0, (c & 4) ? 1 : 0);
  const Vec3 a(0.1, 0.5, 0.5), b(0.9, 0.52, 0.49);
  p.push_back(a);  // 8
  p.push_back(b);  // 9
  for (int k = 0; k < 8; ++k) {  // the ring, radius 0.05 around the segment's middle
    const double phi = 2 * std::numbers::pi * (k + rng.uniform(-0.1, 0.1)) / 8;
    p.emplace_back(0.5 + rng.uniform(-0.01, 0.01), 0.51 + 0.05 * std::cos(phi),
                   0.495 + 0.05 * std::sin(phi));
  }
  for (int i = 0; i < 150; ++i)
    p.emplace_back(rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95));
  const DelaunayResult plain = delaunay_tetrahedralize(p);
  ASSERT_FALSE(has_edge(plain, 8, 9));
  EXPECT_TRUE(plain.steiner_points.empty());

  const DelaunayResult d = delaunay_tetrahedralize(p, {{8, 9}, {0, 7}});
  EXPECT_EQ(d.missing_edges, 0U);
  ASSERT_FALSE(d.steiner_points.empty());
  std::vector<Vec3> all = p;
  all.insert(all.end(), d.steiner_points.begin(), d.steiner_points.end());
  // Every Steiner point lies on a-b (or on the cube's diagonal 0-7); the pieces between
  // consecutive points along each segment are edges.
  for (const auto& [from, to] : {std::pair{8U, 9U}, std::pair{0U, 7U}}) {
    const Vec3 u = all[to] - all[from];
    std::vector<std::pair<double, std::uint32_t>> along{{0.0, from}, {1.0, to}};
    for (std::uint32_t i = p.size(); i < all.size(); ++i) {
      const double t = (all[i] - all[from]).dot(u) / u.squaredNorm();
      if ((all[i] - all[from] - t * u).norm() < 1e-12) along.emplace_back(t, i);
    }
    std::sort(along.begin(), along.end());
    for (std::size_t k = 0; k + 1 < along.size(); ++k) {
      EXPECT_TRUE(has_edge(d, along[k].second, along[k + 1].second))
          << "piece " << k << " of " << from << "-" << to;
    }
    if (from == 8) {
      EXPECT_GT(along.size(), 2U);
    }
  }
  EXPECT_NEAR(check_delaunay(all, d, true), 1.0, 1e-9);
  EXPECT_THROW((void)delaunay_tetrahedralize(p, {{8, static_cast<std::uint32_t>(p.size())}}),
               InvalidArgument);
}

}  // namespace
}  // namespace ramiform::detail
