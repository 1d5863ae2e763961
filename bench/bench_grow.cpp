// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Space colonization and L-system benchmarks on fixed procedural inputs.
//
// Colonization: N attraction points uniform in a ball crown of radius R = 10 centred at
// (0, 0, 14) (root at the origin, so a short trunk grows first). With s = R (4 pi / 3 / N)^(1/3)
// the mean point spacing: D = s, d_i = 6 s, d_k = 2 s. Counters: nodes, iterations, points
// reached (fraction), status (0 completed, 1 stalled, 2 max iterations).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/random.h"
#include "ramiform/grow/lsystem.h"
#include "ramiform/grow/space_colonization.h"

namespace {

using ramiform::Vec3;

constexpr double kRadius = 10;

std::vector<Vec3> crown(std::size_t n) {
  ramiform::Rng rng(42);
  std::vector<Vec3> out;
  out.reserve(n);
  while (out.size() < n) {
    const Vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (p.squaredNorm() <= 1) out.push_back(Vec3(0, 0, kRadius + 4) + kRadius * p);
  }
  return out;
}

ramiform::ColonizationOptions crown_options(std::size_t n) {
  const double s = kRadius * std::cbrt(4 * std::numbers::pi / 3 / static_cast<double>(n));
  ramiform::ColonizationOptions o;
  o.step = s;
  o.influence = 6 * s;
  o.kill = 2 * s;
  o.max_iterations = 100000;
  return o;
}

void BM_Colonization(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const auto points = crown(n);
  const auto o = crown_options(n);
  ramiform::Context ctx(threads);
  ramiform::ColonizationResult r;
  for (auto _ : state) {
    r = ramiform::grow_space_colonization(points, o, &ctx);
    benchmark::DoNotOptimize(r.skeleton.nodes.data());
  }
  state.counters["points"] = static_cast<double>(n);
  state.counters["nodes"] = static_cast<double>(r.skeleton.node_count());
  state.counters["iterations"] = static_cast<double>(r.iterations);
  state.counters["reached"] = static_cast<double>(r.points_reached) / static_cast<double>(n);
  state.counters["status"] = r.status == ramiform::ColonizationStatus::kCompleted ? 0
                             : r.status == ramiform::ColonizationStatus::kStalled ? 1
                                                                                   : 2;
}
// Args: points, threads (0 = all cores).
BENCHMARK(BM_Colonization)
    ->Args({10'000, 0})
    ->Args({100'000, 0})
    ->Args({100'000, 1})
    ->Args({1'000'000, 0})
    ->Args({1'000'000, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_LSystemMonopodial(benchmark::State& state) {
  const auto ex = ramiform::lsystem_examples();
  std::string text;
  for (const auto& [name, t] : ex)
    if (name == "monopodial") text = t;
  ramiform::LSystemOptions o;
  o.iterations = static_cast<int>(state.range(0));
  std::size_t edges = 0;
  for (auto _ : state) {
    const auto s = ramiform::lsystem_skeleton(text, "monopodial", o);
    edges = s.edge_count();
    benchmark::DoNotOptimize(s.nodes.data());
  }
  state.counters["edges"] = static_cast<double>(edges);
}
BENCHMARK(BM_LSystemMonopodial)->Arg(10)->Arg(16)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
