// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Reading and writing point sets (positions with optional normals) as text or PLY (see
/// docs/formats.md).

#include <string>
#include <string_view>

#include "ramiform/core/geometry.h"

namespace ramiform {

/// Reads a point set. `.ply` (any case): element `vertex` with x, y, z and optionally nx, ny, nz.
/// Any other extension (`.xyz`, `.txt`, `.pts`, `.pwn`, ...) is text: one point per non-empty
/// line, "x y z" or "x y z nx ny nz", numbers separated by spaces, tabs or commas; '#' starts a
/// comment. Every line must have the same count (3 or 6) as the first point line.
///
/// Throws `InputError` naming the file and line (text) or element index (binary PLY) for an
/// unreadable file, malformed or non-finite numbers, wrong field counts, a zero normal (0 0 0), or
/// no points at all (a text file without point lines, a PLY file with `element vertex 0`: the
/// message says "no points"). Also refused, as the skeleton reader does, are coordinates whose span
/// is more than double precision can hold (the bounding box's diagonal length overflows, e.g.
/// points at
/// +-1e308): the message names the first point that breaks the rule (its line in text, "vertex
/// K" in PLY) and the coordinate range.
[[nodiscard]] PointSet read_points(const std::string& path);

/// Parses point text as `read_points` does; `source_name` is the file name used in messages.
[[nodiscard]] PointSet parse_points_text(std::string_view text, const std::string& source_name);

/// Parses the bytes of a PLY point set as `read_points` does.
[[nodiscard]] PointSet parse_points_ply(std::string_view bytes, const std::string& source_name);

/// Writes a point set atomically: binary little-endian PLY (double x, y, z[, nx, ny, nz]) for a
/// `.ply` extension, otherwise text "x y z[ nx ny nz]" per line with the shortest numbers that
/// read back identically. Throws `InvalidArgument` when the normal count is neither 0 nor the
/// point count or a value is not finite; `Failure` when the file cannot be written.
void write_points(const PointSet& points, const std::string& path);

}  // namespace ramiform
