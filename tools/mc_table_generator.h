// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Generator of the marching-cubes tables in `src/polygonize/mc_tables.inc`. Header-only so the
/// tool `tools/gen_mc_tables.cpp` and the consistency test share one implementation.
///
/// Conventions (the tables and `marching_cubes.cpp` rely on them):
/// - corner i of a cell sits at offset (i & 1, (i >> 1) & 1, (i >> 2) & 1); bit i of a case
///   index is set when corner i is inside (f > iso);
/// - edge e = 4 * axis + k runs along `axis` (0 = x, 1 = y, 2 = z) from the corner with that
///   axis bit 0 to the corner with it 1; k holds the two other coordinates, lower axis first
///   (axis x: k = y + 2z; axis y: k = x + 2z; axis z: k = x + 2y);
/// - face 2 * axis + side is the cell face at coordinate `side` along `axis`.
///
/// Face rule: on a face whose inside corners are diagonal (the ambiguous face), the two inside
/// corners are treated as connected, i.e. the contour cuts off each outside corner. The rule
/// depends only on the four corner signs of the face, so two cells sharing a face always draw
/// the same contour on it and the result is watertight by construction.
///
/// Each case's polygons are the closed loops of the face contours on the cube's surface, oriented
/// so that they are counter-clockwise seen from outside (the normal points to lower f). Each loop
/// is triangulated by the minimum-weight triangulation (sum of squared diagonal lengths, integer
/// arithmetic) among those whose diagonals never join two vertices on a common cube face (such a
/// diagonal could also be drawn by the neighbouring cell and make an edge non-manifold).

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ramiform::mc_gen {

/// Offset of corner `c` along `axis` (0 or 1).
inline int corner_bit(int c, int axis) { return (c >> axis) & 1; }

/// The two corners joined by edge `e` (from the axis-0 end to the axis-1 end).
inline std::array<int, 2> edge_corners(int e) {
  const int axis = e / 4;
  const int k = e % 4;
  const int u = axis == 0 ? 1 : 0;  // lower other axis
  const int v = axis == 2 ? 1 : 2;  // higher other axis
  const int base = ((k & 1) << u) | (((k >> 1) & 1) << v);
  return {base, base | (1 << axis)};
}

/// The edge joining corners a and b (which must differ in exactly one bit).
inline int edge_between(int a, int b) {
  const int diff = a ^ b;
  const int axis = diff == 1 ? 0 : (diff == 2 ? 1 : 2);
  const int u = axis == 0 ? 1 : 0;
  const int v = axis == 2 ? 1 : 2;
  const int k = corner_bit(a, u) | (corner_bit(a, v) << 1);
  return 4 * axis + k;
}

/// The four corners of face `f` in cyclic order (counter-clockwise seen from outside the cube
/// for side 1, clockwise for side 0; orientation is handled separately).
inline std::array<int, 4> face_corners(int f) {
  const int axis = f / 2;
  const int side = f % 2;
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  const int base = side << axis;
  return {base, base | (1 << u), base | (1 << u) | (1 << v), base | (1 << v)};
}

/// Doubled coordinates of the midpoint of edge e (integers 0..2).
inline std::array<int, 3> edge_midpoint2(int e) {
  const auto [a, b] = edge_corners(e);
  std::array<int, 3> m{};
  for (int d = 0; d < 3; ++d) m[d] = corner_bit(a, d) + corner_bit(b, d);
  return m;
}

/// True when edges a and b lie on a common face of the cube.
inline bool share_face(int a, int b) {
  for (int f = 0; f < 6; ++f) {
    const auto q = face_corners(f);
    bool has_a = false;
    bool has_b = false;
    for (int k = 0; k < 4; ++k) {
      const int e = edge_between(q[k], q[(k + 1) % 4]);
      has_a = has_a || e == a;
      has_b = has_b || e == b;
    }
    if (has_a && has_b) return true;
  }
  return false;
}

/// A directed contour segment on a face: from the crossing on edge `from` to that on `to`.
struct Segment {
  int face = 0;
  int from = 0;
  int to = 0;
};

/// The contour segments of case `c` on face `f`, oriented so that seen from outside the cube the
/// inside corners lie to the right of each segment (then the loops run counter-clockwise around
/// the outward surface normal).
inline std::vector<Segment> face_segments(int c, int f) {
  const auto q = face_corners(f);
  std::array<bool, 4> in{};
  for (int k = 0; k < 4; ++k) in[k] = ((c >> q[k]) & 1) != 0;
  std::vector<int> crossing;  // cyclic positions k: face edge between q[k] and q[k+1]
  for (int k = 0; k < 4; ++k)
    if (in[k] != in[(k + 1) % 4]) crossing.push_back(k);
  // Each unoriented segment comes with one corner it cuts off and whether that corner is inside.
  struct Raw {
    int ka, kb, corner;
    bool corner_inside;
  };
  std::vector<Raw> raw;
  if (crossing.size() == 2) {
    const int k0 = crossing[0];
    // corner q[k0 + 1] lies on the far side of the first crossing edge, cut off with its run.
    raw.push_back({crossing[0], crossing[1], (k0 + 1) % 4, in[(k0 + 1) % 4]});
  } else if (crossing.size() == 4) {
    // Ambiguous face: the inside corners are connected, each outside corner is cut off.
    for (int k = 0; k < 4; ++k) {
      if (in[k]) continue;
      raw.push_back({(k + 3) % 4, k, k, false});
    }
  }
  const int axis = f / 2;
  const int outward = (f % 2) == 1 ? 1 : -1;  // outward normal along `axis`
  std::vector<Segment> out;
  for (const auto& r : raw) {
    const int ea = edge_between(q[r.ka], q[(r.ka + 1) % 4]);
    const int eb = edge_between(q[r.kb], q[(r.kb + 1) % 4]);
    const auto A = edge_midpoint2(ea);
    const auto B = edge_midpoint2(eb);
    std::array<int, 3> Q{};
    for (int d = 0; d < 3; ++d) Q[d] = 2 * corner_bit(q[r.corner], d);
    const std::array<int, 3> t{B[0] - A[0], B[1] - A[1], B[2] - A[2]};
    const std::array<int, 3> w{Q[0] - A[0], Q[1] - A[1], Q[2] - A[2]};
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    // (t x w) . m, with m the outward face normal: > 0 when the corner is to the left.
    const int cross = (t[u] * w[v] - t[v] * w[u]) * outward;
    if (cross == 0) throw std::logic_error("mc_gen: corner on a contour segment");
    const bool corner_left = cross > 0;
    // Inside corners must be on the right, outside corners on the left.
    if (corner_left == r.corner_inside) {
      out.push_back({f, eb, ea});
    } else {
      out.push_back({f, ea, eb});
    }
  }
  return out;
}

/// One marching-cubes case.
struct McCase {
  std::vector<std::vector<int>> loops;        ///< closed polygons (edge ids), CCW from outside
  std::vector<std::array<int, 3>> triangles;  ///< edge ids, CCW from outside
};

/// Minimum-weight triangulation of one loop; see the file comment.
inline std::vector<std::array<int, 3>> triangulate_loop(const std::vector<int>& loop) {
  const int n = static_cast<int>(loop.size());
  if (n < 3) throw std::logic_error("mc_gen: loop with fewer than 3 vertices");
  auto allowed = [&](int i, int j) {                        // i < j
    if (j == i + 1 || (i == 0 && j == n - 1)) return true;  // polygon side
    return !share_face(loop[i], loop[j]);
  };
  auto weight = [&](int i, int j) -> long long {
    if (j == i + 1 || (i == 0 && j == n - 1)) return 0;
    const auto a = edge_midpoint2(loop[i]);
    const auto b = edge_midpoint2(loop[j]);
    long long s = 0;
    for (int d = 0; d < 3; ++d) s += static_cast<long long>(a[d] - b[d]) * (a[d] - b[d]);
    return s;
  };
  constexpr long long kInf = std::numeric_limits<long long>::max() / 4;
  std::vector<std::vector<long long>> cost(n, std::vector<long long>(n, kInf));
  std::vector<std::vector<int>> split(n, std::vector<int>(n, -1));
  for (int i = 0; i + 1 < n; ++i) cost[i][i + 1] = 0;
  for (int len = 2; len < n; ++len) {
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      if (!allowed(i, j)) continue;
      for (int k = i + 1; k < j; ++k) {
        if (cost[i][k] >= kInf || cost[k][j] >= kInf) continue;
        const long long c = cost[i][k] + cost[k][j] + weight(i, k) + weight(k, j);
        if (c < cost[i][j]) {
          cost[i][j] = c;
          split[i][j] = k;
        }
      }
    }
  }
  if (cost[0][n - 1] >= kInf) throw std::logic_error("mc_gen: loop has no valid triangulation");
  std::vector<std::array<int, 3>> tris;
  std::vector<std::array<int, 2>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2) continue;
    const int k = split[i][j];
    tris.push_back({loop[i], loop[k], loop[j]});
    stack.push_back({k, j});
    stack.push_back({i, k});
  }
  return tris;
}

/// Builds case `c`.
inline McCase generate_case(int c) {
  std::array<int, 12> next{};
  next.fill(-1);
  std::array<int, 12> prev_count{};
  for (int f = 0; f < 6; ++f) {
    for (const auto& s : face_segments(c, f)) {
      if (next[s.from] != -1) throw std::logic_error("mc_gen: edge starts two segments");
      next[s.from] = s.to;
      ++prev_count[s.to];
    }
  }
  McCase out;
  std::array<bool, 12> used{};
  for (int e = 0; e < 12; ++e) {
    if (next[e] == -1) {
      if (prev_count[e] != 0) throw std::logic_error("mc_gen: edge ends a segment only");
      continue;
    }
    if (prev_count[e] != 1) throw std::logic_error("mc_gen: edge does not end exactly one segment");
    if (used[e]) continue;
    std::vector<int> loop;
    int x = e;
    while (!used[x]) {
      used[x] = true;
      loop.push_back(x);
      x = next[x];
    }
    if (x != e) throw std::logic_error("mc_gen: contour does not close");
    out.loops.push_back(loop);
    for (const auto& t : triangulate_loop(loop)) out.triangles.push_back(t);
  }
  return out;
}

/// All 256 cases.
inline std::array<McCase, 256> generate_mc_tables() {
  std::array<McCase, 256> cases;
  for (int c = 0; c < 256; ++c) cases[c] = generate_case(c);
  return cases;
}

/// The text of `src/polygonize/mc_tables.inc` for `cases`.
inline std::string format_mc_tables(const std::array<McCase, 256>& cases) {
  std::size_t max_tris = 0;
  for (const auto& c : cases) max_tris = std::max(max_tris, c.triangles.size());
  std::ostringstream s;
  s << "// generated by tools/gen_mc_tables.cpp \u2014 do not edit\n"
       "// Marching-cubes tables; conventions in tools/mc_table_generator.h. Corner i of a cell\n"
       "// sits at (i & 1, (i >> 1) & 1, (i >> 2) & 1); bit i of a case is set when corner i is\n"
       "// inside. Ambiguous faces connect their inside corners. Triangles list edge ids,\n"
       "// counter-clockwise seen from outside (the normal points to lower f).\n\n";
  s << "inline constexpr int kMcMaxTriangles = " << max_tris << ";\n\n";
  s << "/// The two corners of each edge, from the low end to the high end along its axis.\n";
  s << "inline constexpr std::uint8_t kMcEdgeCorners[12][2] = {";
  for (int e = 0; e < 12; ++e) {
    const auto ec = edge_corners(e);
    s << (e == 0 ? "" : ", ") << "{" << ec[0] << ", " << ec[1] << "}";
  }
  s << "};\n\n";
  s << "/// Number of triangles of each case.\n";
  s << "inline constexpr std::uint8_t kMcTriangleCount[256] = {";
  for (int c = 0; c < 256; ++c) {
    s << (c % 16 == 0 ? "\n    " : " ") << cases[c].triangles.size() << (c == 255 ? "" : ",");
  }
  s << "};\n\n";
  s << "/// Edge ids of each case's triangles, three per triangle, -1 padded.\n";
  s << "inline constexpr std::int8_t kMcTriangles[256][" << 3 * max_tris << "] = {\n";
  for (int c = 0; c < 256; ++c) {
    s << "    {";
    std::size_t k = 0;
    for (const auto& t : cases[c].triangles) {
      for (int v : t) s << (k++ == 0 ? "" : ", ") << v;
    }
    for (; k < 3 * max_tris; ++k) s << (k == 0 ? "" : ", ") << -1;
    s << "},  // " << c << "\n";
  }
  s << "};\n";
  return s.str();
}

}  // namespace ramiform::mc_gen
