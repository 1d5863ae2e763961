// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "polygonize/edge_roots.h"

#include <cmath>
#include <utility>

#include "ramiform/core/tolerances.h"

namespace ramiform::detail {

std::vector<Vec3> find_edge_roots_along(const Field& field, const std::vector<Vec3>& a,
                                        const std::vector<Vec3>& d, std::vector<double> fa,
                                        std::vector<double> fb, int steps,
                                        std::uint64_t& evaluations) {
  const std::size_t n = a.size();
  const double iso = field.iso();
  // Work with g = f - iso on the parameter t in [0, 1] of each edge.
  std::vector<double> ta(n, 0.0), tb(n, 1.0), t(n, 0.0);
  for (std::size_t e = 0; e < n; ++e) {
    fa[e] -= iso;
    fb[e] -= iso;
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
      const double g = std::isnan(values[q]) ? 0.0 : values[q] - iso;
      if (std::abs(g) <= tol::kRootValue * std::abs(iso)) {  // on the surface
        ta[e] = tb[e] = t[e];
        fa[e] = fb[e] = 0.0;
        continue;
      }
      if ((g > 0.0) == (fa[e] > 0.0)) {
        ta[e] = t[e];
        fa[e] = g;
        if (last_side[e] == -1) fb[e] *= 0.5;  // Illinois: halve the end that stayed
        last_side[e] = -1;
      } else {
        tb[e] = t[e];
        fb[e] = g;
        if (last_side[e] == 1) fa[e] *= 0.5;
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
