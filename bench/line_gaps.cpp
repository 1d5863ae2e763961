// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Silhouette gaps and suggestive-contour totals on the shared scanned models (docs/drawing.md,
// "Limits"). Not a timing benchmark: a measurement printed as a table.
//
//   ramiform_line_gaps [--t-d A,B,...] [MODEL ...]   (default: bunny.ply cow.off kitten.xyz
//   oni.pwn)
//
// Each model is read as `ramiform draw` reads it (MPU of the oriented points, 10,000 particles
// seeded from the points in the MPU's cells), then drawn from azimuth 0, 90, 180 and 270
// (elevation 15). Gaps: every particle in the wider tracing band |v·n| < k_c·k_e is projected
// onto the contour generator (Newton onto f = iso and ∇f·(x − eye) = 0, the Hessian term a central
// difference along the view; at most 4 δ from the particle); a projected point farther than 2 δ
// from every traced silhouette point is uncovered. Uncovered points within 2 δ of each other
// form one gap; a gap's length is its largest extent. Also the silhouette time of the view
// (LineStats, 2 threads) and the suggestive contours' line count and length in δ.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include "ramiform/field/mpu.h"
#include "ramiform/field/point_normals.h"
#include "ramiform/io/surface_points.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"

#ifdef RAMIFORM_LINE_GAPS_OLD
namespace ramiform {
std::vector<Polyline> silhouettes_old(const Field&, const ParticleSystem&, const Camera&,
                                      const LineOptions&, LineStats*, const Context*);
}
#endif

namespace {

using namespace ramiform;

std::string models_dir() {
  const char* env = std::getenv("RAMIFORM_MODELS");
  return env != nullptr && *env != 0 ? env : RAMIFORM_MODELS_DIR;
}

// Newton onto f = iso, g = ∇f·(x − eye) = 0; false when it does not converge within 4 δ.
bool onto_contour(const Field& field, const Vec3& eye, Vec3& q, double delta) {
  const Vec3 start = q;
  std::vector<Vec3> pts(3), grads(3);
  std::vector<double> vals(3);
  for (int round = 0; round < 20; ++round) {
    const Vec3 d = q - eye;
    const double dist = d.norm();
    const Vec3 v = d / dist;
    const double h = 1e-3 * delta;
    pts[0] = q;
    pts[1] = q + h * v;
    pts[2] = q - h * v;
    field.evaluate(pts, vals, grads);
    const Vec3 grad = grads[0];
    const double gn = grad.norm();
    if (!(gn > 0)) return false;
    const Vec3 n = grad / gn;
    const double surface = (vals[0] - field.iso()) / gn;
    const double nv = n.dot(v);
    if (std::abs(surface) < 1e-5 * delta && std::abs(nv) < 1e-5) return true;
    const Vec3 hv = (grads[1] - grads[2]) / (2 * h);
    const Vec3 grad_g = dist * hv + grad;
    const Vec3 to_surface = -(vals[0] - field.iso()) / (gn * gn) * grad;
    Vec3 u = grad_g - grad_g.dot(n) * n;
    if (!(u.norm() > 0)) return false;
    u.normalize();
    const double s = -(grad.dot(d) + grad_g.dot(to_surface)) / grad_g.dot(u);
    q += to_surface + s * u;
    if (!std::isfinite(s) || (q - start).norm() > 4 * delta) return false;
  }
  return false;
}

struct Gaps {
  std::size_t probes = 0, uncovered = 0, gaps = 0;
  double total = 0, longest = 0;  // × mean δ
};

Gaps measure_gaps(const Field& field, const ParticleSystem& system, const Camera& camera,
                  const std::vector<Polyline>& sil, const LineOptions& o, double mean_delta) {
  std::vector<Vec3> line_points;
  for (const Polyline& l : sil)
    line_points.insert(line_points.end(), l.points.begin(), l.points.end());
  Gaps g;
  std::vector<Vec3> open;
  std::vector<double> open_delta;
  for (const SurfaceParticle& p : system.particles) {
    if (std::abs(view_vector(camera, p.position).dot(p.normal)) >= o.k_c * o.k_e) continue;
    Vec3 q = p.position;
    if (!onto_contour(field, camera.eye, q, p.delta)) continue;
    ++g.probes;
    const double r2 = 4 * p.delta * p.delta;
    const bool covered = std::any_of(line_points.begin(), line_points.end(),
                                     [&](const Vec3& s) { return (s - q).squaredNorm() <= r2; });
    if (!covered) {
      open.push_back(q);
      open_delta.push_back(p.delta);
    }
  }
  g.uncovered = open.size();
  // Gaps: components of the uncovered points linked within 2 δ.
  std::vector<std::size_t> parent(open.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t a = 0; a < open.size(); ++a)
    for (std::size_t b = a + 1; b < open.size(); ++b)
      if ((open[a] - open[b]).norm() <= 2 * std::max(open_delta[a], open_delta[b]))
        parent[find(a)] = find(b);
  for (std::size_t r = 0; r < open.size(); ++r) {
    if (find(r) != r) continue;
    ++g.gaps;
    double extent = 0;
    for (std::size_t a = 0; a < open.size(); ++a)
      for (std::size_t b = a + 1; b < open.size(); ++b)
        if (find(a) == r && find(b) == r) extent = std::max(extent, (open[a] - open[b]).norm());
    extent /= mean_delta;
    g.total += extent;
    g.longest = std::max(g.longest, extent);
  }
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> models = {"bunny.ply", "cow.off", "kitten.xyz", "oni.pwn"};
  // --t-d A,B,...: suggestive contours only, their count and length for each t_d.
  std::vector<double> sweep;
  int first = 1;
  if (argc > 2 && std::string(argv[1]) == "--t-d") {
    for (std::string rest = argv[2]; !rest.empty();) {
      const std::size_t comma = rest.find(',');
      sweep.push_back(std::stod(rest.substr(0, comma)));
      rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    }
    first = 3;
  }
  if (argc > first) models.assign(argv + first, argv + argc);
  const Context ctx(2);
  std::printf("%-11s %4s %6s %9s %5s %8s %8s %7s %7s %5s %9s\n", "model", "az", "probes",
              "uncovered", "gaps", "total_d", "longest", "sil_ms", "evals", "sug", "sug_len_d");
  for (const std::string& file : models) {
    const SurfacePoints read = read_surface_points(models_dir() + "/" + file);
    const PointSet points = orient_normals(read.points, {}, nullptr, &ctx);
    FieldPtr field = make_mpu_field(points, {}, nullptr, &ctx);
    const std::vector<ParticleCell> cells = field_cells(*field);
    ParticleOptions po;
    po.count = 10000;
    const ParticleSystem system =
        spread_particles(*field, po, cells, points.positions, nullptr, &ctx);
    Aabb box;
    double mean_delta = 0;
    for (const SurfaceParticle& p : system.particles) {
      box.extend(p.position);
      mean_delta += p.delta;
    }
    mean_delta /= static_cast<double>(system.particles.size());
    const LineOptions o;
    for (const double az : {0.0, 90.0, 180.0, 270.0}) {
      const Camera cam = frame_box(box, az, 15.0);
      if (!sweep.empty()) {
        for (const double t_d : sweep) {
          LineOptions so;
          so.t_d = t_d;
          LineStats sst;
          (void)suggestive_contours(*field, system, cam, so, &sst, &ctx);
          std::printf("%-11s %4.0f t_d %-6g particles %5zu lines %4zu length %6.0f d\n",
                      file.c_str(), az, t_d, sst.suggestive_particles, sst.lines[1],
                      sst.length[1] / mean_delta);
        }
        continue;
      }
      // The least time of 5 runs (the machine is shared).
      double best = 1e300;
      std::uint64_t evals = 0;
      std::vector<Polyline> sil;
      for (int rep = 0; rep < 5; ++rep) {
        LineStats st;
        sil = silhouettes(*field, system, cam, o, &st, &ctx);
        best = std::min(best, st.seconds_silhouettes);
        evals = st.field_evals;
      }
#ifdef RAMIFORM_LINE_GAPS_OLD
      double best_old = 1e300;
      std::uint64_t evals_old = 0;
      std::vector<Polyline> sil_old;
      for (int rep = 0; rep < 5; ++rep) {
        LineStats st;
        sil_old = silhouettes_old(*field, system, cam, o, &st, &ctx);
        best_old = std::min(best_old, st.seconds_silhouettes);
        evals_old = st.field_evals;
      }
      const Gaps g_old = measure_gaps(*field, system, cam, sil_old, o, mean_delta);
      std::printf("%-11s %4.0f %6zu %9zu %5zu %8.1f %8.1f %7.2f %7llu  (old seeding)\n",
                  file.c_str(), az, g_old.probes, g_old.uncovered, g_old.gaps, g_old.total,
                  g_old.longest, 1e3 * best_old, static_cast<unsigned long long>(evals_old));
#endif
      LineStats sst;
      (void)suggestive_contours(*field, system, cam, o, &sst, &ctx);
      const Gaps g = measure_gaps(*field, system, cam, sil, o, mean_delta);
      std::printf("%-11s %4.0f %6zu %9zu %5zu %8.1f %8.1f %7.2f %7llu %5zu %9.0f\n", file.c_str(),
                  az, g.probes, g.uncovered, g.gaps, g.total, g.longest, 1e3 * best,
                  static_cast<unsigned long long>(evals), sst.lines[1], sst.length[1] / mean_delta);
    }
  }
  return 0;
}
