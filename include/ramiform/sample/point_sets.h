// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Point distributions inside, near and on implicit surfaces and triangle meshes, from the thesis
/// Kochhar 2010, *Application of implicit methods to the interactive modeling of trees* (M.Sc.
/// thesis, University of Calgary), chapters 5-6 and §7.1; "thesis" below means this one. These
/// point sets feed space colonization (grow/).
///
/// Every sampler is deterministic: equal inputs and seed give identical points on any thread
/// count (candidates are drawn in fixed blocks from `Rng::split(block)`, field values are
/// computed in parallel, and acceptance runs in candidate order). Every sampler first cuts the
/// sampling box into cells and drops those where the field's conservative `bound()` shows the
/// target set cannot be (cells where the bound shows every point qualifies accept candidates
/// without evaluating the field). All distributions stop at `count` points or when they cannot
/// place more; `SampleStats::saturated` says which. See docs/sampling.md.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/sample/props.h"

namespace ramiform {

/// What a sampler did.
struct SampleStats {
  std::size_t points = 0;         ///< points returned
  std::size_t attempts = 0;       ///< candidates drawn
  std::uint64_t field_evals = 0;  ///< field evaluations (the field's counter difference)
  bool saturated = false;  ///< stopped before `count`: no room left, or attempt budget spent
  double seconds = 0;      ///< wall time
};

/// Uniform rejection sampling inside the surface (f > iso), thesis §6.1.
struct UniformOptions {
  std::size_t count = 1000;       ///< number of points (>= 0)
  std::size_t max_attempts = 0;   ///< candidate budget; 0 = 1000 * count + 10^6
};

/// Stratified (jittered grid) sampling inside the surface (thesis §5.1, Figure 5.1): one
/// jittered point per grid cell, the grid spacing chosen so that at least `count` cells'
/// points fall inside; then exactly `count` of those points are kept (a seeded random subset,
/// returned in grid order).
struct StratifiedOptions {
  std::size_t count = 1000;  ///< number of points (>= 0)
};

/// Poisson-disk sampling inside the surface by dart throwing with a background grid (Cook;
/// thesis §5.1): candidates uniform inside, accepted when at least `min_distance` from every
/// accepted point. Stops at `count`, or (saturated) after `max_failures` consecutive inside
/// candidates fell too close to accepted points.
struct PoissonOptions {
  std::size_t count = 1000;    ///< number of points (>= 0)
  /// Minimum distance between any two points (model units, >= 0); 0 = automatic: 0.75 (V /
  /// count)^(1/3) for the estimated inside volume V (about 60 % of the saturation density).
  double min_distance = 0.0;
  std::size_t max_failures = 20000;  ///< consecutive too-close candidates that mean saturation
  std::size_t max_attempts = 0;      ///< candidate budget; 0 = 1000 * count + 10^6
};

/// A radial kernel of Lane's method (thesis §5.2.2, Figures 5.7 and 5.9): after each point the
/// pdf at distance d from it is multiplied by factor(d). `table` holds (distance, factor) pairs
/// with non-decreasing distances starting at 0 and factors >= 0; factor(d) interpolates
/// linearly between pairs (a repeated distance makes a step; at the step the later factor
/// applies) and is 1 beyond the last pair. An empty table is the identity (uniform points).
struct LaneKernel {
  std::vector<std::pair<double, double>> table;  ///< (distance in model units, factor) pairs

  /// Figure 5.7: factor 0 within `radius`, 1 beyond (gives Poisson-disk-like sets).
  [[nodiscard]] static LaneKernel disk(double radius);
  /// Figure 5.9: factor 0 within `zero_radius`, `factor` (> 1 clusters) up to `ring_radius`,
  /// then 1.
  [[nodiscard]] static LaneKernel ring(double zero_radius, double ring_radius, double factor);
  /// Parses "none", "disk R", "ring R0 R1 F", or "table d0 f0 d1 f1 ..." (numbers separated by
  /// spaces or commas). Throws InvalidArgument naming the problem.
  [[nodiscard]] static LaneKernel parse(const std::string& text);

  /// factor(d) for d >= 0.
  [[nodiscard]] double factor(double d) const;
  /// The end of the kernel's initial zero run: factor(d) == 0 for all d < zero_radius().
  [[nodiscard]] double zero_radius() const;
  /// The last table distance (0 for the identity).
  [[nodiscard]] double reach() const;
  /// Throws InvalidArgument naming the bad pair.
  void validate() const;
};

/// Lane and Prusinkiewicz's method in 3-D (thesis §5.2.2, §6.1): a piecewise-constant pdf on a
/// voxel grid over the bounding box, deformed by `kernel` after each point (the factor taken at
/// each voxel centre). A voxel is chosen from the pdf, a point uniform in it, and the point is
/// kept when it is inside and no accepted point lies closer than kernel.zero_radius() (checked
/// at the exact distance, so the disk kernel guarantees that minimum distance); otherwise it is
/// drawn again. Saturated when the pdf is zero everywhere or the attempt budget is spent.
struct LaneOptions {
  std::size_t count = 1000;  ///< number of points (>= 0)
  LaneKernel kernel;         ///< pdf deformation after each point; empty = none
  std::size_t grid = 64;     ///< voxels along the longest box axis (2..512)
  /// Start with pdf 1 only in voxels the field's bound() says may hold inside points (true), or
  /// in every voxel of the box as the thesis does (false: same distribution, more rejections).
  bool prune_grid = true;
  std::size_t max_attempts = 0;  ///< candidate budget; 0 = 1000 * count + 10^6
};

/// Density driven by field values (thesis §6.1, Figure 6.3b): inside, with density proportional
/// to (iso / f)^exponent — inversely proportional to the field for exponent 1, so points are
/// dense near the boundary and sparse deep inside. Rejection: a uniform inside candidate is kept
/// with probability (iso / f)^exponent (requires iso > 0).
struct FieldDensityOptions {
  std::size_t count = 1000;    ///< number of points (>= 0)
  double exponent = 1.0;       ///< density ~ f^-exponent (finite, >= 0)
  double min_distance = 0.0;   ///< optional Poisson-disk minimum distance (>= 0; 0 = none)
  std::size_t max_attempts = 0;  ///< candidate budget; 0 = 1000 * count + 10^6
};

/// Points near the boundary, inside (thesis Figure 6.3a): density 1 where iso < f < iso + width,
/// `interior_density` (0..1) deeper inside.
struct BoundaryOptions {
  std::size_t count = 1000;  ///< number of points (>= 0)
  /// Width of the boundary layer in field units (> 0); 0 = 0.2 * |iso| (0.2 if iso is 0).
  double width = 0.0;
  double interior_density = 0.0;  ///< relative density deeper inside, in [0, 1]
  double min_distance = 0.0;      ///< optional Poisson-disk minimum distance (>= 0; 0 = none)
  std::size_t max_attempts = 0;   ///< candidate budget; 0 = 1000 * count + 10^6
};

/// Points outside and near the surface: iso - epsilon < f < iso (thesis §6.2.1), near-uniform
/// (`Method::kProject`) or uniform (`Method::kReject`) in that band, or Poisson-disk with
/// `min_distance`. Every returned point satisfies the band condition for the exact field value,
/// whichever method or speed-up is used.
struct NearSurfaceOptions {
  /// How candidates become band points.
  enum class Method : std::uint8_t {
    /// Candidates uniform in the cells whose bound() meets a wider band |f - c| < W / 2 around
    /// the band's centre c = iso - epsilon / 2 (W = `project_width`); each one in that wider
    /// band is moved along the gradient by Newton steps (at most two, each at most one cell
    /// long) to the value t = c + (f - c) epsilon / W, i.e. the wider band is compressed onto
    /// the band, and kept only if the exact value at the moved point is in the band. Exactly
    /// uniform in the band where f is affine across the wider band; otherwise the density per
    /// unit of surface area is right to first order in W (curvature and gradient change cancel
    /// between the two halves of the wider band) and varies slightly across the band's
    /// thickness. On the benchmark surface about 30x more candidates become band points than
    /// with rejection (docs/sampling.md, "Speed"). Not in the thesis; it applies when use_cache
    /// and use_lane_grid are off and prune is on (those are the thesis's rejection variants,
    /// which ignore `method`).
    kProject,
    /// Rejection (thesis §6.2.1): candidates uniform in the bound-pruned cells, kept when their
    /// value is in the band. Exactly uniform in the band; slow when the band is thin.
    kReject,
  };
  std::size_t count = 1000;          ///< number of points (>= 0)
  double epsilon = 0.01;             ///< band width in field units (> 0)
  double min_distance = 0.0;         ///< Poisson-disk minimum distance (>= 0; 0 = none)
  Method method = Method::kProject;  ///< projection (default) or rejection, see Method
  /// kProject: width W of the wider band in field units (0 = automatic, else >= epsilon).
  /// Automatic: 0.2 sampling-cell edges (box longest side / 128) times the median gradient
  /// norm near the band (from 2048 pilot points), at most the distance from the band's centre
  /// to the smallest and to the largest pilot value (so the wider band stays clear of the flat
  /// 0 outside compact-support primitives), at least epsilon. Larger W keeps more candidates
  /// but moves them farther, where the field is less affine.
  double project_width = 0.0;
  /// §6.2.2 field cache: cubes of edge `cache_cell` along the band (found by bound-pruned
  /// subdivision, kept in a hash table) with the field cached at their corners. A candidate
  /// outside every cube is rejected without evaluation (no band point can be there); inside a
  /// cube the trilinear interpolation of the corners pre-classifies it, and only candidates whose
  /// interpolated value lies within `cache_tolerance` of the band are evaluated exactly.
  bool use_cache = false;
  double cache_cell = 0.0;  ///< cache cube edge (model units); 0 = longest box side / 64
  /// Pre-filter slack in field units (>= 0); 0 = automatic per cube: max(epsilon, a quarter of
  /// the spread of its corner values). Too small a slack loses band points where the field
  /// bends within a cube (the result is then slightly non-uniform, never wrong).
  double cache_tolerance = 0.0;
  /// §6.2.3: draw candidates with Lane's method from a voxel grid whose pdf is non-zero only in
  /// voxels that may meet the band (bound-based, and within a cache cube when use_cache); with
  /// min_distance > 0 its kernel is the disk of that radius.
  bool use_lane_grid = false;
  std::size_t grid = 64;  ///< Lane grid voxels along the longest box axis (2..512)
  /// Skip space with the field's bound() (true). false reproduces the thesis's baselines
  /// (Tables 6.1-6.2, first rows): candidates uniform in the whole box, or Lane's pdf 1 in every
  /// voxel. Same guarantee, many more rejections; for benchmarks and checks.
  bool prune = true;
  /// Sampling box; empty = automatic: bounds() grown until the field's bound on a shell around
  /// it is <= iso - epsilon (at most by the box diagonal on each side).
  Aabb box;
  std::size_t max_attempts = 0;  ///< candidate budget; 0 = 1000 * count + 10^6
};

/// Points near a triangle mesh (thesis §6.3): a triangle chosen with probability proportional
/// to its area (inverse CDF), a uniform point in it (Turk), moved along the interpolated
/// vertex normal (the mesh's normals if it has one per vertex, else area-weighted face normals,
/// interpolated barycentrically and normalized) by an offset uniform in [min_offset,
/// max_offset]. The distance of a point to the mesh is at most |offset|; for a point offset
/// outward from a convex mesh it is at least offset * cos(angle between the interpolated and
/// the face normal).
struct NearMeshOptions {
  std::size_t count = 1000;  ///< number of points (>= 0)
  double min_offset = 0.0;   ///< model units (may be negative: inside)
  double max_offset = 1.0;   ///< model units, >= min_offset
};

/// The inside samplers: points with f > iso. `ctx` gives threads, progress and cancellation
/// (throws Cancelled); `stats` may be null. Throw InvalidArgument naming a bad option.
[[nodiscard]] PointSet sample_uniform(const Field& field, const UniformOptions& options,
                                      std::uint64_t seed, Context* ctx = nullptr,
                                      SampleStats* stats = nullptr);
[[nodiscard]] PointSet sample_stratified(const Field& field, const StratifiedOptions& options,
                                         std::uint64_t seed, Context* ctx = nullptr,
                                         SampleStats* stats = nullptr);
[[nodiscard]] PointSet sample_poisson(const Field& field, const PoissonOptions& options,
                                      std::uint64_t seed, Context* ctx = nullptr,
                                      SampleStats* stats = nullptr);
[[nodiscard]] PointSet sample_lane(const Field& field, const LaneOptions& options,
                                   std::uint64_t seed, Context* ctx = nullptr,
                                   SampleStats* stats = nullptr);
[[nodiscard]] PointSet sample_field_density(const Field& field,
                                            const FieldDensityOptions& options,
                                            std::uint64_t seed, Context* ctx = nullptr,
                                            SampleStats* stats = nullptr);
[[nodiscard]] PointSet sample_boundary(const Field& field, const BoundaryOptions& options,
                                       std::uint64_t seed, Context* ctx = nullptr,
                                       SampleStats* stats = nullptr);
/// Points with iso - epsilon < f < iso (see NearSurfaceOptions).
[[nodiscard]] PointSet sample_near_surface(const Field& field, const NearSurfaceOptions& options,
                                           std::uint64_t seed, Context* ctx = nullptr,
                                           SampleStats* stats = nullptr);

/// Points near a mesh (see NearMeshOptions); each point's normal is the direction it was moved
/// along. Throws InvalidArgument for bad options, InputError for a mesh without triangles of
/// positive area or with an out-of-range index.
[[nodiscard]] PointSet sample_near_mesh(const TriMesh& mesh, const NearMeshOptions& options,
                                        std::uint64_t seed);

/// Thinning (thesis §7.1, `point_set_thin crown secondary 80`): of the n points inside
/// `secondary` (f > iso), removes round(percent / 100 * n); points outside are all kept. The
/// thesis removes "the first d% n"; here the removed ones are a uniformly random subset chosen
/// with `seed` (partial Fisher-Yates), so the thinned region keeps its distribution. The
/// survivors keep their order (and normals). `percent` in [0, 100] (InvalidArgument otherwise).
/// `secondary` is evaluated on `ctx`'s threads (nullptr: all cores).
[[nodiscard]] PointSet thin_points(const PointSet& points, const Field& secondary, double percent,
                                   std::uint64_t seed, const Context* ctx = nullptr);

/// The distribution names: "uniform", "stratified", "poisson", "lane", "field" (density from
/// field values), "boundary" (denser near the surface, Figure 6.3a), "near_surface"
/// (f in (iso - eps, iso)).
[[nodiscard]] std::vector<std::string> distribution_names();

/// The props keys distribution `name` accepts (docs/sampling.md); InvalidArgument for an
/// unknown name.
[[nodiscard]] std::vector<std::string> distribution_keys(const std::string& name);

/// Samples `field` with distribution `name`, reading its parameters from `props` (keys in
/// docs/sampling.md: count, min_distance, epsilon, cache, grid, kernel, ...);
/// `count_override` > 0 replaces props' count (default 1000). Throws InvalidArgument for an
/// unknown distribution (naming the closest) and InputError (props.source, line) for a bad or
/// unknown key.
[[nodiscard]] PointSet generate_points(const Field& field, const std::string& name,
                                       const Props& props, std::uint64_t seed,
                                       std::size_t count_override = 0, Context* ctx = nullptr,
                                       SampleStats* stats = nullptr);

}  // namespace ramiform
