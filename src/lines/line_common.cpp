// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "lines/line_common.h"

#include <cmath>

#include "ramiform/core/errors.h"

namespace ramiform::detail {
namespace {

std::vector<Vec3> particle_positions(const ParticleSystem& particles) {
  if (particles.particles.empty()) throw InvalidArgument("lines: the particle system is empty");
  std::vector<Vec3> out;
  out.reserve(particles.particles.size());
  for (const SurfaceParticle& p : particles.particles) out.push_back(p.position);
  return out;
}

}  // namespace

DeltaLookup::DeltaLookup(const ParticleSystem& particles)
    : system_(&particles), positions_(particle_positions(particles)), tree_(positions_) {}

std::uint32_t DeltaLookup::nearest(const Vec3& p) const {
  thread_local std::vector<std::pair<std::uint32_t, double>> found;
  tree_.nearest(p, 1, found);
  return found.empty() ? 0 : found[0].first;
}

double DeltaLookup::delta_at(const Vec3& p) const { return system_->particles[nearest(p)].delta; }

LinePointHash::LinePointHash(double cell) : inv_cell_(1.0 / cell), slots_(std::size_t{1} << 6) {
  if (!(cell > 0) || !std::isfinite(inv_cell_)) {
    throw InvalidArgument("lines: line point hash cell must be positive and finite");
  }
}

std::array<std::int64_t, 3> LinePointHash::cell_of(const Vec3& p) const {
  return {static_cast<std::int64_t>(std::floor(p.x() * inv_cell_)),
          static_cast<std::int64_t>(std::floor(p.y() * inv_cell_)),
          static_cast<std::int64_t>(std::floor(p.z() * inv_cell_))};
}

std::uint64_t LinePointHash::key(std::int64_t x, std::int64_t y, std::int64_t z) {
  // 21 bits per axis (wrapping): distinct cells may share a key, which only costs a distance
  // test, never a wrong answer.
  const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v) & 0x1FFFFFu; };
  return (u(x) << 42) | (u(y) << 21) | u(z);
}

void LinePointHash::insert(const Vec3& p, std::uint32_t line, std::int32_t index) {
  if (entries_.size() >= kNone - 1) throw InvalidArgument("lines: too many line points");
  if (2 * (used_ + 1) > slots_.size()) grow();
  const auto c = cell_of(p);
  const std::uint64_t k = key(c[0], c[1], c[2]);
  const auto e = static_cast<std::uint32_t>(entries_.size());
  entries_.push_back(Entry{p, line, index, kNone});
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t s = home(k);; s = (s + 1) & mask) {
    Slot& slot = slots_[s];
    if (slot.first == kNone) {
      slot = Slot{k, e, e};
      ++used_;
      return;
    }
    if (slot.key == k) {
      entries_[slot.last].next = e;
      slot.last = e;
      return;
    }
  }
}

void LinePointHash::grow() {
  std::vector<Slot> old(slots_.size() * 2);
  old.swap(slots_);
  --shift_;
  const std::size_t mask = slots_.size() - 1;
  for (const Slot& slot : old) {
    if (slot.first == kNone) continue;
    std::size_t s = home(slot.key);
    while (slots_[s].first != kNone) s = (s + 1) & mask;
    slots_[s] = slot;
  }
}

void project_to_surface(const Field& field, std::span<Vec3> points, std::span<const double> scale,
                        double tolerance, int max_rounds, std::span<double> values,
                        std::span<Vec3> gradients, std::span<std::uint8_t> ok, const Context* ctx) {
  const std::size_t n = points.size();
  const double iso = field.iso();
  std::vector<std::uint32_t> active(n);
  for (std::size_t i = 0; i < n; ++i) {
    active[i] = static_cast<std::uint32_t>(i);
    ok[i] = 0;
  }
  std::vector<Vec3> batch;
  std::vector<double> f;
  std::vector<Vec3> g;
  for (int round = 0; round <= max_rounds && !active.empty(); ++round) {
    batch.resize(active.size());
    f.resize(active.size());
    g.resize(active.size());
    for (std::size_t k = 0; k < active.size(); ++k) batch[k] = points[active[k]];
    field.evaluate(batch, f, g, ctx);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < active.size(); ++k) {
      const std::uint32_t i = active[k];
      values[i] = f[k];
      gradients[i] = g[k];
      const double g2 = g[k].squaredNorm();
      if (!(g2 > 0) || !std::isfinite(g2) || !std::isfinite(f[k])) continue;  // fails
      const double distance = (f[k] - iso) / std::sqrt(g2);
      if (std::abs(distance) <= tolerance * scale[i]) {
        ok[i] = 1;
        continue;
      }
      if (round == max_rounds) continue;  // fails
      Vec3 move = -(f[k] - iso) / g2 * g[k];
      const double length = move.norm();
      if (length > scale[i]) move *= scale[i] / length;
      points[i] += move;
      active[kept++] = i;
    }
    active.resize(kept);
  }
}

double polyline_length(const Polyline& line) {
  double length = 0;
  for (std::size_t i = 1; i < line.points.size(); ++i)
    length += (line.points[i] - line.points[i - 1]).norm();
  if (line.closed && line.points.size() > 2)
    length += (line.points.front() - line.points.back()).norm();
  return length;
}

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace ramiform::detail

namespace ramiform {

ParticleLookup::ParticleLookup(const ParticleSystem& particles)
    : impl_(std::make_unique<Impl>(particles)) {}

ParticleLookup::~ParticleLookup() = default;

void ParticleLookup::Impl::check(const ParticleSystem& particles) const {
  if (&delta.system() != &particles || delta.positions().size() != particles.particles.size()) {
    throw InvalidArgument("lines: the particle lookup was made for another particle system");
  }
}

}  // namespace ramiform
