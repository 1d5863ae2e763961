// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// A generated neuron (tests/support/neuron_fixture.h: single-point soma, six primary dendrites,
// an axon with two collaterals, tips of 0.2 um) of 3000 and 10000 samples meshed as
// `ramiform mesh cell.swc --fit-radii` does with its default options: the SWC text read with soma
// regions, edges split and per-piece weights fitted, the convolution surface polygonized to the
// default deviation tolerance (5 % of the local radius, p99). Timed per iteration: parse, fit,
// polygonize (the CLI's normals, swc_type labels, checks and file writing are not). Counters:
// samples, triangles, and the radius error (median, p90) measured once after the loop, as
// --stats reports it. docs/benchmarks.md ("Neurons") has the numbers.

#include <benchmark/benchmark.h>

#include <string>

#include "ramiform/core/context.h"
#include "ramiform/field/radius_fit.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/io/swc_io.h"
#include "ramiform/polygonize/refine.h"
#include "support/neuron_fixture.h"

namespace {

using namespace ramiform;

struct Meshed {
  TriMesh mesh;
  FieldPtr field;
};

Meshed mesh_like_the_cli(const std::string& swc, Context& ctx) {
  const Skeleton skeleton = parse_swc(swc, "neuron.swc");
  const SkeletonFieldOptions field_options = SkeletonFieldOptions{}.resolved();
  SplitSkeleton split = split_edges(skeleton);
  const RadiusFitResult fit = fit_edge_weights(split.skeleton, field_options, {}, &ctx);
  Meshed m;
  m.field = make_skeleton_field(split.skeleton, field_options, fit.weights);
  m.mesh = polygonize_to_tolerance(*m.field, split.skeleton, ToleranceOptions{}, &ctx);
  return m;
}

void BM_NeuronFitRadii(benchmark::State& state) {
  test::NeuronOptions o;
  o.target_samples = static_cast<int>(state.range(0));
  test::NeuronFacts facts;
  const std::string swc = test::neuron_swc(o, &facts);
  Context ctx(0);
  Meshed m;
  for (auto _ : state) {
    m = mesh_like_the_cli(swc, ctx);
    benchmark::DoNotOptimize(m.mesh.triangles.data());
  }
  const RadiusErrorReport e =
      measure_radius_error(*m.field, parse_swc(swc, "neuron.swc"), {}, &ctx);
  state.counters["samples"] = facts.samples;
  state.counters["triangles"] = static_cast<double>(m.mesh.triangle_count());
  state.counters["radius_error_median"] = e.median;
  state.counters["radius_error_p90"] = e.p90;
}

}  // namespace

BENCHMARK(BM_NeuronFitRadii)->Arg(3000)->Arg(10000)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK_MAIN();
