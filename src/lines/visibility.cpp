// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Hidden lines: classify_visibility() of lines.h.
//
// kSurfels follows Proença, Jorge & Costa Sousa 2008, "Suggestive Contours over Point-Set
// Implicits" (GRAPP), §3 (after Foster et al. 2005, "Drawing surfaces"): every particle carries
// a disk oriented by its normal, of radius the distance to its nearest particle, placed slightly
// behind the particle; the disks fill a depth buffer and a line point shows where it is not
// behind the buffer. kRays asks the field itself instead: is any point of the segment from the
// eye to the line point inside the surface?
//
// Deviation from the paper: the radius is the distance to the third nearest particle. The
// paper's nearest distance leaves holes wherever the particles are unevenly spread: on 10,000
// particles of an MPU bunny (spacing CV 0.16), 32 of 1,870 points away from contours that rays
// found hidden (some behind 30 δ of solid) showed through such holes; with the second nearest
// 23, the third 17. On an even spread (a hexagonal one) all three distances are equal.
//
// kRays. The segment eye → p is shortened by occlusion_tolerance·δ at p's end (the point q);
// a line point lies on the surface, so without the shortening the surface it sits on would hide
// it wherever the segment grazes or leaves through it. What the test stands for: the part of
// the segment in field.bounds() (nothing outside is inside) is cut into N equal pieces, N the
// fewest with pieces at most kLeaf·δ long, and the point is hidden when f > iso at q or at the
// midpoint of a piece (a sample). So an inside stretch of the segment longer than kLeaf·δ (an
// occluder the ray crosses over more than that) always holds a sample; only the existence of an
// inside sample matters, no root is located. detail::rays_visibility_exhaustive
// (visibility_reference.h) evaluates every sample; the rounds below give the same flags while
// evaluating few of them:
//   1. f at the eye and at every q (one batch): an inside q (the common case of a hidden point,
//      the solid in front of it reaching within the tolerance) settles the point.
//   2. Each open segment, on its own (in parallel, so the flags do not depend on the thread
//      count): the samples interval bounds do not prove outside (f ≤ iso). On an MPU field,
//      detail::mpu_ray_samples walks the octree cells the segment crosses: subtrees proven
//      outside once for all views are skipped whole, and in the other cells the samples are
//      bounded in halving runs over the cell's own local functions only. On other fields, runs
//      of samples doubling in length from q's end (2, 4, 8, …: the box of a run that reaches
//      the surface the point sits on never clears, and a large box is costly to bound) are
//      halved under field.bound() of their boxes. Short runs (a few samples) are left open
//      without a bound. A run proven inside (bound's lo > iso) names one of its samples, the
//      candidate, and the segment stops there.
//   3. The candidates and the open samples are evaluated in one batch; any f > iso hides the
//      point. (A candidate not confirmed — rounding at the edge of a bound, never seen — sends
//      its segment through round 2 again without stopping at proofs of inside.)
// Measured on the bunny (10,000 particles, docs/benchmarks.md): 2.3 times less time than the
// bounds of boxes around groups of rays this replaced (an MPU field's bound(box) visits every
// leaf whose support meets the box), with three times the evaluations.
//
// kSurfels. The depth buffer covers the camera's frame (camera.h). Its value for a line point
// is the least depth, over the disks, of the point where the view ray through the line point
// meets a disk: a depth buffer sampled at the point's own image position instead of a pixel
// centre. Near a contour the surface's depth changes without bound across the image, so a
// buffer sampled half a pixel away from a contour point sees its own surface well in front of
// it (on a unit sphere seen from 4 units, half a pixel of a 1024-pixel buffer is 0.04 in
// depth, about a third of δ for 1,500 particles). The min is order independent, and only the
// values at line points are ever read, so only those are computed: the disks' conservative
// image rectangles (of their bounding cubes) are binned into tiles of 8×8 pixels of a grid
// with surfel_resolution pixels along the frame's height, and each line point meets the disks
// of its tile. Measured on the tests' two spheres (disks one radius back): sampled at pixel
// centres, the flags differed from the analytic ones on 20 % of the points at 128 pixels, 9 %
// at 256, 0.06 % at 1024; sampled at the points, on 0.09 % at every resolution, all within the
// tolerance band (the resolution then sets only the bins, hence the speed). "Slightly behind": each
// disk is moved away from the eye, along the view ray through its particle, by kSurfelBehind times
// its radius. On a sphere, a disk tangent at a particle covers a contour point's image position
// from as far as twice its radius, and lies in front of the contour point by as much as the
// in-plane distance to it, up to its radius: so the disks go back by their radius (with
// nearest-particle radii, half of it left 24 % of the tests' lone sphere's contour hidden, three
// quarters none). Offsetting along −n instead, the paper's other reading, barely moves a disk in
// depth near a contour and shrinks the outline of occluders instead. A line point is visible when
// its depth ≤ buffer + occlusion_tolerance·δ; points outside the frame or behind the eye are left
// visible (the frame is all the buffer covers, and they are not drawn). The price of the offset: an
// occluder thinner than a disk's radius plus the tolerance does not hide what lies right behind it.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "field/mpu_rays.h"
#include "field/point_kdtree.h"
#include "lines/line_common.h"
#include "lines/visibility_reference.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/lines/lines.h"

namespace ramiform {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = 3.14159265358979323846 / 180.0;

/// kRays: the longest piece of a segment around one sample, × δ at its line point.
constexpr double kLeaf = 0.5;
/// kRays (fields other than MPU): runs of at most this many samples are left open without a
/// bound.
constexpr std::int64_t kDirectRun = 3;
/// kSurfels: how far each disk is moved away from the eye, × its radius.
constexpr double kSurfelBehind = 1.0;
/// kSurfels: a disk's radius is the distance to this nearest other particle.
constexpr int kNeighbour = 3;

/// Every line point of the lines, in order, with δ from its nearest particle.
struct Points {
  std::vector<Vec3> p;
  std::vector<std::uint32_t> line;  ///< index of the point's line
  std::vector<double> delta;
};

Points gather(std::span<const Polyline> lines, const ParticleSystem& particles,
              const detail::PointKdTree& tree, const Context* ctx) {
  Points pts;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    for (const Vec3& p : lines[l].points) {
      pts.p.push_back(p);
      pts.line.push_back(static_cast<std::uint32_t>(l));
    }
  }
  pts.delta.resize(pts.p.size());
  parallel::for_chunks(
      pts.p.size(), 256,
      [&](std::size_t b, std::size_t e) {
        std::vector<std::pair<std::uint32_t, double>> near;
        for (std::size_t i = b; i < e; ++i) {
          tree.nearest(pts.p[i], 1, near);
          pts.delta[i] = particles.particles[near[0].first].delta;
        }
      },
      ctx);
  return pts;
}

// ---- kRays ---------------------------------------------------------------------------------

/// The shortened segment eye → q of every line point, and the points it settles without
/// samples (round 1 of the file comment).
struct Segments {
  std::vector<Vec3> q;                  ///< q of point i at i + 1; the eye at 0
  std::vector<std::uint8_t> settled;    ///< 1: visible[i] is final after round 1
  std::vector<detail::RaySamples> ray;  ///< the samples of the points not settled
  std::vector<std::uint32_t> point;     ///< the line point of each ray
  std::uint64_t evals = 0;
};

/// [lo, hi] of s in [0, 1] where eye + s·dir lies in the closed box; lo > hi when nowhere.
std::pair<double, double> clip(const Vec3& eye, const Vec3& dir, const Aabb& box) {
  double lo = 0, hi = 1;
  for (int k = 0; k < 3; ++k) {
    const double a = box.min()[k], b = box.max()[k];
    if (dir[k] == 0) {
      if (eye[k] < a || eye[k] > b) return {1, 0};
      continue;
    }
    double t0 = (a - eye[k]) / dir[k], t1 = (b - eye[k]) / dir[k];
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  return {lo, hi};
}

/// Rounds 1 and 2 of the file comment's kRays: sets visible[i] of the settled points (and
/// visible = 1 for the others, until a sample says otherwise).
Segments segments(const Field& field, const Camera& camera, const Points& pts, double tolerance,
                  std::vector<std::uint8_t>& visible, const Context* ctx) {
  const std::size_t n = pts.p.size();
  const Vec3& eye = camera.eye;
  const double iso = field.iso();
  Segments out;
  out.q.resize(n + 1);
  out.q[0] = eye;
  out.settled.assign(n, 1);
  std::vector<std::uint8_t> empty(n, 0);  // the shortened segment is empty: nothing in front
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = pts.p[i] - eye;
    const double len = d.norm();
    const double cut = tolerance * pts.delta[i];
    if (!(len > cut)) {
      empty[i] = 1;
      out.q[i + 1] = eye;
    } else {
      out.q[i + 1] = eye + d * ((len - cut) / len);
    }
  }
  std::vector<double> f(out.q.size());
  field.evaluate(out.q, f, {}, ctx);
  out.evals = out.q.size();
  if (f[0] > iso) {  // the eye is inside: every segment starts inside
    for (std::size_t i = 0; i < n; ++i) visible[i] = empty[i];
    return out;
  }
  const Aabb bounds = field.bounds();
  for (std::size_t i = 0; i < n; ++i) {
    visible[i] = f[i + 1] > iso && empty[i] == 0 ? 0 : 1;
    if (empty[i] != 0 || f[i + 1] > iso) continue;
    detail::RaySamples r;
    r.origin = eye;
    r.dir = out.q[i + 1] - eye;
    const auto [lo, hi] = clip(eye, r.dir, bounds);
    if (!(lo <= hi)) continue;  // never inside the bounds: clear
    // The longest piece, in s units (floored at a millionth of the segment: δ ≤ 0 must not
    // ask for samples without end).
    const double leaf = std::max(kLeaf * pts.delta[i] / r.dir.norm(), 1e-6);
    const double pieces = std::max(1.0, std::ceil((hi - lo) / leaf));
    r.count = static_cast<std::uint32_t>(pieces);
    r.step = (hi - lo) / pieces;
    r.first = lo + 0.5 * r.step;
    out.settled[i] = 0;
    out.ray.push_back(r);
    out.point.push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

/// The samples of `ray` that field.bound() does not prove outside (any field): runs of samples
/// from the line point's end doubling in length (2, 4, 8, … samples: the box of a run that
/// reaches the surface the point lies on never clears, and a large one is costly to bound), each
/// halved until proven outside, proven inside (then, with stop_inside, its middle sample is the
/// candidate returned) or at most kDirectRun samples long (then left open).
std::int64_t bound_samples(const Field& field, const detail::RaySamples& ray, bool stop_inside,
                           std::vector<std::uint32_t>& open) {
  open.clear();
  // Boxes are widened by a hair over the samples' rounding (some 1e-16 of the coordinates).
  const double hair = 1e-9 * (ray.origin.cwiseAbs().maxCoeff() + ray.dir.cwiseAbs().maxCoeff());
  const double iso = field.iso();
  std::vector<std::pair<std::int64_t, std::int64_t>> runs;
  const auto last = static_cast<std::int64_t>(ray.count) - 1;
  for (std::int64_t end = last, length = 2; end >= 0; length *= 2) {
    const std::int64_t begin = std::max<std::int64_t>(0, end - length + 1);
    runs.emplace_back(begin, end);
    end = begin - 1;
  }
  std::reverse(runs.begin(), runs.end());  // the runs nearest the point first
  while (!runs.empty()) {
    const auto [r0, r1] = runs.back();
    runs.pop_back();
    if (r1 - r0 < kDirectRun) {
      for (std::int64_t k = r0; k <= r1; ++k) open.push_back(static_cast<std::uint32_t>(k));
      continue;
    }
    Aabb box;
    box.extend(detail::ray_sample(ray, static_cast<std::uint32_t>(r0)));
    box.extend(detail::ray_sample(ray, static_cast<std::uint32_t>(r1)));
    box = Aabb(box.min() - Vec3::Constant(hair), box.max() + Vec3::Constant(hair));
    const Interval range = field.bound(box);
    if (range.hi <= iso) continue;
    if (range.lo > iso && stop_inside) return r0 + (r1 - r0) / 2;
    const std::int64_t mid = r0 + (r1 - r0) / 2;
    runs.emplace_back(mid + 1, r1);
    runs.emplace_back(r0, mid);
  }
  std::sort(open.begin(), open.end());
  return -1;
}

/// The samples of a ray left to evaluate: the MPU's walk through its cells
/// (detail::mpu_ray_samples), else bound_samples.
std::int64_t open_samples(const Field& field, const detail::RaySamples& ray, bool stop_inside,
                          std::vector<std::uint32_t>& open) {
  std::int64_t candidate = -1;
  if (detail::mpu_ray_samples(field, ray, stop_inside, candidate, open)) return candidate;
  return bound_samples(field, ray, stop_inside, open);
}

std::uint64_t classify_rays(const Field& field, const Camera& camera, const Points& pts,
                            double tolerance, std::vector<std::uint8_t>& visible,
                            const Context* ctx) {
  const Segments seg = segments(field, camera, pts, tolerance, visible, ctx);
  std::uint64_t evals = seg.evals;
  const std::size_t m = seg.ray.size();
  if (m == 0) return evals;
  const double iso = field.iso();
  // Round 3: the samples each ray leaves open, or a candidate proven inside.
  std::vector<std::vector<std::uint32_t>> open(m);
  std::vector<std::int64_t> candidate(m, -1);
  parallel::for_chunks(
      m, 8,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t r = b; r < e; ++r)
          candidate[r] = open_samples(field, seg.ray[r], true, open[r]);
      },
      ctx);
  // Round 4: evaluate them, in ray order; any sample inside hides the point.
  auto evaluate = [&](const std::vector<std::uint32_t>& which) {
    std::vector<Vec3> x;
    std::vector<std::uint32_t> owner;
    for (const std::uint32_t r : which) {
      if (candidate[r] >= 0) {
        x.push_back(detail::ray_sample(seg.ray[r], static_cast<std::uint32_t>(candidate[r])));
        owner.push_back(r);
        continue;
      }
      for (const std::uint32_t k : open[r]) {
        x.push_back(detail::ray_sample(seg.ray[r], k));
        owner.push_back(r);
      }
    }
    std::vector<double> f(x.size());
    field.evaluate(x, f, {}, ctx);
    evals += x.size();
    std::vector<std::uint8_t> inside(m, 0);
    for (std::size_t k = 0; k < x.size(); ++k)
      if (f[k] > iso) inside[owner[k]] = 1;
    return inside;
  };
  std::vector<std::uint32_t> all(m);
  for (std::uint32_t r = 0; r < m; ++r) all[r] = r;
  const std::vector<std::uint8_t> inside = evaluate(all);
  // A candidate the bounds proved inside that its evaluation does not confirm (rounding at
  // the edge of a bound; never seen): that ray again, without stopping at proofs of inside.
  std::vector<std::uint32_t> again;
  for (std::uint32_t r = 0; r < m; ++r) {
    if (inside[r] != 0) {
      visible[seg.point[r]] = 0;
    } else if (candidate[r] >= 0) {
      again.push_back(r);
    }
  }
  if (!again.empty()) {
    for (const std::uint32_t r : again)
      candidate[r] = open_samples(field, seg.ray[r], false, open[r]);
    const std::vector<std::uint8_t> second = evaluate(again);
    for (const std::uint32_t r : again)
      if (second[r] != 0) visible[seg.point[r]] = 0;
  }
  return evals;
}

// ---- kSurfels ------------------------------------------------------------------------------

/// A particle's disk in camera coordinates (x right, y up, z = depth).
struct Disk {
  Vec3 c;  ///< centre, moved behind the particle
  Vec3 n;  ///< unit normal
  double r2 = 0;
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;  ///< covered pixels (inclusive), x0 > x1 when none
};

void classify_surfels(const ParticleSystem& particles, const std::vector<double>& radii,
                      const Camera& camera, const Points& pts, const LineOptions& options,
                      std::vector<std::uint8_t>& visible, const Context* ctx) {
  const CameraFrame frame = camera_frame(camera);
  const double half_h = std::tan(0.5 * camera.fov_deg * kDeg);
  const int height = options.surfel_resolution;
  const int width = static_cast<int>(
      std::clamp(std::round(camera.aspect * height), 1.0, static_cast<double>(1 << 24)));
  const double pixel = 2 * half_h / height;  // pixel size in camera units
  const double left = -0.5 * width * pixel;
  // Pixel column / row of image coordinates (rows from the top).
  auto column = [&](double x) { return std::floor((x - left) / pixel); };
  auto row = [&](double y) { return std::floor((half_h - y) / pixel); };
  auto to_camera = [&](const Vec3& v) {
    return Vec3(v.dot(frame.right), v.dot(frame.up), v.dot(frame.forward));
  };

  const std::size_t m = particles.particles.size();
  std::vector<Disk> disks(m);
  parallel::for_chunks(
      m, 256,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const SurfaceParticle& sp = particles.particles[i];
          const double r = radii[i];
          Disk& d = disks[i];
          const Vec3 rel = sp.position - camera.eye;
          const double dist = rel.norm();
          if (!(dist > 0)) continue;
          d.c = to_camera(rel + (kSurfelBehind * r / dist) * rel);
          d.n = to_camera(sp.normal);
          d.r2 = r * r;
          if (!(d.c.z() - r > 0)) continue;  // reaches the eye's plane: not drawn
          // Conservative image rectangle: x = X/Z over the disk's bounding cube.
          const double za = d.c.z() - r, zb = d.c.z() + r;
          const double xa = d.c.x() - r, xb = d.c.x() + r;
          const double ya = d.c.y() - r, yb = d.c.y() + r;
          const double xmin = std::min(xa / za, xa / zb), xmax = std::max(xb / za, xb / zb);
          const double ymin = std::min(ya / za, ya / zb), ymax = std::max(yb / za, yb / zb);
          const double c0 = std::max(column(xmin), 0.0);
          const double c1 = std::min(column(xmax), width - 1.0);
          const double r0 = std::max(row(ymax), 0.0);
          const double r1 = std::min(row(ymin), height - 1.0);
          if (c0 > c1 || r0 > r1) continue;
          d.x0 = static_cast<int>(c0);
          d.x1 = static_cast<int>(c1);
          d.y0 = static_cast<int>(r0);
          d.y1 = static_cast<int>(r1);
        }
      },
      ctx);

  // The pixel of every line point (-1: not in the frame or not in front of the eye).
  const std::size_t n = pts.p.size();
  std::vector<std::int64_t> pixel_of(n, -1);
  std::vector<double> depth(n, 0);
  std::vector<Vec2> image(n, Vec2::Zero());
  for (std::size_t i = 0; i < n; ++i) {
    const Projected pr = project(camera, frame, pts.p[i]);
    depth[i] = pr.depth;
    image[i] = Vec2(pr.x, pr.y);
    if (!(pr.depth > 0)) continue;
    const double cx = column(pr.x), cy = row(pr.y);
    if (!(cx >= 0 && cx < width && cy >= 0 && cy < height)) continue;
    pixel_of[i] = static_cast<std::int64_t>(cy) * width + static_cast<std::int64_t>(cx);
  }

  // Bin the disks into tiles, only the tiles some line point falls in.
  const int tile = std::max(8, (std::max(width, height) + 127) / 128);
  const int tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
  const std::size_t tiles = static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y);
  std::vector<std::uint8_t> wanted(tiles, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (pixel_of[i] < 0) continue;
    const std::int64_t px = pixel_of[i] % width, py = pixel_of[i] / width;
    wanted[static_cast<std::size_t>(py / tile * tiles_x + px / tile)] = 1;
  }
  std::vector<std::size_t> start(tiles + 1, 0);
  auto for_tiles = [&](const Disk& d, auto&& fn) {
    for (int ty = d.y0 / tile; ty <= d.y1 / tile; ++ty) {
      for (int tx = d.x0 / tile; tx <= d.x1 / tile; ++tx) {
        const std::size_t t = static_cast<std::size_t>(ty) * tiles_x + static_cast<std::size_t>(tx);
        if (wanted[t] != 0) fn(t);
      }
    }
  };
  for (const Disk& d : disks) {
    if (d.x0 <= d.x1) for_tiles(d, [&](std::size_t t) { ++start[t + 1]; });
  }
  for (std::size_t t = 0; t < tiles; ++t) start[t + 1] += start[t];
  std::vector<std::uint32_t> binned(start[tiles]);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t k = 0; k < disks.size(); ++k) {
      if (disks[k].x0 <= disks[k].x1)
        for_tiles(disks[k], [&](std::size_t t) { binned[fill[t]++] = k; });
    }
  }

  parallel::for_chunks(
      n, 256,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          visible[i] = 1;
          if (pixel_of[i] < 0) continue;
          const int px = static_cast<int>(pixel_of[i] % width);
          const int py = static_cast<int>(pixel_of[i] / width);
          const std::size_t t =
              static_cast<std::size_t>(py / tile) * tiles_x + static_cast<std::size_t>(px / tile);
          // The ray through the point: t·(x, y, 1), t the depth.
          const Vec3 ray(image[i].x(), image[i].y(), 1.0);
          double buffer = kInf;
          for (std::size_t k = start[t]; k < start[t + 1]; ++k) {
            const Disk& d = disks[binned[k]];
            if (px < d.x0 || px > d.x1 || py < d.y0 || py > d.y1) continue;
            const double nd = d.n.dot(ray);
            if (nd == 0) continue;
            const double z = d.n.dot(d.c) / nd;
            if (!(z > 0) || !(z < buffer)) continue;
            if ((z * ray - d.c).squaredNorm() <= d.r2) buffer = z;
          }
          if (depth[i] > buffer + options.occlusion_tolerance * pts.delta[i]) visible[i] = 0;
        }
      },
      ctx);
}

}  // namespace

std::vector<double> detail::surfel_radii(const ParticleSystem& particles, const PointKdTree& tree,
                                         const Context* ctx) {
  const std::size_t m = particles.particles.size();
  std::vector<double> radii(m);
  parallel::for_chunks(
      m, 256,
      [&](std::size_t b, std::size_t e) {
        std::vector<std::pair<std::uint32_t, double>> near;
        for (std::size_t i = b; i < e; ++i) {
          const SurfaceParticle& sp = particles.particles[i];
          // The distance to the kNeighbour-th nearest other particle (coincident ones do not
          // count; with fewer, the farthest found, or δ for a lone particle).
          double r = sp.delta;
          for (std::size_t k = kNeighbour + 1;; k *= 2) {
            tree.nearest(sp.position, k, near);
            int found = 0;
            for (const auto& [j, d2] : near) {
              if (j == i || !(d2 > 0)) continue;
              r = std::sqrt(d2);
              if (++found == kNeighbour) break;
            }
            if (found == kNeighbour || near.size() < k) break;  // done, or no more particles
          }
          radii[i] = r;
        }
      },
      ctx);
  return radii;
}

std::vector<std::uint8_t> detail::rays_visibility_exhaustive(
    const Field& field, const ParticleSystem& particles, const Camera& camera,
    std::span<const Polyline> lines, double occlusion_tolerance, const Context* ctx) {
  std::vector<Vec3> positions(particles.particles.size());
  for (std::size_t i = 0; i < positions.size(); ++i) positions[i] = particles.particles[i].position;
  const detail::PointKdTree tree(positions);
  const Points pts = gather(lines, particles, tree, ctx);
  std::vector<std::uint8_t> visible(pts.p.size(), 1);
  const Segments seg = segments(field, camera, pts, occlusion_tolerance, visible, ctx);
  for (std::size_t r = 0; r < seg.ray.size(); ++r) {
    std::vector<Vec3> x(seg.ray[r].count);
    for (std::uint32_t k = 0; k < seg.ray[r].count; ++k) x[k] = detail::ray_sample(seg.ray[r], k);
    std::vector<double> f(x.size());
    field.evaluate(x, f, {}, ctx);
    if (std::any_of(f.begin(), f.end(), [&](double v) { return v > field.iso(); }))
      visible[seg.point[r]] = 0;
  }
  return visible;
}

void classify_visibility(const Field& field, const ParticleSystem& particles, const Camera& camera,
                         std::span<Polyline> lines, const LineOptions& options, LineStats* stats,
                         const Context* ctx, const ParticleLookup* lookup) {
  const auto start = std::chrono::steady_clock::now();
  validate(camera);
  validate(options);
  std::size_t total_points = 0;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    for (std::size_t i = 0; i < lines[l].points.size(); ++i) {
      if (!is_finite(lines[l].points[i])) {
        throw InvalidArgument("classify_visibility: line " + std::to_string(l) + " point " +
                              std::to_string(i) + " is not finite");
      }
    }
    total_points += lines[l].points.size();
  }
  std::vector<std::uint8_t> visible(total_points, 1);
  std::uint64_t evals = 0;
  if (options.visibility != Visibility::kNone && total_points > 0) {
    if (particles.particles.empty()) {
      throw InvalidArgument(
          "classify_visibility: no particles (δ at a line point is its nearest particle's)");
    }
    std::optional<detail::DeltaLookup> own;
    if (lookup != nullptr) {
      lookup->impl().check(particles);
    } else {
      own.emplace(particles);
    }
    const detail::PointKdTree& tree = own ? own->tree() : lookup->impl().delta.tree();
    const Points pts = gather(lines, particles, tree, ctx);
    if (options.visibility == Visibility::kRays) {
      evals = classify_rays(field, camera, pts, options.occlusion_tolerance, visible, ctx);
    } else if (lookup != nullptr) {
      classify_surfels(particles, lookup->impl().radii(ctx), camera, pts, options, visible, ctx);
    } else {
      classify_surfels(particles, detail::surfel_radii(particles, tree, ctx), camera, pts, options,
                       visible, ctx);
    }
  }
  // Write the flags back; the hidden length gives each segment half to each end.
  double length = 0, hidden = 0;
  std::size_t k = 0;
  for (Polyline& line : lines) {
    const std::size_t n = line.points.size();
    line.visible.assign(visible.begin() + static_cast<std::ptrdiff_t>(k),
                        visible.begin() + static_cast<std::ptrdiff_t>(k + n));
    k += n;
    const std::size_t segments = n < 2 ? 0 : (line.closed ? n : n - 1);
    for (std::size_t s = 0; s < segments; ++s) {
      const std::size_t a = s, b = (s + 1) % n;
      const double l = (line.points[b] - line.points[a]).norm();
      length += l;
      hidden += 0.5 * l * ((line.visible[a] == 0 ? 1 : 0) + (line.visible[b] == 0 ? 1 : 0));
    }
  }
  if (stats != nullptr) {
    stats->hidden_fraction = length > 0 ? hidden / length : 0.0;
    stats->field_evals += evals;
    stats->seconds_visibility +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

}  // namespace ramiform
