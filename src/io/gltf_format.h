// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// glTF 2.0 binary (.glb) output of a triangle mesh.

#include <ostream>

#include "ramiform/core/geometry.h"

namespace ramiform::io {

/// Writes `mesh` as one glTF 2.0 binary asset (Khronos glTF 2.0 specification, "GLB File
/// Format Specification"): a 12-byte header, a JSON chunk and a BIN chunk. One mesh with one
/// triangle primitive; POSITION (and NORMAL when present) as float32 VEC3, indices as uint32
/// SCALAR. Positions are rounded to float32 (glTF has no double vertex attribute). The bytes
/// depend only on the mesh.
void write_glb(const TriMesh& mesh, std::ostream& out);

}  // namespace ramiform::io
