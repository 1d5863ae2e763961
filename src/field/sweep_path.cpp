// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "field/sweep_path.h"

#include <algorithm>
#include <cmath>

#include "field/sweep_common.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"

namespace ramiform::detail::sweep {
namespace {

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
// Pieces per pruning block of the coarse projection.
constexpr std::size_t kBlock = 8;

Vec3 any_normal(const Vec3& T) {
  const Vec3 e = std::abs(T.x()) > 0.9 ? Vec3::UnitY() : Vec3::UnitX();
  return (e - e.dot(T) * T).normalized();
}

}  // namespace

Vec3 rotate_between(const Vec3& a, const Vec3& b, const Vec3& x) {
  const Vec3 h = a + b;
  const double h2 = h.squaredNorm();
  if (h2 < 1e-12) return x - x.dot(b) * b;
  const Vec3 x1 = x - (2 * x.dot(h) / h2) * h;
  return x1 - 2 * x1.dot(b) * b;
}

Path::Path(const Curve3& curve, double tolerance_option, const std::string& what) : curve_(curve) {
  try {
    validate(curve);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(what + ": path: " + e.what());
  }
  extent_ = extent_of(curve.points);
  if (!(extent_ > 0))
    throw InvalidArgument(what + ": the path has zero length (all its points coincide)");
  tol_ = tolerance_for(tolerance_option, extent_);
  polyline_ = curve.kind == CurveKind::kPolyline;
  flatten_path(curve, what);
  for (const auto& p : curve.points) box_.extend(p);
  for (const auto& p : v_) box_.extend(p);
  build_frames();
  for (std::size_t b = 0; b + 1 < v_.size(); b += kBlock) {
    Block block{Aabb(), b, std::min(v_.size() - 1, b + kBlock)};
    for (std::size_t i = block.begin; i <= block.end; ++i) block.box.extend(v_[i]);
    blocks_.push_back(block);
  }
}

// The flattened vertices without coincident neighbours (the last point replaces the one it
// coincides with, so the path still ends at t = 1), with their parameters and arc lengths.
void Path::flatten_path(const Curve3& curve, const std::string& what) {
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
}

Path::Coarse Path::coarse(const Vec3& p) const {
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

// Newton–Raphson on g(t) = (C(t) - p)·C'(t) from t, clamped to [0, 1]; true when it converged
// (including at an end of the path where the minimum lies beyond it).
bool Path::newton(const Vec3& p, double& t) const {
  for (int it = 0; it < kNewtonIterations; ++it) {
    const Vec3 x = point(t);
    const Vec3 d1 = derivative(t);
    const Vec3 d2 = second_derivative(t);
    const double g = (x - p).dot(d1);
    const double gp = d1.squaredNorm() + (x - p).dot(d2);
    if ((t <= 0 && g >= 0) || (t >= 1 && g <= 0)) return true;
    if (std::abs(g) <= kNewtonResidual * extent_ * d1.norm()) return true;
    if (!(gp > 0)) return false;
    const double tn = std::clamp(t - g / gp, 0.0, 1.0);
    const double step = std::abs(tn - t);
    t = tn;
    if (step <= kNewtonStep) return true;
  }
  return false;
}

Path::Projection Path::project(const Vec3& p) const {
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
  const bool converged = newton(p, t);
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

PathFrame Path::frame_at_s(double s) const {
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

std::size_t Path::piece_of_t(double t) const {
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  const std::size_t j = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - t_.begin() - 1, 0));
  return std::min(j, pieces() - 1);
}

// Polyline frame at position u of piece j. Along a piece the frame is constant (the piece's
// direction and RMF normal). At an interior vertex the tangent turns in the bend plane from
// the incoming to the outgoing direction, and points in the wedge beyond both pieces take the
// tangent orthogonal to p - V (the section revolves about the bend axis: a rounded joint, no
// notch); without a point (path_frame), the bisector.
void Path::polyline_frame(Projection& pr, std::size_t j, double u, const Vec3* p) const {
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
      const double theta = pm::atan2(en, b.dot(a));
      double phi = 0.5 * theta;
      if (p != nullptr) {
        const Vec3 r = *p - v_[v];
        phi = std::clamp(pm::atan2(r.dot(a), -r.dot(e)), 0.0, theta);
      }
      pr.tangent = pm::cos(phi) * a + pm::sin(phi) * e;
      pr.normal = rotate_between(a, pr.tangent, pn_[v - 1]);
      pr.normal = (pr.normal - pr.normal.dot(pr.tangent) * pr.tangent).normalized();
    }
  }
  pr.binormal = pr.tangent.cross(pr.normal);
}

// Exact unit tangent C'/|C'|, or the piece's direction where C' vanishes (cusps).
Vec3 Path::smooth_tangent(double t, std::size_t j) const {
  const Vec3 d = derivative(t);
  const double n = d.norm();
  return n > tol::kCoincident * extent_ ? Vec3(d / n) : piece_direction(j);
}

// Fills s and ds/dt from position w of piece j.
void Path::set_s(Projection& pr, std::size_t j, double w) const {
  w = std::clamp(w, 0.0, 1.0);
  pr.s = s_[j] + w * (s_[j + 1] - s_[j]);
  pr.dsdt = (s_[j + 1] - s_[j]) / (t_[j + 1] - t_[j]);
}

// Smooth paths: the normal and binormal at pr.t, from the RMF normals of the two neighbouring
// frame samples blended linearly, made orthogonal to pr.tangent and normalized.
void Path::smooth_frame(Projection& pr) const {
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

void Path::build_frames() {
  if (polyline_) {
    build_polyline_frames();
    return;
  }
  sample_smooth_frames();
  build_smooth_frames();
}

void Path::build_polyline_frames() {
  pn_.resize(pieces());
  pn_[0] = any_normal(piece_direction(0));
  for (std::size_t j = 0; j + 1 < pieces(); ++j) {
    const Vec3 b = piece_direction(j + 1);
    Vec3 r = rotate_between(piece_direction(j), b, pn_[j]);
    r -= r.dot(b) * b;
    pn_[j + 1] = r.norm() > 1e-6 ? Vec3(r.normalized()) : any_normal(b);
  }
}

// Frame samples: the vertices, and on smooth curves more points inside each piece so that
// consecutive tangents turn by at most kFrameAngle (double reflection is fourth-order accurate
// in the step, and the blend between samples second-order).
void Path::sample_smooth_frames() {
  const std::size_t n = v_.size();
  vt_.resize(n);
  for (std::size_t j = 0; j < n; ++j) vt_[j] = smooth_tangent(t_[j], std::min(j, pieces() - 1));
  ft_.clear();
  fp_.clear();
  ftan_.clear();
  for (std::size_t j = 0; j + 1 < n; ++j) {
    const double angle = pm::acos(std::clamp(vt_[j].dot(vt_[j + 1]), -1.0, 1.0));
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
}

// Double reflection from sample to sample (Wang, Jüttler, Zheng & Liu 2008): reflect the
// normal and tangent across the plane bisecting the two sample points, then across the one
// that takes the reflected tangent onto the next tangent.
void Path::build_smooth_frames() {
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

}  // namespace ramiform::detail::sweep
