// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Marching cubes: cells per second on a 200-segment branching tree (Cauchy convolution surface) at
// growing resolutions, with bound-based block skipping (the default).

#include <benchmark/benchmark.h>

#include "ramiform/field/skeleton_field.h"
#include "ramiform/polygonize/marching_cubes.h"
#include "ramiform/skeleton/generate.h"

namespace {

using namespace ramiform;

void BM_MarchingCubes(benchmark::State& state) {
  BranchingTreeOptions tree;
  tree.segments = 200;
  const Skeleton s = branching_tree(tree);
  const FieldPtr f = make_skeleton_field(s, {});
  MarchingCubesOptions o;
  o.resolution = static_cast<int>(state.range(0));
  MarchingCubesStats stats;
  std::size_t triangles = 0;
  for (auto _ : state) {
    const TriMesh m = marching_cubes(*f, o, nullptr, &stats);
    triangles = m.triangle_count();
  }
  state.SetItemsProcessed(state.iterations() * stats.cells_total);
  state.counters["cells"] = static_cast<double>(stats.cells_total);
  state.counters["cells_visited"] = static_cast<double>(stats.cells_visited);
  state.counters["triangles"] = static_cast<double>(triangles);
}

}  // namespace

BENCHMARK(BM_MarchingCubes)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
