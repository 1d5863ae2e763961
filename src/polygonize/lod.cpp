// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/lod.h"

#include <algorithm>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/polygonize/improve.h"

namespace ramiform {
namespace {

using Tol = ToleranceOptions;

void check_levels(std::span<const LodLevel> levels) {
  if (levels.empty()) throw InvalidArgument("lod: no level given");
  const bool budgets = levels[0].max_triangles > 0;
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const LodLevel& l = levels[k];
    const std::string which = "lod: level " + std::to_string(k);
    if ((l.max_triangles > 0) == (l.tolerance > 0) || (l.max_triangles > 0) != budgets) {
      throw InvalidArgument(which +
                            " must give a tolerance or a triangle budget, the same kind as level 0");
    }
    if (!budgets && !(l.tolerance >= Tol::kMinTolerance && l.tolerance <= Tol::kMaxTolerance)) {
      throw InvalidArgument(which + ": tolerance " + format_number(l.tolerance) +
                            " is outside [" + format_number(Tol::kMinTolerance) + ", " +
                            format_number(Tol::kMaxTolerance) + "]");
    }
    if (k > 0 && (budgets ? l.max_triangles >= levels[k - 1].max_triangles
                          : l.tolerance <= levels[k - 1].tolerance)) {
      throw InvalidArgument(which + " is not coarser than level " + std::to_string(k - 1) +
                            " (give the levels finest first: tolerances increasing, budgets "
                            "decreasing)");
    }
  }
}

struct Attempt {
  TriMesh mesh;
  LodStats stats;
};

Attempt mesh_at(const Field& field, const Skeleton& skeleton, const Tol& base, double tolerance,
                std::size_t budget, int levels, Context* ctx) {
  Tol o = base;
  o.tolerance = std::clamp(tolerance, Tol::kMinTolerance, Tol::kMaxTolerance);
  o.max_triangles = budget;
  o.tets.levels = levels;
  Attempt a;
  a.mesh = polygonize_to_tolerance(field, skeleton, o, ctx, &a.stats.mesher);
  a.stats.tolerance = o.tolerance;
  a.stats.levels = levels;
  a.stats.triangles = a.mesh.triangle_count();
  return a;
}

// Coarsens `a.mesh` (the coarsest base mesh, over `budget`) by the polygonizer's own
// topology-safe collapses: improve_triangles() with every triangle a candidate (smallest angle
// below 59 degrees) at a growing edge tolerance, until the mesh is within the budget. Returns
// false when even the largest tolerance leaves it over.
bool coarsen_to_budget(Attempt& a, const Field& field, const Skeleton& skeleton,
                       std::size_t budget, Context* ctx) {
  for (double tol = 0.1; tol <= 0.8 + 1e-9; tol *= 2) {
    ImproveOptions o;
    o.tolerance = tol;
    o.min_angle_deg = 59.0;
    o.max_turn_deg = 60.0;
    o.max_rounds = 24;
    ImproveStats st;
    improve_triangles(a.mesh, field, skeleton, o, ctx, &st);
    a.stats.triangles = a.mesh.triangle_count();
    a.stats.coarsen_tolerance = tol;
    if (a.stats.triangles <= budget) return true;
  }
  return false;
}

// A budget level: the finest mesh within `budget` found by scaling the tolerance.
Attempt mesh_to_budget(const Field& field, const Skeleton& skeleton, const Tol& base,
                       double tolerance, std::size_t budget, Context* ctx) {
  constexpr int kAttempts = 5;
  constexpr double kLow = 0.75;  // a count of at least this share of the budget is good enough
  int levels = base.tets.levels;
  Attempt best;
  bool have = false;
  int made = 0;
  for (int i = 0; i < kAttempts; ++i) {
    Attempt a = mesh_at(field, skeleton, base, tolerance, budget, levels, ctx);
    ++made;
    const std::size_t n = a.stats.triangles;
    if (n > budget) {
      // The base mesh alone is over the budget (refinement never exceeds it).
      if (levels > TetrahedralOptions::kMinLevels) {
        --levels;
        continue;
      }
      if (have) break;
      if (coarsen_to_budget(a, field, skeleton, budget, ctx)) {
        best = std::move(a);
        have = true;
        break;
      }
      throw InvalidArgument("lod: a budget of " + std::to_string(budget) +
                            " triangles is below the coarsest mesh of this skeleton (" +
                            std::to_string(n) + " triangles at 0 levels, " +
                            std::to_string(a.stats.triangles) + " after coarsening)");
    }
    const bool stopped = a.stats.mesher.refine.budget_reached;
    // Better: within the budget and either not stopped by it where the best was, or finer.
    const bool better = !have || (best.stats.mesher.refine.budget_reached && !stopped) ||
                        (stopped == best.stats.mesher.refine.budget_reached &&
                         n > best.stats.triangles);
    if (better) {
      best = std::move(a);
      have = true;
    }
    if (stopped) {
      tolerance = best.stats.tolerance * 1.5;  // stopped mid-way: ask for less
    } else if (static_cast<double>(n) < kLow * static_cast<double>(budget) &&
               tolerance > Tol::kMinTolerance) {
      tolerance = best.stats.tolerance * static_cast<double>(n) /
                  (0.9 * static_cast<double>(budget));
    } else {
      break;
    }
    if (tolerance > Tol::kMaxTolerance && stopped) break;
  }
  best.stats.attempts = made;
  return best;
}

}  // namespace

std::vector<TriMesh> polygonize_lods(const Field& field, const Skeleton& skeleton,
                                     const ToleranceOptions& base,
                                     std::span<const LodLevel> levels, Context* ctx,
                                     std::vector<LodStats>* stats) {
  check_levels(levels);
  std::vector<TriMesh> meshes;
  std::vector<LodStats> all;
  double tolerance = base.tolerance;
  std::size_t cap = base.max_triangles;
  for (const LodLevel& l : levels) {
    Attempt a;
    if (l.max_triangles > 0) {
      a = mesh_to_budget(field, skeleton, base, tolerance, std::min(l.max_triangles, cap), ctx);
    } else {
      a = mesh_at(field, skeleton, base, l.tolerance, cap, base.tets.levels, ctx);
      a.stats.attempts = 1;
    }
    tolerance = a.stats.tolerance;
    cap = a.stats.triangles;
    all.push_back(a.stats);
    meshes.push_back(std::move(a.mesh));
  }
  if (stats != nullptr) *stats = std::move(all);
  return meshes;
}

}  // namespace ramiform
