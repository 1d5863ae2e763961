// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
// Anisotropic skeleton primitives (Rigaudière, Gesquière & Faudot, §3.2–4.3): the deformation
// functions def(t) against their formulas and finite differences, the segment / Bezier / surface
// fields against the geometry they promise (surface exactly r(t) / def(t) from the skeleton),
// their gradients, bounds and thread independence, and skeleton_distances against brute force.

#include "ramiform/field/anisotropic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "field/field_test_util.h"
#include "ramiform/core/context.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/operators.h"

namespace ramiform {
namespace {

using test::check_bound_in_box;
using test::grown;
using test::random_point;
using test::random_unit;
using K = Deformation::Kind;

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

Deformation make_def(K kind, double parameter = 0, double waves = 1, std::vector<double> v = {}) {
  Deformation d;
  d.kind = kind;
  d.parameter = parameter;
  d.waves = waves;
  d.values = std::move(v);
  return d;
}

// One of each kind (and a second flat exponent), all valid.
std::vector<Deformation> all_deformations() {
  return {make_def(K::kIdentity),
          make_def(K::kSquaredCosine, 0.3),
          make_def(K::kFlatEnds, 0),  // default exponent 8
          make_def(K::kFlatEnds, 4),
          make_def(K::kWave, 0.5, 2),
          make_def(K::kWave, 0.2, 3.5),
          make_def(K::kLinear, 0, 1, {1, 2, 0.5}),
          make_def(K::kBezier, 0, 1, {1, 0.5, 2, 1.5})};
}

// Interior kinks of a deformation (the knots of a piecewise linear one).
bool near_kink(const Deformation& d, double t, double eps) {
  if (d.kind != K::kLinear) return false;
  const double m = static_cast<double>(d.values.size() - 1);
  const double x = t * m;
  return std::abs(x - std::round(x)) < eps * m;
}

// Bernstein sum of coefficients c at t, written out with binomials.
double bernstein_sum(const std::vector<double>& c, double t) {
  const int n = static_cast<int>(c.size()) - 1;
  double s = 0;
  for (int i = 0; i <= n; ++i) {
    double binom = 1;
    for (int k = 1; k <= i; ++k) binom = binom * (n - k + 1) / k;
    s += c[static_cast<std::size_t>(i)] * binom * std::pow(t, i) * std::pow(1 - t, n - i);
  }
  return s;
}

Vec3 bernstein_point(const std::vector<Vec3>& c, double t) {
  const int n = static_cast<int>(c.size()) - 1;
  Vec3 s = Vec3::Zero();
  for (int i = 0; i <= n; ++i) {
    double binom = 1;
    for (int k = 1; k <= i; ++k) binom = binom * (n - k + 1) / k;
    s += c[static_cast<std::size_t>(i)] * (binom * std::pow(t, i) * std::pow(1 - t, n - i));
  }
  return s;
}

// ---------------------------------------------------------------------------------------------
// Deformation functions
// ---------------------------------------------------------------------------------------------

TEST(Deformation, DerivativeMatchesCentralDifferences) {
  for (const Deformation& d : all_deformations()) {
    const std::string name = format_deformation(d);
    for (int i = 1; i < 100; ++i) {
      const double t = 0.005 + 0.99 * i / 100.0;
      if (near_kink(d, t, 1e-4)) continue;
      double dv = 0;
      const double v = deformation_value(d, t, &dv);
      ASSERT_TRUE(std::isfinite(v)) << name << " t=" << t;
      const double h = 1e-6;
      const double fd = (deformation_value(d, t + h) - deformation_value(d, t - h)) / (2 * h);
      EXPECT_NEAR(dv, fd, 1e-6 * std::max(1.0, std::abs(fd))) << name << " at t=" << t;
    }
  }
}

TEST(Deformation, ValuesMatchTheDocumentedFormulas) {
  auto near = [](double got, double want) {
    EXPECT_NEAR(got, want, 1e-14 * std::max(1.0, std::abs(want)));
  };
  // identity
  for (double t : {0.0, 0.3, 1.0}) {
    double dv = 7;
    EXPECT_EQ(deformation_value(make_def(K::kIdentity), t, &dv), 1.0);
    EXPECT_EQ(dv, 0.0);
  }
  // squared-cosine: 1 / (s + (1 - s) sin^2(pi t))
  const Deformation sc = make_def(K::kSquaredCosine, 0.3);
  EXPECT_DOUBLE_EQ(deformation_value(sc, 0.5), 1.0);
  near(deformation_value(sc, 0.0), 1 / 0.3);
  near(deformation_value(sc, 1.0), 1 / 0.3);
  near(deformation_value(sc, 0.25), 1 / (0.3 + 0.7 * 0.5));
  near(deformation_value(sc, 0.1), 1 / (0.3 + 0.7 * std::pow(std::sin(kPi * 0.1), 2)));
  // s = 0: pointed ends (infinite def, derivative reported as 0)
  double dv = 5;
  EXPECT_EQ(deformation_value(make_def(K::kSquaredCosine, 0), 0.0, &dv), kInf);
  EXPECT_EQ(dv, 0.0);
  // flat: (1 - |2t - 1|^n)^(-1/n)
  const Deformation flat = make_def(K::kFlatEnds, 4);
  EXPECT_DOUBLE_EQ(deformation_value(flat, 0.5), 1.0);
  near(deformation_value(flat, 0.75), std::pow(1 - std::pow(0.5, 4), -0.25));
  near(deformation_value(flat, 0.1), std::pow(1 - std::pow(0.8, 4), -0.25));
  EXPECT_EQ(deformation_value(flat, 0.0), kInf);
  EXPECT_EQ(deformation_value(flat, 1.0), kInf);
  near(deformation_value(make_def(K::kFlatEnds, 0), 0.75), std::pow(1 - std::pow(0.5, 8), -0.125));
  // wave: 1 / (1 + a cos(2 pi w t))
  const Deformation wave = make_def(K::kWave, 0.5, 2);
  near(deformation_value(wave, 0.0), 1 / 1.5);
  near(deformation_value(wave, 0.25), 1 / 0.5);
  near(deformation_value(wave, 0.1), 1 / (1 + 0.5 * std::cos(2 * kPi * 2 * 0.1)));
  // linear through the values at t = i / (m - 1)
  const Deformation lin = make_def(K::kLinear, 0, 1, {1, 2, 0.5});
  EXPECT_EQ(deformation_value(lin, 0.0), 1.0);
  EXPECT_EQ(deformation_value(lin, 0.5), 2.0);
  EXPECT_EQ(deformation_value(lin, 1.0), 0.5);
  near(deformation_value(lin, 0.25), 1.5);
  near(deformation_value(lin, 0.75), 1.25);
  (void)deformation_value(lin, 0.25, &dv);
  near(dv, 2.0);
  (void)deformation_value(lin, 0.75, &dv);
  near(dv, -3.0);
  // bezier: Bernstein sum of the values
  const std::vector<double> b = {1, 0.5, 2, 1.5};
  const Deformation bez = make_def(K::kBezier, 0, 1, b);
  EXPECT_EQ(deformation_value(bez, 0.0), 1.0);
  EXPECT_EQ(deformation_value(bez, 1.0), 1.5);
  near(deformation_value(bez, 0.5), (1 + 3 * 0.5 + 3 * 2 + 1.5) / 8);
  near(deformation_value(bez, 0.3), bernstein_sum(b, 0.3));
  (void)deformation_value(bez, 0.0, &dv);
  near(dv, 3 * (0.5 - 1));
  // a single-coefficient bezier is constant
  EXPECT_EQ(deformation_value(make_def(K::kBezier, 0, 1, {2.5}), 0.7, &dv), 2.5);
  EXPECT_EQ(dv, 0.0);
}

TEST(Deformation, RangeBracketsDenseSamples) {
  std::vector<Deformation> defs = all_deformations();
  defs.push_back(make_def(K::kSquaredCosine, 0));
  defs.push_back(make_def(K::kWave, 0.9, 0.3));
  defs.push_back(make_def(K::kBezier, 0, 1, {3, 0.2, 0.2, 5, 1}));
  for (const Deformation& d : defs) {
    const Interval r = deformation_range(d);
    const std::string name = format_deformation(d);
    double lo = kInf, hi = -kInf;
    for (int i = 0; i <= 20000; ++i) {
      const double t = i / 20000.0;
      const double v = deformation_value(d, t);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      ASSERT_GE(v, r.lo * (1 - 1e-14)) << name << " t=" << t;
      ASSERT_LE(v, r.hi * (1 + 1e-14)) << name << " t=" << t;
    }
    EXPECT_GT(r.lo, 0) << name;
    // The range is attained (tight) for the closed-form kinds.
    if (d.kind != K::kBezier && !(d.kind == K::kWave && d.waves < 1)) {
      EXPECT_NEAR(lo, r.lo, 1e-6 * r.lo) << name;
      if (std::isfinite(r.hi)) {
        EXPECT_NEAR(hi, r.hi, 1e-6 * r.hi) << name;
      }
    }
  }
}

TEST(Deformation, ParseFormatRoundTrip) {
  for (const std::string text :
       {"identity", "squared-cosine:0.3", "squared-cosine:0", "squared-cosine:1", "flat:8",
        "flat:2.5", "wave:0.5,2", "wave:0,0.25", "linear:1,2,1", "linear:0.5,3,1e-05,7",
        "bezier:1,0.5,2", "bezier:4"}) {
    const Deformation d = parse_deformation(text);
    EXPECT_EQ(format_deformation(d), text);
    const Deformation e = parse_deformation(format_deformation(d));
    EXPECT_EQ(e.kind, d.kind) << text;
    EXPECT_EQ(e.parameter, d.parameter) << text;
    EXPECT_EQ(e.waves, d.waves) << text;
    EXPECT_EQ(e.values, d.values) << text;
  }
  // Defaults and aliases.
  EXPECT_EQ(parse_deformation("none").kind, K::kIdentity);
  EXPECT_EQ(parse_deformation("squared-cosine").parameter, 0.25);
  EXPECT_EQ(parse_deformation("flat").parameter, 8.0);
  EXPECT_EQ(parse_deformation("wave:0.4").waves, 1.0);
  EXPECT_EQ(format_deformation(make_def(K::kFlatEnds, 0)), "flat:8");
  for (const Deformation& d : all_deformations()) {
    const Deformation e = parse_deformation(format_deformation(d));
    for (double t : {0.1, 0.37, 0.5, 0.9}) {
      EXPECT_EQ(deformation_value(e, t), deformation_value(d, t)) << format_deformation(d);
    }
  }
}

// format_deformation writes the shortest text that reads back to the same double.
TEST(Deformation, ParseFormatRoundTripIsExactForAnyDouble) {
  for (const Deformation& d :
       {make_def(K::kSquaredCosine, 0.123456789), make_def(K::kWave, 0.1 + 0.2, 1.0 / 3),
        make_def(K::kLinear, 0, 1, {1.0000001, 2}), make_def(K::kFlatEnds, 2.0000003)}) {
    const Deformation e = parse_deformation(format_deformation(d));
    EXPECT_EQ(e.parameter, d.parameter) << format_deformation(d);
    EXPECT_EQ(e.waves, d.waves) << format_deformation(d);
    EXPECT_EQ(e.values, d.values) << format_deformation(d);
  }
}

TEST(Deformation, BadInputsNameTheProblem) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"linear:1", {"linear", "2 to 64", "got 1"}},
      {"squared-cosine:2", {"squared-cosine", "[0, 1]", "got 2"}},
      {"squared-cosine:-0.1", {"squared-cosine", "[0, 1]"}},
      {"wave:1", {"amplitude", "[0, 1)", "got 1"}},
      {"wave:0.5,0", {"wave count", "got 0"}},
      {"wave", {"wave", "1 to 2"}},
      {"bogus:1", {"unknown kind 'bogus'", "squared-cosine"}},
      {"linear:1,-2", {"value 2", "> 0", "got -2"}},
      {"bezier:1,0", {"value 2", "> 0"}},
      {"flat:1", {"flat-ends exponent", "[2, 64]"}},
      {"flat:65", {"flat-ends exponent"}},
      {"linear:1,x", {"'x' is not a finite number"}},
      {"linear:1,,2", {"'' is not a finite number"}},
      {"bezier:1,nan", {"'nan' is not a finite number"}},
      {"identity:1", {"identity takes 0"}},
      {"squared-cosine:0.1,0.2", {"squared-cosine takes 0 to 1"}},
  };
  for (const auto& [text, parts] : cases) {
    try {
      (void)parse_deformation(text);
      ADD_FAILURE() << text << " was accepted";
    } catch (const InvalidArgument& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("'" + text + "'"), std::string::npos) << msg;
      for (const std::string& p : parts) {
        EXPECT_NE(msg.find(p), std::string::npos) << text << ": '" << p << "' not in: " << msg;
      }
    }
  }
  // validate() on the struct names the caller's label and the problem.
  try {
    validate(make_def(K::kBezier), "my def");
    ADD_FAILURE();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("my def: bezier needs 1 to 64 values, got 0"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(validate(make_def(K::kWave, kInf), "w"), InvalidArgument);
  EXPECT_THROW(validate(make_def(K::kLinear, 0, 1, {1, kInf}), "l"), InvalidArgument);
  EXPECT_THROW(validate(make_def(K::kLinear, 0, 1, std::vector<double>(65, 1.0)), "l"),
               InvalidArgument);
  EXPECT_NO_THROW(validate(make_def(K::kLinear, 0, 1, std::vector<double>(64, 1.0)), "l"));
  // The field constructors refuse bad deformations and radii.
  EXPECT_THROW((void)make_anisotropic_segment_field(Vec3(0, 0, 0), Vec3(1, 0, 0), 0.5,
                                                    make_def(K::kWave, 1.5)),
               InvalidArgument);
  EXPECT_THROW((void)make_anisotropic_segment_field(Vec3(0, 0, 0), Vec3(0, 0, 0), 0.5, {}),
               InvalidArgument);
  EXPECT_THROW((void)make_anisotropic_segment_field(Vec3(0, 0, 0), Vec3(1, 0, 0), -1, {}),
               InvalidArgument);
  EXPECT_THROW((void)make_bezier_field(BezierCurve{{Vec3(0, 0, 0), Vec3(1, 0, 0)}, {}}, 0, {}),
               InvalidArgument);
}

// ---------------------------------------------------------------------------------------------
// Fields: the surface lies where the paper says
// ---------------------------------------------------------------------------------------------

// s in [0, smax] where f(q + s dir) crosses iso (f(q) > iso >= f(q + smax dir)), by bisection.
double crossing(const Field& f, const Vec3& q, const Vec3& dir, double smax) {
  double lo = 0, hi = smax;
  EXPECT_GT(f.value(q), f.iso());
  EXPECT_LE(f.value(q + smax * dir), f.iso());
  for (int i = 0; i < 200 && hi - lo > 0; ++i) {
    const double m = 0.5 * (lo + hi);
    if (m == lo || m == hi) break;
    (f.value(q + m * dir) > f.iso() ? lo : hi) = m;
  }
  return 0.5 * (lo + hi);
}

// A unit vector perpendicular to `tangent`, turned by `angle` about it.
Vec3 perpendicular(const Vec3& tangent, double angle) {
  const Vec3 u = tangent.normalized();
  Vec3 a = u.unitOrthogonal();
  const Vec3 b = u.cross(a);
  return std::cos(angle) * a + std::sin(angle) * b;
}

TEST(AnisotropicFields, IdentitySegmentSurfaceIsRadiusAway) {
  const Vec3 a(0.3, -1, 0.2), b(2, 1.5, -0.4);
  const double r = 0.4;
  const FieldPtr f = make_anisotropic_segment_field(a, b, r, Deformation{});
  EXPECT_EQ(f->iso(), 0.5);
  for (double t : {0.0, 0.1, 0.37, 0.5, 0.8, 1.0}) {
    for (double ang : {0.0, 1.0, 2.5, 4.0}) {
      const Vec3 q = a + t * (b - a);
      EXPECT_NEAR(crossing(*f, q, perpendicular(b - a, ang), 3 * r), r, 1e-9) << t << " " << ang;
    }
  }
  // The round caps: from an end straight away from the segment.
  EXPECT_NEAR(crossing(*f, a, (a - b).normalized(), 3 * r), r, 1e-9);
  EXPECT_NEAR(crossing(*f, b, (b - a).normalized(), 3 * r), r, 1e-9);
  const Vec3 oblique = ((b - a).normalized() + perpendicular(b - a, 0.7)).normalized();
  EXPECT_NEAR(crossing(*f, b, oblique, 3 * r), r, 1e-9);
}

// A gently curved cubic (radius of curvature well above the skin's thickness).
BezierCurve test_cubic() {
  return BezierCurve{{Vec3(0, 0, 0), Vec3(1.5, 1.5, 0.2), Vec3(3, 1.5, 0.8), Vec3(4.5, 0, 0.5)},
                     {}};
}

TEST(AnisotropicFields, IdentityBezierSurfaceIsRadiusAway) {
  const BezierCurve c = test_cubic();
  const double r = 0.25;
  const FieldPtr f = make_bezier_field(c, r, Deformation{});
  const BezierProjector proj(c);
  int checked = 0;
  for (double t : {0.05, 0.2, 0.5, 0.63, 0.9}) {
    for (double ang : {0.0, 1.3, 2.9, 4.4}) {
      const Vec3 q = bezier_point(c, t);
      const Vec3 n = perpendicular(bezier_derivative(c, t), ang);
      // The ray's nearest curve point stays C(t) up to beyond the surface.
      ASSERT_NEAR(proj.project(q + 2 * r * n).t, t, 1e-9);
      EXPECT_NEAR(crossing(*f, q, n, 3 * r), r, 1e-9) << t << " " << ang;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 20);
  // Caps at the ends.
  EXPECT_NEAR(crossing(*f, c.controls[0], -bezier_derivative(c, 0).normalized(), 3 * r), r, 1e-9);
  EXPECT_NEAR(crossing(*f, c.controls[3], bezier_derivative(c, 1).normalized(), 3 * r), r, 1e-9);
}

TEST(AnisotropicFields, SquaredCosineThickness) {
  const double s = 0.3;
  const double r = 0.5;
  const Deformation def = make_def(K::kSquaredCosine, s);
  const Vec3 a(-1, 0.5, 0), b(3, -0.5, 1);
  const FieldPtr seg = make_anisotropic_segment_field(a, b, r, def);
  const BezierCurve c = test_cubic();
  const FieldPtr bez = make_bezier_field(c, r, def);
  const BezierProjector proj(c);
  for (double t : {0.5, 0.02, 0.05, 0.1, 0.3, 0.75, 0.97}) {
    const double want = r * (s + (1 - s) * std::pow(std::sin(kPi * t), 2));
    if (t == 0.5) {
      EXPECT_EQ(want, r);
    }
    for (double ang : {0.4, 2.0, 3.7}) {
      EXPECT_NEAR(crossing(*seg, a + t * (b - a), perpendicular(b - a, ang), 2 * r), want, 1e-9)
          << "segment t=" << t;
      const Vec3 q = bezier_point(c, t);
      const Vec3 n = perpendicular(bezier_derivative(c, t), ang);
      ASSERT_NEAR(proj.project(q + 1.5 * r * n).t, t, 1e-9);
      EXPECT_NEAR(crossing(*bez, q, n, 2 * r), want, 1e-9) << "bezier t=" << t;
    }
  }
}

TEST(AnisotropicFields, OtherDeformationsThinTheSkinByDef) {
  const double r = 0.4;
  const Vec3 a(0, 0, 0), b(0, 0, 5);
  for (const Deformation& def : all_deformations()) {
    const FieldPtr f = make_anisotropic_segment_field(a, b, r, def);
    for (double t : {0.07, 0.25, 0.5, 0.61, 0.9}) {
      const double want = r / deformation_value(def, t);
      EXPECT_NEAR(crossing(*f, a + t * (b - a), Vec3(0.6, 0.8, 0), 3 * r), want, 1e-9)
          << format_deformation(def) << " t=" << t;
    }
  }
  // def = infinity (flat ends at t = 0) removes the neighbourhood of the end.
  const FieldPtr flat = make_anisotropic_segment_field(a, b, r, make_def(K::kFlatEnds, 8));
  EXPECT_EQ(flat->value(a + Vec3(0.01, 0, 0)), 0.0);
  EXPECT_EQ(flat->value(a - Vec3(0, 0, 0.05)), 0.0);
  EXPECT_GT(flat->value(0.5 * (a + b)), flat->iso());
}

TEST(AnisotropicFields, PerControlRadiiFollowTheBernsteinRadius) {
  BezierCurve c = test_cubic();
  c.radii = {0.2, 0.35, 0.15, 0.3};
  const FieldPtr f = make_bezier_field(c, 99 /* ignored */, Deformation{});
  const FieldPtr g = make_bezier_field(c, 99, make_def(K::kLinear, 0, 1, {1, 2}));
  const BezierProjector proj(c);
  for (double t : {0.03, 0.2, 0.45, 0.7, 0.95}) {
    const double rt = bernstein_sum(c.radii, t);
    EXPECT_NEAR(bezier_radius(c, t), rt, 1e-14);
    for (double ang : {0.0, 2.2, 4.1}) {
      const Vec3 q = bezier_point(c, t);
      const Vec3 n = perpendicular(bezier_derivative(c, t), ang);
      ASSERT_NEAR(proj.project(q + 1.5 * rt * n).t, t, 1e-9);
      EXPECT_NEAR(crossing(*f, q, n, 2 * rt), rt, 1e-9) << "t=" << t;
      EXPECT_NEAR(crossing(*g, q, n, 2 * rt), rt / (1 + t), 1e-9) << "t=" << t;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Fields: gradients, bounds, threads, operators
// ---------------------------------------------------------------------------------------------

struct TestField {
  std::string name;
  FieldPtr field;
  Aabb skeleton_box;                                     // box of the skeleton
  double thickness;                                      // largest skin thickness
  std::function<Vec3(Rng&)> near;                        // a random point near the skeleton
  std::function<double(const Vec3&)> skeleton_distance;  // distance to the skeleton
};

BicubicPatch wavy_patch() {
  BicubicPatch p;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      const double z = 0.6 * std::sin(1.3 * i + 0.4) * std::cos(0.9 * j) + 0.1 * i * j;
      p.controls[static_cast<std::size_t>(4 * i + j)] = Vec3(i, j + 0.2 * i, z);
    }
  }
  return p;
}

std::vector<TestField> test_fields() {
  std::vector<TestField> out;
  {
    const Vec3 a(-1, 0.2, 0.3), b(2, 1.1, -0.5);
    const double r = 0.4;
    TestField t{"segment squared-cosine",
                make_anisotropic_segment_field(a, b, r, make_def(K::kSquaredCosine, 0.4)),
                Aabb(a.cwiseMin(b), a.cwiseMax(b)),
                r,
                nullptr,
                nullptr};
    t.near = [a, b, r](Rng& rng) -> Vec3 {
      return a + rng.uniform(-0.1, 1.1) * (b - a) + rng.uniform(0, 1.8 * r) * random_unit(rng);
    };
    t.skeleton_distance = [a, b](const Vec3& p) { return test::brute_distance(p, a, b); };
    out.push_back(std::move(t));
  }
  {
    const Vec3 a(0, 0, 0), b(0, 3, 1);
    const double r = 0.3;
    TestField t{"segment linear",
                make_anisotropic_segment_field(a, b, r, make_def(K::kLinear, 0, 1, {2, 1, 1.5})),
                Aabb(a.cwiseMin(b), a.cwiseMax(b)),
                r,
                nullptr,
                nullptr};
    t.near = [a, b, r](Rng& rng) -> Vec3 {
      return a + rng.uniform(-0.1, 1.1) * (b - a) + rng.uniform(0, 1.8 * r) * random_unit(rng);
    };
    t.skeleton_distance = [a, b](const Vec3& p) { return test::brute_distance(p, a, b); };
    out.push_back(std::move(t));
  }
  {
    BezierCurve c = test_cubic();
    c.radii = {0.2, 0.35, 0.15, 0.3};
    Aabb box;
    for (const Vec3& p : c.controls) box.extend(p);
    TestField t{"bezier wave radii",
                make_bezier_field(c, 1, make_def(K::kWave, 0.4, 1.5)),
                box,
                0.35 / 0.6,
                nullptr,
                nullptr};
    t.near = [c](Rng& rng) {
      const double s = rng.uniform(-0.05, 1.05);
      const Vec3 q = bezier_point(c, std::clamp(s, 0.0, 1.0));
      return Vec3(q + rng.uniform(0, 0.6) * random_unit(rng));
    };
    auto proj = std::make_shared<BezierProjector>(c);
    t.skeleton_distance = [proj](const Vec3& p) { return proj->project(p).distance; };
    out.push_back(std::move(t));
  }
  {
    BezierCurve c{{Vec3(0, 0, 0), Vec3(1, 2, 0), Vec3(2, -1, 1), Vec3(3, 1, 0), Vec3(4, 0, 0.5)},
                  {}};
    Aabb box;
    for (const Vec3& p : c.controls) box.extend(p);
    TestField t{"quartic bezier bezier-def",
                make_bezier_field(c, 0.2, make_def(K::kBezier, 0, 1, {1, 0.6, 2, 1.2})),
                box,
                0.2 / 0.6,
                nullptr,
                nullptr};
    t.near = [c](Rng& rng) {
      const Vec3 q = bezier_point(c, rng.uniform());
      return Vec3(q + rng.uniform(0, 0.5) * random_unit(rng));
    };
    auto proj = std::make_shared<BezierProjector>(c);
    t.skeleton_distance = [proj](const Vec3& p) { return proj->project(p).distance; };
    out.push_back(std::move(t));
  }
  {
    auto sk = std::make_shared<const SurfaceSkeleton>(make_patch_surface(wavy_patch()),
                                                      SubdivisionOptions{10, 4});
    const double r = 0.15;
    TestField t{"patch def_u/def_v",
                make_surface_skeleton_field(sk, r, make_def(K::kLinear, 0, 1, {1, 2}),
                                            make_def(K::kBezier, 0, 1, {1, 0.5, 1.5})),
                sk->box(),
                r / 0.5,
                nullptr,
                nullptr};
    t.near = [sk, r](Rng& rng) {
      const Vec3 q = sk->surface().point(rng.uniform(), rng.uniform());
      return Vec3(q + rng.uniform(0, 3 * r) * random_unit(rng));
    };
    t.skeleton_distance = [sk](const Vec3& p) { return sk->project(p).distance; };
    out.push_back(std::move(t));
  }
  {
    Superquadric q;
    q.radii = Vec3(1, 0.8, 0.6);
    q.e1 = 0.7;
    q.e2 = 1.3;
    q.center = Vec3(0.5, -0.2, 0.1);
    auto sk = std::make_shared<const SurfaceSkeleton>(make_superquadric_surface(q),
                                                      SubdivisionOptions{10, 4});
    const double r = 0.1;
    TestField t{"superquadric",
                make_surface_skeleton_field(sk, r, make_def(K::kWave, 0.3, 2),
                                            make_def(K::kSquaredCosine, 0.5)),
                sk->box(),
                r / 0.5,
                nullptr,
                nullptr};
    t.near = [sk, r](Rng& rng) {
      const Vec3 p = sk->surface().point(rng.uniform(), rng.uniform());
      return Vec3(p + rng.uniform(0, 3 * r) * random_unit(rng));
    };
    t.skeleton_distance = [sk](const Vec3& p) { return sk->project(p).distance; };
    out.push_back(std::move(t));
  }
  {
    Superquadric q;  // plain sphere, identity deformations
    auto sk = std::make_shared<const SurfaceSkeleton>(make_superquadric_surface(q),
                                                      SubdivisionOptions{10, 4});
    TestField t{"superquadric sphere",
                make_surface_skeleton_field(sk, 0.2, {}, {}),
                sk->box(),
                0.2,
                nullptr,
                nullptr};
    t.near = [sk](Rng& rng) {
      const Vec3 p = sk->surface().point(rng.uniform(), rng.uniform());
      return Vec3(p + rng.uniform(0, 0.35) * random_unit(rng));
    };
    t.skeleton_distance = [sk](const Vec3& p) { return sk->project(p).distance; };
    out.push_back(std::move(t));
  }
  return out;
}

TEST(AnisotropicFields, GradientsMatchCentralDifferences) {
  const double h = 1e-6;
  for (const TestField& tf : test_fields()) {
    Rng rng(17);
    int tested = 0, skipped = 0, nonzero = 0;
    for (int i = 0; i < 400; ++i) {
      const Vec3 p = tf.near(rng);
      const Vec3 g = tf.field->gradient(p);
      if (tf.skeleton_distance(p) < 1e-3) {  // on the skeleton the distance has a kink
        ++skipped;
        continue;
      }
      // Skip points whose stencil straddles a discontinuity of the gradient (the medial axis,
      // the end planes of a segment, the knots of a linear def, the feature boundaries of a
      // surface's flat approximation): there the analytic gradient jumps within h.
      bool smooth = true;
      for (int k = 0; k < 3 && smooth; ++k) {
        for (double sgn : {-1.0, 1.0}) {
          Vec3 q = p;
          q[k] += sgn * h;
          if ((tf.field->gradient(q) - g).norm() > 1e-3 * (g.norm() + 1 / tf.thickness))
            smooth = false;
        }
      }
      // ... or the edge of the kernel's support (f is only C1 there: O(h) truncation error).
      int zeros = tf.field->value(p) == 0 ? 1 : 0;
      for (int k = 0; k < 3; ++k) {
        for (double sgn : {-1.0, 1.0}) {
          Vec3 q = p;
          q[k] += sgn * h;
          zeros += tf.field->value(q) == 0 ? 1 : 0;
        }
      }
      if (zeros != 0 && zeros != 7) smooth = false;
      if (!smooth) {
        ++skipped;
        continue;
      }
      ++tested;
      if (g.norm() > 1e-6) ++nonzero;
      const Vec3 fd = test::central_gradient(*tf.field, p, h);
      ASSERT_LE((g - fd).norm(), 1e-5 * g.norm() + 1e-8)
          << tf.name << " at " << p.transpose() << ": analytic " << g.transpose() << " vs central "
          << fd.transpose();
    }
    EXPECT_GT(tested, 320) << tf.name << " (skipped " << skipped << ")";
    EXPECT_GT(nonzero, 200) << tf.name;
  }
}

TEST(AnisotropicFields, BoundContainsSampledValues) {
  for (const TestField& tf : test_fields()) {
    const FieldPtr& f = tf.field;
    Rng rng(5);
    int straddling = 0;
    for (int b = 0; b < 250; ++b) {
      const Vec3 c =
          b % 3 == 0 ? random_point(rng, grown(tf.skeleton_box, 2 * tf.thickness)) : tf.near(rng);
      Vec3 half;
      for (int k = 0; k < 3; ++k) {
        half[k] = std::exp(rng.uniform(std::log(0.005), std::log(3.0))) * tf.thickness;
      }
      const Aabb box(c - half, c + half);
      bool failed = false;
      straddling += check_bound_in_box(*f, box, rng, 60, tf.name, failed) ? 1 : 0;
      if (failed) return;
    }
    EXPECT_GT(straddling, 10) << tf.name;
  }
}

TEST(AnisotropicFields, BoundsContainEveryInsidePoint) {
  for (const TestField& tf : test_fields()) {
    const Aabb bounds = tf.field->bounds();
    ASSERT_FALSE(bounds.isEmpty()) << tf.name;
    Rng rng(9);
    const Aabb sample = grown(tf.skeleton_box, 3 * tf.thickness);
    std::vector<Vec3> pts;
    for (int i = 0; i < 6000; ++i) pts.push_back(i % 2 ? random_point(rng, sample) : tf.near(rng));
    std::vector<double> v(pts.size());
    tf.field->evaluate(pts, v);
    int inside = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (v[i] <= tf.field->iso()) continue;
      ++inside;
      ASSERT_TRUE(bounds.contains(pts[i]))
          << tf.name << ": " << pts[i].transpose() << " is inside (f = " << v[i]
          << ") but outside bounds " << bounds.min().transpose() << " / "
          << bounds.max().transpose();
    }
    EXPECT_GT(inside, 200) << tf.name;
  }
}

TEST(AnisotropicFields, EvaluationDoesNotDependOnThreads) {
  for (const TestField& tf : test_fields()) {
    Rng rng(3);
    std::vector<Vec3> pts(20000);
    for (auto& p : pts) p = tf.near(rng);
    std::vector<double> v1(pts.size()), v2(pts.size());
    std::vector<Vec3> g1(pts.size()), g2(pts.size());
    Context one(1), two(2);
    tf.field->evaluate(pts, v1, g1, &one);
    tf.field->evaluate(pts, v2, g2, &two);
    EXPECT_EQ(std::memcmp(v1.data(), v2.data(), v1.size() * sizeof(double)), 0) << tf.name;
    EXPECT_EQ(std::memcmp(g1.data(), g2.data(), g1.size() * sizeof(Vec3)), 0) << tf.name;
    // And the batch equals the single-point calls.
    for (std::size_t i = 0; i < pts.size(); i += 997) {
      EXPECT_EQ(tf.field->value(pts[i]), v1[i]) << tf.name;
    }
  }
}

TEST(AnisotropicFields, BlendWithOperators) {
  const std::vector<TestField> fields = test_fields();
  std::vector<FieldPtr> children;
  for (const TestField& tf : fields) children.push_back(tf.field);
  const FieldPtr sum = make_sum(children);
  const FieldPtr uni = make_union(children);
  Rng rng(11);
  int blended = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p = fields[rng.below(fields.size())].near(rng);
    double want = 0, want_max = 0;
    Vec3 want_g = Vec3::Zero();
    int contributing = 0;
    for (const FieldPtr& c : children) {
      const double v = c->value(p);
      want += v;
      want_max = std::max(want_max, v);
      want_g += c->gradient(p);
      contributing += v > 0 ? 1 : 0;
    }
    blended += contributing > 1 ? 1 : 0;
    EXPECT_NEAR(sum->value(p), want, 1e-14 * std::max(1.0, want));
    EXPECT_LE((sum->gradient(p) - want_g).norm(), 1e-12 * std::max(1.0, want_g.norm()));
    EXPECT_EQ(uni->value(p), want_max);
  }
  EXPECT_GT(blended, 50);
  // The blend's bound and bounds still hold.
  const Interval iv = sum->bound(Aabb(Vec3(-2, -2, -2), Vec3(5, 5, 2)));
  EXPECT_LE(iv.lo, iv.hi);
  EXPECT_FALSE(sum->bounds().isEmpty());
}

// ---------------------------------------------------------------------------------------------
// skeleton_distances
// ---------------------------------------------------------------------------------------------

// Distance from p to a Bezier curve by dense sampling, each local minimum refined by
// golden-section search; the minimizing t in *t_out.
double brute_curve_distance(const std::vector<Vec3>& c, const Vec3& p, double* t_out) {
  constexpr int kN = 1000;
  std::vector<double> d(kN + 1);
  for (int i = 0; i <= kN; ++i)
    d[static_cast<std::size_t>(i)] = (bernstein_point(c, i / double(kN)) - p).norm();
  double best = kInf, best_t = 0;
  for (int i = 0; i <= kN; ++i) {
    const double di = d[static_cast<std::size_t>(i)];
    const bool local = (i == 0 || di <= d[static_cast<std::size_t>(i - 1)]) &&
                       (i == kN || di <= d[static_cast<std::size_t>(i + 1)]);
    if (!local) continue;
    double lo = std::max(0.0, (i - 1) / double(kN)), hi = std::min(1.0, (i + 1) / double(kN));
    const double phi = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 80; ++it) {
      const double m1 = hi - phi * (hi - lo), m2 = lo + phi * (hi - lo);
      if ((bernstein_point(c, m1) - p).norm() <= (bernstein_point(c, m2) - p).norm()) {
        hi = m2;
      } else {
        lo = m1;
      }
    }
    for (double t : {lo, hi, 0.5 * (lo + hi), (i) / double(kN)}) {
      const double v = (bernstein_point(c, t) - p).norm();
      if (v < best) {
        best = v;
        best_t = t;
      }
    }
  }
  if (t_out != nullptr) *t_out = best_t;
  return best;
}

Skeleton random_curved_skeleton(std::uint64_t seed) {
  Rng rng(seed);
  Skeleton s;
  for (int i = 0; i < 10; ++i) {
    s.nodes.push_back(
        {Vec3(rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-4, 4)), rng.uniform(0.1, 0.5)});
  }
  // A chain 0-1-...-8 plus two chords; node 9 stays isolated.
  for (std::uint32_t i = 0; i + 1 < 9; ++i) s.edges.push_back({i, i + 1});
  s.edges.push_back({0, 5});
  s.edges.push_back({2, 7});
  s.curves.resize(s.edges.size());
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    if (e % 3 == 1) continue;  // straight
    const Vec3 a = s.nodes[s.edges[e][0]].position, b = s.nodes[s.edges[e][1]].position;
    const int inner = 1 + static_cast<int>(rng.below(4));
    for (int k = 1; k <= inner; ++k) {
      const double f = static_cast<double>(k) / (inner + 1);
      s.curves[e].controls.push_back(a + f * (b - a) + 1.5 * random_unit(rng));
    }
  }
  s.nodes.push_back({Vec3(6, 6, 6), 0.3});  // isolated node 10 (node 9 is one too)
  validate(s);
  return s;
}

TEST(SkeletonDistances, MatchBruteForce) {
  const Skeleton s = random_curved_skeleton(42);
  ASSERT_TRUE(s.has_curves());
  Rng rng(7);
  std::vector<Vec3> pts;
  for (int i = 0; i < 400; ++i)
    pts.push_back(random_point(rng, Aabb(Vec3(-6, -6, -6), Vec3(8, 8, 8))));
  for (std::size_t i = 0; i < 11; ++i)
    pts.push_back(s.nodes[i].position + Vec3(0.01, -0.02, 0.005));
  const std::vector<SkeletonDistance> got = skeleton_distances(s, pts);
  ASSERT_EQ(got.size(), pts.size());
  std::vector<Vec3> controls;
  std::vector<double> radii;
  const std::vector<std::uint32_t> deg = degrees(s);
  int node_hits = 0, curve_hits = 0, straight_hits = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Vec3& p = pts[k];
    // Brute force over every element: edges first, then isolated nodes.
    std::vector<double> dist;
    std::vector<double> ts;
    for (std::size_t e = 0; e < s.edges.size(); ++e) {
      edge_controls(s, e, controls, radii);
      double t = 0;
      if (controls.size() == 2) {
        long double tl = 0;
        dist.push_back(test::brute_distance(p, controls[0], controls[1], &tl));
        t = static_cast<double>(tl);
      } else {
        dist.push_back(brute_curve_distance(controls, p, &t));
      }
      ts.push_back(t);
    }
    double best = kInf;
    std::size_t best_i = 0;
    for (std::size_t e = 0; e < dist.size(); ++e) {
      if (dist[e] < best) best = dist[e], best_i = e;
    }
    bool best_is_node = false;
    for (std::uint32_t n = 0; n < s.nodes.size(); ++n) {
      if (deg[n] != 0) continue;
      const double d = (p - s.nodes[n].position).norm();
      if (d < best) best = d, best_i = n, best_is_node = true;
    }
    const SkeletonDistance& r = got[k];
    ASSERT_NEAR(r.distance, best, 1e-9 * (1 + best)) << "point " << k;
    if (r.is_edge != !best_is_node || r.index != best_i) {
      // Only a near tie may pick another element; it must then be as near.
      const double other = r.is_edge ? dist[r.index] : (p - s.nodes[r.index].position).norm();
      EXPECT_NEAR(other, best, 1e-9 * (1 + best)) << "point " << k;
      continue;
    }
    if (!r.is_edge) {
      ++node_hits;
      EXPECT_EQ(r.t, 0.0);
      continue;
    }
    edge_controls(s, r.index, controls, radii);
    // The reported t is where the distance is attained.
    EXPECT_NEAR((bernstein_point(controls, r.t) - p).norm(), r.distance, 1e-9 * (1 + best));
    EXPECT_NEAR(r.t, ts[r.index], 1e-4) << "point " << k << " edge " << r.index;
    (controls.size() == 2 ? straight_hits : curve_hits)++;
  }
  EXPECT_GT(curve_hits, 50);
  EXPECT_GT(straight_hits, 20);
  EXPECT_GE(node_hits, 2);
  // Threads do not change anything.
  Context one(1), two(2);
  const auto a = skeleton_distances(s, pts, TieRule::kFirst, &one);
  const auto b = skeleton_distances(s, pts, TieRule::kFirst, &two);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    EXPECT_EQ(a[k].distance, b[k].distance);
    EXPECT_EQ(a[k].index, b[k].index);
    EXPECT_EQ(a[k].t, b[k].t);
    EXPECT_EQ(a[k].is_edge, b[k].is_edge);
  }
}

// The one-point path, independently: every element, each curve by project(p, rule) one point at
// a time; the least squared distance wins, ties to the lower element id (edges, then nodes).
SkeletonDistance one_point_nearest(const Skeleton& s, const std::vector<BezierProjector*>& curve,
                                   const Vec3& p, TieRule rule) {
  SkeletonDistance best;
  double best_d2 = kInf;
  const std::vector<std::uint32_t> deg = degrees(s);
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    double d2 = 0, t = 0, distance = 0;
    if (curve[e] != nullptr) {
      const BezierProjection proj = curve[e]->project(p, rule);
      t = proj.t;
      distance = proj.distance;
      d2 = distance * distance;
    } else {
      const Vec3 a = s.nodes[s.edges[e][0]].position, ab = s.nodes[s.edges[e][1]].position - a;
      t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      d2 = (p - (a + t * ab)).squaredNorm();
      distance = std::sqrt(d2);
    }
    if (d2 < best_d2) {
      best_d2 = d2;
      best = {distance, true, static_cast<std::uint32_t>(e), t};
    }
  }
  for (std::uint32_t n = 0; n < s.nodes.size(); ++n) {
    if (deg[n] != 0) continue;
    const double d2 = (p - s.nodes[n].position).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = {std::sqrt(d2), false, n, 0.0};
    }
  }
  return best;
}

TEST(SkeletonDistances, BatchedCurvesEqualTheOnePointPathBitForBit) {
  // Points near the curves (most blocks give each curve 4 or more of them: the batched path),
  // points at the curves' ends and nodes, far points, over several blocks of 256.
  const Skeleton s = random_curved_skeleton(9);
  std::vector<std::unique_ptr<BezierProjector>> owned;
  std::vector<BezierProjector*> curve(s.edges.size(), nullptr);
  std::vector<Vec3> controls;
  std::vector<double> radii;
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    edge_controls(s, e, controls, radii);
    if (controls.size() == 2) continue;
    owned.push_back(std::make_unique<BezierProjector>(BezierCurve{controls, {}}));
    curve[e] = owned.back().get();
  }
  Rng rng(11);
  std::vector<Vec3> pts;
  for (int i = 0; i < 700; ++i) {
    const std::size_t e = rng.below(s.edges.size());
    edge_controls(s, e, controls, radii);
    pts.push_back(bernstein_point(controls, rng.uniform()) + rng.uniform(0, 1.5) * random_unit(rng));
  }
  for (const auto& n : s.nodes) pts.push_back(n.position);
  for (int i = 0; i < 40; ++i) pts.push_back(30.0 * random_unit(rng));
  int curve_hits = 0;
  for (TieRule rule : {TieRule::kFirst, TieRule::kLast}) {
    Context one(1), two(2);
    const auto a = skeleton_distances(s, pts, rule, &one);
    const auto b = skeleton_distances(s, pts, rule, &two);
    // A block holding only a few points (the curves project them one by one).
    const std::vector<Vec3> few(pts.begin(), pts.begin() + 3);
    const auto c = skeleton_distances(s, few, rule);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const SkeletonDistance want = one_point_nearest(s, curve, pts[k], rule);
      for (const auto* got : {&a[k], &b[k], k < few.size() ? &c[k] : &a[k]}) {
        EXPECT_EQ(got->distance, want.distance) << "point " << k;
        EXPECT_EQ(got->t, want.t) << "point " << k;
        EXPECT_EQ(got->is_edge, want.is_edge) << "point " << k;
        EXPECT_EQ(got->index, want.index) << "point " << k;
      }
      if (want.is_edge && curve[want.index] != nullptr) ++curve_hits;
    }
  }
  EXPECT_GT(curve_hits, 500);
  // Exact ties inside one curve, in a batch: a U-shaped cubic symmetric about x = 0 and points
  // on its axis (the tie rule picks t or 1 - t, or an end).
  {
    Skeleton u;
    u.nodes = {{Vec3(-2, 0, 2), 0.2}, {Vec3(2, 0, 2), 0.2}};
    u.edges = {{0, 1}};
    u.curves = {EdgeCurve{{Vec3(-2, 0, -2), Vec3(2, 0, -2)}, {}}};
    BezierProjector projector(BezierCurve{{u.nodes[0].position, Vec3(-2, 0, -2), Vec3(2, 0, -2),
                                           u.nodes[1].position},
                                          {}});
    const std::vector<BezierProjector*> one_curve = {&projector};
    std::vector<Vec3> axis;
    for (int i = 0; i < 12; ++i) axis.emplace_back(0, 0.1 * (i % 3), -1.5 + 0.5 * i);
    axis.emplace_back(0, 0, 50);
    for (TieRule rule : {TieRule::kFirst, TieRule::kLast}) {
      const auto got = skeleton_distances(u, axis, rule);
      for (std::size_t k = 0; k < axis.size(); ++k) {
        const SkeletonDistance want = one_point_nearest(u, one_curve, axis[k], rule);
        EXPECT_EQ(got[k].distance, want.distance) << "axis point " << k;
        EXPECT_EQ(got[k].t, want.t) << "axis point " << k;
      }
      EXPECT_EQ(got.back().t, rule == TieRule::kFirst ? 0.0 : 1.0);
    }
    // Points on the curve (at the parameters where skeleton_distances samples it, and
    // others), within 1e-10 of it, and beyond its ends: the curve is their only element, so
    // the bound from its samples must not rule it out whatever the rounding.
    std::vector<Vec3> on;
    for (int i = 0; i <= 16; ++i) {
      const double t = i / 16.0;
      const Vec3 c = bezier_point(projector.curve(), t);
      on.push_back(c);
      on.push_back(c + Vec3(0, 1e-10, 0));
      on.push_back(c + Vec3(3e-11, -2e-11, 1e-10));
    }
    on.emplace_back(-2, 0, 2.5);
    on.emplace_back(2.000001, 0, 2);
    on.emplace_back(-2, 1e-12, 2);
    const auto got = skeleton_distances(u, on);
    for (std::size_t k = 0; k < on.size(); ++k) {
      const SkeletonDistance want = one_point_nearest(u, one_curve, on[k], TieRule::kFirst);
      EXPECT_TRUE(got[k].is_edge) << "point " << k;
      EXPECT_EQ(got[k].index, 0u) << "point " << k;
      EXPECT_EQ(got[k].distance, want.distance) << "point " << k;
      EXPECT_EQ(got[k].t, want.t) << "point " << k;
    }
  }
  // A non-finite point is refused.
  std::vector<Vec3> bad(pts.begin(), pts.begin() + 5);
  bad[3].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)skeleton_distances(s, bad), InvalidArgument);
}

TEST(SkeletonDistances, TiesPickTheLowerEdgeIndexAndEdgesBeforeNodes) {
  // Two parallel straight edges at y = +-1: the point between them is 1 from both.
  for (bool swap : {false, true}) {
    Skeleton s;
    s.nodes = {
        {Vec3(0, 1, 0), 0.2}, {Vec3(2, 1, 0), 0.2}, {Vec3(0, -1, 0), 0.2}, {Vec3(2, -1, 0), 0.2}};
    s.edges = {{0, 1}, {2, 3}};
    if (swap) std::swap(s.edges[0], s.edges[1]);
    const std::vector<Vec3> p = {Vec3(0.5, 0, 0), Vec3(1.75, 0, 0.25)};
    for (const SkeletonDistance& r : skeleton_distances(s, p)) {
      EXPECT_TRUE(r.is_edge);
      EXPECT_EQ(r.index, 0u) << "swap " << swap;
    }
  }
  // An edge and an isolated node equally near: the edge.
  {
    Skeleton s;
    s.nodes = {{Vec3(2, 0, 0), 0.2}, {Vec3(-1, 0, 0), 0.2}, {Vec3(1, 0, 0), 0.2}};
    s.edges = {{1, 2}};
    const std::vector<Vec3> p = {Vec3(1, 0, 0) + Vec3(0.5, 0, 0)};
    const SkeletonDistance r = skeleton_distances(s, p)[0];
    EXPECT_TRUE(r.is_edge);
    EXPECT_EQ(r.index, 0u);
    EXPECT_EQ(r.distance, 0.5);
    EXPECT_EQ(r.t, 1.0);
  }
  // Two mirror-image curved edges (x -> -x) and points on the mirror plane.
  for (bool swap : {false, true}) {
    Skeleton s;
    s.nodes = {{Vec3(-3, 0.1, 0), 0.2},
               {Vec3(-0.7, 0.3, 0.9), 0.2},
               {Vec3(3, 0.1, 0), 0.2},
               {Vec3(0.7, 0.3, 0.9), 0.2}};
    s.edges = {{0, 1}, {2, 3}};
    s.curves.resize(2);
    s.curves[0].controls = {Vec3(-2.1, 1.3, 0.4), Vec3(-1.3, -0.7, 1.7)};
    s.curves[1].controls = {Vec3(2.1, 1.3, 0.4), Vec3(1.3, -0.7, 1.7)};
    if (swap) {
      std::swap(s.edges[0], s.edges[1]);
      std::swap(s.curves[0], s.curves[1]);
    }
    const std::vector<Vec3> p = {Vec3(0, 0.37, 1.3), Vec3(0, -2.1, 0.3), Vec3(0, 5, -3)};
    for (const SkeletonDistance& r : skeleton_distances(s, p)) {
      EXPECT_TRUE(r.is_edge);
      EXPECT_EQ(r.index, 0u) << "swap " << swap << " distance " << r.distance;
    }
  }
}

TEST(SkeletonDistances, TieRuleOnOneCurve) {
  // A U-shaped cubic, symmetric about x = 0: a point high on the axis is equally near both ends.
  Skeleton s;
  s.nodes = {{Vec3(-2, 0, 2), 0.2}, {Vec3(2, 0, 2), 0.2}};
  s.edges = {{0, 1}};
  s.curves = {EdgeCurve{{Vec3(-2, 0, -2), Vec3(2, 0, -2)}, {}}};
  const std::vector<Vec3> p = {Vec3(0, 0, 50), Vec3(0, 0.3, 1.2)};
  const auto first = skeleton_distances(s, p, TieRule::kFirst);
  const auto last = skeleton_distances(s, p, TieRule::kLast);
  EXPECT_EQ(first[0].t, 0.0);
  EXPECT_EQ(last[0].t, 1.0);
  EXPECT_EQ(first[0].distance, last[0].distance);
  EXPECT_DOUBLE_EQ(first[0].distance, std::sqrt(4.0 + 48.0 * 48.0));
  // Lower on the axis the two nearest points are inside the curve, at t and 1 - t.
  EXPECT_LT(first[1].t, 0.5);
  EXPECT_GT(first[1].t, 0.0);
  EXPECT_NEAR(first[1].t + last[1].t, 1.0, 1e-9);
  EXPECT_NEAR(first[1].distance, last[1].distance, 1e-12);
}

TEST(SkeletonDistances, InvalidSkeletonThrowsInputError) {
  Skeleton s;
  s.nodes = {{Vec3(0, 0, 0), 0.2}, {Vec3(1, 0, 0), 0.2}};
  s.edges = {{0, 1}};
  s.curves = {EdgeCurve{{Vec3(0.5, kInf, 0)}, {}}};
  const std::vector<Vec3> p = {Vec3(0, 0, 0)};
  EXPECT_THROW((void)skeleton_distances(s, p), InputError);
  s.curves.clear();
  s.edges = {{0, 0}};
  EXPECT_THROW((void)skeleton_distances(s, p), InputError);
}

}  // namespace
}  // namespace ramiform
