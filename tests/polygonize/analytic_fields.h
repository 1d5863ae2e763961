// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Analytic fields with exact or conservative bounds, for polygonizer tests that must not depend
// on the skeleton fields.

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "ramiform/field/field.h"

namespace ramiform::test {

/// Signed distance sphere: f = r - |p - c|, iso given (surface radius r - iso). Exact bound.
class SphereField : public Field {
 public:
  SphereField(const Vec3& c, double r, double iso = 0.0) : Field(iso), c_(c), r_(r) {}
  [[nodiscard]] Interval bound(const Aabb& box) const override {
    return {r_ - max_distance(box, c_), r_ - std::sqrt(squared_distance(box, c_))};
  }
  [[nodiscard]] Aabb bounds() const override {
    const double R = r_ - iso();
    if (R <= 0) return {};
    return {c_ - Vec3::Constant(R), c_ + Vec3::Constant(R)};
  }
  [[nodiscard]] std::string describe() const override { return "sdf sphere"; }

 protected:
  void do_evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> g,
                   const Context* /*ctx*/) const override {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec3 d = p[i] - c_;
      v[i] = r_ - d.norm();
      if (!g.empty()) g[i] = -d.normalized();
    }
  }

 private:
  Vec3 c_;
  double r_;
};

/// Quadratic sphere f = 1 - |p - c|^2 / r^2, iso 0: nonlinear along grid edges. Exact bound.
class QuadraticSphereField : public Field {
 public:
  QuadraticSphereField(const Vec3& c, double r) : Field(0.0), c_(c), r_(r) {}
  [[nodiscard]] Interval bound(const Aabb& box) const override {
    const double dmax = max_distance(box, c_);
    return {1.0 - dmax * dmax / (r_ * r_), 1.0 - squared_distance(box, c_) / (r_ * r_)};
  }
  [[nodiscard]] Aabb bounds() const override {
    return {c_ - Vec3::Constant(r_), c_ + Vec3::Constant(r_)};
  }
  [[nodiscard]] std::string describe() const override { return "quadratic sphere"; }

 protected:
  void do_evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> g,
                   const Context* /*ctx*/) const override {
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec3 d = p[i] - c_;
      v[i] = 1.0 - d.squaredNorm() / (r_ * r_);
      if (!g.empty()) g[i] = -2.0 * d / (r_ * r_);
    }
  }

 private:
  Vec3 c_;
  double r_;
};

/// Signed distance torus around the z axis through c: f = r - dist(p, circle(c, R)), iso 0.
/// 1-Lipschitz, so the bound is f(centre) +- half the box diagonal.
class TorusField : public Field {
 public:
  TorusField(const Vec3& c, double R, double r) : Field(0.0), c_(c), R_(R), r_(r) {}
  [[nodiscard]] Interval bound(const Aabb& box) const override {
    const double f = eval(box.center());
    const double h = 0.5 * box.diagonal().norm();
    return {f - h, f + h};
  }
  [[nodiscard]] Aabb bounds() const override {
    const Vec3 e(R_ + r_, R_ + r_, r_);
    return {c_ - e, c_ + e};
  }
  [[nodiscard]] std::string describe() const override { return "sdf torus"; }

 protected:
  void do_evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> /*g*/,
                   const Context* /*ctx*/) const override {
    for (std::size_t i = 0; i < p.size(); ++i) v[i] = eval(p[i]);
  }

 private:
  [[nodiscard]] double eval(const Vec3& p) const {
    const Vec3 d = p - c_;
    return r_ - std::hypot(std::hypot(d.x(), d.y()) - R_, d.z());
  }
  Vec3 c_;
  double R_;
  double r_;
};

/// Sum of Gaussian blobs f = sum exp(-|p - c_i|^2 / s_i^2), iso 0.5 (blended metaballs with
/// topology changes). Exact per-term bounds.
class BlobField : public Field {
 public:
  struct Blob {
    Vec3 c;
    double s;
  };
  explicit BlobField(std::vector<Blob> blobs) : Field(0.5), blobs_(std::move(blobs)) {}
  [[nodiscard]] Interval bound(const Aabb& box) const override {
    Interval r{0.0, 0.0};
    for (const auto& b : blobs_) {
      const double dmax = max_distance(box, b.c);
      r.lo += std::exp(-dmax * dmax / (b.s * b.s));
      r.hi += std::exp(-squared_distance(box, b.c) / (b.s * b.s));
    }
    return r;
  }
  [[nodiscard]] Aabb bounds() const override {
    // f > iso needs some term > iso / n, i.e. d < s sqrt(ln(n / iso)).
    Aabb box;
    const double n = static_cast<double>(blobs_.size());
    for (const auto& b : blobs_) {
      const double R = b.s * std::sqrt(std::log(n / iso()));
      box.extend(b.c - Vec3::Constant(R));
      box.extend(b.c + Vec3::Constant(R));
    }
    return box;
  }
  [[nodiscard]] std::string describe() const override { return "gaussian blobs"; }

 protected:
  void do_evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> /*g*/,
                   const Context* /*ctx*/) const override {
    for (std::size_t i = 0; i < p.size(); ++i) {
      double f = 0.0;
      for (const auto& b : blobs_) f += std::exp(-(p[i] - b.c).squaredNorm() / (b.s * b.s));
      v[i] = f;
    }
  }

 private:
  std::vector<Blob> blobs_;
};

/// Union (max) of fields with the same iso; bound = elementwise max.
class MaxField : public Field {
 public:
  explicit MaxField(std::vector<FieldPtr> children)
      : Field(children.front()->iso()), children_(std::move(children)) {}
  [[nodiscard]] Interval bound(const Aabb& box) const override {
    Interval r = children_.front()->bound(box);
    for (const auto& c : children_) {
      const Interval b = c->bound(box);
      r.lo = std::max(r.lo, b.lo);
      r.hi = std::max(r.hi, b.hi);
    }
    return r;
  }
  [[nodiscard]] Aabb bounds() const override {
    Aabb box;
    for (const auto& c : children_) box.extend(c->bounds());
    return box;
  }
  [[nodiscard]] std::string describe() const override { return "max"; }

 protected:
  void do_evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> /*g*/,
                   const Context* /*ctx*/) const override {
    std::vector<double> tmp(p.size());
    for (std::size_t k = 0; k < children_.size(); ++k) {
      children_[k]->evaluate(p, k == 0 ? v : std::span<double>(tmp));
      if (k == 0) continue;
      for (std::size_t i = 0; i < p.size(); ++i) v[i] = std::max(v[i], tmp[i]);
    }
  }

 private:
  std::vector<FieldPtr> children_;
};

/// A field whose bound lies: it claims "all outside" for every box that misses `honest_box`
/// (for the test that a wrong bound still gives a watertight mesh).
class LyingBoundField : public Field {
 public:
  LyingBoundField(FieldPtr inner, const Aabb& honest_box)
      : Field(inner->iso()), inner_(std::move(inner)), honest_(honest_box) {}
  [[nodiscard]] Interval bound(const Aabb& box) const override {
    if (box.intersects(honest_)) return inner_->bound(box);
    return {iso() - 2.0, iso() - 1.0};
  }
  [[nodiscard]] Aabb bounds() const override { return inner_->bounds(); }
  [[nodiscard]] std::string describe() const override { return "lying bound"; }

 protected:
  void do_evaluate(std::span<const Vec3> p, std::span<double> v, std::span<Vec3> g,
                   const Context* /*ctx*/) const override {
    inner_->evaluate(p, v, g);
  }

 private:
  FieldPtr inner_;
  Aabb honest_;
};

}  // namespace ramiform::test
