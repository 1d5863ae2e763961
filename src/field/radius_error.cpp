// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Measuring the radius error of a surface against a skeleton's requested radii
// (measure_radius_error of radius_fit.h): rays perpendicular to the edges, bracketed on a grid
// of radius multiples and refined by the bracketed root finder of core/roots.h.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "field/radius_fit_detail.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/roots.h"
#include "ramiform/field/radius_fit.h"

namespace ramiform {
namespace {

using detail::EdgeGeometry;

// The bracketing grids, in requested radii: outward while f > iso, inward while f <= iso.
constexpr double kOutward[] = {1.1, 1.25, 1.5,  2.0,  2.5,  3.0, 4.0,
                               6.0, 8.0,  12.0, 16.0, 24.0, 32.0};
constexpr double kInward[] = {0.9, 0.8, 0.65, 0.5, 0.3};
constexpr std::size_t kOutwardSteps = std::size(kOutward);
constexpr std::size_t kInwardSteps = std::size(kInward);
// The search for another tube's entry marches in steps of 1 / kStepsPerRadius radii.
constexpr int kStepsPerRadius = 16;
// The refinement stops once the bracket is this narrow (in requested radii), or after
// kMaxRefine rounds.
constexpr double kRelativeWidth = 1e-9;
constexpr int kMaxRefine = 100;
// The rays' directions are turned this fraction of a step from the fit's angles (0, 1/2 and
// 1/4 of a step) so that samples fall between them.
constexpr double kAnglePhase = 0.37;

// A ray: origin on the edge, unit direction, requested radius, and how far out (in requested
// radii) the surface is searched.
struct Ray {
  Vec3 origin, dir;
  double radius;
  std::uint32_t edge;
  double limit;
};

void check(const RadiusErrorOptions& options) {
  detail::check_at_least(options.stations_per_edge, 1, "stations_per_edge");
  detail::check_at_least(options.directions, 1, "directions");
  if (!std::isfinite(options.search_factor) || options.search_factor <= 1) {
    throw InvalidArgument("search_factor must be finite and > 1, got " +
                          std::to_string(options.search_factor));
  }
  if (!std::isfinite(options.min_gap) || options.min_gap < 0) {
    throw InvalidArgument("min_gap must be finite and >= 0, got " +
                          std::to_string(options.min_gap));
  }
}

// Every station's rays, edge by edge.
std::vector<Ray> candidate_rays(const std::vector<EdgeGeometry>& edges,
                                const RadiusErrorOptions& options) {
  std::vector<Ray> rays;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const EdgeGeometry& g = edges[e];
    for (int k = 0; k < options.stations_per_edge; ++k) {
      const double t = (k + 0.5) / options.stations_per_edge;
      const Vec3 o = g.a + t * g.len * g.u;
      const double r = (1 - t) * g.ra + t * g.rb;
      for (int d = 0; d < options.directions; ++d) {
        const double angle =
            2 * std::numbers::pi * (d + kAnglePhase + 0.5 * (k % 2)) / options.directions;
        rays.push_back({o, pm::cos(angle) * g.e1 + pm::sin(angle) * g.e2, r,
                        static_cast<std::uint32_t>(e), options.search_factor});
      }
    }
  }
  return rays;
}

// Limits the ray's search to where it enters another tube; true when it is kept: its requested
// surface point is outside every other tube, and the entry (if any) is at least min_gap radii
// beyond it.
bool limit_ray(Ray& ray, const detail::TubeIndex& tubes, const RadiusErrorOptions& options,
               std::vector<std::uint32_t>& ids) {
  if (tubes.inside_other(ray.origin + ray.radius * ray.dir, ray.edge, ids)) return false;
  ids.clear();
  Aabb box;
  box.extend(ray.origin + ray.radius * ray.dir);
  box.extend(ray.origin + options.search_factor * ray.radius * ray.dir);
  tubes.query(box, ids);
  std::sort(ids.begin(), ids.end());
  const int steps = static_cast<int>(std::ceil((options.search_factor - 1) * kStepsPerRadius));
  for (int q = 1; q <= steps; ++q) {
    const double factor =
        std::min(options.search_factor, 1.0 + static_cast<double>(q) / kStepsPerRadius);
    const Vec3 p = ray.origin + factor * ray.radius * ray.dir;
    bool entered = false;
    for (const std::uint32_t e : ids) entered = entered || (e != ray.edge && tubes.inside(p, e));
    if (entered) {
      ray.limit = factor;
      break;
    }
  }
  return ray.limit - 1 >= options.min_gap;
}

// The kept rays of `candidates` (limited), in order.
std::vector<Ray> kept_rays(std::vector<Ray>& candidates, const std::vector<EdgeGeometry>& edges,
                           const RadiusErrorOptions& options, const Context* ctx) {
  const detail::TubeIndex tubes(edges);
  std::vector<char> keep(candidates.size(), 0);
  parallel::for_chunks(
      candidates.size(), detail::kRowGrain,
      [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t> ids;
        for (std::size_t j = begin; j < end; ++j)
          keep[j] = limit_ray(candidates[j], tubes, options, ids) ? 1 : 0;
      },
      ctx);
  std::vector<Ray> rays;
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    if (keep[j] != 0) rays.push_back(candidates[j]);
  }
  return rays;
}

// The field along the rays: one batch of points at given multiples of the rays' radii.
class RayProbe {
 public:
  RayProbe(const Field& field, const std::vector<Ray>& rays, const Context* ctx)
      : field_(field), rays_(rays), ctx_(ctx) {}

  // f - iso at rays[which[k]].origin + factor[k] radius dir, for every k.
  const std::vector<double>& operator()(const std::vector<std::size_t>& which,
                                        const std::vector<double>& factor) {
    pts_.resize(which.size());
    vals_.resize(which.size());
    for (std::size_t k = 0; k < which.size(); ++k) {
      const Ray& ray = rays_[which[k]];
      pts_[k] = ray.origin + factor[k] * ray.radius * ray.dir;
    }
    field_.evaluate(pts_, vals_, {}, ctx_);
    for (double& v : vals_) v -= field_.iso();
    return vals_;
  }

 private:
  const Field& field_;
  const std::vector<Ray>& rays_;
  const Context* ctx_;
  std::vector<Vec3> pts_;
  std::vector<double> vals_;
};

// Per ray, in requested radii: the measured radius when the bracketing decides it (0 when the
// skeleton itself is outside, the search limit when f > iso all the way), or a bracket of the
// crossing nearest the requested radius (lo inside, hi outside).
struct RayBrackets {
  std::vector<double> measured, lo, hi, g_lo, g_hi;
  explicit RayBrackets(std::size_t n)
      : measured(n, -1), lo(n, 0), hi(n, 0), g_lo(n, 0), g_hi(n, 0) {}
  void set_lo(std::size_t i, double x, double g) { lo[i] = x, g_lo[i] = g; }
  void set_hi(std::size_t i, double x, double g) { hi[i] = x, g_hi[i] = g; }
};

// The first two batches: on the skeleton (must be inside) and at the requested radius. Returns
// the rays to march outward (up) and inward (down).
void start_brackets(RayProbe& probe, RayBrackets& br, std::vector<std::size_t>& up,
                    std::vector<std::size_t>& down) {
  const std::size_t count = br.measured.size();
  std::vector<std::size_t> all(count);
  for (std::size_t i = 0; i < count; ++i) all[i] = i;
  const std::vector<double>& on_axis = probe(all, std::vector<double>(count, 0.0));
  std::vector<std::size_t> which;
  for (std::size_t i = 0; i < count; ++i) {
    if (on_axis[i] <= 0) {
      br.measured[i] = 0;  // the skeleton itself is outside
    } else {
      br.set_lo(i, 0, on_axis[i]);
      which.push_back(i);
    }
  }
  const std::vector<double>& at_radius = probe(which, std::vector<double>(which.size(), 1.0));
  for (std::size_t k = 0; k < which.size(); ++k) {
    const std::size_t i = which[k];
    if (at_radius[k] > 0) {
      br.set_lo(i, 1.0, at_radius[k]);
      up.push_back(i);
    } else {
      br.set_hi(i, 1.0, at_radius[k]);
      down.push_back(i);
    }
  }
}

// Marches the rays over the grids, one batch per step, until every ray is bracketed or decided.
void march_brackets(RayProbe& probe, const std::vector<Ray>& rays, RayBrackets& br,
                    std::vector<std::size_t> up, std::vector<std::size_t> down,
                    const Context* ctx) {
  std::vector<int> step_of(rays.size(), 0);
  while (!up.empty() || !down.empty()) {
    check_cancel(ctx);
    std::vector<std::size_t> which;
    std::vector<double> factor;
    for (const std::size_t i : up) {
      const auto s = static_cast<std::size_t>(step_of[i]);
      which.push_back(i);
      factor.push_back(s < kOutwardSteps ? std::min(kOutward[s], rays[i].limit) : rays[i].limit);
    }
    for (const std::size_t i : down) {
      which.push_back(i);
      factor.push_back(kInward[static_cast<std::size_t>(step_of[i])]);
    }
    const std::vector<double>& g = probe(which, factor);
    std::vector<std::size_t> next_up, next_down;
    for (std::size_t k = 0; k < which.size(); ++k) {
      const std::size_t i = which[k];
      const bool going_up = k < up.size();
      ++step_of[i];
      if (g[k] > 0) {
        br.set_lo(i, factor[k], g[k]);
        if (going_up) {
          if (factor[k] >= rays[i].limit)
            br.measured[i] = factor[k];  // no crossing before the limit
          else
            next_up.push_back(i);
        }
      } else {
        br.set_hi(i, factor[k], g[k]);
        // Going down past the grid: bracketed by the skeleton point (lo = 0).
        if (!going_up && static_cast<std::size_t>(step_of[i]) < kInwardSteps)
          next_down.push_back(i);
      }
    }
    up.swap(next_up);
    down.swap(next_down);
  }
}

// Refines every bracketed ray with the bracketed root finder, one batch per round, to
// kRelativeWidth; the measured radius is the final bracket's midpoint.
void refine_brackets(RayProbe& probe, RayBrackets& br, const Context* ctx) {
  std::vector<std::size_t> active;
  std::vector<RootBracket> roots(br.measured.size());
  for (std::size_t i = 0; i < br.measured.size(); ++i) {
    if (br.measured[i] >= 0) continue;
    roots[i] = RootBracket(br.lo[i], br.g_lo[i], br.hi[i], br.g_hi[i]);
    active.push_back(i);
  }
  std::vector<double> x;
  for (int it = 0; it < kMaxRefine && !active.empty(); ++it) {
    check_cancel(ctx);
    std::size_t keep = 0;
    for (const std::size_t i : active) {
      if (roots[i].width() > kRelativeWidth) active[keep++] = i;
    }
    active.resize(keep);
    if (active.empty()) break;
    x.resize(active.size());
    for (std::size_t k = 0; k < active.size(); ++k) x[k] = roots[active[k]].probe();
    const std::vector<double>& g = probe(active, x);
    for (std::size_t k = 0; k < active.size(); ++k) roots[active[k]].update(x[k], g[k]);
  }
  for (std::size_t i = 0; i < br.measured.size(); ++i) {
    if (br.measured[i] < 0) br.measured[i] = roots[i].midpoint();
  }
}

// The value of rank `rank` of `v` (reordered).
double nth_value(std::vector<double>& v, std::size_t rank) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(rank), v.end());
  return v[rank];
}

// The report's samples and statistics from the measured radii (in requested radii).
void summarize(const std::vector<Ray>& rays, const std::vector<double>& measured,
               std::size_t edge_count, RadiusErrorReport& report) {
  const std::size_t count = rays.size();
  report.edge_error.assign(edge_count, std::numeric_limits<double>::quiet_NaN());
  report.errors.resize(count);
  report.signed_errors.resize(count);
  report.sample_edge.resize(count);
  double sum = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double rho = measured[i] * rays[i].radius;
    const double err = std::abs(rho - rays[i].radius) / rays[i].radius;
    report.errors[i] = err;
    report.signed_errors[i] = (rho - rays[i].radius) / rays[i].radius;
    report.sample_edge[i] = rays[i].edge;
    double& edge = report.edge_error[rays[i].edge];
    edge = std::isnan(edge) ? err : std::max(edge, err);
    report.max = std::max(report.max, err);
    sum += err;
  }
  report.samples = count;
  if (count == 0) return;
  report.mean = sum / static_cast<double>(count);
  std::vector<double> sorted = report.errors;
  const std::size_t mid = count / 2;
  report.median = nth_value(sorted, mid);
  report.p90 =
      nth_value(sorted, static_cast<std::size_t>(std::floor(0.9 * static_cast<double>(count - 1))));
  if (count % 2 == 0) {
    (void)nth_value(sorted, mid);  // the lower half before mid, for its largest value
    report.median = 0.5 * (report.median +
                           *std::max_element(sorted.begin(),
                                             sorted.begin() + static_cast<std::ptrdiff_t>(mid)));
  }
}

}  // namespace

RadiusErrorReport measure_radius_error(const Field& field, const Skeleton& skeleton,
                                       const RadiusErrorOptions& options, Context* ctx) {
  check(options);
  validate(skeleton);
  const std::vector<EdgeGeometry> edges = detail::edge_geometry(skeleton);
  std::vector<Ray> candidates = candidate_rays(edges, options);
  const std::vector<Ray> rays = kept_rays(candidates, edges, options, ctx);
  RadiusErrorReport report;
  report.skipped = candidates.size() - rays.size();
  RayProbe probe(field, rays, ctx);
  RayBrackets brackets(rays.size());
  std::vector<std::size_t> up, down;
  start_brackets(probe, brackets, up, down);
  march_brackets(probe, rays, brackets, std::move(up), std::move(down), ctx);
  refine_brackets(probe, brackets, ctx);
  summarize(rays, brackets.measured, edges.size(), report);
  return report;
}

}  // namespace ramiform
