// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Field evaluations per second on branching-tree line skeletons of 1k, 10k and 100k segments, with
// and without BVH pruning, for the Cauchy convolution surface and the Wyvill distance surface.
// Points come in spatially coherent batches of 4096 (32 clusters of 128 around random
// segments), as a polygonizer sends them.

#include <benchmark/benchmark.h>

#include "ramiform/core/random.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/skeleton/generate.h"

namespace {

using namespace ramiform;

std::vector<Vec3> clustered_points(const Skeleton& s, std::size_t clusters,
                                   std::size_t per_cluster) {
  Rng rng(7);
  std::vector<Vec3> points;
  points.reserve(clusters * per_cluster);
  for (std::size_t c = 0; c < clusters; ++c) {
    const auto& e = s.edges[rng.below(s.edges.size())];
    const Vec3 mid = 0.5 * (s.nodes[e[0]].position + s.nodes[e[1]].position);
    const double r = s.nodes[e[0]].radius;
    for (std::size_t i = 0; i < per_cluster; ++i) {
      points.push_back(mid +
                       2 * r * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
    }
  }
  return points;
}

void field_eval(benchmark::State& state, SurfaceKind surface) {
  const auto segments = static_cast<int>(state.range(0));
  const bool prune = state.range(1) != 0;
  BranchingTreeOptions tree;
  tree.segments = static_cast<std::size_t>(segments);
  const Skeleton s = branching_tree(tree);
  SkeletonFieldOptions o;
  o.surface = surface;
  if (surface == SurfaceKind::kDistance) o.kernel = Kernel{KernelKind::kWyvill, 0.0};
  o.prune = prune;
  const FieldPtr f = make_skeleton_field(s, o);
  // Without pruning every point meets every primitive: fewer points keep the run short.
  const std::size_t clusters = prune ? 32 : std::max<std::size_t>(1, 32 * 1000 / segments);
  const auto points = clustered_points(s, clusters, 128);
  std::vector<double> values(points.size());
  for (auto _ : state) {
    f->evaluate(points, values);
    benchmark::DoNotOptimize(values.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
  state.counters["segments"] = segments;
}

void BM_ConvolutionEval(benchmark::State& state) { field_eval(state, SurfaceKind::kConvolution); }
void BM_DistanceEval(benchmark::State& state) { field_eval(state, SurfaceKind::kDistance); }

// The equipotential field (Gruber & Wallner 2014, eq. 1) by its treecode: values and gradients,
// as the particle mesher asks for them, on the same trees and points; treecode theta x 100 as
// the second argument (25 is the default, 0 the exact sum).
void BM_EquipotentialEval(benchmark::State& state) {
  BranchingTreeOptions tree;
  tree.segments = static_cast<std::size_t>(state.range(0));
  const Skeleton s = branching_tree(tree);
  EquipotentialOptions o;
  o.theta = static_cast<double>(state.range(1)) / 100.0;
  const Equipotential eq = make_equipotential(s, o);
  const std::size_t clusters = o.theta > 0 ? 32 : 4;
  const auto points = clustered_points(s, clusters, 128);
  std::vector<double> values(points.size());
  std::vector<Vec3> gradients(points.size());
  for (auto _ : state) {
    eq.field->evaluate(points, values, gradients);
    benchmark::DoNotOptimize(values.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
  state.counters["charges"] = static_cast<double>(eq.charges.positions.size());
}

// One Cauchy segment, points in batches of 128: the cost of one segment evaluation.
void BM_CauchySegmentSingle(benchmark::State& state) {
  const FieldPtr f = make_segment_field(Vec3(0, 0, 0), 1, Vec3(5, 0, 0), 1, {});
  Rng rng(3);
  std::vector<Vec3> points(128);
  for (auto& p : points) p = Vec3(rng.uniform(-3, 8), rng.uniform(-3, 3), rng.uniform(-3, 3));
  std::vector<double> values(points.size());
  for (auto _ : state) {
    f->evaluate(points, values);
    benchmark::DoNotOptimize(values.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}

// The scalar closed form, for comparison with the vector path.
void BM_CauchySegmentScalar(benchmark::State& state) {
  Rng rng(3);
  std::vector<Vec3> points(128);
  for (auto& p : points) p = Vec3(rng.uniform(-3, 8), rng.uniform(-3, 3), rng.uniform(-3, 3));
  double sum = 0;
  for (auto _ : state) {
    for (const auto& p : points)
      sum += cauchy_segment_integral(p, Vec3(0, 0, 0), Vec3(5, 0, 0), 1.0);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
}

}  // namespace

BENCHMARK(BM_CauchySegmentScalar);
BENCHMARK(BM_CauchySegmentSingle);
BENCHMARK(BM_ConvolutionEval)
    ->ArgsProduct({{1000, 10000, 100000}, {1, 0}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DistanceEval)
    ->ArgsProduct({{1000, 10000, 100000}, {1, 0}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EquipotentialEval)
    ->ArgsProduct({{1000, 10000, 100000}, {25}})
    ->Args({1000, 0})
    ->Args({1000, 40})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
