// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/field/surface_skeleton.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

#include "field/bvh.h"
#include "ramiform/core/errors.h"
#include "ramiform/core/portable_math.h"
#include "ramiform/core/tolerances.h"

namespace ramiform {

struct SurfaceSkeleton::Bvh {
  detail::BoxBvh tree;
};

namespace {

constexpr double kPi = std::numbers::pi;
// Where |c|^(e - 1) is unbounded (e < 1, c = 0), |c| is raised to this: cos(pi / 2) rounds to
// 6e-17, so the derivative is as large as the rounding of an exact evaluation would make it.
constexpr double kPowerFloor = 1e-16;
// Grid (per side) on which the error of a non-polynomial leaf is sampled.
constexpr int kErrorSamples = 8;
constexpr double kMaxExponent = 10;
// Fraction of a side by which a vanishing corner derivative is looked for inside the side.
constexpr double kNudge = 1.0 / 64;
constexpr int kMaxDepthLimit = 10;

// cos(pi t) and sin(pi t), exactly 0 and +-1 at multiples of 1/2 (poles and seam must close up
// exactly). t - 2 round(t / 2) is exact for the |t| <= 1 used here (std::remainder is, too, but
// is slow in glibc).
double reduce_two(double t) { return t - 2 * std::round(0.5 * t); }

double cos_pi(double t) {
  const double r = reduce_two(t);
  const double a = std::abs(r);
  if (a == 0.5) return 0.0;
  if (a == 0.0) return 1.0;
  if (a == 1.0) return -1.0;
  return pm::cos(kPi * r);
}

double sin_pi(double t) {
  const double r = reduce_two(t);
  const double a = std::abs(r);
  if (a == 0.0 || a == 1.0) return 0.0;
  if (a == 0.5) return r > 0 ? 1.0 : -1.0;
  return pm::sin(kPi * r);
}

// Signed power sign(x) |x|^e.
double signed_pow(double x, double e) {
  if (e == 1.0 || x == 0.0) return x;
  const double m = pm::pow(std::abs(x), e);
  return x < 0 ? -m : m;
}

// d/dx signed_pow(x, e) = e |x|^(e - 1), kept finite at x = 0 for e < 1.
double signed_pow_derivative(double x, double e) {
  if (e == 1.0) return 1.0;
  double a = std::abs(x);
  if (e < 1.0) a = std::max(a, kPowerFloor);
  return e * pm::pow(a, e - 1.0);
}

std::string vec_text(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

class PatchSurface final : public ParametricSurface {
 public:
  explicit PatchSurface(const BicubicPatch& p) : patch_(p) {}

  Vec3 point(double u, double v) const override {
    const auto bu = basis(u);
    const auto bv = basis(v);
    Vec3 s = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      Vec3 row = Vec3::Zero();
      for (int j = 0; j < 4; ++j) row += bv[j] * b(i, j);
      s += bu[i] * row;
    }
    return s;
  }

  void derivatives(double u, double v, Vec3& su, Vec3& sv) const override {
    const auto bu = basis(u);
    const auto bv = basis(v);
    const auto du = basis_derivative(u);
    const auto dv = basis_derivative(v);
    su.setZero();
    sv.setZero();
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) {
        su += du[i] * bv[j] * b(i, j);
        sv += bu[i] * dv[j] * b(i, j);
      }
    }
  }

  std::string describe() const override {
    return "bicubic Bezier patch from " + vec_text(b(0, 0)) + " to " + vec_text(b(3, 3));
  }

  // Guaranteed bound on |S - T| over [u0,u1]x[v0,v1] (see the header): the sub-patch's control
  // points against the bilinear interpolant of its corners, plus the twist term.
  double leaf_error(double u0, double u1, double v0, double v1) const {
    std::array<std::array<Vec3, 4>, 4> c;
    for (int j = 0; j < 4; ++j) {
      const auto col = restrict({b(0, j), b(1, j), b(2, j), b(3, j)}, u0, u1);
      for (int i = 0; i < 4; ++i) c[i][j] = col[i];
    }
    for (int i = 0; i < 4; ++i) c[i] = restrict(c[i], v0, v1);
    double worst = 0;
    for (int i = 0; i < 4; ++i) {
      const double s = i / 3.0;
      for (int j = 0; j < 4; ++j) {
        const double t = j / 3.0;
        const Vec3 bilinear = (1 - s) * (1 - t) * c[0][0] + s * (1 - t) * c[3][0] +
                              (1 - s) * t * c[0][3] + s * t * c[3][3];
        worst = std::max(worst, (c[i][j] - bilinear).norm());
      }
    }
    return worst + 0.25 * (c[0][0] - c[3][0] - c[0][3] + c[3][3]).norm();
  }

 private:
  const Vec3& b(int i, int j) const { return patch_.controls[4 * i + j]; }

  static std::array<double, 4> basis(double t) {
    const double s = 1 - t;
    return {s * s * s, 3 * t * s * s, 3 * t * t * s, t * t * t};
  }
  static std::array<double, 4> basis_derivative(double t) {
    const double s = 1 - t;
    return {-3 * s * s, 3 * s * s - 6 * t * s, 6 * t * s - 3 * t * t, 3 * t * t};
  }
  // Control points of the cubic restricted to [a, b]: its blossom at (a,a,a), (a,a,b), (a,b,b),
  // (b,b,b).
  static std::array<Vec3, 4> restrict(const std::array<Vec3, 4>& p, double a, double b) {
    const auto blossom = [&p](double t1, double t2, double t3) {
      const Vec3 q0 = (1 - t1) * p[0] + t1 * p[1];
      const Vec3 q1 = (1 - t1) * p[1] + t1 * p[2];
      const Vec3 q2 = (1 - t1) * p[2] + t1 * p[3];
      const Vec3 r0 = (1 - t2) * q0 + t2 * q1;
      const Vec3 r1 = (1 - t2) * q1 + t2 * q2;
      return Vec3((1 - t3) * r0 + t3 * r1);
    };
    return {blossom(a, a, a), blossom(a, a, b), blossom(a, b, b), blossom(b, b, b)};
  }

  BicubicPatch patch_;
};

class SuperquadricSurface final : public ParametricSurface {
 public:
  explicit SuperquadricSurface(const Superquadric& q) : q_(q) {}

  Vec3 point(double u, double v) const override {
    const Angles a = angles(u, v);
    const double c1 = signed_pow(a.ce, q_.e1);
    const Vec3 local(q_.radii.x() * c1 * signed_pow(a.cw, q_.e2),
                     q_.radii.y() * c1 * signed_pow(a.sw, q_.e2),
                     q_.radii.z() * signed_pow(a.se, q_.e1));
    return q_.rotation * local + q_.center;
  }

  void derivatives(double u, double v, Vec3& su, Vec3& sv) const override {
    const Angles a = angles(u, v);
    const double c1 = signed_pow(a.ce, q_.e1);
    const double c2 = signed_pow(a.cw, q_.e2);
    const double s2 = signed_pow(a.sw, q_.e2);
    // d/d(eta) and d/d(omega) of the signed powers; eta' = pi, omega' = 2 pi.
    const double dc1 = -signed_pow_derivative(a.ce, q_.e1) * a.se;
    const double ds1 = signed_pow_derivative(a.se, q_.e1) * a.ce;
    const double dc2 = -signed_pow_derivative(a.cw, q_.e2) * a.sw;
    const double ds2 = signed_pow_derivative(a.sw, q_.e2) * a.cw;
    const Vec3 du(q_.radii.x() * c1 * dc2, q_.radii.y() * c1 * ds2, 0.0);
    const Vec3 dv(q_.radii.x() * dc1 * c2, q_.radii.y() * dc1 * s2, q_.radii.z() * ds1);
    su = q_.rotation * (2 * kPi * du);
    sv = q_.rotation * (kPi * dv);
  }

  std::string describe() const override {
    std::ostringstream s;
    s << "superquadric at " << vec_text(q_.center) << " radii " << vec_text(q_.radii) << " e1 "
      << q_.e1 << " e2 " << q_.e2;
    return s.str();
  }

  int minimum_depth() const override { return 2; }

 private:
  struct Angles {
    double ce, se, cw, sw;
  };
  static Angles angles(double u, double v) {
    return {cos_pi(v - 0.5), sin_pi(v - 0.5), cos_pi(2 * u - 1), sin_pi(2 * u - 1)};
  }

  Superquadric q_;
};

// The two triangles of a leaf, split along (u0,v0)-(u1,v1), as a linear map of the leaf's local
// coordinates (s, t) in [0,1]^2.
Vec3 leaf_triangles_at(const Vec3& p00, const Vec3& p10, const Vec3& p11, const Vec3& p01, double s,
                       double t) {
  if (s >= t) return p00 + s * (p10 - p00) + t * (p11 - p10);
  return p00 + t * (p01 - p00) + s * (p11 - p01);
}

// True when the angle between derivatives a and b is <= epsilon (cos_eps its cosine), or one
// of them is (numerically) zero.
bool side_is_flat(const Vec3& a, const Vec3& b, double zero, double cos_eps) {
  const double na = a.norm();
  const double nb = b.norm();
  if (!(na > zero) || !(nb > zero)) return true;
  return (a / na).dot(b / nb) >= cos_eps;
}

// Nearest-feature classification of a point against a triangle (or segment).
enum class Feature { kFace, kEdge, kVertex };

struct Foot {
  Vec3 q;       // nearest point
  double w[3];  // barycentric weights of a, b, c
  Feature feature;
  int i, j;  // kEdge: the edge's vertex indices; kVertex: i
};

// Ericson, "Real-Time Collision Detection" §5.1.5, with the Voronoi region reported.
template <class TriT>
Foot closest_on(const TriT& tri, const Vec3& p) {
  Foot f{};
  const Vec3& a = tri.a;
  const Vec3& b = tri.b;
  const Vec3& c = tri.c;
  const auto vertex = [&f](const Vec3& v, int i) {
    f.q = v;
    f.w[0] = f.w[1] = f.w[2] = 0;
    f.w[i] = 1;
    f.feature = Feature::kVertex;
    f.i = i;
    return f;
  };
  const auto edge = [&f](const Vec3& x, const Vec3& y, int i, int j, double t) {
    f.q = x + t * (y - x);
    f.w[0] = f.w[1] = f.w[2] = 0;
    f.w[i] = 1 - t;
    f.w[j] = t;
    f.feature = Feature::kEdge;
    f.i = i;
    f.j = j;
    return f;
  };
  const Vec3 ab = b - a;
  if (tri.is_segment) {
    const double l2 = ab.squaredNorm();
    const double t = l2 > 0 ? (p - a).dot(ab) / l2 : 0.0;
    if (t <= 0) return vertex(a, 0);
    if (t >= 1) return vertex(b, 1);
    return edge(a, b, 0, 1, t);
  }
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return vertex(a, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return vertex(b, 1);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return edge(a, b, 0, 1, d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return vertex(c, 2);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return edge(a, c, 0, 2, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return edge(b, c, 1, 2, (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double denom = 1 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  f.q = a + v * ab + w * ac;
  f.w[0] = 1 - v - w;
  f.w[1] = v;
  f.w[2] = w;
  f.feature = Feature::kFace;
  return f;
}

// A triangle for the error estimate; a zero-area one acts as its longest edge a-b.
struct PlainTri {
  Vec3 a, b, c;
  bool is_segment = false;
};

PlainTri plain_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = (b - a).squaredNorm();
  const double bc = (c - b).squaredNorm();
  const double ca = (a - c).squaredNorm();
  const double longest = std::max({ab, bc, ca});
  const double area2 = (b - a).cross(c - a).squaredNorm();
  if (area2 > (tol::kCoincident * longest) * (tol::kCoincident * longest)) return {a, b, c, false};
  if (bc == longest) return {b, c, a, true};
  if (ca == longest) return {c, a, b, true};
  return {a, b, c, true};
}

// Estimate of the Hausdorff distance between the true piece S([u0,u1]x[v0,v1]) and the leaf's
// two triangles, for surfaces without a guaranteed bound: true -> triangles from a 9 x 9 grid of
// surface points; triangles -> true from a 5 x 5 grid of triangle points against the 4 x 4-cell
// mesh of surface points (an approximation 16x finer than the leaf). The parametric gap
// |S(u, v) - T(u, v)| would be a bound, but a useless one where the parametrization is strongly
// non-uniform on flat parts (the faces of a boxy superquadric).
double sampled_hausdorff(const ParametricSurface& s, double u0, double u1, double v0, double v1,
                         const Vec3& p00, const Vec3& p10, const Vec3& p11, const Vec3& p01) {
  constexpr int n = kErrorSamples;
  std::array<Vec3, (n + 1) * (n + 1)> grid;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      grid[i * (n + 1) + j] = s.point(u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n);
    }
  }
  const PlainTri leaf[2] = {plain_triangle(p00, p10, p11), plain_triangle(p00, p11, p01)};
  double worst = 0;
  for (const Vec3& q : grid) {
    const double d = std::min((closest_on(leaf[0], q).q - q).squaredNorm(),
                              (closest_on(leaf[1], q).q - q).squaredNorm());
    worst = std::max(worst, d);
  }
  constexpr int m = n / 2;  // cells of the fine mesh per side
  std::array<PlainTri, 2 * m * m> fine;
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) {
      const auto at = [&grid](int a, int b) -> const Vec3& {
        return grid[2 * a * (n + 1) + 2 * b];
      };
      fine[2 * (i * m + j)] = plain_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      fine[2 * (i * m + j) + 1] = plain_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  }
  for (int i = 0; i <= m; ++i) {
    for (int j = 0; j <= m; ++j) {
      const Vec3 x = leaf_triangles_at(p00, p10, p11, p01, static_cast<double>(i) / m,
                                       static_cast<double>(j) / m);
      double best = std::numeric_limits<double>::infinity();
      for (const PlainTri& t : fine) best = std::min(best, (closest_on(t, x).q - x).squaredNorm());
      worst = std::max(worst, best);
    }
  }
  return std::sqrt(worst);
}

}  // namespace

std::shared_ptr<const ParametricSurface> make_patch_surface(const BicubicPatch& p) {
  for (int k = 0; k < 16; ++k) {
    if (!p.controls[k].allFinite()) {
      throw InvalidArgument("bicubic patch: control point " + std::to_string(k) + " (b_" +
                            std::to_string(k / 4) + std::to_string(k % 4) + ") is not finite");
    }
  }
  return std::make_shared<PatchSurface>(p);
}

std::shared_ptr<const ParametricSurface> make_superquadric_surface(const Superquadric& q) {
  if (!q.center.allFinite()) {
    throw InvalidArgument("superquadric: center " + vec_text(q.center) + " is not finite");
  }
  if (!q.radii.allFinite() || !(q.radii.minCoeff() > 0)) {
    throw InvalidArgument("superquadric: radii must be finite and > 0, got " + vec_text(q.radii));
  }
  const auto check_exponent = [](double e, const char* name) {
    if (!(e > 0 && e <= kMaxExponent)) {
      throw InvalidArgument(std::string("superquadric: ") + name + " must be in (0, 10], got " +
                            std::to_string(e));
    }
  };
  check_exponent(q.e1, "e1");
  check_exponent(q.e2, "e2");
  if (!q.rotation.allFinite() ||
      !((q.rotation.transpose() * q.rotation - Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-9)) {
    throw InvalidArgument("superquadric: rotation is not orthonormal");
  }
  return std::make_shared<SuperquadricSurface>(q);
}

SurfaceSkeleton::SurfaceSkeleton(std::shared_ptr<const ParametricSurface> surface,
                                 const SubdivisionOptions& options)
    : surface_(std::move(surface)) {
  if (surface_ == nullptr) throw InvalidArgument("surface skeleton: the surface is null");
  if (!(std::isfinite(options.max_error) && options.max_error >= 0)) {
    throw InvalidArgument("surface skeleton: max_error must be finite and >= 0, got " +
                          std::to_string(options.max_error));
  }
  if (!(options.epsilon_degrees > 0 && options.epsilon_degrees <= 90)) {
    throw InvalidArgument("surface skeleton: epsilon_degrees must be in (0, 90], got " +
                          std::to_string(options.epsilon_degrees));
  }
  if (options.max_depth < 0 || options.max_depth > kMaxDepthLimit) {
    throw InvalidArgument("surface skeleton: max_depth must be in 0..10, got " +
                          std::to_string(options.max_depth));
  }
  const ParametricSurface& s = *surface_;
  const int min_depth = std::clamp(s.minimum_depth(), 0, kMaxDepthLimit);
  const int max_depth = std::max(options.max_depth, min_depth);
  const double cos_eps = pm::cos(options.epsilon_degrees * kPi / 180);
  const auto* patch = dynamic_cast<const PatchSurface*>(&s);
  error_is_estimate_ = patch == nullptr;

  // The surface's size sets the threshold below which a derivative counts as zero.
  Aabb sampled;
  for (int i = 0; i <= kErrorSamples; ++i) {
    for (int j = 0; j <= kErrorSamples; ++j) {
      sampled.extend(
          s.point(static_cast<double>(i) / kErrorSamples, static_cast<double>(j) / kErrorSamples));
    }
  }
  if (!sampled.min().allFinite() || !sampled.max().allFinite()) {
    throw InvalidArgument("surface skeleton: " + s.describe() + " is not finite");
  }
  // The rule of the point and skeleton readers: distances on it must not overflow.
  if (!std::isfinite(sampled.diagonal().norm())) {
    throw InvalidArgument("surface skeleton: " + s.describe() +
                          " spans more than double precision can hold (from " +
                          format_number(sampled.min().minCoeff()) + " to " +
                          format_number(sampled.max().maxCoeff()) + ")");
  }
  const double zero = tol::kCoincident * std::max(sampled.diagonal().norm(), 1e-300);

  const auto add_triangle = [this](const Vec3& a, const Vec3& b, const Vec3& c, const Vec2& uva,
                                   const Vec2& uvb, const Vec2& uvc) {
    Tri t{a, b, c, uva, uvb, uvc, false};
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if ((b - a).cross(c - a).squaredNorm() <=
        (tol::kCoincident * longest) * (tol::kCoincident * longest)) {
      // Zero area: keep the longest edge as a-b (a segment; c lies on it).
      t.is_segment = true;
      if ((c - b).squaredNorm() == longest) {
        t = Tri{b, c, a, uvb, uvc, uva, true};
      } else if ((a - c).squaredNorm() == longest) {
        t = Tri{c, a, b, uvc, uva, uvb, true};
      }
    }
    triangles_.push_back(t);
  };

  const auto subdivide = [&](const auto& self, double u0, double u1, double v0, double v1,
                             int depth) -> void {
    const Vec3 p00 = s.point(u0, v0);
    const Vec3 p10 = s.point(u1, v0);
    const Vec3 p11 = s.point(u1, v1);
    const Vec3 p01 = s.point(u0, v1);
    const auto split_in_four = [&] {
      const double um = 0.5 * (u0 + u1);
      const double vm = 0.5 * (v0 + v1);
      self(self, u0, um, v0, vm, depth + 1);
      self(self, um, u1, v0, vm, depth + 1);
      self(self, u0, um, vm, v1, depth + 1);
      self(self, um, u1, vm, v1, depth + 1);
    };
    bool split = depth < min_depth;
    if (!split && depth < max_depth) {
      // S_u (axis 0) or S_v (axis 1) at (u, v); where it vanishes at a corner only (the seam
      // of a pinched superquadric), its limit direction from inside the side, taken a step of
      // kNudge of the side towards the other end. Zero along the whole side (a pole) stays zero.
      const auto side_derivative = [&](double u, double v, int axis, double toward) {
        Vec3 d[2];
        s.derivatives(u, v, d[0], d[1]);
        if (d[axis].norm() > zero) return d[axis];
        double& moved = axis == 0 ? u : v;
        moved += kNudge * (toward - moved);
        s.derivatives(u, v, d[0], d[1]);
        return d[axis];
      };
      split = !(side_is_flat(side_derivative(u0, v0, 0, u1), side_derivative(u1, v0, 0, u0), zero,
                             cos_eps) &&
                side_is_flat(side_derivative(u0, v1, 0, u1), side_derivative(u1, v1, 0, u0), zero,
                             cos_eps) &&
                side_is_flat(side_derivative(u0, v0, 1, v1), side_derivative(u0, v1, 1, v0), zero,
                             cos_eps) &&
                side_is_flat(side_derivative(u1, v0, 1, v1), side_derivative(u1, v1, 1, v0), zero,
                             cos_eps));
    }
    if (split) {
      split_in_four();
      return;
    }
    if (!(p00.allFinite() && p10.allFinite() && p11.allFinite() && p01.allFinite())) {
      throw InvalidArgument("surface skeleton: " + s.describe() + " is not finite at (u, v) = (" +
                            std::to_string(u0) + ", " + std::to_string(v0) + ")");
    }
    double error = 0;
    if (patch != nullptr) {
      error = patch->leaf_error(u0, u1, v0, v1);
    } else {
      error = sampled_hausdorff(s, u0, u1, v0, v1, p00, p10, p11, p01);
    }
    if (options.max_error > 0 && error > options.max_error && depth < max_depth) {
      // Flat by the paper's test, but a bulge inside keeps it too far from its triangles.
      split_in_four();
      return;
    }
    ++patch_count_;
    depth_reached_ = std::max(depth_reached_, depth);
    add_triangle(p00, p10, p11, Vec2(u0, v0), Vec2(u1, v0), Vec2(u1, v1));
    add_triangle(p00, p11, p01, Vec2(u0, v0), Vec2(u1, v1), Vec2(u0, v1));
    error_bound_ = std::max(error_bound_, error);
  };
  subdivide(subdivide, 0.0, 1.0, 0.0, 1.0, 0);

  std::vector<Aabb> boxes;
  boxes.reserve(triangles_.size());
  for (const Tri& t : triangles_) {
    Aabb b(t.a);
    b.extend(t.b);
    b.extend(t.c);
    boxes.push_back(b);
    box_.extend(b);
  }
  auto bvh = std::make_shared<Bvh>();
  bvh->tree = detail::BoxBvh(std::move(boxes));
  bvh_ = std::move(bvh);
}

SurfaceProjection SurfaceSkeleton::project(const Vec3& p) const {
  const std::uint32_t id = bvh_->tree.nearest(
      p, [&](std::uint32_t k) { return (closest_on(triangles_[k], p).q - p).squaredNorm(); });
  if (id >= triangles_.size()) {
    // Every distance overflowed (NaN): the point is too far for double precision.
    throw InvalidArgument("surface skeleton: no distance from " + vec_text(p) + " to " +
                          surface_->describe() + " fits a double");
  }
  const Tri& t = triangles_[id];
  const Foot f = closest_on(t, p);
  const Vec2* uv[3] = {&t.uva, &t.uvb, &t.uvc};
  SurfaceProjection out;
  out.triangle = id;
  out.point = f.q;
  const Vec3 d = p - f.q;
  out.distance = d.norm();
  if (out.distance > 0) out.gradient = d / out.distance;
  const Vec2 uvq = f.w[0] * t.uva + f.w[1] * t.uvb + f.w[2] * t.uvc;
  out.u = uvq.x();
  out.v = uvq.y();
  if (f.feature == Feature::kFace) {
    // The in-plane g with g.ab = du_b, g.ac = du_c: g = alpha ab + beta ac (Gram system).
    const Vec3 ab = t.b - t.a;
    const Vec3 ac = t.c - t.a;
    const double g11 = ab.dot(ab);
    const double g12 = ab.dot(ac);
    const double g22 = ac.dot(ac);
    const double det = g11 * g22 - g12 * g12;
    const Vec2 db = t.uvb - t.uva;
    const Vec2 dc = t.uvc - t.uva;
    if (det > 0) {
      for (int k = 0; k < 2; ++k) {
        const double alpha = (g22 * db[k] - g12 * dc[k]) / det;
        const double beta = (g11 * dc[k] - g12 * db[k]) / det;
        (k == 0 ? out.grad_u : out.grad_v) = alpha * ab + beta * ac;
      }
    }
  } else if (f.feature == Feature::kEdge) {
    const Vec3* v[3] = {&t.a, &t.b, &t.c};
    const Vec3 e = *v[f.j] - *v[f.i];
    const double l2 = e.squaredNorm();
    if (l2 > 0) {
      const Vec2 duv = *uv[f.j] - *uv[f.i];
      out.grad_u = (duv.x() / l2) * e;
      out.grad_v = (duv.y() / l2) * e;
    }
  }
  return out;
}

std::pair<double, double> SurfaceSkeleton::distance_range(const Aabb& box) const {
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite()) {
    throw InvalidArgument("surface skeleton: distance_range needs a non-empty finite box");
  }
  const double r = 0.5 * box.diagonal().norm();
  const double d = project(box.center()).distance;
  const double lo = std::max({0.0, d - r, std::sqrt(squared_distance(box, box_))});
  return {lo, d + r};
}

SkeletonTriangle SurfaceSkeleton::triangle(std::size_t i) const {
  if (i >= triangles_.size()) {
    throw InvalidArgument("surface skeleton: triangle " + std::to_string(i) + " of " +
                          std::to_string(triangles_.size()));
  }
  const Tri& t = triangles_[i];
  return SkeletonTriangle{{t.a, t.b, t.c}, {t.uva, t.uvb, t.uvc}};
}

}  // namespace ramiform
