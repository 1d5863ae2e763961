// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/mesh/deviation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "field/bvh.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/roots.h"
#include "ramiform/mesh/surface_points.h"

namespace ramiform {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// f - iso and grad f at p (NaN when not finite).
struct Probe {
  double g = 0.0;
  Vec3 grad = Vec3::Zero();
};

Probe probe(const Field& field, const Vec3& p) {
  const std::array<Vec3, 1> points{p};
  std::array<double, 1> value{};
  std::array<Vec3, 1> gradient{};
  field.evaluate(points, value, gradient);
  return {value[0] - field.iso(), gradient[0]};
}

double offset_value(const Field& field, const Vec3& p) { return field.value(p) - field.iso(); }

/// The nearest crossing of f == iso on the ray p + t dir, 0 < t <= search, found by stepping
/// from `first`, doubling the step up to search / 16 (a shell thinner than that can be stepped
/// over), then refining the bracket; kInf when there is none (or a value is not finite).
double crossing_on_ray(const Field& field, const Vec3& p, double g0, const Vec3& dir,
                       double first, double search) {
  const double max_step = search / 16.0;
  double t_prev = 0.0, g_prev = g0;
  double t = std::min({first, max_step, search});
  for (;;) {
    const double gt = offset_value(field, p + t * dir);
    if (!std::isfinite(gt)) return kInf;
    if (gt == 0.0) return t;
    if ((gt > 0.0) != (g_prev > 0.0)) {
      RootOptions o;
      o.tolerance = 1e-12;
      o.max_steps = 200;
      const RootResult r = find_root(
          [&](double s) { return offset_value(field, p + s * dir); }, t_prev, t, o);
      return r.x;
    }
    if (t >= search) return kInf;
    const double step = std::min(std::max(t - t_prev, t), max_step);
    t_prev = t;
    g_prev = gt;
    t = std::min(t + step, search);
  }
}

/// Newton steps along the gradient from z onto the surface; false when they do not converge.
bool newton_to_surface(const Field& field, Vec3& z, double scale) {
  for (int k = 0; k < 20; ++k) {
    const Probe q = probe(field, z);
    const double gg = q.grad.squaredNorm();
    if (!std::isfinite(q.g) || !(gg > 0.0) || !std::isfinite(gg)) return false;
    const Vec3 step = (q.g / gg) * q.grad;
    z -= step;
    if (step.norm() <= 1e-13 * scale) return true;
  }
  return false;
}

/// distance_to_surface with f - iso and grad f at the point already evaluated (`p0`).
SurfaceDistance distance_from(const Field& field, const Vec3& point, const Probe& p0,
                              double search, int refine_steps) {
  SurfaceDistance out;
  out.distance = search;
  out.foot = point;
  if (!(search > 0.0) || !std::isfinite(search) || !point.allFinite()) return out;
  if (!std::isfinite(p0.g)) return out;
  if (p0.g == 0.0) return {0.0, point, true};
  // Towards the surface: f falls along -grad f inside (g > 0) and rises along +grad f outside.
  const double gn = p0.grad.norm();
  double best = kInf;
  Vec3 foot = point;
  auto try_ray = [&](const Vec3& dir, double first) {
    const double t = crossing_on_ray(field, point, p0.g, dir, first, std::min(search, best));
    if (t < best) {
      best = t;
      foot = point + t * dir;
    }
  };
  if (gn > 0.0 && std::isfinite(gn)) {
    const Vec3 dir = (p0.g > 0.0 ? -1.0 : 1.0) / gn * p0.grad;
    const double estimate = std::abs(p0.g) / gn;
    try_ray(dir, std::max(1.2 * estimate, 1e-9 * search));
    if (best == kInf) try_ray(-dir, search / 64.0);
  }
  if (best == kInf) {
    for (int axis = 0; axis < 3; ++axis) {
      for (const double sign : {1.0, -1.0}) {
        Vec3 dir = Vec3::Zero();
        dir[axis] = sign;
        try_ray(dir, search / 64.0);
      }
    }
  }
  if (best == kInf) return out;
  // Foot-point refinement: move along the tangent plane by the tangential part of p - y, back
  // onto the surface, and keep the move when it brings the surface point closer.
  for (int k = 0; k < refine_steps; ++k) {
    const Probe q = probe(field, foot);
    const double qn = q.grad.norm();
    if (!(qn > 0.0) || !std::isfinite(qn)) break;
    const Vec3 n = q.grad / qn;
    const Vec3 v = point - foot;
    const Vec3 w = v - v.dot(n) * n;
    if (w.norm() <= 1e-12 * std::max(best, 1e-300)) break;
    Vec3 z = foot + w;
    if (!newton_to_surface(field, z, search)) break;
    const double d = (point - z).norm();
    if (!(d < best)) break;
    best = d;
    foot = z;
  }
  return {best, foot, true};
}

/// distance_from for many points at once, in lockstep, with one batched field evaluation per
/// step for all points still at work (single-point evaluations cost several times more per
/// point): the crossing on the gradient line by Newton steps along it from the point, each kept
/// inside the bracket the steps before have established (from the point the first step lands on
/// the first-order estimate; where f is convex along the line the steps rise monotonically to
/// the nearest crossing), then the foot-point refinement of distance_from, its Newton steps
/// batched too. A point whose line steps leave their bracket, go beyond the search distance or
/// do not converge is projected by distance_from itself. `out[i]` is set for every i in `ids`.
void project_batch(const Field& field, std::span<const Vec3> points, std::span<const double> value,
                   std::span<const Vec3> grad, std::span<const double> search,
                   std::span<const std::size_t> ids, int refine_steps,
                   std::vector<SurfaceDistance>& out, Context* ctx) {
  const double iso = field.iso();
  const std::size_t n = ids.size();
  std::vector<Vec3> dir(n, Vec3::Zero());
  std::vector<double> t(n, 0.0), lo(n, 0.0), hi(n, 0.0), best(n, kInf);
  std::vector<Vec3> foot(n, Vec3::Zero());
  std::vector<char> fallback(n, 0);
  std::vector<std::size_t> active;
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t i = ids[j];
    const double g0 = value[i] - iso;
    const double gn = grad[i].norm();
    if (!std::isfinite(g0) || !(gn > 0.0) || !std::isfinite(gn) || !(search[i] > 0.0) ||
        !std::isfinite(search[i]) || g0 == 0.0) {
      fallback[j] = 1;
      continue;
    }
    dir[j] = (g0 > 0.0 ? -1.0 : 1.0) / gn * grad[i];
    t[j] = std::abs(g0) / gn;  // the first Newton step from the point
    hi[j] = search[i];
    if (!(t[j] < hi[j])) {
      fallback[j] = 1;
      continue;
    }
    active.push_back(j);
  }
  std::vector<Vec3> at;
  std::vector<double> v;
  std::vector<Vec3> g;
  auto evaluate = [&](const std::vector<std::size_t>& which, auto&& position) {
    at.resize(which.size());
    for (std::size_t k = 0; k < which.size(); ++k) at[k] = position(which[k]);
    v.resize(which.size());
    g.resize(which.size());
    field.evaluate(at, v, g, ctx);
  };
  // The crossing on the line.
  for (int step = 0; step < 24 && !active.empty(); ++step) {
    evaluate(active, [&](std::size_t j) { return Vec3(points[ids[j]] + t[j] * dir[j]); });
    std::vector<std::size_t> next;
    for (std::size_t k = 0; k < active.size(); ++k) {
      const std::size_t j = active[k];
      const double gt = v[k] - iso;
      const double slope = g[k].dot(dir[j]);
      if (!std::isfinite(gt) || !std::isfinite(slope)) {
        fallback[j] = 1;
        continue;
      }
      if (gt == 0.0) {
        best[j] = t[j];
        continue;
      }
      const bool same_side = (gt > 0.0) == (value[ids[j]] - iso > 0.0);
      (same_side ? lo[j] : hi[j]) = t[j];
      const double tn = t[j] - gt / slope;
      if (!(tn > lo[j] && tn < hi[j])) {
        fallback[j] = 1;
        continue;
      }
      const double moved = std::abs(tn - t[j]);
      t[j] = tn;
      if (moved <= 1e-13 * search[ids[j]]) {
        best[j] = t[j];
        continue;
      }
      next.push_back(j);
    }
    active = std::move(next);
  }
  for (const std::size_t j : active) fallback[j] = 1;  // not converged
  active.clear();
  for (std::size_t j = 0; j < n; ++j) {
    if (fallback[j] != 0) continue;
    foot[j] = points[ids[j]] + best[j] * dir[j];
    active.push_back(j);
  }
  // Foot-point refinement, as in distance_from.
  std::vector<Vec3> z(n, Vec3::Zero());
  for (int r = 0; r < refine_steps && !active.empty(); ++r) {
    evaluate(active, [&](std::size_t j) { return foot[j]; });
    std::vector<std::size_t> moving;
    for (std::size_t k = 0; k < active.size(); ++k) {
      const std::size_t j = active[k];
      const double qn = g[k].norm();
      if (!(qn > 0.0) || !std::isfinite(qn)) continue;
      const Vec3 nrm = g[k] / qn;
      const Vec3 d = points[ids[j]] - foot[j];
      const Vec3 w = d - d.dot(nrm) * nrm;
      if (w.norm() <= 1e-12 * std::max(best[j], 1e-300)) continue;
      z[j] = foot[j] + w;
      moving.push_back(j);
    }
    // Newton steps along the gradient onto the surface (newton_to_surface, batched).
    std::vector<std::size_t> converged;
    for (int k = 0; k < 20 && !moving.empty(); ++k) {
      evaluate(moving, [&](std::size_t j) { return z[j]; });
      std::vector<std::size_t> still;
      for (std::size_t m = 0; m < moving.size(); ++m) {
        const std::size_t j = moving[m];
        const double q = v[m] - iso;
        const double gg = g[m].squaredNorm();
        if (!std::isfinite(q) || !(gg > 0.0) || !std::isfinite(gg)) continue;
        const Vec3 step = (q / gg) * g[m];
        z[j] -= step;
        (step.norm() <= 1e-13 * search[ids[j]] ? converged : still).push_back(j);
      }
      moving = std::move(still);
    }
    std::sort(converged.begin(), converged.end());
    std::vector<std::size_t> next;
    for (const std::size_t j : converged) {
      const double d = (points[ids[j]] - z[j]).norm();
      if (!(d < best[j])) continue;
      best[j] = d;
      foot[j] = z[j];
      next.push_back(j);
    }
    active = std::move(next);
  }
  std::vector<std::size_t> rest;
  for (std::size_t j = 0; j < n; ++j) {
    if (fallback[j] != 0) {
      rest.push_back(j);
    } else {
      out[ids[j]] = {best[j], foot[j], true};
    }
  }
  parallel::for_each(
      rest.size(), 16,
      [&](std::size_t k) {
        const std::size_t i = ids[rest[k]];
        out[i] =
            distance_from(field, points[i], {value[i] - iso, grad[i]}, search[i], refine_steps);
      },
      ctx);
}

}  // namespace

SurfaceDistance distance_to_surface(const Field& field, const Vec3& point, double search,
                                    int refine_steps) {
  if (!(search > 0.0) || !std::isfinite(search) || !point.allFinite()) {
    return {search, point, false};
  }
  return distance_from(field, point, probe(field, point), search, refine_steps);
}

std::vector<double> local_radii(const Skeleton& skeleton, std::span<const Vec3> points,
                                const Context* ctx) {
  if (skeleton.nodes.empty()) throw InvalidArgument("local_radii: the skeleton has no nodes");
  // Segments: every edge, plus every node without an edge as a segment of length 0.
  std::vector<std::array<std::uint32_t, 2>> segments = skeleton.edges;
  const std::vector<std::uint32_t> degree = degrees(skeleton);
  for (std::uint32_t i = 0; i < skeleton.nodes.size(); ++i) {
    if (degree[i] == 0) segments.push_back({i, i});
  }
  std::vector<Aabb> boxes;
  boxes.reserve(segments.size());
  for (const auto& [a, b] : segments) {
    Aabb box(skeleton.nodes[a].position);
    box.extend(skeleton.nodes[b].position);
    boxes.push_back(box);
  }
  const detail::BoxBvh bvh(std::move(boxes));
  std::vector<double> radii(points.size(), 0.0);
  parallel::for_chunks(
      points.size(), 512,
      [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          const Vec3& p = points[i];
          // The parameter of p's closest point on segment s (0 at its first node).
          const auto closest = [&](std::uint32_t s) {
            const Vec3& a = skeleton.nodes[segments[s][0]].position;
            const Vec3 ab = skeleton.nodes[segments[s][1]].position - a;
            const double len2 = ab.squaredNorm();
            return len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
          };
          const std::uint32_t id = bvh.nearest(p, [&](std::uint32_t s) {
            const Vec3& a = skeleton.nodes[segments[s][0]].position;
            const Vec3& b = skeleton.nodes[segments[s][1]].position;
            return (p - (a + closest(s) * (b - a))).squaredNorm();
          });
          if (id == UINT32_MAX) continue;  // not finite: radius 0
          const auto& n0 = skeleton.nodes[segments[id][0]];
          const auto& n1 = skeleton.nodes[segments[id][1]];
          const double u = closest(id);
          radii[i] = n0.radius + u * (n1.radius - n0.radius);
        }
      },
      ctx);
  return radii;
}

namespace {

void validate(const DeviationOptions& o) {
  if (!(o.search_radii > 0.0) || !std::isfinite(o.search_radii)) {
    throw InvalidArgument("deviation: search_radii must be finite and > 0, got " +
                          format_number(o.search_radii));
  }
  if (!(o.search_distance >= 0.0) || !std::isfinite(o.search_distance)) {
    throw InvalidArgument("deviation: search_distance must be finite and >= 0, got " +
                          format_number(o.search_distance));
  }
  if (o.refine_steps < 0) {
    throw InvalidArgument("deviation: refine_steps must be >= 0, got " +
                          std::to_string(o.refine_steps));
  }
}

// The first-order shortcut's reach, relative to the search distance (see deviation.h): sample
// points anywhere on the triangles, and the vertices a mesher put on the surface.
constexpr double kFirstOrderSamples = 1e-7;
constexpr double kFirstOrderVertices = 1e-3;

double nearest_rank(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  const auto n = static_cast<double>(values.size());
  auto k = static_cast<std::size_t>(std::ceil(q * n));
  k = std::clamp<std::size_t>(k, 1, values.size()) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

/// Projects every point and summarises.
DeviationSummary summarise(const Field& field, const std::vector<Vec3>& points,
                           const Skeleton* skeleton, double search_distance,
                           const DeviationOptions& o, double first_order, Context* ctx) {
  DeviationSummary s;
  s.points = points.size();
  if (points.empty()) return s;
  std::vector<double> radius;
  if (skeleton != nullptr) radius = local_radii(*skeleton, points, ctx);
  std::vector<double> abs(points.size()), rel(points.size(), 0.0);
  std::vector<char> resolved(points.size(), 0);
  // One batch evaluation first: a point already within `first_order` of the search distance of
  // the surface to first order (a polygonizer's vertex) takes the first-order distance
  // |f - iso| / |grad f|, whose error is of its square over the curvature radius.
  std::vector<double> value(points.size());
  std::vector<Vec3> grad(points.size());
  field.evaluate(points, value, grad, ctx);
  std::vector<double> search(points.size());
  std::vector<SurfaceDistance> found(points.size());
  std::vector<std::size_t> project;
  for (std::size_t i = 0; i < points.size(); ++i) {
    search[i] = skeleton != nullptr ? o.search_radii * radius[i] : search_distance;
    const double gn = grad[i].norm();
    const double first = std::abs(value[i] - field.iso()) / gn;
    if (gn > 0.0 && std::isfinite(first) && first <= first_order * search[i]) {
      found[i] = {first, points[i], true};
    } else if (!(search[i] > 0.0) || !std::isfinite(search[i]) || !points[i].allFinite()) {
      found[i] = {search[i], points[i], false};
    } else {
      project.push_back(i);
    }
  }
  project_batch(field, points, value, grad, search, project, o.refine_steps, found, ctx);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double r = skeleton != nullptr ? radius[i] : 0.0;
    const SurfaceDistance& d = found[i];
    abs[i] = d.distance;
    resolved[i] = d.resolved ? 1 : 0;
    if (skeleton != nullptr) rel[i] = r > 0.0 ? d.distance / r : (d.distance > 0 ? kInf : 0);
  }
  const std::vector<double>& key = skeleton != nullptr ? rel : abs;
  std::size_t worst = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (resolved[i] == 0) ++s.unresolved;
    if (key[i] > key[worst]) worst = i;
  }
  s.worst = points[worst];
  s.abs_p50 = nearest_rank(abs, 0.5);
  s.abs_p99 = nearest_rank(abs, 0.99);
  s.abs_max = *std::max_element(abs.begin(), abs.end());
  if (skeleton != nullptr) {
    s.p50 = nearest_rank(rel, 0.5);
    s.p99 = nearest_rank(rel, 0.99);
    s.max = *std::max_element(rel.begin(), rel.end());
  }
  return s;
}

}  // namespace

DeviationReport measure_deviation(const TriMesh& mesh, const Field& field,
                                  const Skeleton* skeleton, const DeviationOptions& options,
                                  Context* ctx) {
  validate(options);
  if (skeleton != nullptr && skeleton->nodes.empty()) {
    throw InvalidArgument("deviation: the skeleton has no nodes");
  }
  const std::uint64_t evals_before = field.evaluations();
  const MeshAreaSampler sampler(mesh);  // validates indices and vertices
  double search = options.search_distance;
  if (search == 0.0) {
    Aabb box;
    for (const auto& tri : mesh.triangles)
      for (const auto v : tri) box.extend(mesh.positions[v]);
    search = box.isEmpty() ? 1.0 : 0.1 * box.diagonal().norm();
    if (!(search > 0.0)) search = 1.0;
  }
  DeviationReport report;
  report.relative = skeleton != nullptr;
  // Per point: its position, value, gradient, radius and two distances (about 80 bytes).
  check_memory(ctx, 80.0 * static_cast<double>(options.samples),
               "deviation: " + std::to_string(options.samples) + " sample points",
               "ask for fewer samples");
  if (options.samples > 0 && sampler.total_area() > 0.0) {
    std::vector<Vec3> points(options.samples);
    Rng rng(options.seed);
    for (auto& p : points) p = sampler.position(sampler.draw(rng));
    report.samples = summarise(field, points, skeleton, search, options, kFirstOrderSamples, ctx);
  }
  if (options.vertices) {
    std::vector<char> used(mesh.positions.size(), 0);
    for (const auto& tri : mesh.triangles)
      for (const auto v : tri) used[v] = 1;
    std::vector<Vec3> points;
    for (std::size_t v = 0; v < used.size(); ++v)
      if (used[v] != 0) points.push_back(mesh.positions[v]);
    report.vertices =
        summarise(field, points, skeleton, search, options, kFirstOrderVertices, ctx);
  }
  report.field_evaluations = field.evaluations() - evals_before;
  return report;
}

}  // namespace ramiform
