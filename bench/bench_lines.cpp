// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Line drawings (docs/drawing.md, docs/benchmarks.md): the per-view cost of the lines/ stage
// (Proença, Jorge & Costa Sousa 2008) with the particles placed once, outside the timed loop.
// Issue 19's target: the 10,000-particle bunny, all three line kinds, hidden lines removed,
// under 40 ms per view on 2 cores; and the David-size equivalent (60,000 particles, here on the
// kitten). Every iteration draws a fresh view: 12 views 30° of azimuth apart (elevation 15°, the
// turntable of `ramiform draw --views 12`), each once, so the mean time is the turntable's.
// Per-view times vary a lot on some models (a runaway silhouette trace costs seconds on a few
// views, docs/benchmarks.md), hence also the median and the slowest view as counters.
//
// The scanned models are read from $RAMIFORM_MODELS (default: shared/data/models beside the
// source tree, where the tests find the shared data), as `ramiform draw` reads them (30,000 samples
// of a mesh, normals oriented, MPU with default options, particles seeded from the points in the
// MPU's cells). When a model is absent its cases are not registered and a message says so; the
// procedural case (two crossing tori, a union with creases, 10,000 particles) always runs.
//
// Counters, per view: particles; sil/sug/feat = polylines of each kind; evals = point
// evaluations of the field; median_ms and max_ms over the views drawn.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "ramiform/field/mpu.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/point_normals.h"
#include "ramiform/field/primitives.h"
#include "ramiform/io/surface_points.h"
#include "ramiform/lines/lines.h"
#include "ramiform/particles/surface_particles.h"

namespace {

using namespace ramiform;

std::string models_dir() {
  const char* env = std::getenv("RAMIFORM_MODELS");
  return env != nullptr && *env != 0 ? env : RAMIFORM_MODELS_DIR;
}

// A surface with its particles and view-independent feature lines, built once.
struct Scene {
  FieldPtr field;
  ParticleSystem system;
  std::vector<Polyline> features;  // feature_lines() with default options
  Aabb box;                        // of the particles
};

Scene finish(FieldPtr field, std::size_t count, const std::vector<ParticleCell>& cells,
             std::span<const Vec3> seeds) {
  const Context ctx(2);
  Scene s;
  s.field = std::move(field);
  ParticleOptions po;
  po.count = count;
  s.system = spread_particles(*s.field, po, cells, seeds, nullptr, &ctx);
  for (const SurfaceParticle& p : s.system.particles) s.box.extend(p.position);
  s.features = feature_lines(*s.field, s.system, LineOptions{}, nullptr, &ctx);
  return s;
}

// As `ramiform draw FILE --count N` builds it (apps/ramiform/reconstruct_job.cpp).
Scene scanned(const std::string& file, std::size_t count) {
  const Context ctx(2);
  const SurfacePoints read = read_surface_points(models_dir() + "/" + file);
  const PointSet points = orient_normals(read.points, {}, nullptr, &ctx);
  FieldPtr field = make_mpu_field(points, {}, nullptr, &ctx);
  const std::vector<ParticleCell> cells = field_cells(*field);
  return finish(std::move(field), count, cells, points.positions);
}

Scene tori() {
  FieldPtr a = make_circle_field(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.35);
  FieldPtr b = make_circle_field(Vec3(1, 0, 0), Vec3::UnitY(), 0.6, 0.25);
  return finish(make_union({a, b}), 10000, {}, {});
}

// Scenes by name, built on first use (outside any timed loop).
const Scene& scene(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Scene>> scenes;
  auto& s = scenes[name];
  if (!s) {
    if (name == "bunny") {
      s = std::make_unique<Scene>(scanned("bunny.ply", 10000));
    } else if (name == "kitten60k") {
      s = std::make_unique<Scene>(scanned("kitten.xyz", 60000));
    } else {
      s = std::make_unique<Scene>(tori());
    }
  }
  return *s;
}

constexpr int kViews = 12;

Camera view(const Scene& s, std::int64_t i) {
  return frame_box(s.box, 30.0 + 30.0 * static_cast<double>(i % kViews), 15.0);
}

void set_counters(benchmark::State& state, const Scene& s, const LineStats& sum,
                  std::uint64_t evals, std::vector<double> ms) {
  const double n = static_cast<double>(state.iterations());
  std::sort(ms.begin(), ms.end());
  if (!ms.empty()) {
    state.counters["median_ms"] = ms[ms.size() / 2];
    state.counters["max_ms"] = ms.back();
  }
  state.counters["particles"] = static_cast<double>(s.system.particles.size());
  state.counters["sil"] = static_cast<double>(sum.lines[0]) / n;
  state.counters["sug"] = static_cast<double>(sum.lines[1]) / n;
  state.counters["feat"] = static_cast<double>(sum.lines[2]) / n;
  state.counters["evals"] = static_cast<double>(evals) / n;
}

// What one case times.
enum class Part { kDraw, kSilhouettes, kSuggestive, kFeatures, kVisibility };

struct Case {
  std::string scene;
  Part part = Part::kDraw;
  Visibility visibility = Visibility::kRays;
  bool precomputed_features = true;  // kDraw: pass the scene's feature lines
  bool suggestive = true;            // kDraw: extract suggestive contours
};

void run(benchmark::State& state, const Case& c) {
  const Scene& s = scene(c.scene);
  const Context ctx(static_cast<int>(state.range(0)));
  LineOptions o;
  o.visibility = c.visibility;
  o.suggestive = c.suggestive;
  const Field& f = *s.field;
  LineStats sum;
  std::int64_t i = 0;
  std::vector<double> ms;
  // classify_visibility alone: the lines of the views drawn beforehand, classified in turn.
  std::vector<std::vector<Polyline>> views;
  if (c.part == Part::kVisibility) {
    LineOptions none = o;
    none.visibility = Visibility::kNone;
    for (int v = 0; v < kViews; ++v) {
      views.push_back(draw_lines(f, s.system, view(s, v), none, &s.features, nullptr, &ctx).lines);
    }
  }
  f.reset_evaluations();
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const Camera cam = view(s, i);
    LineStats st;
    switch (c.part) {
      case Part::kDraw:
        benchmark::DoNotOptimize(draw_lines(
            f, s.system, cam, o, c.precomputed_features ? &s.features : nullptr, &st, &ctx));
        break;
      case Part::kSilhouettes:
        benchmark::DoNotOptimize(silhouettes(f, s.system, cam, o, &st, &ctx));
        break;
      case Part::kSuggestive:
        benchmark::DoNotOptimize(suggestive_contours(f, s.system, cam, o, &st, &ctx));
        break;
      case Part::kFeatures:
        benchmark::DoNotOptimize(feature_lines(f, s.system, o, &st, &ctx));
        break;
      case Part::kVisibility: {
        std::vector<Polyline>& lines = views[static_cast<std::size_t>(i % kViews)];
        classify_visibility(f, s.system, cam, lines, o, &st, &ctx);
        for (const Polyline& l : lines) ++st.lines[static_cast<int>(l.kind)];
        break;
      }
    }
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count());
    for (int k = 0; k < 3; ++k) sum.lines[k] += st.lines[k];
    ++i;
  }
  set_counters(state, s, sum, f.evaluations(), std::move(ms));
}

void add(const std::string& name, const Case& c) {
  benchmark::RegisterBenchmark(name.c_str(), [c](benchmark::State& st) { run(st, c); })
      ->Arg(1)
      ->Arg(2)
      ->ArgName("threads")
      ->Iterations(kViews)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
}

// The cases of one scene; `parts`: also each line kind and visibility alone.
void add_scene(const std::string& name, bool parts) {
  const std::string p = "BM_Lines/" + name + "/";
  add(p + "draw_rays", {name, Part::kDraw, Visibility::kRays, true});
  add(p + "draw_rays_with_features", {name, Part::kDraw, Visibility::kRays, false});
  if (!parts) return;
  // The paper's Table 1 "w/o suggestive contours" column: silhouettes and feature lines.
  add(p + "draw_rays_no_suggestive", {name, Part::kDraw, Visibility::kRays, true, false});
  add(p + "draw_surfels", {name, Part::kDraw, Visibility::kSurfels, true});
  add(p + "draw_no_visibility", {name, Part::kDraw, Visibility::kNone, true});
  add(p + "silhouettes", {name, Part::kSilhouettes, Visibility::kNone, true});
  add(p + "suggestive_contours", {name, Part::kSuggestive, Visibility::kNone, true});
  add(p + "feature_lines", {name, Part::kFeatures, Visibility::kNone, true});
  add(p + "visibility_rays", {name, Part::kVisibility, Visibility::kRays, true});
  add(p + "visibility_surfels", {name, Part::kVisibility, Visibility::kSurfels, true});
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  add_scene("tori", true);
  const std::string dir = models_dir();
  for (const auto& [name, file, parts] :
       {std::tuple<const char*, const char*, bool>{"bunny", "bunny.ply", true},
        {"kitten60k", "kitten.xyz", true}}) {
    if (std::filesystem::exists(dir + "/" + file)) {
      add_scene(name, parts);
    } else {
      std::fprintf(stderr, "bench_lines: %s/%s absent (set RAMIFORM_MODELS), %s cases skipped\n",
                   dir.c_str(), file, name);
    }
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
