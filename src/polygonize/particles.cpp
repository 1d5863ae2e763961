// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/particles.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "polygonize/particle_layout.h"
#include "polygonize/particle_merge.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/mesh/checks.h"

namespace ramiform {

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kGrain = 1024;
constexpr std::size_t kMaxListed = 100;
// A relaxation round moves a particle this fraction of the way to its neighbours' tangential
// centroid. Half the way keeps the Jacobi iteration from overshooting (the umbrella operator's
// eigenvalues lie in [0, 2], so a full step can flip a zig-zag instead of smoothing it).
constexpr double kRelaxWeight = 0.5;
// A particle whose clamp has been halved below this fraction of its R is bracketing a jump of
// the field rather than a root (a treecode switching approximations, a kernel's cut-off):
// further rounds only halve the step again, so it stops there, unconverged. 2^-40 ~ 1e-12.
constexpr double kStalled = 0x1p-40;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void check_options(const ParticleMeshOptions& o) {
  const auto fail = [](const std::string& what) {
    throw InvalidArgument("polygonize_particles: " + what);
  };
  if (o.n_circ < 3 || o.n_circ > 4096) {
    fail("n_circ must be in 3..4096, got " + std::to_string(o.n_circ));
  }
  if (o.n_sphere < 4 || o.n_sphere > 65536) {
    fail("n_sphere must be in 4..65536, got " + std::to_string(o.n_sphere));
  }
  if (!std::isfinite(o.sphere_factor) || !(o.sphere_factor > 1)) {
    fail("sphere_factor must be finite and > 1, got " + std::to_string(o.sphere_factor));
  }
  if (!(o.gamma_degrees > 0 && o.gamma_degrees <= 180)) {
    fail("gamma_degrees must be in (0, 180], got " + std::to_string(o.gamma_degrees));
  }
  if (!std::isfinite(o.placement_radius) || o.placement_radius < 0) {
    fail("placement_radius must be finite and >= 0, got " + std::to_string(o.placement_radius));
  }
  if (!std::isfinite(o.placement_factor) || !(o.placement_factor > 0)) {
    fail("placement_factor must be finite and > 0, got " + std::to_string(o.placement_factor));
  }
  if (!(o.delta > 0 && o.delta < 1)) {
    fail("delta must be in (0, 1), got " + std::to_string(o.delta));
  }
  if (!std::isfinite(o.max_step) || !(o.max_step > 0)) {
    fail("max_step must be finite and > 0, got " + std::to_string(o.max_step));
  }
  if (o.max_iterations < 1) {
    fail("max_iterations must be >= 1, got " + std::to_string(o.max_iterations));
  }
  if (o.relax < 0 || o.relax > 100) {
    fail("relax must be in 0..100, got " + std::to_string(o.relax));
  }
}

// The particles and what the projection keeps per particle.
struct Particles {
  std::vector<Vec3> position;
  std::vector<Vec3> gradient;    // grad f at the last evaluated position
  std::vector<double> residual;  // f - iso there
  std::vector<double> scale;     // local R
  std::vector<std::uint8_t> converged;
};

// Moves particles `which` onto f == iso by clamped Newton steps along the gradient (see the
// header). Every round evaluates the particles still moving in one batch; a particle leaves the
// set when it converges or its gradient is unusable. Returns the number of rounds.
int project(const Field& field, const ParticleMeshOptions& o, std::vector<std::uint32_t> active,
            Particles& p, std::uint64_t& evaluations, const Context* ctx) {
  const double iso = field.iso();
  const double tolerance = o.delta * std::abs(iso);
  std::vector<double> clamp(active.size());
  std::vector<signed char> last_sign(active.size(), 0);
  for (std::size_t k = 0; k < active.size(); ++k) clamp[k] = o.max_step * p.scale[active[k]];
  // slot[k]: the index into clamp / last_sign of active[k] (stable while `active` shrinks).
  std::vector<std::uint32_t> slot(active.size());
  for (std::size_t k = 0; k < slot.size(); ++k) slot[k] = static_cast<std::uint32_t>(k);
  std::vector<Vec3> points;
  std::vector<double> values;
  std::vector<Vec3> gradients;
  std::vector<std::uint8_t> moving;
  int round = 0;
  while (!active.empty()) {
    ++round;
    check_cancel(ctx);
    const std::size_t n = active.size();
    points.resize(n);
    values.resize(n);
    gradients.resize(n);
    moving.assign(n, 0);
    for (std::size_t k = 0; k < n; ++k) points[k] = p.position[active[k]];
    field.evaluate(points, values, gradients, ctx);
    evaluations += n;
    const bool last = round >= o.max_iterations;
    parallel::for_each(
        n, kGrain,
        [&](std::size_t k) {
          const std::uint32_t i = active[k];
          const double r = values[k] - iso;
          p.gradient[i] = gradients[k];
          p.residual[i] = r;
          if (std::abs(r) <= tolerance) {
            p.converged[i] = 1;
            return;
          }
          p.converged[i] = 0;
          const double norm = gradients[k].norm();
          if (!std::isfinite(r) || !std::isfinite(norm) || !(norm > 0)) return;  // stuck
          const std::uint32_t s = slot[k];
          const signed char sign = r > 0 ? 1 : -1;
          if (last_sign[s] != 0 && sign != last_sign[s]) clamp[s] *= 0.5;
          last_sign[s] = sign;
          if (last || clamp[s] < kStalled * p.scale[i]) return;  // at a jump of f: give up
          const double step = std::clamp(-r / norm, -clamp[s], clamp[s]);
          p.position[i] += (step / norm) * gradients[k];
          moving[k] = 1;
        },
        ctx);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < n; ++k) {
      if (moving[k] == 0) continue;
      active[kept] = active[k];
      slot[kept] = slot[k];
      ++kept;
    }
    active.resize(kept);
    slot.resize(kept);
  }
  return round;
}

// Per particle, its mesh neighbours (compressed rows, ascending, no duplicates).
struct Neighbours {
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> index;
};

Neighbours one_rings(std::size_t n, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  pairs.reserve(6 * triangles.size());
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      pairs.emplace_back(t[k], t[(k + 1) % 3]);
      pairs.emplace_back(t[(k + 1) % 3], t[k]);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  Neighbours nb;
  nb.start.assign(n + 1, 0);
  for (const auto& e : pairs) ++nb.start[e.first + 1];
  for (std::size_t i = 0; i < n; ++i) nb.start[i + 1] += nb.start[i];
  nb.index.reserve(pairs.size());
  for (const auto& e : pairs) nb.index.push_back(e.second);
  return nb;
}

// One relaxation round: each particle moves kRelaxWeight of the way to its neighbours'
// centroid along its tangent plane, all from the old positions; then the moved ones are
// projected again, and a particle that does not converge again is put back. Returns false when
// nothing moved.
bool relax_round(const Field& field, const ParticleMeshOptions& o, const Neighbours& nb,
                 const std::vector<std::uint8_t>& fixed, Particles& p, std::uint64_t& evaluations,
                 const Context* ctx) {
  const std::size_t n = p.position.size();
  std::vector<Vec3> moved = p.position;
  std::vector<std::uint8_t> is_moved(n, 0);
  parallel::for_each(
      n, kGrain,
      [&](std::size_t i) {
        const std::size_t b = nb.start[i];
        const std::size_t e = nb.start[i + 1];
        const double norm = p.gradient[i].norm();
        if (fixed[i] != 0 || e == b || !std::isfinite(norm) || !(norm > 0)) return;
        Vec3 centroid = Vec3::Zero();
        for (std::size_t k = b; k < e; ++k) centroid += p.position[nb.index[k]];
        centroid /= static_cast<double>(e - b);
        const Vec3 normal = p.gradient[i] / norm;
        Vec3 d = centroid - p.position[i];
        d -= d.dot(normal) * normal;
        if (!d.allFinite()) return;
        moved[i] = p.position[i] + kRelaxWeight * d;
        is_moved[i] = 1;
      },
      ctx);
  std::vector<std::uint32_t> which;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (is_moved[i] != 0) which.push_back(i);
  }
  if (which.empty()) return false;
  std::vector<Vec3> old_position(which.size()), old_gradient(which.size());
  std::vector<double> old_residual(which.size());
  std::vector<std::uint8_t> old_converged(which.size());
  for (std::size_t k = 0; k < which.size(); ++k) {
    const std::uint32_t i = which[k];
    old_position[k] = p.position[i];
    old_gradient[k] = p.gradient[i];
    old_residual[k] = p.residual[i];
    old_converged[k] = p.converged[i];
    p.position[i] = moved[i];
  }
  (void)project(field, o, which, p, evaluations, ctx);
  for (std::size_t k = 0; k < which.size(); ++k) {
    const std::uint32_t i = which[k];
    if (p.converged[i] != 0) continue;
    p.position[i] = old_position[k];
    p.gradient[i] = old_gradient[k];
    p.residual[i] = old_residual[k];
    p.converged[i] = old_converged[k];
  }
  return true;
}

// The particles on the boundary loops of open ends: they stay where the movement put them.
std::vector<std::uint8_t> fixed_particles(std::size_t n, const detail::ParticleLayout& layout) {
  std::vector<std::uint8_t> fixed(n, 0);
  for (const auto& loop : layout.open_loops) {
    for (const std::uint32_t i : loop) fixed[i] = 1;
  }
  return fixed;
}

// Tangential relaxation rounds (see the header).
void relax(const Field& field, const ParticleMeshOptions& o, const detail::ParticleLayout& layout,
           const Neighbours& nb, Particles& p, std::uint64_t& evaluations, const Context* ctx) {
  const std::vector<std::uint8_t> fixed = fixed_particles(p.position.size(), layout);
  for (int round = 0; round < o.relax; ++round) {
    if (!relax_round(field, o, nb, fixed, p, evaluations, ctx)) return;
  }
}

// Triangles facing the wrong way: their normal (counter-clockwise seen from outside) points
// along the summed gradient of their corners, that is into the surface. The mesh folds so
// where the surfaces of two branches that are not joined in the skeleton merge: the particles
// of each branch's rings land on the merged surface, over those of the other. (Rounds of full
// umbrella smoothing over the folded triangles and two rings around them, each followed by
// re-projection, were tried and left more inverted triangles than they started with: the fold
// is topological, the rings of the hidden part have no place on the merged surface.)
std::vector<std::uint32_t> inverted_triangles(const std::vector<std::array<std::uint32_t, 3>>& t,
                                              const Particles& p) {
  std::vector<std::uint32_t> out;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const Vec3& a = p.position[t[k][0]];
    const Vec3 normal = (p.position[t[k][1]] - a).cross(p.position[t[k][2]] - a);
    const Vec3 g = p.gradient[t[k][0]] + p.gradient[t[k][1]] + p.gradient[t[k][2]];
    if (normal.dot(g) > 0) out.push_back(static_cast<std::uint32_t>(k));
  }
  return out;
}

}  // namespace

TriMesh polygonize_particles(const Field& field, const Skeleton& skeleton,
                             std::span<const double> edge_spacing,
                             std::span<const std::uint8_t> open_end,
                             const ParticleMeshOptions& options, Context* ctx,
                             ParticleMeshStats* stats) {
  check_options(options);
  validate(skeleton);
  if (!(field.iso() != 0)) {
    throw InvalidArgument("polygonize_particles: the field's iso value must be non-zero");
  }
  const std::size_t edges = skeleton.edges.size();
  const std::size_t nodes = skeleton.nodes.size();
  if (!edge_spacing.empty() && edge_spacing.size() != edges) {
    throw InvalidArgument(
        "polygonize_particles: edge_spacing must be empty or have one value "
        "per edge (" +
        std::to_string(edges) + "), got " + std::to_string(edge_spacing.size()));
  }
  if (!open_end.empty() && open_end.size() != nodes) {
    throw InvalidArgument(
        "polygonize_particles: open_end must be empty or have one entry per "
        "node (" +
        std::to_string(nodes) + "), got " + std::to_string(open_end.size()));
  }

  const auto t_layout = Clock::now();
  detail::ParticleLayoutInput input;
  input.skeleton = &skeleton;
  input.edge_radius.resize(edges);
  input.edge_spacing.resize(edges);
  for (std::size_t e = 0; e < edges; ++e) {
    const double ra = skeleton.nodes[skeleton.edges[e][0]].radius;
    const double rb = skeleton.nodes[skeleton.edges[e][1]].radius;
    input.edge_radius[e] = options.placement_radius > 0
                               ? options.placement_radius
                               : options.placement_factor * 0.5 * (ra + rb);
    input.edge_spacing[e] = edge_spacing.empty() ? 0.5 * std::min(ra, rb) : edge_spacing[e];
  }
  // Branches that run into thicker ones elsewhere in the skeleton are joined there, so that
  // the mesh's connectivity is the merged surface's (polygonize/particle_merge.h).
  detail::MergedSkeleton joined = detail::join_merging_branches(
      skeleton, input.edge_radius, input.edge_spacing,
      std::vector<std::uint8_t>(open_end.begin(), open_end.end()));
  const Skeleton& layout_skeleton = joined.skeleton;
  input.skeleton = &layout_skeleton;
  input.edge_radius = std::move(joined.edge_radius);
  input.edge_spacing = std::move(joined.edge_spacing);
  input.open_end = std::move(joined.open_end);
  detail::ParticleLayoutOptions lo;
  lo.n_circ = options.n_circ;
  lo.n_sphere = options.n_sphere;
  lo.sphere_factor = options.sphere_factor;
  lo.gamma_degrees = options.gamma_degrees;
  detail::ParticleLayout layout = detail::build_particle_layout(input, lo);
  const double seconds_layout = seconds_since(t_layout);

  // Local R: the particle's edge's; at a vertex the largest of its edges'; isolated nodes their
  // radius (the layout places their sphere at it).
  std::vector<double> node_scale(layout_skeleton.nodes.size(), 0.0);
  for (std::size_t e = 0; e < layout_skeleton.edges.size(); ++e) {
    for (const std::uint32_t v : layout_skeleton.edges[e]) {
      node_scale[v] = std::max(node_scale[v], input.edge_radius[e]);
    }
  }
  for (std::size_t v = 0; v < node_scale.size(); ++v) {
    if (node_scale[v] == 0) node_scale[v] = layout_skeleton.nodes[v].radius;
  }
  const std::size_t n = layout.positions.size();
  Particles p;
  p.position = std::move(layout.positions);
  p.gradient.assign(n, Vec3::Zero());
  p.residual.assign(n, std::numeric_limits<double>::quiet_NaN());
  p.converged.assign(n, 0);
  p.scale.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    p.scale[i] =
        layout.edge[i] != kNone ? input.edge_radius[layout.edge[i]] : node_scale[layout.node[i]];
  }

  std::uint64_t evaluations = 0;
  const auto t_move = Clock::now();
  std::vector<std::uint32_t> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<std::uint32_t>(i);
  const int iterations = project(field, options, std::move(all), p, evaluations, ctx);
  const double seconds_move = seconds_since(t_move);

  const auto t_relax = Clock::now();
  const Neighbours nb = one_rings(n, layout.triangles);
  if (options.relax > 0) relax(field, options, layout, nb, p, evaluations, ctx);
  const std::size_t inverted = inverted_triangles(layout.triangles, p).size();
  const double seconds_relax = seconds_since(t_relax);

  TriMesh mesh;
  mesh.positions = std::move(p.position);
  mesh.triangles = std::move(layout.triangles);
  if (stats != nullptr) {
    ParticleMeshStats s;
    s.particles = n;
    for (std::size_t i = 0; i < n; ++i) {
      if (p.converged[i] != 0) {
        ++s.converged;
      } else if (s.unconverged.size() < kMaxListed) {
        s.unconverged.push_back(static_cast<std::uint32_t>(i));
      }
    }
    s.iterations = iterations;
    s.fallback_junctions = layout.fallback_junctions;
    s.joined_branches = joined.joins;
    s.open_loops = layout.open_loops.size();
    s.evaluations = evaluations;
    s.inverted_triangles = inverted;
    const MeshReport report = check_mesh(mesh, ctx);
    s.min_angle = report.min_angle_deg;
    s.median_angle = report.median_angle_deg;
    s.seconds_layout = seconds_layout;
    s.seconds_move = seconds_move;
    s.seconds_relax = seconds_relax;
    *stats = std::move(s);
  }
  return mesh;
}

TriMesh polygonize_particles(const Equipotential& eq, const Skeleton& skeleton,
                             const ParticleMeshOptions& options, Context* ctx,
                             ParticleMeshStats* stats) {
  if (!eq.field) throw InvalidArgument("polygonize_particles: the equipotential has no field");
  return polygonize_particles(*eq.field, skeleton, eq.charges.edge_spacing, eq.charges.open,
                              options, ctx, stats);
}

}  // namespace ramiform
