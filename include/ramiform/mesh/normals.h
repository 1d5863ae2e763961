// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Vertex normals of a triangle mesh: from the field it approximates (the exact surface normal,
/// as written to .glb, PLY and OBJ by default) or from its triangles.

#include "ramiform/core/context.h"
#include "ramiform/core/geometry.h"
#include "ramiform/field/field.h"
#include "ramiform/mesh/bark_uv.h"
#include "ramiform/skeleton/skeleton.h"

namespace ramiform {

/// Sets `mesh.normals` to the outward unit normal of `field`'s surface at every vertex:
/// -grad f / |grad f| (the field is larger inside, DESIGN's convention). Where the gradient is
/// zero or not finite (a critical point, a vertex far from the surface) the vertex takes its
/// area-weighted triangle normal instead, and a vertex in no triangle takes (0, 0, 1). Returns
/// the number of vertices that fell back. Seam copies (`mesh.welded`) get their original's
/// normal. Parallel; the result does not depend on the thread count.
std::size_t set_normals_from_field(TriMesh& mesh, const Field& field,
                                   const Context* ctx = nullptr);

/// Sets `mesh.normals` to the area-weighted average of the unit normals of each vertex's
/// triangles (counter-clockwise from outside), through the seam copies of `mesh.welded`; (0, 0,
/// 1) for a vertex in no triangle or whose triangles cancel. Throws InvalidArgument for a
/// vertex index out of range.
void set_normals_from_faces(TriMesh& mesh);

/// What a written mesh carries besides its positions (the CLI's `mesh` and the scene
/// language's `save_mesh` decide it per output file).
struct SurfaceAttributeOptions {
  bool normals = true;  ///< the field's normals (set_normals_from_field)
  bool uvs = false;     ///< bark texture coordinates and tangents (add_bark_uvs)
  BarkUvOptions bark;
};

/// Gives `mesh`, a mesh of `field`'s surface made from `skeleton`, what `options` asks for:
/// first the field's normals, then bark UVs (splitting the vertices along the seams; the copies
/// get the normals). Without uvs and normals it leaves the mesh as it is. `uv_stats` (may be
/// null) receives add_bark_uvs' figures.
void add_surface_attributes(TriMesh& mesh, const Field& field, const Skeleton& skeleton,
                            const SurfaceAttributeOptions& options, const Context* ctx = nullptr,
                            BarkUvStats* uv_stats = nullptr);

}  // namespace ramiform
