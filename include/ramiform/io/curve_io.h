// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Curve point files for the curves of field/curves.h (profiles of surfaces of revolution,
/// sweep paths, skinning sections): one point per line, "x y" (a planar curve) or "x y z" (a
/// space curve), numbers separated by spaces, tabs or single commas (as in point files,
/// io/points_io.h); '#' starts a comment; blank lines are ignored.

#include <string>
#include <vector>

#include "ramiform/field/curves.h"

namespace ramiform {

/// Reads a curve file: "x y" per point line (Curve2 points) or "x y z" (Curve3 points). Throws
/// InputError(path, line, problem) for an unreadable file, a line with the wrong number of
/// fields, an empty field between commas, a field that is not a number or not finite;
/// InputError(path, 0, "no points") for a file without points.
[[nodiscard]] std::vector<Vec2> read_points2(const std::string& path);
[[nodiscard]] std::vector<Vec3> read_points3(const std::string& path);

}  // namespace ramiform
