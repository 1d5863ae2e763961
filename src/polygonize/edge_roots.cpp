// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/edge_roots.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "ramiform/core/tolerances.h"

namespace ramiform::detail {
namespace {

// Values below this fraction of iso count as this fraction in the logarithm (a finite, very
// negative g: the sign is all that matters there).
constexpr double kLogFloor = 1e-300;

double damping(double g_new, double g_old) {
  const double m = 1 - g_new / g_old;
  return m > 0 ? m : 0.5;
}

}  // namespace

std::vector<Vec3> find_edge_roots_along(const Field& field, const std::vector<Vec3>& a,
                                        const std::vector<Vec3>& d, std::vector<double> fa,
                                        std::vector<double> fb, int steps,
                                        std::uint64_t& evaluations) {
  const std::size_t n = a.size();
  const double iso = field.iso();
  // Work on the parameter t in [0, 1] of each edge with g = log(f / iso) where the field is
  // positive at both ends (the kernel fields: f falls off like a power of the distance, so its
  // logarithm is much closer to linear along an edge and the secant steps land closer), and
  // g = f - iso elsewhere. Either way g > 0 exactly where f > iso. Measured on the 1,500-segment
  // benchmark tree at level 1: 4.8 evaluations per edge with the logarithm and Anderson-Björck
  // (below), 6.2 with f - iso and Illinois.
  const bool use_log = steps > 0 && iso > 0;
  std::vector<char> logarithmic(n, 0);
  auto g_of = [&](std::size_t e, double f) {
    return logarithmic[e] != 0 ? std::log(std::max(f, kLogFloor * iso) / iso) : f - iso;
  };
  std::vector<double> ta(n, 0.0), tb(n, 1.0), t(n, 0.0);
  for (std::size_t e = 0; e < n; ++e) {
    logarithmic[e] = use_log && fa[e] > 0 && fb[e] > 0 ? 1 : 0;
    fa[e] = g_of(e, fa[e]);
    fb[e] = g_of(e, fb[e]);
  }
  std::vector<signed char> last_side(n, 0);  // -1: a replaced last, +1: b replaced last
  auto secant = [&](std::size_t e) {
    const double df = fb[e] - fa[e];
    double s = df != 0.0 ? (ta[e] * fb[e] - tb[e] * fa[e]) / df : 0.5 * (ta[e] + tb[e]);
    if (!(s >= ta[e] && s <= tb[e])) s = 0.5 * (ta[e] + tb[e]);
    return s;
  };
  std::vector<std::uint32_t> active(n);
  for (std::size_t e = 0; e < n; ++e) active[e] = static_cast<std::uint32_t>(e);
  std::vector<Vec3> points;
  std::vector<double> values;
  for (int step = 0; step < steps && !active.empty(); ++step) {
    points.clear();
    std::size_t keep = 0;
    for (const std::uint32_t e : active) {
      if (tb[e] - ta[e] <= tol::kRootFinding) continue;  // converged
      double s = secant(e);
      // Safeguard: a secant step that hugs an end of the bracket becomes a bisection step.
      if (!(s > ta[e] && s < tb[e])) s = 0.5 * (ta[e] + tb[e]);
      t[e] = s;
      points.push_back(a[e] + s * d[e]);
      active[keep++] = e;
    }
    active.resize(keep);
    if (points.empty()) break;
    values.resize(points.size());
    field.evaluate(points, values);
    evaluations += points.size();
    keep = 0;
    for (std::size_t q = 0; q < active.size(); ++q) {
      const std::uint32_t e = active[q];
      if (std::isnan(values[q]) || std::abs(values[q] - iso) <= tol::kRootValue * std::abs(iso)) {  // on the surface
        ta[e] = tb[e] = t[e];
        fa[e] = fb[e] = 0.0;
        continue;
      }
      // Anderson-Björck: when the same end is replaced twice running, the value at the end
      // that stayed is scaled by 1 - g_new / g_old (by 1/2, as Illinois, when that is not
      // positive), so the secant cannot creep along one side.
      const double g = g_of(e, values[q]);
      if ((g > 0.0) == (fa[e] > 0.0)) {
        if (last_side[e] == -1) fb[e] *= damping(g, fa[e]);
        ta[e] = t[e];
        fa[e] = g;
        last_side[e] = -1;
      } else {
        if (last_side[e] == 1) fa[e] *= damping(g, fb[e]);
        tb[e] = t[e];
        fb[e] = g;
        last_side[e] = 1;
      }
      active[keep++] = e;
    }
    active.resize(keep);
  }
  std::vector<Vec3> out(n);
  for (std::size_t e = 0; e < n; ++e) {
    const double s = ta[e] == tb[e] ? ta[e] : secant(e);
    out[e] = a[e] + s * d[e];
  }
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
