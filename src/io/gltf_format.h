// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// glTF 2.0 binary (.glb) output of triangle meshes.

#include <ostream>
#include <span>

#include "ramiform/core/geometry.h"

namespace ramiform::io {

/// Writes `levels` (one mesh, or levels of detail finest first) as one glTF 2.0 binary asset
/// (Khronos glTF 2.0 specification, "GLB File Format Specification"): a 12-byte header, a JSON
/// chunk and a BIN chunk. glTF is +Y up, right-handed, in metres (specification §3.4), so the
/// library's +Z-up coordinates are rotated by -90 degrees about X: (x, y, z) -> (x, z, -y), for
/// positions, normals and tangents alike. Each level is one mesh of one triangle primitive:
/// one bark-brown PBR material (metallic 0, roughness 0.9); POSITION, and when present and asked for NORMAL, TEXCOORD_0 (u, 1 - v: glTF's texture origin
/// is the top left) and TANGENT (xyz rotated, w as the library's: cross(NORMAL, TANGENT.xyz) * w
/// points up the texture image), as float32; indices as uint32. One level: one node. Several:
/// node "LOD0" holds the finest and lists the coarser nodes "LOD1"... in the MSFT_lod extension
/// (with MSFT_screencoverage in its extras); only LOD0 is in the scene. Positions are rounded
/// to float32 (glTF has no double vertex attribute). The bytes depend only on the input.
void write_glb(std::span<const TriMesh> levels, bool normals, bool uvs, std::ostream& out);

}  // namespace ramiform::io
