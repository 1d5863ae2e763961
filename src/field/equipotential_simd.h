// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the equipotential field's treecode (field/equipotential.cpp) evaluated for a group of
// points at once, vectorized over the points with Highway and dispatched at run time like the
// skeleton fields (field/skeleton_field_simd.h). The group's traversal (the list of actions) is
// decided once on the scalar side; this adds, lane by lane, exactly the terms and in exactly the
// order that ChargeTree::eval() adds for each point alone, with the same IEEE operations (no
// fused multiply-adds), so values and gradients are bit-identical to it on every target.

#include <cstddef>
#include <cstdint>

#include "ramiform/core/types.h"

namespace ramiform {
struct ChargeSet;
}

namespace ramiform::detail {

/// A cluster of the charge tree: a binary tree split at the median of the longest axis, leaves of
/// at most 8 charges stored contiguously.
struct ChargeNode {
  Vec3 centroid = Vec3::Zero();  ///< charge-weighted centroid
  double q = 0.0;                ///< total charge
  double rho2 = 0.0;             ///< squared radius of the cluster around its centroid
  /// Second moments about the centroid, sum q (x - c)(x - c)^T: xx, xy, xz, yy, yz, zz.
  double m[6] = {0, 0, 0, 0, 0, 0};
  double trace = 0.0;  ///< m[0] + m[3] + m[5]
  Aabb box;
  std::uint32_t first = 0, count = 0;  ///< leaf: charges [first, first + count); inner: left
  std::uint32_t right = UINT32_MAX;    ///< inner: right child; leaf: UINT32_MAX
};

/// One step of a group's traversal: a cluster every point takes whole (kFar), a leaf every
/// point opens (kOpen), or a cluster each point decides on (kSplit; an inner node's children
/// follow it up to `end`, which the points that take it whole skip).
struct ChargeAction {
  enum Kind : std::uint8_t { kFar, kOpen, kSplit };
  std::uint32_t node = 0;
  std::uint32_t end = 0;
  Kind kind = kFar;
};

/// The kernel w(s) = s^(-(alpha - 1) / 2), s = |p - c|^2 + h2, for an integer alpha in [2, 7].
struct ChargeKernel {
  int alpha = 4;
  double h2 = 0.0;
  double theta2 = 0.0;  ///< a cluster is far when rho2 < theta2 * |p - centroid|^2
};

/// Points of one group as padded SoA, and their sums.
inline constexpr std::size_t kChargeGroup = 32;
struct alignas(64) ChargeGroup {
  double px[kChargeGroup], py[kChargeGroup], pz[kChargeGroup];
  double f[kChargeGroup], gx[kChargeGroup], gy[kChargeGroup], gz[kChargeGroup];
  std::size_t count = 0;  ///< the real points; lanes [count, kChargeGroup) hold copies of point 0
};

/// Sets g.f (and g.gx, gy, gz when `with_gradient`) of the group's points to the sums of the
/// `actions` over the tree `nodes` with the sorted charges `pos`, `val`.
void charge_group_evaluate(const ChargeKernel& kernel, const ChargeNode* nodes, const Vec3* pos,
                           const double* val, const ChargeAction* actions, std::size_t action_count,
                           ChargeGroup& g, bool with_gradient);

/// The scalar traversal of one point (ChargeTree::eval(), as the lambda estimate and the charge
/// fit use it) over a tree built afresh from `charges`: the reference the lanes must equal bit
/// for bit (tests/field/simd_targets_test.cpp).
[[nodiscard]] double charge_tree_value(const ChargeSet& charges, double theta, const Vec3& p,
                                       Vec3* gradient);

}  // namespace ramiform::detail
