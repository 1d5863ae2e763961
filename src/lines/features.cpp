// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Feature lines (creases) traced from straddle particle pairs, after Proença, Jorge & Costa
// Sousa 2008, "Suggestive Contours over Point-Set Implicits" (GRAPP), §6: straddle points by
// eq. 11 found by the neighbourhood search (their improvement 3: the before/after-movement test
// of Foster, Jepp, Wyvill, Costa Sousa, Galbraith & Jorge 2005, "Drawing surfaces" (Computers &
// Graphics) needs the running simulation), then moved along the two faces parallel to the
// feature with steps scaled by δ_i (improvement 4), the crease points estimated between them,
// until eq. 11 fails or another feature line is near.
//
// Choices the paper leaves open:
// - The crease point between two side points a, b (normals n_a, n_b) is the point of the line
//   where their tangent planes meet nearest to a guess (exact for planar faces), projected onto
//   f = iso. The crease direction is n_a × n_b.
// - Side points sit ρ = kSideOffset·δ = 0.05 δ across the crease on each face (c + ρ (t × n_a),
//   projected). Eq. 11 is tested on their normals, not on the straddle pair's: over 2ρ a smooth
//   surface turns by 2ρκ = 0.1 δκ, under k_a unless δ exceeds 1.5 curvature radii, while a
//   crease keeps its full dihedral angle. Straddle pairs are common on smooth surfaces (a torus
//   with 10,000 particles has 30,000 of them: particles 1.5 δ apart often differ by more than
//   k_a); they give no line. Pairs with a particle between them whose normal lies between
//   theirs are dropped before any field evaluation for the same reason.
// - Each particle contributes its best partner (largest normal angle) as a candidate; the
//   candidates, strongest first, are verified in batches (one field evaluation per Newton
//   round for the whole batch) and traced one at a time, skipping those already on a line.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "lines/line_common.h"
#include "ramiform/core/parallel.h"
#include "ramiform/lines/lines.h"

namespace ramiform {
namespace {

using detail::DeltaLookup;
using detail::LinePointHash;

constexpr double kCreaseStep = 1.0;     ///< × δ: step along the crease
constexpr double kSideOffset = 0.05;    ///< × δ: side points' distance from the crease
constexpr double kFeatureNear = 0.5;    ///< × δ: another feature line is near
constexpr double kPairCovered = 2.0;    ///< × δ: a candidate this near a line is not traced
constexpr double kIntermediate = 0.25;  ///< share of a pair's angle that marks a between normal
constexpr double kCreaseJump = 1.0;     ///< × step: farthest a crease point may be from its guess
constexpr int kProjectRounds = 12;      ///< Newton rounds of a projection onto f = iso
constexpr std::size_t kBatch = 256;     ///< candidates verified per batch
constexpr std::size_t kMaxTracePoints = std::size_t{1} << 16;  ///< per direction of one trace
constexpr int kArcMargin = 4;      ///< own points fewer steps away along the trace are not "near"
constexpr double kAdvance = 0.25;  ///< × step: least progress along the crease of a step

// A crease sample: the crease point c, its direction t, and a side point on each face.
struct Crease {
  Vec3 c = Vec3::Zero(), t = Vec3::Zero();
  // Side points and their unit outward normals.
  Vec3 a = Vec3::Zero(), na = Vec3::Zero(), b = Vec3::Zero(), nb = Vec3::Zero();
  double delta = 0;
  bool ok = true;
};

// The point nearest to `guess` on the line where the planes (a, na) and (b, nb) meet.
bool plane_meet(const Vec3& a, const Vec3& na, const Vec3& b, const Vec3& nb, const Vec3& guess,
                Vec3& out) {
  const double c = na.dot(nb);
  const double det = 1 - c * c;
  if (!(det > 1e-12)) return false;
  const double ra = na.dot(a - guess), rb = nb.dot(b - guess);
  const double alpha = (ra - c * rb) / det, beta = (rb - c * ra) / det;
  out = guess + alpha * na + beta * nb;
  return out.allFinite();
}

class CreaseTracer {
 public:
  CreaseTracer(const Field& field, const DeltaLookup& lookup, double k_a, const Context* ctx)
      : field_(field), lookup_(lookup), cos_k_a_(std::cos(k_a)), ctx_(ctx) {}

  // Moves every crease in `cs` to the crease near guesses[i]: the crease point from the current
  // side planes, projected; fresh side points across it, projected; the crease point again from
  // the new side planes, projected. A crease whose side normals no longer differ by more than
  // k_a, or whose projections fail, or whose point lands farther than `reach[i]` from the
  // guess, gets ok = false.
  void refine(std::vector<Crease>& cs, const std::vector<Vec3>& guesses,
              const std::vector<double>& reach) {
    const std::size_t m = cs.size();
    // 1. Crease points from the current side planes.
    pts_.resize(m);
    scale_.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      Crease& k = cs[i];
      if (!k.ok || !plane_meet(k.a, k.na, k.b, k.nb, guesses[i], pts_[i])) {
        k.ok = false;
        pts_[i] = guesses[i];
      }
      scale_[i] = k.delta;
    }
    project();
    for (std::size_t i = 0; i < m; ++i) {
      if (!ok_[i]) cs[i].ok = false;
      cs[i].c = pts_[i];
    }
    // 2. Side points across the crease, on the faces of a and of b.
    pts_.resize(2 * m);
    scale_.resize(2 * m);
    for (std::size_t i = 0; i < m; ++i) {
      Crease& k = cs[i];
      Vec3 t = k.na.cross(k.nb);
      if (!(t.norm() > 0)) k.ok = false;
      t.normalize();
      Vec3 ua = t.cross(k.na), ub = t.cross(k.nb);
      if (ua.dot(k.a - k.c) < 0) ua = -ua;
      if (ub.dot(k.b - k.c) < 0) ub = -ub;
      const double rho = kSideOffset * k.delta;
      pts_[2 * i] = k.c + rho * ua.normalized();
      pts_[2 * i + 1] = k.c + rho * ub.normalized();
      scale_[2 * i] = scale_[2 * i + 1] = k.delta;
    }
    project();
    for (std::size_t i = 0; i < m; ++i) {
      Crease& k = cs[i];
      if (!ok_[2 * i] || !ok_[2 * i + 1]) k.ok = false;
      k.a = pts_[2 * i];
      k.b = pts_[2 * i + 1];
      k.na = -grads_[2 * i].normalized();
      k.nb = -grads_[2 * i + 1].normalized();
      // Eq. 11 across the crease.
      if (!(k.na.dot(k.nb) < cos_k_a_)) k.ok = false;
    }
    // 3. The crease point from the new side planes.
    pts_.resize(m);
    scale_.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
      Crease& k = cs[i];
      if (!k.ok || !plane_meet(k.a, k.na, k.b, k.nb, k.c, pts_[i])) {
        k.ok = false;
        pts_[i] = k.c;
      }
    }
    project();
    for (std::size_t i = 0; i < m; ++i) {
      Crease& k = cs[i];
      if (!ok_[i] || !((pts_[i] - guesses[i]).norm() <= reach[i])) k.ok = false;
      k.c = pts_[i];
      k.t = k.na.cross(k.nb).normalized();
      if (!k.t.allFinite()) k.ok = false;
      if (k.ok) k.delta = lookup_.delta_at(k.c);
    }
  }

 private:
  void project() {
    const std::size_t m = pts_.size();
    values_.resize(m);
    grads_.resize(m);
    ok_.resize(m);
    detail::project_to_surface(field_, pts_, scale_, detail::kLineSurfaceTolerance, kProjectRounds,
                               values_, grads_, ok_, ctx_);
  }

  const Field& field_;
  const DeltaLookup& lookup_;
  double cos_k_a_;
  const Context* ctx_;
  std::vector<Vec3> pts_, grads_;
  std::vector<double> scale_, values_;
  std::vector<std::uint8_t> ok_;
};

struct Candidate {
  double angle;
  std::uint32_t i, j;
};

// True when a particle of `near` lies between the pair's particles (within half their distance
// of their midpoint) with a normal turned by more than kIntermediate of the pair's angle from
// both of theirs: the normal turns gradually there, as on a smooth surface, where a crease
// would give every particle the normal of one face or the other. Saves verifying the many
// straddle pairs of coarsely sampled smooth surfaces.
bool intermediate_normal(const std::vector<SurfaceParticle>& ps,
                         const std::vector<std::pair<std::uint32_t, double>>& near,
                         const Candidate& c) {
  const Vec3 mid = 0.5 * (ps[c.i].position + ps[c.j].position);
  const double r2 = 0.25 * (ps[c.i].position - ps[c.j].position).squaredNorm();
  const double cos_limit = std::cos(kIntermediate * c.angle);
  for (const auto& [k, d2] : near) {
    if (k == c.i || k == c.j || (ps[k].position - mid).squaredNorm() >= r2) continue;
    const Vec3& n = ps[k].normal;
    if (std::max(n.dot(ps[c.i].normal), n.dot(ps[c.j].normal)) < cos_limit) return true;
  }
  return false;
}

}  // namespace

std::vector<Polyline> feature_lines(const Field& field, const ParticleSystem& particles,
                                    const LineOptions& options, LineStats* stats,
                                    const Context* ctx) {
  const auto clock_start = std::chrono::steady_clock::now();
  validate(options);
  const std::uint64_t evals_start = field.evaluations();
  std::vector<Polyline> result;
  if (particles.particles.empty()) return result;
  const DeltaLookup lookup(particles);
  const std::vector<SurfaceParticle>& ps = particles.particles;
  const double k_a = options.k_a_deg * std::numbers::pi / 180;
  const double cos_k_a = std::cos(k_a);

  // Straddle pairs (eq. 11) by the neighbourhood search: each particle's best partner (largest
  // angle) as a candidate, and the number of distinct pairs (a pair seen from both of its
  // particles is counted from the lower index only).
  struct Found {
    std::size_t pairs = 0;
    std::vector<Candidate> best;
  };
  const double r = options.straddle_radius;
  Found found = parallel::reduce(
      ps.size(), 256, Found{},
      [&](std::size_t lo, std::size_t hi) {
        Found part;
        std::vector<std::pair<std::uint32_t, double>> near;
        for (std::size_t i = lo; i < hi; ++i) {
          lookup.tree().within_by_index(ps[i].position, r * ps[i].delta, near);
          double best_cos = cos_k_a;
          std::uint32_t best_j = 0;
          for (const auto& [j, d2] : near) {
            if (j == i) continue;
            const double cosine = ps[i].normal.dot(ps[j].normal);
            if (!(cosine < cos_k_a)) continue;
            const double rj = r * ps[j].delta;
            if (j > i || !(d2 < rj * rj)) ++part.pairs;
            if (cosine < best_cos) {  // ties: the lower index (near is sorted by index)
              best_cos = cosine;
              best_j = j;
            }
          }
          if (best_cos < cos_k_a) {
            const auto ii = static_cast<std::uint32_t>(i);
            const Candidate c{detail::angle_between(ps[i].normal, ps[best_j].normal),
                              std::min(ii, best_j), std::max(ii, best_j)};
            if (!intermediate_normal(ps, near, c)) part.best.push_back(c);
          }
        }
        return part;
      },
      [](Found acc, Found part) {
        acc.pairs += part.pairs;
        acc.best.insert(acc.best.end(), part.best.begin(), part.best.end());
        return acc;
      },
      ctx);
  if (stats != nullptr) stats->straddle_pairs += found.pairs;
  std::vector<Candidate>& candidates = found.best;
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& l, const Candidate& r) {
    if (l.angle != r.angle) return l.angle > r.angle;
    return l.i != r.i ? l.i < r.i : l.j < r.j;
  });
  candidates.erase(
      std::unique(candidates.begin(), candidates.end(),
                  [](const Candidate& l, const Candidate& r) { return l.i == r.i && l.j == r.j; }),
      candidates.end());

  double mean_delta = 0;
  for (const SurfaceParticle& p : ps) mean_delta += p.delta;
  mean_delta /= static_cast<double>(ps.size());
  LinePointHash hash(kPairCovered * mean_delta);
  auto any = [](std::uint32_t, std::int32_t) { return true; };

  CreaseTracer tracer(field, lookup, k_a, ctx);
  std::vector<Crease> batch, one(1);
  std::vector<Vec3> guesses, one_guess(1);
  std::vector<double> reach, one_reach(1);
  std::vector<std::uint32_t> line_of;
  for (std::size_t begin = 0; begin < candidates.size(); begin += kBatch) {
    check_cancel(ctx);
    const std::size_t end = std::min(candidates.size(), begin + kBatch);
    // Verify the batch's uncovered candidates together.
    batch.clear();
    guesses.clear();
    reach.clear();
    for (std::size_t k = begin; k < end; ++k) {
      const SurfaceParticle& pi = ps[candidates[k].i];
      const SurfaceParticle& pj = ps[candidates[k].j];
      const Vec3 mid = 0.5 * (pi.position + pj.position);
      const double delta = std::min(pi.delta, pj.delta);
      if (hash.any_within(mid, kPairCovered * delta, any)) continue;
      Crease c;
      c.a = pi.position;
      c.na = pi.normal;
      c.b = pj.position;
      c.nb = pj.normal;
      c.delta = delta;
      c.c = mid;
      batch.push_back(c);
      guesses.push_back(mid);
      reach.push_back(options.straddle_radius * std::max(pi.delta, pj.delta));
    }
    if (batch.empty()) continue;
    tracer.refine(batch, guesses, reach);
    for (std::size_t k = 0; k < batch.size(); ++k) guesses[k] = batch[k].c;
    tracer.refine(batch, guesses, reach);

    for (const Crease& start : batch) {
      if (!start.ok) continue;
      if (hash.any_within(start.c, kPairCovered * start.delta, any)) continue;
      const auto id = static_cast<std::uint32_t>(result.size());
      Polyline line;
      line.kind = LineKind::kFeature;
      std::vector<Vec3> forward, backward;
      hash.insert(start.c, id, 0);
      for (int direction : {1, -1}) {
        if (line.closed) break;
        std::vector<Vec3>& pts = direction > 0 ? forward : backward;
        Crease cur = start;
        if (direction < 0) cur.t = -cur.t;
        for (;;) {
          const double h = kCreaseStep * cur.delta;
          const Vec3 prev_t = cur.t;
          one[0] = cur;
          one_guess[0] = cur.c + h * cur.t;
          one_reach[0] = kCreaseJump * h;
          tracer.refine(one, one_guess, one_reach);
          const Crease& next = one[0];
          if (!next.ok || !((next.c - cur.c).dot(cur.t) >= kAdvance * h)) break;
          const auto index = static_cast<std::int32_t>(pts.size() + 1);
          const double to_start = (next.c - start.c).norm();
          if (direction > 0 && index >= kArcMargin && to_start < 0.75 * h) {
            if (to_start >= 0.5 * h && (start.c - next.c).dot(cur.t) > 0) pts.push_back(next.c);
            line.closed = true;
            break;
          }
          const bool forward_dir = direction > 0;
          const bool near_other =
              hash.any_within(next.c, kFeatureNear * next.delta,
                              [id, forward_dir, index](std::uint32_t line_id, std::int32_t at) {
                                if (line_id != id) return true;
                                return !forward_dir && at >= 0 && at + index > kArcMargin;
                              });
          if (near_other) break;
          pts.push_back(next.c);
          hash.insert(next.c, id, direction * index);
          cur = next;
          if (cur.t.dot(prev_t) < 0) cur.t = -cur.t;
          if (pts.size() >= kMaxTracePoints) break;
        }
      }
      line.points.assign(backward.rbegin(), backward.rend());
      line.points.push_back(start.c);
      line.points.insert(line.points.end(), forward.begin(), forward.end());
      if (line.points.size() < 3) line.closed = false;
      if (line.points.size() >= 2) {
        result.push_back(std::move(line));
      } else {
        // A lone crease point: keep it from seeding again, but not as a line.
        result.push_back(Polyline{});
        result.back().kind = LineKind::kFeature;
      }
    }
  }
  result.erase(std::remove_if(result.begin(), result.end(),
                              [](const Polyline& l) { return l.points.size() < 2; }),
               result.end());

  if (stats != nullptr) {
    stats->lines[static_cast<int>(LineKind::kFeature)] += result.size();
    for (const Polyline& line : result)
      stats->length[static_cast<int>(LineKind::kFeature)] += detail::polyline_length(line);
    stats->field_evals += field.evaluations() - evals_start;
    stats->seconds_features +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  }
  return result;
}

}  // namespace ramiform
