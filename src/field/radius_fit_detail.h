// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the pieces shared by the radius fit (radius_fit_system.cpp, radius_fit.cpp,
// radius_fit_coverage.cpp) and the radius measurement (radius_error.cpp): the edges as the
// convolution field sees them and the requested shape, the union of the edges' tubes.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "field/bvh.h"
#include "ramiform/core/context.h"
#include "ramiform/core/types.h"
#include "ramiform/field/radius_fit.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform::detail {

/// Points per parallel chunk when building rows and checking tubes.
inline constexpr std::size_t kRowGrain = 512;

/// One edge as the convolution field sees it.
struct EdgeGeometry {
  Vec3 a, b, u, e1, e2;            ///< end points, unit direction, unit frame perpendicular to u
  double len = 0, ra = 1, rb = 1;  ///< length, node radii at a and b
};

/// One EdgeGeometry per edge of a valid skeleton (no zero-length edges).
[[nodiscard]] std::vector<EdgeGeometry> edge_geometry(const Skeleton& skeleton);

/// The requested shape: the union of the tubes {p : d(p, segment) < r(t*)}, t* the closest
/// point parameter (clamped, so the tube ends in spheres of the node radii). Keeps a reference
/// to `edges`.
/// A point counts as inside another edge's requested tube only when it is deeper than this
/// fraction of that tube's radius: circles of a straight chain's shared node lie exactly on both
/// tubes, and rounding must not decide whether they are kept.
inline constexpr double kInsideMargin = 1e-3;

class TubeIndex {
 public:
  explicit TubeIndex(const std::vector<EdgeGeometry>& edges);

  /// Edges whose tube box meets `box`, appended to ids (unordered).
  void query(const Aabb& box, std::vector<std::uint32_t>& ids) const { bvh_.query(box, ids); }

  /// True when p is deeper than `margin` (a fraction of the tube's radius there) inside the
  /// requested tube of edge e.
  [[nodiscard]] bool inside(const Vec3& p, std::uint32_t e, double margin = kInsideMargin) const;

  /// True when p is deeper than `margin` inside the requested tube of an edge other than `own`
  /// (ids: scratch space).
  [[nodiscard]] bool inside_other(const Vec3& p, std::uint32_t own, std::vector<std::uint32_t>& ids,
                                  double margin = kInsideMargin) const;

 private:
  const std::vector<EdgeGeometry>& edges_;
  BoxBvh bvh_;
};

/// Throws InvalidArgument "`what` must be >= `min`, got `v`" when v < min.
void check_at_least(int v, int min, const std::string& what);

/// The skeleton coverage repair of RadiusFitOptions::coverage_margin: samples every half radius
/// along every edge (ends included) and raises the weights `w` (one per edge) of edges with a
/// sample below the level; records its rounds in `result`.
void cover_skeleton(const RadiusFitSystem& system, const RadiusFitOptions& options,
                    Eigen::VectorXd& w, RadiusFitResult& result, Context* ctx);

}  // namespace ramiform::detail
