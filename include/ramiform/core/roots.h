// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// The one bracketed root finder: a root of a function g of one variable on an interval [a, b]
/// over which g changes sign. RootBracket is driven step by step (probe() names the next point,
/// update() takes g there), so that a caller can advance many brackets at once with one batch
/// evaluation per round (the polygonizers' crossing edges, the radius measurement's rays);
/// find_root() is the one-call wrapper for a single function.
///
/// The steps: regula falsi with the Anderson–Björck modification (Anderson & Björck 1973, "A
/// new high order method of regula falsi type for computing a root of an equation", BIT 13:
/// when the same end is replaced twice running, the value kept at the other end is scaled by
/// 1 - g_new / g_old, or halved when that is not positive); once three points are known, the
/// root of the quadratic through the bracket's ends and the point replaced last (a Muller step:
/// Muller 1956, "A method for solving algebraic equations using an automatic computer", MTAC
/// 10) when it lies inside the bracket. When steps "creep" (the same end replaced
/// again and again without its |g| halving, as when g is far from linear, e.g. at the edge of
/// a compactly supported kernel) the modified secant is taken, and after three such steps
/// bisection, which halves the bracket for sure. Every probe lies strictly inside the bracket
/// (a step that would land on or beyond an end becomes a bisection step).
///
/// Vanished ends: when the value at one end is below `vanish_level` (g has all but vanished
/// there, e.g. a field that has fallen to nothing far from the surface), interpolation towards
/// that end would land on the other end; the probes then step 1/32 of the bracket in from the
/// live end, and bisect once such a step has landed on the live side.

#include <functional>
#include <limits>

#include "ramiform/core/tolerances.h"

namespace ramiform {

/// One bracketed root search, driven step by step. Values g may be any real numbers; the sign
/// of g at the bracket's lower end decides which end a new point replaces (a point with g of
/// that sign replaces the lower end, any other the upper one), so the bracket keeps a sign
/// change when it starts with one. Without a sign change at the start every probe still lies
/// in [a, b] and estimate() is a point of it, but not a root: a caller that needs a root checks
/// the signs first (find_root() does). Plain value type; copyable.
class RootBracket {
 public:
  /// The bracket [0, 0] (width 0, already converged); for containers of brackets that are
  /// assigned before use.
  RootBracket() = default;
  /// The bracket [a, b] (a <= b) with g(a) = ga, g(b) = gb. A zero at an end is the root: the
  /// bracket collapses onto that end (onto b when both are 0, with width a - b < 0 then).
  /// `vanish_level`: see the file comment (-infinity: never).
  RootBracket(double a, double ga, double b, double gb,
              double vanish_level = -std::numeric_limits<double>::infinity());

  [[nodiscard]] double lower() const { return a_; }  ///< lower end of the bracket
  [[nodiscard]] double upper() const { return b_; }  ///< upper end of the bracket
  /// upper() - lower(); <= 0 once the bracket has collapsed onto a root.
  [[nodiscard]] double width() const { return b_ - a_; }
  [[nodiscard]] double midpoint() const { return 0.5 * (a_ + b_); }
  [[nodiscard]] double lower_value() const { return ga_; }  ///< g at lower() (as evaluated)
  [[nodiscard]] double upper_value() const { return gb_; }  ///< g at upper() (as evaluated)
  /// Points given to update() so far.
  [[nodiscard]] int updates() const { return updates_; }
  /// True when an end's value is below the vanish level (see the file comment).
  [[nodiscard]] bool is_vanished() const;

  /// The next point to evaluate, strictly inside (lower(), upper()) while width() > 0.
  [[nodiscard]] double probe() const;
  /// `x` when it lies strictly inside the bracket, else the midpoint: a caller's own estimate
  /// (e.g. a secant of a transformed g) made safe to probe.
  [[nodiscard]] double safeguard(double x) const;
  /// Takes g(x) = g for a probed x inside the bracket: x replaces the end whose value has the
  /// same sign. g = 0 or NaN ends the search at x (collapse()).
  void update(double x, double g);
  /// Ends the search at x: the bracket becomes [x, x].
  void collapse(double x);
  /// The best estimate of the root: the collapsed point, else the secant of the evaluated
  /// values at the ends (the midpoint when an end has vanished, or the secant leaves the
  /// bracket).
  [[nodiscard]] double estimate() const;

 private:
  [[nodiscard]] double secant_of(double ya, double yb) const;
  [[nodiscard]] double proposal() const;
  void replace_lower(double x, double g);
  void replace_upper(double x, double g);

  double a_ = 0, b_ = 0;    // the bracket
  double ga_ = 0, gb_ = 0;  // g at its ends, as evaluated
  double fa_ = 0, fb_ = 0;  // the same, scaled by the Anderson–Björck steps
  double c_ = 0;            // the end replaced last, and g there (NaN: none yet)
  double gc_ = std::numeric_limits<double>::quiet_NaN();
  double vanish_level_ = -std::numeric_limits<double>::infinity();
  int slow_ = 0;  // steps running that replaced the same end without halving its |g|
  int updates_ = 0;
  signed char last_side_ = 0;  // -1: the lower end replaced last, +1: the upper end, 0: none
};

/// Options of find_root(); validated at entry (InvalidArgument naming the option).
struct RootOptions {
  /// Stop once the bracket is at most this fraction of b - a wide (>= 0).
  double tolerance = tol::kRootFinding;
  /// Stop at a point where |g| is at most this (>= 0; 0: only an exact zero).
  double value_tolerance = 0;
  int max_steps = 100;  ///< evaluations after the two ends (>= 0)
  /// Values below this count as vanished (RootBracket; -infinity: never).
  double vanish_level = -std::numeric_limits<double>::infinity();
};

/// Outcome of find_root().
struct RootResult {
  double x = 0;         ///< the root estimate (RootBracket::estimate()), in [a, b]
  int evaluations = 0;  ///< calls of g, the two ends included
  /// The bracket reached the tolerance or a point met the value tolerance (else max_steps
  /// stopped the search).
  bool converged = false;
};

/// A root of g in [a, b] (see the file comment for the method). g(x) = NaN ends the search at x.
/// Throws InvalidArgument when a or b is not finite, a > b, g(a) and g(b) are NaN or have the
/// same sign (neither is 0), or an option is out of range.
[[nodiscard]] RootResult find_root(const std::function<double(double)>& g, double a, double b,
                                   const RootOptions& options = {});

}  // namespace ramiform
