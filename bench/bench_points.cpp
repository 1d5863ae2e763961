// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Scans and surface particles (docs/reconstruction.md, docs/particles.md): the MPU fit (Ohtake
// et al. 2003) of 30,000 oriented points of a bumpy sphere (the size of the Stanford bunny's
// scan, 35,947 points, which the target of "under 1 s on 2 cores" is about) and its
// evaluation per point near the surface; normal estimation and orientation of the same points
// without normals; and the paper's particle system (Proença et al. 2008 §4): 10,000 particles
// x 20 iterations (their bunny: target under 0.2 s on 2 cores) on the MPU surface and on an
// analytic torus. Fixed seeds, so every run measures the same work.

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "ramiform/core/random.h"
#include "ramiform/field/mpu.h"
#include "ramiform/field/point_normals.h"
#include "ramiform/field/primitives.h"
#include "ramiform/particles/surface_particles.h"

namespace {

using namespace ramiform;

// r(u) = 1 + 0.1 sin(5 x) sin(4 y) sin(3 z) on the unit direction u: a sphere with bumps.
double bump_radius(const Vec3& u) {
  return 1 + 0.1 * std::sin(5 * u.x()) * std::sin(4 * u.y()) * std::sin(3 * u.z());
}

// `n` random points on the bumpy sphere with outward normals (the gradient of |p| - r(p/|p|)).
PointSet bumpy_sphere(std::size_t n) {
  Rng rng(35947);
  PointSet s;
  while (s.size() < n) {
    Vec3 u(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const double len = u.norm();
    if (!(len > 1e-3 && len <= 1)) continue;
    u /= len;
    const Vec3 p = bump_radius(u) * u;
    const double h = 1e-6;
    Vec3 g;
    for (int k = 0; k < 3; ++k) {
      Vec3 a = p, b = p;
      a[k] += h;
      b[k] -= h;
      g[k] = ((a.norm() - bump_radius(a.normalized())) - (b.norm() - bump_radius(b.normalized()))) /
             (2 * h);
    }
    s.positions.push_back(p);
    s.normals.push_back(g.normalized());
  }
  return s;
}

const PointSet& cloud() {
  static const PointSet c = bumpy_sphere(30000);
  return c;
}

const FieldPtr& mpu() {
  static const FieldPtr f = make_mpu_field(cloud());
  return f;
}

void BM_MpuBuild(benchmark::State& state) {
  const Context ctx(static_cast<int>(state.range(0)));
  MpuStats st;
  for (auto _ : state) benchmark::DoNotOptimize(make_mpu_field(cloud(), {}, &st, &ctx));
  state.counters["points"] = static_cast<double>(st.points);
  state.counters["leaves"] = static_cast<double>(st.leaves);
}
BENCHMARK(BM_MpuBuild)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_MpuEvaluate(benchmark::State& state) {
  // Points within 2 % of the surface, where polygonizers and particles evaluate.
  Rng rng(3);
  std::vector<Vec3> p;
  for (std::size_t i = 0; i < 10000; ++i) {
    p.push_back(cloud().positions[i] * rng.uniform(0.98, 1.02));
  }
  std::vector<double> v(p.size());
  std::vector<Vec3> g(p.size());
  const Context ctx(1);
  const bool gradients = state.range(0) != 0;
  for (auto _ : state) {
    mpu()->evaluate(p, v, gradients ? std::span<Vec3>(g) : std::span<Vec3>(), &ctx);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * p.size()));
}
BENCHMARK(BM_MpuEvaluate)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_OrientNormals(benchmark::State& state) {
  PointSet bare = cloud();
  bare.normals.clear();
  const Context ctx(2);
  for (auto _ : state) benchmark::DoNotOptimize(orient_normals(bare, {}, nullptr, &ctx));
}
BENCHMARK(BM_OrientNormals)->Unit(benchmark::kMillisecond)->UseRealTime();

void particles_on(benchmark::State& state, const Field& field) {
  const Context ctx(static_cast<int>(state.range(0)));
  ParticleOptions o;
  o.count = 10000;
  o.iterations = 20;
  ParticleStats st;
  const std::vector<ParticleCell> cells = field_cells(field);
  double simulate = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(spread_particles(field, o, cells, {}, &st, &ctx));
    simulate += st.seconds_simulate;
  }
  state.counters["particles"] = static_cast<double>(st.particles);
  state.counters["simulate_s"] = simulate / static_cast<double>(state.iterations());
  state.counters["spacing_cv"] = st.spacing_cv;
}

void BM_ParticlesMpu(benchmark::State& state) { particles_on(state, *mpu()); }
BENCHMARK(BM_ParticlesMpu)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ParticlesTorus(benchmark::State& state) {
  static const FieldPtr torus =
      make_circle_field(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.35, DistancePrimitiveOptions{});
  particles_on(state, *torus);
}
BENCHMARK(BM_ParticlesTorus)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
