// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal helpers shared by the silhouette and feature-line tracers (silhouettes.cpp,
// features.cpp): δ at any point from the nearest particle, a growable spatial hash of line
// points for "is another line near", batched projection onto f == iso, and polyline length.

#include <array>
#include <cstdint>
#include <mutex>
#include <span>
#include <utility>
#include <vector>

#include "field/point_kdtree.h"
#include "ramiform/core/context.h"
#include "ramiform/core/types.h"
#include "ramiform/field/field.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform::detail {

/// Residual goals of the tracers' correctors, tighter than what lines.h promises (1e-3 δ for
/// |f − iso| / |∇f| and 1e-3 for |n·v|) so that every accepted point meets the promise with a
/// margin.
inline constexpr double kLineSurfaceTolerance = 1e-4;  ///< |f − iso| / |∇f|, × δ
inline constexpr double kLineContourTolerance = 1e-4;  ///< |n·v|

/// δ at any point: the repulsion radius of the nearest particle (ties by index).
class DeltaLookup {
 public:
  /// `particles` must be non-empty and outlive the lookup.
  explicit DeltaLookup(const ParticleSystem& particles);

  /// δ of the particle nearest to p.
  [[nodiscard]] double delta_at(const Vec3& p) const;
  /// Index of the particle nearest to p.
  [[nodiscard]] std::uint32_t nearest(const Vec3& p) const;

  [[nodiscard]] const std::vector<Vec3>& positions() const { return positions_; }
  [[nodiscard]] const PointKdTree& tree() const { return tree_; }
  [[nodiscard]] const ParticleSystem& system() const { return *system_; }

 private:
  const ParticleSystem* system_;
  std::vector<Vec3> positions_;
  PointKdTree tree_;
};

/// The radius of each particle's surfel (Visibility::kSurfels, visibility.cpp): the distance
/// to the third nearest other particle.
[[nodiscard]] std::vector<double> surfel_radii(const ParticleSystem& particles,
                                               const PointKdTree& tree, const Context* ctx);

/// A growable uniform grid of line points, each tagged with the line it belongs to and its
/// position along that line. Queries visit the points in insertion order within each cell and
/// cells in a fixed order, so their answers never depend on anything but the inserted data.
/// The cells live in an open-addressing table (linear probing) and their points in one array,
/// linked cell by cell: the tracers query it at every step (27 cells for a radius near `cell`),
/// where a node-based map's lookups were 5–8 % of a silhouette drawing.
class LinePointHash {
 public:
  /// `cell` > 0: the grid spacing (queries of any radius work; radii near `cell` are fastest).
  explicit LinePointHash(double cell);

  void insert(const Vec3& p, std::uint32_t line, std::int32_t index);

  /// True when some point within `radius` of p satisfies accept(line, index).
  template <class Accept>
  [[nodiscard]] bool any_within(const Vec3& p, double radius, Accept&& accept) const {
    if (entries_.empty()) return false;
    const double r2 = radius * radius;
    const auto lo = cell_of(p - Vec3::Constant(radius));
    const auto hi = cell_of(p + Vec3::Constant(radius));
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x) {
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y) {
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
          for (std::uint32_t e = first_of(key(x, y, z)); e != kNone; e = entries_[e].next) {
            const Entry& entry = entries_[e];
            if ((entry.p - p).squaredNorm() < r2 && accept(entry.line, entry.index)) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  struct Entry {
    Vec3 p;
    std::uint32_t line;
    std::int32_t index;
    std::uint32_t next;  // the cell's next point (insertion order), kNone at its last
  };
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t first = kNone;  // kNone: an empty slot
    std::uint32_t last = kNone;
  };
  [[nodiscard]] std::array<std::int64_t, 3> cell_of(const Vec3& p) const;
  [[nodiscard]] static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z);
  [[nodiscard]] std::size_t home(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }
  // The first point of the cell with this key, kNone when it has none.
  [[nodiscard]] std::uint32_t first_of(std::uint64_t key) const {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t s = home(key);; s = (s + 1) & mask) {
      const Slot& slot = slots_[s];
      if (slot.first == kNone) return kNone;
      if (slot.key == key) return slot.first;
    }
  }
  void grow();

  double inv_cell_;
  int shift_ = 64 - 6;  // 64 − log2(slots_.size())
  std::vector<Slot> slots_;
  std::size_t used_ = 0;  // occupied slots
  std::vector<Entry> entries_;
};

/// Batched Newton projection onto f == iso along ∇f: every point moves by
/// −(f − iso) ∇f / |∇f|² per round (each move capped at `scale[i]`) until
/// |f − iso| / |∇f| ≤ tolerance · scale[i]. On return `values`/`gradients` hold f and ∇f at the
/// returned points and ok[i] says whether point i converged within `max_rounds` rounds (points
/// with a zero or non-finite gradient fail). One field evaluation of the still-moving points per
/// round.
void project_to_surface(const Field& field, std::span<Vec3> points, std::span<const double> scale,
                        double tolerance, int max_rounds, std::span<double> values,
                        std::span<Vec3> gradients, std::span<std::uint8_t> ok, const Context* ctx);

/// 3-D length of a polyline, the closing segment included when it is closed.
[[nodiscard]] double polyline_length(const Polyline& line);

/// The angle between two unit vectors, radians (robust near 0 and π).
[[nodiscard]] double angle_between(const Vec3& a, const Vec3& b);

}  // namespace ramiform::detail

namespace ramiform {

struct ParticleLookup::Impl {
  explicit Impl(const ParticleSystem& particles) : delta(particles) {}
  /// surfel_radii() of the particles, made on first use.
  [[nodiscard]] const std::vector<double>& radii(const Context* ctx) const {
    std::call_once(radii_once,
                   [&] { radii_ = detail::surfel_radii(delta.system(), delta.tree(), ctx); });
    return radii_;
  }
  /// Throws InvalidArgument unless this lookup was made for `particles`.
  void check(const ParticleSystem& particles) const;

  detail::DeltaLookup delta;

 private:
  mutable std::once_flag radii_once;
  mutable std::vector<double> radii_;
};

}  // namespace ramiform
