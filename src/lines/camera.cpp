// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include "ramiform/lines/camera.h"

#include <cmath>
#include <numbers>
#include <string>

#include "ramiform/core/errors.h"
#include "ramiform/core/numbers.h"

namespace ramiform {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

bool finite(const Vec3& v) { return v.allFinite(); }

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

[[noreturn]] void bad(const std::string& key, const std::string& problem) {
  throw InputError("--camera", 0, "'" + key + "': " + problem);
}

double number(std::string_view token, const std::string& key) {
  double value = 0;
  switch (parse_number(trim(token), value)) {
    case NumberStatus::kOk:
      return value;
    case NumberStatus::kNotFinite:
      bad(key, "'" + std::string(trim(token)) + "' is not finite");
    default:
      bad(key, "'" + std::string(trim(token)) + "' is not a number");
  }
}

Vec3 vector3(std::string_view text, const std::string& key) {
  Vec3 v;
  int n = 0;
  while (true) {
    const auto comma = text.find(',');
    const auto token = text.substr(0, comma);
    if (n == 3) bad(key, "expects three numbers x,y,z, got more");
    v[n++] = number(token, key);
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  if (n != 3) bad(key, "expects three numbers x,y,z, got " + std::to_string(n));
  return v;
}

}  // namespace

void validate(const Camera& camera) {
  if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up)) {
    throw InvalidArgument("camera: eye, target and up must be finite");
  }
  const Vec3 view = camera.target - camera.eye;
  if (!(view.norm() > 0)) throw InvalidArgument("camera: the eye and the target coincide");
  if (!std::isfinite(view.norm()) || !std::isfinite(camera.up.norm())) {
    throw InvalidArgument(
        "camera: the eye is too far from the target (or up too long) for double "
        "precision: their distance overflows");
  }
  if (!(camera.up.norm() > 0) || view.normalized().cross(camera.up.normalized()).norm() < 1e-9) {
    throw InvalidArgument("camera: up is zero or parallel to the view direction");
  }
  if (!(camera.fov_deg > 0 && camera.fov_deg <= 170)) {
    throw InvalidArgument("camera: fov must be in (0, 170] degrees, got " +
                          format_shortest(camera.fov_deg));
  }
  if (!(camera.aspect > 0) || !std::isfinite(camera.aspect)) {
    throw InvalidArgument("camera: aspect must be positive, got " + format_shortest(camera.aspect));
  }
}

CameraFrame camera_frame(const Camera& camera) {
  CameraFrame f;
  f.forward = (camera.target - camera.eye).normalized();
  f.right = f.forward.cross(camera.up).normalized();
  f.up = f.right.cross(f.forward);
  return f;
}

Projected project(const Camera& camera, const CameraFrame& frame, const Vec3& p) {
  const Vec3 d = p - camera.eye;
  Projected out;
  out.depth = d.dot(frame.forward);
  out.x = d.dot(frame.right) / out.depth;
  out.y = d.dot(frame.up) / out.depth;
  return out;
}

Vec3 view_vector(const Camera& camera, const Vec3& p) { return (p - camera.eye).normalized(); }

Camera frame_box(const Aabb& box, double azimuth_deg, double elevation_deg, double fov_deg,
                 double aspect, ViewUp up) {
  if (box.isEmpty() || !finite(box.min()) || !finite(box.max())) {
    throw InvalidArgument("frame_box: the box is empty or not finite");
  }
  Camera c;
  c.fov_deg = fov_deg;
  c.aspect = aspect;
  c.target = box.center();
  const double radius = std::max(0.5 * box.diagonal().norm(), 1e-12);
  // The bounding sphere subtends the vertical (or, when narrower, horizontal) half-angle.
  const double half = 0.5 * fov_deg * kDeg;
  const double half_x = std::atan(std::tan(half) * aspect);
  const double distance = 1.05 * radius / std::sin(std::min(half, half_x));
  const double az = azimuth_deg * kDeg, el = elevation_deg * kDeg;
  if (up == ViewUp::kY) {
    const Vec3 dir(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
    c.eye = c.target + distance * dir;
    c.up = Vec3(0, 1, 0);
    if (std::abs(dir.y()) > 0.999) c.up = Vec3(0, 0, dir.y() > 0 ? -1 : 1);
  } else {
    const Vec3 dir(std::cos(el) * std::sin(az), -std::cos(el) * std::cos(az), std::sin(el));
    c.eye = c.target + distance * dir;
    c.up = Vec3(0, 0, 1);
    if (std::abs(dir.z()) > 0.999) c.up = Vec3(0, dir.z() > 0 ? 1 : -1, 0);
  }
  validate(c);
  return c;
}

Camera parse_camera(std::string_view text, const Camera& defaults) {
  Camera c = defaults;
  bool seen[5] = {false, false, false, false, false};
  static constexpr std::string_view kKeys[5] = {"eye", "target", "up", "fov", "aspect"};
  while (!trim(text).empty()) {
    const auto semi = text.find(';');
    const std::string_view item = trim(text.substr(0, semi));
    text = semi == std::string_view::npos ? std::string_view{} : text.substr(semi + 1);
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string_view::npos) {
      throw InputError("--camera", 0,
                       "'" + std::string(item) +
                           "' is not KEY=VALUE (keys: eye, target, up, fov, "
                           "aspect)");
    }
    const std::string key(trim(item.substr(0, eq)));
    const std::string_view value = trim(item.substr(eq + 1));
    int k = 0;
    while (k < 5 && kKeys[k] != key) ++k;
    if (k == 5) bad(key, "unknown key (keys: eye, target, up, fov, aspect)");
    if (seen[k]) bad(key, "given twice");
    seen[k] = true;
    switch (k) {
      case 0:
        c.eye = vector3(value, key);
        break;
      case 1:
        c.target = vector3(value, key);
        break;
      case 2:
        c.up = vector3(value, key);
        break;
      case 3:
        c.fov_deg = number(value, key);
        break;
      default:
        c.aspect = number(value, key);
        break;
    }
  }
  validate(c);
  return c;
}

std::vector<Camera> turntable(const Camera& camera, int views) {
  if (views < 1) throw InvalidArgument("turntable: views must be at least 1");
  validate(camera);
  const Vec3 axis = camera.up.normalized();
  std::vector<Camera> out;
  out.reserve(static_cast<std::size_t>(views));
  for (int i = 0; i < views; ++i) {
    const double angle = 2 * std::numbers::pi * i / views;
    const Eigen::AngleAxisd turn(angle, axis);
    Camera c = camera;
    c.eye = camera.target + turn * (camera.eye - camera.target);
    out.push_back(c);
  }
  return out;
}

}  // namespace ramiform
