// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// Feature lines (creases) traced from straddle particle pairs, after Proença, Jorge & Costa
// Sousa 2008, "Suggestive Contours over Point-Set Implicits" (GRAPP), §6: straddle points by
// eq. 11, from the before/after-movement test of Foster, Jepp, Wyvill, Costa Sousa, Galbraith &
// Jorge 2005, "Drawing surfaces" (Computers & Graphics) on the particles' seeding state, and by
// the neighbourhood search (their improvement 3) when that fails, then moved along the two
// faces parallel to the feature with steps scaled by δ_i (improvement 4), the crease points
// estimated between them, until eq. 11 fails or another feature line is near; then the pieces
// of one crease are chained (as §6 chains silhouettes, here in 3-D).
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
// - Movement pairs (seeding and final position of one particle) can lie farther apart than the
//   search radius; the crease point may then be found anywhere between them.
// - A trace stops at a corner (the crease turns by more than kCornerTurn in one step), so that
//   a line is one crease; pieces are joined only end to end in the same direction.
// - Search: each particle contributes its best partner (largest normal angle) as a candidate; the
//   candidates, strongest first, are verified in batches (one field evaluation per Newton
//   round for the whole batch) and traced one at a time, skipping those already on a line.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "lines/line_common.h"
#include "ramiform/core/errors.h"
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
constexpr int kArcMargin = 4;        ///< own points fewer steps away along the trace are not "near"
constexpr double kAdvance = 0.25;    ///< × step: least progress along the crease of a step
constexpr double kCornerTurn = 40;   ///< degrees: a trace stops where it would turn more in a step
constexpr double kChainAngle = 30;   ///< degrees: most turn between two lines joined end to end
constexpr double kChainSide = 0.25;  ///< × δ: most sideways offset of a joined gap
constexpr double kChainBack = 0.5;   ///< × δ: most overlap of two joined ends
constexpr double kChainDrop = 0.05;  ///< × δ: least progress of a point kept at a join

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

// A straddle pair: two surface points (a particle's seeding and final states, or two
// particles) with their unit normals, strongest (largest angle) first.
struct Candidate {
  double angle = 0;
  std::uint32_t i = 0, j = 0;  // particles (movement: i == j)
  Vec3 a = Vec3::Zero(), na = Vec3::Zero(), b = Vec3::Zero(), nb = Vec3::Zero();
  double delta_min = 0, delta_max = 0;
};

bool stronger(const Candidate& l, const Candidate& r) {
  if (l.angle != r.angle) return l.angle > r.angle;
  return l.i != r.i ? l.i < r.i : l.j < r.j;
}

// True when a particle of `near` (other than i and j) lies between a and b (within half their
// distance of their midpoint) with a normal turned by more than kIntermediate of the pair's
// angle from both of theirs: the normal turns gradually there, as on a smooth surface, where a
// crease would give every particle the normal of one face or the other. Saves verifying the
// many straddle pairs of coarsely sampled smooth surfaces.
bool intermediate_normal(const std::vector<SurfaceParticle>& ps,
                         const std::vector<std::pair<std::uint32_t, double>>& near,
                         const Candidate& c) {
  const Vec3 mid = 0.5 * (c.a + c.b);
  const double r2 = 0.25 * (c.a - c.b).squaredNorm();
  const double cos_limit = std::cos(kIntermediate * c.angle);
  for (const auto& [k, d2] : near) {
    if (k == c.i || k == c.j || (ps[k].position - mid).squaredNorm() >= r2) continue;
    const Vec3& n = ps[k].normal;
    if (std::max(n.dot(c.na), n.dot(c.nb)) < cos_limit) return true;
  }
  return false;
}

struct Found {
  std::size_t pairs = 0;
  std::vector<Candidate> best;
};

Found fold(Found acc, Found part) {
  acc.pairs += part.pairs;
  acc.best.insert(acc.best.end(), part.best.begin(), part.best.end());
  return acc;
}

void sort_unique(std::vector<Candidate>& cs) {
  std::sort(cs.begin(), cs.end(), stronger);
  cs.erase(
      std::unique(cs.begin(), cs.end(),
                  [](const Candidate& l, const Candidate& r) { return l.i == r.i && l.j == r.j; }),
      cs.end());
}

// Foster et al.'s test (eq. 11 on one particle): a particle whose normal turned by more than
// k_a between its seeding and the end of the simulation crossed a crease; its seeding and
// final positions straddle it.
Found movement_pairs(const ParticleSystem& particles, const DeltaLookup& lookup, double cos_k_a,
                     const Context* ctx) {
  const std::vector<SurfaceParticle>& ps = particles.particles;
  Found found = parallel::reduce(
      ps.size(), 256, Found{},
      [&](std::size_t lo, std::size_t hi) {
        Found part;
        std::vector<std::pair<std::uint32_t, double>> near;
        for (std::size_t i = lo; i < hi; ++i) {
          const Vec3& n0 = particles.seed_normals[i];
          if (!(n0.dot(ps[i].normal) < cos_k_a)) continue;
          ++part.pairs;
          Candidate c;
          c.i = c.j = static_cast<std::uint32_t>(i);
          c.a = particles.seed_positions[i];
          c.na = n0;
          c.b = ps[i].position;
          c.nb = ps[i].normal;
          c.angle = detail::angle_between(c.na, c.nb);
          c.delta_min = c.delta_max = ps[i].delta;
          const Vec3 mid = 0.5 * (c.a + c.b);
          lookup.tree().within_by_index(mid, 0.5 * (c.a - c.b).norm() + 1e-12 * ps[i].delta, near);
          if (!intermediate_normal(ps, near, c)) part.best.push_back(c);
        }
        return part;
      },
      fold, ctx);
  sort_unique(found.best);
  return found;
}

// The paper's improvement 3: each particle's best partner (largest angle) within
// straddle_radius·δ as a candidate, and the number of distinct pairs (a pair seen from both of
// its particles is counted from the lower index only).
Found search_pairs(const ParticleSystem& particles, const DeltaLookup& lookup, double r,
                   double cos_k_a, const Context* ctx) {
  const std::vector<SurfaceParticle>& ps = particles.particles;
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
            Candidate c;
            c.i = std::min(ii, best_j);
            c.j = std::max(ii, best_j);
            c.a = ps[c.i].position;
            c.na = ps[c.i].normal;
            c.b = ps[c.j].position;
            c.nb = ps[c.j].normal;
            c.angle = detail::angle_between(c.na, c.nb);
            c.delta_min = std::min(ps[c.i].delta, ps[c.j].delta);
            c.delta_max = std::max(ps[c.i].delta, ps[c.j].delta);
            if (!intermediate_normal(ps, near, c)) part.best.push_back(c);
          }
        }
        return part;
      },
      fold, ctx);
  sort_unique(found.best);
  return found;
}

// Verifies the candidates (strongest first) in batches and traces each crease from the ones
// not yet near a line, appending to `result` (a lone crease point appends an empty polyline,
// which keeps it from seeding again; the caller removes them).
class FeatureTracer {
 public:
  FeatureTracer(const Field& field, const DeltaLookup& lookup, double k_a, double mean_delta,
                double fine_delta, double straddle_radius, const Context* ctx)
      : tracer_(field, lookup, k_a, ctx),
        hash_(kPairCovered * mean_delta),
        fine_delta_(fine_delta),
        straddle_radius_(straddle_radius),
        ctx_(ctx) {}

  void trace(const std::vector<Candidate>& candidates, std::vector<Polyline>& result) {
    auto any = [](std::uint32_t, std::int32_t) { return true; };
    for (std::size_t begin = 0; begin < candidates.size(); begin += kBatch) {
      check_cancel(ctx_);
      const std::size_t end = std::min(candidates.size(), begin + kBatch);
      // Verify the batch's uncovered candidates together.
      batch_.clear();
      guesses_.clear();
      reach_.clear();
      for (std::size_t k = begin; k < end; ++k) {
        const Candidate& cand = candidates[k];
        const Vec3 mid = 0.5 * (cand.a + cand.b);
        if (hash_.any_within(mid, kPairCovered * cand.delta_min, any)) continue;
        Crease c;
        c.a = cand.a;
        c.na = cand.na;
        c.b = cand.b;
        c.nb = cand.nb;
        c.delta = cand.delta_min;
        c.c = mid;
        batch_.push_back(c);
        guesses_.push_back(mid);
        // A particle may have moved farther than the search radius: the crease lies between.
        reach_.push_back(std::max(straddle_radius_ * cand.delta_max, (cand.a - cand.b).norm()));
      }
      if (batch_.empty()) continue;
      tracer_.refine(batch_, guesses_, reach_);
      for (std::size_t k = 0; k < batch_.size(); ++k) guesses_[k] = batch_[k].c;
      tracer_.refine(batch_, guesses_, reach_);
      for (const Crease& start : batch_) {
        if (!start.ok) continue;
        if (hash_.any_within(start.c, kPairCovered * start.delta, any)) continue;
        trace_one(start, result);
      }
    }
  }

 private:
  void trace_one(const Crease& start, std::vector<Polyline>& result) {
    const auto id = static_cast<std::uint32_t>(result.size());
    Polyline line;
    line.kind = LineKind::kFeature;
    std::vector<Vec3> forward, backward;
    hash_.insert(start.c, id, 0);
    for (int direction : {1, -1}) {
      if (line.closed) break;
      std::vector<Vec3>& pts = direction > 0 ? forward : backward;
      Crease cur = start;
      if (direction < 0) cur.t = -cur.t;
      Vec3 heading = cur.t;  // the direction of the last step (at first the crease's)
      for (;;) {
        const double h = kCreaseStep * cur.delta;
        const Vec3 prev_t = cur.t;
        one_[0] = cur;
        one_guess_[0] = cur.c + h * cur.t;
        one_reach_[0] = kCreaseJump * h;
        tracer_.refine(one_, one_guess_, one_reach_);
        const Crease& next = one_[0];
        if (!next.ok || !((next.c - cur.c).dot(cur.t) >= kAdvance * h)) break;
        // A corner: the crease turns by more than kCornerTurn within one step (where three
        // faces meet the trace would go on along another crease).
        const Vec3 step = (next.c - cur.c).normalized();
        if (!(step.dot(heading) >= cos_corner_)) break;
        const auto index = static_cast<std::int32_t>(pts.size() + 1);
        const double to_start = (next.c - start.c).norm();
        if (direction > 0 && index >= kArcMargin && to_start < 0.75 * h) {
          if (to_start >= 0.5 * h && (start.c - next.c).dot(cur.t) > 0) pts.push_back(next.c);
          line.closed = true;
          break;
        }
        const bool forward_dir = direction > 0;
        auto other = [id, forward_dir, index](std::uint32_t line_id, std::int32_t at) {
          if (line_id != id) return true;
          return !forward_dir && at >= 0 && at + index > kArcMargin;
        };
        // The step may be long (δ of a coarse particle): it is tested, and enters the hash, at
        // points no farther apart than half the finest δ, so that "near a line" means near its
        // segments: a step does not jump over a line of finer particles, and a candidate of
        // fine particles between two far points of a line is seen as covered.
        const double length = (next.c - cur.c).norm();
        const int pieces = std::max(1, static_cast<int>(std::ceil(length / (0.5 * fine_delta_))));
        bool near_other = false;
        for (int k = 1; k <= pieces && !near_other; ++k) {
          const Vec3 q = cur.c + (static_cast<double>(k) / pieces) * (next.c - cur.c);
          near_other = hash_.any_within(q, kFeatureNear * next.delta, other);
        }
        if (near_other) break;
        pts.push_back(next.c);
        for (int k = 1; k <= pieces; ++k) {
          hash_.insert(cur.c + (static_cast<double>(k) / pieces) * (next.c - cur.c), id,
                       direction * index);
        }
        cur = next;
        heading = step;
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

  CreaseTracer tracer_;
  LinePointHash hash_;
  double fine_delta_;  // the smallest δ of the particles
  double cos_corner_ = std::cos(kCornerTurn * std::numbers::pi / 180);
  double straddle_radius_;
  const Context* ctx_;
  std::vector<Crease> batch_, one_ = std::vector<Crease>(1);
  std::vector<Vec3> guesses_, one_guess_ = std::vector<Vec3>(1);
  std::vector<double> reach_, one_reach_ = std::vector<double>(1);
};

// Unit direction in which an open line leaves through its end `side` (0: front, 1: back).
Vec3 outward(const Polyline& l, int side) {
  const std::size_t n = l.points.size();
  const Vec3 d =
      side == 0 ? Vec3(l.points[0] - l.points[1]) : Vec3(l.points[n - 1] - l.points[n - 2]);
  return d.normalized();
}

// Joins feature lines whose ends meet (§6's chaining, in 3-D): two ends within
// chain_distance·δ whose lines run on in the same direction (within kChainAngle), the gap
// along that direction (sideways at most kChainSide·δ, backwards at most kChainBack·δ). Pairs
// are taken nearest first, each end once; a pair that joins the two ends of one chain closes
// it. Lines never turn a corner: where three creases meet none continues another.
std::vector<Polyline> chain_features(std::vector<Polyline> lines, const DeltaLookup& lookup,
                                     double chain_distance) {
  std::vector<Vec3> ends;          // the ends of the open lines
  std::vector<std::uint32_t> end;  // their ids: 2 line + side
  for (std::size_t l = 0; l < lines.size(); ++l) {
    if (lines[l].closed) continue;
    for (int side : {0, 1}) {
      ends.push_back(side == 0 ? lines[l].points.front() : lines[l].points.back());
      end.push_back(static_cast<std::uint32_t>(2 * l + static_cast<std::size_t>(side)));
    }
  }
  if (ends.empty() || !(chain_distance > 0)) return lines;
  struct Join {
    double gap;
    std::uint32_t e, f;  // end ids, e < f
  };
  std::vector<Join> joins;
  const detail::PointKdTree tree(ends);
  const double cos_angle = std::cos(kChainAngle * std::numbers::pi / 180);
  std::vector<std::pair<std::uint32_t, double>> near;
  for (std::size_t k = 0; k < ends.size(); ++k) {
    const Polyline& la = lines[end[k] / 2];
    const Vec3 ua = outward(la, static_cast<int>(end[k] % 2));
    const double da = lookup.delta_at(ends[k]);
    tree.within_by_index(ends[k], chain_distance * da, near);
    for (const auto& [q, d2] : near) {
      if (q <= k) continue;
      const Polyline& lb = lines[end[q] / 2];
      const Vec3 ub = outward(lb, static_cast<int>(end[q] % 2));
      const double delta = std::min(da, lookup.delta_at(ends[q]));
      const Vec3 g = ends[q] - ends[k];
      if (!(g.norm() <= chain_distance * delta) || !(-ua.dot(ub) >= cos_angle)) continue;
      const Vec3 m = (ua - ub).normalized();
      const double along = g.dot(m);
      if (!(along >= -kChainBack * delta) || !((g - along * m).norm() <= kChainSide * delta)) {
        continue;
      }
      joins.push_back({g.norm(), std::min(end[k], end[q]), std::max(end[k], end[q])});
    }
  }
  if (joins.empty()) return lines;
  std::sort(joins.begin(), joins.end(), [](const Join& l, const Join& r) {
    if (l.gap != r.gap) return l.gap < r.gap;
    return l.e != r.e ? l.e < r.e : l.f < r.f;
  });
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> partner(2 * lines.size(), kNone);
  for (const Join& j : joins) {
    if (partner[j.e] != kNone || partner[j.f] != kNone) continue;
    // Each chain has exactly two free ends, so joining two free ends of one chain closes it.
    partner[j.e] = j.f;
    partner[j.f] = j.e;
  }

  std::vector<Polyline> out;
  std::vector<std::uint8_t> used(lines.size(), 0);
  for (std::size_t first = 0; first < lines.size(); ++first) {
    if (used[first]) continue;
    if (lines[first].closed) {
      used[first] = 1;
      out.push_back(std::move(lines[first]));
      continue;
    }
    // Walk back from `first` through its front end to the chain's free end (or round a loop).
    auto l = static_cast<std::uint32_t>(first);
    std::uint32_t in_side = 1;  // the side we entered l through: walking out through the front
    bool loop = false;
    for (std::size_t steps = 0; steps <= lines.size(); ++steps) {
      const std::uint32_t out_end = 2 * l + (1 - in_side);
      if (partner[out_end] == kNone) break;
      l = partner[out_end] / 2;
      in_side = partner[out_end] % 2;
      if (l == first) {
        loop = true;
        break;
      }
    }
    // The chain starts at l, through its end (1 - in_side), unless it is a loop.
    std::uint32_t start_side = loop ? 0 : 1 - in_side;
    if (loop) l = static_cast<std::uint32_t>(first);
    Polyline joined;
    joined.kind = LineKind::kFeature;
    const std::uint32_t start = l;
    for (;;) {
      used[l] = 1;
      std::vector<Vec3>& pts = lines[l].points;
      if (start_side == 1) std::reverse(pts.begin(), pts.end());
      std::size_t skip = 0;
      if (!joined.points.empty()) {
        // Points of the next line that do not get past the last one (the traces overlap).
        const std::size_t n = joined.points.size();
        const Vec3& last = joined.points[n - 1];
        const Vec3 u = n >= 2 ? Vec3((last - joined.points[n - 2]).normalized()) : Vec3::Zero();
        const double tiny = kChainDrop * lookup.delta_at(last);
        while (skip < pts.size() && n >= 2 && (pts[skip] - last).dot(u) < tiny) ++skip;
      }
      joined.points.insert(joined.points.end(), pts.begin() + static_cast<std::ptrdiff_t>(skip),
                           pts.end());
      const std::uint32_t exit = 2 * l + (1 - start_side);
      if (partner[exit] == kNone) break;
      const std::uint32_t next = partner[exit] / 2;
      if (next == start && loop) break;
      start_side = partner[exit] % 2;
      l = next;
    }
    if (loop) {
      // Drop closing points that do not get short of the first one.
      while (joined.points.size() > 3) {
        const std::size_t n = joined.points.size();
        const Vec3 u = (joined.points[n - 1] - joined.points[n - 2]).normalized();
        if ((joined.points.front() - joined.points[n - 1]).dot(u) >=
            kChainDrop * lookup.delta_at(joined.points[n - 1]))
          break;
        joined.points.pop_back();
      }
      joined.closed = joined.points.size() >= 3;
    }
    if (joined.points.size() >= 2) out.push_back(std::move(joined));
  }
  return out;
}

}  // namespace

std::vector<Polyline> feature_lines(const Field& field, const ParticleSystem& particles,
                                    const LineOptions& options, LineStats* stats,
                                    const Context* ctx) {
  const auto clock_start = std::chrono::steady_clock::now();
  validate(options);
  const bool seeded = has_seed_state(particles);
  if (options.straddle == StraddleSource::kMovement && !seeded && !particles.particles.empty()) {
    throw InvalidArgument(
        "feature lines: straddle 'movement' needs the particles' seeding state (particles "
        "spread by this version, or a state file with seed positions and normals)");
  }
  const std::uint64_t evals_start = field.evaluations();
  std::vector<Polyline> result;
  if (particles.particles.empty()) return result;
  const DeltaLookup lookup(particles);
  const std::vector<SurfaceParticle>& ps = particles.particles;
  const double k_a = options.k_a_deg * std::numbers::pi / 180;
  const double cos_k_a = std::cos(k_a);
  double mean_delta = 0, fine_delta = ps[0].delta;
  for (const SurfaceParticle& p : ps) {
    mean_delta += p.delta;
    fine_delta = std::min(fine_delta, p.delta);
  }
  mean_delta /= static_cast<double>(ps.size());

  FeatureTracer tracer(field, lookup, k_a, mean_delta, fine_delta, options.straddle_radius, ctx);
  std::size_t movement = 0, search = 0;
  bool use_search = options.straddle == StraddleSource::kSearch;
  if (options.straddle != StraddleSource::kSearch && seeded) {
    const Found found = movement_pairs(particles, lookup, cos_k_a, ctx);
    movement = found.pairs;
    tracer.trace(found.best, result);
    // "Which we apply when the Foster et al. method fails" (§6): no line from it.
    if (options.straddle == StraddleSource::kAuto) {
      use_search = std::none_of(result.begin(), result.end(),
                                [](const Polyline& l) { return l.points.size() >= 2; });
    }
  } else if (options.straddle == StraddleSource::kAuto) {
    use_search = true;
  }
  if (use_search) {
    const Found found = search_pairs(particles, lookup, options.straddle_radius, cos_k_a, ctx);
    search = found.pairs;
    tracer.trace(found.best, result);
  }
  result.erase(std::remove_if(result.begin(), result.end(),
                              [](const Polyline& l) { return l.points.size() < 2; }),
               result.end());
  result = chain_features(std::move(result), lookup, options.chain_distance);

  if (stats != nullptr) {
    stats->straddle_pairs += movement + search;
    stats->straddle_pairs_movement += movement;
    stats->straddle_pairs_search += search;
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
