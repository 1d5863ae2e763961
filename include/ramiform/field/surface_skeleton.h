// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Parametric surfaces as skeletons: Rigaudière, Gesquière & Faudot, "Shape Modelling with
/// Skeleton based Implicit Primitives", §4 (distance to a parametric surface), §4.1 (subdivision
/// by the colinearity of the side derivatives, Figure 14), §4.2 (superquadrics), §4.3 (the
/// parameters u, v of the nearest point drive anisotropic fields). Superquadric ellipsoids follow
/// Barr 1981, "Superquadrics and angle-preserving transformations", IEEE CG&A 1 (1) (the
/// superquadric ellipsoid, with signed powers).
///
/// The surface is subdivided into flat sub-patches; each is replaced by the two triangles of its
/// corners (split along the diagonal from (u0, v0) to (u1, v1)), with u and v carried linearly,
/// and the distance is the distance to those triangles, found through a BVH. `error_bound()`
/// says how far that can be from the distance to the true surface.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform {

/// A parametric surface S(u, v) over [0,1]^2 (model units). Implementations are immutable and
/// safe to evaluate from several threads.
class ParametricSurface {
 public:
  virtual ~ParametricSurface() = default;
  /// S(u, v) for u, v in [0, 1].
  [[nodiscard]] virtual Vec3 point(double u, double v) const = 0;
  /// dS/du and dS/dv (model units per unit parameter; may be zero/degenerate at poles).
  virtual void derivatives(double u, double v, Vec3& su, Vec3& sv) const = 0;
  /// A one-line description for messages.
  [[nodiscard]] virtual std::string describe() const = 0;
  /// Depth to which SurfaceSkeleton subdivides at least, whatever the flatness test says: 0 for
  /// an open patch; closed surfaces whose whole parameter square fails to be approximated by two
  /// triangles (superquadrics: 2) say so here.
  [[nodiscard]] virtual int minimum_depth() const { return 0; }
};

/// Bicubic Bezier patch; controls[4 * i + j] is b_ij, i along u, j along v (model units).
/// S(u, v) = sum_ij B_i(u) B_j(v) b_ij with the cubic Bernstein polynomials B.
struct BicubicPatch {
  std::array<Vec3, 16> controls;  ///< b_ij at index 4 i + j
};

/// Barr's superquadric ellipsoid: x = a1 c(η)^e1 c(ω)^e2, y = a2 c(η)^e1 s(ω)^e2,
/// z = a3 s(η)^e1 with signed powers (c^e = sign(c)|c|^e), η = π(v - 1/2) in [-π/2, π/2],
/// ω = π(2u - 1) in [-π, π], then rotated by `rotation` (orthonormal) and moved to `center`.
/// v = 0 and v = 1 are the poles (-z and +z), u = 0 and u = 1 the same seam. e1 = e2 = 1 is an
/// ellipsoid, e -> 0 a box, e = 2 an octahedron, e > 2 pinched.
struct Superquadric {
  Vec3 center = Vec3::Zero();        ///< model units
  Vec3 radii = Vec3::Ones();         ///< a1, a2, a3 > 0, model units
  double e1 = 1;                     ///< north-south exponent, in (0, 10]
  double e2 = 1;                     ///< east-west exponent, in (0, 10]
  Mat3 rotation = Mat3::Identity();  ///< orthonormal (|R^T R - I| <= 1e-9), det +1 or -1
};

/// Validates (throws InvalidArgument naming the non-finite control point's index) and wraps.
/// Outside [0,1]^2 the polynomial is extrapolated.
[[nodiscard]] std::shared_ptr<const ParametricSurface> make_patch_surface(const BicubicPatch& p);
/// Validates (throws InvalidArgument naming the bad parameter: a non-finite center, radii not
/// finite and > 0, e1 or e2 outside (0, 10], a rotation that is not orthonormal) and wraps.
/// The derivatives are exact except where they are unbounded (exponent < 1 at a zero of the
/// cosine or sine): there |c|^(e-1) is evaluated with |c| raised to 1e-16, so they stay finite
/// (huge) and keep their direction. minimum_depth() is 2: at depth 0 and 1 the corners of the
/// closed surface coincide in pairs (seam, poles) and the two triangles would be degenerate.
[[nodiscard]] std::shared_ptr<const ParametricSurface> make_superquadric_surface(
    const Superquadric& q);

/// Options of the curvature-adaptive subdivision (paper §4.1).
struct SubdivisionOptions {
  /// A sub-patch is flat when, on each of its 4 sides, the angle between the derivative along
  /// that side at the side's two end vertices is <= epsilon (paper §4.1, Figure 14); degrees,
  /// in (0, 90].
  double epsilon_degrees = 10;
  /// At most 4^max_depth sub-patches (the paper shows 4 and 6); 0..10. A surface's
  /// minimum_depth() overrides a lower value.
  int max_depth = 6;
  /// Beyond the paper: a sub-patch that passes the angle test is still split (up to max_depth)
  /// while its error bound (error_bound(), per leaf) exceeds this, model units; 0 (the default)
  /// applies the paper's test alone. The angle test misses bulges inside a sub-patch.
  double max_error = 0;
};

/// Result of a projection onto the flat approximation.
struct SurfaceProjection {
  double distance = 0;        ///< distance to the approximation (piecewise planar), model units
  double u = 0, v = 0;        ///< parameters of the nearest point (linear over each triangle)
  Vec3 point = Vec3::Zero();  ///< nearest point on the approximation
  /// Gradient of distance w.r.t. the query point (unit, or 0 on the surface).
  Vec3 gradient = Vec3::Zero();
  /// Exact gradients of u and v w.r.t. the query point for the piecewise-linear definition
  /// (interior of a triangle: the in-plane affine map's gradient; on an edge: along the edge;
  /// at a vertex: 0); per model unit.
  Vec3 grad_u = Vec3::Zero(), grad_v = Vec3::Zero();
  std::uint32_t triangle = 0;  ///< index of the nearest triangle (see SurfaceSkeleton::triangle)
};

/// One triangle of the approximation: 3 vertices and their (u, v) each.
struct SkeletonTriangle {
  std::array<Vec3, 3> vertices;  ///< model units
  std::array<Vec2, 3> uv;        ///< surface parameters of the vertices
};

/// A surface subdivided by the curvature test into flat sub-patches, each replaced by the two
/// triangles of its corners (u, v carried linearly), with a BVH over the triangles.
/// Immutable after construction; queries are thread-safe and allocate nothing.
class SurfaceSkeleton {
 public:
  /// Subdivides `surface` (paper §4.1): a leaf [u0,u1]x[v0,v1] is split in four when the angle
  /// between S_u at (u0,v0) and (u1,v0), S_u at (u0,v1) and (u1,v1), S_v at (u0,v0) and (u0,v1),
  /// or S_v at (u1,v0) and (u1,v1) exceeds epsilon, unless its depth is max(max_depth,
  /// surface->minimum_depth()); leaves shallower than minimum_depth() are always split. Throws
  /// InvalidArgument for a null surface, a bad option (named), or a surface that is not finite
  /// at a sub-patch corner. A derivative shorter than 1e-12 times the surface's size is zero;
  /// a zero one at a corner is replaced by the derivative 1/64 of the side further along the
  /// side (so the seam of a pinched superquadric, e > 1, where all corner derivatives vanish,
  /// is still tested), and if that is zero too (a pole: S_u vanishes along the whole side) the
  /// side counts as flat.
  explicit SurfaceSkeleton(std::shared_ptr<const ParametricSurface> surface,
                           const SubdivisionOptions& options = {});

  /// The nearest point of the triangles to `p` (through the BVH; ties: lowest triangle index).
  /// Degenerate triangles (at superquadric poles) act as their longest edge.
  [[nodiscard]] SurfaceProjection project(const Vec3& p) const;
  /// Lower and upper bound of the distance (to the approximation) over a box (conservative; for
  /// Field::bound): the distance at the centre -/+ the half diagonal (the distance is
  /// 1-Lipschitz), the lower end raised to the distance between `box` and box().
  [[nodiscard]] std::pair<double, double> distance_range(const Aabb& box) const;
  /// Bounding box of the triangles.
  [[nodiscard]] const Aabb& box() const { return box_; }
  /// Number of leaf sub-patches.
  [[nodiscard]] std::size_t patch_count() const { return patch_count_; }
  /// Deepest leaf's depth (0: the whole square is one leaf).
  [[nodiscard]] int depth_reached() const { return depth_reached_; }
  /// Bound on |distance to the true surface - distance to the approximation| (model units): the
  /// max over leaves of the Hausdorff distance between the leaf's true piece and its two
  /// triangles. Bezier patches: guaranteed, via a bound on |S(u, v) - T(u, v)| (T the triangles
  /// as a linear map of (u, v); convex hull property) — the de Casteljau sub-patch control
  /// points against the bilinear interpolant of the corners at (i/3, j/3), plus the
  /// triangles-vs-bilinear twist term |b00 - b30 - b03 + b33| / 4. Superquadrics and other
  /// surfaces (not polynomial; superquadric derivatives are unbounded at the poles for exponents
  /// < 1): an estimate by dense sampling of the Hausdorff distance itself (error_is_estimate()):
  /// per leaf, the distance from a 9 x 9 grid of surface points to the two triangles, and from
  /// a 5 x 5 grid of triangle points to the mesh of the 9 x 9 grid's even points (a 4 x 4-cell
  /// approximation 16 times finer). The parametric gap |S - T| is not used there: on the flat
  /// faces of a boxy superquadric the parametrization is so non-uniform that it would report
  /// errors of a tenth of the radius where the triangles lie on the surface.
  [[nodiscard]] double error_bound() const { return error_bound_; }
  /// True when error_bound() is a sampled estimate rather than a guaranteed bound.
  [[nodiscard]] bool error_is_estimate() const { return error_is_estimate_; }
  /// Number of triangles (two per leaf sub-patch).
  [[nodiscard]] std::size_t triangle_count() const { return triangles_.size(); }
  /// Triangle `i` (< triangle_count(); throws InvalidArgument otherwise), for pictures/tests.
  [[nodiscard]] SkeletonTriangle triangle(std::size_t i) const;
  /// The surface this skeleton approximates.
  [[nodiscard]] const ParametricSurface& surface() const { return *surface_; }

 private:
  /// A triangle with the (u, v) of its vertices. A degenerate one (zero area) has its longest
  /// edge as a–b and acts as that segment.
  struct Tri {
    Vec3 a, b, c;
    Vec2 uva, uvb, uvc;
    bool is_segment = false;
  };
  struct Bvh;  // detail::BoxBvh, kept out of the public header

  std::shared_ptr<const ParametricSurface> surface_;
  std::vector<Tri> triangles_;
  std::shared_ptr<const Bvh> bvh_;  // shared: copies of a skeleton share the immutable tree
  Aabb box_;
  std::size_t patch_count_ = 0;
  int depth_reached_ = 0;
  double error_bound_ = 0;
  bool error_is_estimate_ = false;
};

}  // namespace ramiform
