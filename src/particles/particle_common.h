// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal pieces of the surface particle system (particles/surface_particles.h): Newton
// projection, cell probes, the neighbour grid and the Jacobi simulation.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/types.h"
#include "ramiform/field/field.h"
#include "ramiform/particles/surface_particles.h"

namespace ramiform::particles_detail {

/// Desired δ over the hexagonal spacing the area estimate gives: 1.5 keeps the first ring of
/// neighbours (at the spacing) inside δ and the second ring (at √3 times it) outside.
inline constexpr double kDeltaOverSpacing = 1.5;
/// Final projection: every particle ends with |f − iso| / |∇f| <= this times δ_i.
inline constexpr double kSurfaceTolerance = 1e-4;
/// Cells are always split down to this depth (when max_depth allows) before flatness decides.
inline constexpr int kMinDepth = 3;
/// A cell is judged flat only when at least this many of its 27 probes landed near it.
inline constexpr std::size_t kMinFlatProbes = 4;

void validate(const ParticleOptions& options, const char* who);

/// Newton steps along the gradient towards f == iso for every point, batched. A point stops
/// when |f − iso| / |∇f| <= tol[i]; each step is clamped to max_step[i]. After at most `rounds`
/// steps the residual is measured once more. Returns the residual |f − iso| / |∇f| at the
/// final position of each point (infinity where the gradient vanishes or a value is not finite);
/// `gradients` (resized) holds ∇f there and `first_values` (when non-null) f at the start.
std::vector<double> project(const Field& field, std::vector<Vec3>& points,
                            std::span<const double> max_step, std::span<const double> tol,
                            int rounds, std::vector<Vec3>& gradients,
                            std::vector<double>* first_values, const Context* ctx);

/// What a lattice of projected points says about one cell.
struct CellProbe {
  std::vector<Vec3> points;    ///< projected lattice points that landed in the cell
  std::vector<Vec3> normals;   ///< unit outward normals there
  bool both_signs = false;     ///< the unprojected lattice had points inside and outside
  std::size_t near_count = 0;  ///< probes that landed near the cell (its box grown by h/2)
  double spread_deg = 0;       ///< largest angle between two normals near the cell
  double area = 0;             ///< estimated surface area in the cell
  [[nodiscard]] bool meets() const { return !points.empty() || both_signs; }
};

/// Probes every box with a 3×3×3 lattice (one batch for all boxes).
std::vector<CellProbe> probe_cells(const Field& field, std::span<const Aabb> boxes,
                                   const Context* ctx);

/// The leaves of the adaptive octree under `root` (see adaptive_cells, which uses min_depth =
/// kMinDepth; cells are always split down to min_depth) that meet the surface,
/// visiting only cells that intersect `region` (an empty region means everywhere). `probes`
/// (when non-null) receives the probe of each returned cell.
/// With `max_leaves` > 0, no level is split that would make the leaves outnumber it (about
/// four surface children per split cell).
std::vector<ParticleCell> octree_cells(const Field& field, const ParticleOptions& options,
                                       int min_depth, const Aabb& root, const Aabb& region,
                                       std::vector<CellProbe>* probes, const Context* ctx,
                                       std::size_t max_leaves = 0);

/// The root cube adaptive_cells uses for a field.
Aabb root_cube(const Field& field);

/// Runs `iterations` Jacobi steps on positions[0, n_free) (positions[n_free, n) are fixed
/// neighbours), then projects the free particles onto the surface. Returns the free
/// particles' residuals |f − iso| / |∇f| (infinity: not on the surface), their gradients, and
/// the gradients at their starting positions (the seeding normals of eq. 11).
struct SimulationResult {
  std::vector<double> residual;
  std::vector<Vec3> gradient;
  std::vector<Vec3> initial_gradient;
};
SimulationResult simulate(const Field& field, std::vector<Vec3>& positions,
                          std::span<const double> delta, std::size_t n_free, int iterations,
                          const Context* ctx);

/// Nearest-neighbour distance of each of the first n_free particles among all of them
/// (infinity when none lies within its δ level's cell).
std::vector<double> nearest_distances(std::span<const Vec3> positions,
                                      std::span<const double> delta, std::size_t n_free,
                                      const Context* ctx);

/// Coefficient of variation of nn[i] / delta[i] over the finite entries.
double spacing_cv(std::span<const double> nn, std::span<const double> delta);

/// The eq. 2 weight: a quadratic B-spline falling from 1 at t = 0 to 0 at t = 1 (C1, flat at
/// both ends); t is clamped to [0, 1].
double depth_weight(double t);

}  // namespace ramiform::particles_detail
