// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The batched projection on the certified arcs of a Bezier curve (BezierProjector, degree
// 1..7), vectorized across points with Highway and dispatched at run time (no -march flags).
//
// Each lane runs BezierProjector::project_arcs<N> (bezier_curve.cpp) on its own point with the
// same IEEE operations in the same order: the scan of the arcs' spheres, the visit of the arc
// with the nearest centre, then of every arc that the bound found by that visit does not rule
// out (sphere and chord), each visit the certificate g' > 0, the sign test of g at the arc's
// ends, the Hermite start and the safeguarded Newton iteration (a mask per lane: a lane stops
// where the scalar loop returns). Arcs that are not certified for a lane (rare) go to the exact
// isolation through a callback, one lane at a time. So the nearest point, its parameter and the
// number of candidates are bit-identical to project(p), on every target (as in
// skeleton_field_simd.cpp: only + - * / sqrt, compares and selects, no fused multiply-add).
//
// A lane keeps the nearest candidate (the first of the least squared distance, as choose()
// takes it) and the least squared distance of the others. Where that is within kBezierNearTie
// (relative) of the nearest, choose()'s tie rule might matter: the lane is flagged (`redo`) and
// the caller projects that point one by one, so choose() decides exactly as before.
//
// Order of the work (none of it changes a lane's operations): the points are sorted by the arc
// with the nearest centre (counting sort), so that the lanes of a vector mostly share it and its
// visit reads one arc's constants, broadcast. A visit does the certificate, the sign test and
// the Hermite start for the lanes that need the arc, and queues their Newton runs (point, arc,
// start, stop); the queue runs in full vectors, two at a time (their dependent chains
// interleave), every lane with its own arc's constants (broadcast when the vector's runs share
// one arc, gathered otherwise). The first phase visits every point's nearest-centre arc; its
// runs finish before the second phase fixes each point's pruning bound and visits the other
// arcs, whose runs are independent of each other (the bound is not tightened within the phase).
// Its scan skips a group of 4 consecutive arcs when the group's sphere (holding theirs, inflated
// for rounding) is out of reach for every lane: then each of its arcs fails the per-arc test.
// The candidates of a point may thus arrive in another order than in project_arcs<N>, which
// changes nothing: the nearest and the second-nearest squared distance do not depend on it, and
// equal distances are redone one by one.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "field/bezier_curve_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "field/bezier_curve_simd.h"

HWY_BEFORE_NAMESPACE();
namespace ramiform::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// Lanes of the widest vector of any target (arrays that hold one vector).
constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);

// Per-point state of a batch, in the sorted order (slot k: the k-th point after sorting by the
// arc with the nearest centre; the last vector padded with copies of the last point): the query,
// that arc, the bound that prunes arcs (best2: the least squared distance to a known curve
// point), the nearest candidate so far (what choose() would pick when no two candidates are near
// a tie) and the least squared distance of the others, the counts (as doubles).
constexpr std::size_t kCap = kBezierBatch + kMaxLanes;
struct State {
  alignas(64) double qx[kCap], qy[kCap], qz[kCap], first[kCap];
  alignas(64) double best2[kCap];
  alignas(64) double bd2[kCap], bt[kCap], bx[kCap], by[kCap], bz[kCap], second[kCap];
  alignas(64) double interior[kCap], skipped[kCap];
};

// Newton runs waiting for full vectors: the slot of the point, the arc, the start s0 and the
// stop bound on g² (arc_root<N> in bezier_curve.cpp). Runs are independent of each other, so
// they are queued by the visits and run in full vectors whatever point or arc they come from.
constexpr std::size_t kFlush = 8 * kMaxLanes;  // run the queue once it holds this many
constexpr std::size_t kQueueCap = kFlush + 3 * kMaxLanes;
struct Queue {
  alignas(64) double slot[kQueueCap], arc[kQueueCap], s0[kQueueCap], stop[kQueueCap];
  alignas(64) double qx[kQueueCap], qy[kQueueCap], qz[kQueueCap];
  std::size_t count = 0;
  // Moves run `from` to `to`.
  void copy(std::size_t from, std::size_t to) {
    slot[to] = slot[from];
    arc[to] = arc[from];
    s0[to] = s0[from];
    stop[to] = stop[from];
    qx[to] = qx[from];
    qy[to] = qy[from];
    qz[to] = qz[from];
  }
};

// (a x + b y) + c z: a dot product in the scalar code's order.
HWY_INLINE V dot3(V ax, V ay, V az, V bx, V by, V bz) {
  return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
}

// A candidate (t, point) for the point in slot l: Candidates::add (the nearest so far kept as
// choose() would take it: the first of the least squared distance; the least of the others kept
// too), then best2 = min(best2, d2). The order of the candidates of a point does not change the
// result: `second` is the second least squared distance whatever the order, and where two are
// equally near the point is redone one by one.
inline void add_candidate(State& st, std::size_t l, double t, double x, double y, double z) {
  const double dx = x - st.qx[l], dy = y - st.qy[l], dz = z - st.qz[l];
  const double d2 = dx * dx + dy * dy + dz * dz;
  if (d2 < st.bd2[l]) {
    st.second[l] = st.bd2[l];
    st.bd2[l] = d2;
    st.bt[l] = t;
    st.bx[l] = x;
    st.by[l] = y;
    st.bz[l] = z;
  } else if (d2 < st.second[l]) {
    st.second[l] = d2;
  }
  if (d2 < st.best2[l]) st.best2[l] = d2;
  st.interior[l] += 1;
}

// g at arc end k (in t): C'(t_k)·(C(t_k) - q).
HWY_INLINE V g_end(D d, const BezierArcTable& a, std::size_t k, V qx, V qy, V qz) {
  return dot3(hn::Set(d, a.tx[k]), hn::Set(d, a.ty[k]), hn::Set(d, a.tz[k]),
              hn::Sub(hn::Set(d, a.px[k]), qx), hn::Sub(hn::Set(d, a.py[k]), qy),
              hn::Sub(hn::Set(d, a.pz[k]), qz));
}

// g' at arc end k (in t): |C'|² + C''·(C - q).
HWY_INLINE V g_slope(D d, const BezierArcTable& a, std::size_t k, V qx, V qy, V qz) {
  const double tt = a.tx[k] * a.tx[k] + a.ty[k] * a.ty[k] + a.tz[k] * a.tz[k];
  const V r =
      hn::Add(hn::Set(d, tt), hn::Mul(hn::Set(d, a.sx[k]), hn::Sub(hn::Set(d, a.px[k]), qx)));
  return hn::Add(hn::Add(r, hn::Mul(hn::Set(d, a.sy[k]), hn::Sub(hn::Set(d, a.py[k]), qy))),
                 hn::Mul(hn::Set(d, a.sz[k]), hn::Sub(hn::Set(d, a.pz[k]), qz)));
}

// One vector of queued Newton runs: every lane has its own arc, whose power-basis coefficients
// are given per lane, its query, its start, its stop bounds; then the iteration's state.
template <int N>
struct Runs {
  V ax[N + 1], ay[N + 1], az[N + 1];
  V qx, qy, qz, s0, tolerance, stop;
  V s, lo, hi, out_s;  // out_s: the root's parameter where found
  M active;
};

// One step of arc_root<N> (bezier_curve.cpp) on every active lane of `r`.
template <int N>
HWY_INLINE void newton_step(D d, Runs<N>& r) {
  const V zero = hn::Zero(d), two = hn::Set(d, 2.0), half = hn::Set(d, 0.5);
  const V s = r.s;
  // C, C' and C''/2 by Horner, the first two steps written out as in the scalar code.
  V cx = r.ax[N], cy = r.ay[N], cz = r.az[N];
  V ux = cx, uy = cy, uz = cz;        // C'
  V vx = zero, vy = zero, vz = zero;  // C'' / 2
  cx = hn::Add(hn::Mul(cx, s), r.ax[N - 1]);
  cy = hn::Add(hn::Mul(cy, s), r.ay[N - 1]);
  cz = hn::Add(hn::Mul(cz, s), r.az[N - 1]);
  if constexpr (N >= 2) {
    vx = ux;
    vy = uy;
    vz = uz;
    ux = hn::Add(hn::Mul(ux, s), cx);
    uy = hn::Add(hn::Mul(uy, s), cy);
    uz = hn::Add(hn::Mul(uz, s), cz);
    cx = hn::Add(hn::Mul(cx, s), r.ax[N - 2]);
    cy = hn::Add(hn::Mul(cy, s), r.ay[N - 2]);
    cz = hn::Add(hn::Mul(cz, s), r.az[N - 2]);
  }
  for (int j = N - 3; j >= 0; --j) {
    vx = hn::Add(hn::Mul(vx, s), ux);
    vy = hn::Add(hn::Mul(vy, s), uy);
    vz = hn::Add(hn::Mul(vz, s), uz);
    ux = hn::Add(hn::Mul(ux, s), cx);
    uy = hn::Add(hn::Mul(uy, s), cy);
    uz = hn::Add(hn::Mul(uz, s), cz);
    cx = hn::Add(hn::Mul(cx, s), r.ax[j]);
    cy = hn::Add(hn::Mul(cy, s), r.ay[j]);
    cz = hn::Add(hn::Mul(cz, s), r.az[j]);
  }
  const V rx = hn::Sub(cx, r.qx), ry = hn::Sub(cy, r.qy), rz = hn::Sub(cz, r.qz);
  const V g = dot3(ux, uy, uz, rx, ry, rz);
  // g == 0: the root itself.
  const M exact = hn::And(r.active, hn::Eq(g, zero));
  r.out_s = hn::IfThenElse(exact, s, r.out_s);
  const M active = hn::AndNot(exact, r.active);
  const M negative = hn::Lt(g, zero);
  r.lo = hn::IfThenElse(hn::And(active, negative), s, r.lo);
  r.hi = hn::IfThenElse(hn::AndNot(negative, active), s, r.hi);
  const V gp = hn::Add(dot3(ux, uy, uz, ux, uy, uz), hn::Mul(two, dot3(vx, vy, vz, rx, ry, rz)));
  const V step = hn::Div(g, gp);
  const V next = hn::Sub(s, step);
  const M inside = hn::And(hn::Gt(gp, zero), hn::And(hn::Gt(next, r.lo), hn::Lt(next, r.hi)));
  // Outside the bracket (or g' <= 0): bisection; done once the bracket is below tolerance.
  const M bisect = hn::AndNot(inside, active);
  const V mid = hn::Mul(half, hn::Add(r.lo, r.hi));
  const M bisect_done = hn::And(bisect, hn::Le(hn::Sub(r.hi, r.lo), r.tolerance));
  r.out_s = hn::IfThenElse(bisect_done, mid, r.out_s);
  // Inside: done once g² <= stop or the step is below tolerance.
  const M newton = hn::And(inside, active);
  const M newton_done =
      hn::And(newton, hn::Or(hn::Le(hn::Mul(g, g), r.stop), hn::Le(hn::Abs(step), r.tolerance)));
  r.out_s = hn::IfThenElse(newton_done, next, r.out_s);
  r.s = hn::IfThenElse(bisect, mid, hn::IfThenElse(newton, next, s));
  r.active = hn::AndNot(hn::Or(bisect_done, newton_done), active);
}

// The roots of g for G vectors of runs (arc_root<N> in bezier_curve.cpp, in lockstep with a mask
// per lane): the G chains of dependent steps are interleaved to hide their latency. A lane that
// is done (or a vector whose lanes all are) is left unchanged by further steps. Returns each
// lane's parameter s and point.
template <int N, int G>
HWY_INLINE void arc_roots(D d, Runs<N>* r, V* out_s, V* ox, V* oy, V* oz) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), half = hn::Set(d, 0.5);
  for (int g = 0; g < G; ++g) {
    r[g].lo = zero;
    r[g].hi = one;
    r[g].s = hn::IfThenElse(hn::And(hn::Gt(r[g].s0, zero), hn::Lt(r[g].s0, one)), r[g].s0, half);
    r[g].out_s = r[g].s;
    r[g].active = hn::Eq(zero, zero);
  }
  for (int it = 0; it < kBezierMaxRootIterations; ++it) {
    M any = r[0].active;
    for (int g = 1; g < G; ++g) any = hn::Or(any, r[g].active);
    if (hn::AllFalse(d, any)) break;
    for (int g = 0; g < G; ++g) newton_step<N>(d, r[g]);
  }
  for (int g = 0; g < G; ++g) {
    // Out of iterations: where it stopped.
    const V s = hn::IfThenElse(r[g].active, r[g].s, r[g].out_s);
    // The point: C(s) by Horner (power_point in bezier_curve.cpp; where g == 0 these are the
    // operations that gave the last step's C).
    V x = r[g].ax[N], y = r[g].ay[N], z = r[g].az[N];
    for (int j = N - 1; j >= 0; --j) {
      x = hn::Add(hn::Mul(x, s), r[g].ax[j]);
      y = hn::Add(hn::Mul(y, s), r[g].ay[j]);
      z = hn::Add(hn::Mul(z, s), r[g].az[j]);
    }
    out_s[g] = s;
    ox[g] = x;
    oy[g] = y;
    oz[g] = z;
  }
}

// Runs the queued Newton runs in full vectors, two at a time, and adds their roots to their
// points: all of them when `all` (the last vector padded with copies of the last run), else
// only whole vectors (the rest stays queued).
template <int N>
HWY_NOINLINE void run_queue(D d, const BezierArcTable& a, State& st, Queue& queue, bool all) {
  using DI = hn::RebindToSigned<D>;
  const DI di;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t K = static_cast<std::size_t>(a.count);
  const std::size_t count = queue.count;
  if (count == 0) return;
  const std::size_t runs = all ? (count + lanes - 1) / lanes * lanes : count / lanes * lanes;
  for (std::size_t k = count; k < runs; ++k) queue.copy(count - 1, k);
  // The constants of the arcs of the runs at k: broadcast when they share one arc (the usual
  // case in the first phase, where points come sorted by arc), else gathered.
  auto prepare = [&](std::size_t k, Runs<N>& r, V& t0, V& span) {
    const V arc_v = hn::Load(d, queue.arc + k);
    const bool uniform = hn::AllTrue(d, hn::Eq(arc_v, hn::Set(d, queue.arc[k])));
    const std::size_t arc0 = static_cast<std::size_t>(queue.arc[k]);
    const auto arc = hn::ConvertTo(di, arc_v);
    auto load = [&](const double* base) {
      return uniform ? hn::Set(d, base[arc0]) : hn::GatherIndex(d, base, arc);
    };
    for (int j = 0; j <= N; ++j) {
      const std::size_t o = static_cast<std::size_t>(j) * K;
      r.ax[j] = load(a.ax.data() + o);
      r.ay[j] = load(a.ay.data() + o);
      r.az[j] = load(a.az.data() + o);
    }
    r.qx = hn::Load(d, queue.qx + k);
    r.qy = hn::Load(d, queue.qy + k);
    r.qz = hn::Load(d, queue.qz + k);
    r.s0 = hn::Load(d, queue.s0 + k);
    r.tolerance = load(a.tolerance.data());
    r.stop = hn::Load(d, queue.stop + k);
    t0 = load(a.t0.data());
    span = load(a.span.data());
  };
  auto finish = [&](std::size_t k, V t0, V span, V s, V x, V y, V z) {
    alignas(64) double rt[kMaxLanes], rx[kMaxLanes], ry[kMaxLanes], rz[kMaxLanes];
    hn::Store(hn::Add(t0, hn::Mul(s, span)), d, rt);
    hn::Store(x, d, rx);
    hn::Store(y, d, ry);
    hn::Store(z, d, rz);
    const std::size_t valid = std::min(lanes, count - std::min(count, k));
    for (std::size_t l = 0; l < valid; ++l) {
      add_candidate(st, static_cast<std::size_t>(queue.slot[k + l]), rt[l], rx[l], ry[l], rz[l]);
    }
  };
  std::size_t k = 0;
  for (; k + 2 * lanes <= runs; k += 2 * lanes) {
    Runs<N> r[2];
    V t0[2], span[2], s[2], x[2], y[2], z[2];
    prepare(k, r[0], t0[0], span[0]);
    prepare(k + lanes, r[1], t0[1], span[1]);
    arc_roots<N, 2>(d, r, s, x, y, z);
    finish(k, t0[0], span[0], s[0], x[0], y[0], z[0]);
    finish(k + lanes, t0[1], span[1], s[1], x[1], y[1], z[1]);
  }
  if (k < runs) {
    Runs<N> r[1];
    V t0, span, s, x, y, z;
    prepare(k, r[0], t0, span);
    arc_roots<N, 1>(d, r, &s, &x, &y, &z);
    finish(k, t0, span, s, x, y, z);
  }
  // Whatever was not run moves to the front.
  const std::size_t rest = count > runs ? count - runs : 0;
  for (std::size_t k2 = 0; k2 < rest; ++k2) queue.copy(runs + k2, k2);
  queue.count = rest;
}

// The exact isolation on arc i for the lanes of `m` of the vector at slot `base`, one lane at a
// time (the uncertified branch of visit() in project_arcs<N>).
template <int N>
HWY_NOINLINE void isolate_lanes(D d, const BezierArcTable& a, std::size_t i, std::size_t base, M m,
                                State& st, BezierArcIsolation isolate, const void* projector) {
  const std::size_t K = static_cast<std::size_t>(a.count);
  std::uint8_t bits[(kMaxLanes + 7) / 8] = {};
  hn::StoreMaskBits(d, m, bits);
  const double t0 = a.t0[i], span = a.span[i];
  for (std::size_t l = 0; l < hn::Lanes(d); ++l) {
    if (((bits[l / 8] >> (l % 8)) & 1) == 0) continue;
    const std::size_t slot = base + l;
    const double q[3] = {st.qx[slot], st.qy[slot], st.qz[slot]};
    std::array<double, 32> roots;
    int skipped = 0;
    const int found = isolate(projector, static_cast<int>(i), q, roots.data(), &skipped);
    st.skipped[slot] += skipped;
    for (int k = 0; k < found; ++k) {
      const double sk = roots[static_cast<std::size_t>(k)];
      if (!(sk >= 0 && sk <= 1)) continue;
      const double t = t0 + sk * span;
      if (!(t > 0 && t < 1)) continue;
      double x = a.ax[N * K + i], y = a.ay[N * K + i], z = a.az[N * K + i];
      for (int j = N - 1; j >= 0; --j) {
        const std::size_t o = static_cast<std::size_t>(j) * K + i;
        x = x * sk + a.ax[o];
        y = y * sk + a.ay[o];
        z = z * sk + a.az[o];
      }
      add_candidate(st, slot, t, x, y, z);
    }
  }
}

// visit(i) of project_arcs<N> for the lanes of `m` of the vector at slot `base` (query q;
// (dx, dy, dz) = centre of arc i - q and dc2 its squared norm): the certificate, the sign test
// of g at the arc's ends and the Hermite start; the Newton run itself is queued.
template <int N>
HWY_INLINE void visit(D d, const BezierArcTable& a, std::size_t i, std::size_t base, M m, V qx,
                      V qy, V qz, V dx, V dy, V dz, V dc2, State& st, Queue& queue,
                      BezierArcIsolation isolate, const void* projector) {
  const std::size_t K = static_cast<std::size_t>(a.count);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  // A lower bound of g' on the arc (in s).
  V bend = zero;
  if constexpr (N > 1) {
    bend = hn::Set(d, std::numeric_limits<double>::infinity());
    for (int j = 0; j + 1 < N; ++j) {
      const std::size_t o = static_cast<std::size_t>(j) * K + i;
      const V v = dot3(hn::Set(d, a.ex[o]), hn::Set(d, a.ey[o]), hn::Set(d, a.ez[o]), dx, dy, dz);
      bend = hn::IfThenElse(hn::Lt(v, bend), v, bend);  // std::min(bend, v)
    }
  }
  const V slope = hn::Add(hn::Set(d, a.floor[i]), bend);
  const V rounding = hn::Mul(hn::Set(d, kBezierSlopeRounding * a.second_max[i]),
                             hn::Add(hn::Add(hn::Abs(dx), hn::Abs(dy)), hn::Abs(dz)));
  const M certified = hn::Gt(slope, rounding);
  const M fallback = hn::AndNot(certified, m);
  // Certified: g increasing on the arc, one minimum inside when g goes from - to +.
  const V g0 = g_end(d, a, i, qx, qy, qz);
  const V g1 = g_end(d, a, i + 1, qx, qy, qz);
  const M root = hn::And(hn::And(m, certified), hn::And(hn::Lt(g0, zero), hn::Ge(g1, zero)));
  if (!hn::AllFalse(d, root)) {
    const double span = a.span[i];
    const V g2 = hn::Add(
        hn::Set(d, a.g2_fixed[i]),
        hn::Mul(hn::Set(d, a.g2_per_distance[i]), hn::Add(hn::Sqrt(dc2), hn::Set(d, a.radius[i]))));
    const V cube = hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 2 * a.tolerance[i]), slope), slope), slope);
    const V stop = hn::IfThenElse(hn::Gt(g2, zero), hn::Div(cube, g2),
                                  hn::Set(d, std::numeric_limits<double>::infinity()));
    // Start: the root of g's cubic Hermite interpolant by one Newton step from the chord's.
    const V m0 = hn::Mul(hn::Set(d, span), g_slope(d, a, i, qx, qy, qz));
    const V m1 = hn::Mul(hn::Set(d, span), g_slope(d, a, i + 1, qx, qy, qz));
    V s0 = hn::Div(g0, hn::Sub(g0, g1));
    {
      const V two = hn::Set(d, 2.0), three = hn::Set(d, 3.0), four = hn::Set(d, 4.0),
              six = hn::Set(d, 6.0);
      const V u = s0, u2 = hn::Mul(u, u), u3 = hn::Mul(u2, u);
      const V h = hn::Add(
          hn::Add(hn::Add(hn::Mul(g0, hn::Add(hn::Sub(hn::Mul(two, u3), hn::Mul(three, u2)), one)),
                          hn::Mul(g1, hn::Sub(hn::Mul(three, u2), hn::Mul(two, u3)))),
                  hn::Mul(m0, hn::Add(hn::Sub(u3, hn::Mul(two, u2)), u))),
          hn::Mul(m1, hn::Sub(u3, u2)));
      const V dh =
          hn::Add(hn::Add(hn::Mul(hn::Sub(g1, g0), hn::Sub(hn::Mul(six, u), hn::Mul(six, u2))),
                          hn::Mul(m0, hn::Add(hn::Sub(hn::Mul(three, u2), hn::Mul(four, u)), one))),
                  hn::Mul(m1, hn::Sub(hn::Mul(three, u2), hn::Mul(two, u))));
      const V next = hn::Sub(u, hn::Div(h, dh));
      const M ok = hn::And(hn::Gt(dh, zero), hn::And(hn::Gt(next, zero), hn::Lt(next, one)));
      s0 = hn::IfThenElse(ok, next, s0);
    }
    // Appended lane by lane (Highway's Compress for 64-bit lanes copies a table per call, and a
    // compressing store to memory is microcoded on some CPUs).
    alignas(64) double lane_s0[kMaxLanes], lane_stop[kMaxLanes];
    hn::Store(s0, d, lane_s0);
    hn::Store(stop, d, lane_stop);
    std::uint8_t bits[(kMaxLanes + 7) / 8] = {};
    hn::StoreMaskBits(d, root, bits);
    std::size_t at = queue.count;
    for (std::size_t l = 0; l < hn::Lanes(d); ++l) {
      if (((bits[l / 8] >> (l % 8)) & 1) == 0) continue;
      queue.slot[at] = static_cast<double>(base + l);
      queue.arc[at] = static_cast<double>(i);
      queue.s0[at] = lane_s0[l];
      queue.stop[at] = lane_stop[l];
      queue.qx[at] = st.qx[base + l];
      queue.qy[at] = st.qy[base + l];
      queue.qz[at] = st.qz[base + l];
      ++at;
    }
    queue.count = at;
  }
  // Not certified: the exact isolation on the arc (Rigaudière et al. §3.4).
  if (!hn::AllFalse(d, fallback)) isolate_lanes<N>(d, a, i, base, fallback, st, isolate, projector);
}

template <int N>
void project_batch(const BezierArcTable& a, const double* qx, const double* qy, const double* qz,
                   std::size_t n, BezierArcIsolation isolate, const void* projector,
                   BezierLaneResult* out) {
  const D d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t K = static_cast<std::size_t>(a.count);
  const std::size_t padded = (n + lanes - 1) / lanes * lanes;
  // Padded copies (the last point repeated), then the nearest centre of each point.
  alignas(64) double px[kCap], py[kCap], pz[kCap], first[kCap];
  for (std::size_t k = 0; k < padded; ++k) {
    const std::size_t src = std::min(k, n - 1);
    px[k] = qx[src];
    py[k] = qy[src];
    pz[k] = qz[src];
  }
  // Two vectors at a time: their chains of compares are independent.
  auto nearest = [&](auto group, std::size_t k) {
    constexpr int G = decltype(group)::value;
    V x[G], y[G], z[G], best[G], index[G];
    for (int g = 0; g < G; ++g) {
      x[g] = hn::Load(d, px + k + g * lanes);
      y[g] = hn::Load(d, py + k + g * lanes);
      z[g] = hn::Load(d, pz + k + g * lanes);
      best[g] = hn::Set(d, std::numeric_limits<double>::infinity());
      index[g] = hn::Zero(d);
    }
    V arc = hn::Zero(d);  // i, as a double in every lane
    const V step = hn::Set(d, 1.0);
    for (std::size_t i = 0; i < K; ++i, arc = hn::Add(arc, step)) {
      const V cx = hn::Set(d, a.cx[i]), cy = hn::Set(d, a.cy[i]), cz = hn::Set(d, a.cz[i]);
      for (int g = 0; g < G; ++g) {
        const V dx = hn::Sub(cx, x[g]), dy = hn::Sub(cy, y[g]), dz = hn::Sub(cz, z[g]);
        const V d2 = dot3(dx, dy, dz, dx, dy, dz);
        const M nearer = hn::Lt(d2, best[g]);
        best[g] = hn::IfThenElse(nearer, d2, best[g]);
        index[g] = hn::IfThenElse(nearer, arc, index[g]);
      }
    }
    for (int g = 0; g < G; ++g) hn::Store(index[g], d, first + k + g * lanes);
  };
  std::size_t k0 = 0;
  for (; k0 + 2 * lanes <= padded; k0 += 2 * lanes) nearest(std::integral_constant<int, 2>(), k0);
  if (k0 < padded) nearest(std::integral_constant<int, 1>(), k0);
  // Counting sort of the points by that arc (stable), then the sorted, padded copies.
  std::array<std::uint16_t, kCap> order;
  {
    std::array<std::uint16_t, 65> start{};
    for (std::size_t k = 0; k < n; ++k) ++start[static_cast<std::size_t>(first[k]) + 1];
    for (std::size_t i = 1; i <= K; ++i) start[i] += start[i - 1];
    for (std::size_t k = 0; k < n; ++k)
      order[start[static_cast<std::size_t>(first[k])]++] = static_cast<std::uint16_t>(k);
    for (std::size_t k = n; k < padded; ++k) order[k] = order[n - 1];
  }
  State st;
  for (std::size_t k = 0; k < padded; ++k) {
    st.qx[k] = px[order[k]];
    st.qy[k] = py[order[k]];
    st.qz[k] = pz[order[k]];
    st.first[k] = first[order[k]];
  }
  Queue queue;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  // The first phase: the two ends of the curve, then the arc with the nearest centre, lanes
  // grouped by it.
  for (std::size_t k = 0; k < padded; k += lanes) {
    const V vx = hn::Load(d, st.qx + k), vy = hn::Load(d, st.qy + k), vz = hn::Load(d, st.qz + k);
    const V vfirst = hn::Load(d, st.first + k);
    auto end_d2 = [&](std::size_t e) {
      const V dx = hn::Sub(hn::Set(d, a.px[e]), vx);
      const V dy = hn::Sub(hn::Set(d, a.py[e]), vy);
      const V dz = hn::Sub(hn::Set(d, a.pz[e]), vz);
      return dot3(dx, dy, dz, dx, dy, dz);
    };
    const V d0 = end_d2(0), d1 = end_d2(K);
    const M better = hn::Lt(d1, d0);
    hn::Store(hn::IfThenElse(better, d0, d1), d, st.second + k);
    hn::Store(hn::IfThenElse(better, d1, d0), d, st.bd2 + k);
    hn::Store(hn::IfThenElseZero(better, one), d, st.bt + k);
    hn::Store(hn::IfThenElse(better, hn::Set(d, a.px[K]), hn::Set(d, a.px[0])), d, st.bx + k);
    hn::Store(hn::IfThenElse(better, hn::Set(d, a.py[K]), hn::Set(d, a.py[0])), d, st.by + k);
    hn::Store(hn::IfThenElse(better, hn::Set(d, a.pz[K]), hn::Set(d, a.pz[0])), d, st.bz + k);
    hn::Store(zero, d, st.interior + k);
    hn::Store(zero, d, st.skipped + k);
    const V ends = hn::Min(d0, d1);
    hn::Store(ends, d, st.best2 + k);
    alignas(64) double firsts[kMaxLanes];
    hn::Store(vfirst, d, firsts);
    M pending = hn::Eq(zero, zero);
    while (!hn::AllFalse(d, pending)) {
      const std::size_t f = static_cast<std::size_t>(firsts[hn::FindFirstTrue(d, pending)]);
      const M m = hn::And(pending, hn::Eq(vfirst, hn::Set(d, static_cast<double>(f))));
      pending = hn::AndNot(m, pending);
      // Upper bound of the nearest distance: the curve's ends and this arc's ends.
      hn::Store(hn::IfThenElse(m, hn::Min(hn::Min(ends, end_d2(f)), end_d2(f + 1)),
                               hn::Load(d, st.best2 + k)),
                d, st.best2 + k);
      const V dx = hn::Sub(hn::Set(d, a.cx[f]), vx);
      const V dy = hn::Sub(hn::Set(d, a.cy[f]), vy);
      const V dz = hn::Sub(hn::Set(d, a.cz[f]), vz);
      visit<N>(d, a, f, k, m, vx, vy, vz, dx, dy, dz, dot3(dx, dy, dz, dx, dy, dz), st, queue,
               isolate, projector);
      if (queue.count >= kFlush) run_queue<N>(d, a, st, queue, false);
    }
  }
  run_queue<N>(d, a, st, queue, true);
  // The second phase: every other arc whose sphere is not farther than the best point that the
  // first phase found (the bound is not tightened during this phase, so its visits are
  // independent of each other).
  const V slack = hn::Set(d, 1 + kBezierPruneSlack);
  for (std::size_t k = 0; k < padded; k += lanes) {
    const V vx = hn::Load(d, st.qx + k), vy = hn::Load(d, st.qy + k), vz = hn::Load(d, st.qz + k);
    const V vfirst = hn::Load(d, st.first + k);
    const V prune = hn::Mul(hn::Sqrt(hn::Load(d, st.best2 + k)), slack);
    for (std::size_t i = 0; i < K; ++i) {
      if (i % kBezierGroup == 0) {
        // The whole group is out of reach for every lane: its arcs fail the sphere test below
        // (the group sphere holds theirs, inflated; the test here has a further 1e-10 margin).
        const std::size_t g = i / kBezierGroup;
        const V gx = hn::Sub(hn::Set(d, a.gx[g]), vx);
        const V gy = hn::Sub(hn::Set(d, a.gy[g]), vy);
        const V gz = hn::Sub(hn::Set(d, a.gz[g]), vz);
        const V glim = hn::Add(hn::Set(d, a.gradius[g]), prune);
        const V glim2 = hn::Mul(hn::Mul(glim, glim), hn::Set(d, 1 + 1e-10));
        if (hn::AllTrue(d, hn::Gt(dot3(gx, gy, gz, gx, gy, gz), glim2))) {
          i += kBezierGroup - 1;
          continue;
        }
      }
      const V dx = hn::Sub(hn::Set(d, a.cx[i]), vx);
      const V dy = hn::Sub(hn::Set(d, a.cy[i]), vy);
      const V dz = hn::Sub(hn::Set(d, a.cz[i]), vz);
      const V dc2 = dot3(dx, dy, dz, dx, dy, dz);
      const V lim = hn::Add(hn::Set(d, a.radius[i]), prune);
      M m = hn::Not(hn::Or(hn::Eq(vfirst, hn::Set(d, static_cast<double>(i))),
                           hn::Gt(dc2, hn::Mul(lim, lim))));
      if (hn::AllFalse(d, m)) continue;
      // The second bound: the distance to the arc's chord less its deviation from it.
      const V ux = hn::Set(d, a.ux[i]), uy = hn::Set(d, a.uy[i]), uz = hn::Set(d, a.uz[i]);
      const V wx = hn::Sub(vx, hn::Set(d, a.px[i]));
      const V wy = hn::Sub(vy, hn::Set(d, a.py[i]));
      const V wz = hn::Sub(vz, hn::Set(d, a.pz[i]));
      V along = hn::Mul(dot3(wx, wy, wz, ux, uy, uz), hn::Set(d, a.inv_chord2[i]));
      along = hn::IfThenElse(hn::Lt(along, zero), zero, along);
      along = hn::IfThenElse(hn::Gt(along, one), one, along);
      const V rx = hn::Sub(wx, hn::Mul(along, ux));
      const V ry = hn::Sub(wy, hn::Mul(along, uy));
      const V rz = hn::Sub(wz, hn::Mul(along, uz));
      const V chord_lim = hn::Add(prune, hn::Set(d, a.deviation[i]));
      m = hn::AndNot(hn::Gt(dot3(rx, ry, rz, rx, ry, rz), hn::Mul(chord_lim, chord_lim)), m);
      if (hn::AllFalse(d, m)) continue;
      visit<N>(d, a, i, k, m, vx, vy, vz, dx, dy, dz, dc2, st, queue, isolate, projector);
      if (queue.count >= kFlush) run_queue<N>(d, a, st, queue, false);
    }
  }
  run_queue<N>(d, a, st, queue, true);
  for (std::size_t k = 0; k < padded; k += lanes) {
    // A tie within choose()'s limit is possible: the caller decides it one by one.
    const V bd2 = hn::Load(d, st.bd2 + k);
    const M near =
        hn::Le(hn::Sub(hn::Load(d, st.second + k), bd2), hn::Mul(hn::Set(d, kBezierNearTie), bd2));
    alignas(64) double redo[kMaxLanes], distance[kMaxLanes];
    hn::Store(hn::IfThenElseZero(near, one), d, redo);
    hn::Store(hn::Sqrt(bd2), d, distance);
    for (std::size_t l = 0; l < lanes && k + l < n; ++l) {
      const std::size_t slot = k + l;
      BezierLaneResult& r = out[order[slot]];
      r.t = st.bt[slot];
      r.d2 = st.bd2[slot];
      r.distance = distance[l];
      r.x = st.bx[slot];
      r.y = st.by[slot];
      r.z = st.bz[slot];
      r.counted = static_cast<int>(st.interior[slot] + st.skipped[slot]);
      r.redo = redo[l] != 0;
    }
  }
}

void ProjectArcsBatch(const BezierArcTable& a, const double* qx, const double* qy, const double* qz,
                      std::size_t n, BezierArcIsolation isolate, const void* projector,
                      BezierLaneResult* out) {
  if (n == 0) return;
  switch (a.degree) {
    case 1:
      return project_batch<1>(a, qx, qy, qz, n, isolate, projector, out);
    case 2:
      return project_batch<2>(a, qx, qy, qz, n, isolate, projector, out);
    case 3:
      return project_batch<3>(a, qx, qy, qz, n, isolate, projector, out);
    case 4:
      return project_batch<4>(a, qx, qy, qz, n, isolate, projector, out);
    case 5:
      return project_batch<5>(a, qx, qy, qz, n, isolate, projector, out);
    case 6:
      return project_batch<6>(a, qx, qy, qz, n, isolate, projector, out);
    case 7:
      return project_batch<7>(a, qx, qy, qz, n, isolate, projector, out);
    default:
      return;
  }
}

std::int64_t BezierDispatchedTarget() { return HWY_TARGET; }

}  // namespace HWY_NAMESPACE
}  // namespace ramiform::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ramiform::detail {

HWY_EXPORT(ProjectArcsBatch);

void project_arcs_batch(const BezierArcTable& table, const double* qx, const double* qy,
                        const double* qz, std::size_t n, BezierArcIsolation isolate,
                        const void* projector, BezierLaneResult* out) {
  HWY_DYNAMIC_DISPATCH(ProjectArcsBatch)(table, qx, qy, qz, n, isolate, projector, out);
}

HWY_EXPORT(BezierDispatchedTarget);

std::int64_t bezier_dispatched_target() { return HWY_DYNAMIC_DISPATCH(BezierDispatchedTarget)(); }

}  // namespace ramiform::detail
#endif  // HWY_ONCE
