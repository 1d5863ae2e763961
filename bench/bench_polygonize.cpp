// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Marching cubes: cells per second on a 200-segment branching tree (Cauchy convolution surface) at
// growing resolutions, with bound-based block skipping (the default); the tetrahedral
// polygonizer: triangles per second on 200- and 1000-segment trees at levels 2 and 3; its
// Delaunay tetrahedralization: points per second on uniform random points.
// bench/compare_polygonizers.sh compares the two methods on bigger and real trees.

#include <benchmark/benchmark.h>

#include <vector>

#include "polygonize/delaunay.h"
#include "polygonize/tetrahedral_points.h"
#include "ramiform/core/random.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/grow/lsystem.h"
#include "ramiform/polygonize/marching_cubes.h"
#include "ramiform/polygonize/particles.h"
#include "ramiform/polygonize/tetrahedral.h"
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

// The skeleton-bounded tetrahedral polygonizer on branching trees (segments, levels), cleanup on.
void BM_Tetrahedral(benchmark::State& state) {
  BranchingTreeOptions tree;
  tree.segments = static_cast<std::size_t>(state.range(0));
  const Skeleton s = branching_tree(tree);
  const FieldPtr f = make_skeleton_field(s, {});
  TetrahedralOptions o;
  o.levels = static_cast<int>(state.range(1));
  std::size_t triangles = 0;
  for (auto _ : state) {
    const TriMesh m = polygonize_tetrahedral(*f, s, o);
    triangles = m.triangle_count();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * triangles));
  state.counters["triangles"] = static_cast<double>(triangles);
}

// The equipotential particle mesher (Gruber & Wallner 2014) with its defaults, field built once:
// particles placed, converged and relaxed per second. Argument 0: the built-in L-system
// `binary` at range(1) iterations (4: about the size of the paper's Figure 6, 6: Figure 7);
// argument 1: a branching tree of range(1) segments.
void BM_Particles(benchmark::State& state) {
  Skeleton s;
  if (state.range(0) == 0) {
    LSystemOptions lo;
    lo.iterations = static_cast<int>(state.range(1));
    for (const auto& [name, text] : lsystem_examples()) {
      if (name == "binary") s = lsystem_skeleton(text, name, lo);
    }
  } else {
    BranchingTreeOptions tree;
    tree.segments = static_cast<std::size_t>(state.range(1));
    s = branching_tree(tree);
  }
  const Equipotential eq = make_equipotential(s, {});
  ParticleMeshStats stats;
  for (auto _ : state) {
    const TriMesh m = polygonize_particles(eq, s, {}, nullptr, &stats);
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * stats.particles));
  state.counters["particles"] = static_cast<double>(stats.particles);
  state.counters["evaluations"] = static_cast<double>(stats.evaluations);
  state.counters["min_angle"] = stats.min_angle;
}

// The Delaunay tetrahedralization (Bowyer-Watson, exact predicates) of N uniform random points
// in the unit cube.
void BM_Delaunay(benchmark::State& state) {
  Rng rng(1);
  std::vector<Vec3> points(static_cast<std::size_t>(state.range(0)));
  for (auto& p : points) p = Vec3(rng.uniform(), rng.uniform(), rng.uniform());
  std::size_t tets = 0;
  for (auto _ : state) tets = detail::delaunay_tetrahedralize(points).tets.size();
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["tets"] = static_cast<double>(tets);
}

// Step 1 of the tetrahedral polygonizer alone (the bounding points with the gap points between
// branches the skeleton does not join) on `ramiform generate --segments N` trees (seed 1). Its
// crown keeps its size as N grows, so the close pairs of edges, and the gap points, grow faster
// than N (docs/benchmarks.md, "Scale").
void BM_BoundingPoints(benchmark::State& state) {
  BranchingTreeOptions tree;
  tree.segments = static_cast<std::size_t>(state.range(0));
  const Skeleton s = branching_tree(tree);
  const TetrahedralOptions o;
  std::size_t points = 0, gap = 0;
  for (auto _ : state) {
    const detail::tets::BoundingPoints set = detail::tets::bounding_points(s, o);
    points = set.points.size();
    gap = set.gap_points;
  }
  state.counters["points"] = static_cast<double>(points);
  state.counters["gap_points"] = static_cast<double>(gap);
}

}  // namespace

BENCHMARK(BM_BoundingPoints)->Arg(10000)->Arg(30000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Delaunay)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Particles)->Args({0, 4})->Args({0, 6})->Args({1, 200})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Tetrahedral)->ArgsProduct({{200, 1000}, {2, 3}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MarchingCubes)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
