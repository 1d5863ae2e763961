// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The modeler's shapes (Kochhar 2010, "Application of implicit methods to the interactive modeling
// of trees" (M.Sc. thesis), chapters 3-4): field evaluations per second at 65,536 random points of
// each shape's bounding box, and marching cubes at 96 cells along the longest side (what `save_mesh
// NAME FILE` does by default).

#include <benchmark/benchmark.h>

#include <functional>
#include <numbers>

#include "ramiform/core/random.h"
#include "ramiform/field/curves.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/primitives.h"
#include "ramiform/field/rbf.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/field/sweep.h"
#include "ramiform/field/warps.h"
#include "ramiform/mesh/mesh_field.h"
#include "ramiform/polygonize/marching_cubes.h"

namespace {

using namespace ramiform;

Curve2 square(double x0, double y0, double x1, double y1) {
  Curve2 c;
  c.closed = true;
  c.points = {Vec2(x0, y0), Vec2(x1, y0), Vec2(x1, y1), Vec2(x0, y1)};
  return c;
}

FieldPtr sphere(double r, const Vec3& c = Vec3::Zero()) {
  SkeletonFieldOptions o;
  o.surface = SurfaceKind::kDistance;
  o.kernel = Kernel{KernelKind::kWyvill, 0.0};
  return make_point_field(c, r, o);
}

// The shapes, by benchmark argument.
FieldPtr shape(int which) {
  switch (which) {
    case 0: return make_circle_field(Vec3::Zero(), Vec3::UnitZ(), 1.0, 0.25);
    case 1: return make_box_field(Vec3::Zero(), Vec3(1, 0.75, 0.5), 0.05);
    case 2: {
      TwistOptions t;
      t.rate = std::numbers::pi / 3;
      return make_twist(make_box_field(Vec3::Zero(), Vec3(0.3, 0.3, 1.5), 0.05), t);
    }
    case 3: {  // a train-like CSG of ten primitives
      std::vector<FieldPtr> parts = {make_box_field(Vec3(0, 0, 0.9), Vec3(1.5, 0.5, 0.5), 0.1),
                                     make_box_field(Vec3(-1, 0, 1.9), Vec3(0.5, 0.5, 0.6), 0.1),
                                     make_cylinder_field(Vec3(-0.5, 0, 1.75), Vec3(1.5, 0, 1.75), 0.45, 0.05),
                                     make_cone_field(Vec3(1.1, 0, 2.1), 0.25, Vec3(1.1, 0, 2.7), 0.15, 0.03)};
      for (int i = 0; i < 6; ++i) {
        parts.push_back(make_circle_field(Vec3(-1.0 + (i % 3), i < 3 ? 0.55 : -0.55, 0.35), Vec3::UnitY(), 0.3, 0.1));
      }
      return make_difference(make_union(parts), make_box_field(Vec3(-1, 0, 2.1), Vec3(0.25, 0.7, 0.2), 0.02));
    }
    case 4: {  // the skinned table of Figure 4.10
      Curve3 path;
      path.points = {Vec3::Zero(), Vec3(0, 0, 1.2)};
      std::vector<SkinSection> sections = {{square(0.6, 0.6, 0.8, 0.8), 0}, {square(-0.8, 0.6, -0.6, 0.8), 0},
                                           {square(-0.8, -0.8, -0.6, -0.6), 0}, {square(0.6, -0.8, 0.8, -0.6), 0},
                                           {square(-1, -1, 1, 1), 1}};
      SkinOptions o;
      o.surface.radius = 0.05;
      return make_skin_field(path, sections, o);
    }
    case 5: {  // a goblet: surface of revolution of a closed profile
      Curve2 profile;
      profile.closed = true;
      profile.points = {Vec2(0, 0),    Vec2(0.6, 0),  Vec2(0.6, 0.1), Vec2(0.12, 0.25), Vec2(0.1, 1.0),
                        Vec2(0.6, 1.5), Vec2(0.8, 2.2), Vec2(0.7, 2.2), Vec2(0.5, 1.6),   Vec2(0, 1.45)};
      CurveSurfaceOptions o;
      o.radius = 0.04;
      return make_revolution_field(profile, o);
    }
    case 6: {  // RBF through 100 points of a unit sphere with normals
      std::vector<Vec3> p, n;
      const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
      for (int i = 0; i < 100; ++i) {
        const double z = 1 - 2 * (i + 0.5) / 100;
        const double r = std::sqrt(1 - z * z);
        p.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
        n.push_back(p.back());
      }
      return make_rbf_field(rbf_constraints_from_normals(p, n, 0.1));
    }
    default: {  // a closed mesh (a sphere meshed by marching cubes) as a winding-number shape
      MarchingCubesOptions mc;
      mc.resolution = 24;
      return make_mesh_field(marching_cubes(*sphere(1.0), mc));
    }
  }
}

const char* kNames[] = {"torus", "box", "twisted box", "train CSG", "skinned table", "goblet", "RBF 100", "mesh"};

void BM_ModelEval(benchmark::State& state) {
  const FieldPtr f = shape(static_cast<int>(state.range(0)));
  const Aabb box = f->bounds();
  Rng rng(3);
  std::vector<Vec3> points(65536);
  for (Vec3& p : points) {
    p = box.min() + (box.max() - box.min()).cwiseProduct(Vec3(rng.uniform(), rng.uniform(), rng.uniform()));
  }
  std::vector<double> values(points.size());
  for (auto _ : state) {
    f->evaluate(points, values);
    benchmark::DoNotOptimize(values.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * points.size()));
  state.SetLabel(kNames[state.range(0)]);
}

void BM_ModelMesh(benchmark::State& state) {
  const FieldPtr f = shape(static_cast<int>(state.range(0)));
  MarchingCubesOptions o;
  o.resolution = 96;
  std::size_t triangles = 0;
  for (auto _ : state) {
    const TriMesh m = marching_cubes(*f, o);
    triangles = m.triangles.size();
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.SetLabel(kNames[state.range(0)]);
}

}  // namespace

BENCHMARK(BM_ModelEval)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ModelMesh)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
