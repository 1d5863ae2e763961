// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/polygonize/improve.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "field/bvh.h"
#include "polygonize/in_tetrahedron.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"
#include "ramiform/mesh/deviation.h"

namespace ramiform {
namespace {

using detail::in_tetrahedron;

using Tri = std::array<std::uint32_t, 3>;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kGrain = 16384;  // triangles per chunk of the scans over the whole mesh
constexpr std::size_t kOpGrain = 64;   // bad triangles per chunk of the operations' evaluation
// Request-and-evaluate stages per round: flips and the collapses into an end point need one
// (midpoints), a collapse into the projected midpoint two (the point, then its edges), and a
// relaxation, tried only when no flip or collapse does, two more; the nudge, last, two more.
// The small move, last, needs no field data but local radii.
constexpr int kStages = 13;
// Newton steps onto the surface, as refine_to_surface() takes them: a step below kNewtonStop
// local radii leaves a distance of the order of its square, far below any tolerance.
constexpr int kNewtonSteps = 8;
constexpr double kNewtonStop = 3e-3;
// Below this smallest angle (degrees) a triangle may be replaced by triangles that turn as far
// from the surface as the worst of those they replace (see Improver::follows): no triangle
// must stay below 1 degree.
constexpr double kHardAngleDeg = 1.5;
// How much farther than an old edge beyond the tolerance a new edge may be, at most, as a
// fraction of the tolerance (see Improver::try_replace).
constexpr double kSlack = 0.1;
// The field is evaluated in groups of kGroup points close along a Morton curve, kGroupGrain
// groups per task (see Improver::evaluate_field).
constexpr std::size_t kGroup = 16;
constexpr std::size_t kGroupGrain = 64;
// A new edge from a vertex taken onto the surface shorter than this many local radii needs no
// test of its midpoint (as refine_to_surface()'s min_edge_radii: it sags by less than 1/128 of
// a radius).
constexpr double kShortEdge = 0.25;
// The nudge (see Move::kNudge): its steps, in multiples of the bad triangle's longest edge times
// sin(kHardAngleDeg) (about what opens a needle's angle to kHardAngleDeg) and of its shortest
// edge, and the directions tried in the tangent plane (four more: along the normal and along
// the shortest edge, both ways).
constexpr std::array<double, 4> kNudgeSteps = {0.5, 1.0, 2.0, 4.0};
constexpr int kNudgeDirections = 12;
// The directions of a corner move (Improver::move_directions()).
using MoveDirections = std::array<Vec3, kNudgeDirections + 4>;
// A cluster: vertices joined by edges shorter than this times the bad triangle's longest edge.
constexpr double kClusterEdge = 0.2;
// The small move (see Move::kSmallMove): for a triangle below kLastResortDeg that nothing else
// mends, its vertices may move by at most kSmallMove times the tolerance in local radii (so
// the mesh moves by no more than that anywhere), in steps of kSmallSteps times that bound.
constexpr double kLastResortDeg = 1.0;
constexpr double kSmallMove = 0.5;
constexpr std::array<double, 3> kSmallSteps = {0.25, 0.5, 1.0};
constexpr int kLastRounds = 2;

void validate(const ImproveOptions& o) {
  if (!(o.tolerance > 0.0) || !std::isfinite(o.tolerance)) {
    throw InvalidArgument("improve: tolerance must be finite and > 0, got " +
                          format_number(o.tolerance));
  }
  if (!(o.min_angle_deg > 0.0 && o.min_angle_deg < 60.0)) {
    throw InvalidArgument("improve: min_angle_deg must be in (0, 60), got " +
                          format_number(o.min_angle_deg));
  }
  if (!(o.max_turn_deg > 0.0 && o.max_turn_deg <= 90.0)) {
    throw InvalidArgument("improve: max_turn_deg must be in (0, 90], got " +
                          format_number(o.max_turn_deg));
  }
  if (o.max_rounds < 0) {
    throw InvalidArgument("improve: max_rounds must be >= 0, got " + std::to_string(o.max_rounds));
  }
}

// The sine of the smallest corner angle of the triangle a, b, c (the corner opposite the
// shortest edge, at most 60 degrees, where the sine increases with the angle); 0 when
// degenerate.
double min_angle_sine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, bc = c - b, ca = a - c;
  const double lab = ab.squaredNorm(), lbc = bc.squaredNorm(), lca = ca.squaredNorm();
  const double cross = ab.cross(-ca).norm();
  if (!(cross > tol::kCoincident * std::max({lab, lbc, lca}))) return 0.0;
  if (lbc <= lab && lbc <= lca) return cross / std::sqrt(lab * lca);  // at a
  if (lca <= lab) return cross / std::sqrt(lab * lbc);                // at b
  return cross / std::sqrt(lbc * lca);                                // at c
}

// Counts over a mesh (its triangles with alive[t] != 0, all without `alive`): triangles under
// 10 and 1 degrees, the smallest angle (as a sine), and the triangles whose smallest angle has a
// sine under sin_bad, in index order.
struct Scan {
  std::size_t below_10 = 0, below_1 = 0;
  double min_sine = 1.0;
  std::vector<std::uint32_t> bad;
};
// `sines` (may be null) receives every triangle's sine, one per triangle.
Scan scan(const TriMesh& mesh, const std::vector<char>* alive, double sin_bad, const Context* ctx,
          std::vector<double>* sines) {
  if (sines != nullptr) sines->assign(mesh.triangles.size(), 0.0);
  const double s10 = pm::sin(10 * kDeg), s1 = pm::sin(1 * kDeg);
  const std::size_t n = mesh.triangles.size();
  std::vector<Scan> parts((n + kGrain - 1) / kGrain);
  parallel::for_chunks(
      n, kGrain,
      [&](std::size_t b, std::size_t e) {
        Scan& p = parts[b / kGrain];
        for (std::size_t t = b; t < e; ++t) {
          if (alive != nullptr && (*alive)[t] == 0) continue;
          const auto& f = mesh.triangles[t];
          const double s =
              min_angle_sine(mesh.positions[f[0]], mesh.positions[f[1]], mesh.positions[f[2]]);
          if (sines != nullptr) (*sines)[t] = s;
          p.below_10 += s < s10 ? 1 : 0;
          p.below_1 += s < s1 ? 1 : 0;
          p.min_sine = std::min(p.min_sine, s);
          if (s < sin_bad) p.bad.push_back(static_cast<std::uint32_t>(t));
        }
      },
      ctx);
  Scan all;
  for (const Scan& p : parts) {
    all.below_10 += p.below_10;
    all.below_1 += p.below_1;
    all.min_sine = std::min(all.min_sine, p.min_sine);
    all.bad.insert(all.bad.end(), p.bad.begin(), p.bad.end());
  }
  if (n == 0) all.min_sine = 0;
  return all;
}

// Field data is cached by the exact bits of the point it was computed at: vertices never move
// (a vertex that moves becomes a new vertex), so a midpoint or a Newton start computed twice
// from the same end points has the same bits.
struct PointKey {
  std::array<std::uint64_t, 3> bits;
  bool operator==(const PointKey& o) const {
    return ((bits[0] ^ o.bits[0]) | (bits[1] ^ o.bits[1]) | (bits[2] ^ o.bits[2])) == 0;
  }
};
PointKey key_of(const Vec3& p) {
  return {{std::bit_cast<std::uint64_t>(p.x()), std::bit_cast<std::uint64_t>(p.y()),
           std::bit_cast<std::uint64_t>(p.z())}};
}
std::uint64_t hash_of(const PointKey& k) {
  std::uint64_t h = k.bits[0] * 0x9E3779B97F4A7C15ull;
  h = (h ^ (h >> 29) ^ k.bits[1]) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 31) ^ k.bits[2]) * 0x94D049BB133111EBull;
  return h ^ (h >> 32);
}

// The field data per point: an open-addressing table (linear probing, power-of-two size, at
// most half full) of 8-byte slots, a tag of the point's hash and the index of its entry (the
// point and its value, in the order they were made). A lookup reads one slot and one entry;
// the node-based std::unordered_map it replaces read three scattered places (the bucket, the
// node before, the node), and its lookups were most of the operations' own time on
// archi_Tree_1 (2026-12-07, perf). Lookups run in parallel, insertions only between them.
template <class Value>
class PointCache {
 public:
  // The value at p, or null.
  [[nodiscard]] const Value* find(const Vec3& p) const {
    if (entries_.empty()) return nullptr;
    const PointKey k = key_of(p);
    const std::uint64_t h = hash_of(k);
    const auto tag = static_cast<std::uint32_t>(h);
    for (std::size_t i = h >> shift_;; i = (i + 1) & mask_) {
      const Slot s = slots_[i];
      if (s.index == kNone) return nullptr;
      if (s.tag == tag && entries_[s.index].key == k) return &entries_[s.index].value;
    }
  }
  // The index of p's entry, made (its value default) when new; `fresh` says whether it was.
  std::uint32_t insert(const Vec3& p, bool& fresh) {
    if (2 * (entries_.size() + 1) > slots_.size()) grow();
    const PointKey k = key_of(p);
    const std::uint64_t h = hash_of(k);
    const auto tag = static_cast<std::uint32_t>(h);
    std::size_t i = h >> shift_;
    for (;; i = (i + 1) & mask_) {
      const Slot s = slots_[i];
      if (s.index == kNone) break;
      if (s.tag == tag && entries_[s.index].key == k) {
        fresh = false;
        return s.index;
      }
    }
    fresh = true;
    const auto index = static_cast<std::uint32_t>(entries_.size());
    slots_[i] = {tag, index};
    entries_.push_back({k, Value{}});
    return index;
  }
  Value& operator[](std::uint32_t index) { return entries_[index].value; }

 private:
  struct Slot {
    std::uint32_t tag = 0, index = kNone;
  };
  struct Entry {
    PointKey key;
    Value value;
  };
  void grow() {
    const std::size_t size = std::max<std::size_t>(1024, 2 * slots_.size());
    slots_.assign(size, Slot{});
    mask_ = size - 1;
    shift_ = 64 - std::countr_zero(size);
    for (std::uint32_t e = 0; e < entries_.size(); ++e) {
      const std::uint64_t h = hash_of(entries_[e].key);
      std::size_t i = h >> shift_;
      while (slots_[i].index != kNone) i = (i + 1) & mask_;
      slots_[i] = {static_cast<std::uint32_t>(h), e};
    }
  }
  std::vector<Slot> slots_;
  std::vector<Entry> entries_;
  std::size_t mask_ = 0;
  int shift_ = 64;
};

// The field at an edge's midpoint: the first-order distance to the surface (model units) and
// the outward unit normal -grad f / |grad f| (zero where the gradient vanishes).
struct Probe {
  double distance = 0;
  Vec3 normal = Vec3::Zero();
};

// A Newton projection onto the surface from a start point.
struct Projection {
  Vec3 z = Vec3::Zero();
  double start_distance = 0;  // first-order distance of the start point to the surface
  Probe at_z;                 // the outward normal at (the last Newton step before) z
  // The smallest local radius of the vertices it replaces (z lies within a small step of them),
  // its scale and the new vertex's radius.
  double radius = 0;
  bool ok = false;  // converged
  // Whether it converged no farther from `start` than `reach` beyond the start's own distance
  // to the surface (a step that jumped to another part of the surface is not taken).
  [[nodiscard]] bool lands_within(const Vec3& start, double reach) const {
    return ok && (z - start).norm() <= reach + 2.0 * start_distance;
  }
};

// The field data an operation asked for and did not find.
struct Requests {
  std::vector<Vec3> midpoints;  // first-order distance to the surface
  std::vector<Vec3> starts;     // Newton projections
  std::vector<double> scales;   // their local radii
  // Per start, the vertices around what the new vertex replaces (the disk's boundary, a run of
  // around_count[i] in `around`): the midpoints of its new edges to them are evaluated in the
  // stage of the projection, which saves the operation a stage.
  std::vector<std::uint32_t> around, around_count;
  std::vector<std::uint32_t> radii;  // local radii of vertices
  [[nodiscard]] bool empty() const { return midpoints.empty() && starts.empty() && radii.empty(); }
};

// Scratch lists of one thread's operations.
struct Scratch {
  std::vector<std::uint32_t> disk, around, hits, cluster;
  std::vector<std::uint64_t> edges;                    // directed, as edge_key()
  std::vector<std::array<std::uint32_t, 2>> boundary;  // directed
  std::vector<Tri> moved;
  std::vector<std::array<Vec3, 4>> tets;
  std::vector<Vec3> old_normals;
  bool relaxed = false;  // see Improver::follows
  bool nudging = false;  // see Improver::try_replace
  // prepare_disk()'s results: the smallest angle (sine) of the disk, the box of its corners,
  // and the disk triangles with one cluster vertex (the triangle, that corner).
  double old_worst = 1.0;
  Aabb box;
  std::vector<std::array<std::uint32_t, 2>> kept;  // in the order of `boundary`
  std::vector<std::array<std::uint32_t, 2>> moved_kept, moved_boundary;  // scratch
  std::vector<std::size_t> order;
  std::vector<std::pair<double, std::size_t>> candidates;  // (sine, index), see choose()
  // The cluster prepare_disk() last looked at in choose() call `call`, and its answer.
  std::vector<std::uint32_t> prepared;
  bool prepared_ok = false;
  std::uint64_t call = 0, prepared_call = ~std::uint64_t{0};
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// Most vertices one operation replaces by one (a cluster of near-coincident vertices).
constexpr std::size_t kMaxCluster = 12;

// An operation on the mesh. `quality`: the smallest angle (as a sine) of the triangles it
// makes; -1 when none is possible.
struct Op {
  enum class Kind { kNone, kFlip, kReplace } kind = Kind::kNone;
  std::uint32_t t = kNone;  // flip: the triangle and its edge k -> k + 1
  int k = 0;
  // replace: the vertices (sorted) that become one new vertex at z
  std::array<std::uint32_t, kMaxCluster> s{};
  std::size_t ns = 0;
  Vec3 z = Vec3::Zero();
  double z_radius = 0;
  double quality = -1;
};

// Where choose() resumes a triangle in the next evaluation stage: the levels before
// `level` were decided (they lacked no data), `op` is the best of them.
// A level's choice of one corner to move (the relaxation's, the nudge's): the best offer whose
// fan beats both the fan's old worst triangle and the level's floor; kNone when none does.
struct CornerChoice {
  bool chosen = false;  // made (once per triangle; later stages reuse it)
  std::uint32_t corner = kNone;
  Vec3 start = Vec3::Zero();  // where the corner goes, before its projection
  double within = 0;          // how far from `start` the projection may land
  double quality = 0;         // the chosen fan's smallest-angle sine

  void offer(std::uint32_t w, double q, const Vec3& at, double reach, double old_worst) {
    if (q > old_worst && q > quality) {
      corner = w;
      quality = q;
      start = at;
      within = reach;
    }
  }
};

struct Resume {
  int level = 0;
  Op op;
  // The candidates of `level` found not to fit (bit i: flip i, end point i, cluster vertex i):
  // the mesh and the data they read stay as they are through the stages, and the bar they
  // failed only rises, so the next stages pass over them.
  std::uint32_t failed = 0;
  CornerChoice relax;  // the relaxation level's choice
  CornerChoice nudge;  // the nudge level's choice
};
// The moves choose() tries, in this order (kOrder): flips of the triangle's edges;
// relaxation of a corner; the collapse of its shortest edge into an end point, into its
// midpoint on the surface; the collapse of the cluster of near-coincident vertices around that
// edge into one of them, into their centroid on the surface; the collapse of the patch of bad
// triangles around it; a nudge of a corner; a small move. Relaxation comes second: on archi_Tree_1
// (fitted radii), where most bad triangles are caps of 7-9 degrees that only a relaxation mends,
// that order takes a quarter less time than collapses first, for the same result.
enum class Move {
  kFlip,
  kRelax,
  kEdgeToEnd,
  kEdgeToMidpoint,
  kClusterToVertex,
  kClusterToCentroid,
  kPatch,
  kNudge,
  kSmallMove
};
constexpr std::array<Move, 9> kOrder = {
    Move::kFlip,           Move::kRelax,           Move::kEdgeToEnd,
    Move::kEdgeToMidpoint, Move::kClusterToVertex, Move::kClusterToCentroid,
    Move::kPatch,          Move::kNudge,           Move::kSmallMove};
constexpr int kLevels = static_cast<int>(kOrder.size());

class Improver {
 public:
  Improver(TriMesh& mesh, const Field& field, const Skeleton& skeleton, const ImproveOptions& o,
           const Context* threads)
      : mesh_(mesh),
        field_(field),
        skeleton_(skeleton),
        o_(o),
        threads_(threads),
        sin_bad_(pm::sin(o.min_angle_deg * kDeg)),
        sin_hard_(pm::sin(kHardAngleDeg * kDeg)),
        sin_last_(pm::sin(kLastResortDeg * kDeg)),
        cos_turn_(pm::cos(o.max_turn_deg * kDeg)),
        alive_(mesh.triangles.size(), 1),
        head_(mesh.positions.size(), kNone),
        next_(3 * mesh.triangles.size(), kNone),
        radius_(mesh.positions.size(), std::numeric_limits<double>::quiet_NaN()),
        touched_(mesh.positions.size(), 0) {
    std::vector<Aabb> boxes;
    boxes.reserve(skeleton.nodes.size());
    for (const auto& n : skeleton.nodes) boxes.emplace_back(n.position, n.position);
    nodes_ = detail::BoxBvh(std::move(boxes));
    // Corner c = 3 t + k (vertex k of triangle t) is chained to the next corner of the same
    // vertex; going backwards leaves every chain ascending.
    for (std::size_t t = mesh.triangles.size(); t-- > 0;) {
      for (std::uint32_t k = 0; k < 3; ++k) {
        const auto c = static_cast<std::uint32_t>(3 * t + k);
        const std::uint32_t v = mesh.triangles[t][k];
        next_[c] = head_[v];
        head_[v] = c;
      }
    }
  }

  Scan scan_all() { return scan(mesh_, &alive_, sin_bad_, threads_, &sines_); }

  // The triangles left below kLastResortDeg, in index order; from now on they may take the
  // small move (Move::kSmallMove).
  std::vector<std::uint32_t> last_resort() {
    small_moves_ = true;
    std::vector<std::uint32_t> out;
    for (std::size_t t = 0; t < sines_.size(); ++t) {
      if (alive_[t] != 0 && sines_[t] < sin_last_) out.push_back(static_cast<std::uint32_t>(t));
    }
    return out;
  }

  // The counts of scan() over the triangles left, from the sines kept up to date.
  Scan scan_kept() const {
    const double s10 = pm::sin(10 * kDeg), s1 = pm::sin(1 * kDeg);
    Scan all;
    bool any = false;
    for (std::size_t t = 0; t < sines_.size(); ++t) {
      if (alive_[t] == 0) continue;
      const double s = sines_[t];
      all.below_10 += s < s10 ? 1 : 0;
      all.below_1 += s < s1 ? 1 : 0;
      all.min_sine = std::min(all.min_sine, s);
      any = true;
    }
    if (!any) all.min_sine = 0;
    return all;
  }

  // One round over `bad` (triangle ids); returns the operations applied and fills `next_bad`
  // with the bad triangles next to a change (or whose operation lacked data), for the next
  // round.
  std::size_t round(std::vector<std::uint32_t> bad, std::vector<std::uint32_t>& next_bad,
                    ImproveStats& st) {
    std::sort(bad.begin(), bad.end(), [&](std::uint32_t a, std::uint32_t b) {
      const double sa = sines_[a], sb = sines_[b];
      return sa < sb || (sa == sb && a < b);
    });
    // Ask, evaluate, ask again: each stage evaluates what the operations could not decide on;
    // a triangle that lacked nothing is decided and leaves the stages.
    const std::size_t nb = bad.size();
    prefetch_radii(bad);
    std::vector<Resume> chosen(nb);
    std::vector<char> decided(nb, 0);
    std::vector<std::uint32_t> open(nb);
    for (std::size_t i = 0; i < nb; ++i) open[i] = static_cast<std::uint32_t>(i);
    std::vector<std::uint32_t> walk;
    for (int stage = 0; stage < kStages && !open.empty(); ++stage) {
      std::vector<Requests> slots(open.size());
      // The triangles are looked at in index order, near each other in the mesh's arrays (in
      // the order of their angles they jump across the whole mesh); their requests stay in the
      // order of `open`.
      walk.resize(open.size());
      for (std::size_t j = 0; j < open.size(); ++j) walk[j] = static_cast<std::uint32_t>(j);
      std::sort(walk.begin(), walk.end(),
                [&](std::uint32_t x, std::uint32_t y) { return bad[open[x]] < bad[open[y]]; });
      parallel::for_chunks(
          open.size(), kOpGrain,
          [&](std::size_t b, std::size_t e) {
            Scratch scratch;
            for (std::size_t w = b; w < e; ++w) {
              const std::uint32_t j = walk[w];
              const std::uint32_t i = open[j];
              bool missing = false;
              chosen[i].op = choose(bad[i], scratch, &slots[j], missing, chosen[i]);
              decided[i] = missing ? 0 : 1;
            }
          },
          threads_);
      Requests all;
      std::vector<std::uint32_t> still;
      for (std::size_t j = 0; j < open.size(); ++j) {
        const Requests& r = slots[j];
        if (r.empty()) continue;
        still.push_back(open[j]);
        all.midpoints.insert(all.midpoints.end(), r.midpoints.begin(), r.midpoints.end());
        all.starts.insert(all.starts.end(), r.starts.begin(), r.starts.end());
        all.scales.insert(all.scales.end(), r.scales.begin(), r.scales.end());
        all.around.insert(all.around.end(), r.around.begin(), r.around.end());
        all.around_count.insert(all.around_count.end(), r.around_count.begin(),
                                r.around_count.end());
        all.radii.insert(all.radii.end(), r.radii.begin(), r.radii.end());
      }
      open = std::move(still);
      if (all.empty()) break;
      evaluate(all);
    }
    // Apply, worst first. An operation is decided again on the mesh as the earlier ones left
    // it, unless nothing it reads changed: every operation of a triangle reads only the
    // triangles around its corners and their neighbours, and every change marks the corners of
    // the triangles it changes.
    std::vector<std::uint32_t> touched;
    std::size_t done = 0;
    Scratch scratch;
    for (std::size_t i = 0; i < nb; ++i) {
      const std::uint32_t t = bad[i];
      if (alive_[t] == 0 || sines_[t] >= sin_bad_) continue;
      Op op = chosen[i].op;
      if (decided[i] == 0 || near_touched(mesh_.triangles[t])) {
        bool missing = false;
        Resume fresh;
        op = choose(t, scratch, nullptr, missing, fresh);
        if (op.kind == Op::Kind::kNone && missing) mark(mesh_.triangles[t], touched);
      }
      if (op.kind == Op::Kind::kNone) continue;
      apply(op, touched, st);
      ++done;
    }
    // The next round looks at the bad triangles around the vertices touched.
    next_bad.clear();
    for (const std::uint32_t w : touched) {
      touched_[w] = 0;
      for (std::uint32_t c = head_[w]; c != kNone; c = next_[c]) {
        const std::uint32_t t = c / 3;
        if (sines_[t] < sin_bad_) next_bad.push_back(t);
      }
    }
    std::sort(next_bad.begin(), next_bad.end());
    next_bad.erase(std::unique(next_bad.begin(), next_bad.end()), next_bad.end());
    return done;
  }

  // The local radii of the corners of the triangles `bad` and of their neighbours, in one batch
  // before the stages: the flips and the relaxation need them before they can ask for a
  // projection or judge an edge, and asking for them as they came cost a stage (the corners'
  // neighbours are the disks' boundaries of a flip and a relaxation). touched_ marks the
  // vertices listed, and is cleared again.
  void prefetch_radii(const std::vector<std::uint32_t>& bad) {
    Requests pre;
    for (const std::uint32_t t : bad) {
      for (const std::uint32_t x : mesh_.triangles[t]) {
        for (std::uint32_t c = head_[x]; c != kNone; c = next_[c]) {
          for (const std::uint32_t w : mesh_.triangles[c / 3]) {
            if (touched_[w] == 0 && std::isnan(radius_[w])) {
              touched_[w] = 1;
              pre.radii.push_back(w);
            }
          }
        }
      }
    }
    for (const std::uint32_t w : pre.radii) touched_[w] = 0;
    evaluate(pre);
  }

  // Drops removed triangles and unused vertices, keeping the order of the rest.
  void compact() {
    std::vector<std::uint32_t> remap(mesh_.positions.size(), kNone);
    std::uint32_t kept = 0;
    for (std::uint32_t v = 0; v < remap.size(); ++v) {
      if (head_[v] == kNone) continue;
      mesh_.positions[kept] = mesh_.positions[v];
      remap[v] = kept++;
    }
    mesh_.positions.resize(kept);
    std::size_t alive = 0;
    for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (alive_[t] == 0) continue;
      const Tri& f = mesh_.triangles[t];
      mesh_.triangles[alive++] = {remap[f[0]], remap[f[1]], remap[f[2]]};
    }
    mesh_.triangles.resize(alive);
    mesh_.normals.clear();
  }

 private:
  const Vec3& pos(std::uint32_t v) const { return mesh_.positions[v]; }
  double sine(const Tri& f) const { return min_angle_sine(pos(f[0]), pos(f[1]), pos(f[2])); }
  static double sine_of(const std::array<Vec3, 3>& p) { return min_angle_sine(p[0], p[1], p[2]); }
  static Vec3 normal_of(const std::array<Vec3, 3>& p) { return (p[1] - p[0]).cross(p[2] - p[0]); }
  Vec3 normal(const Tri& f) const { return normal_of({pos(f[0]), pos(f[1]), pos(f[2])}); }
  static bool has(const Tri& f, std::uint32_t v) { return f[0] == v || f[1] == v || f[2] == v; }

  std::size_t valence(std::uint32_t v) const {
    std::size_t n = 0;
    for (std::uint32_t c = head_[v]; c != kNone; c = next_[c]) ++n;
    return n;
  }

  // The distinct neighbours of v, sorted.
  void ring(std::uint32_t v, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint32_t c = head_[v]; c != kNone; c = next_[c]) {
      for (const std::uint32_t w : mesh_.triangles[c / 3]) {
        if (w != v) out.push_back(w);
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  // The local radius of vertex v, or NaN (asked for in `req`) when not known yet.
  double radius(std::uint32_t v, Requests* req, bool& missing) const {
    const double r = radius_[v];
    if (std::isnan(r)) {
      missing = true;
      if (req != nullptr) req->radii.push_back(v);
    }
    return r;
  }

  // The field at the midpoint of p-q; null (asked for in `req`) when not known yet.
  const Probe* probe(const Vec3& p, const Vec3& q, Requests* req, bool& missing) const {
    const Vec3 m = 0.5 * (p + q);
    const Probe* pr = probe_.find(m);
    if (pr == nullptr) {
      missing = true;
      if (req != nullptr) req->midpoints.push_back(m);
    }
    return pr;
  }

  // The first-order distance of the midpoint of p-q to the surface, relative to the smaller of
  // the radii rp, rq (as refine_to_surface() measures an edge); NaN when not known yet.
  double edge_distance(const Vec3& p, const Vec3& q, double rp, double rq, Requests* req,
                       bool& missing) const {
    const Probe* pr = probe(p, q, req, missing);
    const double r = std::min(rp, rq);
    if (pr == nullptr || std::isnan(r)) return std::numeric_limits<double>::quiet_NaN();
    return r > 0 ? pr->distance / r : kInf;
  }

  // Whether the new triangles of normals `fresh` follow the surface at the probe: each turns
  // from the surface's normal there by less than max_turn_deg, or by no more than the old
  // triangles of normals `old` the change replaces (in a wrinkle of the mesh), and by less
  // than 90 degrees (a fold, or a triangle standing across the surface, turns far more) unless
  // `relaxed` (a triangle below kHardAngleDeg in a crumpled patch may go as long as no new
  // triangle turns farther than the worst old one).
  template <class Fresh, class Old>
  bool follows(const Fresh& fresh, const Old& old, const Probe& pr, bool relaxed) const {
    double floor = 1.0;
    for (const Vec3& n : old) floor = std::min(floor, n.dot(pr.normal) / n.norm());
    floor = std::min(cos_turn_, relaxed ? floor : std::max(floor, 0.0));
    for (const Vec3& n : fresh) {
      if (!(n.dot(pr.normal) > floor * n.norm())) return false;
    }
    return true;
  }

  // Whether a new triangle of normal `fresh` turns by less than 60 degrees from `src`, the
  // normal of the triangle it replaces (a nudge's fold test, see try_replace()).
  static bool keeps_side(const Vec3& fresh, const Vec3& src) {
    return fresh.dot(src) > 0.5 * fresh.norm() * src.norm();
  }

  // The smallest angle's sine over the kept triangles of the prepared disk (sc.kept) with their
  // moving corner at `start`; -1 when `guard_sides` and a triangle not already below the hard
  // angle turns over.
  double fan_quality(const Vec3& start, const Scratch& sc, bool guard_sides) const {
    double quality = 1.0;
    for (const auto& [kt, kk] : sc.kept) {
      const Tri& g = mesh_.triangles[kt];
      std::array<Vec3, 3> q{pos(g[0]), pos(g[1]), pos(g[2])};
      q[kk] = start;
      if (guard_sides && sines_[kt] >= sin_hard_ && !keeps_side(normal_of(q), normal(g))) {
        return -1;
      }
      quality = std::min(quality, sine_of(q));
    }
    return quality;
  }

  // The projection of `start` onto the surface; null (asked for in `req`, with the smallest
  // local radius of `cluster` as its scale and the new vertex's radius; for a corner's move,
  // `sc` not null, with the boundary of the disk prepare_disk() left in it) when not known yet.
  const Projection* projection(const Vec3& start, const std::vector<std::uint32_t>& cluster,
                               const Scratch* sc, Requests* req, bool& missing) const {
    if (const Projection* p = projection_.find(start); p != nullptr) return p;
    missing = true;
    double scale = kInf;
    bool lacking = false;
    for (const std::uint32_t x : cluster) scale = std::min(scale, radius(x, req, lacking));
    if (req != nullptr && !lacking) {
      req->starts.push_back(start);
      req->scales.push_back(scale);
      std::uint32_t count = 0;
      if (sc != nullptr) {
        for (const auto& edge : sc->boundary) req->around.push_back(edge[0]);
        count = static_cast<std::uint32_t>(sc->boundary.size());
      }
      req->around_count.push_back(count);
    }
    return nullptr;
  }

  // Whether a skeleton node lies in one of the tetrahedra `make_tets` puts into sc.tets (all
  // inside `box`; made only when a node lies in the box).
  template <class MakeTets>
  bool sweeps_node(const Aabb& box, Scratch& sc, MakeTets&& make_tets) const {
    sc.hits.clear();
    nodes_.query(box, sc.hits);
    if (sc.hits.empty()) return false;
    sc.tets.clear();
    make_tets();
    for (const std::uint32_t h : sc.hits) {
      const Vec3& p = skeleton_.nodes[h].position;
      for (const auto& q : sc.tets) {
        if (in_tetrahedron(p, q[0], q[1], q[2], q[3])) return true;
      }
    }
    return false;
  }

  // Whether a new edge p-q (end radii rp, rq) may replace edges as far as `old` (a function of
  // the new edge's relative distance d returning a bound on the old edges' that is at least d
  // exactly when their largest is, so that it may stop looking once it knows; its flag is set
  // while lacking): within the tolerance, or no farther than them (when `check_distance`); and
  // whether the new triangles on it, of normals `normals`, follow the surface there. The old
  // edges are looked at only when the new one is beyond the tolerance. False while lacking data
  // (then `lacking` is set).
  template <class Fold, class Old>
  bool edge_fits(const Vec3& p, const Vec3& q, double rp, double rq, Fold&& fold_ok,
                 bool check_distance, Requests* req, bool& lacking, Old&& old) const {
    bool missing = false;
    const Probe* pr = probe(p, q, req, missing);
    const double r = std::min(rp, rq);
    if (missing || std::isnan(r)) {
      lacking = true;
      return false;
    }
    if (!fold_ok(*pr)) return false;
    if (!check_distance) return true;
    const double d = r > 0 ? pr->distance / r : kInf;
    if (d <= o_.tolerance) return true;
    const double before = old(d, missing);
    if (missing) {
      lacking = true;
      return false;
    }
    return d <= before;
  }

  // The flip of triangle t's edge k -> k + 1 (see the header); fills `op` when it beats it.
  void try_flip(std::uint32_t t1, int k, Scratch& sc, Requests* req, bool& missing, Op& op) const {
    const Tri f1 = mesh_.triangles[t1];
    const std::uint32_t a = f1[k], b = f1[(k + 1) % 3], c = f1[(k + 2) % 3];
    std::uint32_t t2 = kNone;
    int with_b = 0;
    for (std::uint32_t corner = head_[a]; corner != kNone; corner = next_[corner]) {
      const Tri& f = mesh_.triangles[corner / 3];
      if (!has(f, b)) continue;
      ++with_b;
      if (f[(corner + 2) % 3] == b) t2 = corner / 3;  // the directed edge b -> a
    }
    if (with_b != 2 || t2 == kNone) return;
    const Tri f2 = mesh_.triangles[t2];
    std::uint32_t d = kNone;
    for (const std::uint32_t w : f2) {
      if (w != a && w != b) d = w;
    }
    if (d == kNone || d == c || valence(a) <= 3 || valence(b) <= 3) return;
    const std::array<Vec3, 3> g1{pos(a), pos(d), pos(c)}, g2{pos(d), pos(b), pos(c)};
    const double old_worst = std::min(sines_[t1], sines_[t2]);
    const double new_worst = std::min(sine_of(g1), sine_of(g2));
    if (!(new_worst > old_worst) || !(new_worst > op.quality)) return;
    for (std::uint32_t corner = head_[c]; corner != kNone; corner = next_[corner]) {
      if (has(mesh_.triangles[corner / 3], d)) return;  // the edge c-d exists
    }
    const Vec3 n1 = normal_of(g1), n2 = normal_of(g2);
    Aabb box(pos(a));
    box.extend(pos(b));
    box.extend(pos(c));
    box.extend(pos(d));
    if (sweeps_node(box, sc, [&] { sc.tets.push_back({pos(a), pos(b), pos(c), pos(d)}); })) {
      return;
    }
    bool lacking = false;
    const double rc = radius(c, req, lacking), rd = radius(d, req, lacking);
    const std::array<Vec3, 2> fresh{n1, n2}, old{normal(f1), normal(f2)};
    auto fold_ok = [&](const Probe& pr) { return follows(fresh, old, pr, sc.relaxed); };
    auto bound = [&](double dist, bool& m) {
      const double ra = radius(a, req, m), rb = radius(b, req, m);
      double before = edge_distance(pos(a), pos(b), ra, rb, req, m);
      if (sc.relaxed) {
        // Below kHardAngleDeg: as far as the farthest edge of the pair, plus kSlack of the
        // tolerance (as try_replace()); the pair's other edges are asked for only when the
        // flipped edge does not do.
        if (m || dist <= before + kSlack * o_.tolerance) return before + kSlack * o_.tolerance;
        for (const auto& [x, y] :
             {std::pair{a, c}, std::pair{b, c}, std::pair{a, d}, std::pair{b, d}}) {
          before = std::max(
              before, edge_distance(pos(x), pos(y), radius(x, req, m), radius(y, req, m), req, m));
        }
        before += kSlack * o_.tolerance;
      }
      return before;
    };
    const bool fits = edge_fits(pos(c), pos(d), rc, rd, fold_ok, true, req, lacking, bound);
    if (lacking) {
      missing = true;
      return;
    }
    if (!fits) return;
    op = Op{};
    op.kind = Op::Kind::kFlip;
    op.t = t1;
    op.k = k;
    op.quality = new_worst;
  }

  // Whether the vertices `cluster` (sorted, at most kMaxCluster) may be replaced by one new
  // vertex: the triangles around them (the disk) must form a disk whose interior vertices are
  // exactly the cluster and whose boundary is one simple cycle, with every edge between two
  // boundary vertices on it (no chord). Then each disk triangle with one cluster vertex keeps
  // its boundary edge and takes the new vertex for that one (in its own orientation), the
  // others (two or three cluster vertices) go; the mesh stays a closed, oriented 2-manifold,
  // and the new vertex has one triangle per boundary edge. For one vertex this is moving it,
  // for two the collapse of their edge under the link condition. Fills sc.disk (and the rest
  // that try_replace() reads) when it may.
  bool prepare_disk(const std::vector<std::uint32_t>& cluster, Scratch& sc) const {
    if (sc.prepared_call == sc.call && sc.prepared == cluster) return sc.prepared_ok;
    sc.prepared_call = sc.call;
    sc.prepared = cluster;
    sc.prepared_ok = false;
    if (cluster.size() == 1) return prepare_vertex(cluster[0], sc);
    auto in_cluster = [&](std::uint32_t w) {
      return std::binary_search(cluster.begin(), cluster.end(), w);
    };
    std::vector<std::uint32_t>& disk = sc.disk;
    disk.clear();
    for (const std::uint32_t x : cluster) {
      for (std::uint32_t c = head_[x]; c != kNone; c = next_[c]) disk.push_back(c / 3);
    }
    std::sort(disk.begin(), disk.end());
    disk.erase(std::unique(disk.begin(), disk.end()), disk.end());
    // Directed edges; each at most once (2-manifold around the cluster), the boundary those
    // whose reverse is not in the disk.
    auto& edges = sc.edges;
    auto& boundary = sc.boundary;
    edges.clear();
    boundary.clear();
    for (const std::uint32_t t : disk) {
      const Tri& f = mesh_.triangles[t];
      for (int i = 0; i < 3; ++i) edges.push_back(edge_key(f[i], f[(i + 1) % 3]));
    }
    std::sort(edges.begin(), edges.end());
    if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
    for (const std::uint64_t e : edges) {
      const auto a = static_cast<std::uint32_t>(e >> 32), b = static_cast<std::uint32_t>(e);
      const bool inner = std::binary_search(edges.begin(), edges.end(), edge_key(b, a));
      const bool touches = in_cluster(a) || in_cluster(b);
      if (inner && !touches) return false;  // a chord
      if (!inner && touches) return false;  // a cluster vertex on the boundary
      if (!inner) boundary.push_back({a, b});
    }
    // One simple cycle: every boundary vertex starts exactly one boundary edge (the list is
    // sorted by start), and walking from the first edge visits all of them.
    const std::size_t nb = boundary.size();
    if (nb < 3) return false;
    for (std::size_t i = 1; i < nb; ++i) {
      if (boundary[i][0] == boundary[i - 1][0]) return false;
    }
    std::size_t steps = 0;
    std::uint32_t at = boundary[0][1];
    while (at != boundary[0][0] && steps < nb) {
      const auto it =
          std::lower_bound(boundary.begin(), boundary.end(), std::array<std::uint32_t, 2>{at, 0});
      if (it == boundary.end() || (*it)[0] != at) return false;
      at = (*it)[1];
      ++steps;
    }
    if (steps + 1 != nb) return false;
    // A disk: V - E + F = 1.
    const long long n_edges = static_cast<long long>(edges.size() + nb) / 2;
    if (static_cast<long long>(cluster.size() + nb) - n_edges +
            static_cast<long long>(disk.size()) !=
        1) {
      return false;
    }
    // What every position of the new vertex is judged against.
    sc.old_worst = 1.0;
    sc.old_normals.clear();
    sc.kept.clear();
    sc.box = Aabb(pos(cluster[0]));
    for (const std::uint32_t t : disk) {
      const Tri& f = mesh_.triangles[t];
      sc.old_worst = std::min(sc.old_worst, sines_[t]);
      sc.old_normals.push_back(normal(f));
      int in = 0, k = 0;
      for (int i = 0; i < 3; ++i) {
        sc.box.extend(pos(f[i]));
        if (in_cluster(f[i])) ++in, k = i;
      }
      if (in == 1) sc.kept.push_back({t, static_cast<std::uint32_t>(k)});
    }
    // Each kept triangle holds one boundary edge, from its corner after the cluster's.
    if (sc.kept.size() != nb) return false;
    std::sort(sc.kept.begin(), sc.kept.end(), [&](const auto& x, const auto& y) {
      return mesh_.triangles[x[0]][(x[1] + 1) % 3] < mesh_.triangles[y[0]][(y[1] + 1) % 3];
    });
    sc.prepared_ok = true;
    return true;
  }

  // prepare_disk() for one vertex x: its fan is a disk when its opposite edges form one simple
  // cycle (a 2-manifold vertex); the edges are then x's to its neighbours.
  bool prepare_vertex(std::uint32_t x, Scratch& sc) const {
    sc.disk.clear();
    sc.edges.clear();
    sc.boundary.clear();
    sc.kept.clear();
    sc.old_normals.clear();
    sc.old_worst = 1.0;
    sc.box = Aabb(pos(x));
    for (std::uint32_t c = head_[x]; c != kNone; c = next_[c]) {
      const std::uint32_t t = c / 3, k = c % 3;
      const Tri& f = mesh_.triangles[t];
      if (f[(k + 1) % 3] == x || f[(k + 2) % 3] == x) return false;
      sc.disk.push_back(t);
      sc.kept.push_back({t, k});
      sc.boundary.push_back({f[(k + 1) % 3], f[(k + 2) % 3]});
      sc.edges.push_back(edge_key(x, f[(k + 1) % 3]));
      sc.old_worst = std::min(sc.old_worst, sines_[t]);
      sc.old_normals.push_back(normal(f));
      sc.box.extend(pos(f[(k + 1) % 3]));
      sc.box.extend(pos(f[(k + 2) % 3]));
    }
    const std::size_t nb = sc.boundary.size();
    if (nb < 3) return false;
    // kept and boundary in the order of the boundary edges' starts.
    std::vector<std::size_t>& order = sc.order;
    order.resize(nb);
    for (std::size_t i = 0; i < nb; ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t i, std::size_t j) { return sc.boundary[i][0] < sc.boundary[j][0]; });
    sc.moved_kept.resize(nb);
    sc.moved_boundary.resize(nb);
    for (std::size_t i = 0; i < nb; ++i) {
      sc.moved_kept[i] = sc.kept[order[i]];
      sc.moved_boundary[i] = sc.boundary[order[i]];
    }
    std::swap(sc.kept, sc.moved_kept);
    std::swap(sc.boundary, sc.moved_boundary);
    std::sort(sc.disk.begin(), sc.disk.end());
    std::sort(sc.edges.begin(), sc.edges.end());
    const auto& boundary = sc.boundary;
    for (std::size_t i = 1; i < nb; ++i) {
      if (boundary[i][0] == boundary[i - 1][0]) return false;
    }
    std::size_t steps = 0;
    std::uint32_t at = boundary[0][1];
    while (at != boundary[0][0] && steps < nb) {
      const auto it =
          std::lower_bound(boundary.begin(), boundary.end(), std::array<std::uint32_t, 2>{at, 0});
      if (it == boundary.end() || (*it)[0] != at) return false;
      at = (*it)[1];
      ++steps;
    }
    if (steps + 1 != nb) return false;
    sc.prepared_ok = true;
    return true;
  }

  // Moving the corner a level chose (CornerChoice) to its start's projection onto the surface,
  // when that lands within the choice's reach: try_replace() with the corner alone.
  void try_corner(const CornerChoice& choice, std::vector<std::uint32_t>& cluster, Scratch& sc,
                  Requests* req, bool& missing, Op& op) const {
    if (choice.corner == kNone) return;
    cluster.assign(1, choice.corner);
    if (!prepare_disk(cluster, sc)) return;
    if (const Projection* p = projection(choice.start, cluster, &sc, req, missing);
        p != nullptr && p->lands_within(choice.start, choice.within)) {
      try_replace(cluster, p->z, p->radius, &p->at_z, sc, req, missing, op);
    }
  }

  // Whether replacing the vertices `cluster` (prepare_disk() holds, sc is as it left it) by z
  // sweeps a skeleton node: the cluster's vertices move to z one after the other, each sweeping
  // a tetrahedron with each of its triangles as the earlier moves left them.
  bool sweeps_node_to(const std::vector<std::uint32_t>& cluster, const Vec3& z, Scratch& sc) const {
    Aabb box = sc.box;
    box.extend(z);
    return sweeps_node(box, sc, [&] {
      sc.moved.assign(sc.disk.size(), Tri{});
      for (std::size_t i = 0; i < sc.disk.size(); ++i) sc.moved[i] = mesh_.triangles[sc.disk[i]];
      constexpr std::uint32_t kZ = kNone;  // z's label in `moved`
      auto at = [&](std::uint32_t w) { return w == kZ ? z : pos(w); };
      for (const std::uint32_t x : cluster) {
        for (Tri& f : sc.moved) {
          int k = -1;
          for (int i = 0; i < 3; ++i) {
            if (f[i] == x) k = i;
          }
          if (k < 0) continue;
          sc.tets.push_back({pos(x), z, at(f[(k + 1) % 3]), at(f[(k + 2) % 3])});
          f[k] = kZ;
        }
      }
    });
  }

  // The operation replacing the vertices `cluster` by one new vertex at z of local radius rz,
  // leaving `quality` as the smallest sine around it.
  static Op replace_op(const std::vector<std::uint32_t>& cluster, const Vec3& z, double rz,
                       double quality) {
    Op op;
    op.kind = Op::Kind::kReplace;
    std::copy(cluster.begin(), cluster.end(), op.s.begin());
    op.ns = cluster.size();
    op.z = z;
    op.z_radius = rz;
    op.quality = quality;
    return op;
  }

  // The smallest sine of the kept triangles of the disk (prepare_disk() holds) with their
  // cluster corner at z, or -1 as soon as one of them does not beat both the disk's old worst
  // and `quality`, or `accept(t, corners)` refuses it.
  template <class Accept>
  double worst_sine_with(const Vec3& z, const Scratch& sc, double quality, Accept&& accept) const {
    double worst = 1.0;
    for (const auto& [t, k] : sc.kept) {
      const Tri& f = mesh_.triangles[t];
      std::array<Vec3, 3> p{pos(f[0]), pos(f[1]), pos(f[2])};
      p[k] = z;
      const double s = sine_of(p);
      if (!(s > sc.old_worst) || !(s > quality) || !accept(t, p)) return -1.0;
      worst = std::min(worst, s);
    }
    return worst;
  }

  // A small move (Move::kSmallMove): replacing the vertices `cluster` (prepare_disk() holds, sc
  // is as it left it; none farther from z than the move's bound) by one new vertex at z of
  // local radius rz, judged by the geometry alone: the smallest angle rises, no skeleton node
  // is swept, and each new triangle turns by less than 60 degrees from the one it replaces
  // (any way when that one is below kHardAngleDeg: its normal is noise) and not against the
  // fan's area vector. Fills `op` when it beats it.
  void try_small_move(const std::vector<std::uint32_t>& cluster, const Vec3& z, double rz,
                      Scratch& sc, Op& op) const {
    Vec3 area = Vec3::Zero();
    for (const Vec3& n : sc.old_normals) area += n;
    const double new_worst =
        worst_sine_with(z, sc, op.quality, [&](std::uint32_t t, const std::array<Vec3, 3>& p) {
          const Vec3 n = normal_of(p);
          return sines_[t] >= sin_hard_ ? keeps_side(n, normal(mesh_.triangles[t]))
                                        : n.dot(area) > 0;
        });
    if (new_worst < 0 || sweeps_node_to(cluster, z, sc)) return;
    op = replace_op(cluster, z, rz, new_worst);
  }

  // Replacing the vertices `cluster`, for which prepare_disk() holds (sc is as it left it), by
  // one new vertex at z of local radius rz (`on_surface`: the surface normal at z when z was
  // taken onto the surface, else null); fills `op` when it beats it.
  void try_replace(const std::vector<std::uint32_t>& cluster, const Vec3& z, double rz,
                   const Probe* on_surface, Scratch& sc, Requests* req, bool& missing,
                   Op& op) const {
    const auto& edges = sc.edges;
    const auto& boundary = sc.boundary;
    const std::size_t nb = boundary.size();
    // The smallest angle must rise.
    const double new_worst = worst_sine_with(
        z, sc, op.quality, [](std::uint32_t, const std::array<Vec3, 3>&) { return true; });
    if (new_worst < 0 || sweeps_node_to(cluster, z, sc)) return;
    // Every new edge z-w stays within the tolerance, or no farther than the edges from the
    // cluster to w it replaces (an edge from a cluster vertex that stays where it is, z, is
    // no new edge), and every new triangle (w, w', z) on the boundary edge w -> w' follows the
    // surface at the midpoint of z-w (a triangle whose cluster vertex is at z is no new one).
    bool lacking = std::isnan(rz);
    bool fits = true;
    for (std::size_t i = 0; i < nb && (fits || req != nullptr); ++i) {
      const std::uint32_t w = boundary[i][0], w_next = boundary[i][1];
      const auto& [t, k] = sc.kept[i];
      const bool moved = pos(mesh_.triangles[t][k]) != z;
      bool same = false;
      for (const std::uint32_t x : cluster) {
        if (pos(x) == z && std::binary_search(edges.begin(), edges.end(), edge_key(x, w))) {
          same = true;
        }
      }
      if (same && !moved) continue;
      bool m = false;
      const double rw = radius(w, req, m);
      const std::array<Vec3, 1> fresh{normal_of({pos(w), pos(w_next), z})};
      // A nudge may instead keep each triangle within 60 degrees of itself (any way, for one
      // below kHardAngleDeg: its normal is noise and its area next to none): at a pinched neck
      // of the mesh the triangles stand across the surface and the gradient there says little
      // of how they should turn, while a short step that turns none of them far does not fold
      // the mesh, and its new edges are held to the distance test below.
      const bool intrinsic =
          sc.nudging && (sines_[t] < sin_hard_ || keeps_side(fresh[0], normal(mesh_.triangles[t])));
      // A new vertex taken onto the surface and a new edge short against the radius: the
      // chord sags by less than L^2 / 8 r (refine_to_surface()'s min_edge_radii), and the
      // triangle is judged against the surface normal at z.
      if (on_surface != nullptr) {
        if (m) {
          lacking = true;
          continue;
        }
        if ((z - pos(w)).norm() <= kShortEdge * std::min(rz, rw)) {
          if (moved && !intrinsic && !follows(fresh, sc.old_normals, *on_surface, sc.relaxed)) {
            fits = false;
          }
          continue;
        }
      }
      auto fold_ok = [&](const Probe& pr) {
        return !moved || intrinsic || follows(fresh, sc.old_normals, pr, sc.relaxed);
      };
      const bool ok =
          edge_fits(z, pos(w), rz, rw, fold_ok, !same, req, m, [&](double dist, bool& mm) {
            // An end point moving by |z - x| moves the midpoint by half that: an old edge beyond
            // the tolerance may get that much farther, up to kSlack of the tolerance (the
            // near-coincident vertices of a cluster).
            double before = 0;
            for (const std::uint32_t x : cluster) {
              if (std::binary_search(edges.begin(), edges.end(), edge_key(x, w))) {
                const double rx = radius(x, req, mm);
                const double slack =
                    std::min(0.5 * (z - pos(x)).norm() / std::min(rx, rw), kSlack * o_.tolerance);
                before = std::max(before, edge_distance(pos(x), pos(w), rx, rw, req, mm) + slack);
              }
            }
            // Below kHardAngleDeg: as far as the farthest edge of the disk (asked for only when the
            // edges from the cluster to w do not do: a patch's disk has dozens).
            if (sc.relaxed) {
              if (mm || dist <= before + kSlack * o_.tolerance)
                return before + kSlack * o_.tolerance;
              auto widen = [&](std::uint32_t x, std::uint32_t y) {
                before = std::max(before,
                                  edge_distance(pos(std::min(x, y)), pos(std::max(x, y)),
                                                radius(x, req, mm), radius(y, req, mm), req, mm));
              };
              for (const std::uint64_t e : edges) {
                widen(static_cast<std::uint32_t>(e >> 32), static_cast<std::uint32_t>(e));
              }
              for (const auto& [x, y] : boundary) widen(x, y);
              before += kSlack * o_.tolerance;
            }
            return before;
          });
      if (m) {
        lacking = true;
      } else if (!ok) {
        fits = false;
      }
    }
    if (!fits) return;
    if (lacking) {
      missing = true;
      return;
    }
    op = replace_op(cluster, z, rz, new_worst);
  }

  // The operation for the bad triangle t, by levels: flips of its edges; the collapse of its
  // shortest edge into an end point; into its midpoint taken onto the surface; the collapse of
  // the cluster of near-coincident vertices around that edge into one of them; into their
  // centroid on the surface; the patch of bad triangles around t into its centroid on the
  // surface; relaxations of its corners. A level is tried only when the ones before cannot
  // make the triangle good, and that is known: with `req` (the evaluation stages) the field
  // data a level lacks is asked for there, `missing` says whether some was lacking, and
  // `resume` keeps the levels decided for the next stage. The best of those tried wins.
  Op choose(std::uint32_t t, Scratch& sc, Requests* req, bool& missing, Resume& resume) const {
    Op op = resume.op;
    ++sc.call;
    const Tri f = mesh_.triangles[t];
    sc.relaxed = sines_[t] < sin_hard_;
    int k = 0;
    double shortest = kInf, longest = 0;
    for (int i = 0; i < 3; ++i) {
      const double len = (pos(f[i]) - pos(f[(i + 1) % 3])).squaredNorm();
      if (len < shortest) shortest = len, k = i;
      longest = std::max(longest, len);
    }
    const std::uint32_t u = f[k], v = f[(k + 1) % 3];
    std::vector<std::uint32_t>& cluster = sc.cluster;
    // Tries candidate `bit` of the current level, run(lacking), unless an earlier stage found
    // it not to fit (Resume::failed); returns whether it lacked data.
    auto attempt = [&](int bit, auto&& run) {
      if (((resume.failed >> bit) & 1u) != 0) return false;
      bool lacking = false;
      const double before = op.quality;
      run(lacking);
      if (lacking) {
        missing = true;
        return true;
      }
      if (!(op.quality > before)) resume.failed |= 1u << bit;
      return false;
    };
    for (int level = resume.level; level < kLevels; ++level) {
      const Move move = kOrder[level];
      switch (move) {
        case Move::kFlip:
          for (int e = 0; e < 3; ++e) {
            attempt(e, [&](bool& lacking) { try_flip(t, e, sc, req, lacking, op); });
          }
          break;
        case Move::kEdgeToEnd:
        case Move::kEdgeToMidpoint: {
          cluster = {std::min(u, v), std::max(u, v)};
          if (!prepare_disk(cluster, sc)) break;
          if (move == Move::kEdgeToEnd) {
            for (int e = 0; e < 2; ++e) {
              const std::uint32_t x = e == 0 ? u : v;
              attempt(e, [&](bool& lacking) {
                try_replace(cluster, pos(x), radius(x, req, lacking), nullptr, sc, req, lacking,
                            op);
              });
            }
            break;
          }
          const Vec3 mid = 0.5 * (pos(u) + pos(v));
          if (const Projection* p = projection(mid, cluster, nullptr, req, missing);
              p != nullptr && p->ok && p->lands_within(mid, std::sqrt(shortest))) {
            try_replace(cluster, p->z, p->radius, &p->at_z, sc, req, missing, op);
          }
          break;
        }
        case Move::kClusterToVertex:
        case Move::kClusterToCentroid: {
          // The vertices joined to u or v by a chain of edges shorter than kClusterEdge times
          // the triangle's longest edge.
          const double reach2 = kClusterEdge * kClusterEdge * longest;
          if (shortest > reach2) break;
          cluster = {u, v};
          for (std::size_t i = 0; i < cluster.size() && cluster.size() <= kMaxCluster; ++i) {
            const std::uint32_t x = cluster[i];
            for (std::uint32_t c = head_[x]; c != kNone; c = next_[c]) {
              for (const std::uint32_t w : mesh_.triangles[c / 3]) {
                if (w != x && (pos(w) - pos(x)).squaredNorm() <= reach2 &&
                    std::find(cluster.begin(), cluster.end(), w) == cluster.end()) {
                  cluster.push_back(w);
                }
              }
            }
          }
          if (cluster.size() <= 2 || cluster.size() > kMaxCluster) break;
          Vec3 centroid = Vec3::Zero();
          for (const std::uint32_t x : cluster) centroid += pos(x);
          centroid /= static_cast<double>(cluster.size());
          std::sort(cluster.begin(), cluster.end());
          if (!prepare_disk(cluster, sc)) break;
          if (move == Move::kClusterToVertex) {
            // The best of the candidates that pass is the first that passes in the order of
            // their smallest angles (ties by vertex): in the evaluation stages the field is
            // asked for one candidate at a time, the next only once the one before failed (a
            // cluster has up to kMaxCluster candidates, and asking for all of them at once was
            // a third of the pass's field points on a 30,000-segment tree).
            auto& order = sc.candidates;
            order.clear();
            for (std::size_t i = 0; i < cluster.size(); ++i) {
              const double q =
                  worst_sine_with(pos(cluster[i]), sc, op.quality,
                                  [](std::uint32_t, const std::array<Vec3, 3>&) { return true; });
              if (q >= 0) order.push_back({q, i});
            }
            std::sort(order.begin(), order.end(), [](const auto& x, const auto& y) {
              return x.first > y.first || (x.first == y.first && x.second < y.second);
            });
            for (const auto& [q, i] : order) {
              const std::uint32_t x = cluster[i];  // (try_replace reads the cluster, not x)
              const bool lacked = attempt(static_cast<int>(i), [&](bool& lacking) {
                try_replace(cluster, pos(x), radius(x, req, lacking), nullptr, sc, req, lacking,
                            op);
              });
              if (lacked && req != nullptr) break;
            }
            break;
          }
          if (const Projection* p = projection(centroid, cluster, nullptr, req, missing);
              p != nullptr && p->ok && p->lands_within(centroid, std::sqrt(reach2))) {
            try_replace(cluster, p->z, p->radius, &p->at_z, sc, req, missing, op);
          }
          break;
        }
        case Move::kPatch: {
          // The bad region: the vertices of the bad triangles joined to t through shared
          // corners, into their centroid on the surface (a crumpled patch). Only for a
          // triangle below kHardAngleDeg: it rarely wins elsewhere (8 of 5,300 changes on the
          // 1,500-segment tree) and costs a fifth of the pass.
          if (!sc.relaxed) break;
          cluster.assign(f.begin(), f.end());
          bool small = true;
          for (std::size_t i = 0; i < cluster.size() && small; ++i) {
            const std::uint32_t x = cluster[i];
            for (std::uint32_t c = head_[x]; c != kNone && small; c = next_[c]) {
              const Tri& g = mesh_.triangles[c / 3];
              if (sines_[c / 3] >= sin_bad_) continue;
              for (const std::uint32_t w : g) {
                if (std::find(cluster.begin(), cluster.end(), w) != cluster.end()) continue;
                cluster.push_back(w);
                if (cluster.size() > kMaxCluster) small = false;
              }
            }
          }
          if (!small) break;
          Vec3 centroid = Vec3::Zero();
          for (const std::uint32_t x : cluster) centroid += pos(x);
          centroid /= static_cast<double>(cluster.size());
          double reach = 0;
          for (const std::uint32_t x : cluster) reach = std::max(reach, (pos(x) - centroid).norm());
          std::sort(cluster.begin(), cluster.end());
          if (!prepare_disk(cluster, sc)) break;
          if (const Projection* p = projection(centroid, cluster, nullptr, req, missing);
              p != nullptr && p->ok && p->lands_within(centroid, reach)) {
            try_replace(cluster, p->z, p->radius, &p->at_z, sc, req, missing, op);
          }
          break;
        }
        case Move::kNudge: {
          // Below kHardAngleDeg, when no move before fits at all (elsewhere it would replace a
          // better-placed change and alter meshes it need not): a corner moves a short step (half
          // to four times what opens a needle's angle to kHardAngleDeg, or times its shortest edge)
          // in one of the directions of kNudgeDirections in its fan's tangent plane (of its area
          // vector), along that normal or along the shortest edge, and back onto the surface. Of
          // the three corners and their steps, the one whose fan gets the best smallest angle
          // without turning a triangle over is tried (keeps_side(), the test try_replace() applies
          // too). It mends the needles the moves before leave: their short edge lies on a pinched
          // neck of the mesh (a cycle of three edges that is no triangle, so the link condition
          // refuses its collapse), where the refined mesh stands across the surface and every
          // larger move turns a triangle against the gradient (on archi_Tree_1 and the studio's
          // tree, 2026-12-07: short edges of 5e-6 to 7e-4 against others of 0.01-0.07, in clusters
          // of near-coincident vertices).
          if (!sc.relaxed || op.kind != Op::Kind::kNone) break;
          CornerChoice& nudge = resume.nudge;
          if (!nudge.chosen) {
            nudge.quality = std::max(op.quality, 0.0);
            const double base = std::sqrt(longest) * sin_hard_;
            for (const std::uint32_t w : f) {
              MoveDirections dirs;
              if (!corner_moves(w, f, k, cluster, sc, dirs)) continue;
              for (std::size_t si = 0; si < 2 * kNudgeSteps.size(); ++si) {
                const double step = kNudgeSteps[si % kNudgeSteps.size()] *
                                    (si < kNudgeSteps.size() ? base : std::sqrt(shortest));
                for (const Vec3& dir : dirs) {
                  const Vec3 start = pos(w) + step * dir;
                  // (a step that turns a triangle over is no candidate: the sine of its angle
                  // does not see it)
                  nudge.offer(w, fan_quality(start, sc, true), start, step, sc.old_worst);
                }
              }
            }
            nudge.chosen = true;
          }
          sc.nudging = true;
          try_corner(nudge, cluster, sc, req, missing, op);
          sc.nudging = false;
          break;
        }
        case Move::kSmallMove: {
          // Below kLastResortDeg, when no move before fits at all: the triangle's vertices move
          // by at most kSmallMove tolerances of their local radius, judged by the geometry alone
          // (try_small_move()): every point of the mesh then moves by no more than that, so its
          // distance to the surface changes by less than the tolerance. It mends the needles
          // the tests of the field refuse where they say little (generated trees, 2026-12-07):
          // next to vertices refinement left off the surface, where the first-order distances
          // of the edges reach 0.75-6.5 radii and any move puts one a hundredth of a radius
          // farther, and where the gradient nearly vanishes and every collapse turns a
          // triangle against it. Candidates: the shortest edge collapsed into an end or its
          // midpoint (when that is a small move), and each corner moved by kSmallSteps of its
          // bound in the nudge's directions; the best that passes is taken.
          if (!small_moves_ || sines_[t] >= sin_last_ || op.kind != Op::Kind::kNone) break;
          std::array<double, 3> r{};
          bool lacking = false;
          for (int i = 0; i < 3; ++i) r[i] = radius(f[i], req, lacking);
          if (lacking) {
            missing = true;
            break;
          }
          const double ruv = std::min(r[k], r[(k + 1) % 3]);
          const double bound = kSmallMove * o_.tolerance * ruv, length = std::sqrt(shortest);
          cluster = {std::min(u, v), std::max(u, v)};
          if (0.5 * length <= bound && prepare_disk(cluster, sc)) {
            if (length <= bound) {
              try_small_move(cluster, pos(u), ruv, sc, op);
              try_small_move(cluster, pos(v), ruv, sc, op);
            }
            try_small_move(cluster, 0.5 * (pos(u) + pos(v)), ruv, sc, op);
          }
          for (int i = 0; i < 3; ++i) {
            const std::uint32_t w = f[i];
            MoveDirections dirs;
            if (!corner_moves(w, f, k, cluster, sc, dirs)) continue;
            for (const double step : kSmallSteps) {
              for (const Vec3& dir : dirs) {
                try_small_move(cluster, pos(w) + step * kSmallMove * o_.tolerance * r[i] * dir,
                               r[i], sc, op);
              }
            }
          }
          break;
        }
        case Move::kRelax: {
          // The corners on the shortest edge (a needle's two close corners, a cap's apex and
          // one end): moving the corner of the smallest angle changes that angle least, and
          // only a triangle below kHardAngleDeg tries it too. Only the corner whose move gives
          // the best fan before its projection onto the surface (which moves it along the
          // normal only) is projected and tried.
          CornerChoice& relax = resume.relax;
          if (!relax.chosen) {
            std::vector<std::uint32_t>& around = sc.around;
            relax.quality = std::max(op.quality, 0.0);
            for (const std::uint32_t w : f) {
              if (w == f[(k + 2) % 3] && !sc.relaxed) continue;
              // The centroid of the neighbours, in the tangent plane (the fan's area vector).
              ring(w, around);
              if (around.empty()) continue;
              Vec3 centroid = Vec3::Zero(), area = Vec3::Zero();
              for (const std::uint32_t x : around) centroid += pos(x);
              centroid /= static_cast<double>(around.size());
              for (std::uint32_t c = head_[w]; c != kNone; c = next_[c]) {
                area += normal(mesh_.triangles[c / 3]);
              }
              const double an = area.norm();
              if (!(an > 0)) continue;
              const Vec3 n = area / an;
              const Vec3 start = centroid - (centroid - pos(w)).dot(n) * n;
              double reach = 0;
              for (const std::uint32_t x : around)
                reach = std::max(reach, (pos(x) - pos(w)).norm());
              cluster.assign(1, w);
              if (!prepare_disk(cluster, sc)) continue;
              relax.offer(w, fan_quality(start, sc, false), start, 0.5 * reach, sc.old_worst);
            }
            relax.chosen = true;
          }
          try_corner(relax, cluster, sc, req, missing, op);
          break;
        }
      }
      // A level that lacked data is decided again once it is there; the next levels wait for
      // it (they are tried only when this one cannot make the triangle good).
      if (missing) return op;
      resume.level = level + 1;
      resume.failed = 0;
      resume.op = op;
      if (op.quality >= sin_bad_) return op;
    }
    return op;
  }

  // The disk of corner w of the bad triangle f alone (`cluster` = {w}, prepare_disk()) and the
  // directions a move of w takes there (move_directions() about the disk's area vector); false
  // when the disk cannot be prepared or has no area.
  bool corner_moves(std::uint32_t w, const Tri& f, int k, std::vector<std::uint32_t>& cluster,
                    Scratch& sc, MoveDirections& dirs) const {
    cluster.assign(1, w);
    if (!prepare_disk(cluster, sc)) return false;
    Vec3 area = Vec3::Zero();
    for (const Vec3& n : sc.old_normals) area += n;
    const double an = area.norm();
    if (!(an > 0)) return false;
    dirs = move_directions(f, k, area / an);
    return true;
  }

  // The directions in which a nudge or a small move takes a corner of the bad triangle f
  // (shortest edge k -> k + 1) whose fan has the unit area vector n: kNudgeDirections in the
  // tangent plane, from the triangle's longest edge (or any, when that lies along n), then n
  // and the shortest edge, both ways.
  MoveDirections move_directions(const Tri& f, int k, const Vec3& n) const {
    Vec3 e1 = pos(f[(k + 1) % 3]) - pos(f[(k + 2) % 3]);
    if (!((e1 - e1.dot(n) * n).squaredNorm() > 1e-6 * e1.squaredNorm())) {
      e1 = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    }
    e1 = (e1 - e1.dot(n) * n).normalized();
    const Vec3 e2 = n.cross(e1);
    const Vec3 along = (pos(f[k]) - pos(f[(k + 1) % 3])).normalized();
    std::array<Vec3, kNudgeDirections + 4> dirs;
    for (int j = 0; j < kNudgeDirections; ++j) {
      const double angle = 2.0 * std::numbers::pi * j / kNudgeDirections;
      dirs[j] = pm::cos(angle) * e1 + pm::sin(angle) * e2;
    }
    dirs[kNudgeDirections] = n;
    dirs[kNudgeDirections + 1] = -n;
    dirs[kNudgeDirections + 2] = along;
    dirs[kNudgeDirections + 3] = -along;
    return dirs;
  }

  // Whether a corner of f or one of their neighbours was touched by a change of this round.
  bool near_touched(const Tri& f) const {
    for (const std::uint32_t x : f) {
      if (touched_[x] != 0) return true;
      for (std::uint32_t c = head_[x]; c != kNone; c = next_[c]) {
        for (const std::uint32_t w : mesh_.triangles[c / 3]) {
          if (touched_[w] != 0) return true;
        }
      }
    }
    return false;
  }

  void unlink(std::uint32_t c) {
    std::uint32_t* p = &head_[mesh_.triangles[c / 3][c % 3]];
    while (*p != c) p = &next_[*p];
    *p = next_[c];
  }
  void link(std::uint32_t c) {
    const std::uint32_t v = mesh_.triangles[c / 3][c % 3];
    next_[c] = head_[v];
    head_[v] = c;
  }
  void mark(const Tri& f, std::vector<std::uint32_t>& touched) {
    for (const std::uint32_t w : f) {
      if (touched_[w] == 0) {
        touched_[w] = 1;
        touched.push_back(w);
      }
    }
  }

  void apply(const Op& op, std::vector<std::uint32_t>& touched, ImproveStats& st) {
    if (op.kind == Op::Kind::kFlip) {
      const std::uint32_t t1 = op.t;
      const Tri f1 = mesh_.triangles[t1];
      const std::uint32_t a = f1[op.k], b = f1[(op.k + 1) % 3], c = f1[(op.k + 2) % 3];
      std::uint32_t t2 = kNone;
      for (std::uint32_t corner = head_[a]; corner != kNone; corner = next_[corner]) {
        if (mesh_.triangles[corner / 3][(corner + 2) % 3] == b) t2 = corner / 3;
      }
      std::uint32_t d = kNone;
      for (const std::uint32_t w : mesh_.triangles[t2]) {
        if (w != a && w != b) d = w;
      }
      for (const std::uint32_t t : {t1, t2}) {
        for (std::uint32_t i = 0; i < 3; ++i) unlink(3 * t + i);
      }
      // (a, b, c), (b, a, d) -> (a, d, c), (d, b, c): every directed edge of the quad's
      // boundary is kept, so orientation and manifoldness stay.
      mesh_.triangles[t1] = {a, d, c};
      mesh_.triangles[t2] = {d, b, c};
      sines_[t1] = sine(mesh_.triangles[t1]);
      sines_[t2] = sine(mesh_.triangles[t2]);
      for (const std::uint32_t t : {t1, t2}) {
        for (std::uint32_t i = 0; i < 3; ++i) link(3 * t + i);
      }
      mark(mesh_.triangles[t1], touched);
      mark(mesh_.triangles[t2], touched);
      ++st.flips;
      return;
    }
    const auto z = static_cast<std::uint32_t>(mesh_.positions.size());
    mesh_.positions.push_back(op.z);
    radius_.push_back(op.z_radius);
    head_.push_back(kNone);
    touched_.push_back(0);
    const auto first = op.s.begin(), last = op.s.begin() + static_cast<std::ptrdiff_t>(op.ns);
    std::vector<std::uint32_t> disk;
    for (auto it = first; it != last; ++it) {
      for (std::uint32_t c = head_[*it]; c != kNone; c = next_[c]) disk.push_back(c / 3);
    }
    std::sort(disk.begin(), disk.end());
    disk.erase(std::unique(disk.begin(), disk.end()), disk.end());
    for (const std::uint32_t t : disk) {
      Tri& f = mesh_.triangles[t];
      mark(f, touched);
      int in = 0;
      for (const std::uint32_t w : f) in += std::binary_search(first, last, w) ? 1 : 0;
      for (std::uint32_t i = 0; i < 3; ++i) {
        if (in > 1 || std::binary_search(first, last, f[i])) unlink(3 * t + i);
      }
      if (in > 1) {
        alive_[t] = 0;
        continue;
      }
      for (std::uint32_t i = 0; i < 3; ++i) {
        if (std::binary_search(first, last, f[i])) {
          f[i] = z;
          link(3 * t + i);
        }
      }
      sines_[t] = sine(f);
    }
    mark({z, z, z}, touched);
    if (op.ns == 1) {
      ++st.relaxed;
    } else {
      ++st.collapses;
      st.clusters += op.ns > 2 ? 1 : 0;
    }
  }

  // The field's values and gradients at `points`. A field restricts each chunk of a batch to
  // the primitives near the chunk's box, and sorts a batch along a space-filling curve only
  // when it is large: the few points scattered over the tree that the last Newton steps and
  // stages ask for would each meet every primitive. The points are therefore sorted here along
  // a Morton curve and evaluated in groups of kGroup consecutive points (measured on the
  // 1,500-segment tree: the pass's evaluations take a third of the time the field's own
  // chunks of 128 take).
  void evaluate_field(std::span<const Vec3> points, std::span<double> value,
                      std::span<Vec3> grad) const {
    const std::size_t n = points.size();
    Aabb box;
    for (const Vec3& p : points) box.extend(p);
    const Vec3 lo = box.min();
    const double extent = std::max(box.diagonal().maxCoeff(), tol::kCoincident);
    auto spread = [](std::uint64_t v) {  // 21 bits -> every third bit of 63
      v &= 0x1fffff;
      v = (v | v << 32) & 0x1f00000000ffffull;
      v = (v | v << 16) & 0x1f0000ff0000ffull;
      v = (v | v << 8) & 0x100f00f00f00f00full;
      v = (v | v << 4) & 0x10c30c30c30c30c3ull;
      v = (v | v << 2) & 0x1249249249249249ull;
      return v;
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order(n);
    for (std::size_t i = 0; i < n; ++i) {
      std::uint64_t code = 0;
      for (int a = 0; a < 3; ++a) {
        const double x = std::clamp((points[i][a] - lo[a]) / extent, 0.0, 1.0);
        code |= spread(static_cast<std::uint64_t>(x * 2097151.0)) << a;
      }
      order[i] = {code, static_cast<std::uint32_t>(i)};
    }
    std::sort(order.begin(), order.end());
    parallel::for_chunks(
        (n + kGroup - 1) / kGroup, kGroupGrain,
        [&](std::size_t gb, std::size_t ge) {
          std::array<Vec3, kGroup> group, gg;
          std::array<double, kGroup> gv;
          for (std::size_t g = gb; g < ge; ++g) {
            const std::size_t b = g * kGroup, e = std::min(n, b + kGroup), m = e - b;
            for (std::size_t i = b; i < e; ++i) group[i - b] = points[order[i].second];
            field_.evaluate(std::span<const Vec3>(group.data(), m), std::span<double>(gv.data(), m),
                            std::span<Vec3>(gg.data(), m), threads_);
            for (std::size_t i = b; i < e; ++i) {
              value[order[i].second] = gv[i - b];
              grad[order[i].second] = gg[i - b];
            }
          }
        },
        threads_);
  }

  // Evaluates the requests (batches over the field and the skeleton) into the caches.
  void evaluate(Requests& r) {
    std::sort(r.radii.begin(), r.radii.end());
    r.radii.erase(std::unique(r.radii.begin(), r.radii.end()), r.radii.end());
    if (!r.radii.empty()) {
      std::vector<Vec3> at(r.radii.size());
      for (std::size_t i = 0; i < at.size(); ++i) at[i] = pos(r.radii[i]);
      const std::vector<double> rad = local_radii(skeleton_, at, threads_);
      for (std::size_t i = 0; i < r.radii.size(); ++i) radius_[r.radii[i]] = rad[i];
    }
    const double iso = field_.iso();
    // The projections first: the midpoints of each new vertex's edges to the vertices around
    // it join the stage's midpoints (as try_replace() will ask for them: not the edges short
    // enough to need no test).
    std::vector<Vec3> follow;
    std::vector<Vec3> z;
    std::vector<double> scale;
    std::vector<std::uint32_t> projections;
    std::vector<std::size_t> around_begin, around_end;
    std::size_t at = 0;
    for (std::size_t i = 0; i < r.starts.size(); ++i) {
      const std::size_t begin = at;
      at += r.around_count[i];
      bool fresh = false;
      const std::uint32_t e = projection_.insert(r.starts[i], fresh);
      if (!fresh) continue;
      z.push_back(r.starts[i]);
      scale.push_back(r.scales[i]);
      projections.push_back(e);
      around_begin.push_back(begin);
      around_end.push_back(at);
    }
    if (!z.empty()) {
      const std::size_t n = z.size();
      std::vector<char> ok(n, 0);
      std::vector<double> d0(n, 0.0);
      std::vector<Vec3> normal(n, Vec3::Zero());
      std::vector<std::size_t> active(n);
      for (std::size_t i = 0; i < n; ++i) active[i] = i;
      for (int step = 0; step < kNewtonSteps && !active.empty(); ++step) {
        std::vector<Vec3> pts(active.size());
        for (std::size_t j = 0; j < active.size(); ++j) pts[j] = z[active[j]];
        std::vector<double> v(active.size());
        std::vector<Vec3> g(active.size());
        evaluate_field(pts, v, g);
        std::vector<std::size_t> next;
        for (std::size_t j = 0; j < active.size(); ++j) {
          const std::size_t i = active[j];
          const double gg = g[j].squaredNorm();
          if (!std::isfinite(v[j]) || !(gg > 0.0) || !std::isfinite(gg)) continue;
          if (step == 0) d0[i] = std::abs(v[j] - iso) / std::sqrt(gg);
          normal[i] = -g[j] / std::sqrt(gg);
          if (std::abs(v[j] - iso) / std::sqrt(gg) <= tol::kRootFinding * scale[i]) {
            ok[i] = 1;
            continue;
          }
          const Vec3 s = ((v[j] - iso) / gg) * g[j];
          z[i] -= s;
          if (s.norm() <= kNewtonStop * scale[i]) {
            ok[i] = 1;
            continue;
          }
          next.push_back(i);
        }
        active = std::move(next);
      }
      for (std::size_t i = 0; i < n; ++i) {
        Projection& pr = projection_[projections[i]];
        pr.z = z[i];
        pr.start_distance = d0[i];
        pr.at_z.normal = normal[i];
        pr.radius = scale[i];
        pr.ok = ok[i] != 0;
        if (!pr.ok) continue;
        for (std::size_t k = around_begin[i]; k < around_end[i]; ++k) {
          const std::uint32_t w = r.around[k];
          const double rw = radius_[w];
          if ((z[i] - pos(w)).norm() <= kShortEdge * std::min(scale[i], rw)) continue;
          follow.push_back(0.5 * (z[i] + pos(w)));
        }
      }
    }
    // Each point once: the operations of a stage ask for many of the same midpoints (the edges
    // around a vertex, the same collapse seen from several bad triangles; 36-41 % of the
    // requests on the 10,000- and 30,000-segment trees).
    std::vector<Vec3> points;
    std::vector<std::uint32_t> probes;
    auto ask = [&](const Vec3& m) {
      bool fresh = false;
      const std::uint32_t e = probe_.insert(m, fresh);
      if (!fresh) return;
      points.push_back(m);
      probes.push_back(e);
    };
    for (const Vec3& m : r.midpoints) ask(m);
    for (const Vec3& m : follow) ask(m);
    if (!points.empty()) {
      std::vector<double> value(points.size());
      std::vector<Vec3> grad(points.size());
      evaluate_field(points, value, grad);
      for (std::size_t i = 0; i < value.size(); ++i) {
        const double g = grad[i].norm();
        Probe& pr = probe_[probes[i]];
        pr.distance = std::isfinite(value[i]) && g > 0 && std::isfinite(g)
                          ? std::abs(value[i] - iso) / g
                          : kInf;
        if (g > 0 && std::isfinite(g)) pr.normal = -grad[i] / g;
      }
    }
  }

  TriMesh& mesh_;
  const Field& field_;
  const Skeleton& skeleton_;
  const ImproveOptions& o_;
  const Context* threads_;
  double sin_bad_, sin_hard_, sin_last_, cos_turn_;
  bool small_moves_ = false;  // see last_resort()
  detail::BoxBvh nodes_;
  std::vector<char> alive_;
  std::vector<double> sines_;  // per triangle, min_angle_sine(), kept up to date
  // Corner chains: head_[v] is v's first corner, next_[c] the next corner of the same vertex
  // (kNone ends a chain); they list exactly the alive triangles around each vertex.
  std::vector<std::uint32_t> head_, next_;
  std::vector<double> radius_;  // local radius per vertex, NaN until asked for
  std::vector<char> touched_;
  PointCache<Probe> probe_;  // at edge midpoints
  PointCache<Projection> projection_;
};

}  // namespace

void improve_triangles(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                       const ImproveOptions& options, Context* ctx, ImproveStats* stats) {
  validate(options);
  if (skeleton.nodes.empty()) throw InvalidArgument("improve: the skeleton has no nodes");
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (v >= mesh.positions.size()) {
        throw InvalidArgument("improve: triangle " + std::to_string(t) + " refers to vertex " +
                              std::to_string(v) + ", the mesh has " +
                              std::to_string(mesh.positions.size()));
      }
    }
  }
  if (mesh.positions.size() >= kNone || 3 * mesh.triangles.size() >= kNone) {
    throw InvalidArgument(
        "improve: the mesh has too many vertices or triangles for 32-bit indices");
  }
  check_cancel(ctx);
  if (options.max_rounds == 0) {
    if (stats != nullptr) *stats = ImproveStats{};
    return;
  }
  // The loops that change the mesh get only the thread count: cancellation is looked at between
  // rounds, where the mesh is whole.
  const Context threads(ctx != nullptr ? ctx->threads() : 0);
  ImproveStats st;
  st.triangles_before = st.triangles_after = mesh.triangles.size();
  Improver im(mesh, field, skeleton, options, &threads);
  Scan first = im.scan_all();
  st.below_10_deg_before = st.below_10_deg_after = first.below_10;
  st.below_1_deg_before = st.below_1_deg_after = first.below_1;
  st.min_angle_deg_before = st.min_angle_deg_after = pm::asin(std::min(1.0, first.min_sine)) / kDeg;
  std::vector<std::uint32_t> bad = std::move(first.bad), next;
  std::size_t changes = 0;
  for (int round = 0; round < options.max_rounds && !bad.empty(); ++round) {
    if (ctx != nullptr && ctx->is_cancelled()) break;
    const std::size_t done = im.round(std::move(bad), next, st);
    bad = std::move(next);
    next = {};
    if (done == 0) break;
    changes += done;
    ++st.rounds;
    if (ctx != nullptr) ctx->report("improve", static_cast<double>(round + 1) / options.max_rounds);
  }
  // The last resort: triangles still below kLastResortDeg get up to kLastRounds more rounds in
  // which the small move is allowed (a mesh without such triangles stays as the rounds left it).
  for (int round = 0; round < kLastRounds; ++round) {
    if (ctx != nullptr && ctx->is_cancelled()) break;
    bad = im.last_resort();
    if (bad.empty()) break;
    const std::size_t done = im.round(std::move(bad), next, st);
    if (done == 0) break;
    changes += done;
    ++st.rounds;
  }
  if (changes > 0) {
    const Scan after = im.scan_kept();
    im.compact();
    st.below_10_deg_after = after.below_10;
    st.below_1_deg_after = after.below_1;
    st.min_angle_deg_after = pm::asin(std::min(1.0, after.min_sine)) / kDeg;
    st.triangles_after = mesh.triangles.size();
  }
  if (stats != nullptr) *stats = st;
  check_cancel(ctx);
}

}  // namespace ramiform
