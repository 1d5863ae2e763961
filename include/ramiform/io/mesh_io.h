// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Reading and writing triangle meshes as PLY, OBJ and OFF (see docs/formats.md). Polygons with
/// more than three vertices are fan-triangulated (v0 v1 v2, v0 v2 v3, ...). Degenerate triangles
/// (repeated indices) are kept; indices out of range are errors.

#include <string>
#include <string_view>

#include "ramiform/core/geometry.h"

namespace ramiform {

/// Reads a mesh, choosing the format by the extension (case-insensitive): `.ply` (ASCII or
/// binary; faces in a `vertex_indices` or `vertex_index` list of any integer type; optional
/// per-vertex nx, ny, nz become `normals`), `.obj` (`v`, `vn`, `f` with v, v/vt, v//vn, v/vt/vn
/// corners, negative indices) or `.off`.
///
/// Throws `InputError` naming the file and the line (text) or the element index (binary PLY,
/// face checks) for an unknown extension, an unreadable or empty file, a malformed header,
/// malformed or non-finite numbers, wrong field counts, faces with fewer than 3 vertices or
/// vertex indices out of range.
[[nodiscard]] TriMesh read_mesh(const std::string& path);

/// Parses the bytes of a PLY mesh; `source_name` is the file name used in messages.
[[nodiscard]] TriMesh parse_mesh_ply(std::string_view bytes, const std::string& source_name);

/// Parses OBJ text. Normals are kept only when the file has exactly one `vn` per `v` and every
/// face corner that names a normal names the one with its vertex's index (as `write_mesh`
/// writes them); otherwise `normals` is left empty.
[[nodiscard]] TriMesh parse_mesh_obj(std::string_view text, const std::string& source_name);

/// Parses OFF text: "OFF", then "nv nf ne" (on the same line or the next), nv lines "x y z",
/// nf lines "n i0 ... i(n-1) [colour]" with 0-based indices; '#' starts a comment.
[[nodiscard]] TriMesh parse_mesh_off(std::string_view text, const std::string& source_name);

/// Writes a mesh, choosing the format by the extension (case-insensitive): `.ply` (binary
/// little-endian; vertex x, y, z and, with normals, nx, ny, nz as double; faces as a uchar/uint
/// `vertex_indices` list), `.obj` (text; `vn` lines and v//vn corners when there are normals) or
/// `.off` (text, no normals) or `.glb` (glTF 2.0 binary, write only: float32 positions and
/// normals, uint32 indices). Numbers in .ply/.obj/.off are written so that reading gives
/// identical doubles. The write is atomic (io/atomic_file.h).
///
/// Throws `InvalidArgument` for another extension, a normal count that is neither 0 nor the
/// vertex count, non-finite coordinates or indices out of range; `Failure` when the file cannot
/// be written.
void write_mesh(const TriMesh& mesh, const std::string& path);

}  // namespace ramiform
