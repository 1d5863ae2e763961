// SPDX-License-Identifier: MIT
// Copyright (c) 2026 the ramiform authors
#include <chrono>

#include "ramiform/lines/lines.h"

namespace ramiform {

LineDrawing draw_lines(const Field& field, const ParticleSystem& particles, const Camera& camera,
                       const LineOptions& options, const std::vector<Polyline>* features,
                       LineStats* stats, const Context* ctx, const ParticleLookup* lookup) {
  validate(camera);
  validate(options);
  LineDrawing drawing;
  drawing.camera = camera;
  if (stats != nullptr) stats->particles = particles.particles.size();
  auto append = [&](std::vector<Polyline> lines) {
    for (Polyline& line : lines) drawing.lines.push_back(std::move(line));
  };
  if (options.silhouettes)
    append(silhouettes(field, particles, camera, options, stats, ctx, lookup));
  if (options.suggestive)
    append(suggestive_contours(field, particles, camera, options, stats, ctx));
  if (options.features) {
    if (features != nullptr) {
      drawing.lines.insert(drawing.lines.end(), features->begin(), features->end());
    } else {
      append(feature_lines(field, particles, options, stats, ctx));
    }
  }
  classify_visibility(field, particles, camera, drawing.lines, options, stats, ctx, lookup);
  return drawing;
}

}  // namespace ramiform
