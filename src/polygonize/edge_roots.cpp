// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/edge_roots.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "ramiform/core/parallel.h"
#include "ramiform/core/tolerances.h"

namespace ramiform::detail {
namespace {

// Field values below this fraction of iso count as this fraction in the transforms below (a
// finite, very negative g: only its sign matters there).
constexpr double kFloor = 1e-300;
constexpr std::size_t kGrain = 8192;  // edges per parallel task
// Below this g = 1 - (f / iso)^(-2/3) the field has all but vanished (f < 1e-6 iso: far beyond
// the surface, or exactly 0 and floored): interpolation towards such an end lands on the other
// end, so the bracket steps towards the live end instead (see propose), and the final estimate
// is the bracket's midpoint. (A 4.4 m lattice edge of archi_Tree_1 at level 0 runs from a node,
// f = 2.8 iso, to where f = 0; the vertex ended on the node's own point and left the node
// outside the mesh.)
constexpr double kVanished = -1e4;

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
  if (std::abs(a) * w <= 1e-12 * std::abs(b)) {
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

std::vector<Vec3> find_edge_roots_along(const Field& field, const std::vector<Vec3>& a,
                                        const std::vector<Vec3>& d, std::vector<double> fa,
                                        std::vector<double> fb, int steps,
                                        std::uint64_t& evaluations) {
  const std::size_t n = a.size();
  const double iso = field.iso();
  // Work on the parameter t in [0, 1] of each edge. Where the field is positive at both ends
  // (the kernel fields), g = 1 - (f / iso)^(-2/3): the Cauchy convolution of one straight
  // segment falls off like (1 + s^2 d^2)^(-3/2) with the distance d from its axis, and d^2 is a
  // quadratic in t along any line, so there g is exactly quadratic in t, and nearly so where a
  // few segments blend. Elsewhere g = f - iso. Either way g > 0 exactly where f > iso.
  // - The first step is the secant of log f between the ends (over a whole edge log f is
  //   closer to linear than g).
  // - Later steps take the root of the quadratic through the bracket's ends and the point
  //   replaced last, when it lies inside the bracket; otherwise regula falsi with the
  //   Anderson-Björck modification (when the same end is replaced twice running, the value
  //   at the end that stayed is scaled by 1 - g_new / g_old, or halved); bisection when a step
  //   would hug an end.
  // Measured on the 1,500-segment benchmark tree at level 1: 3.6 evaluations per edge; 4.8
  // with Anderson-Björck on log f alone, 6.2 with Illinois on f - iso.
  const bool use_transform = steps > 0 && iso > 0;
  std::vector<char> transformed(n, 0);
  std::vector<double> ta(n, 0.0), tb(n, 1.0), t(n, 0.0);
  auto g_of = [&](std::size_t e, double f) {
    if (transformed[e] == 0) return f - iso;
    const double c = std::cbrt(std::max(f, kFloor * iso) / iso);
    return 1.0 - 1.0 / (c * c);
  };
  parallel::for_each(n, kGrain, [&](std::size_t e) {
    // A zero end (beyond a truncated or compactly supported kernel) is floored, see kFloor.
    transformed[e] = use_transform && fa[e] >= 0 && fb[e] >= 0 && fa[e] + fb[e] > 0 ? 1 : 0;
    fa[e] = g_of(e, fa[e]);
    fb[e] = g_of(e, fb[e]);
    // An end exactly on the surface is the root (the sign test below needs g != 0 at a).
    if (fa[e] == 0) tb[e] = 0.0;
    if (fb[e] == 0) ta[e] = 1.0;
  });
  // Undamped values at the bracket's ends, and the point replaced last (NaN: none yet).
  std::vector<double> ga(fa), gb(fb);
  std::vector<double> tc(n, 0.0), gc(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<signed char> last_side(n, 0);  // -1: a replaced last, +1: b replaced last
  // Steps running that replaced the same end without halving its |g| (creeping).
  std::vector<unsigned char> slow(n, 0);
  // The secant root in the bracket of values ya at ta and yb at tb (the midpoint if none).
  auto secant_of = [&](std::size_t e, double ya, double yb) {
    const double df = yb - ya;
    double s = df != 0.0 ? (ta[e] * yb - tb[e] * ya) / df : 0.5 * (ta[e] + tb[e]);
    if (!(s >= ta[e] && s <= tb[e])) s = 0.5 * (ta[e] + tb[e]);
    return s;
  };
  auto secant = [&](std::size_t e) { return secant_of(e, fa[e], fb[e]); };  // damped
  auto vanished = [&](std::size_t e) {
    return transformed[e] != 0 && std::min(ga[e], gb[e]) < kVanished;
  };
  auto propose = [&](std::size_t e, int step) {
    if (transformed[e] != 0 && step == 0 && !vanished(e)) {  // secant of log f = -3/2 log(1 - g)
      const double la = -1.5 * std::log1p(-fa[e]);
      const double lb = -1.5 * std::log1p(-fb[e]);
      if (la != lb && std::isfinite(la) && std::isfinite(lb))
        return (ta[e] * lb - tb[e] * la) / (lb - la);
    }
    // Creeping: the same end replaced again and again without its |g| halving (g far from
    // quadratic, as for a compactly supported kernel, whose g falls to -infinity at the edge of
    // its support: the interpolants stay near the other end). Then the damped secant, and
    // after three such steps bisection, which halves the bracket for sure. (Without this, on
    // the Wyvill distance surface of the 1,500-segment benchmark tree 1.2 % of the vertices
    // ended far off the surface; with a plain "same end twice" rule the Cauchy field spent
    // 8 % more evaluations.)
    if (vanished(e)) {
      // The root lies far nearer the live end (a Cauchy field falls off like the distance^-3:
      // f < 1e-6 iso some 100 radii out, the surface about 1 radius out): steps of 1/32 of the
      // bracket towards it; bisection once a step has landed inside.
      const bool a_live = ga[e] > gb[e] ? ga[e] > 0 : false;
      const bool inside_last = last_side[e] == (a_live ? -1 : 1);
      if (step == 0 || inside_last) return 0.5 * (ta[e] + tb[e]);
      const double w = (tb[e] - ta[e]) / 32;
      return a_live ? ta[e] + w : tb[e] - w;
    }
    if (slow[e] >= 3) return 0.5 * (ta[e] + tb[e]);
    if (!std::isnan(gc[e]) && slow[e] == 0) {
      const double u = quadratic_root(tb[e] - ta[e], ga[e], gb[e], tc[e] - ta[e], gc[e]);
      if (!std::isnan(u)) return ta[e] + u;
    }
    return secant(e);
  };
  std::vector<std::uint32_t> active(n);
  for (std::size_t e = 0; e < n; ++e) active[e] = static_cast<std::uint32_t>(e);
  std::vector<Vec3> points;
  std::vector<double> values;
  // Every round: drop the converged edges, propose a point per edge, evaluate them in one
  // batch, update each bracket; the per-edge work runs in parallel (it is independent per edge
  // and as costly as the evaluations' bookkeeping), the compactions serially.
  std::vector<char> done(n, 0);
  for (int step = 0; step < steps && !active.empty(); ++step) {
    std::size_t keep = 0;
    for (const std::uint32_t e : active) {
      if (tb[e] - ta[e] > tol::kRootFinding) active[keep++] = e;
    }
    active.resize(keep);
    if (active.empty()) break;
    points.resize(active.size());
    parallel::for_each(active.size(), kGrain, [&](std::size_t q) {
      const std::uint32_t e = active[q];
      double s = propose(e, step);
      // Safeguard: a step that hugs an end of the bracket becomes a bisection step.
      if (!(s > ta[e] && s < tb[e])) s = 0.5 * (ta[e] + tb[e]);
      t[e] = s;
      points[q] = a[e] + s * d[e];
    });
    values.resize(points.size());
    field.evaluate(points, values);
    evaluations += points.size();
    parallel::for_each(active.size(), kGrain, [&](std::size_t q) {
      const std::uint32_t e = active[q];
      if (std::isnan(values[q]) || std::abs(values[q] - iso) <= tol::kRootValue * std::abs(iso)) {
        ta[e] = tb[e] = t[e];  // on the surface
        fa[e] = fb[e] = 0.0;
        done[e] = 1;
        return;
      }
      const double g = g_of(e, values[q]);
      if ((g > 0.0) == (fa[e] > 0.0)) {
        const bool creep = last_side[e] == -1 && std::abs(g) > 0.5 * std::abs(ga[e]);
        slow[e] = creep ? static_cast<unsigned char>(slow[e] + 1) : 0;
        if (last_side[e] == -1) fb[e] *= damping(g, fa[e]);
        tc[e] = ta[e];
        gc[e] = ga[e];
        ta[e] = t[e];
        fa[e] = ga[e] = g;
        last_side[e] = -1;
      } else {
        const bool creep = last_side[e] == 1 && std::abs(g) > 0.5 * std::abs(gb[e]);
        slow[e] = creep ? static_cast<unsigned char>(slow[e] + 1) : 0;
        if (last_side[e] == 1) fa[e] *= damping(g, fb[e]);
        tc[e] = tb[e];
        gc[e] = gb[e];
        tb[e] = t[e];
        fb[e] = gb[e] = g;
        last_side[e] = 1;
      }
    });
    keep = 0;
    for (const std::uint32_t e : active) {
      if (done[e] == 0) active[keep++] = e;
    }
    active.resize(keep);
  }
  std::vector<Vec3> out(n);
  parallel::for_each(n, kGrain, [&](std::size_t e) {
    // Out of steps: the secant of the undamped values (the damped ones may have shrunk one
    // end's value to nothing, which would put the vertex at that end).
    const double s = ta[e] == tb[e] ? ta[e]
                     : vanished(e)  ? 0.5 * (ta[e] + tb[e])
                                    : secant_of(e, ga[e], gb[e]);
    out[e] = a[e] + s * d[e];
  });
  return out;
}

std::vector<Vec3> find_edge_roots(const Field& field, const std::vector<Vec3>& a,
                                  const std::vector<Vec3>& b, std::vector<double> fa,
                                  std::vector<double> fb, int steps, std::uint64_t& evaluations) {
  std::vector<Vec3> d(a.size());
  for (std::size_t e = 0; e < a.size(); ++e) d[e] = b[e] - a[e];
  return find_edge_roots_along(field, a, d, std::move(fa), std::move(fb), steps, evaluations);
}

}  // namespace ramiform::detail
