// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/tetrahedral_lattice.h"

#include <algorithm>
#include <span>

#include "core/bucket_order.h"
#include "ramiform/core/parallel.h"

namespace ramiform::detail::tets {

Lattice::Lattice(const Tetrahedralization& tz, int levels)
    : pts_(tz.points),
      tets_(tz.tets),
      neighbor_(tz.neighbors),
      m_(1 << levels),
      side_(static_cast<std::size_t>(m_) + 1),
      vertex_(tz.points.size(), kNone),
      slot_of_(tz.tets.size(), kNone) {
  build_tables();
}

void Lattice::add_round(const Field& field, const std::vector<std::uint32_t>& list,
                        const std::vector<char>& live, const Context* ctx) {
  const std::size_t first_point = refs_.size();
  const Round round = add_slots(list, live);
  add_corner_points(round);
  add_edge_points(round, ctx);
  add_face_points(round);
  add_inner_points(round);
  evaluate_from(field, first_point, ctx);
}

Lattice::Round Lattice::add_slots(const std::vector<std::uint32_t>& list,
                                  const std::vector<char>& live) {
  Round round;
  round.first = static_cast<std::uint32_t>(slot_tet_.size());
  round.live = &live;
  for (std::size_t r = 0; r < list.size(); ++r) {
    slot_tet_.push_back(list[r]);
    if (live[r] == 1) slot_of_[list[r]] = round.first + static_cast<std::uint32_t>(r);
  }
  round.end = static_cast<std::uint32_t>(slot_tet_.size());
  tet_edge_.resize(6 * static_cast<std::size_t>(round.end), kNone);
  tet_face_.resize(4 * static_cast<std::size_t>(round.end), kNone);
  inner_first_.resize(round.end, kNone);
  return round;
}

// Corners, by point id.
void Lattice::add_corner_points(const Round& round) {
  for (std::uint32_t slot = round.first; slot < round.end; ++slot) {
    if (!round.is_live(slot)) continue;
    const Tet& t = tets_[slot_tet_[slot]];
    for (int k = 0; k < 4; ++k) {
      if (vertex_[t[k]] != kNone) continue;
      vertex_[t[k]] = static_cast<std::uint32_t>(refs_.size());
      Bary w{};
      w[k] = static_cast<std::uint8_t>(m_);
      refs_.emplace_back(slot, w);
    }
  }
}

// The new slots' corner pairs, sorted; equal pairs share their points, and a pair seen in an
// earlier round keeps the points it got there. At level 0 edges hold no points (their sort was
// a tenth of a level-0 run).
void Lattice::add_edge_points(const Round& round, const Context* ctx) {
  std::vector<EdgeRef> raw;
  for (std::uint32_t slot = round.first; m_ > 1 && slot < round.end; ++slot) {
    if (!round.is_live(slot)) continue;
    const Tet& t = tets_[slot_tet_[slot]];
    for (int e = 0; e < 6; ++e) {
      const std::uint64_t key =
          (std::uint64_t{t[kEdgeCorners[e][0]]} << 32U) | t[kEdgeCorners[e][1]];
      raw.push_back({key, 6 * slot + static_cast<std::uint32_t>(e)});
    }
  }
  const std::vector<EdgeRef> edges = sorted_edges(raw, ctx);
  std::vector<EdgeRef> known;  // (pair, first point id) of the new distinct pairs
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (i > 0 && edges[i].key == edges[i - 1].key) {
      tet_edge_[edges[i].ref] = tet_edge_[edges[i - 1].ref];
      continue;
    }
    const auto old =
        std::lower_bound(edge_points_.begin(), edge_points_.end(), EdgeRef{edges[i].key, 0});
    if (old != edge_points_.end() && old->key == edges[i].key) {
      tet_edge_[edges[i].ref] = old->ref;
      continue;
    }
    tet_edge_[edges[i].ref] = static_cast<std::uint32_t>(refs_.size());
    known.push_back({edges[i].key, static_cast<std::uint32_t>(refs_.size())});
    const std::uint32_t slot = edges[i].ref / 6;
    const auto& c = kEdgeCorners[edges[i].ref % 6];
    for (int j = 1; j < m_; ++j) {
      Bary w{};
      w[c[0]] = static_cast<std::uint8_t>(m_ - j);
      w[c[1]] = static_cast<std::uint8_t>(j);
      refs_.emplace_back(slot, w);
    }
  }
  if (!known.empty()) {
    const auto middle = static_cast<std::ptrdiff_t>(edge_points_.size());
    edge_points_.insert(edge_points_.end(), known.begin(), known.end());
    std::inplace_merge(edge_points_.begin(), edge_points_.begin() + middle, edge_points_.end());
  }
}

// `raw` in ascending order, bucketed by the lower corner (point ids are dense): linear, where
// a comparison sort of the 950 k pairs of the benchmark tree's level-1 run took 0.028 s.
std::vector<Lattice::EdgeRef> Lattice::sorted_edges(const std::vector<EdgeRef>& raw,
                                                    const Context* ctx) const {
  const std::vector<std::uint32_t> order = detail::bucket_order(
      raw.size(), pts_.size(),
      [&](std::size_t i) { return static_cast<std::uint32_t>(raw[i].key >> 32U); },
      [&](std::uint32_t x, std::uint32_t y) { return raw[x] < raw[y]; }, ctx);
  std::vector<EdgeRef> out(raw.size());
  for (std::size_t i = 0; i < order.size(); ++i) out[i] = raw[order[i]];
  return out;
}

// The face opposite corner k is shared with the face neighbour across it; the slot that comes
// first makes its points.
void Lattice::add_face_points(const Round& round) {
  for (std::uint32_t slot = round.first; slot < round.end; ++slot) {
    if (!round.is_live(slot)) continue;
    const std::uint32_t t = slot_tet_[slot];
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t nb = neighbor_[4 * static_cast<std::size_t>(t) + k];
      const std::uint32_t other = nb == kNone ? kNone : slot_of_[nb];
      if (other != kNone && other < slot) {
        for (int j = 0; j < 4; ++j) {
          if (neighbor_[4 * static_cast<std::size_t>(nb) + j] == t) {
            tet_face_[4 * static_cast<std::size_t>(slot) + k] =
                tet_face_[4 * static_cast<std::size_t>(other) + j];
          }
        }
        continue;
      }
      tet_face_[4 * static_cast<std::size_t>(slot) + k] = static_cast<std::uint32_t>(refs_.size());
      for (const Bary& w : face_bary_[k]) refs_.emplace_back(slot, w);
    }
  }
}

void Lattice::add_inner_points(const Round& round) {
  for (std::uint32_t slot = round.first; slot < round.end; ++slot) {
    if (!round.is_live(slot) || inner_bary_.empty()) continue;
    inner_first_[slot] = static_cast<std::uint32_t>(refs_.size());
    for (const Bary& w : inner_bary_) refs_.emplace_back(slot, w);
  }
}

// Positions and one batch evaluation of the points from `first_point` on.
void Lattice::evaluate_from(const Field& field, std::size_t first_point, const Context* ctx) {
  const std::size_t count = refs_.size() - first_point;
  positions_.resize(refs_.size());
  values_.resize(refs_.size());
  const double inv_m = 1.0 / m_;
  parallel::for_chunks(
      count, 16384,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = first_point + b; i < first_point + e; ++i) {
          const Tet& t = tets_[slot_tet_[refs_[i].first]];
          positions_[i] = lattice_point(TetPoints{pts_[t[0]], pts_[t[1]], pts_[t[2]], pts_[t[3]]},
                                        refs_[i].second, inv_m);
        }
      },
      ctx);
  field.evaluate(std::span<const Vec3>(positions_).subspan(first_point, count),
                 std::span<double>(values_).subspan(first_point, count), {}, ctx);
  evaluated_ += count;
}

// Barycentric enumerations (in a fixed order) of the points strictly inside each face (the
// face opposite corner k) and inside the tetrahedron, and the reverse lookups of id().
void Lattice::build_tables() {
  for (int e = 0; e < 6; ++e) edge_of_[(1U << kEdgeCorners[e][0]) | (1U << kEdgeCorners[e][1])] = e;
  build_face_tables();
  build_tetrahedron_tables();
}

// A face's points are named by the weights (a, b) of its second and third corners in point id
// order, which both tetrahedra sharing the face agree on (corners are sorted by id).
void Lattice::build_face_tables() {
  face_rank_.assign(side_ * side_, 0);
  for (int k = 0; k < 4; ++k) {
    const auto& c = kFaceCorners[k];
    std::uint32_t rank = 0;
    for (int a = 1; a < m_; ++a) {
      for (int b = 1; a + b < m_; ++b) {
        Bary w{};
        w[c[0]] = static_cast<std::uint8_t>(m_ - a - b);
        w[c[1]] = static_cast<std::uint8_t>(a);
        w[c[2]] = static_cast<std::uint8_t>(b);
        face_rank_[a * side_ + b] = rank++;
        face_bary_[k].push_back(w);
      }
    }
  }
}

// Every point of the tetrahedron (all_bary_), and those strictly inside it with their ranks.
void Lattice::build_tetrahedron_tables() {
  for (int a = 0; a <= m_; ++a) {
    for (int b = 0; a + b <= m_; ++b) {
      for (int c = 0; a + b + c <= m_; ++c) {
        all_bary_.push_back({static_cast<std::uint8_t>(m_ - a - b - c),
                             static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b),
                             static_cast<std::uint8_t>(c)});
      }
    }
  }
  inner_rank_.assign(side_ * side_ * side_, 0);
  for (int a = 1; a < m_; ++a) {
    for (int b = 1; a + b < m_; ++b) {
      for (int c = 1; a + b + c < m_; ++c) {
        inner_rank_[(a * side_ + b) * side_ + c] = static_cast<std::uint32_t>(inner_bary_.size());
        inner_bary_.push_back({static_cast<std::uint8_t>(m_ - a - b - c),
                               static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b),
                               static_cast<std::uint8_t>(c)});
      }
    }
  }
}

}  // namespace ramiform::detail::tets
