// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/core/roots.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

// A quadratic whose curvature term |a| w is below this fraction of its slope |b| is solved as
// the line it nearly is (the quadratic formula would cancel catastrophically).
constexpr double kNearlyLinear = 1e-12;
// Steps running without halving |g| at the replaced end, after which bisection takes over.
constexpr int kCreepLimit = 3;
// Near a vanished end the probes step this fraction of the bracket in from the live end.
constexpr double kVanishedStep = 1.0 / 32;

// The Anderson–Björck factor for the value kept at the other end: 1 - g_new / g_old, or 1/2
// when that is not positive.
double damping(double g_new, double g_old) {
  const double m = 1 - g_new / g_old;
  return m > 0 ? m : 0.5;
}

// The root in (0, w) of the quadratic through (0, y0), (w, y1), (x2, y2), or NaN when it has
// none there (Newton's divided differences; the stable form of the quadratic formula).
double quadratic_root(double w, double y0, double y1, double x2, double y2) {
  const double d01 = (y1 - y0) / w;
  const double d12 = (y2 - y1) / (x2 - w);
  const double a = (d12 - d01) / x2;
  const double b = d01 - a * w;
  const double c = y0;
  double u = std::numeric_limits<double>::quiet_NaN();
  if (std::abs(a) * w <= kNearlyLinear * std::abs(b)) {
    u = -c / b;
  } else {
    const double disc = b * b - 4 * a * c;
    if (disc >= 0) {
      const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      const double r1 = q / a;
      const double r2 = c / q;
      u = r1 > 0 && r1 < w ? r1 : r2;
    }
  }
  return u > 0 && u < w ? u : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

RootBracket::RootBracket(double a, double ga, double b, double gb, double vanish_level)
    : a_(a), b_(b), ga_(ga), gb_(gb), fa_(ga), fb_(gb), vanish_level_(vanish_level) {
  // An end exactly on zero is the root (the sign test of update() needs g != 0 at a).
  if (ga == 0) b_ = a;
  if (gb == 0) a_ = b;
}

bool RootBracket::is_vanished() const { return std::min(ga_, gb_) < vanish_level_; }

double RootBracket::safeguard(double x) const { return x > a_ && x < b_ ? x : midpoint(); }

double RootBracket::probe() const { return safeguard(proposal()); }

// The secant root in the bracket of values ya at a and yb at b (the midpoint if none).
double RootBracket::secant_of(double ya, double yb) const {
  const double df = yb - ya;
  double s = df != 0.0 ? (a_ * yb - b_ * ya) / df : midpoint();
  if (!(s >= a_ && s <= b_)) s = midpoint();
  return s;
}

double RootBracket::proposal() const {
  if (is_vanished()) {
    // The root lies far nearer the live end: small steps in from it, bisection once a step
    // has landed on its side.
    const bool a_live = ga_ > gb_ ? ga_ > 0 : false;
    const bool inside_last = last_side_ == (a_live ? -1 : 1);
    if (last_side_ == 0 || inside_last) return midpoint();
    const double w = (b_ - a_) * kVanishedStep;
    return a_live ? a_ + w : b_ - w;
  }
  if (slow_ >= kCreepLimit) return midpoint();
  if (!std::isnan(gc_) && slow_ == 0) {
    const double u = quadratic_root(b_ - a_, ga_, gb_, c_ - a_, gc_);
    if (!std::isnan(u)) return a_ + u;
  }
  return secant_of(fa_, fb_);  // the damped values
}

void RootBracket::replace_lower(double x, double g) {
  const bool creep = last_side_ == -1 && std::abs(g) > 0.5 * std::abs(ga_);
  slow_ = creep ? slow_ + 1 : 0;
  if (last_side_ == -1) fb_ *= damping(g, fa_);
  c_ = a_;
  gc_ = ga_;
  a_ = x;
  fa_ = ga_ = g;
  last_side_ = -1;
}

void RootBracket::replace_upper(double x, double g) {
  const bool creep = last_side_ == 1 && std::abs(g) > 0.5 * std::abs(gb_);
  slow_ = creep ? slow_ + 1 : 0;
  if (last_side_ == 1) fa_ *= damping(g, fb_);
  c_ = b_;
  gc_ = gb_;
  b_ = x;
  fb_ = gb_ = g;
  last_side_ = 1;
}

void RootBracket::update(double x, double g) {
  ++updates_;
  if (g == 0 || std::isnan(g)) {
    collapse(x);
  } else if ((g > 0.0) == (fa_ > 0.0)) {
    replace_lower(x, g);
  } else {
    replace_upper(x, g);
  }
}

void RootBracket::collapse(double x) {
  a_ = b_ = x;
  fa_ = fb_ = 0.0;
}

double RootBracket::estimate() const {
  // The secant of the evaluated values: the damped ones may have shrunk one end's value to
  // nothing, which would put the estimate at that end.
  if (a_ == b_) return a_;
  return is_vanished() ? midpoint() : secant_of(ga_, gb_);
}

RootResult find_root(const std::function<double(double)>& g, double a, double b,
                     const RootOptions& options) {
  if (!(options.tolerance >= 0) || !std::isfinite(options.tolerance)) {
    throw InvalidArgument("find_root: tolerance must be finite and >= 0, got " +
                          format_number(options.tolerance));
  }
  if (!(options.value_tolerance >= 0) || !std::isfinite(options.value_tolerance)) {
    throw InvalidArgument("find_root: value_tolerance must be finite and >= 0, got " +
                          format_number(options.value_tolerance));
  }
  if (options.max_steps < 0) {
    throw InvalidArgument("find_root: max_steps must be >= 0, got " +
                          std::to_string(options.max_steps));
  }
  if (!std::isfinite(a) || !std::isfinite(b) || a > b) {
    throw InvalidArgument("find_root: needs finite a <= b, got [" + format_number(a) + ", " +
                          format_number(b) + "]");
  }
  RootResult result;
  const double ga = g(a);
  const double gb = g(b);
  result.evaluations = 2;
  if (std::isnan(ga) || std::isnan(gb) || (ga != 0 && gb != 0 && (ga > 0) == (gb > 0))) {
    throw InvalidArgument("find_root: g must change sign on [a, b], got g(a) = " +
                          format_number(ga) + ", g(b) = " + format_number(gb));
  }
  RootBracket bracket(a, ga, b, gb, options.vanish_level);
  const double width = options.tolerance * (b - a);
  bool on_root = ga == 0 || gb == 0;
  while (!on_root && bracket.width() > width && result.evaluations - 2 < options.max_steps) {
    const double x = bracket.probe();
    const double gx = g(x);
    ++result.evaluations;
    on_root = std::isnan(gx) || std::abs(gx) <= options.value_tolerance;
    if (on_root) {
      bracket.collapse(x);
    } else {
      bracket.update(x, gx);
    }
  }
  result.converged = on_root || bracket.width() <= width;
  result.x = bracket.estimate();
  return result;
}

}  // namespace ramiform
