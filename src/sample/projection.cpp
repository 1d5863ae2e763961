// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "sample/projection.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "sample/candidate_blocks.h"
#include "sample/point_grid.h"

namespace ramiform::sample_detail {

namespace {

/// Cells of the pilot region (along the longest axis) that estimates the gradient norm.
constexpr int kProjectPilotRegion = 32;
constexpr std::size_t kProjectPilot = 2048;
/// Automatic wider-band thickness, in sampling cells: thin enough that the field is close to
/// affine across it for features a cell wide, thick enough that a good share of the
/// candidates in the cells meeting it lie in it. On the benchmark surface (bench_sample.cpp)
/// wider bands of 0.09-0.22 cells gave 20k-point sets that two-sample chi-square tests on
/// 100-1200 bins could not tell from rejection sampling's.
constexpr double kProjectCells = 0.2;
/// Newton steps per candidate (the second only when the first misses the band).
constexpr int kProjectSteps = 2;

/// One Newton step from p (value f, gradient g) to the value t: false when the gradient is zero
/// or not finite, the step is longer than max_step, or it leaves the box.
bool newton_step(const Vec3& p, double f, const Vec3& g, double t, double max_step, const Aabb& box,
                 Vec3& out) {
  const double g2 = g.squaredNorm();
  if (!(g2 > 0.0) || !std::isfinite(g2)) return false;
  const Vec3 step = ((t - f) / g2) * g;
  const double length = step.norm();
  if (!(length <= max_step)) return false;  // also false for NaN
  out = p + step;
  return box.contains(out);
}

/// One block of projection: each candidate in the wider band gets as its target the value its
/// level maps to in the band (c + (f - c) epsilon / W, the wider band squeezed linearly onto the
/// band) and is moved there by up to kProjectSteps Newton steps; those that land in the band are
/// accepted in candidate order. The buffers live across blocks.
class ProjectBlock {
 public:
  ProjectBlock(const Field& field, const Region& region, const Aabb& box, const ProjectSpec& spec,
               Context* ctx)
      : field_(field),
        region_(region),
        box_(box),
        spec_(spec),
        ctx_(ctx),
        centre_(0.5 * (spec.band.lo + spec.band.hi)),
        wide_(wide_band(spec.band, spec.width)),
        squeeze_((spec.band.hi - spec.band.lo) / spec.width),  // epsilon / W <= 1
        cand_(kBlock),
        target_(kBlock),
        found_(kBlock),
        result_(kBlock) {}

  bool operator()(Rng& rng, std::size_t n, PointGrid& near, PointSet& out) {
    for (std::size_t i = 0; i < n; ++i) {
      bool full = false;  // the wider band is not the target: every candidate is evaluated
      cand_[i] = region_.draw(rng, full);
    }
    std::fill(found_.begin(), found_.begin() + static_cast<std::ptrdiff_t>(n), 0);
    pts_.assign(cand_.begin(), cand_.begin() + static_cast<std::ptrdiff_t>(n));
    index_.resize(n);
    for (std::size_t i = 0; i < n; ++i) index_[i] = static_cast<std::uint32_t>(i);
    for (int step = 0; step <= kProjectSteps && !pts_.empty(); ++step) project_step(step);
    return accept(n, near, out);
  }

 private:
  /// Step 0 evaluates the candidates; step k the points after k Newton steps. Gradients are
  /// needed for every step but the last (they cost little next to the values).
  void project_step(int step) {
    evaluate_parallel(field_, pts_, values_, step < kProjectSteps ? &gradients_ : nullptr, ctx_);
    std::size_t kept = 0;
    for (std::size_t e = 0; e < pts_.size(); ++e) {
      const std::uint32_t i = index_[e];
      if (settle(step, i, pts_[e], values_[e])) continue;
      if (step == kProjectSteps) continue;
      Vec3 next;
      if (!newton_step(pts_[e], values_[e], gradients_[e], target_[i], spec_.max_step, box_,
                       next)) {
        continue;
      }
      pts_[kept] = next;
      index_[kept] = i;
      ++kept;
    }
    pts_.resize(kept);
    index_.resize(kept);
  }

  /// True when candidate i, now at p with value f, needs no further step: it is in the band
  /// (recorded), outside the wider band at step 0, or already at its target.
  bool settle(int step, std::uint32_t i, const Vec3& p, double f) {
    if (step == 0) {
      if (!wide_.contains(f)) return true;
      target_[i] = squeeze_ == 1.0 ? f : centre_ + (f - centre_) * squeeze_;
      if (target_[i] == f) {  // already at its target (W == epsilon: plain rejection)
        if (spec_.band.contains(f)) record(i, p);
        return true;
      }
      return false;
    }
    if (spec_.band.contains(f)) {
      record(i, p);
      return true;
    }
    return false;
  }

  void record(std::uint32_t i, const Vec3& p) {
    result_[i] = p;
    found_[i] = 1;
  }

  bool accept(std::size_t n, PointGrid& near, PointSet& out) const {
    for (std::size_t i = 0; i < n; ++i) {
      if (found_[i] == 0) continue;
      if (near.has_near(result_[i])) continue;
      near.add(result_[i]);
      out.positions.push_back(result_[i]);
      if (out.positions.size() == spec_.count) return true;
    }
    return false;
  }

  const Field& field_;
  const Region& region_;
  const Aabb& box_;
  const ProjectSpec& spec_;
  Context* ctx_;
  double centre_;
  Target wide_;
  double squeeze_;
  std::vector<Vec3> cand_;
  std::vector<double> target_;       ///< the value candidate i is projected to
  std::vector<std::uint8_t> found_;  ///< 1: result_[i] is a band point
  std::vector<Vec3> result_;
  std::vector<Vec3> pts_;  ///< the points still moving
  std::vector<double> values_;
  std::vector<Vec3> gradients_;
  std::vector<std::uint32_t> index_;  ///< candidate of each point still moving
};

}  // namespace

double automatic_project_width(const Field& field, const Aabb& box, const Target& band, double cell,
                               std::uint64_t seed, Context* ctx) {
  const double epsilon = band.hi - band.lo;
  const Region pilot_region(field, box, band, kProjectPilotRegion, ctx);
  if (pilot_region.is_empty()) return epsilon;
  Rng rng = Rng(seed).split(0x70726f6a656374ULL);  // "project"
  std::vector<Vec3> pts(kProjectPilot);
  for (auto& p : pts) {
    bool full = false;
    p = pilot_region.draw(rng, full);
  }
  std::vector<double> values;
  std::vector<Vec3> gradients;
  evaluate_parallel(field, pts, values, &gradients, ctx);
  const double centre = 0.5 * (band.lo + band.hi);
  std::vector<double> norms;
  double lowest = kInf, highest = -kInf;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!std::isfinite(values[i])) continue;
    lowest = std::min(lowest, values[i]);
    highest = std::max(highest, values[i]);
    const double g = gradients[i].norm();
    if (!(g > 0.0) || !std::isfinite(g)) continue;
    if (std::abs(values[i] - centre) < cell * g) norms.push_back(g);
  }
  if (norms.empty()) return epsilon;
  const auto mid = norms.begin() + static_cast<std::ptrdiff_t>(norms.size() / 2);
  std::nth_element(norms.begin(), mid, norms.end());
  const double w = std::min({kProjectCells * cell * *mid, centre - lowest, highest - centre});
  return std::isfinite(w) ? std::max(epsilon, w) : epsilon;
}

Target wide_band(const Target& band, double width) {
  const double centre = 0.5 * (band.lo + band.hi);
  return Target{centre - 0.5 * width, centre + 0.5 * width};
}

PointSet run_project(const Field& field, const Region& region, const Aabb& box,
                     const ProjectSpec& spec, std::uint64_t seed, Context* ctx, SampleStats& st) {
  ProjectBlock block(field, region, box, spec, ctx);
  return run_blocks(region, box, spec.min_distance, spec.count, spec.max_attempts, seed,
                    spec.stream, ctx, st, block);
}

}  // namespace ramiform::sample_detail
