// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Point-to-curve distance queries per second: the closest point on a segment (the baseline),
// cubic and quintic Bezier curves by BezierProjector::project (exact: certified arcs, with the
// root isolation of Rigaudière et al. §3.4 where an arc is not certified; `arcs` = mean arcs per
// curve) and by the Newton baseline (4 starts). 16 random curves (controls in [-1, 1]^3, radius
// 0.1), 256 points each, uniform within 2 radii of a random curve point (fixed seed). The Newton
// benchmarks also report `miss_rate`: the fraction of their points where Newton's distance
// exceeds root isolation's by more than 1e-9 relative. BM_BezierBatched projects the same points
// through project(points, out), one call per curve (256 points), SIMD across points
// (field/bezier_curve_simd.cpp): the same results bit for bit.

#include <benchmark/benchmark.h>
#include <hwy/targets.h>

#include <algorithm>
#include <vector>

#include "ramiform/core/random.h"
#include "ramiform/field/bezier_curve.h"

namespace {

using namespace ramiform;

constexpr int kCurves = 16;
constexpr int kPointsPerCurve = 256;
constexpr double kRadius = 0.1;

Vec3 random_unit_ball(Rng& rng) {
  for (;;) {
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (v.squaredNorm() <= 1) return v;
  }
}

struct Workload {
  std::vector<BezierProjector> curves;
  std::vector<std::vector<Vec3>> points;  // per curve
};

Workload make_workload(int degree) {
  Rng rng(20260 + static_cast<std::uint64_t>(degree));
  Workload w;
  for (int c = 0; c < kCurves; ++c) {
    BezierCurve curve;
    for (int i = 0; i <= degree; ++i) {
      curve.controls.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    }
    std::vector<Vec3> pts;
    for (int k = 0; k < kPointsPerCurve; ++k) {
      pts.push_back(bezier_point(curve, rng.uniform()) + 2 * kRadius * random_unit_ball(rng));
    }
    w.curves.emplace_back(std::move(curve));
    w.points.push_back(std::move(pts));
  }
  return w;
}

const Workload& workload(int degree) {
  static const Workload w1 = make_workload(1);
  static const Workload w3 = make_workload(3);
  static const Workload w5 = make_workload(5);
  return degree == 1 ? w1 : degree == 3 ? w3 : w5;
}

// The baseline: closest point on the segment [a, b], written plainly.
double segment_distance(const Vec3& a, const Vec3& b, const Vec3& p) {
  const Vec3 ab = b - a;
  const double s = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + s * ab - p).norm();
}

void BM_SegmentDistance(benchmark::State& state) {
  const Workload& w = workload(1);
  for (auto _ : state) {
    double sum = 0;
    for (int c = 0; c < kCurves; ++c) {
      const Vec3& a = w.curves[c].curve().controls[0];
      const Vec3& b = w.curves[c].curve().controls[1];
      for (const Vec3& p : w.points[c]) sum += segment_distance(a, b, p);
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kCurves * kPointsPerCurve);
}

void BM_BezierRootIsolation(benchmark::State& state) {
  const Workload& w = workload(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    double sum = 0;
    for (int c = 0; c < kCurves; ++c) {
      for (const Vec3& p : w.points[c]) sum += w.curves[c].project(p).distance;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kCurves * kPointsPerCurve);
  state.counters["degree"] = static_cast<double>(state.range(0));
  double arcs = 0;
  for (const BezierProjector& c : w.curves) arcs += c.arc_count();
  state.counters["arcs"] = arcs / kCurves;
}

// range(1): 0 = the CPU's best Highway target, 1 = AVX2 forced (4 lanes instead of 8 with
// AVX-512), 2 = the emulated target (plain C++ on 2 lanes).
void BM_BezierBatched(benchmark::State& state) {
  const Workload& w = workload(static_cast<int>(state.range(0)));
  const std::int64_t forced[] = {0, HWY_AVX2, HWY_EMU128};
  hwy::SetSupportedTargetsForTest(forced[state.range(1)]);
  if (state.range(1) != 0 && !(hwy::SupportedTargets() & forced[state.range(1)])) {
    hwy::SetSupportedTargetsForTest(0);
    state.SkipWithError("target not supported");
    return;
  }
  std::vector<BezierProjection> out(kPointsPerCurve);
  for (auto _ : state) {
    double sum = 0;
    for (int c = 0; c < kCurves; ++c) {
      w.curves[c].project(w.points[c], out);
      for (const BezierProjection& r : out) sum += r.distance;
    }
    benchmark::DoNotOptimize(sum);
  }
  hwy::SetSupportedTargetsForTest(0);
  state.SetItemsProcessed(state.iterations() * kCurves * kPointsPerCurve);
  state.counters["degree"] = static_cast<double>(state.range(0));
}

// Fraction of the workload's points where Newton (4 starts) is farther than root isolation.
double newton_miss_rate(int degree) {
  const Workload& w = workload(degree);
  int misses = 0;
  for (int c = 0; c < kCurves; ++c) {
    for (const Vec3& p : w.points[c]) {
      const double iso = w.curves[c].project(p).distance;
      if (w.curves[c].project_newton(p, 4).distance > iso * (1 + 1e-9)) ++misses;
    }
  }
  return static_cast<double>(misses) / (kCurves * kPointsPerCurve);
}

void BM_BezierNewton(benchmark::State& state) {
  const int degree = static_cast<int>(state.range(0));
  const Workload& w = workload(degree);
  for (auto _ : state) {
    double sum = 0;
    for (int c = 0; c < kCurves; ++c) {
      for (const Vec3& p : w.points[c]) sum += w.curves[c].project_newton(p, 4).distance;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * kCurves * kPointsPerCurve);
  state.counters["degree"] = degree;
  state.counters["miss_rate"] = newton_miss_rate(degree);
}

}  // namespace

BENCHMARK(BM_SegmentDistance);
BENCHMARK(BM_BezierRootIsolation)->Arg(3)->Arg(5);
BENCHMARK(BM_BezierBatched)->ArgsProduct({{3, 5}, {0, 1, 2}});
BENCHMARK(BM_BezierNewton)->Arg(3)->Arg(5);

BENCHMARK_MAIN();
