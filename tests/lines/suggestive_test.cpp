// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <set>
#include <vector>

#include "ramiform/core/errors.h"
#include "ramiform/field/primitives.h"
#include "ramiform/lines/lines.h"

namespace ramiform {
namespace {

constexpr double kPi = std::numbers::pi;

// The torus of the tests: around the z axis through the origin, circle radius R, tube radius r.
constexpr double kR = 1.0, kr = 0.4;

FieldPtr torus_field() { return make_circle_field(Vec3::Zero(), Vec3::UnitZ(), kR, kr); }

double torus_distance(const Vec3& p) {
  return std::abs(std::hypot(std::hypot(p.x(), p.y()) - kR, p.z()) - kr);
}

// The torus in closed form at (u, v): p = ((R + r cos v) cos u, (R + r cos v) sin u, r sin v).
// Outward normal n; principal directions e_u (along the parallels), e_v (along the meridians)
// with curvatures κ_u = cos v / (R + r cos v) and κ_v = 1 / r (positive where the surface bends
// away from n, as on a sphere).
struct TorusFrame {
  Vec3 p, n, eu, ev;
  double ku = 0, kv = 0;
};

TorusFrame torus_at(double u, double v) {
  TorusFrame t;
  const double rho = kR + kr * std::cos(v);
  t.p = Vec3(rho * std::cos(u), rho * std::sin(u), kr * std::sin(v));
  t.n = Vec3(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
  t.eu = Vec3(-std::sin(u), std::cos(u), 0);
  t.ev = Vec3(-std::sin(v) * std::cos(u), -std::sin(v) * std::sin(u), std::cos(v));
  t.ku = std::cos(v) / rho;
  t.kv = 1.0 / kr;
  return t;
}

// DeCarlo et al. 2003: the radial curvature κ_r = κ_v cos²φ + κ_u sin²φ, φ the angle between w
// (the view vector eye − p projected on the tangent plane) and e_v; and its derivative along the
// unit ŵ by central differences over the parameters (a unit step along ŵ changes u by
// ŵ·e_u / (R + r cos v) and v by ŵ·e_v / r).
struct Radial {
  double kr = 0, dkr = 0, facing = 0;  // κ_r, D_ŵ κ_r, n·(eye − p)/|eye − p|
  Vec3 p;
};

double radial_curvature(const TorusFrame& t, const Vec3& eye, Vec3* w_hat = nullptr) {
  const Vec3 e = (eye - t.p).normalized();
  const Vec3 w = e - e.dot(t.n) * t.n;
  const double a = w.dot(t.ev), b = w.dot(t.eu);
  if (w_hat != nullptr) *w_hat = w.normalized();
  return (t.kv * a * a + t.ku * b * b) / (a * a + b * b);
}

Radial radial_at(double u, double v, const Vec3& eye) {
  const TorusFrame t = torus_at(u, v);
  Radial r;
  Vec3 w;
  r.kr = radial_curvature(t, eye, &w);
  r.p = t.p;
  r.facing = t.n.dot((eye - t.p).normalized());
  const double h = 1e-5;
  const double du = h * w.dot(t.eu) / (kR + kr * std::cos(v)), dv = h * w.dot(t.ev) / kr;
  r.dkr = (radial_curvature(torus_at(u + du, v + dv), eye) -
           radial_curvature(torus_at(u - du, v - dv), eye)) /
          (2 * h);
  return r;
}

// The zero set of κ_r on the torus, sampled where it crosses the parameter lines of a fine
// (u, v) grid (linear interpolation between the grid points).
std::vector<Radial> radial_zeros(const Vec3& eye) {
  const int nu = 720, nv = 720;
  std::vector<double> k(static_cast<std::size_t>(nu * nv));
  auto at = [&](int i, int j) -> double& {
    return k[static_cast<std::size_t>(((i % nu + nu) % nu) * nv + (j % nv + nv) % nv)];
  };
  auto u_of = [&](double i) { return 2 * kPi * i / nu; };
  auto v_of = [&](double j) { return 2 * kPi * j / nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) at(i, j) = radial_curvature(torus_at(u_of(i), v_of(j)), eye);
  std::vector<Radial> zeros;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double k0 = at(i, j);
      for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
        const double k1 = at(i + di, j + dj);
        if ((k0 < 0) == (k1 < 0)) continue;
        const double s = k0 / (k0 - k1);
        zeros.push_back(radial_at(u_of(i + s * di), v_of(j + s * dj), eye));
      }
    }
  }
  return zeros;
}

// A torus seen from `elevation_deg` above its plane, `distance` away, from azimuth
// `azimuth_deg` (0: from −y).
Camera oblique_camera(double elevation_deg = 35, double distance = 6, double azimuth_deg = 0) {
  Camera c;
  const double el = elevation_deg * kPi / 180, az = azimuth_deg * kPi / 180;
  c.eye = distance * Vec3(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el));
  c.target = Vec3::Zero();
  c.up = Vec3::UnitZ();
  return c;
}

const ParticleSystem& torus_particles() {
  static const ParticleSystem ps = [] {
    ParticleOptions o;
    o.count = 15000;
    return spread_particles(*torus_field(), o);
  }();
  return ps;
}

// δ of the particle nearest to p.
double local_delta(const ParticleSystem& ps, const Vec3& p) {
  double best = INFINITY, delta = 0;
  for (const SurfaceParticle& q : ps.particles) {
    const double d = (q.position - p).squaredNorm();
    if (d < best) best = d, delta = q.delta;
  }
  return delta;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

double distance_to_lines(const Vec3& p, const std::vector<Polyline>& lines) {
  double best = INFINITY;
  for (const Polyline& l : lines) {
    if (l.points.size() == 1) best = std::min(best, (l.points[0] - p).norm());
    for (std::size_t j = 1; j < l.points.size(); ++j)
      best = std::min(best, segment_distance(p, l.points[j - 1], l.points[j]));
  }
  return best;
}

// The suggestive contour of DeCarlo et al.: zeros of κ_r with D_w κ_r > 0, facing the eye.
std::vector<Radial> suggestive_zeros(const std::vector<Radial>& zeros) {
  std::vector<Radial> out;
  for (const Radial& z : zeros)
    if (z.dkr > 0 && z.facing > 0) out.push_back(z);
  return out;
}

double distance_to_set(const Vec3& p, const std::vector<Radial>& set) {
  double best = INFINITY;
  for (const Radial& z : set) best = std::min(best, (z.p - p).norm());
  return best;
}

// Every line point: near the analytic suggestive contour (within `max_deltas` of the local δ,
// and within `median_deltas` at the median), on the surface, facing the eye.
void expect_on_suggestive_contour(const std::vector<Polyline>& lines, const ParticleSystem& ps,
                                  const std::vector<Radial>& contour, const Vec3& eye,
                                  double median_deltas, double max_deltas) {
  std::vector<double> rel;
  for (const Polyline& l : lines) {
    EXPECT_EQ(l.kind, LineKind::kSuggestive);
    EXPECT_FALSE(l.closed);
    EXPECT_TRUE(l.visible.empty());
    ASSERT_GE(l.points.size(), 2u);
    for (const Vec3& p : l.points) {
      const double delta = local_delta(ps, p);
      ASSERT_LE(torus_distance(p), 1e-4 * delta);  // the particles' own tolerance
      const double u = std::atan2(p.y(), p.x());
      const double v = std::atan2(p.z(), std::hypot(p.x(), p.y()) - kR);
      EXPECT_GT(torus_at(u, v).n.dot(eye - p), 0) << "a line point faces away from the eye";
      rel.push_back(distance_to_set(p, contour) / delta);
    }
  }
  ASSERT_FALSE(rel.empty());
  std::sort(rel.begin(), rel.end());
  EXPECT_LE(rel[rel.size() / 2], median_deltas) << "median distance / δ";
  EXPECT_LE(rel.back(), max_deltas) << "largest distance / δ";
}

TEST(SuggestiveContours, SphereHasNone) {
  // Radius 1 around c: the distance surface of a point (a box shrunk to its centre).
  const Vec3 c(0.2, -0.1, 0.3);
  const FieldPtr sphere = make_box_field(c, Vec3::Constant(1.0), 1.0);
  ParticleOptions po;
  po.count = 3000;
  const ParticleSystem ps = spread_particles(*sphere, po);
  ASSERT_GT(ps.particles.size(), 2000u);
  for (const Vec3& eye :
       {Vec3(0, 0, 6), Vec3(3, -2, 1.5), Vec3(-1.5, 1.2, -1.0), Vec3(40, 25, -30)}) {
    Camera cam;
    cam.eye = eye;
    cam.target = c;
    cam.up = Vec3(0.3, 1, 0.1);
    for (const double theta : {10.0, 1.0}) {
      LineOptions o;
      o.theta_sc_deg = theta;
      LineStats st;
      const std::vector<Polyline> lines = suggestive_contours(*sphere, ps, cam, o, &st);
      EXPECT_TRUE(lines.empty()) << "eye " << eye.transpose();
      EXPECT_EQ(st.suggestive_particles, 0u) << "eye " << eye.transpose();
      EXPECT_EQ(st.lines[1], 0u);
      EXPECT_GT(st.field_evals, 0u);  // the x± points were evaluated
    }
  }
}

TEST(SuggestiveContours, TorusLinesFollowTheZerosOfRadialCurvature) {
  const FieldPtr f = torus_field();
  const ParticleSystem& ps = torus_particles();
  struct View {
    double elevation, distance, azimuth;
  };
  for (const View view : {View{35, 6, 0}, View{30, 3.5, 70}, View{45, 10, 200}}) {
    SCOPED_TRACE(testing::Message() << "elevation " << view.elevation << ", distance "
                                    << view.distance << ", azimuth " << view.azimuth);
    const Camera cam = oblique_camera(view.elevation, view.distance, view.azimuth);
    const std::vector<Radial> contour = suggestive_zeros(radial_zeros(cam.eye));
    ASSERT_GT(contour.size(), 100u);

    LineOptions o;
    LineStats st;
    f->reset_evaluations();
    const std::vector<Polyline> lines = suggestive_contours(*f, ps, cam, o, &st);
    ASSERT_FALSE(lines.empty());
    EXPECT_EQ(st.lines[1], lines.size());
    EXPECT_EQ(st.lines[0] + st.lines[2], 0u);
    EXPECT_GE(st.suggestive_clusters, lines.size());
    EXPECT_GE(st.suggestive_particles, 2 * lines.size());
    EXPECT_EQ(st.field_evals, f->evaluations());
    EXPECT_GT(st.seconds_suggestive, 0);
    double length = 0;
    for (const Polyline& l : lines)
      for (std::size_t j = 1; j < l.points.size(); ++j)
        length += (l.points[j] - l.points[j - 1]).norm();
    EXPECT_NEAR(st.length[1], length, 1e-12 * length);

    // k_d = 0.5: a particle passes within about k_d δ / 2 of the minimum along w.
    expect_on_suggestive_contour(lines, ps, contour, cam.eye, 0.2, 0.5);

    // Coverage: the analytic suggestive contour where it is stable (away from the silhouette and
    // from eq. 8's cone, D_w κ_r clearly positive) lies near some line.
    const double cos_theta = std::cos((o.theta_sc_deg + 5) * kPi / 180);
    std::size_t tested = 0, covered = 0;
    for (const Radial& z : contour) {
      if (z.facing < 0.15 || z.facing > cos_theta || z.dkr < 1.0) continue;
      ++tested;
      covered += distance_to_lines(z.p, lines) <= 2.0 * local_delta(ps, z.p);
    }
    ASSERT_GT(tested, 100u);
    EXPECT_GE(static_cast<double>(covered), 0.9 * static_cast<double>(tested))
        << covered << " of " << tested << " analytic samples near a line";
  }
}

TEST(SuggestiveContours, TrimmedTreeAndLongestPathAgreeOnClusters) {
  const FieldPtr f = torus_field();
  const ParticleSystem& ps = torus_particles();
  const Camera cam = oblique_camera();
  const std::vector<Radial> contour = suggestive_zeros(radial_zeros(cam.eye));

  LineOptions o;
  o.smoothing = 0;  // line points are then particles, so lines can be matched by their points
  o.k_d = 2.0;      // a wider band of suggestive particles: spanning trees with side branches
  o.fit = SuggestiveFit::kLongestPath;
  LineStats longest_stats;
  const std::vector<Polyline> longest = suggestive_contours(*f, ps, cam, o, &longest_stats);
  o.fit = SuggestiveFit::kTrim;
  LineStats trim_stats;
  const std::vector<Polyline> trimmed = suggestive_contours(*f, ps, cam, o, &trim_stats);
  ASSERT_FALSE(longest.empty());
  ASSERT_GT(trimmed.size(), longest.size()) << "the trees should branch";
  // x± are 2 δ away: a particle passes up to about 1 δ from the minimum along w.
  expect_on_suggestive_contour(longest, ps, contour, cam.eye, 0.6, 1.25);
  expect_on_suggestive_contour(trimmed, ps, contour, cam.eye, 0.6, 1.25);
  EXPECT_EQ(longest_stats.suggestive_particles, trim_stats.suggestive_particles);
  EXPECT_EQ(longest_stats.suggestive_clusters, trim_stats.suggestive_clusters);

  // Every point is a particle; a longest path visits each of its particles once.
  std::map<std::vector<double>, std::size_t> particle_of;
  for (std::size_t i = 0; i < ps.particles.size(); ++i) {
    const Vec3& p = ps.particles[i].position;
    particle_of[{p.x(), p.y(), p.z()}] = i;
  }
  auto index = [&](const Vec3& p) {
    const auto it = particle_of.find({p.x(), p.y(), p.z()});
    EXPECT_NE(it, particle_of.end()) << "a line point is not a particle";
    return it == particle_of.end() ? SIZE_MAX : it->second;
  };
  std::vector<std::set<std::size_t>> longest_sets;
  for (const Polyline& l : longest) {
    std::set<std::size_t> s;
    for (const Vec3& p : l.points) s.insert(index(p));
    EXPECT_EQ(s.size(), l.points.size()) << "a longest path repeats a particle";
    EXPECT_GE(s.size(), static_cast<std::size_t>(o.min_cluster));
    longest_sets.push_back(std::move(s));
  }
  // No particle in two longest paths.
  std::set<std::size_t> all;
  for (const auto& s : longest_sets) {
    for (const std::size_t i : s) EXPECT_TRUE(all.insert(i).second);
  }

  // The trimmed polylines of one cluster form a tree joined at shared end particles: group them
  // by shared particles (union–find over lines); each group is one cluster.
  std::vector<std::size_t> group(trimmed.size());
  for (std::size_t i = 0; i < group.size(); ++i) group[i] = i;
  auto find = [&](std::size_t a) {
    while (group[a] != a) a = group[a];
    return a;
  };
  std::map<std::size_t, std::size_t> line_of_particle;
  for (std::size_t l = 0; l < trimmed.size(); ++l) {
    for (const Vec3& p : trimmed[l].points) {
      const auto [it, fresh] = line_of_particle.emplace(index(p), l);
      if (!fresh) group[find(l)] = find(it->second);
    }
  }
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (std::size_t l = 0; l < trimmed.size(); ++l) groups[find(l)].push_back(l);

  // One longest path per cluster: the groups and the longest paths match one to one by shared
  // particles, and no trimmed polyline (a path in the same tree) is longer than its cluster's
  // longest path.
  auto length = [](const Polyline& l) {
    double s = 0;
    for (std::size_t j = 1; j < l.points.size(); ++j) s += (l.points[j] - l.points[j - 1]).norm();
    return s;
  };
  EXPECT_EQ(groups.size(), longest.size());
  std::set<std::size_t> matched;
  for (const auto& [root, members] : groups) {
    std::set<std::size_t> hits;
    for (const std::size_t l : members) {
      for (const Vec3& p : trimmed[l].points) {
        const std::size_t i = index(p);
        for (std::size_t k = 0; k < longest_sets.size(); ++k)
          if (longest_sets[k].count(i) != 0) hits.insert(k);
      }
    }
    ASSERT_EQ(hits.size(), 1u) << "a trimmed tree meets " << hits.size() << " longest paths";
    const std::size_t k = *hits.begin();
    EXPECT_TRUE(matched.insert(k).second);
    for (const std::size_t l : members) EXPECT_LE(length(trimmed[l]), length(longest[k]) + 1e-12);
  }
}

TEST(SuggestiveContours, SmoothingKeepsEndsAndStaysOnTheSurface) {
  const FieldPtr f = torus_field();
  const ParticleSystem& ps = torus_particles();
  const Camera cam = oblique_camera();
  LineOptions o;
  o.smoothing = 0;
  const std::vector<Polyline> raw = suggestive_contours(*f, ps, cam, o);
  o.smoothing = 4;
  const std::vector<Polyline> smooth = suggestive_contours(*f, ps, cam, o);
  ASSERT_EQ(raw.size(), smooth.size());
  double raw_turn = 0, smooth_turn = 0;
  auto turning = [](const Polyline& l) {
    double s = 0;
    for (std::size_t j = 2; j < l.points.size(); ++j) {
      const Vec3 a = (l.points[j - 1] - l.points[j - 2]).normalized();
      const Vec3 b = (l.points[j] - l.points[j - 1]).normalized();
      s += std::acos(std::clamp(a.dot(b), -1.0, 1.0));
    }
    return s;
  };
  for (std::size_t l = 0; l < raw.size(); ++l) {
    ASSERT_EQ(raw[l].points.size(), smooth[l].points.size());
    EXPECT_EQ(raw[l].points.front(), smooth[l].points.front());
    EXPECT_EQ(raw[l].points.back(), smooth[l].points.back());
    // Interior points re-projected (|f − iso| / |∇f| ≤ 1e-7 δ; |∇f| ≈ 1 on this torus).
    for (std::size_t j = 1; j + 1 < smooth[l].points.size(); ++j) {
      const Vec3& p = smooth[l].points[j];
      EXPECT_LE(torus_distance(p), 1e-6 * local_delta(ps, p));
    }
    raw_turn += turning(raw[l]);
    smooth_turn += turning(smooth[l]);
  }
  EXPECT_LT(smooth_turn, 0.6 * raw_turn) << "smoothing should straighten the lines";
}

bool same_bytes(const std::vector<Polyline>& a, const std::vector<Polyline>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t l = 0; l < a.size(); ++l) {
    if (a[l].points.size() != b[l].points.size() || a[l].closed != b[l].closed ||
        a[l].kind != b[l].kind)
      return false;
    if (std::memcmp(a[l].points.data(), b[l].points.data(), sizeof(Vec3) * a[l].points.size()) != 0)
      return false;
  }
  return true;
}

TEST(SuggestiveContours, SameBytesOnOneAndTwoThreads) {
  const FieldPtr f = torus_field();
  const ParticleSystem& ps = torus_particles();
  const Camera cam = oblique_camera();
  for (const SuggestiveFit fit : {SuggestiveFit::kLongestPath, SuggestiveFit::kTrim}) {
    LineOptions o;
    o.fit = fit;
    const Context one(1), two(2);
    LineStats s1, s2;
    const std::vector<Polyline> a = suggestive_contours(*f, ps, cam, o, &s1, &one);
    const std::vector<Polyline> b = suggestive_contours(*f, ps, cam, o, &s2, &two);
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(same_bytes(a, b));
    EXPECT_EQ(s1.suggestive_particles, s2.suggestive_particles);
    EXPECT_EQ(s1.suggestive_clusters, s2.suggestive_clusters);
    EXPECT_EQ(s1.field_evals, s2.field_evals);
  }
}

// DeCarlo et al.'s t_d, scale-free: particles are kept where δ²·D_ŵ κ_r > t_d. Against the
// analytic D_ŵ κ_r of the torus: a threshold below what the stable contour has keeps it covered,
// and one well above the largest value it has removes every line (the estimate has the right
// scale).
TEST(SuggestiveContours, DerivativeThresholdAgainstTheAnalyticDerivative) {
  const FieldPtr f = torus_field();
  const ParticleSystem& ps = torus_particles();
  const Camera cam = oblique_camera(35, 6, 0);
  const std::vector<Radial> contour = suggestive_zeros(radial_zeros(cam.eye));
  const double cos_theta = std::cos((LineOptions{}.theta_sc_deg + 5) * kPi / 180);
  std::vector<const Radial*> stable;
  std::vector<double> scaled;  // δ²·D_ŵ κ_r at the stable analytic samples
  for (const Radial& z : contour) {
    if (z.facing < 0.15 || z.facing > cos_theta || z.dkr < 1.0) continue;
    stable.push_back(&z);
    const double delta = local_delta(ps, z.p);
    scaled.push_back(delta * delta * z.dkr);
  }
  ASSERT_GT(stable.size(), 100u);
  std::vector<double> sorted = scaled;
  std::sort(sorted.begin(), sorted.end());
  LineOptions o;
  o.t_d = 0.5 * sorted[sorted.size() / 10];
  LineStats all, kept;
  (void)suggestive_contours(*f, ps, cam, {}, &all);
  const std::vector<Polyline> lines = suggestive_contours(*f, ps, cam, o, &kept);
  EXPECT_LE(kept.suggestive_particles, all.suggestive_particles);
  std::size_t tested = 0, covered = 0;
  for (std::size_t k = 0; k < stable.size(); ++k) {
    if (scaled[k] < 2 * o.t_d) continue;
    ++tested;
    covered += distance_to_lines(stable[k]->p, lines) <= 2.0 * local_delta(ps, stable[k]->p);
  }
  EXPECT_GE(static_cast<double>(covered), 0.9 * static_cast<double>(tested))
      << covered << " of " << tested << " (t_d " << o.t_d << ")";
  o.t_d = 4 * sorted.back();
  LineStats none;
  EXPECT_TRUE(suggestive_contours(*f, ps, cam, o, &none).empty());
  EXPECT_EQ(none.suggestive_particles, 0u);
}

// min_line_length drops exactly the lines shorter than that many δ (their particles' mean δ).
TEST(SuggestiveContours, MinLineLengthDropsShortLines) {
  const FieldPtr f = torus_field();
  const ParticleSystem& ps = torus_particles();
  const Camera cam = oblique_camera(30, 3.5, 70);
  LineOptions o;
  o.smoothing = 0;  // line points are then particles: their δ is exact
  const std::vector<Polyline> all = suggestive_contours(*f, ps, cam, o);
  o.min_line_length = 6;
  LineStats st;
  const std::vector<Polyline> kept = suggestive_contours(*f, ps, cam, o, &st);
  std::vector<const Polyline*> expected;
  for (const Polyline& l : all) {
    double length = 0, delta = 0;
    for (std::size_t j = 0; j < l.points.size(); ++j) {
      if (j > 0) length += (l.points[j] - l.points[j - 1]).norm();
      delta += local_delta(ps, l.points[j]);
    }
    delta /= static_cast<double>(l.points.size());
    if (length >= o.min_line_length * delta) expected.push_back(&l);
  }
  ASSERT_LT(expected.size(), all.size());
  ASSERT_EQ(kept.size(), expected.size());
  EXPECT_EQ(st.lines[1], kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(kept[k].points, expected[k]->points);
}

TEST(SuggestiveContours, RejectsBadOptionsAndCameras) {
  const FieldPtr f = torus_field();
  ParticleSystem empty;
  const Camera cam = oblique_camera();
  LineOptions o;
  o.k_d = 0;
  EXPECT_THROW((void)suggestive_contours(*f, empty, cam, o), InvalidArgument);
  o = {};
  o.theta_sc_deg = 95;
  EXPECT_THROW((void)suggestive_contours(*f, empty, cam, o), InvalidArgument);
  o = {};
  o.min_cluster = 1;
  EXPECT_THROW((void)suggestive_contours(*f, empty, cam, o), InvalidArgument);
  for (const double bad : {-0.1, std::nan("")}) {
    o = {};
    o.t_d = bad;
    EXPECT_THROW((void)suggestive_contours(*f, empty, cam, o), InvalidArgument);
    o = {};
    o.min_line_length = bad;
    EXPECT_THROW((void)suggestive_contours(*f, empty, cam, o), InvalidArgument);
  }
  Camera bad = cam;
  bad.target = bad.eye;
  EXPECT_THROW((void)suggestive_contours(*f, empty, bad, {}), InvalidArgument);
  // Valid options and no particles: no lines.
  LineStats st;
  EXPECT_TRUE(suggestive_contours(*f, empty, cam, {}, &st).empty());
  EXPECT_EQ(st.suggestive_particles, 0u);
  EXPECT_EQ(st.suggestive_clusters, 0u);
}

TEST(SuggestiveContours, CancelledThroughTheContext) {
  const FieldPtr f = torus_field();
  Context ctx;
  ctx.cancel();
  EXPECT_THROW(
      (void)suggestive_contours(*f, torus_particles(), oblique_camera(), {}, nullptr, &ctx),
      Cancelled);
}

}  // namespace
}  // namespace ramiform
