// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// The curve-based distance surfaces of sweep.h. The pieces live beside this file: the kernel
// part (sweep_falloff.h), the 2-D distance to sections and profiles (sweep_region.h), the path
// with its projection and frames (sweep_path.h) and the interpolation along it
// (sweep_interpolation.h); this file puts them together as fields.
#include "ramiform/core/portable_math.h"
#include "ramiform/field/sweep.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "field/pointwise_field.h"
#include "field/sweep_common.h"
#include "field/sweep_falloff.h"
#include "field/sweep_interpolation.h"
#include "field/sweep_path.h"
#include "field/sweep_region.h"
#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

using detail::sweep::Box2;
using detail::sweep::Falloff;
using detail::sweep::Interpolator;
using detail::sweep::kReachMargin;
using detail::sweep::make_falloff;
using detail::sweep::make_region;
using detail::sweep::Path;
using detail::sweep::Region2;
using detail::sweep::Weights;

class RevolutionField final : public detail::PointwiseField {
 public:
  RevolutionField(Region2 profile, const Falloff& falloff)
      : PointwiseField(falloff.iso), profile_(std::move(profile)), falloff_(falloff) {}

  Interval bound(const Aabb& box) const override {
    const Vec3 c = box.center();
    const double rho = 0.5 * box.diagonal().norm();
    const double dc = profile_.distance(to_rz(c), nullptr);
    // The (r, z) image of the box lies in [rlo, rhi] x [zlo, zhi]; and d is 1-Lipschitz in p.
    const double dx = std::max({0.0, box.min().x(), -box.max().x()});
    const double dy = std::max({0.0, box.min().y(), -box.max().y()});
    const double rlo = pm::hypot(dx, dy);
    const double rhi = pm::hypot(std::max(std::abs(box.min().x()), std::abs(box.max().x())),
                                  std::max(std::abs(box.min().y()), std::abs(box.max().y())));
    const Box2 rect(Vec2(rlo, box.min().z()), Vec2(rhi, box.max().z()));
    const double dmin =
        std::max({0.0, dc - rho, std::sqrt(rect.squaredExteriorDistance(profile_.box()))});
    return falloff_.range(dmin, dc + rho);
  }

  Aabb bounds() const override {
    if (falloff_.d_inside < 0) return Aabb();
    const double pad = falloff_.d_inside * (1 + kReachMargin);
    const Box2& b = profile_.box();
    const double r = std::max(std::abs(b.min().x()), std::abs(b.max().x())) + pad;
    return Aabb(Vec3(-r, -r, b.min().y() - pad), Vec3(r, r, b.max().y() + pad));
  }

  std::string describe() const override {
    return "surface of revolution about z, " + std::string(profile_.closed() ? "closed" : "open") +
           " profile of " + std::to_string(profile_.vertices().size()) + " flattened points, " +
           kernel_name(falloff_.kernel.kind) + " kernel, iso " + std::to_string(iso());
  }

 private:
  static Vec2 to_rz(const Vec3& p) { return {pm::hypot(p.x(), p.y()), p.z()}; }

  double at(const Vec3& p, Vec3* grad) const override {
    const Vec2 q = to_rz(p);
    Vec2 g2;
    const double d = profile_.distance(q, grad != nullptr ? &g2 : nullptr);
    double dfdd = 0;
    const double f = falloff_.value(d, grad != nullptr ? &dfdd : nullptr);
    if (grad != nullptr) {
      const Vec3 radial = q.x() > 0 ? Vec3(p.x() / q.x(), p.y() / q.x(), 0) : Vec3::Zero();
      *grad = dfdd * (g2.x() * radial + g2.y() * Vec3::UnitZ());
    }
    return f;
  }

  Region2 profile_;
  Falloff falloff_;
};

class SkinField final : public detail::PointwiseField {
 public:
  SkinField(Path path, std::vector<double> group_s, std::vector<std::vector<Region2>> groups,
            SkinInterpolation interpolation, const Falloff& falloff, std::string label)
      : PointwiseField(falloff.iso),
        path_(std::move(path)),
        interp_(group_s, interpolation),
        groups_(std::move(groups)),
        interpolation_(interpolation),
        falloff_(falloff),
        label_(std::move(label)) {
    for (const auto& g : groups_) {
      for (const auto& r : g) extent_ = std::max(extent_, r.extent());
    }
    spread_ = interp_.lebesgue() * extent_;
    const double cut = (falloff_.support_reach() + spread_) * (1 + kReachMargin);
    cutoff2_ = cut * cut;
  }

  // Every value is weight k(d / R) with d >= |p - O| - L E (L bounds sum |w_k|, E the largest
  // section extent, O the projected point on the path), and d <= |p - O| + L E.
  Interval bound(const Aabb& box) const override {
    const Vec3 c = box.center();
    const double rho = 0.5 * box.diagonal().norm();
    const double dpoly = path_.distance_to_polyline(c);
    const double slack = path_.tolerance() * (1 + kReachMargin);
    const double near =
        std::max({0.0, std::sqrt(squared_distance(box, path_.box())), dpoly - rho - slack});
    const double far = dpoly + rho + slack;
    return falloff_.range(near - spread_, far + spread_);
  }

  Aabb bounds() const override {
    if (falloff_.d_inside < 0) return Aabb();
    const double pad =
        pm::hypot(falloff_.d_inside + spread_, falloff_.d_inside) * (1 + kReachMargin);
    return Aabb(path_.box().min() - Vec3::Constant(pad), path_.box().max() + Vec3::Constant(pad));
  }

  std::string describe() const override {
    static const char* kNames[] = {"linear", "quadratic", "cubic"};
    std::size_t sections = 0;
    for (const auto& g : groups_) sections += g.size();
    return label_ + " along a path of " + std::to_string(path_.pieces()) + " flattened pieces, " +
           std::to_string(sections) + " section(s) at " + std::to_string(groups_.size()) +
           " parameter(s), " + kNames[static_cast<int>(interpolation_)] + " interpolation, " +
           kernel_name(falloff_.kernel.kind) + " kernel, iso " + std::to_string(iso());
  }

 private:
  double group_distance(int k, const Vec2& q, Vec2* grad) const {
    double best = std::numeric_limits<double>::infinity();
    for (const Region2& r : groups_[static_cast<std::size_t>(k)]) {
      Vec2 g;
      const double d = r.distance(q, grad != nullptr ? &g : nullptr);
      if (d < best) {
        best = d;
        if (grad != nullptr) *grad = g;
      }
    }
    return best;
  }

  double at(const Vec3& p, Vec3* grad) const override {
    if (squared_distance(path_.box(), p) > cutoff2_) {
      if (grad != nullptr) grad->setZero();
      return 0;
    }
    const Path::Projection pr = path_.project(p);
    const Vec3 r = p - pr.origin;
    const double a = r.dot(pr.tangent);
    const Vec2 q(r.dot(pr.normal), r.dot(pr.binormal));
    const Weights w = interp_.at(pr.s);
    double dint = 0, dds = 0;
    Vec2 g2 = Vec2::Zero();
    for (int c = 0; c < w.count; ++c) {
      Vec2 gk;
      const double dk = group_distance(w.index[c], q, grad != nullptr ? &gk : nullptr);
      dint += w.w[c] * dk;
      dds += w.dw[c] * dk;
      if (grad != nullptr) g2 += w.w[c] * gk;
    }
    const double dplane = std::max(dint, 0.0);
    const double d = pm::hypot(dplane, a);
    double dfdd = 0;
    const double f = falloff_.value(d, grad != nullptr ? &dfdd : nullptr);
    if (grad != nullptr) {
      Vec3 gd = Vec3::Zero();
      if (d > 0) {
        // The frame is treated as constant: for a rotation-minimizing frame dN/dt and dB/dt are
        // parallel to T, and p - O is orthogonal to T wherever the projection is interior.
        const Vec3 gplane =
            dint > 0 ? Vec3(g2.x() * pr.normal + g2.y() * pr.binormal + dds * pr.dsdt * pr.dtdp)
                     : Vec3::Zero();
        gd = (dplane * gplane + a * pr.tangent) / d;
      }
      *grad = dfdd * gd;
    }
    return f;
  }

  Path path_;
  Interpolator interp_;
  std::vector<std::vector<Region2>> groups_;
  SkinInterpolation interpolation_;
  Falloff falloff_;
  std::string label_;
  double extent_ = 0;   // largest distance of a section point from its origin
  double spread_ = 0;   // lebesgue × extent_: |d2 - |q|| <= spread_
  double cutoff2_ = 0;  // squared distance from the path box beyond which f == 0
};

FieldPtr build_skin(const Curve3& path, std::vector<SkinSection> sections,
                    const SkinOptions& options, const std::string& what, const std::string& label) {
  const Falloff falloff = make_falloff(options.surface, what);
  if (options.interpolation != SkinInterpolation::kLinear &&
      options.interpolation != SkinInterpolation::kQuadratic &&
      options.interpolation != SkinInterpolation::kCubic) {
    throw InvalidArgument(what + ": unknown interpolation " +
                          std::to_string(static_cast<int>(options.interpolation)));
  }
  if (sections.empty()) throw InvalidArgument(what + ": no sections");
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const double s = sections[i].s;
    if (!(s >= 0 && s <= 1)) {
      throw InvalidArgument(what + ": section " + std::to_string(i) + ": s = " + std::to_string(s) +
                            " is outside [0, 1]");
    }
    try {
      validate(sections[i].curve);
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(what + ": section " + std::to_string(i) + ": " + e.what());
    }
  }
  Path p(path, options.surface.tolerance, what);
  std::stable_sort(sections.begin(), sections.end(),
                   [](const SkinSection& a, const SkinSection& b) { return a.s < b.s; });
  std::vector<double> group_s;
  std::vector<std::vector<Region2>> groups;
  for (const auto& sec : sections) {
    if (group_s.empty() || sec.s != group_s.back()) {
      group_s.push_back(sec.s);
      groups.emplace_back();
    }
    groups.back().push_back(make_region(sec.curve, options.surface.tolerance));
  }
  return std::make_shared<SkinField>(std::move(p), std::move(group_s), std::move(groups),
                                     options.interpolation, falloff, label);
}

}  // namespace

FieldPtr make_revolution_field(const Curve2& profile, const CurveSurfaceOptions& options) {
  const std::string what = "make_revolution_field";
  const Falloff falloff = make_falloff(options, what);
  try {
    validate(profile);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(what + ": profile: " + e.what());
  }
  for (std::size_t i = 0; i < profile.points.size(); ++i) {
    if (profile.points[i].x() < 0) {
      throw InvalidArgument(what + ": profile point " + std::to_string(i) +
                            " has x = " + std::to_string(profile.points[i].x()) +
                            " < 0 (x is the distance from the z axis)");
    }
  }
  return std::make_shared<RevolutionField>(make_region(profile, options.tolerance), falloff);
}

FieldPtr make_skin_field(const Curve3& path, std::vector<SkinSection> sections,
                         const SkinOptions& options) {
  return build_skin(path, std::move(sections), options, "make_skin_field", "skinned surface");
}

FieldPtr make_sweep_field(const Curve3& path, const Curve2& section,
                          const CurveSurfaceOptions& options) {
  SkinOptions o;
  o.surface = options;
  o.interpolation = SkinInterpolation::kLinear;
  return build_skin(path, {SkinSection{section, 0.0}, SkinSection{section, 1.0}}, o,
                    "make_sweep_field", "sweep surface");
}

PathFrame path_frame(const Curve3& path, double s) { return path_frame(path, s, 0.0); }

PathFrame path_frame(const Curve3& path, double s, double tolerance) {
  if (!(s >= 0 && s <= 1))
    throw InvalidArgument("path_frame: s = " + std::to_string(s) + " is outside [0, 1]");
  if (!std::isfinite(tolerance) || tolerance < 0) {
    throw InvalidArgument("path_frame: tolerance must be finite and >= 0, got " +
                          std::to_string(tolerance));
  }
  return Path(path, tolerance, "path_frame").frame_at_s(s);
}

PathProjection project_on_path(const Curve3& path, const Vec3& p, double tolerance) {
  if (!is_finite(p)) throw InvalidArgument("project_on_path: the point is not finite");
  if (!std::isfinite(tolerance) || tolerance < 0) {
    throw InvalidArgument("project_on_path: tolerance must be finite and >= 0, got " +
                          std::to_string(tolerance));
  }
  const Path::Projection pr = Path(path, tolerance, "project_on_path").project(p);
  return {pr.t, pr.s, pr.origin, pr.newton};
}

}  // namespace ramiform
