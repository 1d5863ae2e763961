// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The hot loop of skeleton fields, vectorized over points with Highway and dispatched at run
// time to the best instruction set of the machine (no -march flags). Each point is computed by
// the same lane-wise code whatever batch it arrives in, so a point's value never depends on the
// batch, the chunking or the thread count.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "field/skeleton_field_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include "field/skeleton_field_simd.h"

HWY_BEFORE_NAMESPACE();
namespace ramiform::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;

// C1 fade window of infinite kernels (tolerances.h: kFadeStart = 0.8 in distance, so 0.64 in
// squared distance): w = 1 for v <= 0.64, 1 - s^2 (3 - 2 s) with s = (v - 0.64) / 0.36 up to
// v = 1, 0 beyond. Returns w and dw/dv.
HWY_INLINE void fade(D d, V v, V& w, V& dw) {
  const V one = hn::Set(d, 1.0);
  V s = hn::Mul(hn::Sub(v, hn::Set(d, 0.64)), hn::Set(d, 1.0 / 0.36));
  s = hn::Min(hn::Max(s, hn::Zero(d)), one);
  w = hn::Sub(one, hn::Mul(hn::Mul(s, s), hn::Sub(hn::Set(d, 3.0), hn::Add(s, s))));
  dw = hn::Mul(hn::Mul(hn::Set(d, -6.0 / 0.36), s), hn::Sub(one, s));
}

HWY_INLINE V dot3(V ax, V ay, V az, V bx, V by, V bz) {
  return hn::MulAdd(az, bz, hn::MulAdd(ay, by, hn::Mul(ax, bx)));
}

// Distance-surface modes: value = weight * k(y) (* fade), y = d^2 / R^2.
template <int kMode, bool kGrad>
HWY_INLINE void distance_primitive(const PrimitiveTable& t, const ModeParams& m, std::uint32_t i,
                                   Chunk& c) {
  const D d;
  const std::size_t lanes = hn::Lanes(d);
  const V ax = hn::Set(d, t.ax[i]), ay = hn::Set(d, t.ay[i]), az = hn::Set(d, t.az[i]);
  const V ux = hn::Set(d, t.ux[i]), uy = hn::Set(d, t.uy[i]), uz = hn::Set(d, t.uz[i]);
  const V len = hn::Set(d, t.len[i]);
  const V r0 = hn::Set(d, t.r0[i]), dr = hn::Set(d, t.dr[i]);
  const V weight = hn::Set(d, t.weight[i]);
  const V inv_cut = hn::Set(d, t.inv_cut[i]);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
  for (std::size_t j = 0; j < c.padded; j += lanes) {
    const V wx = hn::Sub(hn::Load(d, c.px + j), ax);
    const V wy = hn::Sub(hn::Load(d, c.py + j), ay);
    const V wz = hn::Sub(hn::Load(d, c.pz + j), az);
    const V traw = dot3(wx, wy, wz, ux, uy, uz);
    const V tt = hn::Min(hn::Max(traw, zero), len);
    const V qx = hn::NegMulAdd(tt, ux, wx);
    const V qy = hn::NegMulAdd(tt, uy, wy);
    const V qz = hn::NegMulAdd(tt, uz, wz);
    const V d2 = dot3(qx, qy, qz, qx, qy, qz);
    const V R = hn::MulAdd(tt, dr, r0);
    const V inv_r2 = hn::Div(one, hn::Mul(R, R));
    const V y = hn::Mul(d2, inv_r2);
    V k, dkdy;
    if constexpr (kMode == static_cast<int>(PrimitiveMode::kWyvill)) {
      const auto inside = y < one;
      const V a = hn::Set(d, -4.0 / 9.0), b = hn::Set(d, 17.0 / 9.0), cc = hn::Set(d, -22.0 / 9.0);
      k = hn::IfThenElseZero(inside, hn::MulAdd(y, hn::MulAdd(y, hn::MulAdd(y, a, b), cc), one));
      dkdy = hn::IfThenElseZero(
          inside, hn::MulAdd(y, hn::MulAdd(y, hn::Mul(hn::Set(d, 3.0), a), hn::Add(b, b)), cc));
    } else if constexpr (kMode == static_cast<int>(PrimitiveMode::kBlinn)) {
      const V B = hn::Set(d, m.shape);
      k = hn::CallExp(d, hn::Neg(hn::Mul(B, y)));
      dkdy = hn::Neg(hn::Mul(B, k));
    } else if constexpr (kMode == static_cast<int>(PrimitiveMode::kMetaball)) {
      const V x = hn::Sqrt(y);
      const auto near = y <= hn::Set(d, 1.0 / 9.0);
      const auto inside = x < one;
      const V omx = hn::Sub(one, x);
      const V outer_k = hn::IfThenElseZero(inside, hn::Mul(hn::Set(d, 1.5), hn::Mul(omx, omx)));
      // -3 (1 - x) / (2 x); x > 1/3 wherever this branch is taken.
      const V safe_x = hn::Max(x, hn::Set(d, 1.0 / 3.0));
      const V outer_d = hn::IfThenElseZero(inside, hn::Div(hn::Mul(hn::Set(d, -1.5), omx), safe_x));
      k = hn::IfThenElse(near, hn::NegMulAdd(hn::Set(d, 3.0), y, one), outer_k);
      dkdy = hn::IfThenElse(near, hn::Set(d, -3.0), outer_d);
    } else if constexpr (kMode == static_cast<int>(PrimitiveMode::kInversePower)) {
      const V ymin = hn::Set(d, 1e-12);  // x >= 1e-6, see kernels.cpp
      const V ym = hn::Max(y, ymin);
      const V e = hn::Set(d, -(m.shape - 1) / 2);
      k = hn::CallExp(d, hn::Mul(e, hn::CallLog(d, ym)));
      dkdy = hn::IfThenElseZero(y > ymin, hn::Div(hn::Mul(e, k), ym));
    } else {  // kCauchyPoint: k = 1 / (1 + y)^2
      const V q = hn::Add(one, y);
      const V inv_q = hn::Div(one, q);
      k = hn::Mul(inv_q, inv_q);
      dkdy = hn::Mul(hn::Set(d, -2.0), hn::Mul(k, inv_q));
    }
    V value = hn::Mul(weight, k);
    V g = hn::Mul(weight, dkdy);
    if (m.fades) {
      V w, dw;
      fade(d, hn::Mul(y, inv_cut), w, dw);
      g = hn::MulAdd(g, w, hn::Mul(value, hn::Mul(dw, inv_cut)));
      value = hn::Mul(value, w);
    }
    hn::Store(hn::Add(hn::Load(d, c.value + j), value), d, c.value + j);
    if constexpr (kGrad) {
      // grad y = 2 / R^2 (q - y R dr grad t), grad t = u strictly inside the segment, else 0.
      const auto interior = hn::And(traw > zero, traw < len);
      const V c_t = hn::IfThenElseZero(interior, hn::Mul(hn::Mul(y, R), dr));
      const V f = hn::Mul(g, hn::Mul(two, inv_r2));
      hn::Store(hn::MulAdd(f, hn::NegMulAdd(c_t, ux, qx), hn::Load(d, c.gx + j)), d, c.gx + j);
      hn::Store(hn::MulAdd(f, hn::NegMulAdd(c_t, uy, qy), hn::Load(d, c.gy + j)), d, c.gy + j);
      hn::Store(hn::MulAdd(f, hn::NegMulAdd(c_t, uz, qz), hn::Load(d, c.gz + j)), d, c.gz + j);
    }
  }
}

// Convolution of the Cauchy kernel along a segment, closed form (kernels.cpp documents it).
template <bool kGrad>
HWY_INLINE void cauchy_segment(const PrimitiveTable& t, std::uint32_t i, Chunk& c) {
  const D d;
  const std::size_t lanes = hn::Lanes(d);
  const V ax = hn::Set(d, t.ax[i]), ay = hn::Set(d, t.ay[i]), az = hn::Set(d, t.az[i]);
  const V ux = hn::Set(d, t.ux[i]), uy = hn::Set(d, t.uy[i]), uz = hn::Set(d, t.uz[i]);
  const V len = hn::Set(d, t.len[i]);
  const V s = hn::Set(d, t.s[i]);
  const V s2 = hn::Mul(s, s);
  const V weight = hn::Set(d, t.weight[i]);
  const V inv_cut = hn::Set(d, t.inv_cut[i]);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), half = hn::Set(d, 0.5);
  const V half_pi = hn::Set(d, 1.57079632679489661923);
  const V s_len = hn::Mul(s, len);
  for (std::size_t j = 0; j < c.padded; j += lanes) {
    const V wx = hn::Sub(hn::Load(d, c.px + j), ax);
    const V wy = hn::Sub(hn::Load(d, c.py + j), ay);
    const V wz = hn::Sub(hn::Load(d, c.pz + j), az);
    const V x = dot3(wx, wy, wz, ux, uy, uz);
    const V qx = hn::NegMulAdd(x, ux, wx);
    const V qy = hn::NegMulAdd(x, uy, wy);
    const V qz = hn::NegMulAdd(x, uz, wz);
    const V h2 = dot3(qx, qy, qz, qx, qy, qz);
    const V P = hn::MulAdd(s2, h2, one);
    const V root_p = hn::Sqrt(P);
    const V u1 = hn::Sub(len, x);
    const V d1 = hn::MulAdd(s2, hn::Mul(u1, u1), P);
    const V d0 = hn::MulAdd(s2, hn::Mul(x, x), P);
    const V inv_p = hn::Div(one, P);
    const V inv_d1 = hn::Div(one, d1);
    const V inv_d0 = hn::Div(one, d0);
    // u1 / (2 P d1) + x / (2 P d0)
    const V rational = hn::Mul(hn::Mul(half, inv_p), hn::MulAdd(u1, inv_d1, hn::Mul(x, inv_d0)));
    const V inv_root_p = hn::Div(one, root_p);
    const V A = hn::Mul(hn::Mul(s, u1), inv_root_p);
    const V B = hn::Mul(hn::Mul(s, x), inv_root_p);
    const V sum_ab = hn::Mul(s_len, inv_root_p);  // A + B exactly, > 0
    const V angle = hn::Sub(half_pi, hn::CallAtan(d, hn::Div(hn::NegMulAdd(A, B, one), sum_ab)));
    const V F = hn::MulAdd(angle, hn::Div(hn::Mul(half, inv_p), hn::Mul(s, root_p)), rational);
    // Fade by the squared distance to the segment.
    const V tc = hn::Min(hn::Max(x, zero), len);
    const V ex = hn::NegMulAdd(tc, ux, wx);
    const V ey = hn::NegMulAdd(tc, uy, wy);
    const V ez = hn::NegMulAdd(tc, uz, wz);
    V w, dw;
    fade(d, hn::Mul(dot3(ex, ey, ez, ex, ey, ez), inv_cut), w, dw);
    const V wf = hn::Mul(weight, F);
    hn::Store(hn::MulAdd(wf, w, hn::Load(d, c.value + j)), d, c.value + j);
    if constexpr (kGrad) {
      const V dfdx = hn::Sub(hn::Mul(inv_d0, inv_d0), hn::Mul(inv_d1, inv_d1));
      // j = u1 / (4 P d1^2) + x / (4 P d0^2) + 3 F / (4 P); dF/dq-direction = -4 s^2 j
      const V quarter_inv_p = hn::Mul(hn::Set(d, 0.25), inv_p);
      const V jj = hn::Mul(quarter_inv_p,
                           hn::MulAdd(hn::Set(d, 3.0), F,
                                      hn::MulAdd(u1, hn::Mul(inv_d1, inv_d1),
                                                 hn::Mul(x, hn::Mul(inv_d0, inv_d0)))));
      const V cq = hn::Mul(hn::Set(d, -4.0), hn::Mul(s2, jj));
      // total = weight * (w * grad F + F * dw * 2 inv_cut * e)
      const V a_u = hn::Mul(weight, hn::Mul(w, dfdx));
      const V a_q = hn::Mul(weight, hn::Mul(w, cq));
      const V a_e = hn::Mul(wf, hn::Mul(dw, hn::Add(inv_cut, inv_cut)));
      hn::Store(hn::MulAdd(a_e, ex, hn::MulAdd(a_q, qx, hn::MulAdd(a_u, ux, hn::Load(d, c.gx + j)))),
                d, c.gx + j);
      hn::Store(hn::MulAdd(a_e, ey, hn::MulAdd(a_q, qy, hn::MulAdd(a_u, uy, hn::Load(d, c.gy + j)))),
                d, c.gy + j);
      hn::Store(hn::MulAdd(a_e, ez, hn::MulAdd(a_q, qz, hn::MulAdd(a_u, uz, hn::Load(d, c.gz + j)))),
                d, c.gz + j);
    }
  }
}

template <int kMode, bool kGrad>
void run_mode(const PrimitiveTable& t, const ModeParams& m, const std::uint32_t* ids,
              std::size_t count, Chunk& c) {
  for (std::size_t k = 0; k < count; ++k) {
    if constexpr (kMode == static_cast<int>(PrimitiveMode::kCauchySegment)) {
      if (t.len[ids[k]] > 0) {
        cauchy_segment<kGrad>(t, ids[k], c);
        continue;
      }
    }
    distance_primitive<kMode == static_cast<int>(PrimitiveMode::kCauchySegment)
                           ? static_cast<int>(PrimitiveMode::kCauchyPoint)
                           : kMode,
                       kGrad>(t, m, ids[k], c);
  }
}

template <bool kGrad>
void run(const PrimitiveTable& t, const ModeParams& m, const std::uint32_t* ids, std::size_t count,
         Chunk& c) {
  switch (m.mode) {
    case PrimitiveMode::kWyvill: return run_mode<0, kGrad>(t, m, ids, count, c);
    case PrimitiveMode::kBlinn: return run_mode<1, kGrad>(t, m, ids, count, c);
    case PrimitiveMode::kMetaball: return run_mode<2, kGrad>(t, m, ids, count, c);
    case PrimitiveMode::kInversePower: return run_mode<3, kGrad>(t, m, ids, count, c);
    case PrimitiveMode::kCauchyPoint: return run_mode<4, kGrad>(t, m, ids, count, c);
    case PrimitiveMode::kCauchySegment: return run_mode<5, kGrad>(t, m, ids, count, c);
  }
}

void Accumulate(const PrimitiveTable& t, const ModeParams& m, const std::uint32_t* ids,
                std::size_t count, Chunk& c, bool with_gradient) {
  if (with_gradient) {
    run<true>(t, m, ids, count, c);
  } else {
    run<false>(t, m, ids, count, c);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ramiform::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ramiform::detail {

HWY_EXPORT(Accumulate);

void accumulate(const PrimitiveTable& table, const ModeParams& mode, const std::uint32_t* ids,
                std::size_t count, Chunk& chunk, bool with_gradient) {
  HWY_DYNAMIC_DISPATCH(Accumulate)(table, mode, ids, count, chunk, with_gradient);
}

}  // namespace ramiform::detail
#endif  // HWY_ONCE
