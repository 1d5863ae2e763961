// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "particles/particle_common.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"

namespace ramiform::particles_detail {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kGrain = 512;

// Area of the polygon where the plane through q with unit normal n cuts the box.
double plane_box_area(const Aabb& box, const Vec3& q, const Vec3& n) {
  std::array<Vec3, 8> corner;
  for (int c = 0; c < 8; ++c) {
    corner[c] =
        Vec3((c & 1) ? box.max().x() : box.min().x(), (c & 2) ? box.max().y() : box.min().y(),
             (c & 4) ? box.max().z() : box.min().z());
  }
  std::vector<Vec3> poly;
  for (int a = 0; a < 8; ++a) {
    for (int bit = 1; bit < 8; bit <<= 1) {
      if (a & bit) continue;
      const int b = a | bit;
      const double da = n.dot(corner[a] - q);
      const double db = n.dot(corner[b] - q);
      if ((da < 0) != (db < 0) && da != db) {
        poly.push_back(corner[a] + (da / (da - db)) * (corner[b] - corner[a]));
      }
    }
  }
  if (poly.size() < 3) return 0.0;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : poly) centre += p;
  centre /= static_cast<double>(poly.size());
  const Vec3 u = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized();
  const Vec3 v = n.cross(u);
  std::vector<std::pair<double, Vec3>> sorted;
  sorted.reserve(poly.size());
  for (const Vec3& p : poly)
    sorted.emplace_back(pm::atan2((p - centre).dot(v), (p - centre).dot(u)), p);
  std::sort(sorted.begin(), sorted.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  double area = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const Vec3& p0 = sorted[i].second;
    const Vec3& p1 = sorted[(i + 1) % sorted.size()].second;
    area += 0.5 * (p0 - centre).cross(p1 - centre).norm();
  }
  return area;
}

// Sorted cell hash, one level per distinct δ (cell size = that δ), rebuilt per step.
class NeighbourGrid {
 public:
  NeighbourGrid(std::span<const Vec3> positions, std::span<const double> delta, const Context* ctx)
      : positions_(positions) {
    const std::size_t n = positions.size();
    sizes_.assign(delta.begin(), delta.end());
    std::sort(sizes_.begin(), sizes_.end());
    sizes_.erase(std::unique(sizes_.begin(), sizes_.end()), sizes_.end());
    level_.resize(n);
    Aabb box;
    for (std::size_t i = 0; i < n; ++i) {
      level_[i] = static_cast<int>(std::lower_bound(sizes_.begin(), sizes_.end(), delta[i]) -
                                   sizes_.begin());
      box.extend(positions[i]);
    }
    origin_ = n == 0 ? Vec3::Zero() : Vec3(box.min() - Vec3::Constant(2.0 * sizes_.back()));
    entries_.resize(n);
    parallel::for_each(
        n, 4096,
        [&](std::size_t i) {
          entries_[i] = {key(level_[i], cell_of(positions[i], level_[i])),
                         static_cast<std::uint32_t>(i)};
        },
        ctx);
    std::sort(entries_.begin(), entries_.end());
    std::size_t unique = 0;
    for (std::size_t i = 0; i < n; ++i)
      unique += (i == 0 || entries_[i].first != entries_[i - 1].first);
    std::size_t cap = 16;
    while (cap < 2 * unique) cap <<= 1;
    mask_ = cap - 1;
    slots_.assign(cap, Slot{});
    for (std::size_t i = 0; i < n;) {
      std::size_t e = i + 1;
      while (e < n && entries_[e].first == entries_[i].first) ++e;
      cell_start_.push_back(static_cast<std::uint32_t>(i));
      std::size_t h = hash(entries_[i].first);
      while (slots_[h].end != 0) h = (h + 1) & mask_;
      slots_[h] = {entries_[i].first, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(e)};
      i = e;
    }
    cell_start_.push_back(static_cast<std::uint32_t>(n));
  }

  [[nodiscard]] int levels() const { return static_cast<int>(sizes_.size()); }
  [[nodiscard]] int level(std::size_t i) const { return level_[i]; }

  /// Number of occupied cells (over all levels), in key order.
  [[nodiscard]] std::size_t cells() const {
    return cell_start_.empty() ? 0 : cell_start_.size() - 1;
  }

  // For every particle i of occupied cell u, calls fn(i, j, level) for the same particles as
  // visit(i) does, in the same order; the 27 neighbour cells of u's own level are looked up
  // once for all its particles.
  template <class Fn>
  void visit_cell(std::size_t u, Fn&& fn) const {
    const std::uint32_t b = cell_start_[u], e = cell_start_[u + 1];
    const std::size_t first = entries_[b].second;
    const int own = level_[first];
    const std::array<std::int64_t, 3> c = cell_of(positions_[first], own);
    std::array<std::pair<std::uint32_t, std::uint32_t>, 27> ranges;
    int nr = 0;
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const Slot* slot = find(key(own, {c[0] + dx, c[1] + dy, c[2] + dz}));
          if (slot != nullptr) ranges[nr++] = {slot->begin, slot->end};
        }
      }
    }
    for (std::uint32_t k = b; k < e; ++k) {
      const std::size_t i = entries_[k].second;
      for (int r = 0; r < nr; ++r) {
        for (std::uint32_t q = ranges[r].first; q < ranges[r].second; ++q) {
          const std::uint32_t j = entries_[q].second;
          if (j != i) fn(i, static_cast<std::size_t>(j), own);
        }
      }
      for (int lv = own + 1; lv < levels(); ++lv)
        visit_level(i, lv, [&](std::size_t j, int l) { fn(i, j, l); });
    }
  }

  // Calls fn(j, level) for every particle j != i of a level >= i's in the 27 cells of that
  // level around particle i (all those within that level's δ of i), in a fixed order.
  template <class Fn>
  void visit(std::size_t i, Fn&& fn) const {
    for (int lv = level_[i]; lv < levels(); ++lv) visit_level(i, lv, fn);
  }

 private:
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t begin = 0, end = 0;
  };
  static constexpr std::int64_t kAxis = std::int64_t{1} << 18;

  [[nodiscard]] const Slot* find(std::uint64_t k) const {
    std::size_t h = hash(k);
    while (slots_[h].end != 0 && slots_[h].key != k) h = (h + 1) & mask_;
    return slots_[h].end == 0 ? nullptr : &slots_[h];
  }

  template <class Fn>
  void visit_level(std::size_t i, int lv, Fn&& fn) const {
    const std::array<std::int64_t, 3> c = cell_of(positions_[i], lv);
    for (std::int64_t dx = -1; dx <= 1; ++dx) {
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const Slot* slot = find(key(lv, {c[0] + dx, c[1] + dy, c[2] + dz}));
          if (slot == nullptr) continue;
          for (std::uint32_t e = slot->begin; e < slot->end; ++e) {
            const std::uint32_t j = entries_[e].second;
            if (j != i) fn(static_cast<std::size_t>(j), lv);
          }
        }
      }
    }
  }

  [[nodiscard]] std::array<std::int64_t, 3> cell_of(const Vec3& p, int lv) const {
    std::array<std::int64_t, 3> c{};
    for (int a = 0; a < 3; ++a) {
      const double t = std::floor((p[a] - origin_[a]) / sizes_[lv]);
      c[a] = static_cast<std::int64_t>(std::clamp(t, 0.0, static_cast<double>(kAxis - 2)));
    }
    return c;
  }
  static std::uint64_t key(int lv, const std::array<std::int64_t, 3>& c) {
    return (static_cast<std::uint64_t>(lv) << 54) |
           (static_cast<std::uint64_t>(c[0] & (kAxis - 1)) << 36) |
           (static_cast<std::uint64_t>(c[1] & (kAxis - 1)) << 18) |
           static_cast<std::uint64_t>(c[2] & (kAxis - 1));
  }
  [[nodiscard]] std::size_t hash(std::uint64_t k) const {
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ULL) >> 20) & mask_;
  }

  std::span<const Vec3> positions_;
  std::vector<double> sizes_;
  std::vector<int> level_;
  Vec3 origin_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries_;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> cell_start_;  // first entry of each occupied cell, then n
  std::size_t mask_ = 0;
};

// Repulsion weight of the neighbour at distance r for radius δ: (1 − r/δ)², 0 beyond δ.
double repulsion(double r, double delta) {
  const double x = 1.0 - r / delta;
  return x > 0 ? x * x : 0.0;
}

struct Reverse {
  std::uint32_t target, source;
  Vec3 push;
};

}  // namespace

void validate(const ParticleOptions& o, const char* who) {
  const std::string w(who);
  if (o.per_cell < 1) throw InvalidArgument(w + ": per_cell must be >= 1");
  if (o.iterations < 0 || o.iterations > ParticleOptions::kMaxIterations) {
    throw InvalidArgument(w + ": iterations must be in [0, " +
                          std::to_string(ParticleOptions::kMaxIterations) + "], got " +
                          std::to_string(o.iterations));
  }
  if (o.max_depth < 0 || o.max_depth > ParticleOptions::kMaxDepth) {
    throw InvalidArgument(w + ": max_depth must be in [0, " +
                          std::to_string(ParticleOptions::kMaxDepth) + "], got " +
                          std::to_string(o.max_depth));
  }
  if (!(o.flatness_deg > 0 && o.flatness_deg < 180)) {
    throw InvalidArgument(w + ": flatness_deg must be in (0, 180), got " +
                          format_number(o.flatness_deg));
  }
}

double depth_weight(double t) {
  t = std::clamp(t, 0.0, 1.0);
  // The uniform quadratic B-spline basis on [0, 3] peaks at 0.75 at x = 1.5; its right half,
  // scaled to 1, falls smoothly from 1 to 0.
  const double x = 1.5 + 1.5 * t;
  const double b = x < 2.0 ? 0.5 * (-2.0 * x * x + 6.0 * x - 3.0) : 0.5 * (3.0 - x) * (3.0 - x);
  return b / 0.75;
}

std::vector<double> project(const Field& field, std::vector<Vec3>& points,
                            std::span<const double> max_step, std::span<const double> tol,
                            int rounds, std::vector<Vec3>& gradients,
                            std::vector<double>* first_values, const Context* ctx) {
  const std::size_t n = points.size();
  const double iso = field.iso();
  std::vector<double> residual(n, kInf);
  gradients.assign(n, Vec3::Zero());
  if (first_values) first_values->assign(n, 0.0);
  std::vector<std::uint32_t> active(n);
  for (std::size_t i = 0; i < n; ++i) active[i] = static_cast<std::uint32_t>(i);
  std::vector<Vec3> pts;
  std::vector<double> val;
  std::vector<Vec3> grad;
  for (int r = 0; r <= rounds && !active.empty(); ++r) {
    pts.resize(active.size());
    for (std::size_t a = 0; a < active.size(); ++a) pts[a] = points[active[a]];
    val.resize(active.size());
    grad.resize(active.size());
    field.evaluate(pts, val, grad, ctx);
    std::vector<std::uint32_t> next;
    for (std::size_t a = 0; a < active.size(); ++a) {
      const std::uint32_t i = active[a];
      if (r == 0 && first_values) (*first_values)[i] = val[a];
      gradients[i] = grad[a];
      const double g = grad[a].norm();
      const double res =
          (g > 0 && std::isfinite(val[a]) && std::isfinite(g)) ? std::abs(val[a] - iso) / g : kInf;
      residual[i] = res;
      if (res <= tol[i] || !std::isfinite(res) || r == rounds) continue;
      Vec3 step = -((val[a] - iso) / (g * g)) * grad[a];
      const double len = step.norm();
      if (len > max_step[i]) step *= max_step[i] / len;
      points[i] += step;
      next.push_back(i);
    }
    active.swap(next);
  }
  return residual;
}

std::vector<CellProbe> probe_cells(const Field& field, std::span<const Aabb> boxes,
                                   const Context* ctx) {
  constexpr int kSide = 3;
  constexpr int kPer = kSide * kSide * kSide;
  const std::size_t n = boxes.size();
  std::vector<Vec3> pts(n * kPer);
  std::vector<double> step(n * kPer), tol(n * kPer);
  for (std::size_t c = 0; c < n; ++c) {
    const Vec3 size = boxes[c].sizes();
    const double h = size.maxCoeff();
    for (int k = 0; k < kPer; ++k) {
      const int ix = k % kSide, iy = (k / kSide) % kSide, iz = k / (kSide * kSide);
      const Vec3 t((ix + 0.5) / kSide, (iy + 0.5) / kSide, (iz + 0.5) / kSide);
      pts[c * kPer + k] = boxes[c].min() + t.cwiseProduct(size);
      step[c * kPer + k] = 0.5 * h;
      tol[c * kPer + k] = 1e-6 * h;
    }
  }
  std::vector<Vec3> grad;
  std::vector<double> first;
  const std::vector<double> res = project(field, pts, step, tol, 8, grad, &first, ctx);
  const double iso = field.iso();
  std::vector<CellProbe> out(n);
  parallel::for_each(
      n, 64,
      [&](std::size_t c) {
        CellProbe& pr = out[c];
        const double h = boxes[c].sizes().maxCoeff();
        const Aabb cell(boxes[c].min() - Vec3::Constant(1e-9 * h),
                        boxes[c].max() + Vec3::Constant(1e-9 * h));
        // The normals are judged over the surface near the cell (its box grown by half its
        // size), so that a cell the surface only grazes is judged by the patch it belongs to.
        const Aabb near(boxes[c].min() - Vec3::Constant(0.5 * h),
                        boxes[c].max() + Vec3::Constant(0.5 * h));
        bool in = false, outside = false;
        std::vector<Vec3> normals;
        for (int k = 0; k < kPer; ++k) {
          const std::size_t i = c * kPer + k;
          (first[i] > iso ? in : outside) = true;
          if (!(res[i] <= 1e-3 * h) || !near.contains(pts[i])) continue;
          const Vec3 nrm = -grad[i].normalized();
          normals.push_back(nrm);
          if (cell.contains(pts[i])) {
            pr.points.push_back(pts[i]);
            pr.normals.push_back(nrm);
          }
        }
        pr.both_signs = in && outside;
        pr.near_count = normals.size();
        double min_dot = 1.0;
        for (std::size_t a = 0; a < normals.size(); ++a) {
          for (std::size_t b = a + 1; b < normals.size(); ++b)
            min_dot = std::min(min_dot, normals[a].dot(normals[b]));
        }
        pr.spread_deg = pm::acos(std::clamp(min_dot, -1.0, 1.0)) * 180.0 / std::numbers::pi;
        Vec3 mean = Vec3::Zero();
        Vec3 centre = Vec3::Zero();
        for (std::size_t a = 0; a < pr.points.size(); ++a) {
          mean += pr.normals[a];
          centre += pr.points[a];
        }
        if (!pr.points.empty() && mean.norm() > 0) {
          centre /= static_cast<double>(pr.points.size());
          pr.area = plane_box_area(boxes[c], centre, mean.normalized());
        }
      },
      ctx);
  return out;
}

SimulationResult simulate(const Field& field, std::vector<Vec3>& positions,
                          std::span<const double> delta, std::size_t n_free, int iterations,
                          const Context* ctx) {
  // Step size of the repulsion (times δ_i): a half of the stable limit of the linearized
  // lattice, which damps the slowest modes in a few steps.
  constexpr double kEta = 0.25;
  const double iso = field.iso();
  std::vector<double> val(n_free);
  std::vector<Vec3> grad(n_free), push(n_free);
  std::vector<Vec3> next(n_free);
  constexpr std::size_t kChunk = 128;  // occupied grid cells per task
  std::vector<std::vector<Reverse>> reverse;
  SimulationResult out;
  for (int it = 0; it < iterations; ++it) {
    check_cancel(ctx);
    field.evaluate(std::span<const Vec3>(positions.data(), n_free), val, grad, ctx);
    // The first step's gradients are the ones at the seeding positions: kept for eq. 11.
    if (it == 0) out.initial_gradient = grad;
    const NeighbourGrid grid(positions, delta, ctx);
    std::fill(push.begin(), push.end(), Vec3::Zero());
    const std::size_t chunks = (grid.cells() + kChunk - 1) / kChunk;
    reverse.resize(chunks);
    parallel::for_chunks(
        chunks, 1,
        [&](std::size_t cb, std::size_t ce) {
          for (std::size_t c = cb; c < ce; ++c) {
            reverse[c].clear();
            const std::size_t e = std::min(grid.cells(), (c + 1) * kChunk);
            for (std::size_t u = c * kChunk; u < e; ++u) {
              grid.visit_cell(u, [&](std::size_t i, std::size_t j, int lv) {
                const Vec3 d = positions[i] - positions[j];
                const double r2 = d.squaredNorm();
                const bool coarser = lv > grid.level(i) && j < n_free;
                if (r2 >= delta[i] * delta[i] && !(coarser && r2 < delta[j] * delta[j])) return;
                const double r = std::sqrt(r2);
                // Coincident particles part along a fixed axis, in opposite directions.
                const Vec3 dir =
                    r > 1e-12 * delta[i] ? Vec3(d / r) : Vec3((i < j ? 1.0 : -1.0) * Vec3::UnitX());
                if (i < n_free) push[i] += repulsion(r, delta[i]) * dir;
                if (coarser) {
                  const double w = repulsion(r, delta[j]);
                  if (w > 0)
                    reverse[c].push_back(
                        {static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i), -w * dir});
                }
              });
            }
          }
        },
        ctx);
    std::vector<Reverse> all;
    for (auto& r : reverse) all.insert(all.end(), r.begin(), r.end());
    std::sort(all.begin(), all.end(), [](const Reverse& a, const Reverse& b) {
      return a.target != b.target ? a.target < b.target : a.source < b.source;
    });
    for (const Reverse& r : all) push[r.target] += r.push;
    parallel::for_each(
        n_free, kGrain,
        [&](std::size_t i) {
          const double g = grad[i].norm();
          if (!(g > 0) || !std::isfinite(val[i]) || !std::isfinite(g)) {
            next[i] = positions[i];
            return;
          }
          const Vec3 nrm = grad[i] / g;
          Vec3 t = kEta * delta[i] * push[i];
          t -= t.dot(nrm) * nrm;
          const double tl = t.norm();
          if (tl > 0.5 * delta[i]) t *= 0.5 * delta[i] / tl;
          Vec3 newton = -((val[i] - iso) / g) * nrm;
          const double nl = newton.norm();
          if (nl > delta[i]) newton *= delta[i] / nl;
          next[i] = positions[i] + t + newton;
        },
        ctx);
    std::copy(next.begin(), next.end(), positions.begin());
    if (ctx != nullptr)
      ctx->report("particles: simulate", static_cast<double>(it + 1) / iterations);
  }
  std::vector<Vec3> free_pts(positions.begin(),
                             positions.begin() + static_cast<std::ptrdiff_t>(n_free));
  std::vector<double> tol(n_free);
  for (std::size_t i = 0; i < n_free; ++i) tol[i] = 0.1 * kSurfaceTolerance * delta[i];
  out.residual = project(field, free_pts, delta.first(n_free), tol, 30, out.gradient, nullptr, ctx);
  // Without steps the seeds only get the final projection (they start on the surface already,
  // to 1e-6 of their cell): its gradients stand for the initial ones, at no extra evaluation.
  if (iterations == 0) out.initial_gradient = out.gradient;
  std::copy(free_pts.begin(), free_pts.end(), positions.begin());
  return out;
}

std::vector<double> nearest_distances(std::span<const Vec3> positions,
                                      std::span<const double> delta, std::size_t n_free,
                                      const Context* ctx) {
  const std::size_t n = positions.size();
  const NeighbourGrid grid(positions, delta, ctx);
  std::vector<double> nn(n, kInf);
  // Pairs from a finer particle to a coarser one are seen only from the finer side: record them
  // per chunk and fold them in afterwards (a minimum, so the order does not matter).
  constexpr std::size_t kChunk = 256;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  std::vector<std::vector<std::pair<std::uint32_t, double>>> reverse(chunks);
  parallel::for_chunks(
      chunks, 1,
      [&](std::size_t cb, std::size_t ce) {
        for (std::size_t c = cb; c < ce; ++c) {
          const std::size_t e = std::min(n, (c + 1) * kChunk);
          for (std::size_t i = c * kChunk; i < e; ++i) {
            double best = kInf;
            const int own = grid.level(i);
            grid.visit(i, [&](std::size_t j, int lv) {
              const double r = (positions[i] - positions[j]).norm();
              best = std::min(best, r);
              if (lv > own) reverse[c].emplace_back(static_cast<std::uint32_t>(j), r);
            });
            nn[i] = best;
          }
        }
      },
      ctx);
  for (const auto& chunk : reverse) {
    for (const auto& [j, r] : chunk) nn[j] = std::min(nn[j], r);
  }
  nn.resize(n_free);
  return nn;
}

double spacing_cv(std::span<const double> nn, std::span<const double> delta) {
  double sum = 0, sum2 = 0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < nn.size(); ++i) {
    if (!std::isfinite(nn[i])) continue;
    const double x = nn[i] / delta[i];
    sum += x;
    sum2 += x * x;
    ++count;
  }
  if (count < 2) return 0.0;
  const double mean = sum / static_cast<double>(count);
  const double var = std::max(0.0, sum2 / static_cast<double>(count) - mean * mean);
  return mean > 0 ? std::sqrt(var) / mean : 0.0;
}

}  // namespace ramiform::particles_detail
