// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The hot loop of skeleton fields, vectorized over points with Highway and dispatched at run
// time to the best instruction set of the machine (no -march flags). Each point is computed by
// the same lane-wise code whatever batch it arrives in, so a point's value never depends on the
// batch, the chunking or the thread count.
//
// Nor on the CPU: every target (the plain C++ fallback EMU128 or SCALAR, SSSE3, SSE4, AVX2,
// AVX-512) performs the same IEEE operations in the same order, so values are bit-identical on
// all of them. Hence no hn::MulAdd
// and relatives (a true fused multiply-add on AVX2/AVX-512, two roundings elsewhere; the
// build's -ffp-contract=off does not reach intrinsics), no Approximate* ops, no reductions
// across lanes, and no hwy/contrib/math (its Exp/Log/Atan fuse internally): exp, log and atan
// below are ramiform's own, from correctly rounded operations only (+ - * / sqrt, min/max with a
// non-NaN second operand, compares, selects and integer bit operations).
// tests/field/simd_targets_test.cpp forces each target and compares values and meshes bytewise.

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "field/skeleton_field_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <limits>

#include "field/skeleton_field_simd.h"
#include "ramiform/core/portable_math.h"

HWY_BEFORE_NAMESPACE();
namespace ramiform::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Every function below is written for any vector descriptor D: the full vectors of the target,
// or partial ones of 1, 2 or 4 lanes for chunks of that few points (accumulate()). The lanes
// are independent and run the same operations, so a point's value is the same in each.

// a * b + c, rounded twice on every target.
template <class V>
HWY_INLINE V mul_add(V a, V b, V c) {
  return hn::Add(hn::Mul(a, b), c);
}
// c - a * b, rounded twice on every target.
template <class V>
HWY_INLINE V neg_mul_add(V a, V b, V c) {
  return hn::Sub(c, hn::Mul(a, b));
}

// c[0] + c[1] x + ... + c[N-1] x^(N-1), Horner's rule.
template <class D, class V = hn::Vec<D>, std::size_t N>
HWY_INLINE V horner(D d, V x, const double (&c)[N]) {
  V p = hn::Set(d, c[N - 1]);
  for (std::size_t k = N - 1; k-- > 0;) p = mul_add(p, x, hn::Set(d, c[k]));
  return p;
}

// The polynomials and constants are those of the scalar functions (core/portable_math.h), in
// the same evaluation order: checked in double arithmetic against mpmath on 1e5 arguments, exp
// is within 0.92 ulp, log within 1.04 ulp and cauchy_angle within 2.2 ulp.
using pm::detail::kAtanPoly;
using pm::detail::kExpPoly;
using pm::detail::kInvLn2;
using pm::detail::kLn2Hi;
using pm::detail::kLn2Lo;
using pm::detail::kLogPoly;
using pm::detail::kRoundMagic;

// 2^k for an integer-valued k + kRoundMagic (k in [-1022, 1023]), from the exponent bits.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V pow2_of_rounded(D d, V k_plus_magic) {
  const hn::RebindToSigned<D> di;
  return hn::BitCast(d,
                     hn::ShiftLeft<52>(hn::Add(hn::BitCast(di, k_plus_magic), hn::Set(di, 1023))));
}

// e^x; 0 below -746 (where e^x rounds to 0) and inf above 710; NaN stays NaN.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V exp_det(D d, V x) {
  const V magic = hn::Set(d, kRoundMagic);
  const V xc = hn::Min(hn::Max(x, hn::Set(d, -746.0)), hn::Set(d, 710.0));
  const V k = hn::Sub(mul_add(xc, hn::Set(d, kInvLn2), magic), magic);
  const V r = neg_mul_add(k, hn::Set(d, kLn2Lo), neg_mul_add(k, hn::Set(d, kLn2Hi), xc));
  const V p = hn::Add(hn::Set(d, 1.0), mul_add(hn::Mul(r, r), horner(d, r, kExpPoly), r));
  // 2^k in two factors, so that k down to -1076 (subnormal results) and up to 1024 (overflow
  // to inf) stay in the exponent range; the first product is exact.
  const V half_k = mul_add(k, hn::Set(d, 0.5), magic);
  const V rest_k = hn::Add(hn::Sub(k, hn::Sub(half_k, magic)), magic);
  const V y = hn::Mul(hn::Mul(p, pow2_of_rounded(d, half_k)), pow2_of_rounded(d, rest_k));
  return hn::IfThenElse(hn::IsNaN(x), x, y);
}

// ln x for normal x > 0 (and inf for inf); callers keep x >= 1e-12.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V log_det(D d, V x) {
  const hn::RebindToSigned<D> di;
  // x = 2^e m with m in [sqrt(2)/2, sqrt(2)): shift the exponent field so that its carry
  // decides e, then put m's mantissa under the exponent of sqrt(2)/2 (as musl's log does).
  const auto bits =
      hn::Add(hn::BitCast(di, x), hn::Set(di, 0x3ff0000000000000LL - 0x3fe6a09e00000000LL));
  const V two52 = hn::Set(d, 4503599627370496.0);
  const V biased_e =
      hn::BitCast(d, hn::Or(hn::ShiftRight<52>(hn::BitCast(hn::RebindToUnsigned<D>(), bits)),
                            hn::BitCast(hn::RebindToUnsigned<D>(), two52)));
  const V e = hn::Sub(biased_e, hn::Set(d, 4503599627370496.0 + 1023.0));  // exact
  const V m = hn::BitCast(d, hn::Add(hn::And(bits, hn::Set(di, 0x000fffffffffffffLL)),
                                     hn::Set(di, 0x3fe6a09e00000000LL)));
  const V f = hn::Sub(m, hn::Set(d, 1.0));  // exact (Sterbenz)
  // ln(1 + f) = 2 atanh(s), s = f / (2 + f); 2 s = f - s f keeps the leading term exact.
  const V s = hn::Div(f, hn::Add(hn::Set(d, 2.0), f));
  const V z = hn::Mul(s, s);
  const V ln_m = neg_mul_add(s, neg_mul_add(z, horner(d, z, kLogPoly), f), f);
  const V y = mul_add(e, hn::Set(d, kLn2Hi), mul_add(e, hn::Set(d, kLn2Lo), ln_m));
  return hn::IfThenElse(hn::Eq(x, hn::Set(d, std::numeric_limits<double>::infinity())), x, y);
}

// pi/2 - atan(num / den) for den > 0, in (0, pi), without forming num / den: one division by
// the larger of |num| and den, reduced to |t| <= tan(pi/8). Far from a segment (num >> den) the
// small angle comes out with full relative precision.
template <class D, class V = hn::Vec<D>>
HWY_INLINE V cauchy_angle(D d, V num, V den) {
  const V a = hn::Abs(num);
  const auto big = hn::Gt(a, den);  // |atan| > pi/4: use atan(den / a)
  // 0 <= p <= q; mid: p / q above tan(pi/8).
  const V p = hn::IfThenElse(big, den, a);
  const V q = hn::IfThenElse(big, a, den);
  const auto mid = hn::Gt(p, hn::Mul(hn::Set(d, 0.41421356237309503), q));
  // atan(p/q) = pi/4 + atan((p - q) / (p + q)) above tan(pi/8).
  const V t = hn::Div(hn::IfThenElse(mid, hn::Sub(p, q), p), hn::IfThenElse(mid, hn::Add(p, q), q));
  const V w = hn::Mul(t, t);
  const V at = mul_add(hn::Mul(t, w), horner(d, w, kAtanPoly), t);
  // atan(p / q)
  const V core = hn::IfThenElse(mid, hn::Add(hn::Set(d, 0.78539816339744828), at), at);
  const V pi = hn::Set(d, 3.1415926535897931);
  const V half_pi = hn::Set(d, 1.5707963267948966);
  // |num| <= den: pi/2 - sign(num) core; |num| > den: core for num > 0, pi - core for num < 0.
  const V small_angle = hn::Sub(half_pi, hn::CopySignToAbs(core, num));
  const V big_angle = hn::IfThenElse(hn::Lt(num, hn::Zero(d)), hn::Sub(pi, core), core);
  return hn::IfThenElse(big, big_angle, small_angle);
}

// C1 fade window of infinite kernels (tolerances.h: kFadeStart = 0.8 in distance, so 0.64 in
// squared distance): w = 1 for v <= 0.64, 1 - s^2 (3 - 2 s) with s = (v - 0.64) / 0.36 up to
// v = 1, 0 beyond. Returns w and dw/dv.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void fade(D d, V v, V& w, V& dw) {
  const V one = hn::Set(d, 1.0);
  V s = hn::Mul(hn::Sub(v, hn::Set(d, 0.64)), hn::Set(d, 1.0 / 0.36));
  s = hn::Min(hn::Max(s, hn::Zero(d)), one);
  w = hn::Sub(one, hn::Mul(hn::Mul(s, s), hn::Sub(hn::Set(d, 3.0), hn::Add(s, s))));
  dw = hn::Mul(hn::Mul(hn::Set(d, -6.0 / 0.36), s), hn::Sub(one, s));
}

template <class V>
HWY_INLINE V dot3(V ax, V ay, V az, V bx, V by, V bz) {
  return mul_add(az, bz, mul_add(ay, by, hn::Mul(ax, bx)));
}

// Distance-surface modes: value = weight * k(y) (* fade), y = d^2 / R^2.
template <class D, int kMode, bool kGrad>
HWY_INLINE void distance_primitive(const PrimitiveTable& t, const ModeParams& m, std::uint32_t i,
                                   Chunk& c, std::size_t n) {
  using V = hn::Vec<D>;
  const D d;
  const std::size_t lanes = hn::Lanes(d);
  const V ax = hn::Set(d, t.ax[i]), ay = hn::Set(d, t.ay[i]), az = hn::Set(d, t.az[i]);
  const V ux = hn::Set(d, t.ux[i]), uy = hn::Set(d, t.uy[i]), uz = hn::Set(d, t.uz[i]);
  const V len = hn::Set(d, t.len[i]);
  const V r0 = hn::Set(d, t.r0[i]), dr = hn::Set(d, t.dr[i]);
  const V weight = hn::Set(d, t.weight[i]);
  const V inv_cut = hn::Set(d, t.inv_cut[i]);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), two = hn::Set(d, 2.0);
  for (std::size_t j = 0; j < n; j += lanes) {
    const V wx = hn::Sub(hn::Load(d, c.px + j), ax);
    const V wy = hn::Sub(hn::Load(d, c.py + j), ay);
    const V wz = hn::Sub(hn::Load(d, c.pz + j), az);
    const V traw = dot3(wx, wy, wz, ux, uy, uz);
    const V tt = hn::Min(hn::Max(traw, zero), len);
    const V qx = neg_mul_add(tt, ux, wx);
    const V qy = neg_mul_add(tt, uy, wy);
    const V qz = neg_mul_add(tt, uz, wz);
    const V d2 = dot3(qx, qy, qz, qx, qy, qz);
    const V R = mul_add(tt, dr, r0);
    const V inv_r2 = hn::Div(one, hn::Mul(R, R));
    const V y = hn::Mul(d2, inv_r2);
    // Lanes beyond the support add exactly +0 (cauchy_segment()); skip a vector of them.
    const V v_cut = hn::Mul(y, inv_cut);
    if (m.fades) {
      if (hn::AllTrue(d, hn::Ge(v_cut, one))) continue;
    } else if constexpr (kMode == static_cast<int>(PrimitiveMode::kWyvill) ||
                         kMode == static_cast<int>(PrimitiveMode::kMetaball)) {
      if (hn::AllTrue(d, hn::Ge(y, one))) continue;  // k = dk/dy = 0 from y = 1 on
    }
    V k, dkdy;
    if constexpr (kMode == static_cast<int>(PrimitiveMode::kWyvill)) {
      const auto inside = y < one;
      const V a = hn::Set(d, -4.0 / 9.0), b = hn::Set(d, 17.0 / 9.0), cc = hn::Set(d, -22.0 / 9.0);
      k = hn::IfThenElseZero(inside, mul_add(y, mul_add(y, mul_add(y, a, b), cc), one));
      dkdy = hn::IfThenElseZero(
          inside, mul_add(y, mul_add(y, hn::Mul(hn::Set(d, 3.0), a), hn::Add(b, b)), cc));
    } else if constexpr (kMode == static_cast<int>(PrimitiveMode::kBlinn)) {
      const V B = hn::Set(d, m.shape);
      k = exp_det(d, hn::Neg(hn::Mul(B, y)));
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
      k = hn::IfThenElse(near, neg_mul_add(hn::Set(d, 3.0), y, one), outer_k);
      dkdy = hn::IfThenElse(near, hn::Set(d, -3.0), outer_d);
    } else if constexpr (kMode == static_cast<int>(PrimitiveMode::kInversePower)) {
      const V ymin = hn::Set(d, 1e-12);  // x >= 1e-6, see kernels.cpp
      const V ym = hn::Max(y, ymin);
      const double exponent = -(m.shape - 1) / 2;
      const V e = hn::Set(d, exponent);
      // The default alpha = 3 is y^-1: one correctly rounded division instead of exp(e log y).
      k = exponent == -1.0 ? hn::Div(one, ym) : exp_det(d, hn::Mul(e, log_det(d, ym)));
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
      fade(d, v_cut, w, dw);
      g = mul_add(g, w, hn::Mul(value, hn::Mul(dw, inv_cut)));
      value = hn::Mul(value, w);
    }
    hn::Store(hn::Add(hn::Load(d, c.value + j), value), d, c.value + j);
    if constexpr (kGrad) {
      // grad y = 2 / R^2 (q - y R dr grad t), grad t = u strictly inside the segment, else 0.
      const auto interior = hn::And(traw > zero, traw < len);
      const V c_t = hn::IfThenElseZero(interior, hn::Mul(hn::Mul(y, R), dr));
      const V f = hn::Mul(g, hn::Mul(two, inv_r2));
      hn::Store(mul_add(f, neg_mul_add(c_t, ux, qx), hn::Load(d, c.gx + j)), d, c.gx + j);
      hn::Store(mul_add(f, neg_mul_add(c_t, uy, qy), hn::Load(d, c.gy + j)), d, c.gy + j);
      hn::Store(mul_add(f, neg_mul_add(c_t, uz, qz), hn::Load(d, c.gz + j)), d, c.gz + j);
    }
  }
}

// Convolution of the Cauchy kernel along a segment, closed form (kernels.cpp documents it).
template <class D, bool kGrad>
HWY_INLINE void cauchy_segment(const PrimitiveTable& t, std::uint32_t i, Chunk& c,
                               std::size_t n) {
  using V = hn::Vec<D>;
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
  const V s_len = hn::Mul(s, len);
  for (std::size_t j = 0; j < n; j += lanes) {
    const V wx = hn::Sub(hn::Load(d, c.px + j), ax);
    const V wy = hn::Sub(hn::Load(d, c.py + j), ay);
    const V wz = hn::Sub(hn::Load(d, c.pz + j), az);
    const V x = dot3(wx, wy, wz, ux, uy, uz);
    // The fade by the squared distance to the segment first: where it is 0 in every lane, the
    // lanes would add exactly +0 to the sums (w = dw = 0 and F finite, for points within about
    // 1e150 of the segment), which leaves every value and gradient as it was (the sums start at
    // +0 and never become -0), so the closed form is skipped: a point's value still does not
    // depend on the lanes beside it. A chunk's candidates reach its box, not each of its
    // points: on a dense tree (4,890 segments, meshed to a tolerance) 53 % of the lanes lie
    // beyond the support, 46 % in vectors wholly beyond it.
    const V tc = hn::Min(hn::Max(x, zero), len);
    const V ex = neg_mul_add(tc, ux, wx);
    const V ey = neg_mul_add(tc, uy, wy);
    const V ez = neg_mul_add(tc, uz, wz);
    const V v_cut = hn::Mul(dot3(ex, ey, ez, ex, ey, ez), inv_cut);
    if (hn::AllTrue(d, hn::Ge(v_cut, one))) continue;
    const V qx = neg_mul_add(x, ux, wx);
    const V qy = neg_mul_add(x, uy, wy);
    const V qz = neg_mul_add(x, uz, wz);
    const V h2 = dot3(qx, qy, qz, qx, qy, qz);
    const V P = mul_add(s2, h2, one);
    const V root_p = hn::Sqrt(P);
    const V u1 = hn::Sub(len, x);
    const V d1 = mul_add(s2, hn::Mul(u1, u1), P);
    const V d0 = mul_add(s2, hn::Mul(x, x), P);
    const V inv_p = hn::Div(one, P);
    const V inv_d1 = hn::Div(one, d1);
    const V inv_d0 = hn::Div(one, d0);
    // u1 / (2 P d1) + x / (2 P d0)
    const V rational = hn::Mul(hn::Mul(half, inv_p), mul_add(u1, inv_d1, hn::Mul(x, inv_d0)));
    // atan(A) + atan(B) with A = s u1 / sqrt(P), B = s x / sqrt(P): pi/2 - atan((1 - A B) /
    // (A + B)), A + B = s len / sqrt(P) > 0; numerator and denominator scaled by P.
    const V angle = cauchy_angle(d, neg_mul_add(s2, hn::Mul(u1, x), P), hn::Mul(s_len, root_p));
    const V F = mul_add(angle, hn::Div(hn::Mul(half, inv_p), hn::Mul(s, root_p)), rational);
    V w, dw;
    fade(d, v_cut, w, dw);
    const V wf = hn::Mul(weight, F);
    hn::Store(mul_add(wf, w, hn::Load(d, c.value + j)), d, c.value + j);
    if constexpr (kGrad) {
      const V dfdx = hn::Sub(hn::Mul(inv_d0, inv_d0), hn::Mul(inv_d1, inv_d1));
      // j = u1 / (4 P d1^2) + x / (4 P d0^2) + 3 F / (4 P); dF/dq-direction = -4 s^2 j
      const V quarter_inv_p = hn::Mul(hn::Set(d, 0.25), inv_p);
      const V jj = hn::Mul(quarter_inv_p, mul_add(hn::Set(d, 3.0), F,
                                                  mul_add(u1, hn::Mul(inv_d1, inv_d1),
                                                          hn::Mul(x, hn::Mul(inv_d0, inv_d0)))));
      const V cq = hn::Mul(hn::Set(d, -4.0), hn::Mul(s2, jj));
      // total = weight * (w * grad F + F * dw * 2 inv_cut * e)
      const V a_u = hn::Mul(weight, hn::Mul(w, dfdx));
      const V a_q = hn::Mul(weight, hn::Mul(w, cq));
      const V a_e = hn::Mul(wf, hn::Mul(dw, hn::Add(inv_cut, inv_cut)));
      hn::Store(mul_add(a_e, ex, mul_add(a_q, qx, mul_add(a_u, ux, hn::Load(d, c.gx + j)))), d,
                c.gx + j);
      hn::Store(mul_add(a_e, ey, mul_add(a_q, qy, mul_add(a_u, uy, hn::Load(d, c.gy + j)))), d,
                c.gy + j);
      hn::Store(mul_add(a_e, ez, mul_add(a_q, qz, mul_add(a_u, uz, hn::Load(d, c.gz + j)))), d,
                c.gz + j);
    }
  }
}

template <class D, int kMode, bool kGrad>
void run_mode(const PrimitiveTable& t, const ModeParams& m, const std::uint32_t* ids,
              std::size_t count, Chunk& c, std::size_t n) {
  for (std::size_t k = 0; k < count; ++k) {
    if constexpr (kMode == static_cast<int>(PrimitiveMode::kCauchySegment)) {
      if (t.len[ids[k]] > 0) {
        cauchy_segment<D, kGrad>(t, ids[k], c, n);
        continue;
      }
    }
    distance_primitive<D,
                       kMode == static_cast<int>(PrimitiveMode::kCauchySegment)
                           ? static_cast<int>(PrimitiveMode::kCauchyPoint)
                           : kMode,
                       kGrad>(t, m, ids[k], c, n);
  }
}

template <class D, bool kGrad>
void run(const PrimitiveTable& t, const ModeParams& m, const std::uint32_t* ids, std::size_t count,
         Chunk& c, std::size_t n) {
  switch (m.mode) {
    case PrimitiveMode::kWyvill: return run_mode<D, 0, kGrad>(t, m, ids, count, c, n);
    case PrimitiveMode::kBlinn: return run_mode<D, 1, kGrad>(t, m, ids, count, c, n);
    case PrimitiveMode::kMetaball: return run_mode<D, 2, kGrad>(t, m, ids, count, c, n);
    case PrimitiveMode::kInversePower: return run_mode<D, 3, kGrad>(t, m, ids, count, c, n);
    case PrimitiveMode::kCauchyPoint: return run_mode<D, 4, kGrad>(t, m, ids, count, c, n);
    case PrimitiveMode::kCauchySegment: return run_mode<D, 5, kGrad>(t, m, ids, count, c, n);
  }
}

// The lanes to compute: a chunk of 1, 2 or 4 points on vectors of that many lanes (where the
// target's are wider), others on the target's full vectors up to the next multiple of their
// lane count (c.padded, a multiple of 16, is the most the caller prepared).
template <bool kGrad>
void run_lanes(const PrimitiveTable& t, const ModeParams& m, const std::uint32_t* ids,
               std::size_t count, Chunk& c) {
  using Full = hn::ScalableTag<double>;
  const std::size_t lanes = hn::Lanes(Full());
  const std::size_t points = c.count;
  if (points <= 1 && lanes > 1) return run<hn::CappedTag<double, 1>, kGrad>(t, m, ids, count, c, 1);
  if (points <= 2 && lanes > 2) return run<hn::CappedTag<double, 2>, kGrad>(t, m, ids, count, c, 2);
  if (points <= 4 && lanes > 4) return run<hn::CappedTag<double, 4>, kGrad>(t, m, ids, count, c, 4);
  const std::size_t n = std::min(c.padded, (points + lanes - 1) / lanes * lanes);
  run<Full, kGrad>(t, m, ids, count, c, c.padded % lanes == 0 ? n : c.padded);
}

void Accumulate(const PrimitiveTable& t, const ModeParams& m, const std::uint32_t* ids,
                std::size_t count, Chunk& c, bool with_gradient) {
  if (with_gradient) {
    run_lanes<true>(t, m, ids, count, c);
  } else {
    run_lanes<false>(t, m, ids, count, c);
  }
}

std::int64_t DispatchedTarget() { return HWY_TARGET; }

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

HWY_EXPORT(DispatchedTarget);

std::int64_t dispatched_target() { return HWY_DYNAMIC_DISPATCH(DispatchedTarget)(); }

}  // namespace ramiform::detail
#endif  // HWY_ONCE
