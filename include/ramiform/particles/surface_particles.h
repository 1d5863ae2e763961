// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Particles spread over an implicit surface f == iso, denser where the surface curves.
///
/// From Proença, Jorge & Costa Sousa 2008, "Suggestive Contours over Point-Set Implicits"
/// (GRAPP), §4 (the particle system) and §3 (local regeneration after an edit), which build on
/// Witkin & Heckbert 1994, "Using particles to sample and control implicit surfaces"
/// (SIGGRAPH), and Foster, Jepp, Wyvill, Costa Sousa, Galbraith & Jorge 2005, "Drawing
/// surfaces" (Computers & Graphics).
///
/// - Cells: the leaves of an octree that meet the surface (an MPU field's own leaves, or
///   adaptive_cells(), which splits a cell while the surface normals in it vary more than
///   `flatness_deg`, so deep cells mark curved regions).
/// - Seeding (§4): k particles per leaf cell on average, taken from points already on the
///   surface (the caller's `seeds`, e.g. an MPU field's input points), else from the cell's
///   probe points projected onto the surface (Newton steps along the gradient), else from
///   random cell points projected.
/// - Repulsion radius δ_i (§4, eq. 2): δ_i = weight((d_i − d_min)/(d_max − d_min)) with d_i the
///   particle's cell depth and weight a quadratic B-spline falling from 1 at d_min to 0 at
///   d_max. The paper leaves the weight unitless; here it interpolates log δ between the spacing
///   the cells give at d_min and at d_max (δ ∝ cell size / √k at both ends), the common scale
///   chosen so that the particles tile the estimated surface area.
/// - Simulation: `iterations` Jacobi steps (each reads the previous positions only), each one
///   batched field evaluation with gradients: the Witkin–Heckbert constraint term (a Newton
///   step to f == iso along ∇f) plus repulsion from the neighbours closer than δ_i, weighted by
///   (1 − r/δ_i)² and projected on the tangent plane. A final projection puts every particle on
///   the surface.
///
/// Progress is reported through `ctx` as "particles: cells" (per octree level) and "particles:
/// simulate" (per step).
///
/// Deviations from the paper: the per-cell particle count is k on average, in proportion to the
/// surface area estimated in each cell over δ² (k exactly per cell would crowd cells that the
/// surface only grazes); neighbours come from a sorted cell hash per δ level, not the octree.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/core/types.h"
#include "ramiform/field/field.h"

namespace ramiform {

/// One octree leaf cell that meets the surface.
struct ParticleCell {
  Aabb box;       ///< the cell, model units
  int depth = 0;  ///< octree depth (0 = root)
};

/// One particle on the surface.
struct SurfaceParticle {
  Vec3 position;           ///< on f == iso, model units
  Vec3 normal;             ///< unit outward normal: −∇f/|∇f| (f > iso inside)
  double delta = 0;        ///< repulsion radius δ_i, model units
  std::uint32_t cell = 0;  ///< index of the cell the particle was seeded in
};

/// Options of adaptive_cells, spread_particles and regenerate_particles.
struct ParticleOptions {
  static constexpr int kMaxDepth = 16;          ///< largest allowed max_depth
  static constexpr int kMaxIterations = 10000;  ///< largest allowed iterations

  std::size_t per_cell = 4;  ///< k initial particles per leaf cell on average (paper §4); >= 1
  /// When > 0: the total number of particles wanted instead of per_cell × cells. Adaptive
  /// cells are then split to a deeper minimum depth until there are at most 2 per_cell
  /// particles per cell on average (or max_depth is reached), no deeper than where the leaves
  /// would outnumber twice this count, and δ is scaled so that this many tile the surface.
  std::size_t count = 0;
  int iterations = 20;     ///< simulation steps, 0..kMaxIterations
  std::uint64_t seed = 1;  ///< seeds the random choices (which seeds, which cell points)
  int max_depth = 8;       ///< deepest adaptive cell, 0..kMaxDepth
  /// Split a surface cell while its sampled surface normals differ by more than this angle
  /// (degrees, in (0, 180)).
  double flatness_deg = 20.0;
};

/// A particle system: the cells it was seeded in and the particles.
struct ParticleSystem {
  double iso = 0;                          ///< the field's iso value
  std::vector<ParticleCell> cells;         ///< leaf cells; particles refer to them by index
  std::vector<SurfaceParticle> particles;  ///< the particles
  /// The seeding state, for the feature-line test of eq. 11 (paper §6; Foster et al.'s normal
  /// "before and after the movement"): per particle, the position it was seeded at (on the
  /// surface, after its initial projection, before the simulation moved it) and the unit
  /// outward normal there. Both parallel to `particles`, or both empty when unknown (e.g. a
  /// system loaded from a file without them, or regenerated from one).
  ///
  /// "Before" is the seeding, "after" the end of the simulation, not the largest turn over
  /// single steps: a particle crosses a rounded crease (MPU surfaces round every crease over a
  /// few δ) in several damped steps that each turn its normal by less than k_a, while the
  /// turn from start to end is the whole dihedral angle; and the two ends are what straddles
  /// the crease, so the pair needs no state from the middle of the run. A particle that
  /// crosses a crease and comes back is missed (the damped Jacobi steps seldom do that).
  std::vector<Vec3> seed_positions;
  std::vector<Vec3> seed_normals;  ///< unit, one per particle (see seed_positions)
  /// The octree's root cube when the cells came from adaptive_cells (regeneration builds the
  /// edited region's cells under it); empty when the caller passed the cells.
  Aabb root;
};

/// What a run did.
struct ParticleStats {
  std::size_t particles = 0;  ///< particles in the result (regeneration: the re-simulated ones)
  std::size_t cells = 0;      ///< cells used (regeneration: the re-seeded ones)
  std::size_t dropped = 0;    ///< particles that could not reach the surface (not in the result)
  std::size_t kept = 0;       ///< regeneration: particles kept unchanged
  int iterations = 0;         ///< simulation steps run
  double residual_max = 0;    ///< max |f − iso| / |∇f| / δ_i over the result's particles
  /// Coefficient of variation (standard deviation / mean) of nearest-neighbour distance / δ_i
  /// over the particles of the result (regeneration: the re-simulated ones) that have a
  /// neighbour within δ_i (one without is left out: it has no spacing to measure).
  double spacing_cv = 0;
  double seconds_cells = 0, seconds_seed = 0, seconds_simulate = 0;  ///< wall-clock seconds
  std::uint64_t field_evals = 0;  ///< point evaluations of the field during the call
};

/// The cells a field brings for spread_particles(): an MPU field's octree leaves (paper §4 places
/// the particles in the MPU's own cells; field/mpu.h), else none (spread_particles() then builds
/// adaptive_cells()).
[[nodiscard]] std::vector<ParticleCell> field_cells(const Field& field);

/// True when `system` has particles and a seeding state for each (seed_positions and
/// seed_normals as long as particles).
[[nodiscard]] bool has_seed_state(const ParticleSystem& system);

/// The particles' positions and normals as a point set, in particle order.
[[nodiscard]] PointSet particle_points(const ParticleSystem& system);

/// Adaptive cells for any field: an octree over a cube around field.bounds(); cells whose
/// bound(box) straddles iso are kept and split (always down to depth 3, or max_depth when that
/// is smaller) while depth < max_depth and the normals at surface points probed in the cell (a
/// 3×3×3 lattice of cell points projected onto the surface) differ by more than flatness_deg.
/// Returns the leaves that meet the surface (a probe landed in them or their probes have both
/// signs), coarsest first. Surface pieces thinner than a third of a depth-3 cell can be
/// missed. Throws InvalidArgument for bad options or a field whose bounds() are not finite.
[[nodiscard]] std::vector<ParticleCell> adaptive_cells(const Field& field,
                                                       const ParticleOptions& options = {},
                                                       const Context* ctx = nullptr);

/// Spreads particles over f == iso (see the file comment). `cells`: the leaf cells to use
/// (boxes non-empty and finite, depth 0..kMaxDepth), e.g. an MPU field's octree leaves; empty →
/// adaptive_cells(field, options) (with `count`, split to a deeper minimum depth). `seeds`: points
/// on or near the surface to start from (e.g. an MPU field's input points); each cell takes its
/// particles from the seeds inside it (chosen deterministically from `options.seed`) and the rest
/// from projected random cell points. Every particle of the result satisfies |f − iso| / |∇f| ≤
/// 1e-4 δ_i; particles that cannot reach it are dropped and counted in stats->dropped. The
/// result has a seeding state (seed_positions, seed_normals; with 0 iterations the normals are
/// those after the final projection). Byte-identical results on any thread count. Throws
/// InvalidArgument for bad options or cells, Cancelled through `ctx`.
[[nodiscard]] ParticleSystem spread_particles(const Field& field,
                                              const ParticleOptions& options = {},
                                              std::span<const ParticleCell> cells = {},
                                              std::span<const Vec3> seeds = {},
                                              ParticleStats* stats = nullptr,
                                              const Context* ctx = nullptr);

/// Local regeneration (paper §3): after an edit confined to `edit_box`, the particles within
/// their δ of edit_box are removed, and the cells that meet edit_box grown by their particles'
/// δ are replaced by the edited field's cells there (built under previous.root, at least as
/// deep as the shallowest old cell; old cells those overlap are replaced too), or re-probed
/// against `edited` when previous.root is empty (caller-given cells: new surface outside them
/// gets no particles). The new cells are seeded at the previous system's depth → δ law, less
/// the kept particles already in them, and simulated against `edited` with the kept particles
/// nearby as fixed neighbours. Every other particle is kept with byte-identical position,
/// normal and δ (and seeding state), in the same order, first in the result (its `cell` is
/// renumbered: kept cells keep their order, then the new cells follow); the new particles follow
/// them, with their own seeding state (when `previous` has none and particles are kept, the
/// result has none either). Stats count
/// the new particles and cells. Throws InvalidArgument for bad options, an empty or non-finite
/// edit_box, a particle whose cell index is out of range, or an iso value different from
/// previous.iso.
[[nodiscard]] ParticleSystem regenerate_particles(const Field& edited,
                                                  const ParticleSystem& previous,
                                                  const Aabb& edit_box,
                                                  const ParticleOptions& options = {},
                                                  ParticleStats* stats = nullptr,
                                                  const Context* ctx = nullptr);

}  // namespace ramiform
