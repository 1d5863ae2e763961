// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/particles.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>

#include "polygonize/particle_layout.h"
#include "polygonize/particle_merge.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/mesh/checks.h"
#include "ramiform/mesh/winding.h"

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
// further rounds only halve the step again. 2^-40 ~ 1e-12.
constexpr double kStalled = 0x1p-40;
// Such a particle is moved sideways (orthogonal to the gradient) by kNudge times its R and
// projected again with its full clamp, at most kMaxNudges times, each time a quarter turn further
// around the gradient and farther; then it stops there, unconverged. The treecode's jumps lie on
// spheres around its clusters, and the surface has no point within delta of the iso value only
// in a narrow band where such a sphere crosses it: on `generate --segments 1000 --seed 12
// --branch-angle 15 --jitter 30 --length-ratio 0.6 --tip-radius 0.04`, a particle stalled 0.5 %
// off the iso value had converging points 0.05 R to either side.
constexpr double kNudge = 0.05;
constexpr int kMaxNudges = 4;
// A particle whose step has been clamped this many rounds in a row, always in the same
// direction, is on a long way (placed deep inside a merged surface, or far out): its clamp then
// grows by kGrowth each round it stays clamped, and is halved as before when the sign flips.
// Particles placed near the surface converge in a handful of rounds and never grow; those buried
// in the merged blob of a crowded crown crawled 0.25 R a round and ran out of rounds (1 of 2.16
// M on `lsystem bush-2d --iterations 5 --radii pipe`, 5 of 18 k on the crown above).
constexpr int kPatience = 8;
constexpr double kGrowth = 1.5;
// The grown clamp stays within this multiple of the first (R a round at the default max_step),
// so that a particle that never finds the surface (a lambda far above the field's values)
// stays near the skeleton instead of flying off exponentially.
constexpr double kMaxGrowth = 4.0;
// Layouts rebuilt at most to repair the nodes the previous one's mesh left outside.
constexpr int kMaxRepairs = 3;

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
  std::vector<std::uint8_t> nudges(active.size(), 0);
  std::vector<std::uint8_t> clamped_run(active.size(), 0);  // rounds clamped in a row
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
          if (last_sign[s] != 0 && sign != last_sign[s]) {
            clamp[s] *= 0.5;
            clamped_run[s] = 0;
          }
          last_sign[s] = sign;
          if (last) return;
          if (clamp[s] < kStalled * p.scale[i]) {
            // At a jump of f: sideways, and again from the full clamp; or give up.
            if (nudges[s] == kMaxNudges) return;
            const Vec3 n = gradients[k] / norm;
            const int axis =
                std::abs(n.x()) <= std::abs(n.y()) && std::abs(n.x()) <= std::abs(n.z())
                    ? 0
                    : (std::abs(n.y()) <= std::abs(n.z()) ? 1 : 2);
            const Vec3 u = n.cross(Vec3::Unit(axis)).normalized();
            const Vec3 w = n.cross(u);
            const Vec3 side[4] = {u, w, -u, -w};
            ++nudges[s];
            p.position[i] += kNudge * nudges[s] * p.scale[i] * side[(nudges[s] - 1) % 4];
            clamp[s] = o.max_step * p.scale[i];
            last_sign[s] = 0;
            clamped_run[s] = 0;
            moving[k] = 1;
            return;
          }
          const double newton = -r / norm;
          const double step = std::clamp(newton, -clamp[s], clamp[s]);
          if (step != newton) {
            if (clamped_run[s] < kPatience) {
              ++clamped_run[s];
            } else {
              clamp[s] = std::min(clamp[s] * kGrowth, kMaxGrowth * o.max_step * p.scale[i]);
            }
          } else {
            clamped_run[s] = 0;
          }
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

// Tangential relaxation rounds (see the header).
void relax(const Field& field, const ParticleMeshOptions& o, const detail::ParticleLayout& layout,
           const Neighbours& nb, Particles& p, std::uint64_t& evaluations, const Context* ctx) {
  const std::vector<std::uint8_t> fixed = fixed_particles(p.position.size(), layout);
  for (int round = 0; round < o.relax; ++round) {
    if (!relax_round(field, o, nb, fixed, p, evaluations, ctx)) return;
  }
}

// Points hashed in cubes of side h, to find those inside a box.
class PointGrid {
 public:
  PointGrid(std::vector<Vec3> points, double h) : points_(std::move(points)), h_(h) {
    for (std::uint32_t k = 0; k < points_.size(); ++k) cells_[key(cell(points_[k]))].push_back(k);
  }
  // Calls f(k) for every point k in the box [lo, hi] (closed), in no particular order.
  template <class F>
  void for_each_in(const Vec3& lo, const Vec3& hi, F&& f) const {
    const std::array<std::int64_t, 3> a = cell(lo);
    const std::array<std::int64_t, 3> b = cell(hi);
    const double cells = static_cast<double>(b[0] - a[0] + 1) *
                         static_cast<double>(b[1] - a[1] + 1) *
                         static_cast<double>(b[2] - a[2] + 1);
    const auto visit = [&](std::uint32_t q) {
      const Vec3& x = points_[q];
      if ((x.array() >= lo.array()).all() && (x.array() <= hi.array()).all()) f(q);
    };
    if (cells > static_cast<double>(points_.size())) {
      for (std::uint32_t q = 0; q < points_.size(); ++q) visit(q);
      return;
    }
    for (std::int64_t i = a[0]; i <= b[0]; ++i) {
      for (std::int64_t j = a[1]; j <= b[1]; ++j) {
        for (std::int64_t k = a[2]; k <= b[2]; ++k) {
          const auto it = cells_.find(key({i, j, k}));
          if (it == cells_.end()) continue;
          for (const std::uint32_t q : it->second) visit(q);
        }
      }
    }
  }

  // Whether a point lies in the box [lo, hi] (closed).
  bool any_in(const Vec3& lo, const Vec3& hi) const {
    const auto in_box = [&](const Vec3& x) {
      return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
    };
    const std::array<std::int64_t, 3> a = cell(lo);
    const std::array<std::int64_t, 3> b = cell(hi);
    // A box over more cells than there are points (a thick branch's triangle among thin
    // twigs' cells) looks at every point instead.
    const double cells = static_cast<double>(b[0] - a[0] + 1) *
                         static_cast<double>(b[1] - a[1] + 1) *
                         static_cast<double>(b[2] - a[2] + 1);
    if (cells > static_cast<double>(points_.size())) {
      return std::any_of(points_.begin(), points_.end(), in_box);
    }
    for (std::int64_t i = a[0]; i <= b[0]; ++i) {
      for (std::int64_t j = a[1]; j <= b[1]; ++j) {
        for (std::int64_t k = a[2]; k <= b[2]; ++k) {
          const auto it = cells_.find(key({i, j, k}));
          if (it == cells_.end()) continue;
          for (const std::uint32_t q : it->second) {
            if (in_box(points_[q])) return true;
          }
        }
      }
    }
    return false;
  }

 private:
  std::array<std::int64_t, 3> cell(const Vec3& x) const {
    return {static_cast<std::int64_t>(std::floor(x.x() / h_)),
            static_cast<std::int64_t>(std::floor(x.y() / h_)),
            static_cast<std::int64_t>(std::floor(x.z() / h_))};
  }
  static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    return (static_cast<std::uint64_t>(c[0] & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(c[1] & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(c[2] & 0x1fffff);
  }
  std::vector<Vec3> points_;
  double h_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

// Puts back (to `before`) the particles of every triangle whose corners, between `before` and
// now, span a box holding one of `nodes`, until no triangle does. Moving every particle along
// the straight line from before to now keeps each triangle inside the convex hull of its six
// corner positions, so no triangle then sweeps across a node: the mesh's winding number at every
// node is what it was before (it is an integer that changes only when the surface crosses the
// point). Returns the particles put back.
std::size_t restore_sweeps(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                           const Particles& before, const PointGrid& nodes, Particles& p,
                           const Context* ctx) {
  std::vector<std::uint8_t> moved(p.position.size(), 0);
  for (std::size_t i = 0; i < moved.size(); ++i) {
    moved[i] = p.position[i] != before.position[i] ? 1 : 0;
  }
  std::size_t restored = 0;
  for (;;) {
    std::vector<std::uint8_t> hit(triangles.size(), 0);
    parallel::for_each(
        triangles.size(), kGrain,
        [&](std::size_t k) {
          const auto& t = triangles[k];
          if (moved[t[0]] == 0 && moved[t[1]] == 0 && moved[t[2]] == 0) return;
          Vec3 lo = p.position[t[0]];
          Vec3 hi = lo;
          for (const std::uint32_t i : t) {
            for (const Vec3* x : std::array<const Vec3*, 2>{&p.position[i], &before.position[i]}) {
              lo = lo.cwiseMin(*x);
              hi = hi.cwiseMax(*x);
            }
          }
          if (nodes.any_in(lo, hi)) hit[k] = 1;
        },
        ctx);
    std::size_t changed = 0;
    for (std::size_t k = 0; k < triangles.size(); ++k) {
      if (hit[k] == 0) continue;
      for (const std::uint32_t i : triangles[k]) {
        if (moved[i] == 0) continue;
        moved[i] = 0;
        p.position[i] = before.position[i];
        p.gradient[i] = before.gradient[i];
        p.residual[i] = before.residual[i];
        p.converged[i] = before.converged[i];
        ++changed;
      }
    }
    if (changed == 0) return restored;
    restored += changed;
  }
}

// A particle's starting point and step scale, bit for bit.
struct ProjectionKey {
  std::array<std::uint64_t, 4> bits;
  bool operator==(const ProjectionKey&) const = default;
};

struct ProjectionKeyHash {
  std::size_t operator()(const ProjectionKey& k) const {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (const std::uint64_t b : k.bits) {
      h ^= b + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    }
    return static_cast<std::size_t>(h);
  }
};

ProjectionKey projection_key(const Vec3& x, double scale) {
  ProjectionKey k{};
  std::memcpy(&k.bits[0], &x.x(), sizeof(double));
  std::memcpy(&k.bits[1], &x.y(), sizeof(double));
  std::memcpy(&k.bits[2], &x.z(), sizeof(double));
  std::memcpy(&k.bits[3], &scale, sizeof(double));
  return k;
}

// Per point of `nodes`, 1 when some triangle's corners, between `start` and `end`, span a box
// holding it: a point no triangle sweeps keeps its winding number (see restore_sweeps).
std::vector<std::uint8_t> swept_points(const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                       const std::vector<Vec3>& start, const std::vector<Vec3>& end,
                                       const PointGrid& nodes, std::size_t points,
                                       const Context* ctx) {
  std::vector<std::atomic<std::uint8_t>> hit(points);
  for (auto& h : hit) h.store(0, std::memory_order_relaxed);
  parallel::for_each(
      triangles.size(), kGrain,
      [&](std::size_t k) {
        const auto& t = triangles[k];
        Vec3 lo = start[t[0]];
        Vec3 hi = lo;
        for (const std::uint32_t i : t) {
          lo = lo.cwiseMin(start[i]).cwiseMin(end[i]);
          hi = hi.cwiseMax(start[i]).cwiseMax(end[i]);
        }
        nodes.for_each_in(lo, hi,
                          [&](std::uint32_t q) { hit[q].store(1, std::memory_order_relaxed); });
      },
      ctx);
  std::vector<std::uint8_t> out(points);
  for (std::size_t q = 0; q < points; ++q) out[q] = hit[q].load(std::memory_order_relaxed);
  return out;
}

// The nodes among `suspects` that the mesh (`positions`, `triangles`) leaves outside: fast
// generalized winding number at most 0.5 (mesh/winding.h), as `ramiform check` tests them.
std::vector<std::uint32_t> nodes_outside(const Skeleton& skeleton,
                                         const std::vector<std::uint32_t>& suspects,
                                         const std::vector<Vec3>& positions,
                                         const std::vector<std::array<std::uint32_t, 3>>& triangles,
                                         const Context* ctx) {
  if (suspects.empty()) return {};
  TriMesh mesh;
  mesh.positions = positions;
  mesh.triangles = triangles;
  std::vector<Vec3> points(suspects.size());
  for (std::size_t k = 0; k < suspects.size(); ++k) {
    points[k] = skeleton.nodes[suspects[k]].position;
  }
  const std::vector<char> inside = points_inside(mesh, points, ctx);
  std::vector<std::uint32_t> out;
  for (std::size_t k = 0; k < suspects.size(); ++k) {
    if (inside[k] == 0) out.push_back(suspects[k]);
  }
  return out;
}

// An edge whose node radii differ by more than this factor is split for the layout.
constexpr double kMaxTaper = 2.0;

// Splits the layout's leaf edges whose thin end is the leaf and whose node radii differ by more
// than kMaxTaper into pieces whose radii differ by at most that (new nodes on the axis, radius
// linear along the edge as the surface's is; appended after the existing nodes, so every node
// keeps its index). A single R per edge (the mean of its node radii) is up to (1 + taper) / 2
// times the surface's radius at the thin end; at a thin leaf its last rings and its cap then
// start far out in the field's tail and slide toward the thick end instead of closing around
// the leaf (a leaf of 0.05 on an edge from 0.5 was left outside, its cap's pole unconverged).
// Each piece's R is its edge's R scaled by the piece's mean radius over the edge's, where that
// is smaller: toward the thick end R stays the edge's (larger rings there moved the rings of an
// acute fork's junction farther out and webbed its crotch). The new nodes are straight chain
// nodes: the layout gives them rings, and only the rings' radii change along the edge. Edges
// whose thin end is a junction keep their R (split, the junction's smaller sphere folded a join
// beside it: 4 -> 38 of 3,000 triangles in ThinBranchBesideAThickerOneIsJoinedAtTheNeck).
void split_tapering_edges(detail::MergedSkeleton& m) {
  Skeleton& s = m.skeleton;
  const std::size_t edges = s.edges.size();
  const std::vector<std::uint32_t> degree = degrees(s);
  for (std::size_t e = 0; e < edges; ++e) {
    const std::uint32_t a = s.edges[e][0];
    const std::uint32_t b = s.edges[e][1];
    const double ra = s.nodes[a].radius;
    const double rb = s.nodes[b].radius;
    const double taper = std::max(ra, rb) / std::min(ra, rb);
    if (!(taper > kMaxTaper) || degree[ra < rb ? a : b] != 1) continue;
    const int pieces = static_cast<int>(std::ceil(std::log(taper) / std::log(kMaxTaper)));
    const Vec3 pa = s.nodes[a].position;
    const Vec3 pb = s.nodes[b].position;
    const double r_edge = m.edge_radius[e];
    const double spacing = m.edge_spacing[e];
    // Radii in geometric steps from a to b; the node where the radius (linear in t) has them.
    std::uint32_t from = a;
    double r_from = ra;
    for (int k = 1; k <= pieces; ++k) {
      std::uint32_t to = b;
      double r_to = rb;
      if (k < pieces) {
        r_to = ra * std::pow(rb / ra, static_cast<double>(k) / pieces);
        const double t = (ra - r_to) / (ra - rb);
        to = static_cast<std::uint32_t>(s.nodes.size());
        s.nodes.push_back(SkeletonNode{pa + t * (pb - pa), r_to});
        if (!s.node_types.empty()) s.node_types.push_back(s.node_types[a]);
        if (!s.open_ends.empty()) s.open_ends.push_back(0);
        if (!m.open_end.empty()) m.open_end.push_back(0);
        if (!m.node_sphere.empty()) m.node_sphere.push_back(0.0);
      }
      const double r = std::min(r_edge, r_edge * (r_from + r_to) / (ra + rb));
      if (k == 1) {
        s.edges[e] = {from, to};
        m.edge_radius[e] = r;
      } else {
        s.edges.push_back({from, to});
        if (!s.curves.empty()) s.curves.emplace_back();
        m.edge_radius.push_back(r);
        m.edge_spacing.push_back(spacing);
      }
      from = to;
      r_from = r_to;
    }
  }
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
  const auto nodes = static_cast<std::uint32_t>(skeleton.nodes.size());
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

  std::vector<double> base_radius(edges);
  std::vector<double> base_spacing(edges);
  for (std::size_t e = 0; e < edges; ++e) {
    const double ra = skeleton.nodes[skeleton.edges[e][0]].radius;
    const double rb = skeleton.nodes[skeleton.edges[e][1]].radius;
    base_radius[e] = options.placement_radius > 0 ? options.placement_radius
                                                  : options.placement_factor * 0.5 * (ra + rb);
    base_spacing[e] = edge_spacing.empty() ? 0.5 * std::min(ra, rb) : edge_spacing[e];
  }
  const std::vector<std::uint8_t> open(open_end.begin(), open_end.end());
  detail::ParticleLayoutOptions lo;
  lo.n_circ = options.n_circ;
  lo.n_sphere = options.n_sphere;
  lo.sphere_factor = options.sphere_factor;
  lo.gamma_degrees = options.gamma_degrees;

  // The skeleton's nodes the mesh must enclose: all but the open leaves (which sit in their
  // loop).
  std::vector<std::uint32_t> checked;
  {
    const auto degree = degrees(skeleton);
    for (std::uint32_t v = 0; v < nodes; ++v) {
      if (!(degree[v] == 1 && !open.empty() && open[v] != 0)) checked.push_back(v);
    }
  }

  // The checked nodes hashed in cubes of twice their mean radius (about a ring's diameter).
  std::optional<PointGrid> node_grid;
  if (!checked.empty()) {
    std::vector<Vec3> points(checked.size());
    double h = 0;
    for (std::size_t k = 0; k < checked.size(); ++k) {
      points[k] = skeleton.nodes[checked[k]].position;
      h += skeleton.nodes[checked[k]].radius;
    }
    node_grid.emplace(std::move(points), 2 * h / static_cast<double>(checked.size()));
  }

  // Branches that run into thicker ones elsewhere in the skeleton are joined there, so that
  // the mesh's connectivity is the merged surface's (polygonize/particle_merge.h). A node the
  // projected mesh leaves outside is repaired in a rebuilt layout: joined to a thicker branch
  // nearby when no join moved it, left in its place when one did (the joined layout, built
  // around the new place, missed the old one).
  std::vector<std::uint8_t> force;
  std::vector<std::uint8_t> tried;  // per node, a bit per force value its layouts have had
  detail::ParticleLayoutInput input;
  std::uint64_t evaluations = 0;
  int iterations = 0;
  double seconds_layout = 0;
  double seconds_move = 0;
  std::size_t first_outside = 0;
  std::size_t unrelaxed = 0;
  // The previous attempt's projections by starting point (and step scale): a particle the
  // rebuilt layout starts where it started before ends where it ended, bit for bit (each one
  // moves on its own, and a field value does not depend on the batch), so it is copied.
  std::unordered_map<ProjectionKey, std::uint32_t, ProjectionKeyHash> previous_start;
  Particles previous;
  // The attempt with the fewest nodes outside (the first among equals) is the result.
  struct Attempt {
    detail::MergedSkeleton joined;
    detail::ParticleLayout layout;
    Particles particles;
    std::vector<std::uint32_t> outside_nodes;  // the skeleton's nodes its mesh left outside
  };
  std::optional<Attempt> best;
  for (int attempt = 0;; ++attempt) {
    const auto t_build = Clock::now();
    detail::MergedSkeleton joined = detail::join_merging_branches(
        skeleton, base_radius, base_spacing, open, force, &field, ctx);
    if (!(options.placement_radius > 0)) split_tapering_edges(joined);
    input.skeleton = &joined.skeleton;
    input.edge_radius = joined.edge_radius;
    input.edge_spacing = joined.edge_spacing;
    input.open_end = joined.open_end;
    input.node_sphere = joined.node_sphere;
    detail::ParticleLayout layout = detail::build_particle_layout(input, lo);
    seconds_layout += seconds_since(t_build);
    const Skeleton& layout_skeleton = joined.skeleton;

    // Local R: the particle's edge's; at a vertex the largest of its edges'; isolated nodes
    // their radius (the layout places their sphere at it).
    std::vector<double> node_scale(layout_skeleton.nodes.size(), 0.0);
    for (std::size_t e = 0; e < layout_skeleton.edges.size(); ++e) {
      for (const std::uint32_t v : layout_skeleton.edges[e]) {
        node_scale[v] = std::max(node_scale[v], input.edge_radius[e]);
      }
    }
    for (std::size_t v = 0; v < node_scale.size(); ++v) {
      if (node_scale[v] == 0) node_scale[v] = layout_skeleton.nodes[v].radius;
      if (!joined.node_sphere.empty()) {
        node_scale[v] = std::max(node_scale[v], joined.node_sphere[v]);
      }
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

    const auto t_move = Clock::now();
    const std::vector<Vec3> start = p.position;
    std::vector<std::uint32_t> active;
    active.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      const auto it = previous_start.find(projection_key(start[i], p.scale[i]));
      if (it == previous_start.end()) {
        active.push_back(i);
        continue;
      }
      const std::uint32_t j = it->second;
      p.position[i] = previous.position[j];
      p.gradient[i] = previous.gradient[j];
      p.residual[i] = previous.residual[j];
      p.converged[i] = previous.converged[j];
    }
    const int rounds = project(field, options, std::move(active), p, evaluations, ctx);
    if (attempt == 0) iterations = rounds;
    seconds_move += seconds_since(t_move);

    // Only a node that a join moved, or that some triangle swept on its way from the layout to
    // the surface, can be outside: every other one keeps the winding number of the layout,
    // whose tubes and spheres it is the centre of (see restore_sweeps).
    const auto t_check = Clock::now();
    std::vector<std::uint32_t> suspects;
    if (node_grid) {
      const std::vector<std::uint8_t> swept =
          swept_points(layout.triangles, start, p.position, *node_grid, checked.size(), ctx);
      for (std::size_t k = 0; k < checked.size(); ++k) {
        const std::uint32_t v = checked[k];
        if (swept[k] != 0 || (!joined.moved.empty() && joined.moved[v] != 0)) {
          suspects.push_back(v);
        }
      }
    }
    const std::vector<std::uint32_t> outside =
        nodes_outside(skeleton, suspects, p.position, layout.triangles, ctx);
    seconds_layout += seconds_since(t_check);
    const bool better = !best || outside.size() < best->outside_nodes.size();
    if (attempt == 0) first_outside = outside.size();
    if (better) {
      best = Attempt{std::move(joined), std::move(layout), {}, outside};
    }
    if (outside.empty() || attempt == kMaxRepairs) {
      if (better) best->particles = std::move(p);
      break;
    }
    // A node left where it was is joined to a thicker branch nearby; one a join moved (whose
    // own place the joined layout missed) stays where it is. Where that leaves it outside too,
    // it takes the way not tried yet (a node joined at the neck, then left in place, is joined
    // on the thicker axis: 1 of 5,001 nodes of a 5,000-segment tree). Each node tries each way
    // once.
    if (force.empty()) {
      force.assign(nodes, detail::kJoinAsFound);
      tried.assign(nodes, 0);
    }
    std::size_t changed = 0;
    const std::vector<std::uint8_t>& moved_nodes = better ? best->joined.moved : joined.moved;
    for (const std::uint32_t v : outside) {
      const bool moved = !moved_nodes.empty() && moved_nodes[v] != 0;
      tried[v] |= static_cast<std::uint8_t>(1U << force[v]);
      const std::uint8_t first = moved ? detail::kJoinNever : detail::kJoinNearby;
      const std::uint8_t second = moved ? detail::kJoinNearby : detail::kJoinNever;
      if ((tried[v] & (1U << first)) == 0) {
        force[v] = first;
      } else if ((tried[v] & (1U << second)) == 0) {
        force[v] = second;
      } else {
        continue;
      }
      ++changed;
    }
    if (changed == 0) {
      if (better) best->particles = std::move(p);
      break;
    }
    previous_start.clear();
    previous_start.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      previous_start.emplace(projection_key(start[i], p.scale[i]), i);
    }
    if (better) {
      best->particles = p;
    }
    previous = std::move(p);
  }
  const detail::MergedSkeleton joined = std::move(best->joined);
  detail::ParticleLayout layout = std::move(best->layout);
  Particles p = std::move(best->particles);
  const std::size_t outside = best->outside_nodes.size();
  const std::size_t n = p.position.size();

  const auto t_relax = Clock::now();
  const Neighbours nb = one_rings(n, layout.triangles);
  if (options.relax > 0) {
    const Particles before = p;
    relax(field, options, layout, nb, p, evaluations, ctx);
    // Relaxation slides particles along the surface; where it folds, that can carry a folded
    // sheet across a node (2 of 5,001 nodes on a 5,000-segment tree). Those moves are undone.
    if (node_grid) unrelaxed = restore_sweeps(layout.triangles, before, *node_grid, p, ctx);
  }
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
    s.repaired_nodes = first_outside - outside;
    s.nodes_outside = outside;
    s.outside_nodes = best->outside_nodes;
    std::sort(s.outside_nodes.begin(), s.outside_nodes.end());
    if (s.outside_nodes.size() > kMaxListed) s.outside_nodes.resize(kMaxListed);
    s.unrelaxed = unrelaxed;
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
