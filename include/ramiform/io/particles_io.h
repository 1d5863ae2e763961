// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

/// \file
/// Saving and reloading a particle system (particles/surface_particles.h), so that a model's
/// particles need not be simulated again (Proença, Jorge & Costa Sousa 2008, "Suggestive
/// Contours over Point-Set Implicits", §3). The format is a binary little-endian PLY file
/// (docs/formats.md, "Particle state (PLY)"): element `vertex` (double x y z nx ny nz delta,
/// uint cell, and when the system has a seeding state double sx sy sz snx sny snz), element
/// `cell` (double xmin ymin zmin xmax ymax zmax, int depth), a header
/// line `comment iso <value>` and, when the cells came from adaptive_cells, `comment root ...`.
/// Other PLY tools see the particles as vertices with normals.

#include <string>
#include <string_view>

#include "ramiform/particles/surface_particles.h"

namespace ramiform {

/// Writes `system` atomically (io/atomic_file.h). Every number round-trips exactly
/// (the root cube, when not empty, as a header line
/// `comment root xmin ymin zmin xmax ymax zmax`; the seeding state when has_seed_state(system)).
/// Throws InvalidArgument when a value is not finite or a particle's cell index is out of range;
/// Failure when the file cannot be written.
void write_particles(const ParticleSystem& system, const std::string& path);

/// Reads a file written by write_particles; a file without the seeding-state properties gives
/// empty seed_positions and seed_normals. Throws InputError naming the file and the element
/// (and its index) or header line for a missing or malformed `comment iso` line, missing or
/// wrongly typed properties (among them some but not all of sx sy sz snx sny snz), a missing `cell`
/// element, truncated data, non-finite numbers, empty cell boxes, depths outside [0,
/// ParticleOptions::kMaxDepth] or a cell index out of range.
[[nodiscard]] ParticleSystem read_particles(const std::string& path);

/// Parses the bytes of a particle file as read_particles does; `source_name` names it in
/// messages.
[[nodiscard]] ParticleSystem parse_particles(std::string_view bytes,
                                             const std::string& source_name);

}  // namespace ramiform
