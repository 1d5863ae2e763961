// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// How far a mesh lies from the implicit surface it approximates: points drawn on the mesh
/// (area-weighted, a fixed seed) and the mesh's vertices are each projected onto the surface
/// f == iso, and the distance is reported in model units and relative to the local skeleton
/// radius (the radius of the nearest skeleton edge, interpolated at its closest point).
///
/// The projection of a point p (`distance_to_surface`):
///  1. the surface is bracketed along the gradient line through p, on the side where |f - iso|
///     falls (a first step of 1.2 times the first-order estimate |f - iso| / |grad f|, then
///     doubling steps of at most 1/16 of the search distance: a shell thinner than that can be
///     stepped over), then the root on that line is found to 1e-12 of the bracket
///     (core/roots.h). Where the gradient vanishes or the line holds no crossing, the other side
///     and the six axis directions are searched the same way and the nearest crossing is kept;
/// 2. the foot point is refined: the tangential part of p - y is added to the current surface
///     point y and the result is taken back to the surface by Newton steps along the gradient;
///     a step is kept only when it brings the surface point closer to p. At the closest point,
///     p - y is normal to the surface, so the refinement stops there.
/// Every surface point found is on the surface (to the root tolerance), so the reported distance
/// is never below the true distance; it equals it where the gradient line through p meets the
/// surface at its closest point (spheres, capsules, tori of distance and point fields) and is
/// refined towards it elsewhere. `measure_deviation` evaluates all its points in one batch
/// first: a sample point within 1e-7 of the search distance of the surface to first order (a
/// polygonizer's vertex) takes the first-order distance |f - iso| / |grad f| (its error is of
/// the order of its square over the curvature radius). For the mesh's vertices, which a mesher
/// put on the surface to within its own tolerance (the particle mesher: |f - iso| <= delta
/// iso), the shortcut applies within 1e-3 of the search distance: the first-order error is
/// then below 1e-3 of the distance itself for curvature radii of the search distance's order. A point where no crossing is found
/// within the search distance is *unresolved*: it is counted at the search distance (it has no
/// surface closer along any line searched) and the report says how many there were.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Options of `measure_deviation`; validated at entry (InvalidArgument naming the option).
struct DeviationOptions {
  std::size_t samples = 20000;  ///< area-weighted points on the mesh (0: none)
  std::uint64_t seed = 1;       ///< seed of the sample points
  bool vertices = true;         ///< also measure at every vertex used by a triangle
  /// With a skeleton: how far to search for the surface, in local radii (> 0).
  double search_radii = 4.0;
  /// Without a skeleton: how far to search, in model units; 0 means a tenth of the mesh's
  /// bounding-box diagonal.
  double search_distance = 0.0;
  int refine_steps = 8;  ///< foot-point refinements per point (>= 0)
};

/// One point's projection onto the surface.
struct SurfaceDistance {
  double distance = 0.0;  ///< |p - foot|; the search distance when unresolved
  Vec3 foot = Vec3::Zero();  ///< the surface point found (p when unresolved)
  bool resolved = false;     ///< a surface point was found within the search distance
};

/// Projects `point` onto the surface f == iso of `field`, searching up to `search` (> 0, model
/// units) away (see the file comment). Never throws for a point: a non-finite value or gradient
/// makes the point unresolved.
[[nodiscard]] SurfaceDistance distance_to_surface(const Field& field, const Vec3& point,
                                                  double search, int refine_steps = 8);

/// The local radius at each point: the radius of the skeleton edge nearest to it, linearly
/// interpolated at the edge's closest point (an isolated node counts as an edge of length 0;
/// ties go to the lower edge index). The skeleton must have at least one node (InvalidArgument
/// otherwise). Parallel; deterministic.
[[nodiscard]] std::vector<double> local_radii(const Skeleton& skeleton,
                                              std::span<const Vec3> points,
                                              const Context* ctx = nullptr);

/// Deviation figures over a set of points. Percentiles are nearest-rank (the value at sorted
/// index ceil(q n) - 1).
struct DeviationSummary {
  std::size_t points = 0;      ///< points measured
  std::size_t unresolved = 0;  ///< points without a surface point within the search distance
  /// Distance relative to the local radius (0 without a skeleton).
  double p50 = 0.0, p99 = 0.0, max = 0.0;
  /// Distance in model units.
  double abs_p50 = 0.0, abs_p99 = 0.0, abs_max = 0.0;
  /// The point of largest deviation (relative with a skeleton, absolute without).
  Vec3 worst = Vec3::Zero();
};

/// What `measure_deviation` found.
struct DeviationReport {
  DeviationSummary samples;   ///< the area-weighted points on the mesh
  DeviationSummary vertices;  ///< the vertices used by triangles (empty when not asked)
  bool relative = false;      ///< a skeleton gave local radii (relative figures are set)
  std::uint64_t field_evaluations = 0;  ///< evaluations made by the measure
};

/// Measures how far `mesh` lies from the surface of `field` (see the file comment). `skeleton`
/// (may be null) gives the local radii for the relative figures and the search distance. Throws
/// InvalidArgument for bad options or a skeleton without nodes, InputError for a mesh vertex
/// index out of range or a non-finite vertex, Cancelled through `ctx`. A mesh without
/// triangles of positive area gets no samples. Parallel; the result does not depend on the
/// thread count.
[[nodiscard]] DeviationReport measure_deviation(const TriMesh& mesh, const Field& field,
                                                const Skeleton* skeleton,
                                                const DeviationOptions& options = {},
                                                Context* ctx = nullptr);

}  // namespace ramiform
