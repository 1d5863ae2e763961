// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/io/particles_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "io/io_test_util.h"
#include "ramiform/core/errors.h"
#include "ramiform/field/operators.h"
#include "ramiform/field/primitives.h"
#include "ramiform/io/points_io.h"

namespace ramiform {
namespace {

using io_test::TempDir;

bool same_bits(const void* a, const void* b, std::size_t n) { return std::memcmp(a, b, n) == 0; }

ParticleSystem sample_system() {
  ParticleSystem s;
  s.iso = 1.0 / 3.0;
  s.root = Aabb(Vec3(-1.0 / 3.0, -2, -2), Vec3(2, 2, 5.0 / 3.0));
  s.cells = {{Aabb(Vec3(-1, -1, -1), Vec3(0, 0, 0)), 1},
             {Aabb(Vec3(0.1, 1e-300, -0.0), Vec3(0.2, 1, M_PI)), 16}};
  s.particles = {{Vec3(0.1, -0.0, 1e-320), Vec3(1, 0, 0), 0.125, 0},
                 {Vec3(1.0 / 7.0, 2e10, -3), Vec3(0.6, -0.8, 0), M_PI, 1},
                 {Vec3(5, 6, 7), Vec3(1, 1, 1).normalized(), 1e-9, 1}};
  return s;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_all(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

std::string message_of(const std::string& path) {
  try {
    (void)read_particles(path);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return {};
}

TEST(ParticlesIo, RoundTripIsExact) {
  const TempDir dir;
  const ParticleSystem s = sample_system();
  const std::string path = dir.file("state.ply");
  write_particles(s, path);
  const ParticleSystem r = read_particles(path);
  EXPECT_TRUE(same_bits(&r.iso, &s.iso, sizeof(double)));
  EXPECT_TRUE(same_bits(r.root.min().data(), s.root.min().data(), 24));
  EXPECT_TRUE(same_bits(r.root.max().data(), s.root.max().data(), 24));
  ASSERT_EQ(r.cells.size(), s.cells.size());
  ASSERT_EQ(r.particles.size(), s.particles.size());
  for (std::size_t c = 0; c < s.cells.size(); ++c) {
    EXPECT_TRUE(same_bits(r.cells[c].box.min().data(), s.cells[c].box.min().data(), 24));
    EXPECT_TRUE(same_bits(r.cells[c].box.max().data(), s.cells[c].box.max().data(), 24));
    EXPECT_EQ(r.cells[c].depth, s.cells[c].depth);
  }
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    EXPECT_TRUE(same_bits(r.particles[i].position.data(), s.particles[i].position.data(), 24)) << i;
    EXPECT_TRUE(same_bits(r.particles[i].normal.data(), s.particles[i].normal.data(), 24)) << i;
    EXPECT_TRUE(same_bits(&r.particles[i].delta, &s.particles[i].delta, 8)) << i;
    EXPECT_EQ(r.particles[i].cell, s.particles[i].cell);
  }
  // Other PLY readers see the particles as points with normals.
  const PointSet pts = read_points(path);
  ASSERT_EQ(pts.size(), 3u);
  EXPECT_TRUE(same_bits(pts.positions[1].data(), s.particles[1].position.data(), 24));
  EXPECT_TRUE(same_bits(pts.normals[2].data(), s.particles[2].normal.data(), 24));
  // Writing again gives the same bytes.
  write_particles(r, dir.file("again.ply"));
  EXPECT_EQ(read_all(path), read_all(dir.file("again.ply")));
}

ParticleSystem seeded_system() {
  ParticleSystem s = sample_system();
  s.seed_positions = {Vec3(0.1, 1.0 / 3.0, -0.0), Vec3(1e-310, -2e10, 7), Vec3(M_PI, 0, -1)};
  s.seed_normals = {Vec3(0, 0, 1), Vec3(0.6, 0, -0.8), Vec3(-1, 1, 1).normalized()};
  return s;
}

TEST(ParticlesIo, SeedingStateRoundTripsExactly) {
  const TempDir dir;
  const ParticleSystem s = seeded_system();
  const std::string path = dir.file("seeded.ply");
  write_particles(s, path);
  EXPECT_NE(read_all(path).find("property double sx\nproperty double sy\nproperty double "
                                "sz\nproperty double snx\nproperty double sny\nproperty "
                                "double snz\n"),
            std::string::npos);
  const ParticleSystem r = read_particles(path);
  ASSERT_TRUE(has_seed_state(r));
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    EXPECT_TRUE(same_bits(r.seed_positions[i].data(), s.seed_positions[i].data(), 24)) << i;
    EXPECT_TRUE(same_bits(r.seed_normals[i].data(), s.seed_normals[i].data(), 24)) << i;
    EXPECT_TRUE(same_bits(r.particles[i].position.data(), s.particles[i].position.data(), 24));
    EXPECT_EQ(r.particles[i].cell, s.particles[i].cell);
  }
  write_particles(r, dir.file("again.ply"));
  EXPECT_EQ(read_all(path), read_all(dir.file("again.ply")));
  // A spread system's state, as `ramiform particles` saves it.
  const FieldPtr ball = make_box_field(Vec3::Zero(), Vec3::Constant(1), 1);
  const ParticleSystem spread = spread_particles(*ball);
  write_particles(spread, dir.file("spread.ply"));
  const ParticleSystem back = read_particles(dir.file("spread.ply"));
  ASSERT_EQ(back.seed_positions.size(), spread.particles.size());
  EXPECT_TRUE(same_bits(back.seed_positions.data(), spread.seed_positions.data(),
                        24 * spread.particles.size()));
  EXPECT_TRUE(same_bits(back.seed_normals.data(), spread.seed_normals.data(),
                        24 * spread.particles.size()));
  // Without the state: valid, empty vectors.
  const ParticleSystem plain = read_particles([&] {
    write_particles(sample_system(), dir.file("plain.ply"));
    return dir.file("plain.ply");
  }());
  EXPECT_TRUE(plain.seed_positions.empty());
  EXPECT_TRUE(plain.seed_normals.empty());
}

TEST(ParticlesIo, MalformedSeedingStateIsRefused) {
  const TempDir dir;
  const std::string good = dir.file("good.ply");
  write_particles(seeded_system(), good);
  const std::string bytes = read_all(good);
  const std::size_t body = bytes.find("end_header\n") + 11;
  constexpr std::size_t kRow = 60 + 48;  // 7 doubles, a uint, 6 doubles

  std::string bad = bytes;
  bad.replace(bad.find("property double snz"), 19, "property double snq");
  const std::string some = dir.file("some.ply");
  write_all(some, bad);
  std::string m = message_of(some);
  EXPECT_NE(m.find("sx sy sz snx sny snz"), std::string::npos) << m;
  EXPECT_NE(m.find("5 of them"), std::string::npos) << m;

  bad = bytes;
  bad.replace(bad.find("property double sy"), 18, "property float  sy");
  const std::string typed = dir.file("typed.ply");
  write_all(typed, bad);
  m = message_of(typed);
  EXPECT_NE(m.find("'sy' has the wrong type"), std::string::npos) << m;

  bad = bytes;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&bad[body + kRow + 60 + 24 + 8], &nan, 8);  // particle 1's sny
  const std::string nonfinite = dir.file("nan.ply");
  write_all(nonfinite, bad);
  m = message_of(nonfinite);
  EXPECT_NE(m.find("vertex 1"), std::string::npos) << m;

  // Writing refuses a seeding state of the wrong length or not finite, without output.
  ParticleSystem s = seeded_system();
  s.seed_normals.pop_back();
  EXPECT_THROW(write_particles(s, dir.file("short.ply")), InvalidArgument);
  s = seeded_system();
  s.seed_positions[2].x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(write_particles(s, dir.file("inf.ply")), InvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(dir.file("short.ply")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("inf.ply")));
}

TEST(ParticlesIo, AReloadedSystemRegeneratesAsTheOriginal) {
  const TempDir dir;
  const FieldPtr ball = make_box_field(Vec3::Zero(), Vec3::Constant(1), 1);
  const FieldPtr edited =
      make_union({ball, make_box_field(Vec3(1, 0, 0), Vec3::Constant(0.2), 0.2)});
  const ParticleSystem s = spread_particles(*ball);
  write_particles(s, dir.file("s.ply"));
  const ParticleSystem r = read_particles(dir.file("s.ply"));
  const Aabb box(Vec3(0.7, -0.3, -0.3), Vec3(1.3, 0.3, 0.3));
  const ParticleSystem a = regenerate_particles(*edited, s, box);
  const ParticleSystem b = regenerate_particles(*edited, r, box);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  ASSERT_EQ(a.cells.size(), b.cells.size());
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    ASSERT_TRUE(same_bits(a.particles[i].position.data(), b.particles[i].position.data(), 24)) << i;
  }
}

TEST(ParticlesIo, WriteRefusesBadSystemsWithoutOutput) {
  const TempDir dir;
  ParticleSystem s = sample_system();
  s.particles[1].cell = 7;
  EXPECT_THROW(write_particles(s, dir.file("a.ply")), InvalidArgument);
  s = sample_system();
  s.particles[0].delta = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_particles(s, dir.file("a.ply")), InvalidArgument);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(ParticlesIo, MalformedFilesAreRefusedWithTheirProblem) {
  const TempDir dir;
  const std::string good = dir.file("good.ply");
  write_particles(sample_system(), good);
  const std::string bytes = read_all(good);
  const std::size_t body = bytes.find("end_header\n") + 11;

  // Truncated body.
  const std::string cut = dir.file("cut.ply");
  write_all(cut, bytes.substr(0, bytes.size() - 5));
  EXPECT_NE(message_of(cut).find("cell"), std::string::npos) << message_of(cut);

  // Particle 1's cell index out of range (the uint after its 7 doubles).
  std::string bad = bytes;
  const std::uint32_t nine = 9;
  std::memcpy(&bad[body + 60 + 56], &nine, 4);
  const std::string range = dir.file("range.ply");
  write_all(range, bad);
  const std::string m = message_of(range);
  EXPECT_NE(m.find("vertex 1"), std::string::npos) << m;
  EXPECT_NE(m.find("out of range"), std::string::npos) << m;

  // A non-finite coordinate.
  bad = bytes;
  const double inf = std::numeric_limits<double>::infinity();
  std::memcpy(&bad[body + 60 * 2], &inf, 8);
  const std::string nonfinite = dir.file("inf.ply");
  write_all(nonfinite, bad);
  EXPECT_NE(message_of(nonfinite).find("vertex 2"), std::string::npos) << message_of(nonfinite);

  // A wrongly typed property and a missing element.
  bad = bytes;
  bad.replace(bad.find("property uint cell"), 18, "property int  cell");
  const std::string typed = dir.file("typed.ply");
  write_all(typed, bad);
  EXPECT_NE(message_of(typed).find("wrong type"), std::string::npos) << message_of(typed);

  const std::string points = dir.file("points.ply");
  PointSet p;
  p.positions = {Vec3(1, 2, 3)};
  write_points(p, points);
  EXPECT_NE(message_of(points).find("comment iso"), std::string::npos) << message_of(points);
  bad = bytes;
  bad.replace(bad.find("comment iso "), 12, "comment isa ");
  const std::string noiso = dir.file("noiso.ply");
  write_all(noiso, bad);
  EXPECT_NE(message_of(noiso).find("comment iso"), std::string::npos);

  bad = bytes;
  bad.replace(bad.find("comment root "), 13, "comment root 1 ");
  const std::string root = dir.file("root.ply");
  write_all(root, bad);
  EXPECT_NE(message_of(root).find("expected 6 numbers"), std::string::npos) << message_of(root);

  // A cell with min > max.
  bad = bytes;
  const double big = 1e9;
  std::memcpy(&bad[body + 60 * 3], &big, 8);
  const std::string box = dir.file("box.ply");
  write_all(box, bad);
  EXPECT_NE(message_of(box).find("cell 0"), std::string::npos) << message_of(box);

  EXPECT_THROW((void)read_particles(dir.file("missing.ply")), InputError);
}

}  // namespace
}  // namespace ramiform
