// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/operators.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

enum class Combine { kSum, kMax, kMin };

void check_children(const std::vector<FieldPtr>& children, const char* what) {
  if (children.empty()) throw InvalidArgument(std::string(what) + " needs at least one child");
  for (std::size_t i = 0; i < children.size(); ++i) {
    if (!children[i]) throw InvalidArgument(std::string(what) + ": child " + std::to_string(i) + " is null");
  }
}

// Sum, union (max) and intersection (min) of children. For max/min each child's values are
// shifted by (iso - child iso) so that every child's surface stays where it was.
class NaryField final : public Field {
 public:
  NaryField(Combine op, std::vector<FieldPtr> children)
      : Field(children.front()->iso()), op_(op), children_(std::move(children)) {}
  NaryField(const NaryField& source, std::vector<FieldPtr> children)
      : Field(source.iso(), source), op_(source.op_), children_(std::move(children)) {}

  Interval bound(const Aabb& box) const override {
    Interval out = shifted(0, children_[0]->bound(box));
    for (std::size_t i = 1; i < children_.size(); ++i) {
      const Interval b = shifted(i, children_[i]->bound(box));
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
    Aabb box = children_[0]->bounds();
    for (std::size_t i = 1; i < children_.size(); ++i) {
      if (op_ == Combine::kMin) {
        box = box.intersection(children_[i]->bounds());
      } else {
        box.extend(children_[i]->bounds());
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
    for (const auto& c : children_) {
      kids.push_back(c->restrict(box));
      changed = changed || kids.back() != c;
    }
    if (!changed) return shared_from_this();
    return std::make_shared<NaryField>(*this, std::move(kids));
  }

  std::string describe() const override {
    const char* name = op_ == Combine::kSum ? "blend" : op_ == Combine::kMax ? "union" : "intersection";
    return std::string(name) + " of " + std::to_string(children_.size()) + " fields";
  }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    const std::size_t n = points.size();
    children_[0]->evaluate(points, values, gradients, ctx);
    apply_shift(0, values);
    std::vector<double> v(n);
    std::vector<Vec3> g(gradients.empty() ? 0 : n);
    for (std::size_t c = 1; c < children_.size(); ++c) {
      children_[c]->evaluate(points, v, g, ctx);
      apply_shift(c, v);
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
    }
  }

 private:
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
};

class DifferenceField final : public Field {
 public:
  DifferenceField(FieldPtr a, FieldPtr b) : Field(a->iso()), a_(std::move(a)), b_(std::move(b)) {}
  DifferenceField(const DifferenceField& s, FieldPtr a, FieldPtr b)
      : Field(s.iso(), s), a_(std::move(a)), b_(std::move(b)) {}

  Interval bound(const Aabb& box) const override {
    const Interval ia = a_->bound(box);
    const Interval ib = b_->bound(box);
    const double sb = iso() - b_->iso();
    // min(f_a, 2 iso - (f_b + sb))
    return {std::min(ia.lo, 2 * iso() - (ib.hi + sb)), std::min(ia.hi, 2 * iso() - (ib.lo + sb))};
  }
  Aabb bounds() const override { return a_->bounds(); }
  FieldPtr restrict(const Aabb& box) const override {
    FieldPtr ra = a_->restrict(box);
    FieldPtr rb = b_->restrict(box);
    if (ra == a_ && rb == b_) return shared_from_this();
    return std::make_shared<DifferenceField>(*this, std::move(ra), std::move(rb));
  }
  std::string describe() const override { return "difference of two fields"; }

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients, const Context* ctx) const override {
    a_->evaluate(points, values, gradients, ctx);
    std::vector<double> v(points.size());
    std::vector<Vec3> g(gradients.empty() ? 0 : points.size());
    b_->evaluate(points, v, g, ctx);
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

class TransformField final : public Field {
 public:
  TransformField(FieldPtr child, const Affine3& t)
      : Field(child->iso()), child_(std::move(child)), forward_(t), inverse_(t.inverse()) {
    linear_inverse_t_ = inverse_.linear().transpose();
  }
  TransformField(const TransformField& s, FieldPtr child)
      : Field(s.iso(), s),
        child_(std::move(child)),
        forward_(s.forward_),
        inverse_(s.inverse_),
        linear_inverse_t_(s.linear_inverse_t_) {}

  Interval bound(const Aabb& box) const override { return child_->bound(map_box(inverse_, box)); }
  Aabb bounds() const override { return map_box(forward_, child_->bounds()); }
  FieldPtr restrict(const Aabb& box) const override {
    FieldPtr r = child_->restrict(map_box(inverse_, box));
    if (r == child_) return shared_from_this();
    return std::make_shared<TransformField>(*this, std::move(r));
  }
  std::string describe() const override { return "transform of (" + child_->describe() + ")"; }

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

FieldPtr make_transform(FieldPtr child, const Affine3& transform) {
  if (!child) throw InvalidArgument("transform: null child");
  if (!transform.matrix().allFinite()) throw InvalidArgument("transform: matrix is not finite");
  const double det = transform.linear().determinant();
  const double scale = transform.linear().norm();
  if (!(std::abs(det) > 1e-12 * scale * scale * scale)) {
    throw InvalidArgument("transform: matrix is singular (determinant " + std::to_string(det) + ")");
  }
  return std::make_shared<TransformField>(std::move(child), transform);
}

}  // namespace ramiform
