// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Anisotropic skeleton primitives (Rigaudière, Gesquière & Faudot, "Shape Modelling with
// Skeleton based Implicit Primitives", §3.2, §3.5, §4.3): the deformation functions def(t) and
// the segment, Bezier-curve and surface elements skinned by field/distance_primitive.h.

#include "ramiform/field/anisotropic.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>

#include "core/bernstein.h"
#include "field/bvh.h"
#include "field/distance_primitive.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/portable_math.h"

namespace ramiform {
namespace {

using detail::DistancePrimitive;
using detail::DistanceRange;
using detail::Element;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = std::numbers::pi;
constexpr double kDefaultFlatExponent = 8;

std::string vec(const Vec3& v) {
  return "(" + format_number(v.x()) + " " + format_number(v.y()) + " " + format_number(v.z()) + ")";
}

double flat_exponent(const Deformation& d) {
  return d.parameter == 0 ? kDefaultFlatExponent : d.parameter;
}

// Value and derivative of a Bezier function with coefficients c (at most 64) over t in [0, 1].
double bernstein(const std::vector<double>& c, double t, double* derivative) {
  const int d = static_cast<int>(c.size()) - 1;
  double work[64];
  if (derivative != nullptr) {
    std::copy(c.begin(), c.end(), work);
    *derivative = detail::casteljau_in_place(work, d, t, 1, 0.0);
  }
  std::copy(c.begin(), c.end(), work);
  return detail::casteljau_in_place(work, d, t, 0, 0.0);
}

// d(M) grows from the skeleton; x = d def / r with its gradient from the pieces.
struct Normalized {
  double x = 0;
  Vec3 gradient = Vec3::Zero();
};

// grad(d def / r) = (def / r) grad d + d (def' / r - def r' / r^2) grad t.
Normalized normalize(double d, const Vec3& grad_d, double def, double def_dt, double r, double r_dt,
                     const Vec3& grad_t) {
  Normalized n;
  if (!std::isfinite(def)) {
    n.x = kInf;
    return n;
  }
  n.x = d * def / r;
  n.gradient = (def / r) * grad_d + (d * (def_dt / r - def * r_dt / (r * r))) * grad_t;
  return n;
}

// The distance range of a skeleton inside `inner` (a box containing it) over `box`, for an
// element whose distance is convex (segments) or only 1-Lipschitz (curves, surfaces).
DistanceRange lipschitz_distance(double dc, const Aabb& box, const Aabb& inner) {
  const double half = 0.5 * box.diagonal().norm();
  return {std::max({0.0, dc - half, std::sqrt(squared_distance(box, inner))}), dc + half};
}

// x range from a distance range and the extremes of def and r.
DistanceRange scale_range(const DistanceRange& d, const Interval& def, double r_min, double r_max) {
  DistanceRange x;
  x.min = d.min * def.lo / r_max;
  x.max = std::isfinite(def.hi) ? d.max * def.hi / r_min : kInf;
  return x;
}

Aabb grow(const Aabb& box, double pad) {
  return {box.min() - Vec3::Constant(pad), box.max() + Vec3::Constant(pad)};
}

class AnisotropicSegment final : public Element {
 public:
  AnisotropicSegment(const Vec3& a, const Vec3& b, double radius, Deformation def)
      : a_(a), b_(b), radius_(radius), def_(std::move(def)), range_(deformation_range(def_)) {
    length_ = (b - a).norm();
    u_ = (b - a) / length_;
    box_ = Aabb(a.cwiseMin(b), a.cwiseMax(b));
  }
  double distance(const Vec3& p, Vec3& gradient) const override {
    const double s = u_.dot(p - a_);
    const double t = std::clamp(s / length_, 0.0, 1.0);
    const Vec3 diff = p - (a_ + (t * length_) * u_);
    const double d = diff.norm();
    const Vec3 grad_d = d > 0 ? Vec3(diff / d) : Vec3::Zero();
    const Vec3 grad_t = s > 0 && s < length_ ? Vec3(u_ / length_) : Vec3::Zero();
    double def_dt = 0;
    const double def = deformation_value(def_, t, &def_dt);
    const Normalized n = normalize(d, grad_d, def, def_dt, radius_, 0, grad_t);
    gradient = n.gradient;
    return n.x;
  }
  DistanceRange range(const Aabb& box) const override {
    // The distance to a segment is convex: its maximum over the box is at a corner.
    const Vec3 c = box.center();
    const double dc = segment_distance(c);
    DistanceRange d = lipschitz_distance(dc, box, box_);
    d.max = 0;
    for (int k = 0; k < 8; ++k) {
      d.max = std::max(d.max, segment_distance(box.corner(static_cast<Aabb::CornerType>(k))));
    }
    return scale_range(d, range_, radius_, radius_);
  }
  Aabb grown_box(double pad) const override { return grow(box_, pad * radius_ / range_.lo); }
  std::string describe() const override {
    return "anisotropic segment skeleton " + vec(a_) + " to " + vec(b_) + ", radius " +
           format_number(radius_) + ", def " + format_deformation(def_);
  }

 private:
  double segment_distance(const Vec3& p) const {
    const double t = std::clamp(u_.dot(p - a_), 0.0, length_);
    return (p - (a_ + t * u_)).norm();
  }
  Vec3 a_, b_, u_;
  double radius_, length_;
  Deformation def_;
  Interval range_;
  Aabb box_;
};

// The order-th derivative of a Bezier function of at most 16 coefficients (a curve's controls
// or radii) at t.
template <class V>
V derivative_at(const std::vector<V>& values, double t, int order, const V& zero) {
  std::array<V, 16> work;
  std::copy(values.begin(), values.end(), work.begin());
  return detail::casteljau_in_place(work.data(), static_cast<int>(values.size()) - 1, t, order,
                                    zero);
}

class BezierElement final : public Element {
 public:
  BezierElement(BezierProjector projector, double radius, Deformation def, TieRule tie)
      : projector_(std::move(projector)),
        radius_(radius),
        def_(std::move(def)),
        range_(deformation_range(def_)),
        tie_(tie) {
    const auto& radii = projector_.curve().radii;
    if (radii.empty()) {
      r_min_ = r_max_ = radius_;
    } else {
      // Convex-hull property of the Bernstein basis: r(t) lies between its coefficients.
      r_min_ = *std::min_element(radii.begin(), radii.end());
      r_max_ = *std::max_element(radii.begin(), radii.end());
    }
  }
  double distance(const Vec3& p, Vec3& gradient) const override {
    return from_projection(p, projector_.project(p, tie_), gradient);
  }
  // The batched projection (SIMD across points), equal point by point to project().
  void distances(std::span<const Vec3> points, std::span<double> out,
                 std::span<Vec3> gradients) const override {
    constexpr std::size_t kBlock = 256;
    std::array<BezierProjection, kBlock> proj;
    for (std::size_t b = 0; b < points.size(); b += kBlock) {
      const std::size_t n = std::min(kBlock, points.size() - b);
      projector_.project(points.subspan(b, n), std::span<BezierProjection>(proj.data(), n), tie_);
      for (std::size_t i = 0; i < n; ++i)
        out[b + i] = from_projection(points[b + i], proj[i], gradients[b + i]);
    }
  }
  DistanceRange range(const Aabb& box) const override {
    const double dc = projector_.project(box.center(), tie_).distance;
    return scale_range(lipschitz_distance(dc, box, projector_.box()), range_, r_min_, r_max_);
  }
  Aabb grown_box(double pad) const override {
    return grow(projector_.box(), pad * r_max_ / range_.lo);
  }
  std::string describe() const override {
    const BezierCurve& c = projector_.curve();
    std::string radius = c.radii.empty() ? format_number(radius_)
                                         : format_number(r_min_) + "–" + format_number(r_max_) +
                                               " (per control point)";
    return "Bezier curve skeleton of degree " + std::to_string(projector_.degree()) + " from " +
           vec(c.controls.front()) + " to " + vec(c.controls.back()) + ", radius " + radius +
           ", def " + format_deformation(def_) +
           (tie_ == TieRule::kLast ? ", ties to the largest t" : "");
  }

 private:
  // The normalized distance and its gradient at p from its projection on the curve.
  double from_projection(const Vec3& p, const BezierProjection& proj, Vec3& gradient) const {
    const double d = proj.distance;
    const Vec3 diff = p - proj.point;
    const Vec3 grad_d = d > 0 ? Vec3(diff / d) : Vec3::Zero();
    const BezierCurve& c = projector_.curve();
    Vec3 grad_t = Vec3::Zero();
    // The projector validated the curve: the derivatives come straight from de Casteljau.
    if (proj.t > 0 && proj.t < 1) {
      const Vec3 c1 = derivative_at(c.controls, proj.t, 1, Vec3(Vec3::Zero()));
      const Vec3 c2 = derivative_at(c.controls, proj.t, 2, Vec3(Vec3::Zero()));
      const double denom = c1.squaredNorm() - c2.dot(diff);
      if (denom > 0) grad_t = c1 / denom;
    }
    double def_dt = 0;
    const double def = deformation_value(def_, proj.t, &def_dt);
    double r = radius_, r_dt = 0;
    if (!c.radii.empty()) {
      r = derivative_at(c.radii, proj.t, 0, 0.0);
      r_dt = derivative_at(c.radii, proj.t, 1, 0.0);
    }
    const Normalized n = normalize(d, grad_d, def, def_dt, r, r_dt, grad_t);
    gradient = n.gradient;
    return n.x;
  }

  BezierProjector projector_;
  double radius_;
  Deformation def_;
  Interval range_;
  TieRule tie_;
  double r_min_ = 1, r_max_ = 1;
};

class SurfaceElement final : public Element {
 public:
  SurfaceElement(std::shared_ptr<const SurfaceSkeleton> skeleton, double radius, Deformation du,
                 Deformation dv)
      : skeleton_(std::move(skeleton)), radius_(radius), du_(std::move(du)), dv_(std::move(dv)) {
    const Interval ru = deformation_range(du_);
    const Interval rv = deformation_range(dv_);
    range_ = {ru.lo * rv.lo, ru.hi * rv.hi};
  }
  double distance(const Vec3& p, Vec3& gradient) const override {
    const SurfaceProjection proj = skeleton_->project(p);
    double du_dt = 0, dv_dt = 0;
    const double du = deformation_value(du_, proj.u, &du_dt);
    const double dv = deformation_value(dv_, proj.v, &dv_dt);
    if (!std::isfinite(du) || !std::isfinite(dv)) {
      gradient.setZero();
      return kInf;
    }
    const double def = du * dv;
    const Vec3 grad_def = (du_dt * dv) * proj.grad_u + (du * dv_dt) * proj.grad_v;
    gradient = (def * proj.gradient + proj.distance * grad_def) / radius_;
    return proj.distance * def / radius_;
  }
  DistanceRange range(const Aabb& box) const override {
    const auto [lo, hi] = skeleton_->distance_range(box);
    return scale_range({lo, hi}, range_, radius_, radius_);
  }
  Aabb grown_box(double pad) const override {
    return grow(skeleton_->box(), pad * radius_ / range_.lo);
  }
  std::string describe() const override {
    return "surface skeleton (" + skeleton_->surface().describe() + "), " +
           std::to_string(skeleton_->patch_count()) + " flat sub-patches (depth " +
           std::to_string(skeleton_->depth_reached()) + "), approximation error " +
           (skeleton_->error_is_estimate() ? "about " : "at most ") +
           format_number(skeleton_->error_bound()) + ", radius " + format_number(radius_) +
           ", def_u " + format_deformation(du_) + ", def_v " + format_deformation(dv_);
  }

 private:
  std::shared_ptr<const SurfaceSkeleton> skeleton_;
  double radius_;
  Deformation du_, dv_;
  Interval range_;
};

void check_radius(double r, const std::string& what) {
  if (!std::isfinite(r) || r <= 0) {
    throw InvalidArgument(what + ": radius must be finite and > 0, got " + format_number(r));
  }
}

std::vector<double> parse_values(const std::string& text, const std::string& what) {
  std::vector<double> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    double v = 0;
    if (parse_number(item, v) != NumberStatus::kOk) {
      throw InvalidArgument(what + ": '" + item + "' is not a finite number");
    }
    out.push_back(v);
    start = comma + 1;
  }
  return out;
}

}  // namespace

void validate(const Deformation& def, const std::string& what) {
  using K = Deformation::Kind;
  auto need = [&](bool ok, const std::string& message) {
    if (!ok) throw InvalidArgument(what + ": " + message);
  };
  switch (def.kind) {
    case K::kIdentity:
      break;
    case K::kSquaredCosine:
      need(std::isfinite(def.parameter) && def.parameter >= 0 && def.parameter <= 1,
           "squared-cosine end thickness must be in [0, 1], got " + format_number(def.parameter));
      break;
    case K::kFlatEnds:
      need(def.parameter == 0 ||
               (std::isfinite(def.parameter) && def.parameter >= 2 && def.parameter <= 64),
           "flat-ends exponent must be in [2, 64], got " + format_number(def.parameter));
      break;
    case K::kWave:
      need(std::isfinite(def.parameter) && def.parameter >= 0 && def.parameter < 1,
           "wave amplitude must be in [0, 1), got " + format_number(def.parameter));
      need(std::isfinite(def.waves) && def.waves > 0 && def.waves <= 1000,
           "wave count must be in (0, 1000], got " + format_number(def.waves));
      break;
    case K::kLinear:
    case K::kBezier: {
      const bool linear = def.kind == K::kLinear;
      need(def.values.size() >= (linear ? 2u : 1u) && def.values.size() <= 64,
           std::string(linear ? "linear" : "bezier") + " needs " + (linear ? "2" : "1") +
               " to 64 values, got " + std::to_string(def.values.size()));
      for (std::size_t i = 0; i < def.values.size(); ++i) {
        need(std::isfinite(def.values[i]) && def.values[i] > 0,
             "value " + std::to_string(i + 1) + " must be finite and > 0, got " +
                 format_number(def.values[i]));
      }
      break;
    }
  }
}

double deformation_value(const Deformation& def, double t, double* derivative) {
  using K = Deformation::Kind;
  double dv = 0, v = 1;
  switch (def.kind) {
    case K::kIdentity:
      break;
    case K::kSquaredCosine: {
      const double s = def.parameter;
      const double sn = pm::sin(kPi * t);
      const double g = s + (1 - s) * sn * sn;
      if (!(g > 0)) {
        v = kInf;
        break;
      }
      v = 1 / g;
      dv = -(1 - s) * kPi * pm::sin(2 * kPi * t) * v * v;
      break;
    }
    case K::kFlatEnds: {
      const double n = flat_exponent(def);
      const double a = std::abs(2 * t - 1);
      const double h = 1 - pm::pow(a, n);
      if (!(h > 0)) {
        v = kInf;
        break;
      }
      v = pm::pow(h, -1 / n);
      dv = (2 * t - 1 >= 0 ? 2.0 : -2.0) * pm::pow(a, n - 1) * v / h;
      break;
    }
    case K::kWave: {
      const double w = 2 * kPi * def.waves;
      const double g = 1 + def.parameter * pm::cos(w * t);
      v = 1 / g;
      dv = def.parameter * w * pm::sin(w * t) * v * v;
      break;
    }
    case K::kLinear: {
      const std::size_t m = def.values.size();
      const double x = std::clamp(t, 0.0, 1.0) * static_cast<double>(m - 1);
      const std::size_t i = std::min(static_cast<std::size_t>(x), m - 2);
      const double f = x - static_cast<double>(i);
      const double step = def.values[i + 1] - def.values[i];
      v = def.values[i] + f * step;
      dv = step * static_cast<double>(m - 1);
      break;
    }
    case K::kBezier:
      v = bernstein(def.values, t, &dv);
      break;
  }
  if (derivative != nullptr) *derivative = std::isfinite(v) ? dv : 0.0;
  return v;
}

Interval deformation_range(const Deformation& def) {
  using K = Deformation::Kind;
  switch (def.kind) {
    case K::kIdentity:
      return {1, 1};
    case K::kSquaredCosine:
      return {1, def.parameter > 0 ? 1 / def.parameter : kInf};
    case K::kFlatEnds:
      return {1, kInf};
    case K::kWave:
      return {1 / (1 + def.parameter), 1 / (1 - def.parameter)};
    case K::kLinear:
    case K::kBezier: {
      const auto [lo, hi] = std::minmax_element(def.values.begin(), def.values.end());
      return {*lo, *hi};
    }
  }
  return {1, 1};
}

Deformation parse_deformation(const std::string& text) {
  const std::size_t colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  const std::string args = colon == std::string::npos ? "" : text.substr(colon + 1);
  const std::string what = "deformation '" + text + "'";
  Deformation d;
  using K = Deformation::Kind;
  auto numbers = [&](std::size_t lo, std::size_t hi) {
    std::vector<double> v = args.empty() ? std::vector<double>{} : parse_values(args, what);
    if (v.size() < lo || v.size() > hi) {
      throw InvalidArgument(what + ": " + kind + " takes " + std::to_string(lo) +
                            (hi > lo ? " to " + std::to_string(hi) : std::string()) +
                            " number(s), got " + std::to_string(v.size()));
    }
    return v;
  };
  if (kind == "identity" || kind == "none") {
    d.kind = K::kIdentity;
    numbers(0, 0);
  } else if (kind == "squared-cosine") {
    d.kind = K::kSquaredCosine;
    const auto v = numbers(0, 1);
    d.parameter = v.empty() ? 0.25 : v[0];
  } else if (kind == "flat") {
    d.kind = K::kFlatEnds;
    const auto v = numbers(0, 1);
    d.parameter = v.empty() ? kDefaultFlatExponent : v[0];
  } else if (kind == "wave") {
    d.kind = K::kWave;
    const auto v = numbers(1, 2);
    d.parameter = v[0];
    if (v.size() > 1) d.waves = v[1];
  } else if (kind == "linear") {
    d.kind = K::kLinear;
    d.values = numbers(2, 64);
  } else if (kind == "bezier") {
    d.kind = K::kBezier;
    d.values = numbers(1, 64);
  } else {
    throw InvalidArgument(what + ": unknown kind '" + kind +
                          "' (expected identity, squared-cosine, flat, wave, linear or bezier)");
  }
  validate(d, what);
  return d;
}

std::string format_deformation(const Deformation& def) {
  using K = Deformation::Kind;
  auto join = [](const std::vector<double>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + format_shortest(v[i]);
    return s;
  };
  switch (def.kind) {
    case K::kIdentity:
      return "identity";
    case K::kSquaredCosine:
      return "squared-cosine:" + format_shortest(def.parameter);
    case K::kFlatEnds:
      return "flat:" + format_shortest(flat_exponent(def));
    case K::kWave:
      return "wave:" + format_shortest(def.parameter) + "," + format_shortest(def.waves);
    case K::kLinear:
      return "linear:" + join(def.values);
    case K::kBezier:
      return "bezier:" + join(def.values);
  }
  return "identity";
}

FieldPtr make_anisotropic_segment_field(const Vec3& a, const Vec3& b, double radius,
                                        const Deformation& def,
                                        const DistancePrimitiveOptions& options) {
  const std::string what = "anisotropic segment";
  if (!a.allFinite() || !b.allFinite()) {
    throw InvalidArgument(what + ": end points must be finite, got " + vec(a) + " and " + vec(b));
  }
  if (!((b - a).norm() > 0)) throw InvalidArgument(what + ": a and b coincide at " + vec(a));
  check_radius(radius, what);
  validate(def, what + ": def");
  const detail::Resolved o = detail::resolve(options, what);
  return std::make_shared<DistancePrimitive>(
      std::make_unique<AnisotropicSegment>(a, b, radius, def), o, 0.0);
}

FieldPtr make_bezier_field(const BezierCurve& curve, double radius, const Deformation& def,
                           TieRule tie, const DistancePrimitiveOptions& options) {
  const std::string what = "bezier curve";
  BezierProjector projector(curve, what);
  if (curve.radii.empty()) check_radius(radius, what);
  validate(def, what + ": def");
  const detail::Resolved o = detail::resolve(options, what);
  return std::make_shared<DistancePrimitive>(
      std::make_unique<BezierElement>(std::move(projector), radius, def, tie), o, 0.0);
}

FieldPtr make_surface_skeleton_field(std::shared_ptr<const SurfaceSkeleton> skeleton, double radius,
                                     const Deformation& def_u, const Deformation& def_v,
                                     const DistancePrimitiveOptions& options) {
  const std::string what = "surface skeleton";
  if (!skeleton) throw InvalidArgument(what + ": no surface");
  check_radius(radius, what);
  validate(def_u, what + ": def_u");
  validate(def_v, what + ": def_v");
  const detail::Resolved o = detail::resolve(options, what);
  return std::make_shared<DistancePrimitive>(
      std::make_unique<SurfaceElement>(std::move(skeleton), radius, def_u, def_v), o, 0.0);
}

}  // namespace ramiform

namespace ramiform {

std::vector<SkeletonDistance> skeleton_distances(const Skeleton& skeleton,
                                                 std::span<const Vec3> points, TieRule tie,
                                                 const Context* ctx) {
  validate(skeleton);
  // Elements: every edge (a projector for the curved ones), then the isolated nodes.
  struct Item {
    bool is_edge;
    std::uint32_t index;
    int curve;  // index into `curves`, -1 for a straight edge or a node
  };
  std::vector<Item> items;
  std::vector<Aabb> boxes;
  std::vector<BezierProjector> curves;
  std::vector<std::uint32_t> curve_item;  // the element id of each curve
  std::vector<Vec3> controls;
  std::vector<double> radii;
  for (std::size_t e = 0; e < skeleton.edges.size(); ++e) {
    edge_controls(skeleton, e, controls, radii);
    Aabb box;
    for (const Vec3& c : controls) box.extend(c);
    int curve = -1;
    if (controls.size() > 2) {
      curve = static_cast<int>(curves.size());
      curves.emplace_back(BezierCurve{controls, {}}, "edge " + std::to_string(e));
      curve_item.push_back(static_cast<std::uint32_t>(items.size()));
    }
    items.push_back({true, static_cast<std::uint32_t>(e), curve});
    boxes.push_back(box);
  }
  const std::vector<std::uint32_t> deg = degrees(skeleton);
  for (std::size_t i = 0; i < skeleton.nodes.size(); ++i) {
    if (deg[i] != 0) continue;
    items.push_back({false, static_cast<std::uint32_t>(i), -1});
    boxes.emplace_back(skeleton.nodes[i].position, skeleton.nodes[i].position);
  }
  const detail::BoxBvh bvh(boxes);
  // Points of each curve (t = j / (kSamples - 1)): their distances bound the curve's from above.
  // `scale`: the largest coordinate of the curves' controls (for the rounding slack below).
  constexpr std::size_t kSamples = 5;
  std::vector<Vec3> samples;
  double scale = 0;
  for (const BezierProjector& c : curves) {
    for (std::size_t j = 0; j < kSamples; ++j)
      samples.push_back(bezier_point(c.curve(), static_cast<double>(j) / (kSamples - 1)));
    for (const Vec3& x : c.curve().controls) scale = std::max(scale, x.cwiseAbs().maxCoeff());
  }
  // The squared distance from p to a straight edge or a node `id`, the edge's parameter in *t.
  auto straight = [&](const Vec3& p, std::uint32_t id, double* t) {
    const Item& item = items[id];
    *t = 0;
    if (!item.is_edge) return (p - skeleton.nodes[item.index].position).squaredNorm();
    const auto [a, b] = skeleton.edges[item.index];
    const Vec3 pa = skeleton.nodes[a].position;
    const Vec3 ab = skeleton.nodes[b].position - pa;
    *t = std::clamp((p - pa).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (p - (pa + *t * ab)).squaredNorm();
  };
  // The nearest element of every point: the least squared distance, ties to the lower id (edges
  // come before nodes), as BoxBvh::nearest decides. A block of points at a time: the curves that
  // may be nearest to each point are found first, then each curve projects all of the block's
  // points that need it in one batched call (BezierProjector::project(points, out), equal bit
  // for bit to project(p)), so the result is the same as projecting one point at a time.
  std::vector<SkeletonDistance> out(points.size());
  constexpr std::size_t kBlock = 256;
  parallel::for_chunks(
      points.size(), kBlock,
      [&](std::size_t begin, std::size_t end) {
        struct Best {
          double d2 = std::numeric_limits<double>::infinity();
          std::uint32_t id = UINT32_MAX;
          double t = 0, distance = 0;
          void offer(std::uint32_t i, double d2_i, double t_i, double distance_i) {
            if (d2_i < d2 || (d2_i == d2 && i < id)) {
              d2 = d2_i;
              id = i;
              t = t_i;
              distance = distance_i >= 0 ? distance_i : std::sqrt(d2_i);
            }
          }
        };
        std::vector<Best> best(end - begin);
        // Per curve, the points of the block (offsets from `begin`) that need its projection.
        std::vector<std::vector<std::uint32_t>> need(curves.size());
        std::vector<std::uint32_t> visited;
        for (std::size_t k = begin; k < end; ++k) {
          const Vec3& p = points[k];
          Best& b = best[k - begin];
          if (!p.allFinite()) {
            throw InvalidArgument("skeleton_distances: point " + std::to_string(k) +
                                  " is not finite: " + vec(p));
          }
          // The straight edges and the nodes exactly, the curves by an upper bound (their
          // sample points, inflated so that it holds for project()'s rounded distance too):
          // `bound` is then at least the nearest squared distance, and every curve whose box is
          // within it was visited (the others are farther than the nearest).
          visited.clear();
          const double slack = 1e-12 * (scale + p.cwiseAbs().maxCoeff());
          double bound = std::numeric_limits<double>::infinity();
          (void)bvh.nearest(
              p,
              [&](std::uint32_t i) {
                const Item& item = items[i];
                if (item.curve < 0) {
                  double t = 0;
                  const double d2 = straight(p, i, &t);
                  b.offer(i, d2, t, -1);
                  return d2;
                }
                visited.push_back(i);
                double d2 = std::numeric_limits<double>::infinity();
                const std::size_t c = static_cast<std::size_t>(item.curve);
                for (std::size_t j = c * kSamples; j < (c + 1) * kSamples; ++j)
                  d2 = std::min(d2, (p - samples[j]).squaredNorm());
                // Inflated past the rounding of both this value and project()'s distance.
                const double r = std::sqrt(d2) * (1 + 1e-9) + slack;
                return r * r;
              },
              &bound);
          for (const std::uint32_t i : visited) {
            if (squared_distance(bvh.item_box(i), p) > bound) continue;
            need[static_cast<std::size_t>(items[i].curve)].push_back(
                static_cast<std::uint32_t>(k - begin));
          }
        }
        // Each curve projects its points in one call.
        std::vector<Vec3> batch;
        std::vector<BezierProjection> projected;
        for (std::size_t c = 0; c < curves.size(); ++c) {
          if (need[c].empty()) continue;
          batch.clear();
          for (const std::uint32_t k : need[c]) batch.push_back(points[begin + k]);
          projected.resize(batch.size());
          curves[c].project(batch, projected, tie);
          for (std::size_t m = 0; m < batch.size(); ++m) {
            const BezierProjection& proj = projected[m];
            best[need[c][m]].offer(curve_item[c], proj.distance * proj.distance, proj.t,
                                   proj.distance);
          }
        }
        for (std::size_t k = begin; k < end; ++k) {
          const Best& b = best[k - begin];
          const Item& item = items[b.id];
          SkeletonDistance& r = out[k];
          r.is_edge = item.is_edge;
          r.index = item.index;
          r.distance = b.distance;
          r.t = b.t;
        }
      },
      ctx);
  return out;
}

}  // namespace ramiform
