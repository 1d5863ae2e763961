// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/sweep_region.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "field/sweep_common.h"

namespace ramiform::detail::sweep {
namespace {

constexpr std::size_t kBlock = 8;  // segments per pruning block

}  // namespace

Region2::Region2(std::vector<Vec2> vertices, bool closed)
    : v_(std::move(vertices)), closed_(closed) {
  const std::size_t n = v_.size();
  const std::size_t segs = closed_ ? n : n - 1;
  for (std::size_t b = 0; b < segs; b += kBlock) {
    Block block{Box2(), b, std::min(segs, b + kBlock)};
    for (std::size_t i = block.begin; i < block.end; ++i) {
      block.box.extend(v_[i]);
      block.box.extend(v_[(i + 1) % n]);
    }
    blocks_.push_back(block);
    box_.extend(block.box);
  }
  for (const auto& v : v_) extent_ = std::max(extent_, v.norm());
}

// A block is visited when it may hold a closer segment, or when a closed region's horizontal
// ray from q towards +x can cross it (the even-odd count must see every crossing).
double Region2::distance(const Vec2& q, Vec2* grad) const {
  const std::size_t n = v_.size();
  double best2 = std::numeric_limits<double>::infinity();
  Vec2 closest = v_[0];
  bool inside = false;
  for (const Block& block : blocks_) {
    const bool near = block.box.squaredExteriorDistance(q) < best2;
    const bool crosses = closed_ && q.y() >= block.box.min().y() && q.y() <= block.box.max().y() &&
                         q.x() < block.box.max().x();
    if (!near && !crosses) continue;
    for (std::size_t i = block.begin; i < block.end; ++i) {
      const Vec2& a = v_[i];
      const Vec2& b = v_[(i + 1) % n];
      if (near) {
        const Vec2 ab = b - a;
        const double l2 = ab.squaredNorm();
        const double u = l2 > 0 ? std::clamp((q - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
        const Vec2 c = a + u * ab;
        const double d2 = (q - c).squaredNorm();
        if (d2 < best2) {
          best2 = d2;
          closest = c;
        }
      }
      if (crosses && ((a.y() > q.y()) != (b.y() > q.y()))) {
        const double x = a.x() + (q.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
        if (q.x() < x) inside = !inside;
      }
    }
  }
  if (inside) {
    if (grad != nullptr) grad->setZero();
    return 0;
  }
  const double d = std::sqrt(best2);
  if (grad != nullptr) *grad = d > 0 ? Vec2((q - closest) / d) : Vec2::Zero();
  return d;
}

Region2 make_region(const Curve2& curve, double tolerance_option) {
  const double tol = tolerance_for(tolerance_option, extent_of(curve.points));
  return Region2(flatten(curve, tol), curve.closed);
}

}  // namespace ramiform::detail::sweep
