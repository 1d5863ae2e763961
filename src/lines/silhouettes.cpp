// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Silhouettes (contour generators, n·v = 0) traced from particles, after Proença, Jorge &
// Costa Sousa 2008, "Suggestive Contours over Point-Set Implicits" (GRAPP), §6: seeds by eq. 9,
// predictor–corrector tracing with steps scaled by δ_i (improvement 1), tracing allowed while
// eq. 10 holds (improvement 2), stops on a closed loop or another silhouette, and the 2-D
// chaining of polylines with close ends and similar directions. The tracer itself follows
// Foster, Jepp, Wyvill, Costa Sousa, Galbraith & Jorge 2005, "Drawing surfaces" (Computers &
// Graphics).
//
// Choices the paper leaves open:
// - Predictor direction: the contour generator is the intersection of f = iso and
//   g(x) = ∇f(x)·(x − eye) = 0 (g = 0 exactly where n·v = 0), so its 3-D tangent is ∇f × ∇g with
//   ∇g = H (x − eye) + ∇f. H (x − eye) is one central difference of ∇f along the view
//   direction (two extra gradients). This is the curve's true tangent everywhere, including
//   where the image contour has a cusp (there the tangent runs along the view ray and the image
//   tangent n × v, the other common choice, points the wrong way by up to 90°). n × v is the
//   fallback where ∇f × ∇g vanishes (a planar region seen edge-on).
// - Corrector: Newton along ∇f onto f = iso together with a Newton step for g = 0 along the
//   tangential part of ∇g (the steepest direction of n·v within the tangent plane). The brief
//   root along w (v projected on the tangent plane) is the same direction where v is a
//   principal direction, but becomes tangent to the contour near cusps, where a root along w is
//   ill-posed; the tangential gradient of g is always transverse to the contour. The central
//   difference is refreshed every third corrector round (quasi-Newton in between).
// - Batching: seeds are corrected in one batch. Seeds are then taken in rounds (by |n·v|, then
//   index); a round holds seeds far apart from each other and from every line traced so far,
//   and its traces advance in lockstep, every corrector round of every trace one batched field
//   evaluation. "Another silhouette is near" is checked trace by trace in a fixed order after
//   each lockstep step, so results do not depend on the thread count. Two traces of one round
//   on the same contour stop where they meet and are joined by the chaining.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <optional>
#include <vector>

#include "lines/line_common.h"
#include "ramiform/lines/camera.h"
#include "ramiform/lines/lines.h"

namespace ramiform {
namespace {

using detail::DeltaLookup;
using detail::LinePointHash;

constexpr int kMaxCorrectorRounds = 8;     ///< corrector rounds per point before it fails
constexpr int kHessianRefresh = 3;         ///< corrector rounds between central differences
constexpr double kHessianStep = 1e-3;      ///< × δ: the central difference's step along v
constexpr double kSeedReach = 4.0;         ///< × δ: farthest a seed may move onto the contour
constexpr double kStepReach = 2.0;         ///< × step: farthest a predicted point may be corrected
constexpr double kGapSeedClearance = 1.5;  ///< × δ: a second-pass seed is this far from lines
constexpr double kRoundSeparation = 16;  ///< × δ: seeds of one round are at least this far apart
constexpr double kMinStepScale = 0.25;   ///< a failed step is halved down to this fraction
constexpr std::size_t kMaxTracePoints = std::size_t{1} << 16;  ///< per direction of one trace
constexpr int kArcMargin = 4;      ///< own points fewer steps away along the trace are not "near"
constexpr double kAdvance = 0.25;  ///< × step: least progress along the tangent of a step
constexpr int kMaxTrim = 3;        ///< overshooting points dropped at most per side of a join
constexpr double kChainCos = 0.70710678118654752;  ///< chained ends: directions within 45°
constexpr double kDegenerate = 1e-9;  ///< relative size below which a direction is unusable

// One point being corrected onto the contour generator.
struct Correction {
  Vec3 q;      // the point (moves)
  Vec3 start;  // where it started
  double delta = 0;
  double reach = 0;        // the point fails when it moves farther than this from start
  Vec3 hv = Vec3::Zero();  // H v̂: the derivative of ∇f along the unit view direction
  Vec3 grad = Vec3::Zero(), grad_g = Vec3::Zero();  // ∇f and ∇g at the final point
  double first_nv = 0;                              // |n·v| where the correction started
  // The correction is given up (kFailed) when first_nv is at least this: a trace step whose
  // predicted point has left the silhouette area (eq. 10) is refused whatever its correction
  // gives, so its rounds would be wasted.
  double give_up_nv = std::numeric_limits<double>::infinity();
  int round = 0;
  enum : std::uint8_t { kRunning, kDone, kFailed } state = kRunning;
};

class Corrector {
 public:
  Corrector(const Field& field, const Camera& camera, const Context* ctx)
      : field_(field), eye_(camera.eye), ctx_(ctx) {}

  // Runs every job to kDone or kFailed; each round one batched evaluation.
  void run(std::vector<Correction>& jobs) {
    active_.clear();
    for (std::uint32_t j = 0; j < jobs.size(); ++j)
      if (jobs[j].state == Correction::kRunning) active_.push_back(j);
    while (!active_.empty()) {
      points_.clear();
      offset_.clear();
      for (const std::uint32_t j : active_) {
        Correction& c = jobs[j];
        offset_.push_back(static_cast<std::uint32_t>(points_.size()));
        points_.push_back(c.q);
        if (c.round % kHessianRefresh == 0) {
          const Vec3 v = (c.q - eye_).normalized();
          const double h = kHessianStep * c.delta;
          points_.push_back(c.q + h * v);
          points_.push_back(c.q - h * v);
        }
      }
      values_.resize(points_.size());
      gradients_.resize(points_.size());
      field_.evaluate(points_, values_, gradients_, ctx_);
      std::size_t kept = 0;
      for (std::size_t k = 0; k < active_.size(); ++k) {
        Correction& c = jobs[active_[k]];
        step(c, offset_[k]);
        if (c.state == Correction::kRunning) active_[kept++] = active_[k];
      }
      active_.resize(kept);
    }
  }

 private:
  void step(Correction& c, std::uint32_t o) {
    const double iso = field_.iso();
    const Vec3 d = c.q - eye_;
    const double dist = d.norm();
    const Vec3 v = d / dist;
    const Vec3 grad = gradients_[o];
    const double gn = grad.norm();
    const double f = values_[o];
    if (!(gn > 0) || !std::isfinite(gn) || !std::isfinite(f) || !(dist > 0)) {
      c.state = Correction::kFailed;
      return;
    }
    if (c.round % kHessianRefresh == 0) {
      c.hv = (gradients_[o + 1] - gradients_[o + 2]) / (2 * kHessianStep * c.delta);
    }
    const Vec3 n = -grad / gn;
    const double nv = n.dot(v);
    if (c.round == 0) {
      c.first_nv = std::abs(nv);
      if (c.first_nv >= c.give_up_nv) {
        c.state = Correction::kFailed;
        return;
      }
    }
    const Vec3 grad_g = dist * c.hv + grad;  // ∇(∇f·(x − eye))
    const double surface = (f - iso) / gn;
    if (std::abs(surface) <= detail::kLineSurfaceTolerance * c.delta &&
        std::abs(nv) <= detail::kLineContourTolerance) {
      c.grad = grad;
      c.grad_g = grad_g;
      c.state = Correction::kDone;
      return;
    }
    if (c.round >= kMaxCorrectorRounds) {
      c.state = Correction::kFailed;
      return;
    }
    // Newton onto f = iso along ∇f, then onto g = 0 along the tangential part of ∇g.
    const Vec3 to_surface = -(f - iso) / (gn * gn) * grad;
    Vec3 u = grad_g - grad_g.dot(n) * n;
    const double un = u.norm();
    if (!(un > kDegenerate * grad_g.norm()) || !std::isfinite(un)) {
      c.state = Correction::kFailed;
      return;
    }
    u /= un;
    const double g = grad.dot(d);
    const double s = -(g + grad_g.dot(to_surface)) / grad_g.dot(u);
    const Vec3 move = to_surface + s * u;
    c.q += move;
    if (!std::isfinite(s) || !((c.q - c.start).norm() <= c.reach)) {
      c.state = Correction::kFailed;
      return;
    }
    ++c.round;
  }

  const Field& field_;
  Vec3 eye_;
  const Context* ctx_;
  std::vector<std::uint32_t> active_, offset_;
  std::vector<Vec3> points_, gradients_;
  std::vector<double> values_;
};

// The unit tangent of the contour generator at a converged point: ∇f × ∇g, else n × v.
Vec3 contour_tangent(const Correction& c, const Vec3& eye) {
  Vec3 t = c.grad.cross(c.grad_g);
  if (t.norm() > kDegenerate * c.grad.norm() * c.grad_g.norm() && t.allFinite())
    return t.normalized();
  t = c.grad.cross(c.q - eye);
  return t.normalized();
}

// One seed's line: the backward points (in travel order), the seed, the forward points.
struct Line {
  Vec3 seed;
  Vec3 seed_tangent;
  double seed_delta = 0;
  std::vector<Vec3> forward, backward;
  bool closed = false;
};

struct Trace {
  std::uint32_t line = 0;
  int direction = 1;  // +1 forward, −1 backward
  Vec3 p, t;          // last accepted point and the unit tangent there (along travel)
  double delta = 0;   // δ at p
  double scale = 1;   // step fraction (halved after a failed step)
  bool finished = false;
};

// Appends `next` to `line` where two traces met: points of either side that overshoot the
// joint (the path would turn back there) and duplicates are left out.
void join(std::vector<Vec3>& line, const std::vector<Vec3>& next) {
  std::size_t skip = 0;
  if (!line.empty()) {
    auto back_overshoots = [&] {
      const std::size_t m = line.size();
      return m >= 2 && (next[skip] - line[m - 1]).dot(line[m - 1] - line[m - 2]) <= 0;
    };
    auto front_overshoots = [&] {
      return skip + 1 < next.size() &&
             (next[skip + 1] - next[skip]).dot(next[skip] - line.back()) <= 0;
    };
    int trimmed = 0;
    for (bool changed = true; changed && trimmed < kMaxTrim; ++trimmed) {
      changed = false;
      if (back_overshoots()) {
        line.pop_back();
        changed = true;
      }
      if (front_overshoots()) {
        ++skip;
        changed = true;
      }
    }
  }
  line.insert(line.end(), next.begin() + static_cast<std::ptrdiff_t>(skip), next.end());
}

// The closing joint of a chained loop, trimmed as in join().
void close_join(std::vector<Vec3>& line) {
  for (int trimmed = 0; trimmed < kMaxTrim && line.size() > 3; ++trimmed) {
    bool changed = false;
    const std::size_t m = line.size();
    if ((line[0] - line[m - 1]).dot(line[m - 1] - line[m - 2]) <= 0) {
      line.pop_back();
      changed = true;
    } else if ((line[1] - line[0]).dot(line[0] - line[m - 1]) <= 0) {
      line.erase(line.begin());
      changed = true;
    }
    if (!changed) break;
  }
}

// Joins polylines whose ends are within chain_distance · δ and run on in similar directions in
// the image (3-D directions where the image direction degenerates). Closes chains whose two
// ends meet. Order: by the first piece of each chain.
std::vector<Polyline> chain(std::vector<Polyline> pieces, const Camera& camera,
                            const DeltaLookup& lookup, double chain_distance) {
  const std::size_t n = pieces.size();
  const CameraFrame frame = camera_frame(camera);
  struct End {
    Vec3 p, dir3;
    double x = 0, y = 0, dx = 0, dy = 0;
    bool image_ok = false;
    double delta = 0;
  };
  auto make_end = [&](const Polyline& line, bool back) {
    const std::size_t m = line.points.size();
    const Vec3& a = back ? line.points[m - 1] : line.points[0];
    const Vec3& b = back ? line.points[m - 2] : line.points[1];
    End e;
    e.p = a;
    e.dir3 = (a - b).normalized();
    const Projected pa = project(camera, frame, a), pb = project(camera, frame, b);
    e.x = pa.x;
    e.y = pa.y;
    e.dx = pa.x - pb.x;
    e.dy = pa.y - pb.y;
    const double len2 = std::hypot(e.dx, e.dy);
    // The image direction is usable when the segment does not run (nearly) along the ray.
    e.image_ok = pa.depth > 0 && pb.depth > 0 && len2 * pa.depth > 0.1 * (a - b).norm();
    if (e.image_ok) {
      e.dx /= len2;
      e.dy /= len2;
    }
    e.delta = lookup.delta_at(a);
    return e;
  };
  std::vector<End> ends(2 * n);
  for (std::size_t k = 0; k < n; ++k) {
    ends[2 * k] = make_end(pieces[k], false);
    ends[2 * k + 1] = make_end(pieces[k], true);
  }
  struct Candidate {
    double d;
    std::uint32_t a, b;
  };
  std::vector<Candidate> candidates;
  if (chain_distance > 0) {
    for (std::uint32_t a = 0; a < 2 * n; ++a) {
      for (std::uint32_t b = a + 1; b < 2 * n; ++b) {
        if (a / 2 == b / 2 && pieces[a / 2].points.size() < 4) continue;
        const End& ea = ends[a];
        const End& eb = ends[b];
        const double d = (ea.p - eb.p).norm();
        if (d > chain_distance * std::max(ea.delta, eb.delta)) continue;
        // The ends continue each other: outward directions opposite.
        const double cos3 = -ea.dir3.dot(eb.dir3);
        const double cos2 = -(ea.dx * eb.dx + ea.dy * eb.dy);
        const bool similar =
            (ea.image_ok && eb.image_ok) ? (cos2 >= kChainCos && cos3 >= 0) : cos3 >= kChainCos;
        if (similar) candidates.push_back({d, a, b});
      }
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& l, const Candidate& r) {
    return l.d != r.d ? l.d < r.d : (l.a != r.a ? l.a < r.a : l.b < r.b);
  });
  // Greedy matching, shortest gaps first; union-find over pieces tells a closing join.
  std::vector<std::int64_t> partner(2 * n, -1);
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<std::uint8_t> closed(n, 0);
  for (const Candidate& c : candidates) {
    if (partner[c.a] >= 0 || partner[c.b] >= 0) continue;
    if (pieces[c.a / 2].closed || pieces[c.b / 2].closed) continue;
    const std::uint32_t ra = find(c.a / 2), rb = find(c.b / 2);
    if (closed[ra] || closed[rb]) continue;
    partner[c.a] = c.b;
    partner[c.b] = c.a;
    if (ra == rb) {
      closed[ra] = 1;
    } else {
      parent[std::max(ra, rb)] = std::min(ra, rb);
    }
  }
  std::vector<Polyline> out;
  std::vector<std::uint8_t> used(n, 0);
  for (std::uint32_t k = 0; k < n; ++k) {
    if (used[k]) continue;
    if (pieces[k].closed) {
      used[k] = 1;
      out.push_back(std::move(pieces[k]));
      continue;
    }
    // The chain's first piece and the end it is entered by: a free end found by walking out
    // of k's front end, or k's front end when the chain is closed.
    const bool is_closed = closed[find(k)] != 0;
    std::uint32_t in = 2 * k;
    if (!is_closed) {
      std::uint32_t e = 2 * k;
      for (std::size_t guard = 0; guard <= n && partner[e] >= 0; ++guard)
        e = static_cast<std::uint32_t>(partner[e]) ^ 1u;
      in = e;
    }
    Polyline line;
    line.kind = LineKind::kSilhouette;
    line.closed = is_closed;
    for (std::size_t guard = 0; guard <= n; ++guard) {
      const std::uint32_t cur = in / 2;
      used[cur] = 1;
      std::vector<Vec3> pts = pieces[cur].points;
      if (in % 2 == 1) std::reverse(pts.begin(), pts.end());
      join(line.points, pts);
      const std::int64_t next = partner[in ^ 1u];
      if (next < 0 || used[static_cast<std::uint32_t>(next) / 2]) break;
      in = static_cast<std::uint32_t>(next);
    }
    if (line.closed) close_join(line.points);
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace

std::vector<Polyline> silhouettes(const Field& field, const ParticleSystem& particles,
                                  const Camera& camera, const LineOptions& options,
                                  LineStats* stats, const Context* ctx,
                                  const ParticleLookup* particle_lookup) {
  const auto clock_start = std::chrono::steady_clock::now();
  validate(camera);
  validate(options);
  const std::uint64_t evals_start = field.evaluations();
  std::vector<Polyline> result;
  if (particles.particles.empty()) return result;
  std::optional<DeltaLookup> own_lookup;
  if (particle_lookup != nullptr) {
    particle_lookup->impl().check(particles);
  } else {
    own_lookup.emplace(particles);
  }
  const DeltaLookup& lookup = own_lookup ? *own_lookup : particle_lookup->impl().delta;
  const Vec3 eye = camera.eye;

  // Seeds (eq. 9), best first.
  std::vector<std::pair<double, std::uint32_t>> seeds;
  for (std::uint32_t i = 0; i < particles.particles.size(); ++i) {
    const SurfaceParticle& p = particles.particles[i];
    const double nv = std::abs(view_vector(camera, p.position).dot(p.normal));
    if (nv < options.k_c) seeds.emplace_back(nv, i);
  }
  std::sort(seeds.begin(), seeds.end());
  if (stats != nullptr) stats->silhouette_seeds += seeds.size();

  // Every seed onto the contour generator, in one batch.
  Corrector corrector(field, camera, ctx);
  std::vector<Correction> jobs(seeds.size());
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const SurfaceParticle& p = particles.particles[seeds[s].second];
    jobs[s].q = jobs[s].start = p.position;
    jobs[s].delta = p.delta;
    jobs[s].reach = kSeedReach * p.delta;
  }
  corrector.run(jobs);
  std::vector<Line> lines;
  std::vector<std::uint32_t> candidates;  // indices into jobs of the corrected seeds
  for (std::uint32_t s = 0; s < jobs.size(); ++s)
    if (jobs[s].state == Correction::kDone) candidates.push_back(s);

  double mean_delta = 0;
  for (const SurfaceParticle& p : particles.particles) mean_delta += p.delta;
  mean_delta /= static_cast<double>(particles.particles.size());
  const double near_factor = std::max(0.5, 0.75 * options.silhouette_step);
  LinePointHash hash(near_factor * mean_delta);

  std::vector<std::uint8_t> consumed(candidates.size(), 0);
  // δ at each candidate, looked up once (a candidate waits through many rounds).
  std::vector<double> candidate_delta(candidates.size(), -1.0);
  std::vector<Trace> traces;
  std::vector<Correction> steps;
  std::vector<std::uint32_t> stepping;
  auto any_line_within = [&](const Vec3& p, double radius) {
    return hash.any_within(p, radius, [](std::uint32_t, std::int32_t) { return true; });
  };
  // Candidates from candidates[first_gap_seed] on are the second pass's (see below).
  std::size_t first_gap_seed = candidates.size();
  bool gap_pass_done = false;
  for (;;) {
    check_cancel(ctx);
    // A round: seeds away from every traced line and from each other.
    traces.clear();
    std::vector<Vec3> picked;
    std::vector<double> picked_delta;
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      if (consumed[k]) continue;
      const Correction& c = jobs[candidates[k]];
      if (candidate_delta[k] < 0) candidate_delta[k] = lookup.delta_at(c.q);
      const double delta = candidate_delta[k];
      const double clearance = k < first_gap_seed ? near_factor : kGapSeedClearance;
      if (any_line_within(c.q, clearance * delta)) {
        consumed[k] = 1;
        continue;
      }
      bool crowded = false;
      for (std::size_t r = 0; r < picked.size() && !crowded; ++r) {
        crowded = (picked[r] - c.q).norm() < kRoundSeparation * std::max(delta, picked_delta[r]);
      }
      if (crowded) continue;
      consumed[k] = 1;
      picked.push_back(c.q);
      picked_delta.push_back(delta);
      Line line;
      line.seed = c.q;
      line.seed_tangent = contour_tangent(c, eye);
      line.seed_delta = delta;
      const auto id = static_cast<std::uint32_t>(lines.size());
      lines.push_back(std::move(line));
      hash.insert(c.q, id, 0);
      Trace t;
      t.line = id;
      t.p = c.q;
      t.t = lines[id].seed_tangent;
      t.delta = delta;
      traces.push_back(t);
    }
    if (traces.empty() && !gap_pass_done) {
      // Second pass (gaps): where the rim is bumpy the contour generator turns sharply, traces
      // stop there by eq. 10, and a piece of it that no eq. 9 seed lies near is missed. Particles
      // of the wider tracing band k_c ≤ |v·n| < k_c·k_e away from every traced line are
      // corrected onto the contour; those that land farther than kGapSeedClearance·δ from every
      // line seed further rounds, traced and chained like the first ones. On the scans this
      // costs 0.5–15 % more field evaluations (bench/line_gaps.cpp).
      gap_pass_done = true;
      const std::size_t first_job = jobs.size();
      for (std::uint32_t i = 0; i < particles.particles.size(); ++i) {
        const SurfaceParticle& p = particles.particles[i];
        const double nv = std::abs(view_vector(camera, p.position).dot(p.normal));
        if (nv < options.k_c || nv >= options.k_c * options.k_e) continue;
        if (any_line_within(p.position, kGapSeedClearance * p.delta)) continue;
        Correction c;
        c.q = c.start = p.position;
        c.delta = p.delta;
        c.reach = kSeedReach * p.delta;
        jobs.push_back(c);
      }
      if (jobs.size() == first_job) break;
      std::vector<Correction> extra(jobs.begin() + static_cast<std::ptrdiff_t>(first_job),
                                    jobs.end());
      corrector.run(extra);
      std::copy(extra.begin(), extra.end(), jobs.begin() + static_cast<std::ptrdiff_t>(first_job));
      first_gap_seed = candidates.size();
      std::vector<std::uint32_t> added;
      for (auto s = static_cast<std::uint32_t>(first_job); s < jobs.size(); ++s)
        if (jobs[s].state == Correction::kDone) added.push_back(s);
      // Best first, as in the first pass: by |v·n| where the correction started, then index.
      std::stable_sort(added.begin(), added.end(), [&](std::uint32_t a, std::uint32_t b) {
        return jobs[a].first_nv < jobs[b].first_nv;
      });
      candidates.insert(candidates.end(), added.begin(), added.end());
      consumed.resize(candidates.size(), 0);
      candidate_delta.resize(candidates.size(), -1.0);
      continue;
    }
    if (traces.empty()) break;

    // Lockstep tracing of the round.
    for (;;) {
      check_cancel(ctx);
      steps.clear();
      stepping.clear();
      for (std::uint32_t k = 0; k < traces.size(); ++k) {
        const Trace& t = traces[k];
        if (t.finished) continue;
        const double h = t.scale * options.silhouette_step * t.delta;
        Correction c;
        c.start = t.p;
        c.q = t.p + h * t.t;
        c.delta = t.delta;
        c.reach = kStepReach * h;
        c.give_up_nv = options.k_c * options.k_e;
        steps.push_back(c);
        stepping.push_back(k);
      }
      if (steps.empty()) break;
      corrector.run(steps);
      for (std::size_t s = 0; s < steps.size(); ++s) {
        Trace& t = traces[stepping[s]];
        Line& line = lines[t.line];
        std::vector<Vec3>& pts = t.direction > 0 ? line.forward : line.backward;
        const Correction& c = steps[s];
        const double h = t.scale * options.silhouette_step * t.delta;
        bool finish = false;
        const bool advanced = c.state == Correction::kDone && (c.q - t.p).dot(t.t) >= kAdvance * h;
        if (!advanced || c.first_nv >= options.k_c * options.k_e) {
          // Failed correction, no progress along the line, or left the silhouette area
          // (eq. 10): shorter steps, then stop.
          if (t.scale > kMinStepScale) {
            t.scale *= 0.5;
          } else {
            finish = true;
          }
        } else {
          const auto index = static_cast<std::int32_t>(pts.size() + 1);
          const double to_seed = (c.q - line.seed).norm();
          if (t.direction > 0 && index >= kArcMargin && to_seed < 0.75 * h) {
            // Back at the seed: a closed loop.
            // Keep the point unless it is very near the seed or past it.
            if (to_seed >= 0.5 * h && (line.seed - c.q).dot(t.t) > 0) pts.push_back(c.q);
            line.closed = true;
            finish = true;
          } else {
            const std::uint32_t own = t.line;
            const std::int32_t here = t.direction * index;  // position along the line
            const double delta_here = lookup.delta_at(c.q);
            const double radius = near_factor * delta_here;
            const bool near_other =
                hash.any_within(c.q, radius, [own, here](std::uint32_t line_id, std::int32_t at) {
                  if (line_id != own) return true;
                  // Own points more than kArcMargin steps away along the line: the trace came
                  // back onto itself (a loop that missed the seed's closing test, or the
                  // backward trace meeting the forward one); without this a trace can circle
                  // a loop until kMaxTracePoints.
                  return std::abs(here - at) > kArcMargin;
                });
            pts.push_back(c.q);
            hash.insert(c.q, t.line, t.direction * index);
            Vec3 tangent = contour_tangent(c, eye);
            if (tangent.dot(t.t) < 0) tangent = -tangent;
            t.p = c.q;
            t.t = tangent;
            t.delta = delta_here;
            t.scale = std::min(1.0, 2 * t.scale);
            finish = near_other || pts.size() >= kMaxTracePoints;
          }
        }
        if (finish) {
          if (t.direction > 0 && !line.closed) {
            // Now the other way from the seed.
            t.direction = -1;
            t.p = line.seed;
            t.t = -line.seed_tangent;
            t.delta = line.seed_delta;
            t.scale = 1;
          } else {
            t.finished = true;
          }
        }
      }
    }
  }

  std::vector<Polyline> pieces;
  for (Line& line : lines) {
    Polyline p;
    p.kind = LineKind::kSilhouette;
    p.closed = line.closed;
    p.points.reserve(line.backward.size() + 1 + line.forward.size());
    p.points.assign(line.backward.rbegin(), line.backward.rend());
    p.points.push_back(line.seed);
    p.points.insert(p.points.end(), line.forward.begin(), line.forward.end());
    if (p.points.size() < 3) p.closed = false;
    if (p.points.size() >= 2) pieces.push_back(std::move(p));
  }
  result = chain(std::move(pieces), camera, lookup, options.chain_distance);

  if (stats != nullptr) {
    stats->lines[static_cast<int>(LineKind::kSilhouette)] += result.size();
    for (const Polyline& line : result)
      stats->length[static_cast<int>(LineKind::kSilhouette)] += detail::polyline_length(line);
    stats->field_evals += field.evaluations() - evals_start;
    stats->seconds_silhouettes +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  }
  return result;
}

}  // namespace ramiform
