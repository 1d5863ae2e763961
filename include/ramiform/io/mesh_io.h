// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Reading and writing triangle meshes as PLY, OBJ and OFF (see docs/formats.md). Polygons with
/// more than three vertices are fan-triangulated (v0 v1 v2, v0 v2 v3, ...). Degenerate triangles
/// (repeated indices) are kept; indices out of range are errors.

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ramiform/core/geometry.h"

namespace ramiform {

/// Reads a mesh, choosing the format by the extension (case-insensitive): `.ply` (ASCII or
/// binary; faces in a `vertex_indices` or `vertex_index` list of any integer type; optional
/// per-vertex nx, ny, nz become `normals`, u v (or s t, texture_u texture_v) `uvs`, and then
/// vertices at identical positions are taken as seam copies: `welded`; an integer `swc_type`
/// becomes `vertex_labels`, as write_mesh stores them), `.obj` (`v`, `vn`, `f` with v, v/vt, v//vn, v/vt/vn
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

/// The up axis of a written file.
enum class UpAxis {
  kZ,  ///< +Z up: the library's coordinates, unchanged
  kY,  ///< +Y up: (x, y, z) -> (x, z, -y), a rotation by -90 degrees about X (right-handed)
};

/// How `write_mesh` writes.
struct MeshWriteOptions {
  /// The up axis of .ply, .obj and .off files (+Z, the library's, by default). A .glb file is
  /// always +Y up, as glTF 2.0 requires (specification §3.4), whatever this says.
  UpAxis up = UpAxis::kZ;
  bool normals = true;  ///< write the mesh's normals (and tangents) when it has them
  bool uvs = true;      ///< write the mesh's texture coordinates (and tangents) when it has them
};

/// Writes a mesh, choosing the format by the extension (case-insensitive):
/// - `.ply`: binary little-endian; vertex x, y, z, then with normals nx, ny, nz, then with uvs
///   u, v, all as double; faces as a uchar/uint `vertex_indices` list. A textured mesh is
///   written with its seam copies (PLY has one texture coordinate per vertex).
/// - `.obj`: text; one `v` (and `vn`) per surface point (seam copies written once, so a closed
///   mesh stays closed by its indices), one `vt` per vertex, corners v, v//vn, v/vt or v/vt/vn.
/// - `.off`: text, positions only (seam copies written once).
/// - `.glb`: glTF 2.0 binary, write only (io/gltf_format.h): +Y up, float32 POSITION, NORMAL,
///   TEXCOORD_0 (u, 1 - v) and TANGENT, uint32 indices.
/// Numbers in .ply/.obj/.off are written so that reading gives identical doubles (in the file's
/// axes). The write is atomic (io/atomic_file.h).
///
/// Throws `InvalidArgument` for another extension, an attribute count that is neither 0 nor the
/// vertex count, tangents without uvs, a `welded` that breaks its invariants, non-finite
/// values or indices out of range; `Failure` when the file cannot be written.
void write_mesh(const TriMesh& mesh, const std::string& path,
                const MeshWriteOptions& options = {});

/// The files `write_mesh_lods` writes for `levels` levels at `path`: `path` itself for one
/// level or a .glb; otherwise one per level, `.lodK` before the extension (tree.ply ->
/// tree.lod0.ply, tree.lod1.ply, ...).
[[nodiscard]] std::vector<std::string> lod_paths(const std::string& path, std::size_t levels);

/// Writes levels of detail, finest first: a .glb gets them all in one file (one node per level,
/// "LOD0"..., in the MSFT_lod convention); another format one file per level (`lod_paths`),
/// each as `write_mesh` writes it. Either every file is written or (on an exception) none of
/// them is left. Returns the paths written. Throws as `write_mesh`, and InvalidArgument for no
/// levels.
std::vector<std::string> write_mesh_lods(std::span<const TriMesh> levels,
                                         const std::string& path,
                                         const MeshWriteOptions& options = {});


}  // namespace ramiform
