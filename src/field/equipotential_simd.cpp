// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The equipotential treecode's group evaluation, vectorized over the group's points with Highway
// and dispatched at run time (no -march flags). Each lane performs the operations of
// ChargeTree::eval() (field/equipotential.cpp) for its point, in the same order, with the same
// correctly rounded IEEE operations (+ - * / sqrt, compares, selects; no fused multiply-adds):
// the values are bit-identical to the scalar path and on every target (SSE4, AVX2, AVX-512 and
// the plain C++ fallback; tests/field/simd_targets_test.cpp forces each one).
//
// The arithmetic, for a point p and a charge c of value q (k = alpha - 1, u = 1 / s):
//   d = p - c, d2 = (dx dx + dy dy) + dz dz, s = d2 + h2, w = u^(k/2),
//   f += q w,  grad += (q ((-k w) u)) d;
// and for a far cluster (monopole plus quadrupole about its centroid, moments M, trace tr):
//   Md = (M0 dx + M1 dy) + M2 dz, ...,  dMd = (dx Mdx + dy Mdy) + dz Mdz,
//   f += q w + ((k/2 w) u) ((k + 2) dMd u - tr),
//   grad += (q ((-k w) u)) d + (((k (k + 2) / 2) w) u) u (2 Md + (tr - (k + 4) dMd u) d).

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "field/equipotential_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>

#include "field/equipotential_simd.h"

HWY_BEFORE_NAMESPACE();
namespace ramiform::detail {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// w = u^(k/2) for alpha = kAlpha (k = alpha - 1), u = 1 / s.
template <int kAlpha, class V>
HWY_INLINE V power(V u) {
  if constexpr (kAlpha == 2) return hn::Sqrt(u);
  if constexpr (kAlpha == 3) return u;
  if constexpr (kAlpha == 4) return hn::Mul(u, hn::Sqrt(u));
  if constexpr (kAlpha == 5) return hn::Mul(u, u);
  if constexpr (kAlpha == 6) return hn::Mul(hn::Mul(u, u), hn::Sqrt(u));
  if constexpr (kAlpha == 7) return hn::Mul(hn::Mul(u, u), u);
}

template <class D>
struct Lanes {
  using V = hn::Vec<D>;
  V px, py, pz, f, gx, gy, gz;
};

// The terms of one charge for the lanes of `take`.
template <int kAlpha, bool kGrad, class D, class M, class V = hn::Vec<D>>
HWY_INLINE void add_charge(D d, const Vec3& c, double q, const ChargeKernel& kn, M take,
                           Lanes<D>& l) {
  const V dx = hn::Sub(l.px, hn::Set(d, c.x()));
  const V dy = hn::Sub(l.py, hn::Set(d, c.y()));
  const V dz = hn::Sub(l.pz, hn::Set(d, c.z()));
  const V d2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
  const V s = hn::Add(d2, hn::Set(d, kn.h2));
  const V u = hn::Div(hn::Set(d, 1.0), s);
  const V w = power<kAlpha>(u);
  const V qv = hn::Set(d, q);
  l.f = hn::IfThenElse(take, hn::Add(l.f, hn::Mul(qv, w)), l.f);
  if constexpr (kGrad) {
    const V t = hn::Mul(qv, hn::Mul(hn::Mul(hn::Set(d, -(kAlpha - 1.0)), w), u));
    l.gx = hn::IfThenElse(take, hn::Add(l.gx, hn::Mul(t, dx)), l.gx);
    l.gy = hn::IfThenElse(take, hn::Add(l.gy, hn::Mul(t, dy)), l.gy);
    l.gz = hn::IfThenElse(take, hn::Add(l.gz, hn::Mul(t, dz)), l.gz);
  }
}

// The cluster's monopole and quadrupole for the lanes of `take` (d = p - centroid given).
template <int kAlpha, bool kGrad, class D, class M, class V = hn::Vec<D>>
HWY_INLINE void add_cluster(D d, const ChargeNode& c, const ChargeKernel& kn, M take, V dx, V dy,
                            V dz, V d2, Lanes<D>& l) {
  constexpr double k = kAlpha - 1.0;
  const V s = hn::Add(d2, hn::Set(d, kn.h2));
  const V u = hn::Div(hn::Set(d, 1.0), s);
  const V w = power<kAlpha>(u);
  const V m0 = hn::Set(d, c.m[0]), m1 = hn::Set(d, c.m[1]), m2 = hn::Set(d, c.m[2]);
  const V m3 = hn::Set(d, c.m[3]), m4 = hn::Set(d, c.m[4]), m5 = hn::Set(d, c.m[5]);
  const V mdx = hn::Add(hn::Add(hn::Mul(m0, dx), hn::Mul(m1, dy)), hn::Mul(m2, dz));
  const V mdy = hn::Add(hn::Add(hn::Mul(m1, dx), hn::Mul(m3, dy)), hn::Mul(m4, dz));
  const V mdz = hn::Add(hn::Add(hn::Mul(m2, dx), hn::Mul(m4, dy)), hn::Mul(m5, dz));
  const V dmd = hn::Add(hn::Add(hn::Mul(dx, mdx), hn::Mul(dy, mdy)), hn::Mul(dz, mdz));
  const V tr = hn::Set(d, c.trace);
  const V qv = hn::Set(d, c.q);
  const V quad = hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 0.5 * k), w), u),
                         hn::Sub(hn::Mul(hn::Mul(hn::Set(d, k + 2.0), dmd), u), tr));
  l.f = hn::IfThenElse(take, hn::Add(l.f, hn::Add(hn::Mul(qv, w), quad)), l.f);
  if constexpr (kGrad) {
    const V a = hn::Mul(qv, hn::Mul(hn::Mul(hn::Set(d, -k), w), u));
    const V b = hn::Mul(hn::Mul(hn::Mul(hn::Set(d, 0.5 * k * (k + 2.0)), w), u), u);
    const V e = hn::Sub(tr, hn::Mul(hn::Mul(hn::Set(d, k + 4.0), dmd), u));
    const V two = hn::Set(d, 2.0);
    const auto component = [&](V g, V dc, V mdc) {
      const V term = hn::Add(hn::Mul(a, dc), hn::Mul(b, hn::Add(hn::Mul(two, mdc), hn::Mul(e, dc))));
      return hn::IfThenElse(take, hn::Add(g, term), g);
    };
    l.gx = component(l.gx, dx, mdx);
    l.gy = component(l.gy, dy, mdy);
    l.gz = component(l.gz, dz, mdz);
  }
}

// The actions for the lanes [j, j + Lanes(d)) of the group. A lane skips the actions before its
// `skip` (the subtree of a split cluster it took whole), as eval()'s traversal never enters it.
template <int kAlpha, bool kGrad, class D>
void run_lanes(D d, const ChargeKernel& kn, const ChargeNode* nodes, const Vec3* pos,
               const double* val, const ChargeAction* actions, std::size_t action_count,
               ChargeGroup& g, std::size_t j) {
  using V = hn::Vec<D>;
  Lanes<D> l;
  l.px = hn::LoadU(d, g.px + j);
  l.py = hn::LoadU(d, g.py + j);
  l.pz = hn::LoadU(d, g.pz + j);
  l.f = l.gx = l.gy = l.gz = hn::Zero(d);
  V skip = hn::Zero(d);  // action indices as doubles (exact below 2^53)
  const V theta2 = hn::Set(d, kn.theta2);
  for (std::size_t a = 0; a < action_count; ++a) {
    const ChargeAction act = actions[a];
    const ChargeNode& c = nodes[act.node];
    const auto active = hn::Le(skip, hn::Set(d, static_cast<double>(a)));
    if (hn::AllFalse(d, active)) continue;
    const V dx = hn::Sub(l.px, hn::Set(d, c.centroid.x()));
    const V dy = hn::Sub(l.py, hn::Set(d, c.centroid.y()));
    const V dz = hn::Sub(l.pz, hn::Set(d, c.centroid.z()));
    const V d2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
    hn::Mask<D> far = hn::FirstN(d, 0);
    if (act.kind == ChargeAction::kFar) {
      far = active;
    } else if (act.kind == ChargeAction::kSplit) {
      far = hn::And(active, hn::Lt(hn::Set(d, c.rho2), hn::Mul(theta2, d2)));
    }
    if (!hn::AllFalse(d, far)) {
      add_cluster<kAlpha, kGrad>(d, c, kn, far, dx, dy, dz, d2, l);
      if (act.kind == ChargeAction::kSplit) {
        skip = hn::IfThenElse(far, hn::Set(d, static_cast<double>(act.end)), skip);
      }
    }
    if (c.right != UINT32_MAX) continue;
    const auto open = hn::AndNot(far, active);
    if (hn::AllFalse(d, open)) continue;
    for (std::uint32_t i = c.first; i < c.first + c.count; ++i) {
      add_charge<kAlpha, kGrad>(d, pos[i], val[i], kn, open, l);
    }
  }
  hn::StoreU(l.f, d, g.f + j);
  if constexpr (kGrad) {
    hn::StoreU(l.gx, d, g.gx + j);
    hn::StoreU(l.gy, d, g.gy + j);
    hn::StoreU(l.gz, d, g.gz + j);
  }
}

template <int kAlpha, bool kGrad>
void run(const ChargeKernel& kn, const ChargeNode* nodes, const Vec3* pos, const double* val,
         const ChargeAction* actions, std::size_t action_count, ChargeGroup& g) {
  const hn::ScalableTag<double> full;
  const std::size_t lanes = hn::Lanes(full);
  // A group of one to four points runs on vectors of that many lanes (the lone evaluations of
  // value() and gradient()); others on full vectors over the padded lanes.
  if (g.count <= 1 && lanes > 1) {
    return run_lanes<kAlpha, kGrad>(hn::CappedTag<double, 1>(), kn, nodes, pos, val, actions,
                                    action_count, g, 0);
  }
  if (g.count <= 2 && lanes > 2) {
    return run_lanes<kAlpha, kGrad>(hn::CappedTag<double, 2>(), kn, nodes, pos, val, actions,
                                    action_count, g, 0);
  }
  if (g.count <= 4 && lanes > 4) {
    return run_lanes<kAlpha, kGrad>(hn::CappedTag<double, 4>(), kn, nodes, pos, val, actions,
                                    action_count, g, 0);
  }
  for (std::size_t j = 0; j < g.count && j + lanes <= kChargeGroup; j += lanes) {
    run_lanes<kAlpha, kGrad>(full, kn, nodes, pos, val, actions, action_count, g, j);
  }
}

template <bool kGrad>
void run_alpha(const ChargeKernel& kn, const ChargeNode* nodes, const Vec3* pos, const double* val,
               const ChargeAction* actions, std::size_t action_count, ChargeGroup& g) {
  switch (kn.alpha) {
    case 2: return run<2, kGrad>(kn, nodes, pos, val, actions, action_count, g);
    case 3: return run<3, kGrad>(kn, nodes, pos, val, actions, action_count, g);
    case 4: return run<4, kGrad>(kn, nodes, pos, val, actions, action_count, g);
    case 5: return run<5, kGrad>(kn, nodes, pos, val, actions, action_count, g);
    case 6: return run<6, kGrad>(kn, nodes, pos, val, actions, action_count, g);
    default: return run<7, kGrad>(kn, nodes, pos, val, actions, action_count, g);
  }
}

void ChargeGroupEvaluate(const ChargeKernel& kn, const ChargeNode* nodes, const Vec3* pos,
                         const double* val, const ChargeAction* actions, std::size_t action_count,
                         ChargeGroup& g, bool with_gradient) {
  if (with_gradient) {
    run_alpha<true>(kn, nodes, pos, val, actions, action_count, g);
  } else {
    run_alpha<false>(kn, nodes, pos, val, actions, action_count, g);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace ramiform::detail
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace ramiform::detail {

HWY_EXPORT(ChargeGroupEvaluate);

void charge_group_evaluate(const ChargeKernel& kernel, const ChargeNode* nodes, const Vec3* pos,
                           const double* val, const ChargeAction* actions, std::size_t action_count,
                           ChargeGroup& g, bool with_gradient) {
  HWY_DYNAMIC_DISPATCH(ChargeGroupEvaluate)(kernel, nodes, pos, val, actions, action_count, g,
                                            with_gradient);
}

}  // namespace ramiform::detail
#endif  // HWY_ONCE
