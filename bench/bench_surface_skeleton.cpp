// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Distance queries per second through a SurfaceSkeleton (field/surface_skeleton.h): a
// superquadric (e1 = e2 = 0.5, epsilon 10 degrees) subdivided to max depth 4 and 6, and a
// curved bicubic Bezier patch at max depth 6. Query points are uniform in 1.5x the skeleton's
// box (fixed seed). Counters: leaf patches, triangles, error_bound (model units).

#include <benchmark/benchmark.h>

#include <vector>

#include "ramiform/core/random.h"
#include "ramiform/field/surface_skeleton.h"

namespace {

using namespace ramiform;

std::vector<Vec3> query_points(const Aabb& box, std::size_t n) {
  Rng rng(7);
  std::vector<Vec3> points;
  points.reserve(n);
  const Vec3 c = box.center();
  const Vec3 h = 0.75 * box.diagonal();
  for (std::size_t i = 0; i < n; ++i) {
    points.emplace_back(c + Vec3(rng.uniform(-1, 1) * h.x(), rng.uniform(-1, 1) * h.y(),
                                 rng.uniform(-1, 1) * h.z()));
  }
  return points;
}

void run(benchmark::State& state, const SurfaceSkeleton& sk) {
  const auto points = query_points(sk.box(), 4096);
  double sum = 0;
  for (auto _ : state) {
    for (const Vec3& p : points) sum += sk.project(p).distance;
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(points.size()));
  // (queries * 1e-9 per iteration)^-1 as a rate: nanoseconds per query.
  state.counters["ns_per_query"] = benchmark::Counter(
      static_cast<double>(points.size()) * 1e-9,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["patches"] = static_cast<double>(sk.patch_count());
  state.counters["triangles"] = static_cast<double>(sk.triangle_count());
  state.counters["error_bound"] = sk.error_bound();
}

void superquadric(benchmark::State& state) {
  Superquadric q;
  q.radii = Vec3(1.5, 1, 0.8);
  q.e1 = q.e2 = 0.5;
  SubdivisionOptions o;
  o.epsilon_degrees = 10;
  o.max_depth = static_cast<int>(state.range(0));
  const SurfaceSkeleton sk(make_superquadric_surface(q), o);
  run(state, sk);
}
BENCHMARK(superquadric)->ArgName("max_depth")->Arg(4)->Arg(6)->Unit(benchmark::kMicrosecond);

void bicubic_patch(benchmark::State& state) {
  const double z[4][4] = {
      {0, 1, -0.5, 0.3}, {0.8, -1.2, 1.5, 0}, {-0.4, 1.6, -1, 0.9}, {0.5, 0, 1.2, -0.7}};
  BicubicPatch p;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) p.controls[4 * i + j] = Vec3(i, j, z[i][j]);
  }
  SubdivisionOptions o;
  o.max_depth = static_cast<int>(state.range(0));
  const SurfaceSkeleton sk(make_patch_surface(p), o);
  run(state, sk);
}
BENCHMARK(bicubic_patch)->ArgName("max_depth")->Arg(4)->Arg(6)->Unit(benchmark::kMicrosecond);

void build_superquadric(benchmark::State& state) {
  Superquadric q;
  q.radii = Vec3(1.5, 1, 0.8);
  q.e1 = q.e2 = 0.5;
  SubdivisionOptions o;
  o.max_depth = static_cast<int>(state.range(0));
  const auto surface = make_superquadric_surface(q);
  for (auto _ : state) {
    const SurfaceSkeleton sk(surface, o);
    benchmark::DoNotOptimize(sk.patch_count());
  }
}
BENCHMARK(build_superquadric)->ArgName("max_depth")->Arg(4)->Arg(6)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
