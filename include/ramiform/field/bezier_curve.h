// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Exact distance from a point to a Bezier curve of any degree 1..15, after Rigaudière,
/// Gesquière & Faudot, "Shape Modelling with Skeleton based Implicit Primitives", §3.3–3.4: the
/// orthogonal projections of P on C are the roots in [0, 1] of g(t) = C'(t)·(C(t) - P), a
/// polynomial of degree 2n-1; [0, 1] is split recursively at the roots of the derivative chain of
/// g until g is monotone on every piece, and g's root on each piece with a sign change is found
/// by a bracketed method. The nearest of these projections and the two end points is the nearest
/// point of the curve.
///
/// Method (BezierProjector):
/// - g is held in the Bernstein basis of degree m = 2n-1 on [0, 1]: its m+1 coefficients are
///   b_k = h_k - w_k·P with h_k and w_k precomputed from the control points (one dot product
///   per coefficient per query), and are evaluated by an O(m) Horner scheme in t/(1-t) (or
///   (1-t)/t for t > 1/2), which has the error bound of de Casteljau's algorithm.
/// - Exact early exit (Descartes' rule of signs for the Bernstein basis): the number of sign
///   changes of the coefficients bounds the number of roots in the open interval, with equal
///   parity. The coefficients are tested on [0, 1], then on halves, quarters, ... (de Casteljau
///   subdivision at midpoints, at most 6 levels). When every piece ends with 0 or 1 sign change
///   and no coefficient is within its rounding-error bound of 0, each root of g is isolated on
///   its own piece and found there by the bracketed method below (in project(), a root where g
///   goes from + to -, a maximum of the distance, is not located at all). This decides nearly
///   every query; otherwise (clustered roots, e.g. near a centre of curvature, or a sign within
///   rounding) the paper's derivative chain runs on all of [0, 1].
/// - Derivative chain (the paper's method): the forward differences of the coefficients are the
///   derivatives g', g'', ..., g^(m-1) (linear). From the linear one up, the roots of g^(j+1)
///   split [0, 1] into pieces on which g^(j) is monotone; on each piece with a sign change its
///   root is found by the bracketed method.
/// - Bracketed method: Newton's method safeguarded by bisection (the bracket is always kept),
///   stopped when a step is below 1e-15 in t or when the quadratic-convergence estimate of the
///   remaining error (step³ / previous step²) is.
/// - Near-double roots: a value at a piece end whose magnitude is within the evaluation's
///   rounding-error bound (coefficient errors included) counts as a root there. So a point near
///   a centre of curvature, where a minimum and a maximum of the distance merge, still yields a
///   candidate at the merge. Guarantee: every root of g across which g changes sign by more
///   than the rounding-error bound is found; a root that is missed lies where |g| is within
///   that bound of 0, which changes the nearest distance only by rounding-level amounts.
///
/// Certified arc path (BezierProjector::project for degree <= 7; not in the paper, which finds
/// all roots on [0, 1] for every query): the constructor halves [0, 1] (to depth 6, at most 64
/// arcs) until each arc, with local parameter s in [0, 1], centre c and radius R of the sphere
/// around its Bernstein controls, has R <= rho / 2 with rho = floor / max|C''|. On an arc
///   g'(s) = [|C'|² + C''·(C - c)] + C''·(c - P) >= floor + min_j E_j·(c - P),
/// where floor is the least Bernstein coefficient of the bracket (degree 2n-2, precomputed) and
/// E_j are the controls of C''. When this bound is > 0 (plus a rounding margin) g is strictly
/// increasing on the arc: it has a root there only if g goes from - to + between the arc's
/// ends, and that root is the arc's only stationary point, a minimum of the distance. A query:
/// - the arc with the nearest centre first; then, with the bound B = the nearest curve point
///   found by then (ends of the curve and of that arc, its minimum), every other arc whose
///   sphere is within B and whose chord is within B + its deviation (the largest distance of
///   its controls from the chord segment). B is not tightened by these visits, so they are
///   independent of each other (the batched path queues their Newton runs);
/// - a certified arc costs two dot products (g at its ends) and, if g changes sign, Newton from
///   the root of g's cubic Hermite interpolant at the arc's ends (values and slopes of g),
///   safeguarded by the bracket and stopped by an a-priori bound (|g''| bounded on the arc) once
///   the step's error is below 1e-15 in t; the root's point is C there, by Horner;
/// - an arc that is not certified (the query near a centre of curvature, a cusp, or far on the
///   concave side) gets the exact isolation above (Descartes, then the paper's derivative chain)
///   on its own g. Same guarantee as the isolation on [0, 1].
///
/// The plain functions (bezier_point, ...) validate the curve and t on every call; the projector
/// validates once.

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform {

namespace detail {
struct BezierArcTable;
}  // namespace detail

/// A Bezier curve over t in [0, 1], with an optional radius per control point.
struct BezierCurve {
  std::vector<Vec3> controls;  ///< n+1 control points, degree n >= 1 (n <= 15), model units
  std::vector<double>
      radii;  ///< empty, or one radius (> 0) per control point: radius(t) = sum B_i^n(t) r_i
};

/// Validates a Bezier curve. Throws InvalidArgument("<what>: ...") naming the problem and the
/// control index: fewer than 2 or more than 16 controls, a non-finite coordinate, radii neither
/// empty nor one per control, a radius not finite or <= 0, a degenerate curve (every control
/// within 1e-12 * extent of the first, i.e. a point; extent = largest |coordinate|).
void validate(const BezierCurve& curve, const std::string& what);

/// C(t) by de Casteljau's algorithm. Validates the curve; throws InvalidArgument for t outside
/// [0, 1] (or not finite).
[[nodiscard]] Vec3 bezier_point(const BezierCurve& c, double t);
/// C'(t) = dC/dt (same checks as bezier_point).
[[nodiscard]] Vec3 bezier_derivative(const BezierCurve& c, double t);
/// C''(t) (0 for degree 1; same checks as bezier_point).
[[nodiscard]] Vec3 bezier_second_derivative(const BezierCurve& c, double t);
/// radius(t) = sum B_i^n(t) r_i; 1 when the curve has no radii (same checks as bezier_point).
[[nodiscard]] double bezier_radius(const BezierCurve& c, double t);
/// d radius / dt; 0 when the curve has no radii (same checks as bezier_point).
[[nodiscard]] double bezier_radius_derivative(const BezierCurve& c, double t);

/// Which projection wins when several are equally near (distances equal within 1e-12 relative).
enum class TieRule {
  kFirst,  ///< the smallest t (the default)
  kLast,   ///< the largest t
};

/// The nearest point of a curve to a query point.
struct BezierProjection {
  double t = 0;         ///< parameter of the nearest point, in [0, 1]
  double distance = 0;  ///< |P - C(t)|, model units
  Vec3 point;           ///< C(t)
  int candidates = 0;   ///< stationary parameters located or counted in (0,1), plus the 2 ends
                        ///< (arcs proven farther than the nearest point are not searched)
  bool tie = false;     ///< another candidate was equally near (the tie rule chose)
};

/// A curve prepared for many projections: the Bernstein coefficients of C'(t)·C(t) and C'(t)
/// in degree 2n-1 are precomputed (relative to the centre of the control box), so that
/// g(t) = C'(t)·(C(t) - P), a polynomial of degree 2n-1, costs one dot product per coefficient
/// per point. project() allocates nothing. Immutable, thread-safe.
class BezierProjector {
 public:
  /// Validates the curve (validate(curve, what)) and precomputes the coefficients of g.
  explicit BezierProjector(BezierCurve curve, const std::string& what = "bezier curve");

  /// The curve as given.
  [[nodiscard]] const BezierCurve& curve() const { return curve_; }
  /// Its degree n (number of controls - 1).
  [[nodiscard]] int degree() const { return n_; }
  /// Box of the control points (contains the curve, convex-hull property).
  [[nodiscard]] const Aabb& box() const { return box_; }

  /// Every t in [0,1] with g(t) = 0, found by root isolation (see the file comment: Descartes'
  /// rule on subdivided Bernstein coefficients when it isolates every root, else the paper's
  /// derivative chain, which splits [0, 1] until g is monotone on each piece), each root then
  /// refined by safeguarded Newton (bracket kept, ~1e-15 in t). An end is included when g is 0
  /// there within rounding (derivative chain) or exactly. Sorted ascending. For tests and for
  /// `eval --distance`. Throws InvalidArgument for a non-finite p.
  [[nodiscard]] std::vector<double> stationary_parameters(const Vec3& p) const;

  /// Nearest point: the candidates are the stationary parameters and the two ends; the nearest
  /// wins, ties (distances within 1e-12 relative, parameters more than 1e-12 apart) by `rule`.
  /// A stationary parameter known to be a maximum of the distance (exact sign test) is counted
  /// in `candidates` but not located. Degree <= 7 takes the certified arc path (file comment):
  /// parts of the curve whose bounding sphere is farther than a curve point already found are
  /// not searched. Throws InvalidArgument for a non-finite p.
  [[nodiscard]] BezierProjection project(const Vec3& p, TieRule rule = TieRule::kFirst) const;

  /// Number of arcs of the fast path (0 above degree 7, where project() isolates on [0, 1]).
  [[nodiscard]] int arc_count() const { return static_cast<int>(arcs_.size()); }

  /// project() on every point of `points` into `out` (same size; throws InvalidArgument
  /// otherwise or for a non-finite point). Equal, bit for bit and point by point, to
  /// project(points[k], rule), whatever the other points of the batch. Degree <= 7 and 4 points
  /// or more: the arc path vectorized across points (Highway, dispatched at run time;
  /// src/field/bezier_curve_simd.cpp): every lane runs the scalar path's operations in the same
  /// order; the Newton runs are queued and run in full vectors (a mask per lane), uncertified
  /// arcs go through the exact isolation one lane at a time; a point whose two nearest
  /// candidates are within 1e-9 (relative, squared distance) is projected one by one so that the
  /// tie rule decides as in project(p). About 3x faster per point than project(p) with AVX-512
  /// (docs/benchmarks.md).
  void project(std::span<const Vec3> points, std::span<BezierProjection> out,
               TieRule rule = TieRule::kFirst) const;

  /// The Newton-iteration baseline, for the benchmark only: Newton on g from the best of
  /// `starts` (>= 2) uniform samples (t = i/(starts-1)), clamped to [0,1], at most 20 steps; the
  /// point where Newton stops is returned as it is (it may be a local minimum, or worse).
  /// `candidates` = starts, `tie` = false. Throws InvalidArgument for starts < 2 or a
  /// non-finite p.
  [[nodiscard]] BezierProjection project_newton(const Vec3& p, int starts = 4) const;

 private:
  static constexpr int kMaxControls = 16;      // degree <= 15
  static constexpr int kMaxCoefficients = 30;  // g has degree <= 29
  static constexpr int kMaxFastDegree = 7;     // the arc path (power basis per arc)
  static constexpr int kMaxFastCoefficients = 2 * kMaxFastDegree;
  static constexpr int kMaxArcs = 64;  // halving to depth 6

  // g restricted to an arc, in Bernstein form on the arc's own parameter s in [0, 1] (same
  // layout as h_, w_, ...): for the exact isolation of an arc out of reach.
  struct ArcG {
    std::array<double, kMaxFastCoefficients> h{};
    std::array<Vec3, kMaxFastCoefficients> w{};
    std::array<double, kMaxFastCoefficients> h_error{};
    std::array<double, kMaxFastCoefficients> w_error{};
  };
  // One arc [t0, t1] of the fast path. C(t0 + s (t1 - t0)) - origin_ = sum_j power[j] s^j.
  struct Arc {
    double t0 = 0, t1 = 1;
    std::array<Vec3, kMaxFastDegree + 1> power{};
    // g' >= floor + min_j second[j]·(centre - P) on the arc: g increasing when this is > 0.
    std::array<Vec3, kMaxFastDegree - 1> second{};  // controls of C'' in s
    double floor = -1;
    double second_max = 0;  // largest |coordinate| of the second[j]
    // |g''| <= g2_fixed + g2_per_distance (|centre - P| + R) on the arc (stops Newton early).
    double g2_fixed = 0, g2_per_distance = 0;
    ArcG g;
  };
  // The per-query scan, structure of arrays: arcs (bounding sphere) and their ends
  // (K + 1 for K arcs: point relative to origin_, C'(t_k), C''(t_k)).
  struct ArcScan {
    std::vector<double> cx, cy, cz, radius;
    // Per arc: its chord (end - start), 1 / |chord|² (0 for a closed arc) and the largest
    // distance of its controls from the chord segment (inflated for rounding).
    std::vector<double> ux, uy, uz, inv_chord2, deviation;
    std::vector<double> px, py, pz, tx, ty, tz, ax, ay, az;
  };

  void build_arcs();
  // The nearest point by the arc path (project() after the checks), for degree N.
  template <int N>
  [[nodiscard]] BezierProjection project_arcs(const Vec3& q, TieRule rule) const;
  // The nearest point by isolation on [0, 1] (project() after the checks, degree > 7).
  [[nodiscard]] BezierProjection project_whole(const Vec3& q, TieRule rule) const;

  // The exact isolation on arc `arc` for the batched path (detail::BezierArcIsolation).
  static int isolate_arc(const void* self, int arc, const double* q, double* roots, int* skipped);

  // Stationary parameters of the point q (relative to origin_) into `roots` (sorted); returns
  // their count. When `locate_maxima` is false, roots where g goes from + to - (maxima of the
  // distance) may be skipped; `skipped` counts them.
  int stationary(const Vec3& q, bool locate_maxima, double* roots, int* skipped) const;
  // C(t) - origin_ (Bernstein form, O(n)).
  [[nodiscard]] Vec3 local_point(double t) const;

  BezierCurve curve_;
  int n_ = 1;  // degree of C
  int m_ = 1;  // degree of g = 2n-1
  Aabb box_;
  Vec3 origin_;                               // centre of box_: the coefficients are relative to it
  std::array<Vec3, kMaxControls> scaled_{};   // C(n,i) (P_i - origin_)
  std::array<Vec3, kMaxControls> first_{};    // C(n-1,i) n (P_{i+1} - P_i)
  std::array<Vec3, kMaxControls> second_{};   // C(n-2,i) n(n-1) (P_{i+2} - 2P_{i+1} + P_i)
  std::array<double, kMaxCoefficients> h_{};  // g's Bernstein coefficients: b_k = h_k - w_k·q
  std::array<Vec3, kMaxCoefficients> w_{};
  std::array<double, kMaxCoefficients> h_error_{};  // rounding bound of h_k
  std::array<double, kMaxCoefficients> w_error_{};  // rounding bound of w_k·q per unit max|q_i|
  std::vector<Arc> arcs_;                           // empty above kMaxFastDegree
  ArcScan scan_;
  std::shared_ptr<const detail::BezierArcTable> table_;  // the arcs for the batched path
};

}  // namespace ramiform
