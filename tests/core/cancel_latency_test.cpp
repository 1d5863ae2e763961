// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Every long operation honours Context::cancel() within a second: jobs that run for seconds
// (the tetrahedral polygonizer, marching cubes, space colonization, L-systems, the slow point
// distributions, the needle cleanup) are cancelled from another thread after 0.3 s and must
// throw Cancelled within 1 s of it. The bound is multiplied by RAMIFORM_TIME_SCALE (default 1,
// 10 in sanitized builds). A second run, cancelled 0.5 s later than the first one ended, must
// still be cancelled: the job was far from done, so the test cannot pass by a job that ends
// early (and it probes a later stage of the job too). These are the only tests that time
// anything: the latency is the requirement.

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/random.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/grow/lsystem.h"
#include "ramiform/grow/space_colonization.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/cleanup.h"
#include "ramiform/polygonize/marching_cubes.h"
#include "ramiform/polygonize/refine.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "ramiform/sample/point_sets.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

using Clock = std::chrono::steady_clock;
using Job = std::function<void(Context&)>;

constexpr double kCancelAfter = 0.3;  // seconds into the job
constexpr double kLaterBy = 0.5;      // the second run's cancel, after the first one ended
constexpr double kMaxLatency = 1.0;   // seconds from cancel() to Cancelled, times the scale
constexpr int kThreads = 2;           // the job sizes below assume about two cores' speed

double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// RAMIFORM_TIME_SCALE (a positive number), else 10 in sanitized builds and 1 otherwise.
double time_scale() {
  if (const char* text = std::getenv("RAMIFORM_TIME_SCALE")) {
    char* end = nullptr;
    const double scale = std::strtod(text, &end);
    if (end != text && scale > 0) return scale;
  }
#ifdef RAMIFORM_TEST_SANITIZED
  return 10.0;
#else
  return 1.0;
#endif
}

// One run of a job, cancelled after `cancel_after` seconds unless it ended before.
struct CancelRun {
  bool cancelled = false;  // the job threw Cancelled
  double elapsed = 0;      // seconds from the start to the end (throw or return)
  double latency = 0;      // seconds from cancel() to the throw
  double fraction = -1;    // the last progress fraction reported before cancel(); -1: none
};

CancelRun run_cancelled(const Job& job, double cancel_after) {
  Context ctx(kThreads);
  std::mutex progress_mutex;
  double last_fraction = -1;
  ctx.set_progress([&](const std::string&, double f) {
    const std::lock_guard lock(progress_mutex);
    last_fraction = f;
  });
  CancelRun run;
  std::mutex mutex;
  std::condition_variable ended;
  bool done = false;
  Clock::time_point cancelled_at;
  const Clock::time_point start = Clock::now();
  std::thread canceller([&] {
    std::unique_lock lock(mutex);
    const auto when = start + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(cancel_after));
    if (ended.wait_until(lock, when, [&] { return done; })) return;
    {
      const std::lock_guard progress_lock(progress_mutex);
      run.fraction = last_fraction;
    }
    cancelled_at = Clock::now();
    ctx.cancel();
  });
  try {
    job(ctx);
  } catch (const Cancelled&) {
    run.cancelled = true;
  }
  const Clock::time_point end = Clock::now();
  {
    const std::lock_guard lock(mutex);
    done = true;
  }
  ended.notify_all();
  canceller.join();
  run.elapsed = seconds(end - start);
  if (run.cancelled) run.latency = seconds(end - cancelled_at);
  return run;
}

// Cancels `job` after kCancelAfter and again kLaterBy after the first run ended; both must be
// cancelled within the bound. `reports_progress`: the job reports progress, which must show it
// was part-way when cancelled.
void expect_prompt_cancel(const std::string& what, const Job& job, bool reports_progress) {
  const double bound = kMaxLatency * time_scale();
  // Under sanitizers everything, setup included, is slower: the first cancel waits as much
  // longer, so that it still falls in the work that reports progress.
  const double cancel_after = kCancelAfter * time_scale();
  const CancelRun first = run_cancelled(job, cancel_after);
  ASSERT_TRUE(first.cancelled) << what << " ended after " << first.elapsed
                               << " s, before the cancel at " << cancel_after
                               << " s: the job is too small for this machine";
  EXPECT_LE(first.latency, bound) << what << ": cancelled at " << cancel_after << " s";
  const double later = first.elapsed + kLaterBy;
  const CancelRun second = run_cancelled(job, later);
  ASSERT_TRUE(second.cancelled) << what << " ended after " << second.elapsed
                                << " s uncancelled: the first cancel came near its end";
  EXPECT_LE(second.latency, bound) << what << ": cancelled at " << later << " s";
  if (reports_progress) {
    EXPECT_GE(first.fraction, 0.0) << what << " reported no progress before the cancel";
    EXPECT_LT(first.fraction, 1.0) << what;
    EXPECT_LT(second.fraction, 1.0) << what;
  }
  std::printf("%s: cancel latency %.3f s at %.2f s, %.3f s at %.2f s (bound %.1f s)\n",
              what.c_str(), first.latency, cancel_after, second.latency, later, bound);
  ::testing::Test::RecordProperty("latency_ms", static_cast<int>(1000 * first.latency));
  ::testing::Test::RecordProperty("later_latency_ms", static_cast<int>(1000 * second.latency));
}

// The benchmark tree with 4 mm twigs (docs/benchmarks.md), 300 segments, and its surface.
struct TwigTree {
  Skeleton skeleton = test::twig_tree(300);
  FieldPtr field = make_skeleton_field(skeleton);
};

TEST(CancelLatency, TetrahedralPolygonizer) {
  const TwigTree tree;
  TetrahedralOptions o;  // levels 3: about 5 s on two loaded cores
  expect_prompt_cancel(
      "tets",
      [&](Context& ctx) { (void)polygonize_tetrahedral(*tree.field, tree.skeleton, o, &ctx); },
      false);
}

TEST(CancelLatency, MeshingToATolerance) {
  const TwigTree tree;
  ToleranceOptions o;
  o.tolerance = 0.005;  // a fine tolerance: several seconds of refinement after the base mesh
  expect_prompt_cancel(
      "tolerance",
      [&](Context& ctx) { (void)polygonize_to_tolerance(*tree.field, tree.skeleton, o, &ctx); },
      false);
}

TEST(CancelLatency, MarchingCubes) {
  const TwigTree tree;
  MarchingCubesOptions o;
  o.resolution = 2000;
  expect_prompt_cancel(
      "mc", [&](Context& ctx) { (void)marching_cubes(*tree.field, o, &ctx); }, true);
}

TEST(CancelLatency, SpaceColonization) {
  std::vector<Vec3> points;  // 300,000 attraction points in a ball of radius 20
  Rng rng(7);
  while (points.size() < 300'000) {
    const Vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (p.squaredNorm() < 1) points.push_back(20 * p + Vec3(0, 0, 25));
  }
  ColonizationOptions o;
  o.step = 0.25;
  o.influence = 4;
  o.kill = 0.5;
  expect_prompt_cancel(
      "space colonization", [&](Context& ctx) { (void)grow_space_colonization(points, o, &ctx); },
      true);
}

TEST(CancelLatency, LSystem) {
  std::string text;
  for (const auto& [name, body] : lsystem_examples()) {
    if (name == "monopodial") text = body;
  }
  ASSERT_FALSE(text.empty());
  LSystemOptions o;
  o.iterations = 21;  // 2 million nodes
  expect_prompt_cancel(
      "lsystem", [&](Context& ctx) { (void)lsystem_skeleton(text, "monopodial", o, &ctx); }, false);
}

TEST(CancelLatency, PoissonDiskSampling) {
  const TwigTree tree;
  PoissonOptions o;
  o.count = 8000;
  expect_prompt_cancel(
      "poisson", [&](Context& ctx) { (void)sample_poisson(*tree.field, o, 1, &ctx); }, true);
}

TEST(CancelLatency, NearSurfaceSampling) {
  const TwigTree tree;
  NearSurfaceOptions o;
  o.count = 100'000;
  expect_prompt_cancel(
      "near_surface", [&](Context& ctx) { (void)sample_near_surface(*tree.field, o, 1, &ctx); },
      true);
}

TEST(CancelLatency, LaneSampling) {
  const TwigTree tree;
  LaneOptions o;
  o.count = 150'000;
  expect_prompt_cancel(
      "lane", [&](Context& ctx) { (void)sample_lane(*tree.field, o, 1, &ctx); }, true);
}

TEST(CancelLatency, StratifiedSampling) {
  const TwigTree tree;
  StratifiedOptions o;
  o.count = 2'000'000;
  expect_prompt_cancel(
      "stratified", [&](Context& ctx) { (void)sample_stratified(*tree.field, o, 1, &ctx); }, false);
}

// The needle cleanup changes the mesh in place: cancelled, it still leaves a valid mesh.
TEST(CancelLatency, NeedleCleanupLeavesAValidMesh) {
  const TwigTree tree;
  TetrahedralOptions o;
  o.cleanup = false;
  o.drop_strays = false;
  const TriMesh raw = polygonize_tetrahedral(*tree.field, tree.skeleton, o);
  const MeshReport before = check_mesh(raw);
  ASSERT_TRUE(before.watertight && before.manifold);
  std::vector<TriMesh> cancelled;
  expect_prompt_cancel(
      "needle cleanup",
      [&](Context& ctx) {
        cancelled.push_back(raw);
        clean_needles(cancelled.back(), {}, nullptr, &ctx);
      },
      false);
  ASSERT_EQ(cancelled.size(), 2u);
  for (const TriMesh& mesh : cancelled) {
    const MeshReport r = check_mesh(mesh);
    EXPECT_TRUE(r.watertight && r.manifold && r.oriented);
    EXPECT_EQ(r.components, before.components);
  }
}

}  // namespace
}  // namespace ramiform
