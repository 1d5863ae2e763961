// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Small hand-built meshes with known answers, for the mesh/ tests.

#include <cmath>
#include <map>
#include <numbers>
#include <utility>

#include "ramiform/core/geometry.h"

namespace ramiform::test {

/// Unit right tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), CCW from outside; volume 1/6.
inline TriMesh tetrahedron(const Vec3& offset = Vec3::Zero()) {
  TriMesh m;
  m.positions = {offset, offset + Vec3(1, 0, 0), offset + Vec3(0, 1, 0), offset + Vec3(0, 0, 1)};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

/// Unit cube [0,1]^3, two triangles per face, CCW from outside; vertex i at the bits of i.
inline TriMesh unit_cube() {
  TriMesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const Vec3 center(0.5, 0.5, 0.5);
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3;
      const int v = (axis + 2) % 3;
      const std::uint32_t base = static_cast<std::uint32_t>(side << axis);
      std::array<std::uint32_t, 4> q{base, base | (1u << u), base | (1u << u) | (1u << v),
                                     base | (1u << v)};
      const Vec3 n =
          (m.positions[q[1]] - m.positions[q[0]]).cross(m.positions[q[2]] - m.positions[q[0]]);
      if (n.dot(m.positions[q[0]] - center) < 0) std::swap(q[1], q[3]);
      m.triangles.push_back({q[0], q[1], q[2]});
      m.triangles.push_back({q[0], q[2], q[3]});
    }
  }
  return m;
}

/// Icosphere: the icosahedron subdivided `levels` times, projected on the sphere; CCW from
/// outside; 20 * 4^levels triangles.
inline TriMesh icosphere(int levels, double radius = 1.0, const Vec3& center = Vec3::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& q : p) q.normalize();
  std::vector<std::array<std::uint32_t, 3>> f = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((p[a] + p[b]).normalized());
      const auto id = static_cast<std::uint32_t>(p.size() - 1);
      mid.emplace(key, id);
      return id;
    };
    std::vector<std::array<std::uint32_t, 3>> g;
    for (const auto& tri : f) {
      const std::uint32_t a = midpoint(tri[0], tri[1]);
      const std::uint32_t b = midpoint(tri[1], tri[2]);
      const std::uint32_t c = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], a, c});
      g.push_back({tri[1], b, a});
      g.push_back({tri[2], c, b});
      g.push_back({a, b, c});
    }
    f = std::move(g);
  }
  TriMesh m;
  for (const auto& q : p) m.positions.push_back(center + radius * q);
  for (auto tri : f) {
    const Vec3 n = (p[tri[1]] - p[tri[0]]).cross(p[tri[2]] - p[tri[0]]);
    if (n.dot(p[tri[0]]) < 0) std::swap(tri[1], tri[2]);
    m.triangles.push_back(tri);
  }
  return m;
}

/// Torus around the z axis: major radius R, minor radius r, nu x nv quads split in two; CCW
/// from outside.
inline TriMesh torus(double R, double r, int nu, int nv) {
  TriMesh m;
  const double two_pi = 2.0 * std::numbers::pi;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = two_pi * i / nu;
      const double v = two_pi * j / nv;
      m.positions.emplace_back((R + r * std::cos(v)) * std::cos(u),
                               (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      // (u, v) increase: d/du x d/dv points outward from the tube for this parametrization.
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

/// Appends `b` to `a` (indices shifted).
inline TriMesh merged(TriMesh a, const TriMesh& b) {
  const auto off = static_cast<std::uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
  return a;
}

}  // namespace ramiform::test
