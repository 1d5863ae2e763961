// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Anisotropic skeleton primitives of Rigaudière, Gesquière & Faudot, "Shape Modelling with
/// Skeleton based Implicit Primitives" (Le2i, Université de Bourgogne): segments (§3.1–3.2),
/// Bezier curves of any degree (§3.3–3.5) and parametric surfaces — bicubic Bezier patches and
/// Barr's superquadrics (§4–4.3) — each skinned by a distance kernel,
///
///   F(M) = weight * k( d(M, Sk) * def(t) / (r(t) / x_iso) ),
///
/// d the Euclidean distance to the skeleton (for surfaces: to its flat-patch approximation,
/// field/surface_skeleton.h), t the parameter of the orthogonal projection (t in [0, 1] on
/// segments and curves, (u, v) in [0, 1]^2 on surfaces), def(t) the deformation function of §3.2
/// (def(u, v) = def_u(u) def_v(v) on surfaces, §4.3), r(t) the radius (one per control point of
/// a curve, Bernstein-interpolated; constant otherwise) and k a distance kernel (kernels.h:
/// Wyvill by default; Murakami's function of the paper's Figure 15 is the `metaball` kernel of
/// Nishimura et al.). With def = 1 the surface lies exactly r(t) away from the skeleton; def(t)
/// = 2 halves the thickness there; def(t) = infinity removes the skeleton's neighbourhood at t.
///
/// Gradients are exact: grad(d def / r) = (def / r) grad d + d (def' / r - def r' / r^2) grad t,
/// with grad t = C'(t) / (|C'|^2 + C''·(C - M)) at an interior projection of a curve (implicit
/// function theorem on C'(t)·(C(t) - M) = 0) and 0 at an end; a surface's (u, v) are linear over
/// each triangle of its approximation. bound(box) uses the distance range over the box and the
/// extremes of def and r over the whole parameter range (conservative, loose for strongly
/// varying def). Primitives blend with every other field and operator (operators.h).

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "ramiform/field/bezier_curve.h"
#include "ramiform/field/field.h"
#include "ramiform/field/primitives.h"
#include "ramiform/field/surface_skeleton.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// A deformation function def(t) on [0, 1] (paper §3.2 and Figures 3a, 4): it multiplies the
/// distance, so the skin's thickness at t is r(t) / def(t).
struct Deformation {
  enum class Kind {
    kIdentity,       ///< def = 1 (an isotropic skin)
    kSquaredCosine,  ///< Figure 3: 1 / (s + (1 - s) sin^2(pi t)); s = `parameter` in [0, 1], the thickness at the ends relative to the middle (0: pointed ends)
    kFlatEnds,       ///< Figure 4: (1 - |2t - 1|^n)^(-1/n), n = `parameter` >= 2 (default 8): a cylinder with flat, slightly rounded ends (a superellipse profile), infinite at t = 0 and 1
    kWave,           ///< Figure 18: 1 / (1 + a cos(2 pi w t)), a = `parameter` in [0, 1), w = `waves` > 0
    kLinear,         ///< piecewise linear through `values` at t = i / (m - 1), m >= 2
    kBezier,         ///< a Bezier function of t with the Bernstein coefficients `values`, m >= 1
  };
  Kind kind = Kind::kIdentity;  ///< which function
  double parameter = 0;         ///< s, n or a (see Kind); 0 for n means the default 8
  double waves = 1;             ///< kWave only: periods over [0, 1]
  std::vector<double> values;   ///< kLinear, kBezier: the values (finite, > 0)
};

/// Throws InvalidArgument("<what>: ...") naming the bad parameter or value index.
void validate(const Deformation& def, const std::string& what);
/// def(t) for t in [0, 1] (may be +infinity: kFlatEnds at the ends, kSquaredCosine with s = 0),
/// and its derivative in `*derivative` when given (0 where def is infinite).
[[nodiscard]] double deformation_value(const Deformation& def, double t,
                                       double* derivative = nullptr);
/// Lower and upper bounds of def over [0, 1] (the upper may be +infinity).
[[nodiscard]] Interval deformation_range(const Deformation& def);
/// "squared-cosine:0.3", "flat:8", "wave:0.5,2", "linear:1,2,1", "bezier:1,0.5,2", "identity":
/// the text form used by the scene language and skeleton JSON. Throws InvalidArgument.
[[nodiscard]] Deformation parse_deformation(const std::string& text);
/// The text form of parse_deformation.
[[nodiscard]] std::string format_deformation(const Deformation& def);

/// A segment skeleton a -> b with an anisotropic skin (§3.2): thickness radius / def(t), t the
/// clamped projection parameter (the ends are capped by the distance to the end points). Throws
/// InvalidArgument for a == b, a non-positive radius, a bad def or bad options.
[[nodiscard]] FieldPtr make_anisotropic_segment_field(const Vec3& a, const Vec3& b, double radius,
                                                      const Deformation& def,
                                                      const DistancePrimitiveOptions& options = {});

/// A Bezier-curve skeleton (§3.3–3.5): thickness r(t) / def(t) with r(t) the curve's radii
/// (BezierCurve::radii, Bernstein-interpolated) or `radius` when it has none. `tie` picks the
/// projection when several are equally near (bezier_curve.h). Throws InvalidArgument.
[[nodiscard]] FieldPtr make_bezier_field(const BezierCurve& curve, double radius,
                                         const Deformation& def, TieRule tie = TieRule::kFirst,
                                         const DistancePrimitiveOptions& options = {});

/// A parametric-surface skeleton (§4): the surface subdivided by the curvature test
/// (surface_skeleton.h), skinned with thickness radius / (def_u(u) def_v(v)). The field's
/// describe() reports the sub-patches and the approximation's error bound.
[[nodiscard]] FieldPtr make_surface_skeleton_field(std::shared_ptr<const SurfaceSkeleton> skeleton,
                                                   double radius, const Deformation& def_u,
                                                   const Deformation& def_v,
                                                   const DistancePrimitiveOptions& options = {});

/// The nearest element of a skeleton to a point (`ramiform eval --distance`).
struct SkeletonDistance {
  double distance = 0;     ///< Euclidean distance to the element
  bool is_edge = true;     ///< an edge (straight or curved), else an isolated node
  std::uint32_t index = 0; ///< the edge's or the node's index
  double t = 0;            ///< parameter of the nearest point on the edge (0 at its first node)
};

/// For every point, the nearest skeleton element: the straight edges (segments), the curved
/// edges (Skeleton::curves; exact distance by BezierProjector, ties by `tie`) and the nodes no
/// edge touches. Equally near elements: the lower edge index, edges before nodes. Through a BVH
/// over the elements' boxes, blocks of 256 points at a time: each curve that may be nearest to
/// some of a block's points projects them in one batched call (BezierProjector::project(points,
/// out), bit for bit project(p)); in parallel on ctx's threads (results never depend on them or
/// on the other points). Throws InputError for an invalid skeleton (validate()) and
/// InvalidArgument for a non-finite point.
[[nodiscard]] std::vector<SkeletonDistance> skeleton_distances(const Skeleton& skeleton,
                                                               std::span<const Vec3> points,
                                                               TieRule tie = TieRule::kFirst,
                                                               const Context* ctx = nullptr);

}  // namespace ramiform
