// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The batched projection on the certified arcs of a Bezier curve (BezierProjector, degree
// 1..7), vectorized across points with Highway and dispatched at run time (no -march flags).
//
// Each lane runs BezierProjector::project_arcs<N> (bezier_curve.cpp) on its own point with the
// same IEEE operations in the same order: the scan of the arcs' spheres, the visit of the arc
// with the nearest centre, then of every arc whose sphere is not farther than the best point
// found, each visit the certificate g' > 0, the sign test of g at the arc's ends, the Hermite
// start and the safeguarded Newton iteration (run in lockstep with a mask per lane: a lane stops
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
// Arcs are per lane: the arc with the nearest centre differs between points. Points are sorted
// by it (counting sort) so that the lanes of a vector mostly share it and every visit reads one
// arc's constants, broadcast to all lanes, with no gathers. Visits of other arcs go arc by arc
// over the vector with the mask of the lanes that need them.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "field/bezier_curve_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

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

// The state of the lanes of one vector: the query, the arc with the nearest centre, the bound
// that prunes arcs (best2: the least squared distance to a known curve point), and the nearest
// candidate so far (what choose() would pick when no two candidates are near a tie).
struct Lanes {
  V qx, qy, qz;
  V first;  // index of the arc with the nearest centre
  V best2;
  V bd2, bt, bx, by, bz;
  V second;             // the least squared distance of the other candidates
  V interior, skipped;  // counts (as doubles)
};

// The same state spilled to memory, for the lanes that take the scalar fallback.
struct LaneArrays {
  alignas(64) double qx[kMaxLanes], qy[kMaxLanes], qz[kMaxLanes];
  alignas(64) double best2[kMaxLanes];
  alignas(64) double bd2[kMaxLanes], bt[kMaxLanes], bx[kMaxLanes], by[kMaxLanes], bz[kMaxLanes];
  alignas(64) double second[kMaxLanes], interior[kMaxLanes], skipped[kMaxLanes];
};

HWY_INLINE void spill(D d, const Lanes& s, LaneArrays& a) {
  hn::Store(s.qx, d, a.qx);
  hn::Store(s.qy, d, a.qy);
  hn::Store(s.qz, d, a.qz);
  hn::Store(s.best2, d, a.best2);
  hn::Store(s.bd2, d, a.bd2);
  hn::Store(s.bt, d, a.bt);
  hn::Store(s.bx, d, a.bx);
  hn::Store(s.by, d, a.by);
  hn::Store(s.bz, d, a.bz);
  hn::Store(s.interior, d, a.interior);
  hn::Store(s.skipped, d, a.skipped);
  hn::Store(s.second, d, a.second);
}

HWY_INLINE void fill(D d, const LaneArrays& a, Lanes& s) {
  s.best2 = hn::Load(d, a.best2);
  s.bd2 = hn::Load(d, a.bd2);
  s.bt = hn::Load(d, a.bt);
  s.bx = hn::Load(d, a.bx);
  s.by = hn::Load(d, a.by);
  s.bz = hn::Load(d, a.bz);
  s.interior = hn::Load(d, a.interior);
  s.skipped = hn::Load(d, a.skipped);
  s.second = hn::Load(d, a.second);
}

// (a x + b y) + c z: a dot product in the scalar code's order.
HWY_INLINE V dot3(V ax, V ay, V az, V bx, V by, V bz) {
  return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
}

// A candidate (t, point) for the lanes of `m`: Candidates::add (the nearest so far kept as
// choose() would take it: the first of the least squared distance; the least of the others
// kept too), then best2 = min(best2, d2).
HWY_INLINE void add_candidate(D d, Lanes& s, M m, V t, V x, V y, V z) {
  const V dx = hn::Sub(x, s.qx), dy = hn::Sub(y, s.qy), dz = hn::Sub(z, s.qz);
  const V d2 = dot3(dx, dy, dz, dx, dy, dz);
  const M better = hn::And(m, hn::Lt(d2, s.bd2));
  s.second =
      hn::IfThenElse(better, s.bd2, hn::IfThenElse(hn::And(m, hn::Lt(d2, s.second)), d2, s.second));
  s.bd2 = hn::IfThenElse(better, d2, s.bd2);
  s.bt = hn::IfThenElse(better, t, s.bt);
  s.bx = hn::IfThenElse(better, x, s.bx);
  s.by = hn::IfThenElse(better, y, s.by);
  s.bz = hn::IfThenElse(better, z, s.bz);
  s.best2 = hn::IfThenElse(hn::And(m, hn::Lt(d2, s.best2)), d2, s.best2);
  s.interior = hn::IfThenElse(m, hn::Add(s.interior, hn::Set(d, 1.0)), s.interior);
}

// The same for one lane in memory (candidates of the isolation fallback).
inline void add_candidate(LaneArrays& a, std::size_t l, double t, double x, double y, double z) {
  const double dx = x - a.qx[l], dy = y - a.qy[l], dz = z - a.qz[l];
  const double d2 = dx * dx + dy * dy + dz * dz;
  if (d2 < a.bd2[l]) {
    a.second[l] = a.bd2[l];
    a.bd2[l] = d2;
    a.bt[l] = t;
    a.bx[l] = x;
    a.by[l] = y;
    a.bz[l] = z;
  } else if (d2 < a.second[l]) {
    a.second[l] = d2;
  }
  if (d2 < a.best2[l]) a.best2[l] = d2;
  a.interior[l] += 1;
}

// g at arc end k (in t): C'(t_k)·(C(t_k) - q).
HWY_INLINE V g_end(D d, const BezierArcTable& a, std::size_t k, const Lanes& s) {
  return dot3(hn::Set(d, a.tx[k]), hn::Set(d, a.ty[k]), hn::Set(d, a.tz[k]),
              hn::Sub(hn::Set(d, a.px[k]), s.qx), hn::Sub(hn::Set(d, a.py[k]), s.qy),
              hn::Sub(hn::Set(d, a.pz[k]), s.qz));
}

// g' at arc end k (in t): |C'|² + C''·(C - q).
HWY_INLINE V g_slope(D d, const BezierArcTable& a, std::size_t k, const Lanes& s) {
  const double tt = a.tx[k] * a.tx[k] + a.ty[k] * a.ty[k] + a.tz[k] * a.tz[k];
  const V r =
      hn::Add(hn::Set(d, tt), hn::Mul(hn::Set(d, a.sx[k]), hn::Sub(hn::Set(d, a.px[k]), s.qx)));
  return hn::Add(hn::Add(r, hn::Mul(hn::Set(d, a.sy[k]), hn::Sub(hn::Set(d, a.py[k]), s.qy))),
                 hn::Mul(hn::Set(d, a.sz[k]), hn::Sub(hn::Set(d, a.pz[k]), s.qz)));
}

// C(s) on arc i by Horner in the power basis (power_point in bezier_curve.cpp).
template <int N>
HWY_INLINE void power_point(D d, const BezierArcTable& a, std::size_t i, V s, V& x, V& y, V& z) {
  const std::size_t K = static_cast<std::size_t>(a.count);
  x = hn::Set(d, a.ax[N * K + i]);
  y = hn::Set(d, a.ay[N * K + i]);
  z = hn::Set(d, a.az[N * K + i]);
  for (int j = N - 1; j >= 0; --j) {
    const std::size_t o = static_cast<std::size_t>(j) * K + i;
    x = hn::Add(hn::Mul(x, s), hn::Set(d, a.ax[o]));
    y = hn::Add(hn::Mul(y, s), hn::Set(d, a.ay[o]));
    z = hn::Add(hn::Mul(z, s), hn::Set(d, a.az[o]));
  }
}

// The root of g on arc i for the lanes of `m` (arc_root<N> in bezier_curve.cpp, in lockstep):
// its parameter s and point.
template <int N>
HWY_INLINE void arc_root(D d, const BezierArcTable& a, std::size_t i, const Lanes& q, M m, V s0,
                         V tolerance, V stop, V& out_s, V& ox, V& oy, V& oz) {
  const std::size_t K = static_cast<std::size_t>(a.count);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0), half = hn::Set(d, 0.5);
  V lo = zero, hi = one;
  V s = hn::IfThenElse(hn::And(hn::Gt(s0, zero), hn::Lt(s0, one)), s0, half);
  out_s = s;
  ox = oy = oz = zero;
  M active = m;
  M need_point = hn::Lt(one, zero);  // none yet
  for (int it = 0; it < kBezierMaxRootIterations && !hn::AllFalse(d, active); ++it) {
    V cx = hn::Set(d, a.ax[N * K + i]), cy = hn::Set(d, a.ay[N * K + i]),
      cz = hn::Set(d, a.az[N * K + i]);
    V ux = zero, uy = zero, uz = zero;  // C'
    V vx = zero, vy = zero, vz = zero;  // C'' / 2
    for (int j = N - 1; j >= 0; --j) {
      const std::size_t o = static_cast<std::size_t>(j) * K + i;
      vx = hn::Add(hn::Mul(vx, s), ux);
      vy = hn::Add(hn::Mul(vy, s), uy);
      vz = hn::Add(hn::Mul(vz, s), uz);
      ux = hn::Add(hn::Mul(ux, s), cx);
      uy = hn::Add(hn::Mul(uy, s), cy);
      uz = hn::Add(hn::Mul(uz, s), cz);
      cx = hn::Add(hn::Mul(cx, s), hn::Set(d, a.ax[o]));
      cy = hn::Add(hn::Mul(cy, s), hn::Set(d, a.ay[o]));
      cz = hn::Add(hn::Mul(cz, s), hn::Set(d, a.az[o]));
    }
    const V rx = hn::Sub(cx, q.qx), ry = hn::Sub(cy, q.qy), rz = hn::Sub(cz, q.qz);
    const V g = dot3(ux, uy, uz, rx, ry, rz);
    // g == 0: the root itself.
    const M exact = hn::And(active, hn::Eq(g, zero));
    out_s = hn::IfThenElse(exact, s, out_s);
    ox = hn::IfThenElse(exact, cx, ox);
    oy = hn::IfThenElse(exact, cy, oy);
    oz = hn::IfThenElse(exact, cz, oz);
    active = hn::AndNot(exact, active);
    const M negative = hn::Lt(g, zero);
    lo = hn::IfThenElse(hn::And(active, negative), s, lo);
    hi = hn::IfThenElse(hn::AndNot(negative, active), s, hi);
    const V gp = hn::Add(dot3(ux, uy, uz, ux, uy, uz), hn::Mul(two, dot3(vx, vy, vz, rx, ry, rz)));
    const V step = hn::Div(g, gp);
    const V next = hn::Sub(s, step);
    const M inside = hn::And(hn::Gt(gp, zero), hn::And(hn::Gt(next, lo), hn::Lt(next, hi)));
    // Outside the bracket (or g' <= 0): bisection; done once the bracket is below tolerance.
    const M bisect = hn::AndNot(inside, active);
    const V mid = hn::Mul(half, hn::Add(lo, hi));
    const M bisect_done = hn::And(bisect, hn::Le(hn::Sub(hi, lo), tolerance));
    out_s = hn::IfThenElse(bisect_done, mid, out_s);
    need_point = hn::Or(need_point, bisect_done);
    // Inside: done once g² <= stop or the step is below tolerance; the point by Taylor from s.
    const M newton = hn::And(inside, active);
    const M newton_done =
        hn::And(newton, hn::Or(hn::Le(hn::Mul(g, g), stop), hn::Le(hn::Abs(step), tolerance)));
    const V h = hn::Neg(step), h2 = hn::Mul(step, step);
    out_s = hn::IfThenElse(newton_done, next, out_s);
    ox = hn::IfThenElse(newton_done, hn::Add(hn::Add(cx, hn::Mul(h, ux)), hn::Mul(h2, vx)), ox);
    oy = hn::IfThenElse(newton_done, hn::Add(hn::Add(cy, hn::Mul(h, uy)), hn::Mul(h2, vy)), oy);
    oz = hn::IfThenElse(newton_done, hn::Add(hn::Add(cz, hn::Mul(h, uz)), hn::Mul(h2, vz)), oz);
    s = hn::IfThenElse(bisect, mid, hn::IfThenElse(newton, next, s));
    active = hn::AndNot(hn::Or(bisect_done, newton_done), active);
  }
  // Out of iterations: where it stopped.
  out_s = hn::IfThenElse(active, s, out_s);
  need_point = hn::Or(need_point, active);
  if (!hn::AllFalse(d, need_point)) {
    V x, y, z;
    power_point<N>(d, a, i, out_s, x, y, z);
    ox = hn::IfThenElse(need_point, x, ox);
    oy = hn::IfThenElse(need_point, y, oy);
    oz = hn::IfThenElse(need_point, z, oz);
  }
}

// The exact isolation on arc i for the lanes of `m`, one lane at a time (the uncertified branch
// of visit() in project_arcs<N>).
template <int N>
HWY_NOINLINE void isolate_lanes(D d, const BezierArcTable& a, std::size_t i, M m, Lanes& s,
                                BezierArcIsolation isolate, const void* projector) {
  const std::size_t K = static_cast<std::size_t>(a.count);
  LaneArrays arrays;
  spill(d, s, arrays);
  std::uint8_t bits[(kMaxLanes + 7) / 8] = {};
  hn::StoreMaskBits(d, m, bits);
  const double t0 = a.t0[i], span = a.span[i];
  for (std::size_t l = 0; l < hn::Lanes(d); ++l) {
    if (((bits[l / 8] >> (l % 8)) & 1) == 0) continue;
    const double q[3] = {arrays.qx[l], arrays.qy[l], arrays.qz[l]};
    std::array<double, 32> roots;
    int skipped = 0;
    const int found = isolate(projector, static_cast<int>(i), q, roots.data(), &skipped);
    arrays.skipped[l] += skipped;
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
      add_candidate(arrays, l, t, x, y, z);
    }
  }
  fill(d, arrays, s);
}

// visit(i) of project_arcs<N> for the lanes of `m`; (dx, dy, dz) = centre of arc i - q and dc2
// its squared norm.
template <int N>
HWY_INLINE void visit(D d, const BezierArcTable& a, std::size_t i, M m, V dx, V dy, V dz, V dc2,
                      Lanes& s, BezierArcIsolation isolate, const void* projector) {
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
  const V g0 = g_end(d, a, i, s);
  const V g1 = g_end(d, a, i + 1, s);
  const M root = hn::And(hn::And(m, certified), hn::And(hn::Lt(g0, zero), hn::Ge(g1, zero)));
  if (!hn::AllFalse(d, root)) {
    const double span = a.span[i];
    const V tolerance = hn::Set(d, a.tolerance[i]);
    const V g2 = hn::Add(
        hn::Set(d, a.g2_fixed[i]),
        hn::Mul(hn::Set(d, a.g2_per_distance[i]), hn::Add(hn::Sqrt(dc2), hn::Set(d, a.radius[i]))));
    const V cube = hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 2 * a.tolerance[i]), slope), slope), slope);
    const V stop = hn::IfThenElse(hn::Gt(g2, zero), hn::Div(cube, g2),
                                  hn::Set(d, std::numeric_limits<double>::infinity()));
    // Start: the root of g's cubic Hermite interpolant by one Newton step from the chord's.
    const V m0 = hn::Mul(hn::Set(d, span), g_slope(d, a, i, s));
    const V m1 = hn::Mul(hn::Set(d, span), g_slope(d, a, i + 1, s));
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
    V rs, rx, ry, rz;
    arc_root<N>(d, a, i, s, root, s0, tolerance, stop, rs, rx, ry, rz);
    const V t = hn::Add(hn::Set(d, a.t0[i]), hn::Mul(rs, hn::Set(d, span)));
    add_candidate(d, s, root, t, rx, ry, rz);
  }
  // Not certified: the exact isolation on the arc (Rigaudière et al. §3.4).
  if (!hn::AllFalse(d, fallback)) isolate_lanes<N>(d, a, i, fallback, s, isolate, projector);
}

// The lanes of one vector, from the points' coordinates and their nearest-centre arcs.
template <int N>
HWY_INLINE void project_vector(D d, const BezierArcTable& a, const double* qx, const double* qy,
                               const double* qz, const double* first, BezierArcIsolation isolate,
                               const void* projector, Lanes& s) {
  const std::size_t K = static_cast<std::size_t>(a.count);
  s.qx = hn::Load(d, qx);
  s.qy = hn::Load(d, qy);
  s.qz = hn::Load(d, qz);
  s.first = hn::Load(d, first);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  s.interior = zero;
  s.skipped = zero;
  // The two ends of the curve: the first candidates.
  auto end_d2 = [&](std::size_t k) {
    const V dx = hn::Sub(hn::Set(d, a.px[k]), s.qx);
    const V dy = hn::Sub(hn::Set(d, a.py[k]), s.qy);
    const V dz = hn::Sub(hn::Set(d, a.pz[k]), s.qz);
    return dot3(dx, dy, dz, dx, dy, dz);
  };
  const V d0 = end_d2(0), d1 = end_d2(K);
  s.bd2 = d0;
  s.bt = zero;
  s.bx = hn::Set(d, a.px[0]);
  s.by = hn::Set(d, a.py[0]);
  s.bz = hn::Set(d, a.pz[0]);
  {
    const M better = hn::Lt(d1, d0);
    s.second = hn::IfThenElse(better, d0, d1);
    s.bd2 = hn::IfThenElse(better, d1, s.bd2);
    s.bt = hn::IfThenElse(better, one, s.bt);
    s.bx = hn::IfThenElse(better, hn::Set(d, a.px[K]), s.bx);
    s.by = hn::IfThenElse(better, hn::Set(d, a.py[K]), s.by);
    s.bz = hn::IfThenElse(better, hn::Set(d, a.pz[K]), s.bz);
  }
  const V ends = hn::Min(d0, d1);
  s.best2 = ends;
  // The arc with the nearest centre first, lanes grouped by it.
  alignas(64) double firsts[kMaxLanes];
  hn::Store(s.first, d, firsts);
  M pending = hn::Eq(zero, zero);
  while (!hn::AllFalse(d, pending)) {
    const std::size_t f = static_cast<std::size_t>(firsts[hn::FindFirstTrue(d, pending)]);
    const M m = hn::And(pending, hn::Eq(s.first, hn::Set(d, static_cast<double>(f))));
    pending = hn::AndNot(m, pending);
    // Upper bound of the nearest distance: the curve's ends and this arc's ends.
    s.best2 = hn::IfThenElse(m, hn::Min(hn::Min(ends, end_d2(f)), end_d2(f + 1)), s.best2);
    const V dx = hn::Sub(hn::Set(d, a.cx[f]), s.qx);
    const V dy = hn::Sub(hn::Set(d, a.cy[f]), s.qy);
    const V dz = hn::Sub(hn::Set(d, a.cz[f]), s.qz);
    visit<N>(d, a, f, m, dx, dy, dz, dot3(dx, dy, dz, dx, dy, dz), s, isolate, projector);
  }
  // Every other arc whose sphere is not farther than the best point found.
  const V slack = hn::Set(d, 1 + kBezierPruneSlack);
  V prune = hn::Mul(hn::Sqrt(s.best2), slack);
  for (std::size_t i = 0; i < K; ++i) {
    const V dx = hn::Sub(hn::Set(d, a.cx[i]), s.qx);
    const V dy = hn::Sub(hn::Set(d, a.cy[i]), s.qy);
    const V dz = hn::Sub(hn::Set(d, a.cz[i]), s.qz);
    const V dc2 = dot3(dx, dy, dz, dx, dy, dz);
    const V lim = hn::Add(hn::Set(d, a.radius[i]), prune);
    const M m = hn::Not(hn::Or(hn::Eq(s.first, hn::Set(d, static_cast<double>(i))),
                               hn::Gt(dc2, hn::Mul(lim, lim))));
    if (hn::AllFalse(d, m)) continue;
    visit<N>(d, a, i, m, dx, dy, dz, dc2, s, isolate, projector);
    prune = hn::Mul(hn::Sqrt(s.best2), slack);
  }
}

template <int N>
void project_batch(const BezierArcTable& a, const double* qx, const double* qy, const double* qz,
                   std::size_t n, BezierArcIsolation isolate, const void* projector,
                   BezierLaneResult* out) {
  const D d;
  const std::size_t lanes = hn::Lanes(d);
  const std::size_t K = static_cast<std::size_t>(a.count);
  const std::size_t padded = (n + lanes - 1) / lanes * lanes;
  constexpr std::size_t kCap = kBezierBatch + kMaxLanes;
  // Padded copies (the last point repeated), then the nearest centre of each point.
  alignas(64) double px[kCap], py[kCap], pz[kCap], first[kCap];
  for (std::size_t k = 0; k < padded; ++k) {
    const std::size_t src = std::min(k, n - 1);
    px[k] = qx[src];
    py[k] = qy[src];
    pz[k] = qz[src];
  }
  for (std::size_t k = 0; k < padded; k += lanes) {
    const V x = hn::Load(d, px + k), y = hn::Load(d, py + k), z = hn::Load(d, pz + k);
    V best = hn::Set(d, std::numeric_limits<double>::infinity());
    V index = hn::Zero(d);
    for (std::size_t i = 0; i < K; ++i) {
      const V dx = hn::Sub(hn::Set(d, a.cx[i]), x);
      const V dy = hn::Sub(hn::Set(d, a.cy[i]), y);
      const V dz = hn::Sub(hn::Set(d, a.cz[i]), z);
      const V d2 = dot3(dx, dy, dz, dx, dy, dz);
      const M nearer = hn::Lt(d2, best);
      best = hn::IfThenElse(nearer, d2, best);
      index = hn::IfThenElse(nearer, hn::Set(d, static_cast<double>(i)), index);
    }
    hn::Store(index, d, first + k);
  }
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
  alignas(64) double sx[kCap], sy[kCap], sz[kCap], sf[kCap];
  for (std::size_t k = 0; k < padded; ++k) {
    sx[k] = px[order[k]];
    sy[k] = py[order[k]];
    sz[k] = pz[order[k]];
    sf[k] = first[order[k]];
  }
  alignas(64) double t[kMaxLanes], d2[kMaxLanes], x[kMaxLanes], y[kMaxLanes], z[kMaxLanes],
      counted[kMaxLanes], redo[kMaxLanes];
  for (std::size_t k = 0; k < padded; k += lanes) {
    Lanes s;
    project_vector<N>(d, a, sx + k, sy + k, sz + k, sf + k, isolate, projector, s);
    hn::Store(s.bt, d, t);
    hn::Store(s.bd2, d, d2);
    hn::Store(s.bx, d, x);
    hn::Store(s.by, d, y);
    hn::Store(s.bz, d, z);
    hn::Store(hn::Add(s.interior, s.skipped), d, counted);
    // A tie within choose()'s limit is possible: the caller decides it one by one.
    const M near = hn::Le(hn::Sub(s.second, s.bd2), hn::Mul(hn::Set(d, kBezierNearTie), s.bd2));
    hn::Store(hn::IfThenElseZero(near, hn::Set(d, 1.0)), d, redo);
    for (std::size_t l = 0; l < lanes && k + l < n; ++l) {
      BezierLaneResult& r = out[order[k + l]];
      r.t = t[l];
      r.d2 = d2[l];
      r.x = x[l];
      r.y = y[l];
      r.z = z[l];
      r.counted = static_cast<int>(counted[l]);
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
