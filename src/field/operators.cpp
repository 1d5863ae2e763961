// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/operators.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>

#include "ramiform/core/errors.h"

namespace ramiform {

CompositeField::CompositeField(double iso, std::span<const FieldPtr> children, const char* what)
    : Field(iso), depth_(1) {
  for (const FieldPtr& c : children) depth_ = std::max(depth_, field_depth(*c) + 1);
  if (depth_ > kMaxFieldDepth) {
    throw InvalidArgument(std::string(what) + ": the fields would be nested " +
                          std::to_string(depth_) + " deep, more than the maximum depth " +
                          std::to_string(kMaxFieldDepth) + " (kMaxFieldDepth)");
  }
}

CompositeField::CompositeField(double iso, const CompositeField& source)
    : Field(iso, source), depth_(source.depth_) {}

std::size_t field_depth(const Field& field) {
  const auto* composite = dynamic_cast<const CompositeField*>(&field);
  return composite != nullptr ? composite->depth() : 1;
}

namespace {

enum class Combine { kSum, kMax, kMin };

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

// A child's description inside its parent's, cut short so that a chain of transforms does not
// build descriptions quadratic in its length.
std::string short_description(const Field& child) {
  constexpr std::size_t kMax = 200;
  std::string text = child.describe();
  if (text.size() > kMax) {
    text.resize(kMax);
    text += "...";
  }
  return text;
}

void check_children(const std::vector<FieldPtr>& children, const char* what) {
  if (children.empty()) throw InvalidArgument(std::string(what) + " needs at least one child");
  for (std::size_t i = 0; i < children.size(); ++i) {
    if (!children[i]) throw InvalidArgument(std::string(what) + ": child " + std::to_string(i) + " is null");
  }
}

// Sum, union (max) and intersection (min) of children. For max/min each child's values are
// shifted by (iso - child iso) so that every child's surface stays where it was. A child that
// occurs several times is evaluated (bounded, restricted) once; its result is combined again at
// each later occurrence, in the children's order, so the arithmetic is that of the unshared tree.
class NaryField final : public CompositeField {
 public:
  NaryField(Combine op, std::vector<FieldPtr> children)
      : CompositeField(children.front()->iso(), children, name_of(op)),
        op_(op),
        children_(std::move(children)) {
    index_sharing();
  }
  NaryField(const NaryField& source, std::vector<FieldPtr> children)
      : CompositeField(source.iso(), source), op_(source.op_), children_(std::move(children)) {
    index_sharing();
  }

  Interval bound(const Aabb& box) const override {
    std::vector<Interval> seen(slots_);
    auto child_bound = [&](std::size_t i) {
      const std::size_t slot = slot_[first_[i]];
      if (first_[i] != i) return seen[slot];
      const Interval b = shifted(i, children_[i]->bound(box));
      if (slot != kNone) seen[slot] = b;
      return b;
    };
    Interval out = child_bound(0);
    for (std::size_t i = 1; i < children_.size(); ++i) {
      const Interval b = child_bound(i);
      switch (op_) {
        case Combine::kSum: out = {out.lo + b.lo, out.hi + b.hi}; break;
        case Combine::kMax: out = {std::max(out.lo, b.lo), std::max(out.hi, b.hi)}; break;
        case Combine::kMin: out = {std::min(out.lo, b.lo), std::min(out.hi, b.hi)}; break;
      }
    }
    if (op_ == Combine::kSum) {
      // Widen by the rounding of the additions.
      const double slack = 1e-12 * std::max(std::abs(out.lo), std::abs(out.hi));
      out = {out.lo - slack, out.hi + slack};
    }
    return out;
  }

  Aabb bounds() const override {
    std::vector<Aabb> seen(slots_);
    auto child_bounds = [&](std::size_t i) {
      const std::size_t slot = slot_[first_[i]];
      if (first_[i] != i) return seen[slot];
      const Aabb b = children_[i]->bounds();
      if (slot != kNone) seen[slot] = b;
      return b;
    };
    Aabb box = child_bounds(0);
    for (std::size_t i = 1; i < children_.size(); ++i) {
      if (op_ == Combine::kMin) {
        box = box.intersection(child_bounds(i));
      } else {
        box.extend(child_bounds(i));
      }
    }
    // A sum can be inside where no child is (two tails adding up): bound it conservatively by
    // the children's supports through the bound() of the union box; callers still prune by
    // bound(). For sums of fields whose values are >= 0 outside their bounds, the union of
    // child bounds is not enough, so grow it until bound() says nothing is inside beyond it.
    if (op_ == Combine::kSum && children_.size() > 1) box = grow_sum_bounds(box);
    return box;
  }

  FieldPtr restrict(const Aabb& box) const override {
    std::vector<FieldPtr> kids;
    kids.reserve(children_.size());
    bool changed = false;
    for (std::size_t i = 0; i < children_.size(); ++i) {
      // Each distinct child restricted once, so its restricted copy stays shared.
      kids.push_back(first_[i] == i ? children_[i]->restrict(box) : kids[first_[i]]);
      changed = changed || kids.back() != children_[i];
    }
    if (!changed) return shared_from_this();
    return std::make_shared<NaryField>(*this, std::move(kids));
  }

  std::string describe() const override {
    return std::string(name_of(op_)) + " of " + std::to_string(children_.size()) + " fields";
  }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    const std::size_t n = points.size();
    const bool with_gradients = !gradients.empty();
    // Values (and gradients) of the children that occur again, by slot, while still needed.
    std::vector<std::vector<double>> kept_values(slots_);
    std::vector<std::vector<Vec3>> kept_gradients(slots_);
    check_cancel(ctx);
    children_[0]->evaluate(points, values, gradients, ctx);
    apply_shift(0, values);
    if (slot_[0] != kNone) {
      kept_values[slot_[0]].assign(values.begin(), values.end());
      kept_gradients[slot_[0]].assign(gradients.begin(), gradients.end());
    }
    std::vector<double> scratch_values(n);
    std::vector<Vec3> scratch_gradients(with_gradients ? n : 0);
    for (std::size_t c = 1; c < children_.size(); ++c) {
      const std::size_t first = first_[c];
      const std::size_t slot = slot_[first];
      std::span<const double> v;
      std::span<const Vec3> g;
      if (first == c) {
        check_cancel(ctx);
        std::vector<double>& vs = slot != kNone ? kept_values[slot] : scratch_values;
        std::vector<Vec3>& gs = slot != kNone ? kept_gradients[slot] : scratch_gradients;
        vs.resize(n);
        gs.resize(with_gradients ? n : 0);
        children_[c]->evaluate(points, vs, gs, ctx);
        apply_shift(c, vs);
        v = vs;
        g = gs;
      } else {
        v = kept_values[slot];
        g = kept_gradients[slot];
      }
      for (std::size_t i = 0; i < n; ++i) {
        switch (op_) {
          case Combine::kSum:
            values[i] += v[i];
            if (!g.empty()) gradients[i] += g[i];
            break;
          case Combine::kMax:
            if (v[i] > values[i]) {
              values[i] = v[i];
              if (!g.empty()) gradients[i] = g[i];
            }
            break;
          case Combine::kMin:
            if (v[i] < values[i]) {
              values[i] = v[i];
              if (!g.empty()) gradients[i] = g[i];
            }
            break;
        }
      }
      if (slot != kNone && last_[slot] == c) {
        kept_values[slot] = {};
        kept_gradients[slot] = {};
      }
    }
  }

 private:
  static const char* name_of(Combine op) {
    return op == Combine::kSum ? "blend" : op == Combine::kMax ? "union" : "intersection";
  }

  // first_[i]: the first index holding the same field as child i; slot_[i] (for a first
  // occurrence) the slot that keeps its result for later occurrences, or kNone when it occurs
  // once; last_[slot]: the last index using the slot.
  void index_sharing() {
    const std::size_t k = children_.size();
    first_.resize(k);
    slot_.assign(k, kNone);
    std::unordered_map<const Field*, std::size_t> index;
    for (std::size_t i = 0; i < k; ++i) {
      const auto [it, is_new] = index.emplace(children_[i].get(), i);
      first_[i] = it->second;
      if (is_new) continue;
      std::size_t& slot = slot_[it->second];
      if (slot == kNone) {
        slot = slots_++;
        last_.push_back(i);
      }
      last_[slot] = i;
    }
  }

  double shift(std::size_t i) const { return op_ == Combine::kSum ? 0.0 : iso() - children_[i]->iso(); }
  Interval shifted(std::size_t i, Interval b) const { return {b.lo + shift(i), b.hi + shift(i)}; }
  void apply_shift(std::size_t i, std::span<double> v) const {
    const double s = shift(i);
    if (s != 0) {
      for (auto& x : v) x += s;
    }
  }

  Aabb grow_sum_bounds(Aabb box) const {
    if (box.isEmpty()) return box;
    // Check six slabs just outside the box; grow the box by its own size until every slab's
    // bound stays at or below iso (f <= iso is outside), at most a few times.
    for (int round = 0; round < 8; ++round) {
      const Vec3 size = box.diagonal().cwiseMax(Vec3::Constant(1e-9));
      Aabb outer(box.min() - size, box.max() + size);
      bool clear = true;
      for (int axis = 0; axis < 3 && clear; ++axis) {
        for (int side = 0; side < 2 && clear; ++side) {
          Aabb slab = outer;
          if (side == 0) {
            slab.max()[axis] = box.min()[axis];
          } else {
            slab.min()[axis] = box.max()[axis];
          }
          clear = bound(slab).hi <= iso();
        }
      }
      if (clear) return box;
      box = outer;
    }
    return box;
  }

  Combine op_;
  std::vector<FieldPtr> children_;
  std::vector<std::size_t> first_, slot_, last_;
  std::size_t slots_ = 0;
};

// A difference of a field with itself evaluates, bounds and restricts it once.
class DifferenceField final : public CompositeField {
 public:
  DifferenceField(FieldPtr a, FieldPtr b)
      : CompositeField(a->iso(), std::array<FieldPtr, 2>{a, b}, "difference"),
        a_(std::move(a)),
        b_(std::move(b)) {}
  DifferenceField(const DifferenceField& s, FieldPtr a, FieldPtr b)
      : CompositeField(s.iso(), s), a_(std::move(a)), b_(std::move(b)) {}

  Interval bound(const Aabb& box) const override {
    const Interval ia = a_->bound(box);
    const Interval ib = b_ == a_ ? ia : b_->bound(box);
    const double sb = iso() - b_->iso();
    // min(f_a, 2 iso - (f_b + sb))
    return {std::min(ia.lo, 2 * iso() - (ib.hi + sb)), std::min(ia.hi, 2 * iso() - (ib.lo + sb))};
  }
  Aabb bounds() const override { return a_->bounds(); }
  FieldPtr restrict(const Aabb& box) const override {
    FieldPtr ra = a_->restrict(box);
    FieldPtr rb = b_ == a_ ? ra : b_->restrict(box);
    if (ra == a_ && rb == b_) return shared_from_this();
    return std::make_shared<DifferenceField>(*this, std::move(ra), std::move(rb));
  }
  std::string describe() const override { return "difference of two fields"; }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    check_cancel(ctx);
    a_->evaluate(points, values, gradients, ctx);
    std::vector<double> v(points.size());
    std::vector<Vec3> g(gradients.empty() ? 0 : points.size());
    if (b_ == a_) {
      std::copy(values.begin(), values.end(), v.begin());
      std::copy(gradients.begin(), gradients.end(), g.begin());
    } else {
      check_cancel(ctx);
      b_->evaluate(points, v, g, ctx);
    }
    const double sb = iso() - b_->iso();
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double nb = 2 * iso() - (v[i] + sb);
      if (nb < values[i]) {
        values[i] = nb;
        if (!g.empty()) gradients[i] = -g[i];
      }
    }
  }

 private:
  FieldPtr a_, b_;
};

class TransformField final : public CompositeField {
 public:
  TransformField(FieldPtr child, const Affine3& t)
      : CompositeField(child->iso(), std::span<const FieldPtr>(&child, 1), "transform"),
        child_(std::move(child)),
        forward_(t),
        inverse_(t.inverse()) {
    linear_inverse_t_ = inverse_.linear().transpose();
  }
  TransformField(const TransformField& s, FieldPtr child)
      : CompositeField(s.iso(), s),
        child_(std::move(child)),
        forward_(s.forward_),
        inverse_(s.inverse_),
        linear_inverse_t_(s.linear_inverse_t_) {}

  [[nodiscard]] const FieldPtr& child() const { return child_; }
  [[nodiscard]] const Affine3& forward() const { return forward_; }

  Interval bound(const Aabb& box) const override { return child_->bound(map_box(inverse_, box)); }
  Aabb bounds() const override { return map_box(forward_, child_->bounds()); }
  FieldPtr restrict(const Aabb& box) const override {
    FieldPtr r = child_->restrict(map_box(inverse_, box));
    if (r == child_) return shared_from_this();
    return std::make_shared<TransformField>(*this, std::move(r));
  }
  std::string describe() const override {
    return "transform of (" + short_description(*child_) + ")";
  }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    std::vector<Vec3> local(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) local[i] = inverse_ * points[i];
    child_->evaluate(local, values, gradients, ctx);
    for (auto& g : gradients) g = linear_inverse_t_ * g;
  }

 private:
  static Aabb map_box(const Affine3& t, const Aabb& box) {
    if (box.isEmpty()) return box;
    Aabb out;
    for (int c = 0; c < 8; ++c) out.extend(t * box.corner(static_cast<Aabb::CornerType>(c)));
    return out;
  }

  FieldPtr child_;
  Affine3 forward_, inverse_;
  Mat3 linear_inverse_t_;
};

}  // namespace

FieldPtr make_sum(std::vector<FieldPtr> children) {
  check_children(children, "blend");
  for (std::size_t i = 1; i < children.size(); ++i) {
    if (children[i]->iso() != children[0]->iso()) {
      throw InvalidArgument("blend: child " + std::to_string(i) + " has iso " +
                            std::to_string(children[i]->iso()) + " but child 0 has " +
                            std::to_string(children[0]->iso()) + "; a sum blend needs equal iso values");
    }
  }
  if (children.size() == 1) return children[0];
  return std::make_shared<NaryField>(Combine::kSum, std::move(children));
}

FieldPtr make_union(std::vector<FieldPtr> children) {
  check_children(children, "union");
  if (children.size() == 1) return children[0];
  return std::make_shared<NaryField>(Combine::kMax, std::move(children));
}

FieldPtr make_intersection(std::vector<FieldPtr> children) {
  check_children(children, "intersection");
  if (children.size() == 1) return children[0];
  return std::make_shared<NaryField>(Combine::kMin, std::move(children));
}

FieldPtr make_difference(FieldPtr a, FieldPtr b) {
  if (!a || !b) throw InvalidArgument("difference: null operand");
  return std::make_shared<DifferenceField>(std::move(a), std::move(b));
}

namespace {

bool invertible(const Affine3& t) {
  if (!t.matrix().allFinite()) return false;
  const double scale = t.linear().norm();
  return std::abs(t.linear().determinant()) > 1e-12 * scale * scale * scale;
}

}  // namespace

FieldPtr make_transform(FieldPtr child, const Affine3& transform) {
  if (!child) throw InvalidArgument("transform: null child");
  if (!transform.matrix().allFinite()) throw InvalidArgument("transform: matrix is not finite");
  if (!invertible(transform)) {
    throw InvalidArgument("transform: matrix is singular (determinant " +
                          std::to_string(transform.linear().determinant()) + ")");
  }
  // A transform of a transform is one transform (the maps composed): a chain of moves, however
  // long, stays one level deep and costs one matrix product per point. Where the composed map
  // is numerically singular (a long chain of shrinking scales) the transforms stay nested.
  if (const auto* inner = dynamic_cast<const TransformField*>(child.get())) {
    const Affine3 composed = transform * inner->forward();
    if (invertible(composed)) return std::make_shared<TransformField>(inner->child(), composed);
  }
  return std::make_shared<TransformField>(std::move(child), transform);
}

}  // namespace ramiform
