// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/delaunay.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "core/bucket_order.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/random.h"

namespace ramiform::detail {
namespace {

constexpr std::uint32_t kNone = UINT32_MAX;
constexpr std::uint64_t kInsertionSeed = 0xb410;  // fixed: the output must not vary
constexpr std::uint32_t kFirstRound = 64;         // points of the first (smallest) round
constexpr std::size_t kFinishGrain = 16384;        // tetrahedra per parallel task of finish()
constexpr double kEps = std::numeric_limits<double>::epsilon() / 2;  // unit roundoff, 2^-53

// Forward error bounds of the floating-point determinants below, as multiples of the unit
// roundoff times the permanent (the determinant's expansion with every term made positive).
// Each term of the 3x3 orientation determinant carries three rounded differences, two rounded
// products and three rounded sums: below 8 units; each term of the in-sphere determinant
// carries five rounded differences, a lift with a square and two sums, three products and
// six sums: below 17 units. Shewchuk (1997, §4.2) derives 7 and 16 for his evaluation order;
// these are the same argument with a margin of about two for the rounding of the permanent.
constexpr double kOrientBound = 16 * kEps;
constexpr double kInsphereBound = 32 * kEps;

std::atomic<std::uint64_t> g_exact_calls{0};

// ---------------------------------------------------------------------------------------------
// Exact arithmetic on floating-point expansions (Shewchuk 1997, §2): a number is an unevaluated
// sum of doubles that do not overlap, in increasing magnitude, so its sign is the sign of its
// largest component. Only the rare undecided predicates come here.
class Expansion {
 public:
  Expansion() = default;
  explicit Expansion(double x) {
    if (x != 0) c_.push_back(x);
  }

  // a - b, exactly.
  static Expansion difference(double a, double b) {
    Expansion e;
    double x = 0, y = 0;
    two_sum(a, -b, x, y);
    if (y != 0) e.c_.push_back(y);
    if (x != 0) e.c_.push_back(x);
    return e;
  }

  friend Expansion operator+(Expansion e, const Expansion& f) {
    for (const double x : f.c_) e.grow(x);
    return e;
  }
  friend Expansion operator-(Expansion e, const Expansion& f) {
    for (const double x : f.c_) e.grow(-x);
    return e;
  }
  friend Expansion operator*(const Expansion& e, const Expansion& f) {
    Expansion product;
    for (const double b : f.c_) {
      for (const double a : e.c_) {  // a * b = x + y exactly (fused multiply-add)
        const double x = a * b;
        const double y = std::fma(a, b, -x);
        product.grow(y);
        product.grow(x);
      }
    }
    return product;
  }

  [[nodiscard]] int sign() const {
    if (c_.empty()) return 0;
    return c_.back() > 0 ? 1 : -1;
  }

 private:
  // x + y = a + b exactly, x the rounded sum (Knuth's two-sum).
  static void two_sum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bv = x - a;
    const double av = x - bv;
    y = (a - av) + (b - bv);
  }

  // Adds b, keeping the components nonoverlapping and increasing (Shewchuk's Grow-Expansion
  // with zero elimination).
  void grow(double b) {
    std::size_t w = 0;
    double q = b;
    for (const double e : c_) {
      double x = 0, h = 0;
      two_sum(q, e, x, h);
      if (h != 0) c_[w++] = h;
      q = x;
    }
    c_.resize(w);
    if (q != 0) c_.push_back(q);
  }

  std::vector<double> c_;
};

// The 3x3 determinant det[u; v; w] (rows), in the same order for doubles and expansions.
template <class T>
T det3(const std::array<T, 3>& u, const std::array<T, 3>& v, const std::array<T, 3>& w) {
  return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

double permanent3(const std::array<double, 3>& u, const std::array<double, 3>& v,
                  const std::array<double, 3>& w) {
  return std::abs(u[0]) * (std::abs(v[1] * w[2]) + std::abs(v[2] * w[1])) +
         std::abs(u[1]) * (std::abs(v[2] * w[0]) + std::abs(v[0] * w[2])) +
         std::abs(u[2]) * (std::abs(v[0] * w[1]) + std::abs(v[1] * w[0]));
}

template <class T>
T lift(const std::array<T, 3>& r) {
  return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
}

// The in-sphere determinant of rows (r_i, |r_i|^2), r_i = p_i - e, expanded along the lift.
template <class T>
T insphere_det(const std::array<std::array<T, 3>, 4>& r) {
  return (lift(r[3]) * det3(r[0], r[1], r[2]) - lift(r[2]) * det3(r[0], r[1], r[3])) +
         (lift(r[1]) * det3(r[0], r[2], r[3]) - lift(r[0]) * det3(r[1], r[2], r[3]));
}

std::array<double, 3> minus(const Vec3& a, const Vec3& b) {
  return {a.x() - b.x(), a.y() - b.y(), a.z() - b.z()};
}

std::array<Expansion, 3> minus_exact(const Vec3& a, const Vec3& b) {
  return {Expansion::difference(a.x(), b.x()), Expansion::difference(a.y(), b.y()),
          Expansion::difference(a.z(), b.z())};
}

int sign_of(double x) { return (x > 0) - (x < 0); }

// ---------------------------------------------------------------------------------------------
// The incremental construction. Tetrahedra are positively oriented; t_[t].n[k] is the tetrahedron
// across the face opposite corner k (kNone outside the enclosing tetrahedron).
using Tet = std::array<std::uint32_t, 4>;

class Builder {
 public:
  explicit Builder(std::vector<Vec3> points) : p_(std::move(points)) {}

  // The enclosing tetrahedron's corners are the last four points.
  void start(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    // A Delaunay tetrahedralization of n points in general position has about 6.7 n
    // tetrahedra; reserving them avoids regrowing (and page-faulting) the arrays.
    const std::size_t expected = 7 * p_.size() + 64;
    t_.reserve(expected);
    Tet t{a, b, c, d};
    if (orient3d(p_[a], p_[b], p_[c], p_[d]) < 0) std::swap(t[0], t[1]);
    t_.push_back({t, {kNone, kNone, kNone, kNone}, 0});
  }

  // Inserts point i; false when it equals a vertex already there.
  bool insert(std::uint32_t i) {
    const Vec3& p = p_[i];
    const std::uint32_t t = locate(p);
    for (const std::uint32_t c : t_[t].v) {
      if (p_[c] == p) return false;
    }
    ++stamp_;
    cavity_.assign(1, t);
    t_[t].mark = in_cavity();
    boundary_.clear();
    for (std::size_t q = 0; q < cavity_.size(); ++q) {
      const std::uint32_t c = cavity_[q];
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t nb = t_[c].n[k];
        if (nb != kNone && t_[nb].mark == in_cavity()) continue;
        if (nb != kNone && t_[nb].mark != outside_cavity()) {
          if (in_sphere(nb, p)) {
            t_[nb].mark = in_cavity();
            cavity_.push_back(nb);
            continue;
          }
          t_[nb].mark = outside_cavity();
        }
        int back = -1;  // the face of nb that faces c
        if (nb != kNone) {
          for (int j = 0; j < 4; ++j) {
            if (t_[nb].n[j] == c) back = j;
          }
        }
        boundary_.push_back({c, k, nb, back});
      }
    }
    // The cone from p to the cavity's boundary: each boundary face (opposite corner k of a
    // cavity tetrahedron) gets p in place of that corner, which keeps the orientation.
    fresh_.clear();
    for (const Face& f : boundary_) {
      Tet tv = t_[f.tet].v;
      tv[f.k] = i;
      fresh_.push_back(tv);
    }
    for (const std::uint32_t c : cavity_) free_.push_back(c);
    // The new tetrahedra meet each other across faces holding p; each such face is named by its
    // other two corners, and found twice (once per side) through an open-addressing table.
    std::size_t size = 16;
    while (size < 6 * boundary_.size()) size *= 2;
    if (table_.size() < size) table_.resize(size);
    const std::size_t mask = size - 1;
    std::size_t matched = 0;
    for (std::size_t q = 0; q < boundary_.size(); ++q) {
      const Face& f = boundary_[q];
      const std::uint32_t s = allocate();
      t_[s].v = fresh_[q];
      if (!vt_.empty()) {
        for (const std::uint32_t v : fresh_[q]) {
          vt_[v] = s;
          touched_[v] = round_;
        }
      }
      t_[s].n = {kNone, kNone, kNone, kNone};
      t_[s].n[f.k] = f.nb;
      if (f.nb != kNone) t_[f.nb].n[f.back] = s;
      for (int j = 0; j < 4; ++j) {
        if (j == f.k) continue;
        std::uint32_t e[2];  // the face opposite j: p and the corners other than j and k
        int m = 0;
        for (int c = 0; c < 4; ++c) {
          if (c != j && c != f.k) e[m++] = fresh_[q][c];
        }
        const std::uint64_t key =
            (std::uint64_t{std::min(e[0], e[1])} << 32U) | std::max(e[0], e[1]);
        std::size_t h = (key * 0x9E3779B97F4A7C15ULL >> 40U) & mask;
        while (table_[h].stamp == stamp_ && table_[h].key != key) h = (h + 1) & mask;
        Slot& slot = table_[h];
        if (slot.stamp == stamp_) {
          t_[s].n[j] = slot.tet;
          t_[slot.tet].n[slot.face] = s;
          ++matched;
        } else {
          slot = {key, stamp_, s, j};
        }
      }
      last_ = s;
    }
    if (2 * matched != 3 * boundary_.size()) {
      throw Failure("Delaunay tetrahedralization: cavity boundary is not closed");
    }
    return true;
  }

  // Makes every piece an edge by midpoint splitting, round after round (see
  // delaunay_tetrahedralize); returns the number of pieces still missing after the last round.
  // An insertion takes away only edges of its cavity, whose corners it marks (touched_); a
  // piece found earlier is checked again when both its ends were marked since the round before.
  std::size_t recover(const std::vector<std::array<std::uint32_t, 2>>& required) {
    index_vertices();
    touched_.assign(p_.size(), 0);
    struct Piece {
      std::array<std::uint32_t, 2> e;
      bool found;
    };
    std::vector<Piece> pieces, next;
    for (const auto& e : required) pieces.push_back({e, false});
    for (std::uint32_t round = 1;; ++round) {
      round_ = round;
      next.clear();
      std::size_t missing = 0;
      for (const Piece& piece : pieces) {
        const auto [a, b] = piece.e;
        const bool recheck = touched_[a] + 1 >= round && touched_[b] + 1 >= round;
        if (a == b || (piece.found && !recheck) || has_edge(a, b)) {
          next.push_back({piece.e, true});
          continue;
        }
        ++missing;
        if (round > kRecoveryRounds) {
          next.push_back({piece.e, false});
          continue;
        }
        p_.push_back(0.5 * (p_[a] + p_[b]));
        vt_.push_back(kNone);
        touched_.push_back(0);
        const auto m = static_cast<std::uint32_t>(p_.size() - 1);
        if (!insert(m)) {  // the midpoint is a vertex already: this piece stays as it is
          p_.pop_back();
          vt_.pop_back();
          touched_.pop_back();
          next.push_back({piece.e, false});
          continue;
        }
        next.push_back({{a, m}, false});
        next.push_back({{m, b}, false});
      }
      if (missing == 0 || round > kRecoveryRounds) return missing;
      pieces.swap(next);
    }
  }

  [[nodiscard]] const std::vector<Vec3>& points() const { return p_; }

  // The live tetrahedra without a corner of the enclosing tetrahedron (points n to n + 3), in
  // the result's canonical form (corners ascending, list sorted), with their face neighbours
  // renumbered to match; Steiner points (from n + 4 on) are renumbered from n on.
  void finish(std::uint32_t n, DelaunayResult& out, const Context* ctx) const {
    const auto limit = static_cast<std::uint32_t>(p_.size() - 4);
    const std::size_t cells = t_.size();
    std::vector<char> dead(cells, 0);
    for (const std::uint32_t f : free_) dead[f] = 1;
    std::vector<Tet> sorted(cells);
    std::vector<std::array<std::uint8_t, 4>> corner(cells);  // sorted position -> corner
    // Corners renumbered (Steiner points down by four, the enclosing corners to kNone) and
    // sorted by a network of five compare-exchanges; per tetrahedron, in parallel.
    parallel::for_chunks(cells, kFinishGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t t = b; t < e; ++t) {
        if (dead[t] != 0) continue;
        Tet v{};
        std::array<std::uint8_t, 4> c{0, 1, 2, 3};
        for (int k = 0; k < 4; ++k) {
          const std::uint32_t x = t_[t].v[k];
          v[k] = x < n ? x : x >= n + 4 ? x - 4 : kNone;
        }
        for (const auto& [i, j] : {std::pair{0, 1}, {2, 3}, {0, 2}, {1, 3}, {1, 2}}) {
          if (v[j] < v[i]) {
            std::swap(v[i], v[j]);
            std::swap(c[i], c[j]);
          }
        }
        if (v[3] >= limit) {
          dead[t] = 1;
          continue;
        }
        sorted[t] = v;
        corner[t] = c;
      }
    }, ctx);
    // By the smallest corner, then by the other three.
    const std::vector<std::uint32_t> kept = bucket_order(
        cells, limit, [&](std::size_t t) { return dead[t] != 0 ? kNoBucket : sorted[t][0]; },
        [&](std::uint32_t x, std::uint32_t y) { return sorted[x] < sorted[y]; }, ctx);
    std::vector<std::uint32_t> renumber(cells, kNone);
    parallel::for_chunks(kept.size(), kFinishGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t q = b; q < e; ++q) renumber[kept[q]] = static_cast<std::uint32_t>(q);
    }, ctx);
    out.tets.resize(kept.size());
    out.neighbors.resize(4 * kept.size());
    parallel::for_chunks(kept.size(), kFinishGrain, [&](std::size_t b, std::size_t e) {
      for (std::size_t q = b; q < e; ++q) {
        const std::uint32_t t = kept[q];
        out.tets[q] = sorted[t];
        for (int k = 0; k < 4; ++k) {
          const std::uint32_t nb = t_[t].n[corner[t][k]];
          out.neighbors[4 * q + k] = nb == kNone ? kNone : renumber[nb];
        }
      }
    }, ctx);
  }

 private:
  struct Face {
    std::uint32_t tet;
    int k;
    std::uint32_t nb;
    int back;
  };
  struct Slot {
    std::uint64_t key;
    std::uint32_t stamp;  // the insertion that filled it (stale slots count as empty)
    std::uint32_t tet;
    int face;
  };

  // vt_[v]: a live tetrahedron with corner v, kept from here on by insert().
  void index_vertices() {
    std::vector<char> dead(t_.size(), 0);
    for (const std::uint32_t f : free_) dead[f] = 1;
    vt_.assign(p_.size(), kNone);
    for (std::uint32_t t = 0; t < t_.size(); ++t) {
      if (dead[t] != 0) continue;
      for (const std::uint32_t v : t_[t].v) vt_[v] = t;
    }
  }

  // Whether a-b is an edge: a search over the tetrahedra around a (across the faces holding a).
  bool has_edge(std::uint32_t a, std::uint32_t b) {
    ++stamp_;
    const std::uint32_t seen = in_cavity();
    cavity_.assign(1, vt_[a]);
    t_[vt_[a]].mark = seen;
    for (std::size_t q = 0; q < cavity_.size(); ++q) {
      const Cell& c = t_[cavity_[q]];
      for (int k = 0; k < 4; ++k) {
        if (c.v[k] == b) return true;
      }
      for (int k = 0; k < 4; ++k) {
        const std::uint32_t nb = c.n[k];
        if (c.v[k] == a || nb == kNone || t_[nb].mark == seen) continue;
        t_[nb].mark = seen;
        cavity_.push_back(nb);
      }
    }
    return false;
  }

  std::uint32_t allocate() {
    if (!free_.empty()) {
      const std::uint32_t s = free_.back();
      free_.pop_back();
      return s;
    }
    t_.emplace_back();
    return static_cast<std::uint32_t>(t_.size() - 1);
  }

  [[nodiscard]] bool in_sphere(std::uint32_t t, const Vec3& p) const {
    const Tet& c = t_[t].v;
    return insphere(p_[c[0]], p_[c[1]], p_[c[2]], p_[c[3]], p) > 0;
  }

  // Visibility walk: cross a face whenever p lies strictly beyond it. The face order rotates
  // from step to step (deterministically) so the walk does not favour one direction.
  std::uint32_t locate(const Vec3& p) {
    std::uint32_t t = last_;
    std::uint32_t prev = kNone;
    for (;;) {
      bool moved = false;
      ++rotation_;
      for (int j = 0; j < 4 && !moved; ++j) {
        const int k = static_cast<int>((rotation_ + static_cast<unsigned>(j)) & 3U);
        const std::uint32_t nb = t_[t].n[k];
        if (nb == prev || nb == kNone) continue;
        std::array<const Vec3*, 4> q{&p_[t_[t].v[0]], &p_[t_[t].v[1]], &p_[t_[t].v[2]],
                                     &p_[t_[t].v[3]]};
        q[k] = &p;
        if (orient3d(*q[0], *q[1], *q[2], *q[3]) < 0) {
          prev = t;
          t = nb;
          moved = true;
        }
      }
      if (!moved) return t;
    }
  }

  std::vector<Vec3> p_;
  // Per tetrahedron: corners, face neighbours (n[k] across the face opposite corner k, kNone
  // outside the enclosing tetrahedron) and the cavity search's mark, together in memory: the
  // search visits them in no spatial order, so one cache line per tetrahedron matters.
  struct Cell {
    Tet v{};
    Tet n{};
    std::uint32_t mark = 0;  // 2 stamp: in the current cavity; 2 stamp + 1: tested, outside
  };
  [[nodiscard]] std::uint32_t in_cavity() const { return 2 * stamp_; }
  [[nodiscard]] std::uint32_t outside_cavity() const { return 2 * stamp_ + 1; }
  std::vector<Cell> t_;
  std::vector<std::uint32_t> free_;
  std::vector<std::uint32_t> vt_;  // see index_vertices(); empty until recover()
  std::vector<std::uint32_t> touched_;  // per point, the last round whose cavity held it
  std::uint32_t round_ = 0;
  std::uint32_t last_ = 0, stamp_ = 0;
  unsigned rotation_ = 0;
  std::vector<std::uint32_t> cavity_;
  std::vector<Face> boundary_;
  std::vector<Tet> fresh_;
  std::vector<Slot> table_;
};

// Interleaves the low 21 bits of x, y, z (bit 3k of the result is bit k of x).
std::uint64_t morton3(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  auto spread = [](std::uint64_t v) {
    v &= 0x1fffffU;
    v = (v | v << 32U) & 0x1f00000000ffffULL;
    v = (v | v << 16U) & 0x1f0000ff0000ffULL;
    v = (v | v << 8U) & 0x100f00f00f00f00fULL;
    v = (v | v << 4U) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2U) & 0x1249249249249249ULL;
    return v;
  };
  return spread(x) | spread(y) << 1U | spread(z) << 2U;
}

}  // namespace

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const auto u = minus(b, a), v = minus(c, a), w = minus(d, a);
  const double det = det3(u, v, w);
  if (std::abs(det) > kOrientBound * permanent3(u, v, w)) return sign_of(det);
  g_exact_calls.fetch_add(1, std::memory_order_relaxed);
  return det3(minus_exact(b, a), minus_exact(c, a), minus_exact(d, a)).sign();
}

int insphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e) {
  // With (a, b, c, d) positively oriented, the determinant of rows (p - e, |p - e|^2) is
  // negative exactly when e lies inside their sphere (checked in the tests on a unit cube's
  // corners), hence the minus signs.
  const std::array<std::array<double, 3>, 4> r{minus(a, e), minus(b, e), minus(c, e), minus(d, e)};
  const double det = insphere_det(r);
  const double perm =
      lift(r[3]) * permanent3(r[0], r[1], r[2]) + lift(r[2]) * permanent3(r[0], r[1], r[3]) +
      lift(r[1]) * permanent3(r[0], r[2], r[3]) + lift(r[0]) * permanent3(r[1], r[2], r[3]);
  if (std::abs(det) > kInsphereBound * perm) return -sign_of(det);
  g_exact_calls.fetch_add(1, std::memory_order_relaxed);
  const std::array<std::array<Expansion, 3>, 4> x{minus_exact(a, e), minus_exact(b, e),
                                                  minus_exact(c, e), minus_exact(d, e)};
  return -insphere_det(x).sign();
}

std::uint64_t exact_predicate_calls() { return g_exact_calls.load(std::memory_order_relaxed); }

DelaunayResult delaunay_tetrahedralize(const std::vector<Vec3>& points,
                                       const std::vector<std::array<std::uint32_t, 2>>& required_edges,
                                       const Context* ctx) {
  DelaunayResult result;
  const auto n = static_cast<std::uint32_t>(points.size());
  for (const auto& e : required_edges) {
    if (e[0] >= n || e[1] >= n) {
      throw InvalidArgument("delaunay_tetrahedralize: required edge " + std::to_string(e[0]) +
                            "-" + std::to_string(e[1]) + " names a point out of range (" +
                            std::to_string(n) + " points)");
    }
  }
  if (n < 4) return result;
  Aabb box;
  for (const auto& q : points) {
    if (!q.allFinite())
      throw InvalidArgument("delaunay_tetrahedralize: point with a non-finite coordinate");
    box.extend(q);
  }
  // The enclosing tetrahedron: a regular one around the points' bounding sphere, its inscribed
  // sphere 10 times as large, so that its corners are far from every circumsphere that
  // matters; tetrahedra touching them are dropped at the end.
  const Vec3 center = box.center();
  const double radius = std::max(0.5 * box.diagonal().norm(), 1e-300);
  std::vector<Vec3> all = points;
  const double s = 10.0 * std::sqrt(3.0) * radius;
  for (const Vec3& corner : {Vec3(1, 1, 1), Vec3(1, -1, -1), Vec3(-1, 1, -1), Vec3(-1, -1, 1)}) {
    all.push_back(center + s * corner);
  }
  // Biased randomized insertion order (Amenta, Choi & Rote 2003): a fixed-seed shuffle cut
  // into rounds of doubling size, each round in Morton order. Within a round consecutive
  // points are close, so walks are short; across rounds the order is random, which keeps the
  // cavities small (measured on the 52 k bounding points of the 1,500-segment benchmark tree:
  // 20 tetrahedra per cavity instead of 35 with one global Morton order, 30 % less time).
  const Vec3 extent = box.diagonal().cwiseMax(Vec3::Constant(1e-300));
  std::vector<std::uint64_t> code(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3 u = ((points[i] - box.min()).array() / extent.array()).matrix() * 2097151.0;
    code[i] = morton3(static_cast<std::uint32_t>(u.x()), static_cast<std::uint32_t>(u.y()),
                      static_cast<std::uint32_t>(u.z()));
  }
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0U);
  Rng rng(kInsertionSeed);
  for (std::uint32_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  for (std::uint32_t i = 0; i < n; ++i) keyed[i] = {code[order[i]], order[i]};
  for (std::uint32_t end = n; end > 0;) {
    const std::uint32_t begin = end > kFirstRound ? end / 2 : 0;
    std::sort(keyed.begin() + begin, keyed.begin() + end);
    end = begin;
  }
  for (std::uint32_t i = 0; i < n; ++i) order[i] = keyed[i].second;
  Builder builder(std::move(all));
  builder.start(n, n + 1, n + 2, n + 3);
  for (const std::uint32_t i : order) {
    if (!builder.insert(i)) ++result.duplicate_points;
  }
  if (!required_edges.empty()) {
    result.missing_edges = builder.recover(required_edges);
    result.steiner_points.assign(builder.points().begin() + n + 4, builder.points().end());
  }
  builder.finish(n, result, ctx);
  return result;
}

}  // namespace ramiform::detail
