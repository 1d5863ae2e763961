// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
//
// docs/fields.md promises bit-identical field values on every CPU: the SIMD kernels
// (src/field/skeleton_field_simd.cpp) are dispatched at run time to SSE4, AVX2, AVX-512 or the
// emulated target, and must round alike on all of them. Each target the machine supports and the
// build compiles is forced in turn (hwy::SetSupportedTargetsForTest) and its field values,
// gradients and a tetrahedral mesh are compared byte for byte with the first target's.

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "field/bezier_curve_simd.h"
#include "field/equipotential_simd.h"
#include "field/field_test_util.h"
#include "field/skeleton_field_simd.h"
#include "ramiform/core/random.h"
#include "ramiform/field/anisotropic.h"
#include "ramiform/field/bezier_curve.h"
#include "ramiform/field/equipotential.h"
#include "ramiform/field/skeleton_field.h"
#include "ramiform/polygonize/tetrahedral.h"
#include "support/fixtures.h"

namespace ramiform {
namespace {

// Forces one Highway target for the lifetime of the object; the destructor restores the CPU's
// own choice (also when an assertion returns early).
class ForcedTarget {
 public:
  explicit ForcedTarget(std::int64_t target) { hwy::SetSupportedTargetsForTest(target); }
  ~ForcedTarget() { hwy::SetSupportedTargetsForTest(0); }
  ForcedTarget(const ForcedTarget&) = delete;
  ForcedTarget& operator=(const ForcedTarget&) = delete;
};

// The targets to compare: every one the CPU supports among those compiled (HWY_TARGETS: with
// no -march flags on x86-64, the SIMD targets SSSE3, SSE4, AVX2, AVX-512 and the plain C++
// fallback, HWY_EMU128, or HWY_SCALAR where Highway deems EMU128 broken, as with GCC < 12.3).
// The fallback is always among them, so even a machine with a single SIMD target compares it
// against plain C++ arithmetic.
std::vector<std::int64_t> targets() {
  hwy::SetSupportedTargetsForTest(0);
  return hwy::SupportedAndGeneratedTargets();
}

std::string target_names(const std::vector<std::int64_t>& list) {
  std::string s;
  for (const std::int64_t t : list) s += std::string(s.empty() ? "" : " ") + hwy::TargetName(t);
  return s;
}

TEST(SimdTargets, EmulatedTargetIsCompared) {
  const auto list = targets();
  RecordProperty("targets", target_names(list));
  ASSERT_GE(list.size(), 2U) << "targets: " << target_names(list);
  bool has_emulated = false;
  for (const std::int64_t t : list)
    has_emulated = has_emulated || t == HWY_EMU128 || t == HWY_SCALAR;
  EXPECT_TRUE(has_emulated) << "targets: " << target_names(list);
  // Forcing a target really reaches the field code's dispatch.
  for (const std::int64_t t : list) {
    const ForcedTarget forced(t);
    EXPECT_EQ(detail::dispatched_target(), t) << hwy::TargetName(t);
  }
  EXPECT_EQ(detail::dispatched_target(), list.front());
}

struct Evaluation {
  std::vector<double> values;
  std::vector<Vec3> gradients;
};

Evaluation evaluate(const Field& f, const std::vector<Vec3>& points) {
  Evaluation e;
  e.values.resize(points.size());
  e.gradients.resize(points.size());
  f.evaluate(points, e.values, e.gradients);
  return e;
}

// The first index where two arrays of doubles differ in any bit, or -1.
long first_difference(const double* a, const double* b, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (std::memcmp(a + i, b + i, sizeof(double)) != 0) return static_cast<long>(i);
  }
  return -1;
}

std::size_t count_differences(const double* a, const double* b, std::size_t n) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += std::memcmp(a + i, b + i, sizeof(double)) != 0;
  return count;
}

// Values and gradients of target `t` equal, bit for bit, those of target `first`.
void expect_same_bits(const Evaluation& e, const Evaluation& reference, std::int64_t t,
                      std::int64_t first) {
  const std::size_t n = e.values.size();
  EXPECT_EQ(first_difference(e.values.data(), reference.values.data(), n), -1)
      << hwy::TargetName(t) << " vs " << hwy::TargetName(first);
  EXPECT_EQ(first_difference(e.gradients[0].data(), reference.gradients[0].data(), 3 * n), -1)
      << hwy::TargetName(t) << " vs " << hwy::TargetName(first);
}

SkeletonFieldOptions field_options(SurfaceKind surface, const Kernel& kernel) {
  SkeletonFieldOptions o;
  o.surface = surface;
  o.kernel = kernel;
  return o;
}

// Every mode of the vector kernels: the Cauchy convolution surface (segments, plus a point
// primitive from a zero-length edge) and each distance-surface kernel, on a random tree with
// tapering radii (so the distance modes' R(t) slope is exercised) and 10,000 points from the
// inside to beyond the fade-out.
TEST(SimdTargets, FieldValuesAndGradientsBitIdentical) {
  const auto list = targets();
  Skeleton s = test::random_tree(11, 40);
  s.nodes.push_back(SkeletonNode{s.nodes[5].position + Vec3(0.3, 0.2, 0.1), 0.7});
  s.edges.push_back({5, static_cast<std::uint32_t>(s.nodes.size() - 1)});
  s.nodes.push_back(SkeletonNode{Vec3(-9, 2, 4), 0.6});  // an isolated node: a point primitive
  Rng rng(2026);
  std::vector<Vec3> points;
  for (int i = 0; i < 9500; ++i) points.push_back(test::point_near(s, rng, 6.0));
  for (int i = 0; i < 500; ++i) {
    points.push_back(s.nodes.back().position + rng.uniform(0, 4.0) * test::random_unit(rng));
  }

  std::vector<std::pair<std::string, SkeletonFieldOptions>> configs;
  configs.emplace_back("convolution cauchy",
                       field_options(SurfaceKind::kConvolution, Kernel{KernelKind::kCauchy, 0.0}));
  configs.emplace_back("distance cauchy",
                       field_options(SurfaceKind::kDistance, Kernel{KernelKind::kCauchy, 0.0}));
  for (const Kernel& k : test::distance_kernels()) {
    configs.emplace_back("distance " + kernel_name(k.kind) + ":" + std::to_string(k.parameter),
                         field_options(SurfaceKind::kDistance, k));
  }
  for (const auto& [what, options] : configs) {
    SCOPED_TRACE(what);
    const FieldPtr f = make_skeleton_field(s, options);
    Evaluation reference;
    for (const std::int64_t t : list) {
      const ForcedTarget forced(t);
      ASSERT_EQ(detail::dispatched_target(), t);
      const Evaluation e = evaluate(*f, points);
      if (t == list.front()) {
        reference = e;
        continue;
      }
      const std::size_t n = points.size();
      const long value_at = first_difference(e.values.data(), reference.values.data(), n);
      EXPECT_EQ(value_at, -1) << hwy::TargetName(t) << " vs " << hwy::TargetName(list.front())
                              << ": "
                              << count_differences(e.values.data(), reference.values.data(), n)
                              << " of " << n << " values differ, first at point " << value_at;
      const long gradient_at =
          first_difference(e.gradients[0].data(), reference.gradients[0].data(), 3 * n);
      EXPECT_EQ(gradient_at, -1) << hwy::TargetName(t) << " vs " << hwy::TargetName(list.front())
                                 << ": "
                                 << count_differences(e.gradients[0].data(),
                                                      reference.gradients[0].data(), 3 * n)
                                 << " of " << 3 * n << " gradient components differ";
    }
  }
}

// The batched Bezier projection (src/field/bezier_curve_simd.cpp) on every target: a cubic and
// a quintic curve field, 4,000 points from on the curves to far away, values and gradients
// identical on every target and to the one-point-at-a-time evaluation.
TEST(SimdTargets, BezierCurveFieldBitIdentical) {
  const auto list = targets();
  Rng rng(77);
  for (const int degree : {3, 5}) {
    SCOPED_TRACE("degree " + std::to_string(degree));
    BezierCurve c;
    for (int i = 0; i <= degree; ++i)
      c.controls.emplace_back(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const FieldPtr f = make_bezier_field(c, 0.3, Deformation{});
    std::vector<Vec3> points;
    for (int i = 0; i < 4000; ++i)
      points.push_back(bezier_point(c, rng.uniform()) +
                       rng.uniform(0, 1.5) * test::random_unit(rng));
    Evaluation reference;
    for (const std::int64_t t : list) {
      const ForcedTarget forced(t);
      ASSERT_EQ(detail::bezier_dispatched_target(), t);
      const Evaluation e = evaluate(*f, points);
      if (t == list.front()) {
        reference = e;
        // One point at a time (the scalar projection) gives the same bits.
        for (std::size_t k = 0; k < points.size(); k += 7) {
          const double v = f->value(points[k]);
          const Vec3 g = f->gradient(points[k]);
          ASSERT_EQ(std::memcmp(&v, &e.values[k], sizeof(double)), 0) << "point " << k;
          ASSERT_EQ(std::memcmp(g.data(), e.gradients[k].data(), sizeof(Vec3)), 0) << "point " << k;
        }
        continue;
      }
      expect_same_bits(e, reference, t, list.front());
    }
  }
}

// The default tetrahedral mesh of a small fork, convolution and distance surface: positions and
// triangles identical on every target.
// The equipotential treecode's group evaluation (src/field/equipotential_simd.cpp) for every
// integer alpha on every target: points on rings around the edges (groups whose clusters are far
// from some points and near others) and scattered ones, values and gradients identical on every
// target, and to the scalar traversal of each point alone.
TEST(SimdTargets, EquipotentialFieldBitIdentical) {
  const auto list = targets();
  const Skeleton s = test::random_tree(5, 40);
  Rng rng(31);
  std::vector<Vec3> points;
  for (const auto& e : s.edges) {
    const Vec3 a = s.nodes[e[0]].position, b = s.nodes[e[1]].position;
    const double r = s.nodes[e[0]].radius;
    for (int k = 0; k < 24; ++k) {
      points.push_back(a + (k / 24.0) * (b - a) + r * Vec3(std::cos(k), std::sin(k), 0.2));
    }
  }
  for (int k = 0; k < 1500; ++k) points.push_back(test::point_near(s, rng, 4.0));
  for (int alpha = 2; alpha <= 7; ++alpha) {
    SCOPED_TRACE("alpha " + std::to_string(alpha));
    EquipotentialOptions o;
    o.alpha = alpha;
    const ChargeSet charges = place_charges(s, o);
    const FieldPtr f = make_equipotential_field(charges, 1.0, o.theta);
    Evaluation reference;
    for (const std::int64_t t : list) {
      const ForcedTarget forced(t);
      const Evaluation e = evaluate(*f, points);
      if (t == list.front()) {
        reference = e;
        for (std::size_t k = 0; k < points.size(); k += 11) {
          Vec3 g;
          const double v = detail::charge_tree_value(charges, o.theta, points[k], &g);
          ASSERT_EQ(std::memcmp(&v, &e.values[k], sizeof(double)), 0) << "point " << k;
          ASSERT_EQ(std::memcmp(g.data(), e.gradients[k].data(), sizeof(Vec3)), 0) << "point " << k;
          const double lone = f->value(points[k]);
          ASSERT_EQ(std::memcmp(&lone, &v, sizeof(double)), 0) << "point " << k;
        }
        continue;
      }
      expect_same_bits(e, reference, t, list.front());
    }
  }
}

TEST(SimdTargets, TetrahedralMeshBitIdentical) {
  const auto list = targets();
  const Skeleton s = test::y_fork(0.1);
  const std::vector<std::pair<std::string, FieldPtr>> fields = {
      {"convolution cauchy", make_skeleton_field(s)},
      {"distance wyvill", test::wyvill_distance_field(s)}};
  for (const auto& [what, f] : fields) {
    SCOPED_TRACE(what);
    TriMesh reference;
    for (const std::int64_t t : list) {
      const ForcedTarget forced(t);
      const TriMesh mesh = polygonize_tetrahedral(*f, s);
      ASSERT_GT(mesh.triangle_count(), 100U);
      if (t == list.front()) {
        reference = mesh;
        continue;
      }
      const char* name = hwy::TargetName(t);
      ASSERT_EQ(mesh.vertex_count(), reference.vertex_count()) << name;
      ASSERT_EQ(mesh.triangle_count(), reference.triangle_count()) << name;
      EXPECT_EQ(first_difference(mesh.positions[0].data(), reference.positions[0].data(),
                                 3 * mesh.vertex_count()),
                -1)
          << name;
      EXPECT_TRUE(mesh.triangles == reference.triangles) << name;
    }
  }
}

}  // namespace
}  // namespace ramiform
