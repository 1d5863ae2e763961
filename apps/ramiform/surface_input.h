// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#pragma once

// The INPUT of `particles` and `draw`: a point cloud or mesh (its MPU implicit), a skeleton (its
// surface, with the field options of `mesh`), or SCRIPT.rf:NAME (a shape of a scene script);
// with the particle options both commands share.

#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common.h"
#include "mesh_job.h"
#include "ramiform/core/context.h"
#include "ramiform/field/field.h"
#include "ramiform/particles/surface_particles.h"
#include "reconstruct_job.h"

namespace ramiform::cli {

struct SurfaceInputArgs {
  std::string input;
  bool skeleton = false;  // --skeleton: INPUT is a skeleton whatever its extension
  ReconstructOptions reconstruct;
  FieldFlags field;
  ParticleOptions particles;
};

// A surface to spread particles over: the field, the cells it brings (an MPU's leaves), the
// points it was fitted to (seeds), and the input's figures for --stats.
struct SurfaceInput {
  FieldPtr field;
  std::vector<ParticleCell> cells;
  std::vector<Vec3> seeds;
  nlohmann::json stats = nlohmann::json::object();
};

// The options of the MPU fit and of reading the points (reconstruct, particles, draw).
void add_mpu_options(CLI::App& c, ReconstructOptions& o);

// Adds INPUT (its description ending in `what`), --skeleton, the particle options, the MPU options
// and the skeleton field options.
void add_surface_input_options(CLI::App& c, SurfaceInputArgs& a, const std::string& what);

// Reads INPUT and builds its surface; timer laps "script", "read", "field", ... as it goes.
SurfaceInput load_surface_input(SurfaceInputArgs& a, Context& ctx, StageTimer& timer);

// --stats figures of a particle run: particles, simulated, kept, dropped, cells, iterations,
// residual_max, spacing_cv, particle_seconds.
void add_particle_stats(nlohmann::json& stats, const ParticleSystem& system,
                        const ParticleStats& ps);

}  // namespace ramiform::cli
