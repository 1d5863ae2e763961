// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the lattice of the tetrahedral polygonizer's 1:8 subdivision (steps 3 and 4 of
// tetrahedral.h; Zhu, Guo & Jin 2013, "Efficient polygonization of tree trunks modeled by
// convolution surfaces", §3.2.2, Figure 4, and §4.1): the points of every region tetrahedron
// subdivided `levels` times, in integer barycentric coordinates, each distinct point positioned
// and evaluated once.

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "polygonize/tetrahedral_types.h"
#include "ramiform/core/context.h"
#include "ramiform/field/field.h"

namespace ramiform::detail::tets {

/// A lattice point in integer barycentric coordinates over its region tetrahedron's corners
/// (which are sorted by point id), summing to 2^levels. Midpoints stay integer.
using Bary = std::array<std::uint8_t, 4>;
/// A leaf tetrahedron of the subdivision: four lattice points.
using BaryTet = std::array<Bary, 4>;

/// The midpoint of two lattice points whose coordinates differ by even numbers.
[[nodiscard]] inline Bary midpoint(const Bary& a, const Bary& b) {
  return {
      static_cast<std::uint8_t>((a[0] + b[0]) / 2), static_cast<std::uint8_t>((a[1] + b[1]) / 2),
      static_cast<std::uint8_t>((a[2] + b[2]) / 2), static_cast<std::uint8_t>((a[3] + b[3]) / 2)};
}

/// The position of a lattice point, (sum_k w_k c_k) * inv_m with inv_m = 1 / 2^levels, summed in
/// corner order. A point on a face or edge shared with another region tetrahedron has zero
/// weights on the other corners, which add exact zeros: both tetrahedra compute bit-identical
/// positions, so their crossing edges match by key and the mesh stays watertight.
[[nodiscard]] inline Vec3 lattice_point(const TetPoints& c, const Bary& w, double inv_m) {
  double x = 0, y = 0, z = 0;
  for (int k = 0; k < 4; ++k) {
    const double wk = w[k];
    x += wk * c[k].x();
    y += wk * c[k].y();
    z += wk * c[k].z();
  }
  return {x * inv_m, y * inv_m, z * inv_m};
}

/// Every distinct lattice point of the extracted region tetrahedra, with its position and field
/// value, evaluated once. Neighbouring region tetrahedra share the lattice points on their
/// common corners, edges and faces: at level 1 all 10 points of a tetrahedron lie on its
/// boundary, at level 2 all but 1 of 35, and a corner is shared by some twenty tetrahedra (on
/// the 1,500-segment benchmark tree at level 1: 303 k evaluations instead of 1.58 M). A point
/// has one global id for the whole run, laid out per round as [new corners | new edge points |
/// new face points | inner points], and is addressed through its region tetrahedron's slot
/// (rounds of hole closing append slots) and barycentric coordinates. Every position comes from
/// lattice_point() on the corners of the first tetrahedron that holds the point, which is
/// bit-identical to what the others would compute.
///
/// Holds references to `tz`, which must outlive it.
class Lattice {
 public:
  Lattice(const Tetrahedralization& tz, int levels);

  /// Adds the tetrahedra `list` (indices into tz.tets; live[r] == 1: extracted, others only
  /// take a slot) as slots [slots(), slots() + list.size()), then positions their new lattice
  /// points and evaluates `field` there in one batch on `ctx`'s threads.
  void add_round(const Field& field, const std::vector<std::uint32_t>& list,
                 const std::vector<char>& live, const Context* ctx);

  /// The global id of the lattice point w of the tetrahedron t (extracted) in slot `slot`.
  [[nodiscard]] std::uint32_t id(std::size_t slot, const Tet& t, const Bary& w) const {
    const int nonzero = (w[0] != 0) + (w[1] != 0) + (w[2] != 0) + (w[3] != 0);
    if (nonzero == 1) {
      int k = 0;
      while (w[k] == 0) ++k;
      return vertex_[t[k]];
    }
    if (nonzero == 2) {
      const int e =
          edge_of_[(w[0] != 0) | (w[1] != 0) << 1U | (w[2] != 0) << 2U | (w[3] != 0) << 3U];
      return tet_edge_[6 * slot + e] + (w[kEdgeCorners[e][1]] - 1);
    }
    if (nonzero == 3) {
      int k = 0;
      while (w[k] != 0) ++k;
      const auto& c = kFaceCorners[k];
      return tet_face_[4 * slot + k] + face_rank_[w[c[1]] * side_ + w[c[2]]];
    }
    return inner_first_[slot] + inner_rank_[(w[1] * side_ + w[2]) * side_ + w[3]];
  }

  /// Whether every lattice point of the tetrahedron t in slot `slot` lies on one side of the
  /// iso value (`inside` says which): then no leaf of it holds a piece of the surface.
  [[nodiscard]] bool one_sided(std::size_t slot, const Tet& t, double iso, bool& inside) const {
    inside = values_[id(slot, t, all_bary_[0])] > iso;
    for (const Bary& w : all_bary_) {
      if ((values_[id(slot, t, w)] > iso) != inside) return false;
    }
    return true;
  }

  [[nodiscard]] const Vec3& position(std::uint32_t id) const { return positions_[id]; }
  [[nodiscard]] double value(std::uint32_t id) const { return values_[id]; }
  [[nodiscard]] std::size_t slots() const { return slot_tet_.size(); }
  /// How many lattice points there are (global ids are below this).
  [[nodiscard]] std::size_t size() const { return values_.size(); }
  /// How many lattice points were evaluated (each once).
  [[nodiscard]] std::size_t evaluated() const { return evaluated_; }

 private:
  struct EdgeRef {
    std::uint64_t key;  // corner point ids, lower first
    std::uint32_t ref;  // 6 * slot + local edge, or the pair's first point id
    bool operator<(const EdgeRef& o) const { return key < o.key || (key == o.key && ref < o.ref); }
  };
  // The live slots [first, end) of one round.
  struct Round {
    std::uint32_t first = 0, end = 0;
    const std::vector<char>* live = nullptr;
    [[nodiscard]] bool is_live(std::uint32_t slot) const { return (*live)[slot - first] == 1; }
  };

  static constexpr std::array<std::array<int, 2>, 6> kEdgeCorners{
      {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};
  static constexpr std::array<std::array<int, 3>, 4> kFaceCorners{
      {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}}};

  void build_tables();
  void build_face_tables();
  void build_tetrahedron_tables();
  Round add_slots(const std::vector<std::uint32_t>& list, const std::vector<char>& live);
  void add_corner_points(const Round& round);
  void add_edge_points(const Round& round, const Context* ctx);
  [[nodiscard]] std::vector<EdgeRef> sorted_edges(const std::vector<EdgeRef>& raw,
                                                  const Context* ctx) const;
  void add_face_points(const Round& round);
  void add_inner_points(const Round& round);
  void evaluate_from(const Field& field, std::size_t first_point, const Context* ctx);

  const std::vector<Vec3>& pts_;
  const std::vector<Tet>& tets_;
  const std::vector<std::uint32_t>& neighbor_;
  int m_;
  std::size_t side_;
  std::array<int, 16> edge_of_{};
  std::array<std::vector<Bary>, 4> face_bary_;
  std::vector<std::uint32_t> face_rank_, inner_rank_;
  std::vector<Bary> inner_bary_;
  std::vector<Bary> all_bary_;           // every lattice point of a tetrahedron
  std::vector<std::uint32_t> vertex_;    // per point id, its corner's global id
  std::vector<std::uint32_t> slot_of_;   // per tetrahedron, its slot if extracted
  std::vector<std::uint32_t> slot_tet_;  // per slot, its tetrahedron
  std::vector<std::uint32_t> tet_edge_;  // per slot and local edge, the edge's first point id
  std::vector<std::uint32_t> tet_face_;  // per slot and face, the face's first point id
  std::vector<std::uint32_t> inner_first_;
  std::vector<EdgeRef> edge_points_;  // every corner pair so far, sorted, with its first id
  std::vector<std::pair<std::uint32_t, Bary>> refs_;  // per point, (slot, barycentric)
  std::vector<Vec3> positions_;
  std::vector<double> values_;
  std::size_t evaluated_ = 0;
};

}  // namespace ramiform::detail::tets
