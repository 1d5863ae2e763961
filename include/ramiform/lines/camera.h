// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// A pinhole camera for line drawings: where the eye is, what it looks at, how wide it sees.
///
/// Camera units: a point p projects to the image plane one unit in front of the eye,
/// (x, y) = ((p − eye)·right, (p − eye)·up') / ((p − eye)·forward), x to the right and y up, so
/// the frame is |y| ≤ tan(fov/2), |x| ≤ aspect·tan(fov/2). SVG drawings use these units for
/// their viewBox (with y flipped).

#include <cstdint>
#include <string_view>
#include <vector>

#include "ramiform/core/types.h"

namespace ramiform {

/// A perspective camera.
struct Camera {
  Vec3 eye{0, 0, 5};     ///< the centre of projection, model units
  Vec3 target{0, 0, 0};  ///< the point the camera looks at (the frame's centre)
  Vec3 up{0, 1, 0};      ///< the upward direction (need not be orthogonal to the view)
  double fov_deg = 30;   ///< vertical field of view, degrees, in (0, 170]
  double aspect = 1;     ///< width / height of the frame, > 0
};

/// The camera's orthonormal frame: forward from the eye to the target, right = forward × up
/// (normalized), up' = right × forward.
struct CameraFrame {
  Vec3 right, up, forward;
};

/// A projected point: (x, y) in camera units, depth = (p − eye)·forward (> 0 in front).
struct Projected {
  double x = 0, y = 0, depth = 0;
};

/// Throws InvalidArgument naming the problem when `camera` is unusable: non-finite values, eye
/// == target, up parallel to the view direction, fov outside (0, 170], aspect ≤ 0.
void validate(const Camera& camera);

/// The camera's frame (validate() first).
[[nodiscard]] CameraFrame camera_frame(const Camera& camera);

/// Projects p (perspective division by depth; depth ≤ 0 gives non-finite x, y).
[[nodiscard]] Projected project(const Camera& camera, const CameraFrame& frame, const Vec3& p);

/// The unit view vector of Proença et al. 2008 eq. 3: (p − eye) / |p − eye|.
[[nodiscard]] Vec3 view_vector(const Camera& camera, const Vec3& p);

/// Which model axis points up in a framed view.
enum class ViewUp : std::uint8_t {
  kY,  ///< +y up (scans, meshes, glTF): azimuth about +y, 0 = looking along −z from +z
  kZ,  ///< +z up (skeletons, trees): azimuth about +z, 0 = looking along +y from −y
};

/// A camera that frames `box` (its bounding sphere fills the frame's smaller side with a 5 %
/// margin) from the direction given by azimuth (degrees about the up axis) and elevation
/// (degrees above the horizontal plane).
[[nodiscard]] Camera frame_box(const Aabb& box, double azimuth_deg = 30, double elevation_deg = 15,
                               double fov_deg = 30, double aspect = 1, ViewUp up = ViewUp::kY);

/// Parses "eye=x,y,z;target=x,y,z;up=x,y,z;fov=deg;aspect=a" (any subset, in any order, spaces
/// allowed around separators). Keys left out come from `defaults`. Throws InputError naming the
/// key and the problem (unknown key, not three numbers, a non-finite number, repeated key), and
/// InvalidArgument through validate() for an unusable result.
[[nodiscard]] Camera parse_camera(std::string_view text, const Camera& defaults);

/// `views` cameras turning about the axis through camera.target along camera.up, the first one
/// equal to `camera`, evenly spaced over 360°. views ≥ 1.
[[nodiscard]] std::vector<Camera> turntable(const Camera& camera, int views);

}  // namespace ramiform
