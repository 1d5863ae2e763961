// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// Internal: the path of sweep and skin surfaces (sweep.h; Kochhar 2010, "Application of implicit
// methods to the interactive modeling of trees" (M.Sc. thesis), §4.1–4.2): the exact curve, its
// flattened polyline with curve parameters and normalized arc lengths, the projection of points on
// it and its rotation-minimizing frames.

#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "ramiform/core/types.h"
#include "ramiform/field/curves.h"
#include "ramiform/field/sweep.h"

namespace ramiform::detail::sweep {

/// A path, flattened once with chord error `tolerance` and evaluated exactly where it is smooth.
/// Rotation-minimizing frames: for polylines one normal per piece, carried across each vertex
/// by the minimal rotation between the two directions (the exact RMF of a polyline); for smooth
/// paths double reflection (Wang, Jüttler, Zheng & Liu 2008, "Computation of rotation minimizing
/// frames", ACM TOG 27(1)) over frame samples at most kFrameAngle of tangent turn apart, blended
/// linearly between samples.
class Path {
 public:
  /// Where a point projects on the path, with the frame there.
  struct Projection {
    double t = 0;     ///< curve parameter, in [0, 1]
    double s = 0;     ///< normalized arc length of the flattened path, in [0, 1]
    double dsdt = 0;  ///< ds/dt on the flattened piece
    Vec3 origin, tangent, normal, binormal;
    Vec3 dtdp = Vec3::Zero();  ///< gradient of t with respect to p (0 where t is locally constant)
    bool newton = false;       ///< Newton's result was accepted
  };
  /// The closest point of the flattened polyline: piece and position u in [0, 1] on it.
  struct Coarse {
    std::size_t piece = 0;
    double u = 0, d2 = std::numeric_limits<double>::infinity();
  };

  /// Throws InvalidArgument prefixed by `what` for an invalid path (validate()) or one of zero
  /// length. `tolerance_option` 0: the default relative to the path's extent (sweep_common.h).
  Path(const Curve3& curve, double tolerance_option, const std::string& what);

  [[nodiscard]] std::size_t pieces() const { return v_.size() - 1; }
  /// A box containing the exact curve (convex hull property) and the flattened path.
  [[nodiscard]] const Aabb& box() const { return box_; }
  /// The chord error of the flattened path.
  [[nodiscard]] double tolerance() const { return tol_; }
  [[nodiscard]] double length() const { return length_; }

  [[nodiscard]] Coarse coarse(const Vec3& p) const;
  /// The projection of p: for polylines the closest point of the polyline (with a rounded
  /// joint's frame in the wedge beyond a bend); for smooth paths Newton–Raphson on
  /// (C(t) − p)·C'(t) = 0 (thesis eq. 4.1) from the coarse result, kept only when it converged
  /// without increasing the distance, else the coarse result on the exact curve.
  [[nodiscard]] Projection project(const Vec3& p) const;
  /// The frame at normalized arc length s in [0, 1].
  [[nodiscard]] PathFrame frame_at_s(double s) const;
  /// The distance from p to the flattened polyline.
  [[nodiscard]] double distance_to_polyline(const Vec3& p) const { return std::sqrt(coarse(p).d2); }

 private:
  struct Block {
    Aabb box;
    std::size_t begin, end;  // pieces [begin, end)
  };

  void flatten_path(const Curve3& curve, const std::string& what);
  [[nodiscard]] Vec3 point(double t) const { return curve_point(curve_, t); }
  [[nodiscard]] Vec3 derivative(double t) const { return curve_derivative(curve_, t); }
  [[nodiscard]] Vec3 second_derivative(double t) const {
    return curve_second_derivative(curve_, t);
  }
  [[nodiscard]] std::size_t piece_of_t(double t) const;
  [[nodiscard]] Vec3 piece_direction(std::size_t j) const {
    return (v_[j + 1] - v_[j]).normalized();
  }
  [[nodiscard]] bool newton(const Vec3& p, double& t) const;
  void polyline_frame(Projection& pr, std::size_t j, double u, const Vec3* p) const;
  [[nodiscard]] Vec3 smooth_tangent(double t, std::size_t j) const;
  void set_s(Projection& pr, std::size_t j, double w) const;
  void smooth_frame(Projection& pr) const;
  void build_frames();
  void build_polyline_frames();
  void sample_smooth_frames();
  void build_smooth_frames();

  Curve3 curve_;
  bool polyline_ = false;
  double extent_ = 0, tol_ = 0, length_ = 0;
  std::vector<Vec3> v_;     // flattened vertices
  std::vector<double> t_;   // their curve parameters
  std::vector<double> s_;   // their normalized arc lengths
  std::vector<Vec3> pn_;    // polylines: the RMF normal of each piece
  std::vector<Vec3> vt_;    // smooth paths: unit tangents at the vertices
  std::vector<double> ft_;  // frame samples: curve parameters (the vertices' and more)
  std::vector<Vec3> fp_;    // frame samples: points (only while building)
  std::vector<Vec3> ftan_;  // frame samples: unit tangents
  std::vector<Vec3> fn_;    // frame samples: RMF normals
  std::vector<Block> blocks_;
  Aabb box_;
};

/// The minimal rotation taking unit vector a to unit vector b (about a × b), applied to x, as
/// two reflections: across the plane orthogonal to a + b (a -> -b), then across the one
/// orthogonal to b (-b -> b). For a hairpin (b = -a, no unique rotation) x loses its component
/// along b instead.
[[nodiscard]] Vec3 rotate_between(const Vec3& a, const Vec3& b, const Vec3& x);

}  // namespace ramiform::detail::sweep
