// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/sweep.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/parallel.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {
namespace {

using Box2 = Eigen::AlignedBox2d;

// Default flattening chord error, relative to the curve's extent (CurveSurfaceOptions).
constexpr double kDefaultRelativeTolerance = 1e-3;
// Newton projection: at most this many steps; converged when the parameter step falls below
// kNewtonStep (t lives in [0, 1], so this is a few ulps), or when the residual
// |(C - p)·C'| / |C'| falls below kNewtonResidual times the path's extent (rounding noise near
// the centre of curvature, where g' is small, can keep the step from shrinking further).
constexpr int kNewtonIterations = 24;
constexpr double kNewtonStep = 1e-15;
constexpr double kNewtonResidual = 1e-13;
// A double reflection whose second reflection vector is this short (squared, unit tangents)
// is the identity: the tangents already agree after the first reflection.
constexpr double kReflectionEpsilon = 1e-24;
// Largest turn of the tangent (radians) between two frame samples of a smooth path.
constexpr double kFrameAngle = 0.005;
// Relative widening of bound() results and support reaches against rounding.
constexpr double kBoundSlack = 1e-12;
constexpr double kReachMargin = 1e-9;
// Segments per pruning block of the 2-D distance and of the coarse path projection.
constexpr std::size_t kBlock = 8;
// Points per parallel chunk of a batch evaluation.
constexpr std::size_t kGrain = 64;

// ---------------------------------------------------------------------------------------------
// The kernel part: f = weight k(d / R), cut off and faded for infinite kernels.

struct Falloff {
  Kernel kernel;
  double iso = 0.5;
  double weight = 1;
  double R = 1;         // radius of influence
  double xc = 1;        // normalized support (cut-off for infinite kernels)
  bool fades = false;   // infinite kernel: C1 fade between 0.8 and 1 of the cut-off
  double d_inside = -1; // f > iso only where d < d_inside; < 0: nowhere inside

  double value(double d, double* dfdd) const {
    const double x = d / R;
    if (!(x < xc)) {
      if (dfdd != nullptr) *dfdd = 0;
      return 0;
    }
    double k = kernel.value(x);
    double dk = kernel.derivative(x) / R;
    if (fades) {
      const double v = (x / xc) * (x / xc);
      const double v0 = tol::kFadeStart * tol::kFadeStart;
      if (v > v0) {
        const double s = (v - v0) / (1 - v0);
        const double fade = 1 - s * s * (3 - 2 * s);
        const double dfade_dd = -6 * s * (1 - s) / (1 - v0) * (2 * x / (xc * xc * R));
        dk = dk * fade + k * dfade_dd;
        k *= fade;
      }
    }
    if (dfdd != nullptr) *dfdd = weight * dk;
    return weight * k;
  }
  // Bound of f over distances in [dmin, dmax] (f is non-increasing in d).
  Interval range(double dmin, double dmax) const {
    const double hi = value(std::max(dmin, 0.0), nullptr);
    const double lo = value(dmax, nullptr);
    return {lo * (1 - kBoundSlack), hi * (1 + kBoundSlack)};
  }
  double support_reach() const { return R * xc; }
};

bool is_infinite(KernelKind k) {
  return k == KernelKind::kBlinn || k == KernelKind::kInversePower || k == KernelKind::kCauchy;
}

void check_positive(double v, const std::string& what, const std::string& name) {
  if (!std::isfinite(v) || v <= 0) {
    throw InvalidArgument(what + ": " + name + " must be finite and > 0, got " + std::to_string(v));
  }
}

Falloff make_falloff(const CurveSurfaceOptions& o, const std::string& what) {
  Falloff f;
  try {
    o.kernel.validate();
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(what + ": " + e.what());
  }
  if (!std::isfinite(o.iso) || o.iso < 0) {
    throw InvalidArgument(what + ": iso must be finite and > 0 (0 = kernel default), got " +
                          std::to_string(o.iso));
  }
  check_positive(o.weight, what, "weight");
  check_positive(o.radius, what, "radius");
  if (!std::isfinite(o.tolerance) || o.tolerance < 0) {
    throw InvalidArgument(what + ": tolerance must be finite and >= 0 (0 = default), got " +
                          std::to_string(o.tolerance));
  }
  f.kernel = o.kernel;
  f.iso = o.iso == 0 ? o.kernel.default_iso() : o.iso;
  f.weight = o.weight;
  double x_iso = 0;
  try {
    x_iso = o.kernel.x_at(f.iso);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(what + ": " + e.what());
  }
  f.R = o.radius / x_iso;
  f.fades = is_infinite(o.kernel.kind);
  f.xc = o.kernel.support(f.iso / f.weight);
  try {
    f.d_inside = std::min(f.xc, o.kernel.x_at(f.iso / f.weight)) * f.R;
  } catch (const InvalidArgument&) {
    f.d_inside = -1;  // weight k never exceeds iso
  }
  return f;
}

template <class V>
double extent_of(const std::vector<V>& pts) {
  Eigen::AlignedBox<double, V::RowsAtCompileTime> box;
  for (const auto& p : pts) box.extend(p);
  return box.isEmpty() ? 0.0 : box.diagonal().norm();
}

double tolerance_for(double option, double extent) {
  if (option > 0) return option;
  return extent > 0 ? kDefaultRelativeTolerance * extent : 1.0;  // a point: any tolerance is exact
}

// ---------------------------------------------------------------------------------------------
// Distance to a flattened planar curve, or to the region it bounds when closed (even-odd rule).

class Region2 {
 public:
  Region2(std::vector<Vec2> vertices, bool closed) : v_(std::move(vertices)), closed_(closed) {
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

  // d(q) and, when `grad` is set, its gradient (0 inside a closed region).
  double distance(const Vec2& q, Vec2* grad) const {
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

  double extent() const { return extent_; }  // largest |vertex| (distance from the origin)
  const Box2& box() const { return box_; }
  const std::vector<Vec2>& vertices() const { return v_; }
  bool closed() const { return closed_; }

 private:
  struct Block {
    Box2 box;
    std::size_t begin, end;
  };
  std::vector<Vec2> v_;
  bool closed_;
  std::vector<Block> blocks_;
  Box2 box_;
  double extent_ = 0;
};

Region2 make_region(const Curve2& curve, double tolerance_option) {
  const double tol = tolerance_for(tolerance_option, extent_of(curve.points));
  return Region2(flatten(curve, tol), curve.closed);
}

// ---------------------------------------------------------------------------------------------
// The path: exact curve, flattened polyline with curve parameters and normalized arc lengths,
// rotation-minimizing frames at the polyline's vertices.

class Path {
 public:
  struct Projection {
    double t = 0, s = 0, dsdt = 0;
    Vec3 origin, tangent, normal, binormal;
    Vec3 dtdp = Vec3::Zero();  // gradient of t with respect to p (0 where t is locally constant)
    bool newton = false;
  };

  Path(const Curve3& curve, double tolerance_option, const std::string& what) : curve_(curve) {
    try {
      validate(curve);
    } catch (const InvalidArgument& e) {
      throw InvalidArgument(what + ": path: " + e.what());
    }
    extent_ = extent_of(curve.points);
    if (!(extent_ > 0)) throw InvalidArgument(what + ": the path has zero length (all its points coincide)");
    tol_ = tolerance_for(tolerance_option, extent_);
    polyline_ = curve.kind == CurveKind::kPolyline;
    const FlattenedCurve3 flat = flatten_with_parameters(curve, tol_);
    const double eps = tol::kCoincident * extent_;
    for (std::size_t i = 0; i < flat.points.size(); ++i) {
      if (v_.empty() || (flat.points[i] - v_.back()).norm() > eps) {
        v_.push_back(flat.points[i]);
        t_.push_back(flat.parameters[i]);
      } else if (i + 1 == flat.points.size() && v_.size() > 1) {
        v_.back() = flat.points[i];
        t_.back() = flat.parameters[i];
      }
    }
    if (v_.size() < 2) throw InvalidArgument(what + ": the path has zero length");
    t_.front() = 0;
    t_.back() = 1;
    s_.assign(v_.size(), 0.0);
    for (std::size_t i = 1; i < v_.size(); ++i) s_[i] = s_[i - 1] + (v_[i] - v_[i - 1]).norm();
    length_ = s_.back();
    for (auto& s : s_) s /= length_;
    s_.back() = 1;
    for (const auto& p : curve.points) box_.extend(p);
    for (const auto& p : v_) box_.extend(p);
    build_frames();
    for (std::size_t b = 0; b + 1 < v_.size(); b += kBlock) {
      Block block{Aabb(), b, std::min(v_.size() - 1, b + kBlock)};
      for (std::size_t i = block.begin; i <= block.end; ++i) block.box.extend(v_[i]);
      blocks_.push_back(block);
    }
  }

  std::size_t pieces() const { return v_.size() - 1; }
  const Aabb& box() const { return box_; }     // contains the exact curve (convex hull property)
  double tolerance() const { return tol_; }    // chord error of the flattened path
  double length() const { return length_; }

  // Closest point of the flattened polyline: piece and position u in [0, 1] on it.
  struct Coarse {
    std::size_t piece = 0;
    double u = 0, d2 = std::numeric_limits<double>::infinity();
  };
  Coarse coarse(const Vec3& p) const {
    Coarse best;
    for (const Block& block : blocks_) {
      if (squared_distance(block.box, p) >= best.d2) continue;
      for (std::size_t j = block.begin; j < block.end; ++j) {
        const Vec3 ab = v_[j + 1] - v_[j];
        const double u = std::clamp((p - v_[j]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        const double d2 = (p - (v_[j] + u * ab)).squaredNorm();
        if (d2 < best.d2) best = {j, u, d2};
      }
    }
    return best;
  }

  Projection project(const Vec3& p) const {
    const Coarse c = coarse(p);
    const std::size_t j = c.piece;
    const double dt = t_[j + 1] - t_[j];
    const Vec3 ab = v_[j + 1] - v_[j];
    Projection out;
    // The polyline's own answer (and the fallback of Newton).
    const double t0 = t_[j] + c.u * dt;
    const bool u_clamped = c.u <= 0 || c.u >= 1;
    const Vec3 dtdp0 = u_clamped ? Vec3::Zero() : Vec3(ab * dt / ab.squaredNorm());
    if (polyline_) {
      out.t = t0;
      out.origin = v_[j] + c.u * ab;
      out.dtdp = dtdp0;
      polyline_frame(out, j, c.u, &p);
      set_s(out, j, c.u);
      return out;
    }
    const Vec3 c0 = point(t0);
    const double d0 = (c0 - p).squaredNorm();
    double t = t0;
    bool converged = false;
    for (int it = 0; it < kNewtonIterations; ++it) {
      const Vec3 x = point(t);
      const Vec3 d1 = derivative(t);
      const Vec3 d2 = second_derivative(t);
      const double g = (x - p).dot(d1);
      const double gp = d1.squaredNorm() + (x - p).dot(d2);
      if ((t <= 0 && g >= 0) || (t >= 1 && g <= 0)) {  // minimum at an end of the path
        converged = true;
        break;
      }
      if (std::abs(g) <= kNewtonResidual * extent_ * d1.norm()) {
        converged = true;
        break;
      }
      if (!(gp > 0)) break;
      const double tn = std::clamp(t - g / gp, 0.0, 1.0);
      const double step = std::abs(tn - t);
      t = tn;
      if (step <= kNewtonStep) {
        converged = true;
        break;
      }
    }
    const Vec3 x = point(t);
    if (converged && (x - p).squaredNorm() <= d0 * (1 + kBoundSlack)) {
      out.t = t;
      out.origin = x;
      out.newton = true;
      const std::size_t k = piece_of_t(t);
      out.tangent = smooth_tangent(t, k);
      if (t > 0 && t < 1) {
        const Vec3 d1 = derivative(t);
        const double gp = d1.squaredNorm() + (x - p).dot(second_derivative(t));
        if (gp > 0) out.dtdp = d1 / gp;
      }
      set_s(out, k, (t - t_[k]) / (t_[k + 1] - t_[k]));
      smooth_frame(out);
      return out;
    }
    out.t = t0;
    out.origin = c0;
    out.tangent = smooth_tangent(t0, j);
    out.dtdp = dtdp0;
    set_s(out, j, c.u);
    smooth_frame(out);
    return out;
  }

  PathFrame frame_at_s(double s) const {
    const std::size_t j = std::min<std::size_t>(
        pieces() - 1,
        static_cast<std::size_t>(std::upper_bound(s_.begin(), s_.end(), s) - s_.begin()) - 1);
    const double w = std::clamp((s - s_[j]) / (s_[j + 1] - s_[j]), 0.0, 1.0);
    Projection pr;
    if (polyline_) {
      pr.t = t_[j] + w * (t_[j + 1] - t_[j]);
      pr.origin = v_[j] + w * (v_[j + 1] - v_[j]);
      polyline_frame(pr, j, w, nullptr);
    } else {
      pr.t = w >= 1 ? t_[j + 1] : t_[j] + w * (t_[j + 1] - t_[j]);
      pr.origin = point(pr.t);
      pr.tangent = smooth_tangent(pr.t, j);
      smooth_frame(pr);
    }
    return {pr.origin, pr.tangent, pr.normal, pr.binormal};
  }

  double distance_to_polyline(const Vec3& p) const { return std::sqrt(coarse(p).d2); }

 private:
  struct Block {
    Aabb box;
    std::size_t begin, end;  // pieces [begin, end)
  };

  Vec3 point(double t) const { return curve_point(curve_, t); }
  Vec3 derivative(double t) const { return curve_derivative(curve_, t); }
  Vec3 second_derivative(double t) const { return curve_second_derivative(curve_, t); }

  std::size_t piece_of_t(double t) const {
    const auto it = std::upper_bound(t_.begin(), t_.end(), t);
    const std::size_t j = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - t_.begin() - 1, 0));
    return std::min(j, pieces() - 1);
  }

  Vec3 piece_direction(std::size_t j) const { return (v_[j + 1] - v_[j]).normalized(); }

  // The minimal rotation taking unit vector a to unit vector b (about a × b), applied to x: two
  // reflections, across the plane orthogonal to a + b (a -> -b) and across the one orthogonal
  // to b (-b -> b).
  static Vec3 rotate_between(const Vec3& a, const Vec3& b, const Vec3& x) {
    const Vec3 h = a + b;
    const double h2 = h.squaredNorm();
    if (h2 < 1e-12) return x - x.dot(b) * b;  // a hairpin: no unique rotation, keep x
    const Vec3 x1 = x - (2 * x.dot(h) / h2) * h;
    return x1 - 2 * x1.dot(b) * b;
  }

  // Polyline frame at position u of piece j. Along a piece the frame is constant (the piece's
  // direction and RMF normal). At an interior vertex the tangent turns in the bend plane from
  // the incoming to the outgoing direction, and points in the wedge beyond both pieces take the
  // tangent orthogonal to p - V (the section revolves about the bend axis: a rounded joint, no
  // notch); without a point (path_frame), the bisector.
  void polyline_frame(Projection& pr, std::size_t j, double u, const Vec3* p) const {
    const bool at_start = u <= 0 && j > 0;
    const bool at_end = u >= 1 && j + 1 < pieces();
    if (!at_start && !at_end) {
      pr.tangent = piece_direction(j);
      pr.normal = pn_[j];
    } else {
      const std::size_t v = at_end ? j + 1 : j;  // the vertex
      const Vec3 a = piece_direction(v - 1), b = piece_direction(v);
      Vec3 e = b - b.dot(a) * a;
      const double en = e.norm();
      if (en < 1e-12) {  // straight on (or a hairpin): the incoming frame
        pr.tangent = a;
        pr.normal = pn_[v - 1];
      } else {
        e /= en;
        const double theta = std::atan2(en, b.dot(a));
        double phi = 0.5 * theta;
        if (p != nullptr) {
          const Vec3 r = *p - v_[v];
          phi = std::clamp(std::atan2(r.dot(a), -r.dot(e)), 0.0, theta);
        }
        pr.tangent = std::cos(phi) * a + std::sin(phi) * e;
        pr.normal = rotate_between(a, pr.tangent, pn_[v - 1]);
        pr.normal = (pr.normal - pr.normal.dot(pr.tangent) * pr.tangent).normalized();
      }
    }
    pr.binormal = pr.tangent.cross(pr.normal);
  }

  // Exact unit tangent C'/|C'|, or the piece's direction where C' vanishes (cusps).
  Vec3 smooth_tangent(double t, std::size_t j) const {
    const Vec3 d = derivative(t);
    const double n = d.norm();
    return n > tol::kCoincident * extent_ ? Vec3(d / n) : piece_direction(j);
  }

  // Fills s and ds/dt from position w of piece j.
  void set_s(Projection& pr, std::size_t j, double w) const {
    w = std::clamp(w, 0.0, 1.0);
    pr.s = s_[j] + w * (s_[j + 1] - s_[j]);
    pr.dsdt = (s_[j + 1] - s_[j]) / (t_[j + 1] - t_[j]);
  }

  // Smooth paths: the normal and binormal at pr.t, from the RMF normals of the two neighbouring
  // frame samples blended linearly, made orthogonal to pr.tangent and normalized.
  void smooth_frame(Projection& pr) const {
    const auto it = std::upper_bound(ft_.begin(), ft_.end(), pr.t);
    const std::size_t i = std::min<std::size_t>(
        ft_.size() - 2, static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - ft_.begin() - 1, 0)));
    const double wf = std::clamp((pr.t - ft_[i]) / (ft_[i + 1] - ft_[i]), 0.0, 1.0);
    const Vec3& T = pr.tangent;
    Vec3 n = (1 - wf) * fn_[i] + wf * fn_[i + 1];
    n -= n.dot(T) * T;
    if (n.norm() < 1e-6) n = any_normal(T);
    pr.normal = n.normalized();
    pr.binormal = T.cross(pr.normal);
  }

  static Vec3 any_normal(const Vec3& T) {
    const Vec3 e = std::abs(T.x()) > 0.9 ? Vec3::UnitY() : Vec3::UnitX();
    return (e - e.dot(T) * T).normalized();
  }

  // Rotation-minimizing normals. Polylines: one normal per piece, carried across each vertex by
  // the minimal rotation between the two directions (the exact RMF of a polyline). Smooth paths:
  // double reflection (Wang, Jüttler, Zheng & Liu 2008) over frame samples.
  void build_frames() {
    const std::size_t n = v_.size();
    if (polyline_) {
      pn_.resize(pieces());
      pn_[0] = any_normal(piece_direction(0));
      for (std::size_t j = 0; j + 1 < pieces(); ++j) {
        const Vec3 b = piece_direction(j + 1);
        Vec3 r = rotate_between(piece_direction(j), b, pn_[j]);
        r -= r.dot(b) * b;
        pn_[j + 1] = r.norm() > 1e-6 ? Vec3(r.normalized()) : any_normal(b);
      }
      return;
    }
    vt_.resize(n);
    for (std::size_t j = 0; j < n; ++j) vt_[j] = smooth_tangent(t_[j], std::min(j, pieces() - 1));
    // Frame samples: the vertices, and on smooth curves more points inside each piece so that
    // consecutive tangents turn by at most kFrameAngle (double reflection is fourth-order
    // accurate in the step, and the blend between samples second-order).
    ft_.clear();
    fp_.clear();
    ftan_.clear();
    for (std::size_t j = 0; j + 1 < n; ++j) {
      const double angle = std::acos(std::clamp(vt_[j].dot(vt_[j + 1]), -1.0, 1.0));
      const int k = std::max(1, static_cast<int>(std::ceil(angle / kFrameAngle)));
      for (int i = 0; i < k; ++i) {
        if (i == 0) {
          ft_.push_back(t_[j]);
          fp_.push_back(v_[j]);
          ftan_.push_back(vt_[j]);
        } else {
          const double t = t_[j] + (t_[j + 1] - t_[j]) * i / k;
          ft_.push_back(t);
          fp_.push_back(point(t));
          ftan_.push_back(smooth_tangent(t, j));
        }
      }
    }
    ft_.push_back(t_.back());
    fp_.push_back(v_.back());
    ftan_.push_back(vt_.back());
    const std::size_t m = ft_.size();
    fn_.resize(m);
    fn_[0] = any_normal(ftan_[0]);
    for (std::size_t j = 0; j + 1 < m; ++j) {
      const Vec3 v1 = fp_[j + 1] - fp_[j];
      const double c1 = v1.squaredNorm();
      if (!(c1 > 0)) {  // coincident samples (a cusp): rotate the normal onto the new tangent
        Vec3 r = fn_[j] - fn_[j].dot(ftan_[j + 1]) * ftan_[j + 1];
        fn_[j + 1] = r.norm() > 1e-6 ? Vec3(r.normalized()) : any_normal(ftan_[j + 1]);
        continue;
      }
      const Vec3 rl = fn_[j] - (2 / c1) * v1.dot(fn_[j]) * v1;
      const Vec3 tl = ftan_[j] - (2 / c1) * v1.dot(ftan_[j]) * v1;
      const Vec3 v2 = ftan_[j + 1] - tl;
      const double c2 = v2.squaredNorm();
      Vec3 r = c2 > kReflectionEpsilon ? Vec3(rl - (2 / c2) * v2.dot(rl) * v2) : rl;
      // Re-orthonormalize against the tangent so rounding does not accumulate along long paths.
      r -= r.dot(ftan_[j + 1]) * ftan_[j + 1];
      fn_[j + 1] = r.norm() > 1e-6 ? Vec3(r.normalized()) : any_normal(ftan_[j + 1]);
    }
    fp_.clear();
    fp_.shrink_to_fit();
  }

  Curve3 curve_;
  bool polyline_ = false;
  double extent_ = 0, tol_ = 0, length_ = 0;
  std::vector<Vec3> v_;   // flattened vertices
  std::vector<double> t_; // their curve parameters
  std::vector<double> s_; // their normalized arc lengths
  std::vector<Vec3> pn_;  // polylines: the RMF normal of each piece
  std::vector<Vec3> vt_;  // smooth paths: unit tangents at the vertices
  std::vector<double> ft_;  // frame samples: curve parameters (the vertices' and more)
  std::vector<Vec3> fp_;    // frame samples: points (only while building)
  std::vector<Vec3> ftan_;  // frame samples: unit tangents
  std::vector<Vec3> fn_;    // frame samples: RMF normals
  std::vector<Block> blocks_;
  Aabb box_;
};

// ---------------------------------------------------------------------------------------------
// Interpolation weights along the path: d2(s) = sum_k w_k(s) D_k with D_k the distance of the
// sections at the k-th distinct s value.

struct Weights {
  int count = 0;
  std::array<int, 4> index{};
  std::array<double, 4> w{}, dw{};  // weight and its derivative d/ds
  void add(int i, double wi, double dwi) {
    for (int k = 0; k < count; ++k) {
      if (index[k] == i) {
        w[k] += wi;
        dw[k] += dwi;
        return;
      }
    }
    index[count] = i;
    w[count] = wi;
    dw[count] = dwi;
    ++count;
  }
};

class Interpolator {
 public:
  Interpolator(std::vector<double> s, SkinInterpolation kind) : s_(std::move(s)), kind_(kind) {
    const int m = static_cast<int>(s_.size());
    // Quadratic: per interval, the triple of neighbouring s values spanning less (so a close pair
    // of sections does not make the parabola swing).
    quad_first_.assign(std::max(m - 1, 0), 0);
    for (int k = 0; k + 1 < m && m >= 3; ++k) {
      const bool has_left = k >= 1, has_right = k + 2 <= m - 1;
      if (has_left && has_right) {
        quad_first_[k] = s_[k + 2] - s_[k] < s_[k + 1] - s_[k - 1] ? k : k - 1;
      } else {
        quad_first_[k] = has_left ? k - 1 : k;
      }
    }
    // Lebesgue-type constant: on every interval each weight is a polynomial of degree <= 3 in
    // u = (s - s_k) / h; its largest |value| is at most the largest |Bernstein coefficient|,
    // computed from its values at u = 0, 1/3, 2/3, 1.
    lebesgue_ = 1;
    for (int k = 0; k + 1 < m; ++k) {
      std::map<int, std::array<double, 4>> values;
      for (int i = 0; i < 4; ++i) {
        Weights w;
        interval_weights(k, s_[k] + (s_[k + 1] - s_[k]) * i / 3.0, w);
        for (int c = 0; c < w.count; ++c) {
          auto [it, fresh] = values.try_emplace(w.index[c], std::array<double, 4>{0, 0, 0, 0});
          it->second[i] = w.w[c];
        }
      }
      double sum = 0;
      for (const auto& [idx, f] : values) {
        const double b1 = (-5 * f[0] + 18 * f[1] - 9 * f[2] + 2 * f[3]) / 6;
        const double b2 = (2 * f[0] - 9 * f[1] + 18 * f[2] - 5 * f[3]) / 6;
        sum += std::max({std::abs(f[0]), std::abs(b1), std::abs(b2), std::abs(f[3])});
      }
      lebesgue_ = std::max(lebesgue_, sum);
    }
  }

  Weights at(double s) const {
    Weights out;
    const int m = static_cast<int>(s_.size());
    if (m == 1 || s <= s_.front()) {
      out.add(0, 1, 0);
      return out;
    }
    if (s >= s_.back()) {
      out.add(m - 1, 1, 0);
      return out;
    }
    const int k = static_cast<int>(std::upper_bound(s_.begin(), s_.end(), s) - s_.begin()) - 1;
    interval_weights(k, s, out);
    return out;
  }

  // An upper bound of sum_k |w_k(s)| over all s.
  double lebesgue() const { return lebesgue_; }

 private:
  void interval_weights(int k, double s, Weights& out) const {
    const int m = static_cast<int>(s_.size());
    const double a = s_[k], h = s_[k + 1] - a;
    const double u = (s - a) / h;
    if (kind_ == SkinInterpolation::kLinear || (kind_ == SkinInterpolation::kQuadratic && m < 3)) {
      out.add(k, 1 - u, -1 / h);
      out.add(k + 1, u, 1 / h);
      return;
    }
    if (kind_ == SkinInterpolation::kQuadratic) {
      const int f = quad_first_[k];
      const double x[3] = {s_[f], s_[f + 1], s_[f + 2]};
      for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3, l = (i + 2) % 3;
        const double den = (x[i] - x[j]) * (x[i] - x[l]);
        out.add(f + i, (s - x[j]) * (s - x[l]) / den, ((s - x[j]) + (s - x[l])) / den);
      }
      return;
    }
    // Cubic Hermite on [s_k, s_k+1] with the slopes of the parabola through each node and its
    // two neighbours (Bessel / Overhauser tangents; one-sided secants at the first and last).
    const double u2 = u * u, u3 = u2 * u;
    const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u;
    const double h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
    const double dh00 = 6 * u2 - 6 * u, dh10 = 3 * u2 - 4 * u + 1;
    const double dh01 = -6 * u2 + 6 * u, dh11 = 3 * u2 - 2 * u;
    out.add(k, h00, dh00 / h);
    out.add(k + 1, h01, dh01 / h);
    // Term h10 · h · m_k: weight h·h10·c, derivative d/ds = dh10 · c (the 1/h and h cancel).
    add_slope(k, h * h10, dh10, out);
    add_slope(k + 1, h * h11, dh11, out);
  }

  // Adds f · m_i (and df · m_i) where the slope m_i at node i is a combination of the D_k.
  void add_slope(int i, double f, double df, Weights& out) const {
    const int m = static_cast<int>(s_.size());
    if (i == 0 || i == m - 1) {
      const int a = i == 0 ? 0 : m - 2;
      const double h = s_[a + 1] - s_[a];
      out.add(a, -f / h, -df / h);
      out.add(a + 1, f / h, df / h);
      return;
    }
    const double h0 = s_[i] - s_[i - 1], h1 = s_[i + 1] - s_[i];
    const double cm = -h1 / (h0 * (h0 + h1));
    const double cp = h0 / (h1 * (h0 + h1));
    const double c0 = (h1 / h0 - h0 / h1) / (h0 + h1);
    out.add(i - 1, f * cm, df * cm);
    out.add(i, f * c0, df * c0);
    out.add(i + 1, f * cp, df * cp);
  }

  std::vector<double> s_;
  SkinInterpolation kind_;
  std::vector<int> quad_first_;
  double lebesgue_ = 1;
};

// Evaluates `eval(p, grad)` over a batch, in parallel chunks for large batches.
template <class Eval>
void evaluate_batch(std::span<const Vec3> points, std::span<double> values, std::span<Vec3> gradients,
                    const Eval& eval) {
  const bool with_gradient = !gradients.empty();
  auto body = [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) values[i] = eval(points[i], with_gradient ? &gradients[i] : nullptr);
  };
  if (points.size() >= 4 * kGrain) {
    parallel::for_chunks(points.size(), kGrain, body);
  } else {
    body(0, points.size());
  }
}

// ---------------------------------------------------------------------------------------------

class RevolutionField final : public Field {
 public:
  RevolutionField(Region2 profile, const Falloff& falloff)
      : Field(falloff.iso), profile_(std::move(profile)), falloff_(falloff) {}

  Interval bound(const Aabb& box) const override {
    const Vec3 c = box.center();
    const double rho = 0.5 * box.diagonal().norm();
    const double dc = profile_.distance(to_rz(c), nullptr);
    // The (r, z) image of the box lies in [rlo, rhi] x [zlo, zhi]; and d is 1-Lipschitz in p.
    const double dx = std::max({0.0, box.min().x(), -box.max().x()});
    const double dy = std::max({0.0, box.min().y(), -box.max().y()});
    const double rlo = std::hypot(dx, dy);
    const double rhi = std::hypot(std::max(std::abs(box.min().x()), std::abs(box.max().x())),
                                  std::max(std::abs(box.min().y()), std::abs(box.max().y())));
    const Box2 rect(Vec2(rlo, box.min().z()), Vec2(rhi, box.max().z()));
    const double dmin = std::max({0.0, dc - rho, std::sqrt(rect.squaredExteriorDistance(profile_.box()))});
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

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients) const override {
    evaluate_batch(points, values, gradients, [this](const Vec3& p, Vec3* grad) { return at(p, grad); });
  }

 private:
  static Vec2 to_rz(const Vec3& p) { return {std::hypot(p.x(), p.y()), p.z()}; }

  double at(const Vec3& p, Vec3* grad) const {
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

class SkinField final : public Field {
 public:
  SkinField(Path path, std::vector<double> group_s, std::vector<std::vector<Region2>> groups,
            SkinInterpolation interpolation, const Falloff& falloff, std::string label)
      : Field(falloff.iso),
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
    const double near = std::max({0.0, std::sqrt(squared_distance(box, path_.box())), dpoly - rho - slack});
    const double far = dpoly + rho + slack;
    return falloff_.range(near - spread_, far + spread_);
  }

  Aabb bounds() const override {
    if (falloff_.d_inside < 0) return Aabb();
    const double pad = std::hypot(falloff_.d_inside + spread_, falloff_.d_inside) * (1 + kReachMargin);
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

 protected:
  void do_evaluate(std::span<const Vec3> points, std::span<double> values,
                   std::span<Vec3> gradients) const override {
    evaluate_batch(points, values, gradients, [this](const Vec3& p, Vec3* grad) { return at(p, grad); });
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

  double at(const Vec3& p, Vec3* grad) const {
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
    const double d = std::hypot(dplane, a);
    double dfdd = 0;
    const double f = falloff_.value(d, grad != nullptr ? &dfdd : nullptr);
    if (grad != nullptr) {
      Vec3 gd = Vec3::Zero();
      if (d > 0) {
        // The frame is treated as constant: for a rotation-minimizing frame dN/dt and dB/dt are
        // parallel to T, and p - O is orthogonal to T wherever the projection is interior.
        const Vec3 gplane = dint > 0 ? Vec3(g2.x() * pr.normal + g2.y() * pr.binormal +
                                            dds * pr.dsdt * pr.dtdp)
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

FieldPtr build_skin(const Curve3& path, std::vector<SkinSection> sections, const SkinOptions& options,
                    const std::string& what, const std::string& label) {
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
      throw InvalidArgument(what + ": profile point " + std::to_string(i) + " has x = " +
                            std::to_string(profile.points[i].x()) +
                            " < 0 (x is the distance from the z axis)");
    }
  }
  return std::make_shared<RevolutionField>(make_region(profile, options.tolerance), falloff);
}

FieldPtr make_skin_field(const Curve3& path, std::vector<SkinSection> sections, const SkinOptions& options) {
  return build_skin(path, std::move(sections), options, "make_skin_field", "skinned surface");
}

FieldPtr make_sweep_field(const Curve3& path, const Curve2& section, const CurveSurfaceOptions& options) {
  SkinOptions o;
  o.surface = options;
  o.interpolation = SkinInterpolation::kLinear;
  return build_skin(path, {SkinSection{section, 0.0}, SkinSection{section, 1.0}}, o, "make_sweep_field",
                    "sweep surface");
}

PathFrame path_frame(const Curve3& path, double s) { return path_frame(path, s, 0.0); }

PathFrame path_frame(const Curve3& path, double s, double tolerance) {
  if (!(s >= 0 && s <= 1)) throw InvalidArgument("path_frame: s = " + std::to_string(s) + " is outside [0, 1]");
  if (!std::isfinite(tolerance) || tolerance < 0) {
    throw InvalidArgument("path_frame: tolerance must be finite and >= 0, got " + std::to_string(tolerance));
  }
  return Path(path, tolerance, "path_frame").frame_at_s(s);
}

PathProjection project_on_path(const Curve3& path, const Vec3& p, double tolerance) {
  if (!is_finite(p)) throw InvalidArgument("project_on_path: the point is not finite");
  if (!std::isfinite(tolerance) || tolerance < 0) {
    throw InvalidArgument("project_on_path: tolerance must be finite and >= 0, got " + std::to_string(tolerance));
  }
  const Path::Projection pr = Path(path, tolerance, "project_on_path").project(p);
  return {pr.t, pr.s, pr.origin, pr.newton};
}

}  // namespace ramiform
