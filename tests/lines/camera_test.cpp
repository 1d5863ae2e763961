// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/lines/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ramiform/core/errors.h"

namespace ramiform {
namespace {

TEST(Camera, ProjectsTheTargetToTheCentreAndKnownPointsToTheirTangents) {
  Camera c;
  c.eye = Vec3(0, 0, 10);
  c.target = Vec3(0, 0, 0);
  const CameraFrame f = camera_frame(c);
  EXPECT_NEAR((f.forward - Vec3(0, 0, -1)).norm(), 0, 1e-15);
  EXPECT_NEAR((f.right - Vec3(1, 0, 0)).norm(), 0, 1e-15);
  const Projected t = project(c, f, c.target);
  EXPECT_DOUBLE_EQ(t.x, 0);
  EXPECT_DOUBLE_EQ(t.y, 0);
  EXPECT_DOUBLE_EQ(t.depth, 10);
  // (2, −1, 5) is 5 in front of the eye: x = 2/5, y = −1/5.
  const Projected p = project(c, f, Vec3(2, -1, 5));
  EXPECT_DOUBLE_EQ(p.x, 0.4);
  EXPECT_DOUBLE_EQ(p.y, -0.2);
  EXPECT_DOUBLE_EQ(p.depth, 5);
  EXPECT_NEAR((view_vector(c, Vec3(0, 0, 0)) - Vec3(0, 0, -1)).norm(), 0, 1e-15);
}

TEST(Camera, FrameBoxKeepsEveryCornerInsideTheFrame) {
  const Aabb box(Vec3(-1, -2, -0.5), Vec3(3, 1, 0.5));
  for (double az : {0.0, 45.0, 200.0}) {
    for (double el : {-30.0, 0.0, 60.0, 90.0}) {
      const Camera c = frame_box(box, az, el, 40, 1.5);
      const CameraFrame f = camera_frame(c);
      const double half = std::tan(20 * std::numbers::pi / 180);
      for (int i = 0; i < 8; ++i) {
        const Projected p = project(c, f, box.corner(static_cast<Aabb::CornerType>(i)));
        EXPECT_GT(p.depth, 0);
        EXPECT_LE(std::abs(p.y), half);
        EXPECT_LE(std::abs(p.x), 1.5 * half);
      }
      EXPECT_NEAR((c.target - box.center()).norm(), 0, 1e-12);
      // The same with +z up: every corner inside, and the frame's up is +z (or, looking
      // straight down or up, the view's up lies in the xy-plane).
      const Camera z = frame_box(box, az, el, 40, 1.5, ViewUp::kZ);
      const CameraFrame fz = camera_frame(z);
      for (int i = 0; i < 8; ++i) {
        const Projected p = project(z, fz, box.corner(static_cast<Aabb::CornerType>(i)));
        EXPECT_LE(std::abs(p.y), half);
        EXPECT_LE(std::abs(p.x), 1.5 * half);
      }
      if (std::abs(el) < 89) EXPECT_GT(fz.up.z(), 0);
    }
  }
  // Azimuth 0, elevation 0 with +z up: the eye on −y, looking along +y.
  const Camera front = frame_box(box, 0, 0, 40, 1, ViewUp::kZ);
  EXPECT_NEAR(camera_frame(front).forward.y(), 1, 1e-12);
}

TEST(Camera, ParsesKeysInAnyOrderAndKeepsDefaultsForTheRest) {
  Camera d;
  d.fov_deg = 25;
  const Camera c = parse_camera(" target=1,2,3 ; eye = 1, 2, 13;fov=40 ", d);
  EXPECT_EQ(c.eye, Vec3(1, 2, 13));
  EXPECT_EQ(c.target, Vec3(1, 2, 3));
  EXPECT_EQ(c.up, d.up);
  EXPECT_EQ(c.fov_deg, 40);
  EXPECT_EQ(parse_camera("", d).fov_deg, 25);
}

TEST(Camera, RefusesBadTextNamingTheKey) {
  const Camera d;
  auto message = [&](const char* text) {
    try {
      (void)parse_camera(text, d);
    } catch (const InputError& e) {
      return std::string(e.what());
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("eye=1,2").find("'eye': expects three numbers"), std::string::npos);
  EXPECT_NE(message("eye=1,2,3,4").find("'eye'"), std::string::npos);
  EXPECT_NE(message("fov=abc").find("'fov': 'abc' is not a number"), std::string::npos);
  EXPECT_NE(message("fov=nan").find("not finite"), std::string::npos);
  EXPECT_NE(message("zoom=2").find("unknown key"), std::string::npos);
  EXPECT_NE(message("fov=20;fov=30").find("given twice"), std::string::npos);
  EXPECT_NE(message("eye").find("not KEY=VALUE"), std::string::npos);
  EXPECT_NE(message("eye=0,0,0").find("coincide"), std::string::npos);
  // Their distance overflows: once reported as "up is ... parallel to the view direction".
  EXPECT_NE(message("eye=1e308,0,0;target=-1e308,0,0").find("too far"), std::string::npos)
      << message("eye=1e308,0,0;target=-1e308,0,0");
  EXPECT_NE(message("up=0,0,-1").find("parallel"), std::string::npos);
  EXPECT_NE(message("fov=180").find("fov must be in"), std::string::npos);
}

TEST(Camera, TurntableKeepsTheDistanceAndReturnsToTheStart) {
  Camera c;
  c.eye = Vec3(3, 1, 4);
  c.target = Vec3(0, 1, 0);
  const auto views = turntable(c, 4);
  ASSERT_EQ(views.size(), 4u);
  EXPECT_EQ(views[0].eye, c.eye);
  for (const Camera& v : views) EXPECT_NEAR((v.eye - v.target).norm(), 5, 1e-12);
  // A quarter turn about +y takes (3, ·, 4) to (4, ·, −3).
  EXPECT_NEAR((views[1].eye - Vec3(4, 1, -3)).norm(), 0, 1e-12);
  EXPECT_THROW((void)turntable(c, 0), InvalidArgument);
}

}  // namespace
}  // namespace ramiform
