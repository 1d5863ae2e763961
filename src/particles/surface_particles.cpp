// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/particles/surface_particles.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include "particles/particle_common.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/memory.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/random.h"

namespace ramiform {
namespace {

using namespace particles_detail;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Area of a hexagonal lattice cell per particle at spacing a: (√3/2) a².
constexpr double kHexArea = 0.86602540378443864676;

bool overlaps(const Aabb& a, const Aabb& b) {
  return (a.min().array() < b.max().array()).all() && (b.min().array() < a.max().array()).all();
}

Aabb grown(const Aabb& b, double by) {
  return Aabb(b.min() - Vec3::Constant(by), b.max() + Vec3::Constant(by));
}

// Largest-remainder split of `total` in proportion to `weight` (ties to the lower index).
std::vector<std::size_t> allocate(std::span<const double> weight, std::size_t total) {
  std::vector<std::size_t> n(weight.size(), 0);
  double sum = 0;
  for (double w : weight) sum += w;
  if (!(sum > 0) || total == 0) return n;
  std::vector<std::pair<double, std::size_t>> rest;
  std::size_t given = 0;
  for (std::size_t c = 0; c < weight.size(); ++c) {
    const double exact = static_cast<double>(total) * weight[c] / sum;
    n[c] = static_cast<std::size_t>(std::floor(exact));
    given += n[c];
    rest.emplace_back(-(exact - std::floor(exact)), c);
  }
  std::sort(rest.begin(), rest.end());
  for (std::size_t k = 0; given < total && k < rest.size(); ++k, ++given) ++n[rest[k].second];
  return n;
}

void check_cells(std::span<const ParticleCell> cells) {
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const Aabb& b = cells[c].box;
    if (b.isEmpty() || !is_finite(b.min()) || !is_finite(b.max()) || !(b.sizes().minCoeff() > 0)) {
      throw InvalidArgument("spread_particles: cell " + std::to_string(c) +
                            " is empty, flat or not finite");
    }
    if (cells[c].depth < 0 || cells[c].depth > ParticleOptions::kMaxDepth) {
      throw InvalidArgument("spread_particles: cell " + std::to_string(c) + " has depth " +
                            std::to_string(cells[c].depth) + ", outside [0, " +
                            std::to_string(ParticleOptions::kMaxDepth) + "]");
    }
  }
}

// For every seed, the first cell (lowest index) containing it, or -1: a hash grid at the
// smallest cell size, coarsened while a cell would register in too many grid cells.
std::vector<std::vector<std::uint32_t>> seeds_per_cell(std::span<const ParticleCell> cells,
                                                       std::span<const Vec3> seeds) {
  std::vector<std::vector<std::uint32_t>> out(cells.size());
  if (seeds.empty() || cells.empty()) return out;
  Aabb all;
  double g = std::numeric_limits<double>::infinity();
  for (const ParticleCell& c : cells) {
    all.extend(c.box);
    g = std::min(g, c.box.sizes().minCoeff());
  }
  const Vec3 o = all.min();
  auto range = [&](const Aabb& b, double size, std::int64_t lo[3], std::int64_t hi[3]) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<std::int64_t>(std::floor((b.min()[a] - o[a]) / size));
      hi[a] = static_cast<std::int64_t>(std::floor((b.max()[a] - o[a]) / size));
    }
  };
  for (;;) {
    double regs = 0;
    for (const ParticleCell& c : cells) {
      std::int64_t lo[3], hi[3];
      range(c.box, g, lo, hi);
      regs += static_cast<double>(hi[0] - lo[0] + 1) * static_cast<double>(hi[1] - lo[1] + 1) *
              static_cast<double>(hi[2] - lo[2] + 1);
    }
    if (regs <= 64.0 * static_cast<double>(cells.size() + seeds.size())) break;
    g *= 2;
  }
  auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x) & 0x1FFFFF) << 42 |
           (static_cast<std::uint64_t>(y) & 0x1FFFFF) << 21 |
           (static_cast<std::uint64_t>(z) & 0x1FFFFF);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    std::int64_t lo[3], hi[3];
    range(cells[c].box, g, lo, hi);
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
          grid[key(x, y, z)].push_back(static_cast<std::uint32_t>(c));
  }
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const Vec3& p = seeds[s];
    if (!is_finite(p) || !all.contains(p)) continue;
    const auto it = grid.find(key(static_cast<std::int64_t>(std::floor((p.x() - o.x()) / g)),
                                  static_cast<std::int64_t>(std::floor((p.y() - o.y()) / g)),
                                  static_cast<std::int64_t>(std::floor((p.z() - o.z()) / g))));
    if (it == grid.end()) continue;
    for (std::uint32_t c : it->second) {  // ascending cell index
      if (cells[c].box.contains(p)) {
        out[c].push_back(static_cast<std::uint32_t>(s));
        break;
      }
    }
  }
  return out;
}

struct Seeded {
  std::vector<Vec3> positions;
  std::vector<double> delta;
  std::vector<std::uint32_t> cell;  // index into the cells passed to seed()
  std::size_t missing = 0;
};

// Initial particles: `want[c]` per cell, from the seeds in the cell, then the cell's surface
// probes, then random cell points projected onto the surface (three rounds at most).
Seeded seed(const Field& field, std::span<const ParticleCell> cells,
            std::span<const CellProbe> probes, std::span<const std::size_t> want,
            std::span<const double> cell_delta, std::span<const Vec3> seeds, std::uint64_t rng_seed,
            const Context* ctx) {
  const std::size_t nc = cells.size();
  const auto in_cell = seeds_per_cell(cells, seeds);
  const Rng base(rng_seed);
  std::vector<std::vector<Vec3>> got(nc);
  // Round 0: seeds (projected) then probes, in a random order per cell.
  std::vector<Vec3> cand;
  std::vector<double> step, tol;
  std::vector<std::uint32_t> cand_cell;
  std::vector<char> cand_projected;
  for (std::size_t c = 0; c < nc; ++c) {
    if (want[c] == 0) continue;
    Rng rng = base.split(c);
    std::vector<std::uint32_t> s = in_cell[c];
    const std::size_t budget = want[c] + want[c] / 2 + 2;
    for (std::size_t k = 0; k < s.size() && k < budget; ++k)
      std::swap(s[k], s[k + rng.below(s.size() - k)]);
    for (std::size_t k = 0; k < s.size() && k < budget; ++k) {
      cand.push_back(seeds[s[k]]);
      cand_cell.push_back(static_cast<std::uint32_t>(c));
      cand_projected.push_back(1);
    }
    std::vector<std::size_t> order(probes[c].points.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    for (std::size_t k = 0; k < order.size(); ++k)
      std::swap(order[k], order[k + rng.below(order.size() - k)]);
    for (std::size_t k : order) {
      cand.push_back(probes[c].points[k]);
      cand_cell.push_back(static_cast<std::uint32_t>(c));
      cand_projected.push_back(0);
    }
  }
  for (int round = 0; round < 4; ++round) {
    if (round > 0) {
      cand.clear();
      cand_cell.clear();
      cand_projected.clear();
      for (std::size_t c = 0; c < nc; ++c) {
        if (got[c].size() >= want[c]) continue;
        Rng rng = base.split(c).split(static_cast<std::uint64_t>(round));
        const std::size_t m = 2 * (want[c] - got[c].size()) + 2;
        for (std::size_t k = 0; k < m; ++k) {
          const Aabb& b = cells[c].box;
          cand.emplace_back(rng.uniform(b.min().x(), b.max().x()),
                            rng.uniform(b.min().y(), b.max().y()),
                            rng.uniform(b.min().z(), b.max().z()));
          cand_cell.push_back(static_cast<std::uint32_t>(c));
          cand_projected.push_back(1);
        }
      }
      if (cand.empty()) break;
    }
    step.resize(cand.size());
    tol.resize(cand.size());
    for (std::size_t k = 0; k < cand.size(); ++k) {
      const double h = cells[cand_cell[k]].box.sizes().maxCoeff();
      step[k] = 0.5 * h;
      tol[k] = cand_projected[k] ? 1e-6 * h : std::numeric_limits<double>::infinity();
    }
    std::vector<Vec3> grad;
    const std::vector<double> res = project(field, cand, step, tol, 8, grad, nullptr, ctx);
    for (std::size_t k = 0; k < cand.size(); ++k) {
      const std::uint32_t c = cand_cell[k];
      if (got[c].size() >= want[c]) continue;
      const double h = cells[c].box.sizes().maxCoeff();
      if (cand_projected[k] &&
          !(res[k] <= 1e-3 * h && grown(cells[c].box, 0.25 * h).contains(cand[k])))
        continue;
      got[c].push_back(cand[k]);
    }
  }
  Seeded out;
  for (std::size_t c = 0; c < nc; ++c) {
    out.missing += want[c] - got[c].size();
    for (const Vec3& p : got[c]) {
      out.positions.push_back(p);
      out.delta.push_back(cell_delta[c]);
      out.cell.push_back(static_cast<std::uint32_t>(c));
    }
  }
  return out;
}

// Simulates `s` (free) with `fixed` neighbours and appends the particles that reached the
// surface to `result` (their cell index offset by `cell_offset`). Fills the stats it can.
void run(const Field& field, const ParticleOptions& options, Seeded& s,
         std::span<const SurfaceParticle> fixed, std::uint32_t cell_offset, ParticleSystem& result,
         ParticleStats& st, const Context* ctx) {
  const auto t = Clock::now();
  const std::size_t n_free = s.positions.size();
  std::vector<Vec3> pos = s.positions;
  std::vector<double> delta = s.delta;
  for (const SurfaceParticle& p : fixed) {
    pos.push_back(p.position);
    delta.push_back(p.delta);
  }
  const SimulationResult sim = simulate(field, pos, delta, n_free, options.iterations, ctx);
  std::vector<char> ok(n_free, 0);
  std::vector<Vec3> kept_pos;
  std::vector<double> kept_delta;
  std::size_t first = result.particles.size();
  for (std::size_t i = 0; i < n_free; ++i) {
    ok[i] = static_cast<char>(sim.residual[i] <= kSurfaceTolerance * delta[i]);
    if (!ok[i]) {
      ++st.dropped;
      continue;
    }
    st.residual_max = std::max(st.residual_max, sim.residual[i] / delta[i]);
    result.particles.push_back(
        {pos[i], -sim.gradient[i].normalized(), delta[i], s.cell[i] + cell_offset});
    // The seeding state (eq. 11's "before"): where the particle started and its normal there;
    // a seed whose gradient cannot give a normal takes its final one (no turn measured).
    const Vec3 g0 = i < sim.initial_gradient.size() ? sim.initial_gradient[i] : Vec3::Zero();
    const double g0n = g0.norm();
    result.seed_positions.push_back(s.positions[i]);
    result.seed_normals.push_back(g0n > 0 && std::isfinite(g0n) ? Vec3(-g0 / g0n)
                                                                : result.particles.back().normal);
    kept_pos.push_back(pos[i]);
    kept_delta.push_back(delta[i]);
  }
  const std::size_t n_new = kept_pos.size();
  for (const SurfaceParticle& p : fixed) {
    kept_pos.push_back(p.position);
    kept_delta.push_back(p.delta);
  }
  const std::vector<double> nn = nearest_distances(kept_pos, kept_delta, n_new, ctx);
  st.spacing_cv = spacing_cv(nn, std::span<const double>(kept_delta).first(n_new));
  st.particles = result.particles.size() - first;
  st.iterations = options.iterations;
  st.seconds_simulate = seconds_since(t);
}

// δ per cell from eq. 2 (relative) and the scale that makes the wanted count tile the area.
struct Plan {
  std::vector<std::size_t> want;
  std::vector<double> delta;
};
Plan plan(std::span<const ParticleCell> cells, std::span<const CellProbe> probes,
          std::size_t total) {
  Plan p;
  const std::size_t nc = cells.size();
  int dmin = ParticleOptions::kMaxDepth + 1, dmax = -1;
  for (std::size_t c = 0; c < nc; ++c) {
    if (probes[c].area > 0) {
      dmin = std::min(dmin, cells[c].depth);
      dmax = std::max(dmax, cells[c].depth);
    }
  }
  std::vector<double> sigma(nc, 1.0), weight(nc, 0.0);
  double area = 0;
  for (std::size_t c = 0; c < nc; ++c) {
    const double t = dmax > dmin ? static_cast<double>(cells[c].depth - dmin) / (dmax - dmin) : 0.0;
    sigma[c] =
        pm::pow(2.0, -static_cast<double>(dmax > dmin ? dmax - dmin : 0) * (1.0 - depth_weight(t)));
    weight[c] = probes[c].area / (sigma[c] * sigma[c]);
    area += probes[c].area;
  }
  p.want = allocate(weight, total);
  double s2 = 0;
  for (std::size_t c = 0; c < nc; ++c) s2 += static_cast<double>(p.want[c]) * sigma[c] * sigma[c];
  const double scale = s2 > 0 ? std::sqrt(area / (kHexArea * s2)) : 0.0;
  p.delta.resize(nc);
  for (std::size_t c = 0; c < nc; ++c) p.delta[c] = kDeltaOverSpacing * scale * sigma[c];
  return p;
}

}  // namespace

bool has_seed_state(const ParticleSystem& system) {
  return !system.particles.empty() && system.seed_positions.size() == system.particles.size() &&
         system.seed_normals.size() == system.particles.size();
}

ParticleSystem spread_particles(const Field& field, const ParticleOptions& options,
                                std::span<const ParticleCell> cells, std::span<const Vec3> seeds,
                                ParticleStats* stats, const Context* ctx) {
  validate(options, "spread_particles");
  check_cells(cells);
  ParticleStats st;
  const std::uint64_t evals0 = field.evaluations();
  ParticleSystem out;
  out.iso = field.iso();
  auto t = Clock::now();
  std::vector<CellProbe> probes;
  if (cells.empty()) {
    out.root = root_cube(field);
    // With `count`, the cells are refined (a deeper minimum depth) until they hold at most
    // 2 k particles each on average, so the start is as close to the goal as with k per cell.
    for (int min_depth = std::min(kMinDepth, options.max_depth);;) {
      out.cells = octree_cells(field, options, min_depth, out.root, Aabb(), &probes, ctx,
                               2 * options.count);
      std::size_t surface = 0;
      for (const CellProbe& p : probes) surface += p.area > 0 ? 1 : 0;
      const double ratio = static_cast<double>(options.count) /
                           (2.0 * static_cast<double>(options.per_cell * surface));
      if (ratio <= 1 || surface == 0 || min_depth >= options.max_depth) break;
      // A level has about 4 times the surface cells of the one above.
      const int more = std::max(1, static_cast<int>(std::ceil(pm::log(ratio) / pm::log(4.0))));
      min_depth = std::min(options.max_depth, min_depth + more);
    }
  } else {
    out.cells.assign(cells.begin(), cells.end());
    std::vector<Aabb> boxes;
    for (const ParticleCell& c : cells) boxes.push_back(c.box);
    probes = probe_cells(field, boxes, ctx);
  }
  st.seconds_cells = seconds_since(t);
  t = Clock::now();
  std::size_t surface_cells = 0;
  for (const CellProbe& p : probes) surface_cells += p.area > 0;
  const std::size_t total = options.count > 0 ? options.count : options.per_cell * surface_cells;
  // Each particle keeps its state and its seed state; the simulation's neighbour lists and the
  // line drawings' work come on top.
  check_memory(
      ctx,
      static_cast<double>(total) * static_cast<double>(sizeof(SurfaceParticle) + 2 * sizeof(Vec3)),
      std::to_string(total) + " surface particles", "ask for fewer particles (count)");
  const Plan pl = plan(out.cells, probes, total);
  Seeded s = seed(field, out.cells, probes, pl.want, pl.delta, seeds, options.seed, ctx);
  st.dropped = s.missing;
  st.seconds_seed = seconds_since(t);
  run(field, options, s, {}, 0, out, st, ctx);
  st.cells = out.cells.size();
  st.field_evals = field.evaluations() - evals0;
  if (stats) *stats = st;
  return out;
}

ParticleSystem regenerate_particles(const Field& edited, const ParticleSystem& previous,
                                    const Aabb& edit_box, const ParticleOptions& options,
                                    ParticleStats* stats, const Context* ctx) {
  validate(options, "regenerate_particles");
  if (edit_box.isEmpty() || !is_finite(edit_box.min()) || !is_finite(edit_box.max())) {
    throw InvalidArgument("regenerate_particles: the edit box is empty or not finite");
  }
  if (edited.iso() != previous.iso) {
    throw InvalidArgument("regenerate_particles: the edited field's iso " +
                          format_number(edited.iso()) + " differs from the particle system's " +
                          format_number(previous.iso));
  }
  const std::size_t nc = previous.cells.size();
  for (const SurfaceParticle& p : previous.particles) {
    if (p.cell >= nc)
      throw InvalidArgument("regenerate_particles: a particle refers to cell " +
                            std::to_string(p.cell) + " of " + std::to_string(nc));
  }
  ParticleStats st;
  const std::uint64_t evals0 = edited.evaluations();
  auto t = Clock::now();
  // δ per old cell (its particles', 0 without particles) and the depth -> δ law.
  std::vector<double> cell_delta(nc, 0.0);
  std::map<int, double> law;
  for (const SurfaceParticle& p : previous.particles) {
    cell_delta[p.cell] = std::max(cell_delta[p.cell], p.delta);
    law.emplace(previous.cells[p.cell].depth, p.delta);
  }
  double delta_max = 0;
  for (double d : cell_delta) delta_max = std::max(delta_max, d);
  auto delta_at = [&](int depth) {
    if (law.empty()) return 0.0;
    const auto hi = law.lower_bound(depth);
    if (hi == law.end()) return std::prev(hi)->second;
    if (hi->first == depth || hi == law.begin()) return hi->second;
    const auto lo = std::prev(hi);
    const double f = static_cast<double>(depth - lo->first) / (hi->first - lo->first);
    return pm::exp((1 - f) * pm::log(lo->second) + f * pm::log(hi->second));
  };
  // The new cells are split at least as deep as the shallowest old cell (deeper when `count`
  // refined them), so that the old δ law applies to them.
  int min_depth = kMinDepth;
  if (nc > 0) {
    min_depth = ParticleOptions::kMaxDepth;
    for (const ParticleCell& c : previous.cells) min_depth = std::min(min_depth, c.depth);
  }
  std::vector<char> affected(nc, 0);
  for (std::size_t c = 0; c < nc; ++c)
    affected[c] =
        static_cast<char>(previous.cells[c].box.intersects(grown(edit_box, cell_delta[c])));
  // The new cells: the edited field's octree under the same root where it meets the edit box or
  // an affected cell; old cells they overlap become affected too, until nothing changes.
  std::vector<ParticleCell> fresh;
  std::vector<CellProbe> probes;
  if (!previous.root.isEmpty()) {
    Aabb region = edit_box;
    std::vector<ParticleCell> all;
    std::vector<CellProbe> all_probes;
    Aabb searched;
    for (;;) {
      for (std::size_t c = 0; c < nc; ++c) {
        if (affected[c]) region.extend(previous.cells[c].box);
      }
      if (searched.isEmpty() || !searched.contains(region)) {
        searched = region;
        all = octree_cells(edited, options, min_depth, previous.root, region, &all_probes, ctx);
      }
      std::vector<char> take(all.size(), 0);
      bool changed = false;
      for (std::size_t k = 0; k < all.size(); ++k) {
        take[k] = static_cast<char>(overlaps(all[k].box, edit_box));
        for (std::size_t c = 0; c < nc && !take[k]; ++c)
          take[k] =
              static_cast<char>(affected[c] != 0 && overlaps(all[k].box, previous.cells[c].box));
      }
      for (std::size_t k = 0; k < all.size(); ++k) {
        if (!take[k]) continue;
        for (std::size_t c = 0; c < nc; ++c) {
          if (!affected[c] && overlaps(all[k].box, previous.cells[c].box)) {
            affected[c] = 1;
            changed = true;
          }
        }
      }
      if (!changed) {
        for (std::size_t k = 0; k < all.size(); ++k) {
          if (take[k]) {
            fresh.push_back(all[k]);
            probes.push_back(std::move(all_probes[k]));
          }
        }
        break;
      }
    }
  } else {
    std::vector<Aabb> boxes;
    for (std::size_t c = 0; c < nc; ++c) {
      if (affected[c]) {
        fresh.push_back(previous.cells[c]);
        boxes.push_back(previous.cells[c].box);
      }
    }
    probes = probe_cells(edited, boxes, ctx);
  }
  st.seconds_cells = seconds_since(t);
  t = Clock::now();
  ParticleSystem out;
  out.iso = previous.iso;
  out.root = previous.root;
  std::vector<std::uint32_t> renumber(nc, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    if (affected[c]) continue;
    renumber[c] = static_cast<std::uint32_t>(out.cells.size());
    out.cells.push_back(previous.cells[c]);
  }
  const auto offset = static_cast<std::uint32_t>(out.cells.size());
  out.cells.insert(out.cells.end(), fresh.begin(), fresh.end());
  // The particles within their δ of the edit box are re-simulated; all others are kept. A kept
  // particle of a replaced cell moves to the new cell that holds it (or the nearest one).
  std::vector<std::size_t> kept_in(fresh.size(), 0);
  std::map<std::uint32_t, std::uint32_t> readded;
  const bool previous_seeds = has_seed_state(previous);
  for (std::size_t pi = 0; pi < previous.particles.size(); ++pi) {
    const SurfaceParticle& p = previous.particles[pi];
    if (grown(edit_box, p.delta).contains(p.position)) continue;
    out.particles.push_back(p);
    if (previous_seeds) {
      out.seed_positions.push_back(previous.seed_positions[pi]);
      out.seed_normals.push_back(previous.seed_normals[pi]);
    }
    if (!affected[p.cell]) {
      out.particles.back().cell = renumber[p.cell];
      continue;
    }
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < fresh.size() && best_d > 0; ++k) {
      const double d = squared_distance(fresh[k].box, p.position);
      if (d < best_d) {
        best_d = d;
        best = k;
      }
    }
    if (fresh.empty()) {
      // No new cell (the surface left the region): the particle keeps its replaced cell.
      if (!readded.contains(p.cell)) {
        readded.emplace(p.cell, static_cast<std::uint32_t>(out.cells.size()));
        out.cells.push_back(previous.cells[p.cell]);
      }
      out.particles.back().cell = readded.at(p.cell);
      continue;
    }
    if (best_d == 0) ++kept_in[best];
    out.particles.back().cell = offset + static_cast<std::uint32_t>(best);
  }
  st.kept = out.particles.size();
  // How many particles each new cell holds at the δ law's density, less the kept ones in it.
  std::vector<double> delta(fresh.size()), weight(fresh.size());
  double expected = 0;
  Aabb reach;
  for (std::size_t k = 0; k < fresh.size(); ++k) {
    delta[k] = delta_at(fresh[k].depth);
    const double a = delta[k] / kDeltaOverSpacing;
    weight[k] =
        a > 0 ? std::max(0.0, probes[k].area / (kHexArea * a * a) - static_cast<double>(kept_in[k]))
              : 0.0;
    expected += weight[k];
    reach.extend(fresh[k].box);
  }
  const std::vector<std::size_t> want =
      allocate(weight, static_cast<std::size_t>(std::llround(expected)));
  Seeded s = seed(edited, fresh, probes, want, delta, {}, options.seed, ctx);
  st.dropped = s.missing;
  st.seconds_seed = seconds_since(t);
  // Fixed neighbours: the kept particles near the new cells.
  std::vector<SurfaceParticle> fixed;
  if (!reach.isEmpty()) {
    const Aabb near = grown(reach, 2.0 * delta_max);
    for (std::size_t i = 0; i < st.kept; ++i) {
      if (near.contains(out.particles[i].position)) fixed.push_back(out.particles[i]);
    }
  }
  run(edited, options, s, fixed, offset, out, st, ctx);
  // Kept particles without a seeding state leave the whole system without one (a partial one
  // would make the movement test see only the re-simulated region).
  if (!previous_seeds && st.kept > 0) {
    out.seed_positions.clear();
    out.seed_normals.clear();
  }
  st.cells = fresh.size();
  st.field_evals = edited.evaluations() - evals0;
  if (stats) *stats = st;
  return out;
}

}  // namespace ramiform
